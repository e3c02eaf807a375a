//! Which Ksl a cell hands the fluid: foamgrain's conserving form (the default) or CFDEM's.
//!
//! With w_pc the share of particle p in cell c, β_p its implicit drag coefficient (kg/s), u_p
//! the fluid velocity at the particle (the drag's interpolation, m/s), v_p its velocity (m/s),
//! V_c the cell volume (m³), U_c the fluid velocity of the cell and ε_c its voidage:
//! * [`KslForm::Conserving`] (foamgrain, ADR 0004; [`crate::exchange`](mod@crate::exchange)):
//!   Ksl_c = Σ_p w_pc β_p / V_c and Us_c = Σ_p w_pc β_p v_p / Σ_p w_pc β_p, so that
//!   Σ_c V_c Ksl_c (U_c − Us_c) = Σ_p β_p (u_p − v_p) with the smooth interpolation;
//! * [`KslForm::Cfdem`] (CFDEMcoupling's `implicitCouple::impMomSource`; Madden et al. 2020,
//!   eq. 12): with F_c = Σ_p w_pc β_p (u_p − v_p) the implicit drag of the cell's particles (N,
//!   CFDEM's `impParticleForces`) and Us_c CFDEM's average of the particle velocities
//!   ([`UsAveraging`]),
//!   Ksl_c = |F_c| / (V_c |U_c − Us_c|) where |U_c − Us_c| > 10⁻¹⁵ m/s (OpenFOAM's `SMALL`) and
//!   ε_c < `maxAlpha` (1 − `minAlphaP`, default 1 − 10⁻¹⁵), else 0; then capped at `KslLimit`
//!   (default 10¹⁰ kg/(m³ s)). Only the magnitude of F_c is kept: the fluid's momentum loss
//!   V_c Ksl_c (U_c − Us_c) has F_c's magnitude along U_c − Us_c, so it equals F_c when the
//!   cell's drag is parallel to U_c − Us_c (e.g. one velocity for all its particles and u_p =
//!   U_c), and differs otherwise: the form does not conserve momentum.
//!
//! The two forms agree exactly when every particle in a cell has the same velocity v and u_p =
//! U_c (centre interpolation): then Us_c = v in both and |F_c| = Σ w β |U_c − v|.
//!
//! The sums CFDEM's form needs (Σ w F, Σ w, Σ w v) are gathered with the conserving sums
//! ([`CfdemSums`], one pass over the particles); the form itself needs U and ε of the cell and
//! is applied where they are held ([`form_cfdem`]).

use mesh::v3::V3;

/// OpenFOAM's `SMALL` (double precision): CFDEM's guard on |U − Us| and its default
/// `1 − maxAlpha`.
pub const SMALL: f64 = 1e-15;

/// CFDEM's default `KslLimit`, kg/(m³ s).
pub const DEFAULT_KSL_LIMIT: f64 = 1e10;

/// How Us averages the velocities of a cell's particles in CFDEM's form (`averagingModel`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UsAveraging {
    /// `dense`: Us_c = Σ_p w_pc v_p / Σ_p w_pc (the share-weighted mean).
    #[default]
    Dense,
    /// `dilute`: Us_c = v of the last particle (in particle order) with a positive share in
    /// the cell (CFDEM's `dilute::setVectorAverage`: each particle overwrites the cell's value).
    Dilute,
}

/// CFDEM's form and its settings (`implicitCoupleProps`, `averagingModel`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CfdemKsl {
    /// `KslLimit`: the cap on Ksl, kg/(m³ s).
    pub limit: f64,
    /// `maxAlpha` = 1 − `minAlphaP`: cells with ε at or above it get Ksl = 0.
    pub max_voidage: f64,
    /// How Us averages the particle velocities.
    pub averaging: UsAveraging,
}

impl Default for CfdemKsl {
    fn default() -> Self {
        CfdemKsl {
            limit: DEFAULT_KSL_LIMIT,
            max_voidage: 1.0 - SMALL,
            averaging: UsAveraging::Dense,
        }
    }
}

