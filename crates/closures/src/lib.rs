//! Fluid–particle closures: pure functions of local fluid and particle state.
//!
//! Owns: drag laws (force per particle as β·(u_f − v_p), β in kg/s, [`drag`]), the other
//! fluid–particle forces (pressure gradient, viscous stress divergence, buoyancy, virtual mass,
//! Saffman and Mei lift, [`forces`]) and the model A / B / Bfull formulations (Zhou et al.
//! 2010, [`model`]), the fluid–particle heat transfer (Nusselt correlations, [`heat`]), and
//! the DEM time-step criteria (Rayleigh, Hertz), LIGGGHTS's Hertz contact parameters, particle relaxation times and the coupling interval ([`timestep`]).
//! No mesh, no I/O: callers pass numbers in SI units (ADR 0004: the fluid pressure is
//! kinematic, p/ρ in m²/s², wherever a pressure gradient appears).
//!
//! Start with [`DragLaw::from_name`] (CFDEM's `forceModels` names) and [`DragLaw::beta`] on a
//! [`DragInput`], then [`model::particle_forces`] for the model type. Hot-path functions never
//! fail; user-supplied parameters and inputs are checked once with the `check`/`new`
//! functions, which return a [`ClosureError`] naming the quantity.

pub mod drag;
pub mod error;
pub mod forces;
pub mod heat;
pub mod input;
pub mod model;
pub mod timestep;

pub use drag::{DragClosure, DragLaw, Parcel, DEFAULT_VOIDAGE_FLOOR, DRAG_LAW_NAMES};
pub use error::ClosureError;
pub use heat::{nusselt, Nusselt};
pub use input::{sphere_volume, DragInput};
pub use model::{particle_forces, FluidAtParticle, ModelType, ParticleForces};
