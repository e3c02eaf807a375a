//! The per-particle state a drag law needs, and the Reynolds numbers built from it.

use crate::error::{non_negative, positive, ClosureError};
use std::f64::consts::PI;

/// Local fluid and particle state at one particle, SI units.
///
/// `slip` is |u_f − v_p| with u_f the *interstitial* fluid velocity at the particle (what
/// OpenFOAM's `U` holds in CFD-DEM solvers), so the superficial slip is `voidage * slip`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragInput {
    /// Fluid volume fraction ε at the particle (1 = no particles), dimensionless.
    pub voidage: f64,
    /// Particle diameter d, m.
    pub diameter: f64,
    /// Slip speed |u_f − v_p|, m/s.
    pub slip: f64,
    /// Fluid density ρ, kg/m³.
    pub rho: f64,
    /// Fluid dynamic viscosity μ = ν ρ, Pa·s.
    pub mu: f64,
    /// Local Sauter-mean diameter ⟨d⟩ = Σd³/Σd² of the particles around this one, m; used only
    /// by the polydisperse laws (equal to `diameter` for a monodisperse bed).
    pub sauter_diameter: f64,
}

impl DragInput {
    /// A monodisperse input (`sauter_diameter = diameter`).
    pub fn new(voidage: f64, diameter: f64, slip: f64, rho: f64, mu: f64) -> Self {
        DragInput {
            voidage,
            diameter,
            slip,
            rho,
            mu,
            sauter_diameter: diameter,
        }
    }

    /// The same input with the local Sauter-mean diameter ⟨d⟩ set (polydisperse laws).
    pub fn with_sauter_diameter(mut self, sauter_diameter: f64) -> Self {
        self.sauter_diameter = sauter_diameter;
        self
    }

    /// Particle volume V_p = π d³/6, m³.
    #[inline]
    pub fn particle_volume(&self) -> f64 {
        sphere_volume(self.diameter)
    }

    /// Particle Reynolds number on the superficial slip, Re = ε ρ d |u_f − v_p| / μ
    /// (the definition of Wen–Yu, Di Felice, Koch–Hill (with d, not the radius) and Beetstra
    /// as CFDEMcoupling uses them), dimensionless.
    #[inline]
    pub fn reynolds(&self) -> f64 {
        self.voidage * self.rho * self.diameter * self.slip / self.mu
    }

    /// Single-particle Reynolds number on the interstitial slip, Re = ρ d |u_f − v_p| / μ
    /// (Schiller–Naumann).
    #[inline]
    pub fn reynolds_single(&self) -> f64 {
        self.rho * self.diameter * self.slip / self.mu
    }

    /// Checks every quantity is finite and in range: ε in (0, 1], d, ρ, μ, ⟨d⟩ > 0, slip ≥ 0.
    /// The error names the offending quantity; callers add the particle id.
    pub fn check(&self) -> Result<(), ClosureError> {
        if !(self.voidage.is_finite() && self.voidage > 0.0 && self.voidage <= 1.0) {
            return Err(ClosureError::BadInput {
                quantity: "voidage",
                value: self.voidage,
                reason: "must be in (0, 1]",
            });
        }
        positive("diameter", self.diameter)?;
        non_negative("slip", self.slip)?;
        positive("rho", self.rho)?;
        positive("mu", self.mu)?;
        positive("sauter_diameter", self.sauter_diameter)
    }
}

/// Volume of a sphere of diameter `d`: π d³/6.
#[inline]
pub fn sphere_volume(d: f64) -> f64 {
    PI / 6.0 * d * d * d
}
