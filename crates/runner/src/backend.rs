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

use crate::error::RunError;
pub use crate::plan::{DemBackend, FluidBackend};

use crate::native::{NativeDem, NativeFluid};
use crate::plan::RunPlan;
use crate::report::{Event, RunReport};
use crate::run_loop::{couple_loop, coupling_steps, LoopContext};
use liggghts_deck::Deck;
use std::path::{Path, PathBuf};

/// Ranks `mpirun` (Open MPI, MPICH/PMI) says this process is one of, without initialising MPI:
/// 1 when launched alone.
pub fn launched_ranks() -> usize {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.parse().ok())
        .unwrap_or(1)
}

/// How this process runs: alone, or as one rank of `mpirun -np N foamgrain run …`. Holds the
/// MPI environment (initialised once, when the backends or the launch need it) for the whole
/// run: the LIGGGHTS ranks, the coupler's ranks and grainPisoFoam's spawn share it.
pub struct Launch {
    #[cfg(any(feature = "mpi", feature = "liggghts"))]
    universe: Option<mpi::environment::Universe>,
    rank: usize,
    size: usize,
}

impl Launch {
    /// Initialises MPI if `fluid`/`dem` or an `mpirun` launch need it. Refuses what N ranks
    /// cannot run: a build without MPI under `mpirun -np N` (N > 1), and the native DEM or the
    /// file coupling on N ranks (the native DEM uses threads in one process; LIGGGHTS
    /// in-process is the DEM that runs on N ranks).
    pub fn init(fluid: FluidBackend, dem: DemBackend) -> Result<Launch, RunError> {
        let launched = launched_ranks();
        if launched > 1 && dem != DemBackend::Liggghts {
            return Err(RunError::Backend(format!(
                "launched on {launched} ranks, but --dem {} runs on one process (the native \
                 DEM uses threads: run `foamgrain run CASE --np THREADS` without mpirun); \
                 `mpirun -np N` runs --dem liggghts, LIGGGHTS on the N ranks",
                dem.name()
            )));
        }
        #[cfg(any(feature = "mpi", feature = "liggghts"))]
        {
            let needs =
                launched > 1 || fluid == FluidBackend::OpenFoam || dem == DemBackend::Liggghts;
            if needs {
                #[cfg(feature = "mpi")]
                foam_link::prepare_environment();
                let universe = mpi::initialize().ok_or_else(|| {
                    RunError::Backend("MPI is already initialised in this process".into())
                })?;
                use mpi::topology::Communicator;
                let world = universe.world();
                let (rank, size) = (world.rank() as usize, world.size() as usize);
                return Ok(Launch {
                    universe: Some(universe),
                    rank,
                    size,
                });
            }
            Ok(Launch {
                universe: None,
                rank: 0,
                size: 1,
            })
        }
        #[cfg(not(any(feature = "mpi", feature = "liggghts")))]
        {
            let _ = fluid;
            if launched > 1 {
                return Err(RunError::Backend(format!(
                    "launched on {launched} ranks, but this foamgrain was built without MPI; \
                     build it with `cargo build --release -p cli --features mpi,liggghts`"
                )));
            }
            Ok(Launch { rank: 0, size: 1 })
        }
    }

    /// This rank (0 alone).
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// Number of ranks (1 alone).
    pub fn size(&self) -> usize {
        self.size
    }

    /// Whether every rank's `ok` is true (collective; `ok` itself alone). A rank that failed
    /// before a collective section tells the others this way, so that none waits for it.
    ///
    /// The ranks that arrive first wait without spinning: the reduction is nonblocking
    /// (`MPI_Iallreduce`) and tested with naps growing to 20 ms (`nap::STAGE`), so ranks waiting for
    /// rank 0's stage 1 (minutes) leave the cores to it, where a blocking `MPI_Allreduce`
    /// busy-polls in Open MPI (measured before: three waiting ranks took a whole core while
    /// LIGGGHTS packed for a 4-rank run).
    pub fn all_ok(&self, ok: bool) -> bool {
        #[cfg(any(feature = "mpi", feature = "liggghts"))]
        if let Some(u) = &self.universe {
            use mpi::collective::{CommunicatorCollectives, SystemOperation};
            let world = u.world();
            let mut all = 0i32;
            let mine = ok as i32;
            mpi::request::scope(|scope| {
                let request =
                    world.immediate_all_reduce_into(scope, &mine, &mut all, SystemOperation::min());
                crate::nap::wait(request, crate::nap::STAGE);
            });
            return all == 1;
        }
        ok
    }

