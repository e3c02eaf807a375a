//! The particle–particle contact forces of one step, over the half pair list.
//!
//! The list stores its pairs row by row in the particles' spatial order ([`PairList`]). During
//! a run the particles themselves are stored in that order ([`PairList::is_identity`]) and the
//! pass reads their arrays directly; otherwise (the set-up, the steps before the first
//! rebuild) the per-particle data are copied into that order, so a pass reads from nearby
//! memory either way.
//! Each thread takes a contiguous range of rows and, row a after row a:
//! 1. *evaluates* the pairs of row a: a pair in contact gets its [`ContactOutput`] (force on i,
//!    torques on i and j) and its history advanced, a pair apart has its history reset;
//! 2. *reduces* sorted position a, whose pairs all lie in rows ≤ a: its force and torque are
//!    summed from zero over its contacts in ascending order of the partner's particle index —
//!    −F and the j-torque where it is the pair's j (partners below it), +F and the i-torque
//!    where it is the pair's i (partners above). Positions with a pair in an earlier thread's
//!    range are reduced after all threads are done.
//!
//! That order is the one a serial loop over particles i with their partners j > i produces,
//! so the sums are those of the serial loop bit for bit, for every thread count and whatever
//! the spatial order (a run continued from a restart file builds its list at other positions
//! and still sums alike).

use mesh::v3::V3;
use rayon::prelude::*;

use crate::contact::{
    contact_force, ContactInput, ContactModel, ContactOutput, History, HistoryUse,
};
use crate::material::Materials;
use crate::neighbor::{PairList, PairView, ROLE_J};
use crate::particles::Particles;
use crate::periodic::Periodic;
use crate::sim::STREAM_BLOCK;

/// `slot_out` of a pair not in contact.
const APART: u32 = u32::MAX;

/// Per-particle data in the list's spatial order and the per-pair results of the last
/// evaluation (buffers kept from step to step).
#[derive(Debug, Default)]
pub struct PairForces {
    /// Positions (m), by sorted position.
    x: Vec<V3>,
    /// Velocities (m/s), by sorted position.
    v: Vec<V3>,
    /// Angular velocities (rad/s), by sorted position.
    omega: Vec<V3>,
    /// Radii (m), by sorted position; copied at each list build.
    radius: Vec<f64>,
    /// Masses (kg), by sorted position; copied at each list build.
    mass: Vec<f64>,
    /// Types, by sorted position; copied at each list build.
    atom_type: Vec<u32>,
    /// The list generation radii, masses and types were copied for.
    generation: Option<u64>,
    /// Outputs of the pairs in contact; each thread's range of pairs fills its own range of
    /// `out` from the start, so only contacts are written and read back.
    out: Vec<ContactOutput>,
    /// Per pair: its index in `out`, [`APART`] when not in contact.
    slot_out: Vec<u32>,
    /// Per sorted position: total contact force (N) and torque (N·m).
    sums: Vec<[V3; 2]>,
    /// The same by particle index (unused while the two orders are the same).
    sums_by_index: Vec<[V3; 2]>,
    /// Whether the last evaluation's sorted positions were the particle indices.
    identity: bool,
}

/// Per-particle data by sorted position, for the kernel.
#[derive(Clone, Copy)]
struct Frame<'a> {
    x: &'a [V3],
    v: &'a [V3],
    omega: &'a [V3],
    radius: &'a [f64],
    mass: &'a [f64],
    atom_type: &'a [u32],
    /// The box's periodic axes (pairs across a face are measured to the nearest image).
    periodic: Option<&'a Periodic>,
}

/// The pair's output, or `None` when its particles (sorted positions `i`, `j`) are apart (its
/// history is then reset).
#[inline]
#[allow(clippy::too_many_arguments)]
fn evaluate_pair(
    d: &Frame,
    i: usize,
    j: usize,
    h: &mut History,
    mats: &Materials,
    model: &ContactModel,
    dt: f64,
    history: HistoryUse,
) -> Option<ContactOutput> {
    let (x, r, m) = (d.x, d.radius, d.mass);
    let dx = match d.periodic {
        None => x[i] - x[j],
        Some(per) => per.delta(x[i], x[j]),
    };
    let rsq = dx.dot(&dx);
    let radsum = r[i] + r[j];
    if rsq >= radsum * radsum {
        if *h != History::default() {
            *h = History::default();
        }
        return None;
    }
    let dist = rsq.sqrt();
    let inp = ContactInput {
        n: (1.0 / dist * dx),
        r: dist,
        deltan: radsum - dist,
        radi: r[i],
        radj: r[j],
        reff: r[i] * r[j] / radsum,
        meff: m[i] * m[j] / (m[i] + m[j]),
        vrel: (d.v[i] - d.v[j]),
        omega_i: d.omega[i],
        omega_j: d.omega[j],
        is_wall: false,
    };
    let coeffs = mats.pair(d.atom_type[i], d.atom_type[j]);
    Some(contact_force(model, coeffs, &inp, h, dt, history))
}

/// Force and torque on sorted position `s` in the canonical order (module docs); `slot_out`
/// and `out` hold pairs and outputs from index `offset` on.
#[inline]
fn reduce_position(
    view: &PairView,
    s: usize,
    slot_out: &[u32],
    out: &[ContactOutput],
    offset: usize,
) -> [V3; 2] {
    let (mut f, mut t) = (V3::zeros(), V3::zeros());
    for &e in view.reduction(s) {
        let k = slot_out[(e & !ROLE_J) as usize - offset];
        if k == APART {
            continue;
        }
        let o = &out[k as usize - offset];
        if e & ROLE_J != 0 {
            f -= o.force;
            t += o.torque_j;
        } else {
            f += o.force;
            t += o.torque_i;
        }
    }
    [f, t]
}

