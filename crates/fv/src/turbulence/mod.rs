//! Turbulence of the native fluid: what `constant/turbulenceProperties` selects
//! ([`properties`]) and the standard k–ε model with wall functions ([`k_epsilon`]), as
//! OpenFOAM v1912's pisoFoam runs it.
//!
//! * [`properties`]: laminar, RAS kEpsilon (others refused), the schemes and solvers of k, ε;
//! * [`k_epsilon`]: the model's equations, solved after the PISO correctors;
//! * [`wall_functions`]: `nutkWallFunction`, `epsilonWallFunction` (log law);
//! * [`near_wall`]: their wall distance y (OpenFOAM's `nearWallDist`);
//! * [`scalar_bc`]: boundary conditions of k, ε and νt (and, read by [`crate::temperature::bc`],
//!   of T and α_t);
//! * [`scalar_eqn`]: the transport equation of a cell scalar (ddt, convection, Laplacian,
//!   `setValues`);
//! * `scalar_field`: one cell scalar with its conditions, read and written (k, ε, νt, T);
//! * [`bound`]: OpenFOAM's `bound` of k and ε.

pub mod bound;
pub mod k_epsilon;
pub mod near_wall;
pub mod properties;
pub mod scalar_bc;
pub mod scalar_eqn;
pub(crate) mod scalar_field;
pub mod wall_functions;

pub use k_epsilon::{KEpsilon, KEpsilonCoeffs};
pub use properties::{KEpsilonSettings, TurbulenceSettings};
