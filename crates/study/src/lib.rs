//! Cell-size studies of CFD-DEM cases (Volk, Ghia & Liu 2018, seed 001): how the drag on a
//! fixed bed depends on the fluid cell size, per voidage method.
//!
//! Start with [`cellsize::cellsize`] on a case in CFDEM layout whose `CFD/system` holds a
//! `blockMeshDict.template` (e.g. `openfoam-cases/binary-bed`) and [`cellsize::write_outputs`];
//! `foamgrain study cellsize` (crate `cli`) runs it from the command line.
//!
//! Modules, one concept each:
//! * [`template`]: blockMesh templates with cell-count placeholders and the native generator
//!   of the same mesh;
//! * [`pack`]: the bed packed once by the native DEM; [`frozen`]: a particle side that never
//!   moves;
//! * [`steady`]: the steady-state criterion of a run; [`run`]: one steady run (grid, method,
//!   velocity) and what it records;
//! * [`diameters`]: the three reference diameters and Δx/d; [`spread`]: the voidage spread in
//!   the bed; [`reference`](mod@reference): Gidaspow and Ergun on the measured bed, U_mf;
//! * [`cellsize`](mod@cellsize): the study, its GCI, CSV, JSON and plots.
//!
//! Invariant: the particles never move and every run starts from the same packed bed, so the
//! runs differ only in the grid, the voidage method and the velocity. SI units, kinematic
//! pressure inside the solver, Pa in reports.
pub mod cellsize;
pub mod diameters;
pub mod error;
pub mod frozen;
pub mod pack;
pub mod reference;
pub mod run;
pub mod spread;
pub mod steady;
pub mod template;

pub use cellsize::{cellsize, write_outputs, StudyEvent, StudyOptions, StudyReport};
pub use error::StudyError;
