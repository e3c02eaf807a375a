//! DEM time-step criteria (Rayleigh, Hertz), LIGGGHTS's Hertz contact parameters from
//! (E, ν, e), particle relaxation times and the coupling interval they suggest. SI units.

use crate::error::{positive, ClosureError};
use std::f64::consts::PI;

/// Rayleigh time step, s: the time a Rayleigh surface wave takes to cross a particle,
/// dt_R = π r √(ρ_p/G) / (0.1631 ν + 0.8766), G = E/(2(1+ν)) the shear modulus
/// (seed `002` eq. 10, which prints G as "g"; Li, Xu & Thornton 2005). r (m), ρ_p (kg/m³),
/// E (Pa), ν. 0.1631ν + 0.8766 fits the root of the Rayleigh-wave equation (the wave speed over
/// the shear-wave speed) to 0.3 % for 0 ≤ ν ≤ 0.49 (tested). DEM practice takes 10–30 %
/// of dt_R as the step.
pub fn rayleigh_time_step(radius: f64, density: f64, young: f64, poisson: f64) -> f64 {
    let shear = young / (2.0 * (1.0 + poisson));
    PI * radius * (density / shear).sqrt() / (0.1631 * poisson + 0.8766)
}

/// The constant of Hertz's contact duration, 2·∫₀¹(1 − x^(5/2))^(−½)dx·(15/16)^(2/5)
/// = 2.9432·0.97452 ≈ 2.8682 (seed `002` eq. 11 rounds it to 2.87).
pub const HERTZ_DURATION_CONSTANT: f64 = 2.868_265;

/// Duration of an elastic Hertz contact, s: t_H = 2.868 (m*²/(R* E*² v))^(1/5) for effective
/// mass m* (kg), radius R* (m) and modulus E* (Pa) and normal impact speed v (m/s)
/// (Johnson 1985, Contact Mechanics; seed `002` eq. 11, where the exponent printed "2" is 1/5). A DEM step
/// of t_H/20 or less resolves the contact.
pub fn hertz_contact_time(m_eff: f64, r_eff: f64, y_eff: f64, speed: f64) -> f64 {
    hertz_contact_time_with(HERTZ_DURATION_CONSTANT, m_eff, r_eff, y_eff, speed)
}

/// The constant as seed `002` eq. 11 prints it and LIGGGHTS's `fix check/timestep/gran`
/// uses it: 2.87, 0.06 % above [`HERTZ_DURATION_CONSTANT`]. The native DEM's
/// `check/timestep/gran` takes it so that its warnings carry LIGGGHTS's digits.
pub const HERTZ_DURATION_CONSTANT_ROUNDED: f64 = 2.87;

/// [`hertz_contact_time`] with the leading constant given (s; the same units).
pub fn hertz_contact_time_with(
    constant: f64,
    m_eff: f64,
    r_eff: f64,
    y_eff: f64,
    speed: f64,
) -> f64 {
    constant * (m_eff * m_eff / (r_eff * y_eff * y_eff * speed)).powf(0.2)
}

/// LIGGGHTS's `pair gran model hertz` normal contact between two spheres of one material,
/// from Young's modulus E, Poisson ratio ν and restitution e (LIGGGHTS 3.8 `pair_gran`
/// documentation, `normal_model_hertz.h`):
/// Y* = E/(2(1−ν²)), R* = r₁r₂/(r₁+r₂), m* = m₁m₂/(m₁+m₂), β = ln e/√(ln²e + π²),
/// k_n = (4/3) Y* √(R* δ), S_n = 2 Y* √(R* δ), γ_n = −2 √(5/6) β √(S_n m*), and the normal force
/// F_n = k_n δ − γ_n δ̇ (δ the overlap, δ̇ its rate of change, positive on approach).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    /// Effective Young's modulus Y*, Pa.
    pub y_eff: f64,
    /// Effective radius R*, m.
    pub r_eff: f64,
    /// Effective mass m*, kg.
    pub m_eff: f64,
    /// LIGGGHTS's damping parameter β = ln e/√(ln²e + π²) (≤ 0), dimensionless.
    pub damping: f64,
}

