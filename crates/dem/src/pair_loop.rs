//! The particle–particle contact forces of one step, over the half pair list.
//!
//! The list stores its pairs row by row in the particles' spatial order ([`PairList`]); the
//! per-particle data are copied into that order each step, so a pass reads from nearby memory.
//! Each particle (sorted position) owns a range of *slots*, one per pair it belongs to, ordered
//! by the partner's particle index ([`PairView::reduction_range`]). Each thread takes a
//! contiguous range of rows and, row a after row a:
//! 1. *evaluates* the pairs of row a: a pair in contact writes its force and torque on i into
//!    i's slot and −force and the torque on j into j's slot, and advances its history; a pair
//!    apart resets its history (and its slots to zero, if it was in contact at the last
//!    evaluation — slots of pairs apart hold zero);
//! 2. *reduces* sorted position a, whose pairs all lie in rows ≤ a: its force and torque are
//!    its slots summed from zero in order. Positions with a pair in an earlier thread's
//!    range are reduced after all threads are done (a thread writes slots of positions after
//!    its range into a list applied then).
//!
//! That order is the one a serial loop over particles i with their partners j > i produces
//! (−F added where the former subtracted F is the same IEEE operation, and a zero slot leaves
//! a sum that started from +0 unchanged), so the sums are those of the serial loop bit for
//! bit, for every thread count and whatever the spatial order (a run continued from a restart
//! file builds its list at other positions and still sums alike). The reduction reads its
//! slots in one sequential sweep.

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
    /// The list generation the slots and `live` were laid out for.
    slots_generation: Option<u64>,
    /// Per reduction slot ([`crate::neighbor::PairView::slots`]): the force (N) and torque
    /// (N·m) of the slot's pair on the slot's particle; zero for pairs apart.
    slots: Vec<[V3; 2]>,
    /// Per pair: whether its slots hold a contact (written at the last evaluation).
    live: Vec<bool>,
    /// Per sorted position: total contact force (N) and torque (N·m).
    sums: Vec<[V3; 2]>,
    /// The same by particle index.
    sums_by_index: Vec<[V3; 2]>,
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

/// Σ of `slots` from zero, in order: the force and torque on a sorted position.
#[inline]
fn sum_slots(slots: &[[V3; 2]]) -> [V3; 2] {
    let (mut f, mut t) = (V3::zeros(), V3::zeros());
    for [sf, st] in slots {
        f += sf;
        t += st;
    }
    [f, t]
}

/// A slot write for a position after the writing thread's range: (slot, force, torque).
type LateWrite = (u32, [V3; 2]);

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
        self.load(pairs, p);
        let periodic = pairs.periodic().copied();
        let n = self.x.len();
        let np = pairs.len();
        if self.slots_generation != Some(pairs.generation()) {
            self.slots.clear();
            self.slots.resize(2 * np, [V3::zeros(); 2]);
            self.live.clear();
            self.live.resize(np, false);
            self.slots_generation = Some(pairs.generation());
        }
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
        let (mut hist, mut live, mut slots, mut sums) = (
            hist,
            &mut self.live[..],
            &mut self.slots[..],
            &mut self.sums[..],
        );
        let slot_start = |a: usize| {
            if a < n {
                view.reduction_range(a).start
            } else {
                2 * np
            }
        };
        for c in 0..nt {
            let len = (first[rows[c + 1]] - first[rows[c]]) as usize;
            let (h, h_rest) = hist.split_at_mut(len);
            let (l, l_rest) = live.split_at_mut(len);
            let (sl, sl_rest) = slots.split_at_mut(slot_start(rows[c + 1]) - slot_start(rows[c]));
            let (sm, sm_rest) = sums.split_at_mut(rows[c + 1] - rows[c]);
            work.push((rows[c]..rows[c + 1], h, l, sl, sm));
            (hist, live, slots, sums) = (h_rest, l_rest, sl_rest, sm_rest);
        }
        let frame = Frame {
            x: &self.x,
            v: &self.v,
            omega: &self.omega,
            radius: &self.radius,
            mass: &self.mass,
            atom_type: &self.atom_type,
            periodic: periodic.as_ref(),
        };
        let (si, sj) = (view.si, view.sj);
        let done: Vec<(Vec<usize>, Vec<LateWrite>)> = work
            .into_par_iter()
            .map(|(range, hist, live, slots, sums)| {
                let base = first[range.start] as usize;
                let slot_base = slot_start(range.start);
                let slot_end = slot_start(range.end);
                let mut later = Vec::new();
                let mut late_writes: Vec<LateWrite> = Vec::new();
                // slot `at` of this range, or of a later one
                let put = |slots: &mut [[V3; 2]], late: &mut Vec<LateWrite>, at, value| {
                    if at < slot_end {
                        slots[at - slot_base] = value;
                    } else {
                        late.push((at as u32, value));
                    }
                };
                for a in range.clone() {
                    for k in first[a] as usize..first[a + 1] as usize {
                        let (i, j) = (si[k] as usize, sj[k] as usize);
                        let q = k - base;
                        let o = evaluate_pair(&frame, i, j, &mut hist[q], mats, model, dt, history);
                        let (at_i, at_j) = view.slots(k);
                        match o {
                            Some(o) => {
                                put(slots, &mut late_writes, at_i, [o.force, o.torque_i]);
                                put(slots, &mut late_writes, at_j, [-o.force, o.torque_j]);
                                live[q] = true;
                            }
                            None if live[q] => {
                                put(slots, &mut late_writes, at_i, [V3::zeros(); 2]);
                                put(slots, &mut late_writes, at_j, [V3::zeros(); 2]);
                                live[q] = false;
                            }
                            None => {}
                        }
                    }
                    if view.low_row(a) >= range.start {
                        let at = view.reduction_range(a);
                        sums[a - range.start] =
                            sum_slots(&slots[at.start - slot_base..at.end - slot_base]);
                    } else {
                        later.push(a);
                    }
                }
                (later, late_writes)
            })
            .collect();
        for (_, late_writes) in &done {
            for &(at, value) in late_writes {
                self.slots[at as usize] = value;
            }
        }
        for (later, _) in done {
            for s in later {
                self.sums[s] = sum_slots(&self.slots[view.reduction_range(s)]);
            }
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
        let [f, t] = self.sums_by_index[i];
        (f, t)
    }
}
