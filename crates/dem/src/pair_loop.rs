//! The particle–particle contact forces of one step, over the half pair list.
//!
//! The list stores its pairs row by row in the particles' spatial order ([`PairList`]): row a
//! holds the pairs of sorted position a with the partners b > a, ascending. During a run the
//! particles themselves are stored in that order ([`PairList::is_identity`]) and the pass
//! reads their arrays directly; otherwise (the set-up, the steps before the first rebuild) the
//! per-particle data are copied into that order, so a pass reads from nearby memory either
//! way.
//!
//! As LIGGGHTS's half-list pair loop does (Newton's third law), each pair in contact adds its
//! force and torques to both of its particles' sums as soon as it is evaluated: +F and the
//! i-torque to the pair's i, −F and the j-torque to its j (i the member with the smaller
//! insertion index, [`PairList::build_keyed`]). Sweeping the rows in order, a sorted position
//! p receives the contributions of rows a < p in ascending a and then those of its own row in
//! ascending partner: its sum runs from zero over its contacts in *ascending sorted position
//! of the partner*. That is the canonical order of the sums.
//!
//! Each thread takes a contiguous range of rows. A sorted position whose pairs all lie in its
//! own thread's range is summed there directly, in the canonical order; one with a pair in an
//! earlier thread's range (a few cell layers at each range boundary) gets every contribution
//! written to its thread's *spill* list instead, and after all threads are done the spill
//! lists are added in thread order — again the canonical order. So the sums are the same bit
//! for bit on every thread count; they depend on the spatial order, i.e. on the positions at
//! the last list build.

use mesh::v3::V3;
use rayon::prelude::*;

use crate::contact::{
    contact_force, ContactInput, ContactModel, ContactOutput, History, HistoryUse,
};
use crate::material::Materials;
use crate::neighbor::PairList;
use crate::particles::Particles;
use crate::periodic::Periodic;
use crate::sim::STREAM_BLOCK;

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

/// A contribution to the sums of a sorted position owned by another thread or summed after
/// the threads (module docs): position, force (N), torque (N·m).
type Spill = (u32, V3, V3);

/// Adds a contact's force `f` and torque `t` to sorted position `s`: directly into `sums`
/// (rows `lo..hi` of this thread) when all of `s`'s pairs lie in this thread's range, else to
/// `spill`.
#[inline]
#[allow(clippy::too_many_arguments)]
fn add(
    s: usize,
    f: V3,
    t: V3,
    lo: usize,
    hi: usize,
    low_row: &[u32],
    sums: &mut [[V3; 2]],
    spill: &mut Vec<Spill>,
) {
    if s < hi && (lo == 0 || low_row[s] as usize >= lo) {
        let sum = &mut sums[s - lo];
        sum[0] += f;
        sum[1] += t;
    } else {
        spill.push((s as u32, f, t));
    }
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
        let (mut hist, mut sums) = (hist, &mut self.sums[..]);
        for c in 0..nt {
            let len = (first[rows[c + 1]] - first[rows[c]]) as usize;
            let (h, h_rest) = hist.split_at_mut(len);
            let (sm, sm_rest) = sums.split_at_mut(rows[c + 1] - rows[c]);
            work.push((rows[c]..rows[c + 1], h, sm));
            (hist, sums) = (h_rest, sm_rest);
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
        let (si, sj, low_row) = (view.si, view.sj, view.low_row);
        let spills: Vec<Vec<Spill>> = work
            .into_par_iter()
            .map(|(range, hist, sums)| {
                let (lo, hi) = (range.start, range.end);
                sums.fill([V3::zeros(); 2]);
                let base = first[lo] as usize;
                let mut spill = Vec::new();
                for k in base..first[hi] as usize {
                    let (i, j) = (si[k] as usize, sj[k] as usize);
                    let h = &mut hist[k - base];
                    if let Some(o) = evaluate_pair(&frame, i, j, h, mats, model, dt, history) {
                        add(i, o.force, o.torque_i, lo, hi, low_row, sums, &mut spill);
                        add(j, -o.force, o.torque_j, lo, hi, low_row, sums, &mut spill);
                    }
                }
                spill
            })
            .collect();
        for (s, f, t) in spills.into_iter().flatten() {
            let sum = &mut self.sums[s as usize];
            sum[0] += f;
            sum[1] += t;
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
