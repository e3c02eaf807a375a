//! Conduction between touching particles: LIGGGHTS 3.8's `fix heat/gran` (=
//! `heat/gran/conduction`, `fix_heat_gran_conduction.cpp`).
//!
//! For a pair i, j with centre distance r < r_i + r_j, the heat flow into i is
//!
//!   Q_ij = h_c (T_j − T_i),   h_c = 4 k_i k_j / (k_i + k_j) · √A   (W/K)
//!
//! (k the types' `thermalConductivity`, W/(m K); h_c = 0 if either k < 10⁻⁶), and j receives
//! −Q_ij. The contact area A (m²), by `contact_area`:
//! - `overlap` (default): the circle where the two sphere surfaces cross,
//!   A = −π/4 · (r − r_i − r_j)(r + r_i − r_j)(r − r_i + r_j)(r + r_i + r_j) / r²,
//!   or π min(r_i, r_j)² when r < max(r_i, r_j) (one centre inside the other sphere); with
//!   `area_correction yes` the overlap r_i + r_j − r is first scaled by (Y*/Y*_orig)^(1/1.5),
//!   Y* from `youngsModulus`, Y*_orig from `youngsModulusOriginal` (Hertz's stress–strain
//!   exponent 1.5), so a softened material conducts as the original one would;
//! - `projection`: π max(r_i, r_j)²;
//! - `constant A`.
//!
//! The formulas are evaluated in LIGGGHTS's operation order. Walls with a `temperature` conduct
//! too ([`super::walls`]).
//!
//! Order: the flows of all pairs are computed in parallel, one per pair of the list, then added
//! to the particles serially in the list's order — row by row in the spatial order, which is
//! the order in which the pair loop sums forces ([`crate::pair_loop`]); so the sums are the same
//! for every thread count.

use rayon::prelude::*;

use crate::neighbor::PairList;
use crate::particles::Particles;

/// Conductivity below which a contact does not conduct (W/(m K)): LIGGGHTS's
/// `SMALL_FIX_HEAT_GRAN`.
pub const SMALL_CONDUCTIVITY: f64 = 1e-6;

/// Hertz's stress–strain exponent (`stressStrainExponent` of `model hertz`), for
/// `area_correction`.
const HERTZ_EXPONENT: f64 = 1.5;

/// `contact_area` of `heat/gran`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactArea {
    /// `overlap`: the cross-section of the two spheres' surfaces.
    Overlap,
    /// `projection`: π max(r_i, r_j)².
    Projection,
    /// `constant A` (m²).
    Constant(f64),
}

/// `heat/gran`'s conduction settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Conduction {
    /// `thermalConductivity` per atom type (W/(m K)).
    pub conductivity: Vec<f64>,
    /// How the contact area is computed.
    pub area: ContactArea,
    /// With `area_correction yes`: per type pair (ntypes × ntypes, row-major), the factor the
    /// overlap is scaled by, (Y*/Y*_orig)^(1/1.5).
    pub deltan_ratio: Option<Vec<f64>>,
}

/// Y* of two types, 1/((1 − ν_i²)/Y_i + (1 − ν_j²)/Y_j) (Pa), as `fix heat/gran` computes it
/// for the area correction.
fn y_eff(y: &[f64], nu: &[f64], i: usize, j: usize) -> f64 {
    1. / ((1. - nu[i] * nu[i]) / y[i] + (1. - nu[j] * nu[j]) / y[j])
}

/// The `area_correction` factors per type pair (row-major): (Y*/Y*_orig)^(1/1.5), from E
/// (`youngsModulus`), E_orig (`youngsModulusOriginal`) and ν per type.
pub fn deltan_ratio(y: &[f64], y_orig: &[f64], nu: &[f64]) -> Vec<f64> {
    let n = y.len();
    let mut r = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let ratio = y_eff(y, nu, i, j) / y_eff(y_orig, nu, i, j);
            r.push(ratio.powf(1. / HERTZ_EXPONENT));
        }
    }
    r
}

impl Conduction {
    /// The contact area of particles of radii `ri`, `rj` (types `ti`, `tj`, 1-based) whose
    /// centres are `r` apart (m²).
    pub fn contact_area(&self, r: f64, ri: f64, rj: f64, ti: u32, tj: u32) -> f64 {
        match self.area {
            ContactArea::Constant(a) => a,
            ContactArea::Projection => {
                let rmax = ri.max(rj);
                std::f64::consts::PI * rmax * rmax
            }
            ContactArea::Overlap => {
                let radsum = ri + rj;
                let mut r = r;
                if let Some(ratio) = &self.deltan_ratio {
                    let n = self.conductivity.len();
                    let delta_n = (radsum - r) * ratio[(ti as usize - 1) * n + tj as usize - 1];
                    r = radsum - delta_n;
                }
                if r < ri.max(rj) {
                    let a = ri.min(rj);
                    a * a * std::f64::consts::PI
                } else {
                    -std::f64::consts::PI / 4.0
                        * ((r - ri - rj) * (r + ri - rj) * (r - ri + rj) * (r + ri + rj))
                        / (r * r)
                }
            }
        }
    }