/// The Ksl form (`implicitCoupleProps/KslForm`, module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum KslForm {
    /// foamgrain's: Ksl = Σ w β / V, Us β-weighted; conserves momentum.
    #[default]
    Conserving,
    /// CFDEM's: Ksl = |Σ w F| / (V |U − Us|).
    Cfdem(CfdemKsl),
}

impl KslForm {
    /// CFDEM's settings, `None` for the conserving form.
    pub fn cfdem(&self) -> Option<CfdemKsl> {
        match self {
            KslForm::Conserving => None,
            KslForm::Cfdem(c) => Some(*c),
        }
    }
}

/// Per-cell sums of CFDEM's form over the particles added in particle order.
#[derive(Clone, Debug, PartialEq)]
pub struct CfdemSums {
    /// How Us averages.
    pub averaging: UsAveraging,
    /// Σ_p w_pc β_p (u_p − v_p): the implicit drag of the cell's particles, N.
    pub drag: Vec<V3>,
    /// Σ_p w_pc (dimensionless).
    pub weight: Vec<f64>,
    /// Σ_p w_pc v_p (m/s) with `dense`; with `dilute` v of the last particle with w_pc > 0.
    pub velocity: Vec<V3>,
}

/// Values per cell of [`CfdemSums`] when summed over ranks: Σ w F (3), Σ w, Σ w v (3).
pub const CFDEM_SUMS_WIDTH: usize = 7;

impl CfdemSums {
    /// Zero sums on `n_cells` cells.
    pub fn new(n_cells: usize, averaging: UsAveraging) -> CfdemSums {
        CfdemSums {
            averaging,
            drag: vec![V3::zeros(); n_cells],
            weight: vec![0.0; n_cells],
            velocity: vec![V3::zeros(); n_cells],
        }
    }

    /// Adds share `w` of a particle with drag coefficient `b` (kg/s), fluid velocity at the
    /// particle `u` and velocity `v` (m/s) to cell `c`.
    #[inline]
    pub fn add(&mut self, c: usize, w: f64, b: f64, u: V3, v: V3) {
        let wb = w * b;
        for a in 0..3 {
            self.drag[c][a] += wb * (u[a] - v[a]);
        }
        self.weight[c] += w;
        match self.averaging {
            UsAveraging::Dense => {
                for a in 0..3 {
                    self.velocity[c][a] += w * v[a];
                }
            }
            UsAveraging::Dilute => {
                if w > 0.0 {
                    self.velocity[c] = v;
                }
            }
        }
    }

    /// Cell `c`'s [`CFDEM_SUMS_WIDTH`] values appended to `out`.
    pub fn record(&self, c: usize, out: &mut Vec<f64>) {
        let (d, v) = (self.drag[c], self.velocity[c]);
        out.extend_from_slice(&[d[0], d[1], d[2], self.weight[c], v[0], v[1], v[2]]);
    }

    /// Cell `c` set from a record of [`CfdemSums::record`]'s layout (summed over ranks).
    pub fn set(&mut self, c: usize, s: &[f64]) {
        self.drag[c] = V3::new(s[0], s[1], s[2]);
        self.weight[c] = s[3];
        self.velocity[c] = V3::new(s[4], s[5], s[6]);
    }

    /// CFDEM's Us of cell `c`, m/s (0 where no particle has a share).
    pub fn us(&self, c: usize) -> V3 {
        let w = self.weight[c];
        match self.averaging {
            _ if w <= 0.0 => V3::zeros(),
            UsAveraging::Dense => self.velocity[c].map(|x| x / w),
            UsAveraging::Dilute => self.velocity[c],
        }
    }
}

/// CFDEM's Ksl of one cell, kg/(m³ s) (module docs): drag `drag` = Σ w F (N), fluid velocity
/// `u` and Us `us` (m/s), voidage `eps`, volume `volume` (m³).
pub fn cfdem_ksl(settings: &CfdemKsl, drag: V3, u: V3, us: V3, eps: f64, volume: f64) -> f64 {
    let ur = (u - us).norm();
    let ksl = if ur > SMALL && eps < settings.max_voidage {
        drag.norm() / ur / volume
    } else {
        0.0
    };
    ksl.min(settings.limit)
}

