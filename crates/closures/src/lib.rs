//! Fluid–particle closures: pure functions of local fluid and particle state.
//!
//! Owns: drag laws (force per particle as β·(u_f − v_p), β in kg/s, [`drag`]), the other
//! fluid–particle forces (pressure gradient, viscous stress divergence, buoyancy, virtual mass,
//! lift) and the model A / B / Bfull formulations (Zhou et al. 2010),
//! and the DEM time-step criteria (Rayleigh, Hertz), particle relaxation times and the coupling
//! interval. No mesh, no I/O: callers pass numbers in SI units (ADR 0004: the
//! fluid pressure is kinematic, p/ρ in m²/s², wherever a pressure gradient appears).
//!
//! Start with [`DragLaw::from_name`] (CFDEM's `forceModels` names) and [`DragLaw::beta`] on a
//! [`DragInput`]. Hot-path functions never fail; user-supplied parameters and inputs are
//! checked once with the `check`/`new` functions, which return a [`ClosureError`].

pub mod drag;
pub mod error;
pub mod input;

pub use drag::{DragClosure, DragLaw, DEFAULT_VOIDAGE_FLOOR, DRAG_LAW_NAMES};
pub use error::ClosureError;
pub use input::{sphere_volume, DragInput};