impl HertzContact {
    /// Contact of two spheres (radii m, masses kg) of one material; errors name the bad input.
    pub fn new(
        young: f64,
        poisson: f64,
        restitution: f64,
        radii: [f64; 2],
        masses: [f64; 2],
    ) -> Result<Self, ClosureError> {
        positive("youngsModulus", young)?;
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(ClosureError::BadInput {
                quantity: "poissonsRatio",
                value: poisson,
                reason: "must be in (-1, 0.5)",
            });
        }
        if !(restitution > 0.0 && restitution <= 1.0) {
            return Err(ClosureError::BadInput {
                quantity: "coefficientRestitution",
                value: restitution,
                reason: "must be in (0, 1]",
            });
        }
        for r in radii {
            positive("radius", r)?;
        }
        for m in masses {
            positive("mass", m)?;
        }
        let ln_e = restitution.ln();
        Ok(HertzContact {
            y_eff: young / (2.0 * (1.0 - poisson * poisson)),
            r_eff: radii[0] * radii[1] / (radii[0] + radii[1]),
            m_eff: masses[0] * masses[1] / (masses[0] + masses[1]),
            damping: ln_e / (ln_e * ln_e + PI * PI).sqrt(),
        })
    }

    /// Normal stiffness k_n = (4/3) Y* √(R* δ) at overlap δ (m), N/m.
    pub fn stiffness(&self, overlap: f64) -> f64 {
        4.0 / 3.0 * self.y_eff * (self.r_eff * overlap).sqrt()
    }

    /// Normal damping γ_n = −2 √(5/6) β √(2 Y* √(R* δ) m*) at overlap δ (m), kg/s.
    pub fn damping_coefficient(&self, overlap: f64) -> f64 {
        let s_n = 2.0 * self.y_eff * (self.r_eff * overlap).sqrt();
        -2.0 * (5.0f64 / 6.0).sqrt() * self.damping * (s_n * self.m_eff).sqrt()
    }

    /// Normal force F_n = k_n δ + γ_n δ̇, N (positive = repulsive), at overlap δ (m) growing at
    /// `overlap_rate` δ̇ (m/s).
    pub fn normal_force(&self, overlap: f64, overlap_rate: f64) -> f64 {
        if overlap <= 0.0 {
            return 0.0;
        }
        self.stiffness(overlap) * overlap + self.damping_coefficient(overlap) * overlap_rate
    }

    /// Duration of the undamped contact at impact speed `speed` (m/s), s: [`hertz_contact_time`].
    pub fn contact_time(&self, speed: f64) -> f64 {
        hertz_contact_time(self.m_eff, self.r_eff, self.y_eff, speed)
    }
}

/// Stokes relaxation time of a sphere, s: τ = ρ_p d²/(18 μ) (ρ_p kg/m³, d m, μ Pa·s): the
/// e-folding time of its velocity relative to the fluid in creeping flow.
pub fn stokes_relaxation_time(density: f64, diameter: f64, mu: f64) -> f64 {
    density * diameter * diameter / (18.0 * mu)
}

/// Relaxation time under a drag law, s: τ = m_p/β (m_p kg, β kg/s). Equals
/// [`stokes_relaxation_time`] for β = 3πμd; smaller in dense beds and at finite Re.
pub fn drag_relaxation_time(mass: f64, beta: f64) -> f64 {
    mass / beta
}

/// Default fraction of the particle relaxation time one coupling interval may span: the
/// acceleration-number limit above which CFDEMcoupling's `checkCouplingInterval` warns.
pub const DEFAULT_COUPLING_FRACTION: f64 = 0.1;

/// The acceleration number of CFDEMcoupling's `checkCouplingInterval`, dimensionless: the
/// coupling time (DEM step × `couplingInterval`, s) over the smallest particle relaxation time
/// (s, CFDEM uses [`stokes_relaxation_time`]). Above [`DEFAULT_COUPLING_FRACTION`] (0.1) the
/// particles change their slip noticeably between two exchanges, and CFDEM warns "you should
/// use a smaller coupling interval".
pub fn acceleration_number(coupling_time: f64, relaxation_time: f64) -> f64 {
    coupling_time / relaxation_time
}

/// Number of DEM steps per coupling interval so that the interval spans at most `fraction` of
/// the relaxation time τ: ⌊fraction·τ/dt_DEM⌋, at least 1. The particle applies the implicit
/// drag every DEM step (ADR 0004), but the fluid sees the particles' response only at the next
/// exchange, so the exchange must resolve τ: the result keeps [`acceleration_number`] ≤
/// `fraction`. Errors name the non-positive input.
pub fn coupling_interval_steps(
    dem_dt: f64,
    relaxation_time: f64,
    fraction: f64,
) -> Result<u64, ClosureError> {
    positive("demTimeStep", dem_dt)?;
    positive("relaxationTime", relaxation_time)?;
    positive("couplingFraction", fraction)?;
    let steps = (fraction * relaxation_time / dem_dt).floor();
    Ok(if steps >= 1.0 {
        steps.min(u64::MAX as f64) as u64
    } else {
        1
    })
}