/// Ksl and Us of CFDEM's form on every cell from `sums`, with the cells' fluid velocity `u`,
/// voidage `eps` and volumes `volumes` (same lengths): overwrites `ksl` and `us`.
pub fn form_cfdem(
    settings: &CfdemKsl,
    sums: &CfdemSums,
    u: &[V3],
    eps: &[f64],
    volumes: &[f64],
    ksl: &mut [f64],
    us: &mut [V3],
) {
    for c in 0..ksl.len() {
        us[c] = sums.us(c);
        ksl[c] = cfdem_ksl(settings, sums.drag[c], u[c], us[c], eps[c], volumes[c]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three particles in one cell of V = 2·10⁻³ m³ with U = u_p = (1, 0, 0) m/s: shares w,
    /// β (kg/s) and velocities v. The expected values were evaluated independently (python:
    /// F = Σ w β (U − v), Us = Σ w v / Σ w, Ksl = |F| / (|U − Us| V); Σ w β / V and
    /// Σ w β v / Σ w β for the conserving form).
    const PARTICLES: [(f64, f64, V3); 3] = [
        (1.0, 0.02, V3::new(0.2, 0.1, 0.0)),
        (0.5, 0.05, V3::new(0.6, -0.3, 0.1)),
        (0.25, 0.01, V3::new(-0.1, 0.0, 0.4)),
    ];
    const U: V3 = V3::new(1.0, 0.0, 0.0);
    const V: f64 = 2e-3;

    fn sums(averaging: UsAveraging) -> CfdemSums {
        let mut s = CfdemSums::new(1, averaging);
        for (w, b, v) in PARTICLES {
            s.add(0, w, b, U, v);
        }
        s
    }

    #[test]
    fn cfdem_ksl_of_one_cell_by_hand() {
        let s = sums(UsAveraging::Dense);
        let us = s.us(0);
        let expected = [
            0.2714285714285714,
            -0.028571428571428564,
            0.08571428571428573,
        ];
        for a in 0..3 {
            assert!((us[a] - expected[a]).abs() < 1e-15, "{us:?}");
        }
        let k = CfdemKsl::default();
        let ksl = cfdem_ksl(&k, s.drag[0], U, us, 0.5, V);
        assert!((ksl - 20.0774867985363).abs() < 1e-12, "{ksl}");
        // the conserving form of the same particles is 23.75 (Σ w β / V): the forms differ
        // when the velocities differ
        let swb: f64 = PARTICLES.iter().map(|(w, b, _)| w * b).sum();
        assert!((swb / V - 23.75).abs() < 1e-12);
        // the cap, the guard on |U − Us| and maxAlpha
        let capped = CfdemKsl { limit: 10.0, ..k };
        assert_eq!(cfdem_ksl(&capped, s.drag[0], U, us, 0.5, V), 10.0);
        assert_eq!(cfdem_ksl(&k, s.drag[0], us, us, 0.5, V), 0.0);
        let dilute_cells = CfdemKsl {
            max_voidage: 0.5,
            ..k
        };
        assert_eq!(cfdem_ksl(&dilute_cells, s.drag[0], U, us, 0.5, V), 0.0);
    }

    #[test]
    fn dilute_takes_the_last_particle_with_a_share() {
        let mut s = sums(UsAveraging::Dilute);
        assert_eq!(s.us(0), PARTICLES[2].2);
        s.add(0, 0.0, 1.0, U, V3::new(9.0, 9.0, 9.0));
        assert_eq!(s.us(0), PARTICLES[2].2, "a zero share does not overwrite");
        assert_eq!(CfdemSums::new(1, UsAveraging::Dilute).us(0), V3::zeros());
    }

    #[test]
    fn a_record_round_trips() {
        let s = sums(UsAveraging::Dense);
        let mut out = Vec::new();
        s.record(0, &mut out);
        assert_eq!(out.len(), CFDEM_SUMS_WIDTH);
        let mut t = CfdemSums::new(1, UsAveraging::Dense);
        t.set(0, &out);
        assert_eq!(t, s);
    }
}
