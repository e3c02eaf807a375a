//! Full-tier tests of grainPisoFoam, foamgrain's volume-averaged PISO solver for Debian's
//! OpenFOAM v1912 (`openfoam-cases/solver`). A dev-only crate: the library is the test harness,
//! the checks are in `tests/`.
//!
//! - [`solver::grain_piso_foam`] builds the solver once per test process with
//!   `openfoam-cases/solver/build.sh` (idempotent: about a second when already built) and
//!   returns its path, or `None` in the fast tier when OpenFOAM is not installed.
//! - [`case::TestCase`] copies a case template from `cases/` into a temporary directory, meshes
//!   it with `blockMesh`, sets cell values of fields, runs serial or `-parallel` and reads the
//!   results back with the `foam` crate.
//!
//! - [`darcy`] the Darcy drop of frozen bed fields (bounds for a heterogeneous bed) and
//!   patch means of written fields; [`frozen_bed`] the Ergun case on frozen coupling fields
//!   (`fixtures/ergun-bed`, used by `tests/frozen_ergun_bed.rs` and `examples/frozen_ergun.rs`).
//!
//! Templates: `cases/cavity` (lid-driven cavity on a skewed 16×16 mesh, Re 10) and
//! `cases/column` (a 1-D column of 60 cells for a prescribed porous block).

pub mod case;
pub mod darcy;
pub mod frozen_bed;
pub mod solver;

pub use case::TestCase;
pub use solver::grain_piso_foam;
