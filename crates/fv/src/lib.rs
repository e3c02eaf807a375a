//! Native volume-averaged incompressible Navier–Stokes solver (PISO) on an OpenFOAM polyMesh.
//!
//! Owns: finite-volume discretisation on the collocated unstructured mesh, boundary conditions,
//! the PISO loop with Rhie–Chow fluxes and implicit interphase momentum exchange, linear solvers,
//! reading a case's `0/`, `constant/` and `system/` and writing OpenFOAM time directories.
//!
//! Modules:
//! * [`geometry`]: [`FvGeometry`], interpolation weights and deltas computed once per mesh;
//! * [`fvc`]: explicit operators (gradients, snGrad, ∇·τ, surface integrals) on a frozen field.

pub mod bc;
pub mod error;
pub mod fields;
pub mod fluid;
pub mod fvc;
pub mod geometry;
pub mod ldu;
pub mod linsolve;
pub mod settings;
pub mod testfields;

pub use error::{FvError, Result};
pub use fluid::{Fluid, Model, StepReport};
pub use geometry::{FvGeometry, FvPatch, V3};
