//! Time-step advice for a coupled run: the DEM criteria, the particle relaxation time, the
//! CFL number of the fluid step and the coupling interval, with warnings in the spirit of
//! CFDEMcoupling's coupling-interval check.
//!
//! Formulas (closures' functions, which carry the references):
//! * Rayleigh step dt_R ([`closures::timestep::rayleigh_time_step`], seed `002` eq. 10); DEM
//!   practice: dt_DEM ≤ 0.2 dt_R (warned above);
//! * Hertz contact duration t_H for two equal spheres at the impact speed
//!   ([`closures::timestep::HertzContact::contact_time`], seed `002` eq. 11); warned when
//!   dt_DEM > t_H / 20;
//! * relaxation times: Stokes τ_St = ρ_p d²/(18 μ) and under the configured drag law at the
//!   given voidage and slip, τ = m_p/β ([`closures::timestep::drag_relaxation_time`]);
//! * coupling time Δt_c = couplingInterval · dt_DEM; CFL = |U|_max Δt_CFD / Δx with Δx the
//!   smallest cell's V^(1/3).
//!
//! Warnings (each a sentence naming the quantities): the CFD step larger than the coupling time
//! (CFDEM stops there), the coupling time not a whole multiple of the CFD step, the coupling
//! time longer than `coupling_fraction` (default 0.1) of the drag relaxation time, the DEM step
//! above the Rayleigh/Hertz limits, CFL > 1.

use crate::error::CoupleError;
use closures::timestep::{
    coupling_interval_steps, drag_relaxation_time, rayleigh_time_step, stokes_relaxation_time,
    HertzContact, DEFAULT_COUPLING_FRACTION,
};
use closures::{DragClosure, DragInput};

/// What the advice is computed from (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimestepInput {
    /// Particle radius, m.
    pub radius: f64,
    /// Particle density, kg/m³.
    pub density: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson ratio.
    pub poisson: f64,
    /// Coefficient of restitution.
    pub restitution: f64,
    /// Impact speed for the Hertz time, m/s.
    pub impact_speed: f64,
    /// Fluid density, kg/m³.
    pub rho: f64,
    /// Fluid kinematic viscosity, m²/s.
    pub nu: f64,
    /// The drag law for the relaxation time.
    pub drag: DragClosure,
    /// Voidage at which the drag relaxation time is evaluated.
    pub voidage: f64,
    /// Slip speed at which the drag relaxation time is evaluated, m/s.
    pub slip: f64,
    /// DEM step, s, if known.
    pub dem_dt: Option<f64>,
    /// CFD step, s, if known.
    pub cfd_dt: Option<f64>,
    /// DEM steps per coupling step, if known.
    pub coupling_interval: Option<u64>,
    /// Largest fluid speed, m/s, if known.
    pub fluid_speed: Option<f64>,
    /// Smallest cell size, m, if known.
    pub cell_size: Option<f64>,
    /// Fraction of the relaxation time a coupling interval may span.
    pub coupling_fraction: f64,
}

/// The advice.
#[derive(Clone, Debug, PartialEq)]
pub struct TimestepAdvice {
    /// Rayleigh time step, s.
    pub rayleigh: f64,
    /// Hertz contact duration, s.
    pub hertz: f64,
    /// Largest advisable DEM step, min(0.2 dt_R, t_H/20), s.
    pub dem_dt_max: f64,
    /// Stokes relaxation time, s.
    pub stokes_relaxation: f64,
    /// Relaxation time under the drag law, s.
    pub drag_relaxation: f64,
    /// Coupling time couplingInterval · dt_DEM, s (with both known).
    pub coupling_time: Option<f64>,
    /// The largest coupling interval (DEM steps) resolving `coupling_fraction` of the drag
    /// relaxation time, with the DEM step given or else `dem_dt_max`.
    pub suggested_interval: u64,
    /// CFL of the CFD step (with speed, size and step known).
    pub cfl: Option<f64>,
    /// Warnings, one sentence each.
    pub warnings: Vec<String>,
}

