//! Per-particle fluid forces of one coupling step, and what each side receives.
//!
//! For every particle inside the mesh the fluid state is interpolated ([`crate::interpolate`])
//! — u_f and ε with the drag's rule, ∇p and ∇·τ with their force models' rules — the drag law
//! gives β (kg/s) at ε floored to the law's floor, and [`closures::model::particle_forces`]
//! splits the force by the model type (A, B, Bfull). Then ([`crate::config::DragSettings`]):
//! * the DEM side gets (β, u_f) when `implForceDEM` is on and applies β (u_f − v) every DEM
//!   step; otherwise it gets β = 0 and the drag frozen into `f_ext`;
//! * the fluid gets β in Ksl/Us (`implicitCouple`), or the drag in `f` when
//!   `treatForceExplicit` is on, or nothing with `treatForceDEM`; the model's explicitly
//!   coupled part (Bfull's pressure and viscous forces) always goes into `f`.
//!
//! A particle outside the mesh feels no fluid force and gives nothing to the fluid; it is
//! counted. Units: SI, kinematic p (ADR 0004).

use crate::config::{DragSettings, Forces};
use crate::interpolate::{Interpolation, Placement};
use crate::sides::{FluidState, ParticleState};
use closures::model::{particle_forces, FluidAtParticle, ModelType};
use closures::DragInput;
use mesh::v3::{add, mag, scale, sub, V3};
use rayon::prelude::*;

/// Fluid properties and force models of a coupling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Physics {
    /// Fluid density ρ, kg/m³.
    pub rho: f64,
    /// Kinematic viscosity ν, m²/s.
    pub nu: f64,
    /// Gravity g, m/s² (used by Archimedes).
    pub gravity: V3,
    /// `modelType`.
    pub model: ModelType,
    /// The force models.
    pub forces: Forces,
    /// `implicitCouple`: the drag's reaction is handed to the fluid as Ksl/Us.
    pub implicit_couple: bool,
}

/// The fluid force on one particle and its split between the sides.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ParticleCoupling {
    /// β for the DEM side (kg/s): applied as β (u_f − v) each DEM step; 0 when the drag is
    /// frozen into `f_ext`.
    pub beta_dem: f64,
    /// Fluid velocity at the particle, m/s.
    pub u_f: V3,
    /// Explicit force for the DEM side, N.
    pub f_ext: V3,
    /// The total fluid force at the coupling time, N (drag + explicit).
    pub total: V3,
    /// β summed into Ksl (kg/s).
    pub beta_fluid: f64,
    /// Force whose reaction goes into `f`, N.
    pub f_fluid: V3,
}

/// The couplings of all particles, and how many had no fluid.
#[derive(Clone, Debug, PartialEq)]
pub struct ForceSet {
    /// One per particle.
    pub particles: Vec<ParticleCoupling>,
    /// Particles outside the mesh (no fluid force).
    pub outside: usize,
}

/// The forces on every particle (parallel over particles), with the voidage field `voidage`.
pub fn particle_couplings(
    physics: &Physics,
    placement: &Placement,
    fluid: &FluidState<'_>,
    voidage: &[f64],
    particles: &ParticleState<'_>,
) -> ForceSet {
    let mu = physics.nu * physics.rho;
    let cells = Cells { fluid, voidage };
    let out: Vec<ParticleCoupling> = (0..placement.len())
        .into_par_iter()
        .map(|i| one_particle(physics, mu, placement, &cells, particles, i).unwrap_or_default())
        .collect();
    let outside = (0..placement.len())
        .filter(|&i| !placement.inside(i))
        .count();
    ForceSet {
        particles: out,
        outside,
    }
}

/// The cell fields the forces read.
struct Cells<'a> {
    fluid: &'a FluidState<'a>,
    voidage: &'a [f64],
}

/// Volume of a sphere of radius r, m³.
#[inline]
fn ball(r: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

#[inline]
fn one_particle(
    ph: &Physics,
    mu: f64,
    placement: &Placement,
    cells: &Cells<'_>,
    p: &ParticleState<'_>,
    i: usize,
) -> Option<ParticleCoupling> {
    let fluid = cells.fluid;
    let drag_rule = ph
        .forces
        .drag
        .map_or(Interpolation::Cell, |d| d.interpolation);
    let u_f = placement.value_at(fluid.u, i, drag_rule)?;
    let eps = placement.value_at(cells.voidage, i, drag_rule)?;
    let r = p.radius[i];
    let v = p.velocity[i];
    let volume = ball(r);
    let (beta, floored) = match ph.forces.drag {
        Some(DragSettings { closure, .. }) => {
            let x = DragInput::new(eps, 2.0 * r, mag(sub(u_f, v)), ph.rho, mu);
            let floored = eps.clamp(closure.voidage_floor, 1.0);
            (closure.beta(&x), floored)
        }
        None => (0.0, eps.clamp(f64::MIN_POSITIVE, 1.0)),
    };
    let grad_p = match ph.forces.grad_p {
        Some(rule) => placement.value_at(fluid.grad_p, i, rule)?,
        None => [0.0; 3],
    };
    let div_tau = match ph.forces.viscous {
        Some(rule) => placement.value_at(fluid.div_tau, i, rule)?,
        None => [0.0; 3],
    };
    let at = FluidAtParticle {
        u: u_f,
        grad_p,
        div_tau,
        voidage: floored,
        rho: ph.rho,
    };
    let g = if ph.forces.archimedes {
        ph.gravity
    } else {
        [0.0; 3]
    };
    let f = particle_forces(ph.model, beta, volume, &at, v, g);
    let settings = ph.forces.drag;
    let implicit_dem = settings.is_some_and(|d| d.implicit_dem);
    let explicit_fluid = settings.is_some_and(|d| d.explicit_fluid);
    let dem_only = settings.is_some_and(|d| d.dem_only);
    let (beta_dem, f_ext) = if implicit_dem {
        (f.beta, f.explicit)
    } else {
        (0.0, add(f.explicit, f.drag))
    };
    let (beta_fluid, drag_to_f) = if dem_only {
        (0.0, [0.0; 3])
    } else if explicit_fluid {
        (0.0, f.drag)
    } else if ph.implicit_couple {
        (f.beta, [0.0; 3])
    } else {
        (0.0, [0.0; 3])
    };
    Some(ParticleCoupling {
        beta_dem,
        u_f,
        f_ext,
        total: f.total(),
        beta_fluid,
        f_fluid: add(f.explicit_coupled, drag_to_f),
    })
}

/// Σ of the total fluid forces on the particles, N.
pub fn total_force(set: &ForceSet) -> V3 {
    set.particles
        .iter()
        .fold([0.0; 3], |acc, c| add(acc, c.total))
}

/// Σ_p [β_fluid (u_f − v) + f_fluid]: the momentum per time the fluid gives the particles at
/// the coupling time, N, which Σ_c V_c [Ksl_c (U_c − Us_c) − f_c] equals to round-off when u_f
/// is the smooth interpolation (ADR 0004).
pub fn fluid_momentum_loss(set: &ForceSet, velocity: &[V3]) -> V3 {
    set.particles
        .iter()
        .zip(velocity)
        .fold([0.0; 3], |acc, (c, &v)| {
            add(acc, add(scale(c.beta_fluid, sub(c.u_f, v)), c.f_fluid))
        })
}
