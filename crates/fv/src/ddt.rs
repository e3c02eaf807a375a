//! The coefficients of the implicit time derivatives: Euler and the second-order backward
//! differentiation formula (`ddtSchemes default backward`).
//!
//! With Δt the step, Δt₀ the previous step, OpenFOAM v1912's `backwardDdtScheme` forms
//!
//!   ∂(αU)/∂t ≈ (c αU − c₀ α°U° + c₀₀ α°°U°°)/Δt,
//!   c = 1 + Δt/(Δt + Δt₀), c₀₀ = Δt²/(Δt₀(Δt + Δt₀)), c₀ = c + c₀₀
//!
//! (for Δt₀ = Δt: (3αU − 4α°U° + α°°U°°)/(2Δt), second order; Ferziger & Perić,
//! *Computational Methods for Fluid Dynamics*, 3rd ed., §6.2.2). On the first step of a run
//! there is no second old level: OpenFOAM then takes Δt₀ = GREAT = 10¹⁵ s (`deltaT0_(vf)` while
//! `timeIndex < 2`), which makes c = c₀ = 1 and c₀₀ ≈ Δt²/10³⁰ — Euler to round-off; the same
//! numbers are used here. The same coefficients scale `ddtCorr`'s old fluxes
//! (`fvcDdtPhiCorr`) and ∂ε/∂t of the continuity equation. Euler is c = c₀ = 1, c₀₀ = 0.

/// OpenFOAM's `GREAT` (`doubleScalarGREAT`), the previous step of a run's first step (s).
const GREAT: f64 = 1.0e15;

/// The three coefficients of one step (dimensionless; the derivative divides by Δt).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DdtCoeffs {
    /// Of the new level, c.
    pub c: f64,
    /// Of the old level, c₀.
    pub c0: f64,
    /// Of the old-old level, c₀₀ (0 for Euler).
    pub c00: f64,
}

impl DdtCoeffs {
    /// Implicit Euler.
    pub const EULER: DdtCoeffs = DdtCoeffs {
        c: 1.0,
        c0: 1.0,
        c00: 0.0,
    };

    /// The backward formula for step `dt` after a step `dt0` (s); `first`: the run's first step
    /// (no old-old level, Δt₀ = GREAT).
    pub fn backward(dt: f64, dt0: f64, first: bool) -> DdtCoeffs {
        let dt0 = if first { GREAT } else { dt0 };
        let c = 1.0 + dt / (dt + dt0);
        let c00 = dt * dt / (dt0 * (dt + dt0));
        DdtCoeffs {
            c,
            c0: c + c00,
            c00,
        }
    }

    /// Whether the old-old level enters (c₀₀ ≠ 0).
    pub fn uses_old_old(&self) -> bool {
        self.c00 != 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backward_is_bdf2_at_constant_step_and_euler_first() {
        let k = DdtCoeffs::backward(0.1, 0.1, false);
        assert!((k.c - 1.5).abs() < 1e-15 && (k.c0 - 2.0).abs() < 1e-15);
        assert!((k.c00 - 0.5).abs() < 1e-15);
        let first = DdtCoeffs::backward(1e-3, 1e-3, true);
        assert_eq!((first.c, first.c0), (1.0, 1.0));
        assert!(first.c00 < 1e-35);
        // exact for a quadratic in time: u = t², steps 0.1 then 0.2
        let (t00, t0, t) = (0.0f64, 0.2, 0.3);
        let k = DdtCoeffs::backward(t - t0, t0 - t00, false);
        let d = (k.c * t * t - k.c0 * t0 * t0 + k.c00 * t00 * t00) / (t - t0);
        assert!((d - 2.0 * t).abs() < 1e-12, "{d}");
    }
}
