//! Momentum exchange fields per cell (ADR 0004), distributed with the voidage shares.
//!
//! With w_pc the renormalised share of particle p in cell c ([`Placement::for_each_weight`]),
//! V_c the cell volume (m³), β_p the implicit drag coefficient (kg/s), v_p the particle
//! velocity (m/s) and F_p the explicitly coupled part of the particle force (N):
//! * `Ksl_c = Σ_p w_pc β_p / V_c` (kg/(m³·s));
//! * `Us_c = Σ_p w_pc β_p v_p / Σ_p w_pc β_p` (m/s, 0 where Σ w β = 0);
//! * `f_c = −Σ_p w_pc F_p / V_c` (N/m³), the force density of the particles on the fluid.
//!
//! Hence Σ_c V_c Ksl_c = Σ_p β_p and Σ_c V_c f_c = −Σ_p F_p over the particles inside the mesh,
//! to round-off; a particle without any share (outside the mesh) is counted in
//! [`Outside`] with its β and force instead of being dropped. A particle partly outside the
//! mesh has its shares renormalised over the cells inside (ADR 0004), so it is counted whole.
//!
//! The sums run over particles in index order (`Sums`), so the result does not depend on the
//! number of threads; the per-cell finish runs in parallel. In the coupler the sums run
//! alongside the force loop ([`crate::forces::couplings_and_exchange`]).

use crate::interpolate::Placement;
use crate::ksl::CfdemSums;
use mesh::v3::V3;
use rayon::prelude::*;

/// What could not be put into a cell.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outside {
    /// Particles with no share in any cell.
    pub particles: usize,
    /// Σ β of those particles, kg/s.
    pub beta: f64,
    /// Σ explicit force of those particles, N.
    pub force: V3,
}

/// The exchange fields of one coupling step.
#[derive(Clone, Debug, PartialEq)]
pub struct Exchange {
    /// Implicit coefficient per cell, kg/(m³·s).
    pub ksl: Vec<f64>,
    /// β-weighted particle velocity per cell, m/s.
    pub us: Vec<V3>,
    /// Explicit force density on the fluid per cell, N/m³.
    pub f: Vec<V3>,
    /// What lay outside the mesh.
    pub outside: Outside,
    /// The per-cell sums of CFDEM's Ksl form ([`crate::ksl`]), `None` with the conserving
    /// form; `ksl` and `us` are CFDEM's once [`crate::ksl::form_cfdem`] has run.
    pub cfdem: Option<CfdemSums>,
}

impl Exchange {
    /// Σ_c V_c Ksl_c, kg/s (equals Σ β over the particles inside the mesh).
    pub fn total_ksl(&self, cell_volumes: &[f64]) -> f64 {
        self.ksl.iter().zip(cell_volumes).map(|(k, v)| k * v).sum()
    }

    /// Σ_c V_c Ksl_c Us_c, kg·m/s² (equals Σ β v over the particles inside the mesh).
    pub fn total_ksl_us(&self, cell_volumes: &[f64]) -> V3 {
        let mut s = V3::zeros();
        for ((k, u), v) in self.ksl.iter().zip(&self.us).zip(cell_volumes) {
            for a in 0..3 {
                s[a] += k * v * u[a];
            }
        }
        s
    }

    /// Σ_c V_c f_c, N (equals −Σ F over the particles inside the mesh).
    pub fn total_f(&self, cell_volumes: &[f64]) -> V3 {
        let mut s = V3::zeros();
        for (f, v) in self.f.iter().zip(cell_volumes) {
            for a in 0..3 {
                s[a] += f[a] * v;
            }
        }
        s
    }
}

/// The exchange fields for particles at `placement` with drag coefficients `beta` (kg/s),
/// velocities `velocity` (m/s) and explicit forces `force` (N), on cells of volumes
/// `cell_volumes` (m³). Slices are per particle (same length as the placement) and per cell.
pub fn exchange(
    placement: &Placement,
    cell_volumes: &[f64],
    beta: &[f64],
    velocity: &[V3],
    force: &[V3],
) -> Exchange {
    assert_eq!(beta.len(), placement.len(), "one β per particle");
    assert_eq!(velocity.len(), placement.len(), "one velocity per particle");
    assert_eq!(force.len(), placement.len(), "one force per particle");
    exchange_with(placement, cell_volumes, |i| {
        (beta[i], velocity[i], force[i])
    })
}