impl PairForces {
    /// Evaluates every pair of `pairs` for the particles `p` (the list built for them),
    /// advancing or using the history as `history` says, with time step `dt` (s), and sums
    /// the contact force and torque of every particle ([`PairForces::sum`]).
    pub fn evaluate(
        &mut self,
        pairs: &mut PairList,
        p: &Particles,
        mats: &Materials,
        model: &ContactModel,
        dt: f64,
        history: HistoryUse,
    ) {
        self.identity = pairs.is_identity();
        if !self.identity {
            self.load(pairs, p);
        }
        let periodic = pairs.periodic().copied();
        let n = p.len();
        let np = pairs.len();
        self.out.resize(np, ContactOutput::default());
        self.slot_out.resize(np, APART);
        self.sums.resize(n, [V3::zeros(); 2]);
        let (view, hist) = pairs.split_mut();
        // rows split into one range per thread with about equal numbers of pairs (any split
        // gives the same result)
        let nt = rayon::current_num_threads().clamp(1, n.max(1));
        let first = view.row_first;
        let mut rows = vec![0usize; nt + 1];
        for c in 1..nt {
            let target = (np * c / nt) as u32;
            rows[c] = first[..n].partition_point(|&f| f < target).max(rows[c - 1]);
        }
        rows[nt] = n;
        let mut work = Vec::with_capacity(nt);
        let (mut hist, mut slot_out, mut out, mut sums) = (
            hist,
            &mut self.slot_out[..],
            &mut self.out[..],
            &mut self.sums[..],
        );
        for c in 0..nt {
            let len = (first[rows[c + 1]] - first[rows[c]]) as usize;
            let (h, h_rest) = hist.split_at_mut(len);
            let (so, so_rest) = slot_out.split_at_mut(len);
            let (o, o_rest) = out.split_at_mut(len);
            let (sm, sm_rest) = sums.split_at_mut(rows[c + 1] - rows[c]);
            work.push((rows[c]..rows[c + 1], h, so, o, sm));
            (hist, slot_out, out, sums) = (h_rest, so_rest, o_rest, sm_rest);
        }
        let frame = match self.identity {
            true => Frame {
                x: &p.x,
                v: &p.v,
                omega: &p.omega,
                radius: &p.radius,
                mass: &p.mass,
                atom_type: &p.atom_type,
                periodic: periodic.as_ref(),
            },
            false => Frame {
                x: &self.x,
                v: &self.v,
                omega: &self.omega,
                radius: &self.radius,
                mass: &self.mass,
                atom_type: &self.atom_type,
                periodic: periodic.as_ref(),
            },
        };
        let (si, sj) = (view.si, view.sj);
        let deferred: Vec<Vec<usize>> = work
            .into_par_iter()
            .map(|(range, hist, slot_out, out, sums)| {
                let base = first[range.start] as usize;
                let mut used = 0;
                let mut later = Vec::new();
                for a in range.clone() {
                    for k in first[a] as usize..first[a + 1] as usize {
                        let (i, j) = (si[k] as usize, sj[k] as usize);
                        let q = k - base;
                        let o = evaluate_pair(&frame, i, j, &mut hist[q], mats, model, dt, history);
                        slot_out[q] = match o {
                            Some(o) => {
                                out[used] = o;
                                used += 1;
                                (base + used - 1) as u32
                            }
                            None => APART,
                        };
                    }
                    if view.low_row(a) >= range.start {
                        sums[a - range.start] = reduce_position(&view, a, slot_out, out, base);
                    } else {
                        later.push(a);
                    }
                }
                later
            })
            .collect();
        for s in deferred.into_iter().flatten() {
            self.sums[s] = reduce_position(&view, s, &self.slot_out, &self.out, 0);
        }
        if self.identity {
            return;
        }
        // by particle index, so that the per-particle pass reads them in its own order
        self.sums_by_index.resize(n, [V3::zeros(); 2]);
        let (sums, rank) = (&self.sums, pairs.ranks());
        self.sums_by_index
            .par_iter_mut()
            .zip(rank)
            .with_min_len(STREAM_BLOCK)
            .for_each(|(dst, &s)| *dst = sums[s as usize]);
    }

    /// Copies positions, velocities and angular velocities into the list's spatial order,
    /// and radii, masses and types after a build.
    fn load(&mut self, pairs: &PairList, p: &Particles) {
        let order = pairs.order();
        let gather = |dst: &mut Vec<V3>, src: &[V3]| {
            dst.resize(order.len(), V3::zeros());
            dst.par_iter_mut()
                .zip(order)
                .with_min_len(STREAM_BLOCK)
                .for_each(|(d, &i)| *d = src[i as usize]);
        };
        gather(&mut self.x, &p.x);
        gather(&mut self.v, &p.v);
        gather(&mut self.omega, &p.omega);
        if self.generation != Some(pairs.generation()) {
            self.radius.clear();
            self.radius
                .extend(order.iter().map(|&i| p.radius[i as usize]));
            self.mass.clear();
            self.mass.extend(order.iter().map(|&i| p.mass[i as usize]));
            self.atom_type.clear();
            self.atom_type
                .extend(order.iter().map(|&i| p.atom_type[i as usize]));
            self.generation = Some(pairs.generation());
        }
    }

    /// The total contact force (N) and torque (N·m) on particle `i` from the last evaluation.
    #[inline]
    pub fn sum(&self, i: usize) -> (V3, V3) {
        let [f, t] = match self.identity {
            true => self.sums[i],
            false => self.sums_by_index[i],
        };
        (f, t)
    }
}
