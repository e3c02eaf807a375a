//! Runs coupled CFD-DEM cases laid out as CFDEM does (`CASE/CFD`, `CASE/DEM`).
//!
//! Owns: the pairing of a particle backend with a fluid backend, the run loop's outputs
//! (integral quantities per coupling step as CSV, PNG plots) and the validation of a case against
//! references computed from the case's own parameters and its measured bed.
pub mod backend;
pub mod bed;
pub mod bed_heat;
pub mod branch;
pub mod checks;
pub mod conveyor;
pub mod error;
pub mod fluid;
pub mod fluid_case;
pub mod fluidised;
#[cfg(feature = "mpi")]
pub mod foam_fluid;
pub mod heat_plot;
pub mod heating;
pub mod heating_run;
mod interval_check;
pub mod journal;
pub mod layout;
#[cfg(feature = "liggghts")]
mod mesh_part;
mod monitors;
#[cfg(any(feature = "mpi", feature = "liggghts"))]
mod nap;
pub mod native;
mod outputs;
mod particle_probe;
pub mod patches;
pub mod plan;
pub mod plot;
pub mod probes;
#[cfg(any(feature = "mpi", feature = "liggghts"))]
pub mod ranks;
pub mod ranks_report;
pub mod reference;
pub mod report;
pub mod run;
mod run_loop;
pub mod sample;
pub mod schumann;
pub mod slab_profile;
pub mod smoothing;
mod stage1;
pub mod surface_values;
pub mod timed;
pub mod validation;
mod whole;