/// [`exchange`] with the per-particle (β, v, F) given by `particle(i)`.
pub fn exchange_with(
    placement: &Placement,
    cell_volumes: &[f64],
    particle: impl Fn(usize) -> (f64, V3, V3),
) -> Exchange {
    let mut sums = Sums::new(cell_volumes.len());
    for i in 0..placement.len() {
        let (b, v, fp) = particle(i);
        sums.add(placement, i, b, v, fp, V3::zeros());
    }
    sums.finish(cell_volumes)
}

/// Running sums of the exchange fields over particles added in index order: Σ w β, Σ w β v and
/// −Σ w F per cell, and what lay outside the mesh; with CFDEM's Ksl form also its sums.
pub(crate) struct Sums {
    sum_wb: Vec<f64>,
    sum_wbv: Vec<V3>,
    sum_wf: Vec<V3>,
    outside: Outside,
    cfdem: Option<CfdemSums>,
}

impl Sums {
    /// Zero sums on `n_cells` cells.
    pub(crate) fn new(n_cells: usize) -> Sums {
        Sums {
            sum_wb: vec![0.0; n_cells],
            sum_wbv: vec![V3::zeros(); n_cells],
            sum_wf: vec![V3::zeros(); n_cells],
            outside: Outside::default(),
            cfdem: None,
        }
    }

    /// As [`Sums::new`], also gathering `cfdem` (zero sums on the same cells), or not (`None`).
    pub(crate) fn with_cfdem(n_cells: usize, cfdem: Option<CfdemSums>) -> Sums {
        Sums {
            cfdem,
            ..Sums::new(n_cells)
        }
    }

    /// Adds particle `i` with drag coefficient `b` (kg/s), velocity `v` (m/s), explicit
    /// force `fp` (N) and fluid velocity at the particle `u` (m/s; read by CFDEM's Ksl form
    /// only) to its cells, or to [`Outside`] when it has no share.
    #[inline]
    pub(crate) fn add(&mut self, placement: &Placement, i: usize, b: f64, v: V3, fp: V3, u: V3) {
        if !placement.inside(i) {
            self.outside.particles += 1;
            self.outside.beta += b;
            for a in 0..3 {
                self.outside.force[a] += fp[a];
            }
            return;
        }
        placement.for_each_weight(i, |c, w| {
            let c = c as usize;
            let wb = w * b;
            self.sum_wb[c] += wb;
            for a in 0..3 {
                self.sum_wbv[c][a] += wb * v[a];
                self.sum_wf[c][a] -= w * fp[a];
            }
            if let Some(k) = self.cfdem.as_mut() {
                k.add(c, w, b, u, v);
            }
        });
    }

    /// Ksl = Σ w β / V, Us = Σ w β v / Σ w β (0 where Σ w β = 0) and f = −Σ w F / V on cells of
    /// volumes `cell_volumes` (m³); parallel over cells.
    pub(crate) fn finish(self, cell_volumes: &[f64]) -> Exchange {
        let Sums {
            sum_wb: mut ksl,
            sum_wbv: mut us,
            sum_wf: mut f,
            outside,
            cfdem,
        } = self;
        ksl.par_iter_mut()
            .zip(us.par_iter_mut())
            .zip(f.par_iter_mut())
            .zip(cell_volumes.par_iter())
            .for_each(|(((k, u), f), &volume)| {
                let sum_wb = *k;
                *u = if sum_wb != 0.0 {
                    u.map(|x| x / sum_wb)
                } else {
                    V3::zeros()
                };
                let inv = 1.0 / volume;
                *k = sum_wb * inv;
                *f = f.map(|x| x * inv);
            });
        Exchange {
            ksl,
            us,
            f,
            outside,
            cfdem,
        }
    }
}