    /// h_c of two types with contact area `a` (W/K).
    pub fn conductance(&self, ti: u32, tj: u32, a: f64) -> f64 {
        let ki = self.conductivity[ti as usize - 1];
        let kj = self.conductivity[tj as usize - 1];
        if ki < SMALL_CONDUCTIVITY || kj < SMALL_CONDUCTIVITY {
            0.
        } else {
            4. * ki * kj / (ki + kj) * a.sqrt()
        }
    }

    /// Adds the conduction of every touching pair of `pairs` to `flux` (W), +Q_ij to the pair's
    /// i and −Q_ij to its j, in the list's order; `pair_flux` is a buffer.
    pub fn pass(
        &self,
        pairs: &PairList,
        p: &Particles,
        temp: &[f64],
        pair_flux: &mut Vec<f64>,
        flux: &mut [f64],
    ) {
        let periodic = pairs.periodic();
        let (x, rad, ty) = (&p.x, &p.radius, &p.atom_type);
        pair_flux.clear();
        pair_flux.resize(pairs.len(), 0.0);
        pair_flux
            .par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(k, q)| {
                let (i, j) = pairs.pair(k);
                let d = match periodic {
                    None => x[i] - x[j],
                    Some(per) => per.delta(x[i], x[j]),
                };
                let rsq = d.dot(&d);
                let radsum = rad[i] + rad[j];
                if rsq >= radsum * radsum {
                    return;
                }
                let a = self.contact_area(rsq.sqrt(), rad[i], rad[j], ty[i], ty[j]);
                *q = (temp[j] - temp[i]) * self.conductance(ty[i], ty[j], a);
            });
        for (k, &q) in pair_flux.iter().enumerate() {
            if q != 0.0 {
                let (i, j) = pairs.pair(k);
                flux[i] += q;
                flux[j] -= q;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn overlap(k: f64) -> Conduction {
        Conduction {
            conductivity: vec![k],
            area: ContactArea::Overlap,
            deltan_ratio: None,
        }
    }

    #[test]
    fn overlap_area_is_the_lens_circle() {
        // two unit spheres 1.8 apart cross on a circle of radius √(1 − 0.9²)
        let c = overlap(1.0);
        let a = c.contact_area(1.8, 1.0, 1.0, 1, 1);
        let want = std::f64::consts::PI * (1.0 - 0.81);
        assert!((a - want).abs() < 1e-14, "{a} {want}");
        // unequal spheres: the circle's radius from the intersection of the two spheres
        let (r, r1, r2) = (2.5f64, 1.0f64, 2.0f64);
        let xc = (r * r + r1 * r1 - r2 * r2) / (2.0 * r);
        let want = std::f64::consts::PI * (r1 * r1 - xc * xc);
        let a = c.contact_area(r, r1, r2, 1, 1);
        assert!((a - want).abs() < 1e-14 * want.max(1.0), "{a} {want}");
        // a centre inside the other sphere: the smaller sphere's cross-section
        let a = c.contact_area(1.5, 1.0, 2.0, 1, 1);
        assert_eq!(a, std::f64::consts::PI);
    }

    #[test]
    fn conductance_is_the_harmonic_mean_times_root_area() {
        let c = Conduction {
            conductivity: vec![2.0, 6.0],
            area: ContactArea::Constant(4.0),
            deltan_ratio: None,
        };
        // 4·2·6/(2+6)·√4 = 12
        assert_eq!(c.conductance(1, 2, 4.0), 12.0);
        let c = Conduction {
            conductivity: vec![2.0, 1e-7],
            ..c
        };
        assert_eq!(c.conductance(1, 2, 4.0), 0.0);
    }

    #[test]
    fn area_correction_of_equal_moduli_changes_nothing() {
        let r = deltan_ratio(&[5e6], &[5e6], &[0.45]);
        assert_eq!(r, vec![1.0]);
        // E 100× softer than the original: the overlap shrinks by 100^(−2/3)
        let r = deltan_ratio(&[1e7], &[1e9], &[0.3]);
        assert!((r[0] - 0.01f64.powf(2.0 / 3.0)).abs() < 1e-15);
    }
}