impl TimestepAdvice {
    /// (name, value, unit) rows for printing; `None` where unknown.
    pub fn rows(&self) -> Vec<(&'static str, Option<f64>, &'static str)> {
        vec![
            ("Rayleigh time step", Some(self.rayleigh), "s"),
            ("Hertz contact time", Some(self.hertz), "s"),
            ("largest advisable DEM step", Some(self.dem_dt_max), "s"),
            ("Stokes relaxation time", Some(self.stokes_relaxation), "s"),
            ("drag relaxation time", Some(self.drag_relaxation), "s"),
            ("coupling time", self.coupling_time, "s"),
            (
                "suggested coupling interval",
                Some(self.suggested_interval as f64),
                "DEM steps",
            ),
            ("CFL", self.cfl, ""),
        ]
    }
}

/// Computes the advice; errors name the bad input.
pub fn advise(x: &TimestepInput) -> Result<TimestepAdvice, CoupleError> {
    let d = 2.0 * x.radius;
    let mass = x.density * closures::sphere_volume(d);
    let contact = HertzContact::new(x.young, x.poisson, x.restitution, [x.radius; 2], [mass; 2])?;
    for (name, v) in [
        ("impact speed", x.impact_speed),
        ("fluid density", x.rho),
        ("viscosity", x.nu),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(CoupleError::Parameter(format!(
                "{name} {v} is not a positive number"
            )));
        }
    }
    let mu = x.nu * x.rho;
    let input = DragInput::new(x.voidage, d, x.slip, x.rho, mu);
    input.check()?;
    let rayleigh = rayleigh_time_step(x.radius, x.density, x.young, x.poisson);
    let hertz = contact.contact_time(x.impact_speed);
    let dem_dt_max = (0.2 * rayleigh).min(hertz / 20.0);
    let stokes = stokes_relaxation_time(x.density, d, mu);
    let beta = x.drag.beta(&input);
    let drag_relax = drag_relaxation_time(mass, beta);
    let dem_dt = x.dem_dt.unwrap_or(dem_dt_max);
    let suggested = coupling_interval_steps(dem_dt, drag_relax, x.coupling_fraction)?;
    let coupling_time = match (x.coupling_interval, x.dem_dt) {
        (Some(n), Some(dt)) => Some(n as f64 * dt),
        _ => None,
    };
    let cfl = match (x.fluid_speed, x.cfd_dt, x.cell_size) {
        (Some(u), Some(dt), Some(h)) if h > 0.0 => Some(u * dt / h),
        _ => None,
    };
    let mut warnings = Vec::new();
    if let Some(dt) = x.dem_dt {
        if dt > 0.2 * rayleigh {
            warnings.push(format!(
                "DEM step {dt:e} s is above 20 % of the Rayleigh time step {rayleigh:e} s"
            ));
        }
        if dt > hertz / 20.0 {
            warnings.push(format!(
                "DEM step {dt:e} s resolves the Hertz contact time {hertz:e} s with fewer \
                 than 20 steps"
            ));
        }
    }
    if let (Some(tc), Some(cfd)) = (coupling_time, x.cfd_dt) {
        if cfd > tc * (1.0 + 1e-9) {
            warnings.push(format!(
                "CFD step {cfd:e} s is larger than the coupling time {tc:e} s \
                 (couplingInterval × DEM step); CFDEMcoupling stops here"
            ));
        } else {
            let ratio = tc / cfd;
            if (ratio - ratio.round()).abs() > 1e-6 * ratio {
                warnings.push(format!(
                    "coupling time {tc:e} s is not a whole multiple of the CFD step {cfd:e} s"
                ));
            }
        }
    }
    if let Some(tc) = coupling_time {
        if tc > x.coupling_fraction * drag_relax {
            warnings.push(format!(
                "coupling time {tc:e} s exceeds {} of the particle relaxation time \
                 {drag_relax:e} s: at most {suggested} DEM steps per coupling step resolve it",
                x.coupling_fraction
            ));
        }
    }
    if let Some(c) = cfl {
        if c > 1.0 {
            warnings.push(format!("CFL number {c:.3} exceeds 1"));
        }
    }
    Ok(TimestepAdvice {
        rayleigh,
        hertz,
        dem_dt_max,
        stokes_relaxation: stokes,
        drag_relaxation: drag_relax,
        coupling_time,
        suggested_interval: suggested,
        cfl,
        warnings,
    })
}

/// The default fraction of the relaxation time a coupling interval may span.
pub const COUPLING_FRACTION: f64 = DEFAULT_COUPLING_FRACTION;
