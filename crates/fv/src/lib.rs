//! Native volume-averaged incompressible Navier–Stokes solver (PISO) on an OpenFOAM polyMesh.
//!
//! Owns: finite-volume discretisation on the collocated unstructured mesh, boundary conditions,
//! the PISO loop with Rhie–Chow fluxes and implicit interphase momentum exchange, linear solvers,
//! reading a case's `0/`, `constant/` and `system/` and writing OpenFOAM time directories.
//!
//! Modules:
//! * [`geometry`]: [`FvGeometry`], interpolation weights and deltas computed once per mesh;
//! * [`fvc`]: explicit operators (gradients, snGrad, ∇·τ, surface integrals, reconstruction of
//!   cell vectors from face fluxes) on a frozen field;
//! * [`convection`]: the `div(phi,U)` schemes (`linear`, `upwind`, `limitedLinear ψ`,
//!   `limitedLinearV ψ`, `linearUpwind`, `linearUpwindV`, the `bounded` prefix);
//! * [`ldu`]: the matrix in OpenFOAM's LDU layout and its row-wise copy for the solvers;
//! * [`linsolve`]: PCG, PBiCG, BiCGStab and smoothSolver with OpenFOAM's residual and
//!   iteration counting (DIC/DILU preconditioning and smoothing), and `GAMG` through
//!   [`amg`], an aggregation multigrid;
//! * [`diffusion`]: one implicit diffusion step of a cell field (CFDEM's `constDiffSmoothing`);
//! * [`cyclic`]: translational `cyclic` patch pairs ([`mesh::cyclic`]), solved as internal
//!   faces;
//! * [`bc`]: boundary conditions of U and p; [`fields`]: U, p and phi of a time directory;
//!   [`frozen`]: U, p of a time directory with ∇p and ∇·τ, for a fluid that does not move;
//! * [`settings`]: what `system/` and `constant/` ask for, refusing what is not supported;
//! * [`turbulence`]: `turbulenceProperties` and the k–ε model with wall functions;
//! * [`fv_options`]: `fvOptions` sources holding a mean velocity (`meanVelocityForce`,
//!   CFDEM's `meanSupVelocityForce`);
//! * [`temperature`]: the temperature equation of CFDEM's `cfdemSolverPisoScalar` (when the
//!   caller asks for heat, [`settings::Settings::enable_temperature`]);
//! * [`courant`]: the Courant number of a step from the face fluxes (OpenFOAM's `CourantNo.H`);
//! * [`fluid`]: the PISO step ([`Fluid`]).
//!
//! Verified against Debian's OpenFOAM v1912 on the same meshes: the lid-driven cavity and an
//! O-grid pipe agree with icoFoam to round-off (same solvers, same iteration counts), restarts
//! from our time directories too; a skewed, graded cavity at Re 1000 with a non-orthogonal
//! corrector agrees with pisoFoam to round-off for every convection scheme and every momentum
//! solver above (`tests/schemes.rs`), and to the solver tolerance with GAMG; periodic
//! channels (`cyclic` pairs, `meanVelocityForce`; laminar, sheared and k–ε) to round-off
//! (`tests/periodic.rs`); plane and
//! Hagen–Poiseuille profiles, Ergun's pressure drop through a porous block and the time order
//! of Euler and Crank–Nicolson against closed forms; OpenFOAM's `CrankNicolson 0.9` on the
//! skewed cavity and the k–ε channel to round-off (`tests/schemes.rs`, `tests/k_epsilon.rs`).
//! The temperature equation agrees with scalarTransportFoam on a developing channel flow to
//! 6e-12 K, and with the closed forms of advection–diffusion, erfc diffusion and a heated box
//! (`tests/temperature.rs`).
//! Speed: `cargo bench -p fv`, `examples/bench_vs_pisofoam.rs` against pisoFoam (PCG or
//! GAMG), `examples/amg_vs_dic.rs` for the pressure solvers alone. `examples/check_settings.rs`
//! tells what the solver makes of a case's settings.

pub mod amg;
pub mod bc;
pub mod cn_files;
pub mod convection;
pub mod courant;
pub mod cyclic;
pub mod ddt;
pub mod diffusion;
pub mod error;
pub mod fields;
pub mod fluid;
pub mod frozen;
pub mod fv_options;
pub mod fvc;
pub mod gather;
pub mod geometry;
pub mod ldu;
pub mod linsolve;
mod reduce;
pub mod settings;
mod sweep;
mod team;
pub mod temperature;
pub mod testfields;
pub mod turbulence;

pub use error::{FvError, Result};
pub use fluid::{Fluid, Model, PorousTimeFlux, StepReport};
pub use geometry::{CyclicSide, FvGeometry, FvPatch, V3};
