//! Drag on a coarse-grained parcel: a sphere of diameter d_p that stands for CG³ real particles
//! of diameter d_p/CG (LIGGGHTS-PFM's `coarsegraining CG`).
//!
//! CFDEMcoupling-PFM's drag models (`GidaspowDrag`, `KochHillDrag`, `BeetstraDrag`,
//! `DiFeliceDrag`, `SchillerNaumannDrag`: their `scaleDia_`, set from the Props key `scale` or
//! else from LIGGGHTS's `cg`, and `scaleDrag_`) evaluate Re and the law with the real
//! particle's diameter d_p/CG and multiply its force by CG³ (Gidaspow and Koch–Hill through
//! the parcel's volume, V_p β_p(d_p/CG); Di Felice and Schiller–Naumann through
//! d_p² CG = (d_p/CG)² CG³; Beetstra explicitly) and by `scaleDrag`:
//!
//! β_parcel(ε, d_p, |u − v|) = scaleDrag · CG³ · β(ε, d_p/CG, |u − v|)   (kg/s),
//!
//! so a bed of parcels at the voidage and slip of a bed of real particles feels the same drag
//! per unit volume (Radl et al. 2011, the parcel approach). The local Sauter-mean diameter of
//! the polydisperse laws is the real particles' too (PFM's `averagingModel::setDSauter`
//! divides the radii by CG).

use crate::error::ClosureError;
use crate::input::DragInput;

/// A parcel's coarse graining as the drag sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parcel {
    /// CG ≥ 1: a parcel of diameter d stands for CG³ particles of diameter d/CG.
    pub cg: f64,
    /// PFM's `scaleDrag` (> 0; default 1): a further factor on the drag.
    pub scale_drag: f64,
}

impl Parcel {
    /// Real particles: CG = 1, `scaleDrag` 1 (the drag is the law's, bit for bit).
    pub const REAL: Parcel = Parcel {
        cg: 1.0,
        scale_drag: 1.0,
    };

    /// A checked parcel: CG ≥ 1 (LIGGGHTS-PFM's bound) and `scaleDrag` > 0, both finite.
    pub fn new(cg: f64, scale_drag: f64) -> Result<Parcel, ClosureError> {
        if !(cg.is_finite() && cg >= 1.0) {
            return Err(ClosureError::BadParameter {
                model: "coarse graining",
                key: "scale",
                value: cg,
                reason: "must be ≥ 1",
            });
        }
        if !(scale_drag.is_finite() && scale_drag > 0.0) {
            return Err(ClosureError::BadParameter {
                model: "coarse graining",
                key: "scaleDrag",
                value: scale_drag,
                reason: "must be > 0",
            });
        }
        Ok(Parcel { cg, scale_drag })
    }

    /// Whether this is [`Parcel::REAL`] (the drag is then not touched at all).
    #[inline]
    pub fn is_real(&self) -> bool {
        *self == Parcel::REAL
    }

    /// The real particle a parcel's drag input stands for: diameter and Sauter diameter / CG.
    #[inline]
    pub fn real_particle(&self, x: &DragInput) -> DragInput {
        let mut r = *x;
        r.diameter /= self.cg;
        r.sauter_diameter /= self.cg;
        r
    }

    /// The parcel's β (kg/s) from `beta_real`, the law evaluated on [`Parcel::real_particle`]:
    /// scaleDrag · CG³ · β_real.
    #[inline]
    pub fn scale(&self, beta_real: f64) -> f64 {
        self.scale_drag * self.cg * self.cg * self.cg * beta_real
    }
}

impl Default for Parcel {
    fn default() -> Self {
        Parcel::REAL
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drag::{DragClosure, DragLaw};
    use std::f64::consts::PI;

    const MU: f64 = 1.5e-4 * 10.0;
    const RHO: f64 = 10.0;

    /// A packed bed of parcels (Gidaspow's Ergun branch, ε < 0.8) gives Ergun's pressure
    /// gradient of the *real* particles, written out by hand: Σ β (u − v) / V_bed =
    /// ε [150 μ (1 − ε)² U/(ε³ d²) + 1.75 ρ (1 − ε) U²/(ε³ d)] with U = ε |u − v| the
    /// superficial slip and d the real diameter (Ergun 1952; model A's drag carries ε times the
    /// gradient, the pressure-gradient force −V_p∇p the other (1 − ε)).
    #[test]
    fn a_parcel_bed_feels_ergun_of_the_real_particles() {
        let (eps, d_real, slip): (f64, f64, f64) = (0.4, 5e-4, 0.02);
        let u_sup = eps * slip;
        let ergun = 150.0 * MU * (1.0 - eps).powi(2) * u_sup / (eps.powi(3) * d_real * d_real)
            + 1.75 * RHO * (1.0 - eps) * u_sup * u_sup / (eps.powi(3) * d_real);
        for cg in [1.0, 2.0, 3.0, 4.5] {
            let closure =
                DragClosure::from(DragLaw::GIDASPOW).with_parcel(Parcel::new(cg, 1.0).unwrap());
            let d = cg * d_real;
            let x = DragInput::new(eps, d, slip, RHO, MU);
            // parcels per bed volume: (1 − ε)/V_parcel
            let per_volume = (1.0 - eps) / (PI * d * d * d / 6.0);
            let gradient = per_volume * closure.beta(&x) * slip / eps;
            assert!(
                (gradient / ergun - 1.0).abs() < 1e-12,
                "cg {cg}: {gradient} vs Ergun {ergun}"
            );
        }
    }

    /// Schiller–Naumann in the Stokes limit: CG³ real spheres of diameter d/CG at Re ≪ 1 feel
    /// 3πμ(d/CG)u each (Stokes 1851; Re = 3.3e-8, so the correction 0.15 Re^0.687 is 1.1e-6).
    #[test]
    fn a_parcel_in_stokes_flow_is_cg_cubed_stokes_spheres() {
        let (d, slip, cg) = (1e-4, 1e-9, 3.0);
        let mu = 1e-3;
        let x = DragInput::new(1.0, d, slip, 1000.0, mu);
        let closure =
            DragClosure::from(DragLaw::SchillerNaumann).with_parcel(Parcel::new(cg, 1.0).unwrap());
        let stokes = cg.powi(3) * 3.0 * PI * mu * (d / cg);
        assert!((closure.beta(&x) / stokes - 1.0).abs() < 2e-6);
        let doubled =
            DragClosure::from(DragLaw::SchillerNaumann).with_parcel(Parcel::new(cg, 2.0).unwrap());
        assert!((doubled.beta(&x) / stokes - 2.0).abs() < 4e-6);
    }

    #[test]
    fn bad_factors_are_named() {
        let e = Parcel::new(0.5, 1.0).unwrap_err().to_string();
        assert!(e.contains("scale") && e.contains("≥ 1"), "{e}");
        let e = Parcel::new(2.0, 0.0).unwrap_err().to_string();
        assert!(e.contains("scaleDrag"), "{e}");
        assert!(Parcel::new(f64::NAN, 1.0).is_err());
    }
}