    /// The MPI world, when MPI is initialised.
    #[cfg(any(feature = "mpi", feature = "liggghts"))]
    pub(crate) fn world(&self) -> Option<mpi::topology::SimpleCommunicator> {
        self.universe.as_ref().map(|u| u.world())
    }

    /// Ends every rank at once after `err` on this one (MPI_Abort, so that no rank waits in a
    /// collective for this one), after printing it with this rank's number; alone, returns it.
    pub fn fail_together(&self, err: RunError) -> RunError {
        #[cfg(any(feature = "mpi", feature = "liggghts"))]
        if self.size > 1 {
            if let Some(world) = self.world() {
                use mpi::topology::Communicator;
                eprintln!(
                    "foamgrain rank {} of {}: error: {err}",
                    self.rank, self.size
                );
                world.abort(1);
            }
        }
        err
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

/// The native fluid of the run's case with the coupling's settings (`modelType`,
/// `useDDTvoidfraction`, `solveFlow`, the coupling's ρ, the fields added mass and lift ask
/// for).
fn open_native_fluid(plan: &RunPlan) -> Result<NativeFluid, RunError> {
    let config = &plan.layout.coupling;
    let mut fluid = NativeFluid::open(
        &plan.layout.cfd,
        plan.fluid.clone(),
        plan.fluid_model(),
        config.ddt_voidage,
        config.solve_flow,
        plan.settings.physics.rho,
    )
    .map_err(RunError::Fluid)?;
    let forces = &config.forces;
    if forces.needs_vorticity() || forces.needs_ddt_u() {
        fluid.request(forces.needs_vorticity(), forces.needs_ddt_u());
    }
    if forces.needs_turbulence() {
        fluid
            .request_turbulence()
            .map_err(|e| RunError::Backend(format!("{}: {e}", config.file.display())))?;
    }
    Ok(fluid)
}

/// What grainPisoFoam cannot carry: k and ε (`KochHillRWDrag`) are in none of its replies;
/// the vorticity ∇ × U (`MeiLift`, `SaffmanLift`) and DU/Dt (`virtualMassForce` with
/// `splitUrelCalculation`) come only in the replies to one coupler rank
/// ([`foam_link::SpawnOptions::vorticity`], `ddt_u`). What is missing (`several`: several
/// coupler ranks) is refused before a solver is spawned.
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
fn foam_can_carry(layout: &crate::layout::CaseLayout, several: bool) -> Result<(), RunError> {
    let forces = &layout.coupling.forces;
    if forces.needs_turbulence() {
        return Err(RunError::Backend(format!(
            "{}: KochHillRWDrag needs the fluid's k and epsilon per cell, which grainPisoFoam's \
             exchange does not carry: run --fluid native (a k-epsilon case), or KochHillDrag",
            layout.coupling.file.display()
        )));
    }
    let missing = match (forces.needs_vorticity(), forces.needs_ddt_u()) {
        _ if !several => return Ok(()),
        (true, _) => "MeiLift/SaffmanLift need the fluid's vorticity ∇ × U",
        (false, true) => "virtualMassForce with splitUrelCalculation needs the fluid's DU/Dt",
        (false, false) => return Ok(()),
    };
    Err(RunError::Backend(format!(
        "{}: {missing}, which grainPisoFoam's exchange with several coupler ranks does not \
         carry: run one coupler rank, or --fluid native (or, for virtualMassForce, \
         splitUrelCalculation false, which needs only U)",
        layout.coupling.file.display()
    )))
}

/// Runs stage 2 on the chosen pair of sides.
pub(crate) fn run_pair(
    ctx: LoopContext<'_>,
    fluid: FluidBackend,
    dem: DemBackend,
    launch: &Launch,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let plan = ctx.plan;
    let (layout, run_deck) = (&plan.layout, &plan.run_deck);
    let native_fluid = || open_native_fluid(plan);
    match (fluid, dem) {
        (FluidBackend::Native, DemBackend::Native) => {
            let dem = native_dem(run_deck, &layout.dem, events)?;
            couple_loop(ctx, dem, native_fluid()?, events)
        }
        (FluidBackend::Native, DemBackend::LiggghtsFile) => {
            let dt = run_deck.time_step().ok_or_else(|| {
                RunError::Backend(format!(
                    "{}: file coupling needs `timestep DT` with a number",
                    layout.run_deck.display()
                ))
            })?;
            let interval = plan.settings.coupling_interval;
            let dt_c = interval as f64 * dt;
            let steps = coupling_steps(plan.fluid.start_time, plan.end_time(ctx.opts), dt_c);
            let options = liggghts::FileOptions::new(steps * interval);
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
        (fluid, dem) => mpi_pair::run(ctx, fluid, dem, launch, events),
        #[cfg(not(any(feature = "mpi", feature = "liggghts")))]
        (fluid, dem) => {
            let _ = launch;
            Err(unavailable(
                fluid,
                dem,
                "this foamgrain was built without MPI backends; build it with \
                 `cargo build --release -p cli --features mpi,liggghts` (needs openmpi-bin \
                 libopenmpi-dev libclang-dev, and libliggghts-dev for `liggghts`)",
            ))
        }
    }
}

/// The pairs that need MPI (grainPisoFoam spawned over MPI, LIGGGHTS in this process).
#[cfg(any(feature = "mpi", feature = "liggghts"))]
mod mpi_pair {
    use super::*;

    /// Runs one MPI pair on the MPI environment of `launch`: opens the sides and runs the
    /// loop. On N ranks (`mpirun -np N`, LIGGGHTS on all of them) rank 0 holds the fluid and
    /// the others a stand-in ([`crate::fluid::StandInFluid`]); an error on any rank ends all
    /// of them ([`Launch::fail_together`]).
    pub(super) fn run(
        ctx: LoopContext<'_>,
        fluid: FluidBackend,
        dem: DemBackend,
        launch: &Launch,
        events: &mut dyn FnMut(Event),
    ) -> Result<RunReport, RunError> {
        let world = launch
            .world()
            .ok_or_else(|| RunError::Backend("MPI was not initialised for this pair".into()))?;
        if launch.size() > 1 {
            return ranked(ctx, fluid, launch, &world, events).map_err(|e| launch.fail_together(e));
        }
        let plan = ctx.plan;
        let layout = &plan.layout;
        match (fluid, dem) {
            #[cfg(feature = "liggghts")]
            (FluidBackend::Native, DemBackend::Liggghts) => {
                let dem = open_liggghts(&world, layout)?;
                let fluid = open_native_fluid(plan)?;
                couple_loop(ctx, dem, fluid, events)
            }
            #[cfg(feature = "mpi")]
            (FluidBackend::OpenFoam, DemBackend::Native) => {
                let dem = native_dem(&plan.run_deck, &layout.dem, events)?;
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
        }
    }

    /// N coupler ranks, LIGGGHTS on all of them, each coupling the particles its LIGGGHTS
    /// rank owns ([`couple::ranks`]); the fluid on rank 0 (grainPisoFoam spawned from rank 0
    /// alone, on its own `--np` ranks).
    #[cfg(feature = "liggghts")]
    fn ranked(
        mut ctx: LoopContext<'_>,
        fluid: FluidBackend,
        launch: &Launch,
        world: &mpi::topology::SimpleCommunicator,
        events: &mut dyn FnMut(Event),
    ) -> Result<RunReport, RunError> {
        let plan = ctx.plan;
        let layout = &plan.layout;
        let dem = open_liggghts(world, layout)?;
        ctx.ranks = Some(Box::new(crate::ranks::MpiRanks::new(world)));
        match fluid {
            FluidBackend::Native if launch.rank() == 0 => {
                let fluid = open_native_fluid(plan)?;
                if launch.size() > 1 {
                    // rank 0's coupler on its part too: it sums the ranks into whole fields
                    let dt_c = plan.settings.coupling_interval as f64
                        * couple::ParticleSide::time_step(&dem);
                    let state = couple::ParticleSide::state(&dem);
                    let t0 = crate::fluid::RunFluid::time(&fluid);
                    let at = (state.position, state.radius);
                    let cut = crate::mesh_part::native_on_part(
                        plan,
                        couple::FluidSide::mesh(&fluid),
                        at,
                        t0,
                        dt_c,
                    )?;
                    (ctx.part_mesh, ctx.part, ctx.whole) = cut;
                }
                couple_loop(ctx, dem, fluid, events)
            }
            FluidBackend::Native => {
                let state = couple::ParticleSide::state(&dem);
                let (stand_in, part) =
                    crate::mesh_part::stand_in_on_part(plan, state.position, state.radius)?;
                ctx.part = part;
                couple_loop(ctx, dem, stand_in, events)
            }
            #[cfg(feature = "mpi")]
            FluidBackend::OpenFoam => {
                // every rank joins the spawn and gets its own link to the solver's ranks
                let (fluid, cells) = open_foam_ranked(world, layout, ctx.opts.fluid_ranks)?;
                ctx.owners = Some(Box::new(cells));
                match fluid {
                    Some(fluid) => {
                        // rank 0 on its part too: the solver's ranks hold the fluid
                        let dt_c = plan.settings.coupling_interval as f64
                            * couple::ParticleSide::time_step(&dem);
                        let state = couple::ParticleSide::state(&dem);
                        let (fluid, part, whole) = crate::mesh_part::foam_on_part(
                            plan,
                            fluid,
                            state.position,
                            state.radius,
                            dt_c,
                        )?;
                        (ctx.part, ctx.whole) = (part, whole);
                        couple_loop(ctx, dem, fluid, events)
                    }
                    None => {
                        let state = couple::ParticleSide::state(&dem);
                        let (stand_in, part) =
                            crate::mesh_part::stand_in_on_part(plan, state.position, state.radius)?;
                        ctx.part = part;
                        couple_loop(ctx, dem, stand_in, events)
                    }
                }
            }
            #[cfg(not(feature = "mpi"))]
            FluidBackend::OpenFoam => Err(unavailable(
                fluid,
                DemBackend::Liggghts,
                "this foamgrain lacks the cargo feature `mpi`",
            )),
        }
    }

    #[cfg(not(feature = "liggghts"))]
    fn ranked(
        _ctx: LoopContext<'_>,
        fluid: FluidBackend,
        _launch: &Launch,
        _world: &mpi::topology::SimpleCommunicator,
        _events: &mut dyn FnMut(Event),
    ) -> Result<RunReport, RunError> {
        Err(unavailable(
            fluid,
            DemBackend::Liggghts,
            "N ranks run LIGGGHTS in-process: build foamgrain with `--features mpi,liggghts`",
        ))
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
        foam_can_carry(layout, false)?;
        let solver = solver_path()?;
        let ranks = match ranks {
            0 => foam_link::case_setup::decomposed_ranks(&layout.cfd)
                .map_err(|e| backend_err("grainPisoFoam", e))?
                .unwrap_or(1),
            n => n,
        };
        let forces = &layout.coupling.forces;
        let options = foam_link::SpawnOptions {
            heat: layout.coupling.heat.is_some(),
            cfdem_ksl: None,
            vorticity: forces.needs_vorticity(),
            ddt_u: forces.needs_ddt_u(),
        };
        let fluid =
            foam_link::OpenFoamFluid::spawn_with(world, &layout.cfd, ranks, &solver, options)
                .map_err(|e| backend_err("grainPisoFoam", e))?;
        Ok(crate::foam_fluid::FoamFluid::new(fluid))
    }

    /// grainPisoFoam spawned from all the coupler's ranks ([`foam_link::OpenFoamFluid::spawn_ranked`]):
    /// rank 0 gets the fluid (with the whole mesh the spawn read), every rank its link to the
    /// solver ranks.
    #[cfg(all(feature = "mpi", feature = "liggghts"))]
    fn open_foam_ranked(
        world: &mpi::topology::SimpleCommunicator,
        layout: &crate::layout::CaseLayout,
        ranks: usize,
    ) -> Result<(Option<foam_link::OpenFoamFluid>, foam_link::SolverCells), RunError> {
        foam_can_carry(layout, true)?;
        let solver = if mpi::topology::Communicator::rank(world) == 0 {
            solver_path()?
        } else {
            PathBuf::new()
        };
        let ranks = match ranks {
            0 => foam_link::case_setup::decomposed_ranks(&layout.cfd)
                .map_err(|e| backend_err("grainPisoFoam", e))?
                .unwrap_or(1),
            n => n,
        };
        let (fluid, cells) = foam_link::OpenFoamFluid::spawn_ranked_with(
            world,
            &layout.cfd,
            ranks,
            &solver,
            foam_link::SpawnOptions {
                heat: layout.coupling.heat.is_some(),
                cfdem_ksl: layout.coupling.momentum.ksl_form().cfdem(),
                vorticity: false,
                ddt_u: false,
            },
        )
        .map_err(|e| backend_err("grainPisoFoam", e))?;
        Ok((fluid, cells))
    }
}
