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

use crate::native::{NativeDem, NativeFluid};
use crate::run::{couple_loop, coupling_steps, Event, LoopContext, RunError, RunReport};
use liggghts_deck::Deck;
use std::path::{Path, PathBuf};

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

fn backend_err(what: &str, e: impl std::fmt::Display) -> RunError {
    RunError::Backend(format!("{what}: {e}"))
}

/// The DEM time step of a deck (`timestep DT`), s.
fn deck_time_step(deck: &Deck) -> Option<f64> {
    deck.commands
        .iter()
        .find(|c| c.words.first().map(String::as_str) == Some("timestep"))
        .and_then(|c| c.words.get(1))
        .and_then(|w| w.parse().ok())
}

/// The grainPisoFoam binary: `$FOAMGRAIN_SOLVER`, else `$FOAMGRAIN_CACHE/bin/grainPisoFoam`,
/// else `~/.cache/foamgrain/bin/grainPisoFoam` (where `openfoam-cases/solver/build.sh` puts
/// it).
pub fn solver_path() -> Result<PathBuf, RunError> {
    let path = if let Some(p) = std::env::var_os("FOAMGRAIN_SOLVER") {
        PathBuf::from(p)
    } else {
        let cache = std::env::var_os("FOAMGRAIN_CACHE")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache/foamgrain")))
            .unwrap_or_else(|| PathBuf::from(".cache/foamgrain"));
        cache.join("bin/grainPisoFoam")
    };
    if path.is_file() {
        Ok(path)
    } else {
        Err(RunError::Backend(format!(
            "grainPisoFoam not found at {} (build it with openfoam-cases/solver/build.sh, or \
             set FOAMGRAIN_SOLVER)",
            path.display()
        )))
    }
}

/// Stage 1 with the `liggghts` binary: runs the init deck in the DEM directory.
pub(crate) fn pack_with_liggghts(
    init: &Path,
    dem_dir: &Path,
    vars: &[(String, String)],
) -> Result<(), RunError> {
    liggghts::run_deck(init, dem_dir, vars, "init")
        .map(|_| ())
        .map_err(|e| backend_err("LIGGGHTS (stage 1)", e))
}

/// The run deck on the native DEM, its warnings in the run's log.
fn native_dem(
    run_deck: &Deck,
    dem_dir: &Path,
    events: &mut dyn FnMut(Event),
) -> Result<NativeDem, RunError> {
    Ok(crate::native::run_native_deck(
        run_deck,
        dem_dir,
        &mut |w| events(Event::Message(format!("warning: {w}"))),
    )?)
}

/// Runs stage 2 on the chosen pair of sides.
pub(crate) fn run_pair(
    ctx: LoopContext<'_>,
    run_deck: &Deck,
    model: fv::Model,
    fluid: FluidBackend,
    dem: DemBackend,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let layout = ctx.layout;
    let (ddt, solve, rho) = (ctx.ddt_voidage, ctx.solve_flow, ctx.settings.physics.rho);
    let native_fluid =
        || NativeFluid::open(&layout.cfd, model, ddt, solve, rho).map_err(RunError::Fluid);
    match (fluid, dem) {
        (FluidBackend::Native, DemBackend::Native) => {
            let dem = native_dem(run_deck, &layout.dem, events)?;
            couple_loop(ctx, dem, native_fluid()?, events)
        }
        (FluidBackend::Native, DemBackend::LiggghtsFile) => {
            let dt = deck_time_step(run_deck).ok_or_else(|| {
                RunError::Backend(format!(
                    "{}: file coupling needs `timestep DT` with a number",
                    layout.run_deck.display()
                ))
            })?;
            let dt_c = ctx.coupling_interval as f64 * dt;
            let start = ctx.fluid_settings.start_time;
            let end = ctx.opts.end_time.unwrap_or(ctx.fluid_settings.end_time);
            let steps = coupling_steps(start, end, dt_c);
            let options = liggghts::FileOptions::new(steps * ctx.coupling_interval);
            events(Event::Message(format!(
                "LIGGGHTS file coupling: {steps} exchanges of about 10 s each (LIGGGHTS polls \
                 its files every 10 s)"
            )));
            let side = liggghts::FileDem::open(&layout.run_deck, &layout.dem, &[], options)
                .map_err(|e| backend_err("LIGGGHTS (file coupling)", e))?;
            couple_loop(ctx, side, native_fluid()?, events)
        }
        (FluidBackend::OpenFoam, DemBackend::LiggghtsFile) => Err(unavailable(
            fluid,
            dem,
            "file coupling is offered with the native fluid only",
        )),
        #[cfg(any(feature = "mpi", feature = "liggghts"))]
        (fluid, dem) => mpi_pair::run(ctx, run_deck, model, fluid, dem, events),
        #[cfg(not(any(feature = "mpi", feature = "liggghts")))]
        (fluid, dem) => Err(unavailable(
            fluid,
            dem,
            "this foamgrain was built without MPI backends; build it with \
             `cargo build --release -p cli --features mpi,liggghts` (needs openmpi-bin \
             libopenmpi-dev libclang-dev, and libliggghts-dev for `liggghts`)",
        )),
    }
}

