//! Model A / B / Bfull: which fluid–particle forces act on a particle, and how their reactions
//! reach the fluid (Zhou, Kuang, Chu & Yu 2010, J. Fluid Mech. 661, 482–510; seed `002`
//! eq. 3–6; CFDEMcoupling's `modelType`).
//!
//! | model | drag coefficient | −V_pρ∇p, V_pρ∇·τ on the particle | their reaction on the fluid | fluid equation (ADR 0004) |
//! |---|---|---|---|---|
//! | A | β | yes | none: the fluid equation's −ε∇p and ∇·(ετ) already hold it | −ε∇p + ∇·(ετ) − (Ksl/ρ)(U − Us) |
//! | B | β/ε | no (folded into the drag) | — | −∇p + ∇·τ − (Ksl/ρ)(U − Us) |
//! | Bfull | β | yes | explicitly, in `f` | −∇p + ∇·τ − (Ksl/ρ)(U − Us) + f/ρ |
//!
//! β is the drag law's (model A) coefficient. In all three the drag's reaction goes to the fluid
//! implicitly (Ksl, Us), and buoyancy −ρV_p g acts on the particle only, with no reaction in the
//! fluid, because OpenFOAM's kinematic `p` in CFDEM's solvers carries no hydrostatic part and
//! the fluid equation no gravity (CFDEMcoupling's `Archimedes` with `treatForceDEM`; pass
//! g = 0 if the pressure does hold the hydrostatic part). ε enters only as: model B divides
//! the drag by ε (Zhou et al.'s f_d^B = f_d^A/ε), and the fluid equations above.
//!
//! The three are equivalent at steady uniform flow (tested): with n = (1−ε)/V_p particles per
//! volume, model A's fluid balance ε∇p = −nβu makes the particle feel β u/ε in total, which is
//! model B's drag; Bfull gives the same with the fluid pressure balance written without ε.

use crate::error::ClosureError;
use crate::forces::{buoyancy, pressure_gradient, viscous_stress};
use v3::V3;

/// The model type (`modelType` in CFDEM's `couplingProperties`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelType {
    /// Zhou et al.'s model A (set II of Anderson & Jackson): pressure and viscous forces on the
    /// particle, ε∇p in the fluid.
    A,
    /// Model B: drag/ε only, ∇p in the fluid.
    B,
    /// CFDEM's "Bfull": model A's particle forces, their reaction explicit in a model-B fluid.
    BFull,
}

impl ModelType {
    /// CFDEM's `modelType` value: `A`, `B` or `Bfull`; other names are an error listing these.
    pub fn from_name(name: &str) -> Result<ModelType, ClosureError> {
        match name {
            "A" => Ok(ModelType::A),
            "B" => Ok(ModelType::B),
            "Bfull" => Ok(ModelType::BFull),
            _ => Err(ClosureError::UnknownModel {
                family: "modelType",
                name: name.to_string(),
                valid: "A, B, Bfull".to_string(),
            }),
        }
    }

    /// The name CFDEM writes.
    pub fn name(&self) -> &'static str {
        match self {
            ModelType::A => "A",
            ModelType::B => "B",
            ModelType::BFull => "Bfull",
        }
    }

    /// The drag coefficient the model applies, kg/s: β (A, Bfull) or β/ε (B).
    #[inline]
    pub fn drag_coefficient(&self, beta: f64, voidage: f64) -> f64 {
        match self {
            ModelType::B => beta / voidage,
            ModelType::A | ModelType::BFull => beta,
        }
    }
}

/// The fluid state interpolated to one particle, SI units, kinematic pressure and stress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FluidAtParticle {
    /// Interstitial fluid velocity u_f, m/s.
    pub u: V3,
    /// ∇(p/ρ), m/s².
    pub grad_p: V3,
    /// ∇·(τ/ρ) of the viscous stress (the fluid's +∇·τ term), m/s².
    pub div_tau: V3,
    /// Voidage ε (the value the drag law saw, after any floor), dimensionless.
    pub voidage: f64,
    /// Fluid density ρ, kg/m³.
    pub rho: f64,
}

/// The fluid force on one particle split the way the exchange needs it. The force on the
/// particle is `beta·(u_f − v_p) + explicit`; the fluid receives `−beta·(u_f − v_p)` implicitly
/// (through Ksl = Σ w β / V and Us) and `−explicit_coupled` explicitly (through f).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleForces {
    /// Implicit drag coefficient, kg/s: applied to the particle and summed into Ksl.
    pub beta: f64,
    /// The drag β (u_f − v_p), N.
    pub drag: V3,
    /// Explicit force on the particle (pressure gradient, viscous, buoyancy as the model has
    /// them), N.
    pub explicit: V3,
    /// The part of `explicit` whose reaction the fluid receives in `f`, N.
    pub explicit_coupled: V3,
}

impl ParticleForces {
    /// Total fluid force on the particle, N.
    #[inline]
    pub fn total(&self) -> V3 {
        self.drag + self.explicit
    }
}

/// The forces on a particle of volume `volume` (m³) and velocity `v_p` (m/s) under `model`,
/// given the drag law's β (kg/s), the fluid at the particle and gravity `g` (m/s²; zero if the
/// pressure holds the hydrostatic part). See the module table.
#[inline]
pub fn particle_forces(
    model: ModelType,
    beta: f64,
    volume: f64,
    fluid: &FluidAtParticle,
    v_p: V3,
    g: V3,
) -> ParticleForces {
    let beta = model.drag_coefficient(beta, fluid.voidage);
    let drag = beta * (fluid.u - v_p);
    let archimedes = buoyancy(volume, fluid.rho, g);
    let stresses = match model {
        ModelType::B => V3::zeros(),
        ModelType::A | ModelType::BFull => {
            pressure_gradient(volume, fluid.rho, fluid.grad_p)
                + viscous_stress(volume, fluid.rho, fluid.div_tau)
        }
    };
    let explicit_coupled = match model {
        ModelType::BFull => stresses,
        ModelType::A | ModelType::B => V3::zeros(),
    };
    ParticleForces {
        beta,
        drag,
        explicit: (stresses + archimedes),
        explicit_coupled,
    }
}