/// The pairs that need MPI (grainPisoFoam spawned over MPI, LIGGGHTS in this process).
#[cfg(any(feature = "mpi", feature = "liggghts"))]
mod mpi_pair {
    use super::*;

    /// Runs one MPI pair: initialises MPI once for this process (both backends share the
    /// universe), opens the sides and runs the loop.
    pub(super) fn run(
        ctx: LoopContext<'_>,
        #[cfg_attr(not(feature = "mpi"), allow(unused_variables))] run_deck: &Deck,
        #[cfg_attr(not(feature = "liggghts"), allow(unused_variables))] model: fv::Model,
        fluid: FluidBackend,
        dem: DemBackend,
        events: &mut dyn FnMut(Event),
    ) -> Result<RunReport, RunError> {
        #[cfg(feature = "mpi")]
        foam_link::prepare_environment();
        let universe = mpi::initialize().ok_or_else(|| {
            RunError::Backend("MPI is already initialised in this process".into())
        })?;
        let world = universe.world();
        let layout = ctx.layout;
        let report = match (fluid, dem) {
            #[cfg(feature = "liggghts")]
            (FluidBackend::Native, DemBackend::Liggghts) => {
                let dem = open_liggghts(&world, layout)?;
                let fluid = NativeFluid::open(
                    &layout.cfd,
                    model,
                    ctx.ddt_voidage,
                    ctx.solve_flow,
                    ctx.settings.physics.rho,
                )
                .map_err(RunError::Fluid)?;
                couple_loop(ctx, dem, fluid, events)
            }
            #[cfg(feature = "mpi")]
            (FluidBackend::OpenFoam, DemBackend::Native) => {
                let dem = native_dem(run_deck, &layout.dem, events)?;
                let fluid = open_foam(&world, layout, ctx.opts.fluid_ranks)?;
                couple_loop(ctx, dem, fluid, events)
            }
            #[cfg(all(feature = "mpi", feature = "liggghts"))]
            (FluidBackend::OpenFoam, DemBackend::Liggghts) => {
                // LIGGGHTS first: its deck is checked before a solver is spawned.
                let dem = open_liggghts(&world, layout)?;
                let fluid = open_foam(&world, layout, ctx.opts.fluid_ranks)?;
                couple_loop(ctx, dem, fluid, events)
            }
            (fluid, dem) => Err(unavailable(
                fluid,
                dem,
                "this foamgrain lacks the cargo feature for one of these backends; build it \
                 with `--features mpi,liggghts`",
            )),
        };
        drop(world);
        drop(universe);
        report
    }

    #[cfg(feature = "liggghts")]
    fn open_liggghts(
        world: &mpi::topology::SimpleCommunicator,
        layout: &crate::layout::CaseLayout,
    ) -> Result<liggghts::LiggghtsDem, RunError> {
        liggghts::LiggghtsDem::open(world, &layout.run_deck, &layout.dem, &[])
            .map_err(|e| backend_err("LIGGGHTS (in-process)", e))
    }

    #[cfg(feature = "mpi")]
    fn open_foam(
        world: &mpi::topology::SimpleCommunicator,
        layout: &crate::layout::CaseLayout,
        ranks: usize,
    ) -> Result<crate::foam_fluid::FoamFluid, RunError> {
        let solver = solver_path()?;
        let fluid = foam_link::OpenFoamFluid::spawn(world, &layout.cfd, ranks.max(1), &solver)
            .map_err(|e| backend_err("grainPisoFoam", e))?;
        Ok(crate::foam_fluid::FoamFluid::new(fluid))
    }
}
