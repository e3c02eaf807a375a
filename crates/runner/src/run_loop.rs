//! Stage 2 on any pair of sides ([`couple_loop`]): the schedule ([`Schedule`]), the coupler
//! with its ranks and smoothing, what is observed and written as the steps close
//! ([`crate::outputs`]), the steps themselves ([`Stage2::steps`]) and the end of the run — the
//! per-rank report, the population's balance, CFDEM's clock and the checks ([`Stage2::finish`]).
//!
//! The order of a step (ARCHITECTURE.md, "The run loop"): the DEM advances interval k → the
//! exchange k → the fluid advances interval k → the step closes. Where the fluid computes in
//! processes of its own its advance k runs while the DEM advances interval k + 1, and step k
//! closes after that ([`crate::outputs::Open`]); the results are the sequential order's bit for
//! bit.

use crate::checks;
use crate::error::{io_err, setup_err, RunError};
use crate::fluid::RunFluid;
use crate::layout::ValidationSpec;
use crate::monitors::RunMonitors;
use crate::outputs::{population_summary, pvd_entries_until, Observer, Open, Outputs};
use crate::plan::FluidBackend;
use crate::plan::{RunOptions, RunPlan};
use crate::report::{Event, RunReport};
use crate::timed::Timed;
use crate::validation::write_json;
use crate::whole::{Observed, WholeMesh};
use couple::{Coupler, FluidSide, ParticleSide};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Coupling intervals of `dt_c` seconds from `start` to `end` (the last one may end past
/// `end`; a rounding error of 1e-9 intervals does not add one).
pub(crate) fn coupling_steps(start: f64, end: f64, dt_c: f64) -> u64 {
    ((end - start) / dt_c - 1e-9).ceil().max(0.0) as u64
}

/// Everything the coupled loop needs besides its two sides.
pub(crate) struct LoopContext<'a> {
    /// The case, read once.
    pub(crate) plan: &'a RunPlan,
    pub(crate) opts: &'a RunOptions,
    pub(crate) stop: &'a AtomicBool,
    pub(crate) init_seconds: f64,
    /// The coupler's ranks on N ranks (`None`: one process).
    pub(crate) ranks: Option<Box<dyn couple::Ranks>>,
    /// On N ranks with grainPisoFoam: the straight link to the solver ranks owning the cells
    /// ([`couple::ranks::CellOwners`]).
    pub(crate) owners: Option<Box<dyn couple::ranks::CellOwners>>,
    /// The part of the mesh this coupler rank holds ([`couple::part`]; every rank but 0, and
    /// rank 0 too on N ranks unless the mesh cannot be cut; `None`: the whole mesh).
    pub(crate) part: Option<couple::part::Parted>,
    /// On coupler rank 0 with the native fluid on several ranks: the mesh of its coupler's
    /// part (the fluid holds the whole mesh; [`crate::mesh_part::native_on_part`]).
    pub(crate) part_mesh: Option<foam::PolyMesh>,
    /// On coupler rank 0 holding a part of the mesh: what it keeps of the whole mesh and
    /// observes on it ([`crate::whole`]).
    pub(crate) whole: Option<(WholeMesh, Observed)>,
}

/// The loop's clock: coupling interval, steps, write interval.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Schedule {
    /// The coupling interval, s: `couplingInterval` DEM steps.
    pub(crate) dt_c: f64,
    /// Fluid steps per coupling interval.
    pub(crate) fluid_steps: f64,
    /// The fluid's time at the start (> 0: a restart), s.
    pub(crate) start: f64,
    /// The end time, s.
    pub(crate) end: f64,
    /// Coupling steps to run.
    pub(crate) steps: u64,
    /// A time is written every this many coupling steps (and at the last).
    pub(crate) write_every: u64,
}

impl Schedule {
    /// The schedule of a run whose DEM steps `dem_dt` seconds and whose fluid starts at
    /// `start`; the fluid's `deltaT` must divide the coupling interval.
    pub(crate) fn of(
        plan: &RunPlan,
        opts: &RunOptions,
        dem_dt: f64,
        start: f64,
    ) -> Result<Schedule, RunError> {
        let interval = plan.settings.coupling_interval;
        let cfd_dt = plan.fluid.delta_t;
        let dt_c = interval as f64 * dem_dt;
        let ratio = dt_c / cfd_dt;
        if (ratio - ratio.round()).abs() > 1e-6 * ratio || ratio.round() < 1.0 {
            return Err(setup_err(
                &plan.layout.control.path,
                format!(
                    "deltaT {cfd_dt} s must divide the coupling interval {interval} × {dem_dt} s \
                     = {dt_c} s"
                ),
            ));
        }
        let end = plan.end_time(opts);
        let write_every = match plan.fluid.write {
            fv::settings::WriteControl::RunTime(t) => (t / dt_c).round().max(1.0) as u64,
            fv::settings::WriteControl::TimeStep(n) => {
                ((n as f64 * cfd_dt) / dt_c).round().max(1.0) as u64
            }
        };
        Ok(Schedule {
            dt_c,
            fluid_steps: ratio.round(),
            start,
            end,
            steps: coupling_steps(start, end, dt_c),
            write_every,
        })
    }
}

/// Stage 2 on any pair of sides: the schedule, the samples, the outputs and the checks.
pub(crate) fn couple_loop<P: ParticleSide, F: RunFluid>(
    ctx: LoopContext<'_>,
    dem: P,
    fluid: F,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let mesh = fluid.mesh().clone();
    let mut ctx = ctx;
    let (whole, observed) = ctx.whole.take().unzip();
    let mut run = Stage2::open(ctx, &mesh, whole.as_ref(), dem, fluid, events)?;
    run.observed = observed;
    let observer = run.observer(events);
    let mut out = run.outputs(&observer, events)?;
    run.watch(&observer, &out, events)?;
    let t_loop = Instant::now();
    let (stopped, held_max) = run.steps(&observer, &mut out, events)?;
    let Outputs {
        monitors,
        samples,
        output_seconds,
        profiles,
        slabs,
        ..
    } = out;
    let end = End {
        monitors,
        samples,
        profiles,
        slabs,
        output_seconds,
        t_loop,
        stopped,
        held_max,
    };
    run.finish(end, events)
}

/// The coupled run under way: its sides, the coupler and the schedule.
struct Stage2<'a, P: ParticleSide, F: RunFluid> {
    plan: &'a RunPlan,
    opts: &'a RunOptions,
    stop: &'a AtomicBool,
    init_seconds: f64,
    /// The mesh the coupler holds (rank 0's part, with `whole`).
    mesh: &'a foam::PolyMesh,
    /// On rank 0 holding a part: what it keeps of the whole mesh ([`crate::whole`]).
    whole: Option<&'a WholeMesh>,
    /// What the observer measures, when measured before the loop (rank 0 on a part).
    observed: Option<Observed>,
    dem: Timed<P>,
    fluid: Timed<F>,
    coupler: Coupler,
    schedule: Schedule,
    /// grainPisoFoam's advance of step k runs during the DEM's interval k + 1.
    overlap: bool,
    /// The fluid's cells are on grainPisoFoam's ranks ([`couple::ranks::CellOwners`]).
    owned: bool,
    rank: usize,
    n_ranks: usize,
    /// The particles at the start (all ranks') and their volume (this rank's).
    n_particles: usize,
    initial_volume: f64,
}

/// What the loop leaves for the end of the run.
struct End {
    monitors: RunMonitors,
    samples: Vec<crate::sample::Sample>,
    profiles: crate::heating_run::Profiles,
    slabs: crate::slab_profile::Record,
    output_seconds: f64,
    t_loop: Instant,
    stopped: bool,
    held_max: usize,
}

impl<'a, P: ParticleSide, F: RunFluid> Stage2<'a, P, F> {
    /// The coupler on the sides' mesh with the run's ranks and smoothing, the schedule and the
    /// initial voidage; announces the run.
    fn open(
        ctx: LoopContext<'a>,
        mesh: &'a foam::PolyMesh,
        whole: Option<&'a WholeMesh>,
        dem: P,
        fluid: F,
        events: &mut dyn FnMut(Event),
    ) -> Result<Self, RunError> {
        let LoopContext {
            plan,
            opts,
            stop,
            init_seconds,
            ranks,
            owners,
            part,
            part_mesh,
            whole: _,
        } = ctx;
        let dem = Timed::new(dem);
        let mut fluid = Timed::new(fluid);
        let owned = owners.is_some();
        if owned && (plan.layout.coupling.monitors.needs_fields() || plan.settings.heat.is_some()) {
            // the monitors, and with heat the outlet gas temperature and a heating case's gas
            // profile, read whole fields on rank 0, which no coupler rank holds otherwise
            fluid.inner.want_held();
        }
        let schedule = Schedule::of(plan, opts, dem.time_step(), fluid.inner.time())?;
        let mut coupler = Coupler::new(part_mesh.as_ref().unwrap_or(mesh), plan.settings)?;
        if let (Some(_), Some(w)) = (&part_mesh, whole) {
            // the native fluid on rank 0: the coupler sums the ranks into whole fields
            coupler.set_root_volumes(w.cell_volumes.clone());
        }
        drop(part_mesh);
        coupler.set_coupling_time_step(plan.settings.coupling_interval as f64 * dem.time_step());
        if let Some(ranks) = ranks {
            coupler.set_ranks(ranks);
        }
        if let Some(owners) = owners {
            coupler.set_owners(owners);
        }
        if let Some(part) = part {
            coupler.set_part(part);
        }
        if let Some(s) = plan.layout.coupling.smoothing {
            coupler.set_smoothing(crate::smoothing::native(mesh, s)?);
        }
        coupler.set_ksl_form(plan.layout.coupling.momentum.ksl_form());
        coupler.set_bed_heat(crate::bed_heat::bed_heat(plan, mesh)?);
        let (rank, n_ranks) = (coupler.ranks().rank(), coupler.ranks().size());
        // The voidage of the initial particles, so that the first coupling interval blends
        // from it (not from an empty domain, which would make ∂ε/∂t a spurious source).
        let initial_volume = coupler
            .exchange(&dem.state(), &fluid.state())?
            .deposit
            .particle_volume;
        let n_particles = {
            let mut n = [dem.state().len() as f64];
            coupler.ranks().all_sum(&mut n);
            n[0] as usize
        };
        let overlap = !opts.no_overlap && fluid.inner.runs_apart();
        let run = Stage2 {
            plan,
            opts,
            stop,
            init_seconds,
            mesh,
            whole,
            observed: None,
            dem,
            fluid,
            coupler,
            schedule,
            overlap,
            owned,
            rank,
            n_ranks,
            n_particles,
            initial_volume,
        };
        run.announce(events);
        Ok(run)
    }

    /// Cells of the whole mesh (rank 0 on a part holds fewer).
    fn whole_cells(&self) -> usize {
        self.whole.map_or(self.mesh.n_cells, |w| w.shell.n_cells)
    }

    /// The log lines that open stage 2.
    fn announce(&self, events: &mut dyn FnMut(Event)) {
        let n_ranks = self.n_ranks;
        if n_ranks > 1 {
            events(Event::Message(if self.owned {
                format!(
                    "{n_ranks} ranks: LIGGGHTS on each, each rank couples the particles its \
                     LIGGGHTS rank owns and exchanges the cells they touch straight with the \
                     grainPisoFoam ranks owning them"
                )
            } else {
                format!(
                    "{n_ranks} ranks: LIGGGHTS on each, each rank couples the particles its \
                     LIGGGHTS rank owns; the fluid on rank 0"
                )
            }));
            if self.plan.layout.coupling.monitors.basic_io {
                events(Event::Message(
                    "warning: the IOModel's particle files are not written on several ranks \
                     (no rank holds all particles); the deck's dumps have them"
                        .into(),
                ));
            }
            if self.plan.layout.coupling.monitors.particle_probe.is_some() {
                events(Event::Message(
                    "warning: particleProbe's files are not written on several ranks".into(),
                ));
            }
        }
        let s = &self.schedule;
        events(Event::Message(format!(
            "stage 2: {} particles, {} cells, {} coupling steps of {} s ({} DEM + {} fluid steps each), model {}, voidage {}",
            self.n_particles,
            self.whole_cells(),
            s.steps,
            s.dt_c,
            self.plan.settings.coupling_interval,
            s.fluid_steps,
            self.plan.layout.coupling.model.name(),
            self.plan.settings.method.name(),
        )));
    }

    /// What a step's sample measures: the column along the flow (the validationDict's axis,
    /// else against gravity) and the inlet and outlet patches (the validationDict's, else the
    /// ones the start fields' boundary conditions make inlet and outlet); on N ranks rank 0's
    /// column and bins, which rank 0 measured on the whole mesh ([`crate::whole`]).
    fn observer(&mut self, events: &mut dyn FnMut(Event)) -> Observer {
        let observed = self.observed.take().unwrap_or_else(|| {
            let geometry = self.coupler.voidage_mesh().geometry();
            let s = &self.schedule;
            crate::whole::observed(self.plan, self.mesh, geometry, s.start, s.dt_c)
        });
        let crate::whole::Observed {
            mut column,
            inlet,
            outlet,
            notes,
            outlet_cells,
            air_cells,
            mut heating,
            mut slabs,
        } = observed;
        for note in notes {
            events(Event::Message(note));
        }
        let ranks = self.coupler.ranks();
        if self.n_ranks > 1 {
            // rank 0's: a rank holding a part of the mesh sees only its part
            let mut c = [column.floor, column.area];
            ranks.broadcast(&mut c);
            [column.floor, column.area] = c;
            heating.iter_mut().for_each(|h| h.agree(ranks));
            slabs.iter_mut().for_each(|s| s.agree(ranks));
        }
        let physics = &self.plan.settings.physics;
        let spec = &self.plan.layout.validation;
        Observer {
            air_cells,
            outlet_cells,
            heating,
            slabs,
            column,
            rho: physics.rho,
            g: physics.gravity.dot(&physics.gravity).sqrt(),
            inlet,
            outlet,
            conveyor: match spec {
                Some(ValidationSpec::PneumaticConveying(c)) => Some(c.clone()),
                _ => None,
            },
        }
    }

    /// Coupler rank 0 in grainPisoFoam's sparse exchange (without the whole replies the
    /// monitors ask for) holds no current fluid field: the solver ranks send it U of the cells
    /// the observer samples (a conveyor's air) and, for `checkCouplingInterval`, max |U|/∛V
    /// after each advance ([`RunFluid::watch`]).
    fn watch(
        &mut self,
        observer: &Observer,
        out: &Outputs<'_>,
        events: &mut dyn FnMut(Event),
    ) -> Result<(), RunError> {
        if self.rank != 0 || !self.owned {
            return Ok(());
        }
        let cells = observer
            .air_cells
            .as_ref()
            .map(crate::branch::AirCells::listed)
            .unwrap_or_default();
        let cfl = out.interval_checks.is_some();
        let watching = (!cells.is_empty() || cfl)
            && (self.fluid.inner)
                .watch(&cells, cfl)
                .map_err(RunError::Fluid)?;
        if !watching {
            return Ok(());
        }
        events(Event::Message(format!(
            "rank 0 samples U of {} cells{} from grainPisoFoam's ranks after each advance",
            cells.len(),
            if cfl { " and max |U|/∛V" } else { "" }
        )));
        Ok(())
    }

    /// What the run writes as its steps close; a run started from a later time
    /// (`startFrom latestTime`, a restart) continues the earlier run's series: its rows and
    /// particle files up to the start time are kept.
    fn outputs<'o>(
        &self,
        observer: &'o Observer,
        events: &mut dyn FnMut(Event),
    ) -> Result<Outputs<'o>, RunError>
    where
        'a: 'o,
    {
        let plan: &'a RunPlan = self.plan;
        // the monitors' whole fields are written on the whole mesh: rank 0 on a part has its
        // cell count, patches and cell volumes; its coupler's own ε is never set there with
        // grainPisoFoam on several ranks (the owners hold ε), and is whole with the native
        // fluid (the coupler's root sums), the ones a whole-mesh coupler holds
        let (mesh, eps_before, cell_volumes): (&'a foam::PolyMesh, _, _) = match self.whole {
            Some(w) if self.owned => (&w.shell, vec![1.0; w.shell.n_cells], w.cell_volumes.clone()),
            Some(w) => (
                &w.shell,
                self.coupler.voidage().to_vec(),
                w.cell_volumes.clone(),
            ),
            None => (
                self.mesh,
                self.coupler.voidage().to_vec(),
                self.coupler.voidage_mesh().geometry().cell_volumes.clone(),
            ),
        };
        let layout = &plan.layout;
        let s = self.schedule;
        let post = layout.post_processing();
        let csv = post.join("integrals.csv");
        let restart = s.start > 0.0;
        let (kept_rows, vtp) = match restart {
            true => (
                crate::sample::rows_until(&csv, s.start),
                pvd_entries_until(&post.join("particles/particles.pvd"), s.start),
            ),
            false => (Vec::new(), Vec::new()),
        };
        if restart {
            events(Event::Message(format!(
                "restart at t = {} s: {} rows of integrals.csv and {} particle files kept",
                s.start,
                kept_rows.len(),
                vtp.len()
            )));
        }
        if self.overlap {
            events(Event::Message(
                "overlap: the fluid's advance runs during the next DEM interval (not at write \
                 times or liggghtsCommands; --no-overlap for the sequential order)"
                    .into(),
            ));
        }
        let start_name = couple::output::time_name(s.start);
        let (probes, surface) = self.function_objects(&start_name, events)?;
        Ok(Outputs {
            layout,
            observer,
            monitors: RunMonitors::new(&layout.coupling.monitors, &layout.cfd, &start_name),
            interval_checks: crate::interval_check::IntervalChecks::new(
                layout.coupling.monitors.interval_check,
                s.dt_c,
                s.dt_c / s.fluid_steps,
            ),
            particle_probes: self.particle_probes(&start_name)?,
            probes,
            surface,
            commands: &plan.commands,
            command_runs: vec![0; plan.commands.commands.len()],
            csv,
            kept_rows,
            samples: Vec::with_capacity(s.steps as usize),
            vtp,
            eps_before,
            ddt_eps: vec![0.0; mesh.n_cells],
            cell_volumes,
            mesh,
            rho: self.plan.settings.physics.rho,
            writes: 0,
            output_seconds: 0.0,
            start: s.start,
            end: s.end,
            dt_c: s.dt_c,
            steps: s.steps,
            rank: self.rank,
            n_ranks: self.n_ranks,
            profiles: crate::heating_run::Profiles {
                snapshots: Vec::new(),
                cell_size: observer
                    .heating
                    .as_ref()
                    .map_or(f64::NAN, |p| p.cell_size()),
                particle_capacity: plan.run_deck.materials().thermal_capacity,
            },
            slabs: crate::slab_profile::Record {
                profiler: observer.slabs.clone(),
                rows: Vec::new(),
            },
        })
    }

    /// `probeModel particleProbe`'s files (one rank; with `verboseToFile`).
    fn particle_probes(
        &self,
        start_name: &str,
    ) -> Result<Option<crate::particle_probe::ParticleProbes>, RunError> {
        let Some(cfg) = &self.plan.layout.coupling.monitors.particle_probe else {
            return Ok(None);
        };
        if self.n_ranks > 1 {
            return Ok(None);
        }
        let control = &self.plan.layout.control;
        let precision = crate::probes::write_precision(&control.body)
            .map_err(|m| setup_err(&control.path, m))?;
        Ok(crate::particle_probe::ParticleProbes::new(
            cfg,
            &self.plan.settings.physics,
            &self.plan.layout.cfd,
            start_name,
            self.rank,
            precision,
        ))
    }

    /// The controlDict's `probes` and `surfaceFieldValue`, which the native fluid runs on
    /// rank 0 (grainPisoFoam runs OpenFOAM's own).
    fn function_objects(
        &self,
        start_name: &str,
        events: &mut dyn FnMut(Event),
    ) -> Result<(crate::probes::Probes, crate::surface_values::SurfaceValues), RunError> {
        if self.opts.fluid != FluidBackend::Native || self.rank != 0 {
            return Ok(Default::default());
        }
        let cfd = &self.plan.layout.cfd;
        let control = &self.plan.layout.control;
        let locator = self.coupler.voidage_mesh().locator();
        // rank 0's coupler on a part: the probes are located on the fluid's whole mesh, whose
        // locator is built (and dropped) only when there are probes
        let whole = std::cell::OnceCell::new();
        let on_part = self.coupler.part().is_some();
        let locate = |x| match on_part {
            false => locator.locate(x),
            true => whole
                .get_or_init(|| {
                    let g = mesh::MeshGeometry::new(self.mesh).ok()?;
                    mesh::Locator::new(self.mesh, &g).ok()
                })
                .as_ref()
                .and_then(|l: &mesh::Locator| l.locate(x)),
        };
        let heat = self.plan.settings.heat.is_some();
        let (probes, warnings) =
            crate::probes::Probes::read(cfd, control, start_name, heat, &|x| {
                locate(x).map(|c| c as usize)
            })?;
        for w in warnings {
            events(Event::Message(format!("warning: {w}")));
        }
        let patches: Vec<String> = self.mesh.boundary.iter().map(|p| p.name.clone()).collect();
        let (surface, warnings) =
            crate::surface_values::SurfaceValues::read(cfd, control, start_name, &patches)?;
        for w in warnings {
            events(Event::Message(format!("warning: {w}")));
        }
        Ok((probes, surface))
    }

    /// The coupling steps; returns whether a stop request ended them early and the most
    /// particles this rank held.
    fn steps(
        &mut self,
        observer: &Observer,
        out: &mut Outputs<'_>,
        events: &mut dyn FnMut(Event),
    ) -> Result<(bool, usize), RunError> {
        let Schedule {
            steps,
            write_every,
            start,
            dt_c,
            ..
        } = self.schedule;
        let commands = &self.plan.commands;
        let whole = self.whole;
        let (dem, fluid, coupler) = (&mut self.dem, &mut self.fluid, &mut self.coupler);
        let mut held_max = 0;
        let mut evacuation = observer
            .conveyor
            .as_ref()
            .map(|_| crate::conveyor::Evacuation::default());
        let mut open: Option<Open> = None;
        events(Event::LoopStarted { steps });
        for k in 1..=steps {
            // on N ranks: the ranks enter LIGGGHTS's run together, so that none spins in its
            // first collective while rank 0 writes or waits for grainPisoFoam
            coupler.ranks().meet();
            coupler.advance_particles(dem)?;
            if let Some(o) = open.take() {
                fluid.finish_advance().map_err(RunError::Fluid)?;
                let step = out.close(o, dem, fluid, coupler.ranks(), events)?;
                coupler.recycle(step);
            }
            let (step, dt) = coupler.hand_over(dem, fluid)?;
            if coupler.part().is_some() {
                fluid.inner.cells_held(coupler.voidage_mesh().n_cells());
            }
            if let Some(c) = &out.interval_checks {
                let state = fluid.inner.state();
                let volumes = whole.map(|w| &w.cell_volumes[..]);
                let u_by_size = fluid.inner.watched().and_then(|w| w.u_by_size);
                let ps = dem.state();
                if let Some(lines) =
                    c.check(k, coupler, &step, &ps, &state, volumes, u_by_size, dt_c)?
                {
                    lines.into_iter().for_each(|l| events(Event::Message(l)));
                }
            }
            if let Some(p) = &mut out.particle_probes {
                // the exchange's values, before the fluid advances
                let physics = &coupler.settings().physics;
                let voidage = &step.voidage.epsilon;
                let state = fluid.inner.state();
                // the time the step's exchange closes, as the fluid names it (the coupling
                // clock's k·Δt_c carries the DEM step's rounding in its last digits)
                let t = start + k as f64 * dt_c;
                let t = couple::output::time_name(t).parse().unwrap_or(t);
                p.sample(t, physics, &step.placement, &state, voidage, &dem.state())?;
            }
            fluid.start_advance(dt).map_err(RunError::Fluid)?;
            // the native fluid advances on rank 0 alone: the others sleep meanwhile
            coupler.ranks().meet();
            held_max = held_max.max(dem.state().len());
            let mut sample = observer.sample(&*dem, &step, coupler.ranks(), evacuation.as_mut());
            if self.plan.layout.coupling.wall_heat.is_some() {
                // wallHeatTransferYagi: the walls' heat into the fluid (its own column)
                sample.heat_from_wall = step.heat.as_ref().map(|h| h.account.from_wall);
            }
            // a heating case's solid profile at its sample times (collective on N ranks)
            let solid = observer
                .heating
                .as_ref()
                .filter(|p| p.due(dem.time()))
                .and_then(|p| p.solid(&dem.state(), coupler.ranks()));
            // a fluidised bed's voidage profiles (collective on N ranks)
            let slabs = observer.slabs.as_ref().map(|p| {
                let ps = dem.state();
                p.measure(ps.position, ps.radius, coupler.ranks())
            });
            // every rank stops at the same step (a signal reaches the ranks at different steps)
            let stop_now = {
                let mut s = [f64::from(u8::from(self.stop.load(Ordering::SeqCst)))];
                coupler.ranks().all_max(&mut s);
                s[0] > 0.0
            };
            let write_now = k % write_every == 0 || k == steps || stop_now;
            let located_volume =
                RunMonitors::wants_located_volume(&self.plan.layout.coupling.monitors)
                    .then(|| Observer::located_volume(&*dem, &step, coupler.ranks()));
            let o = Open {
                k,
                step,
                sample,
                write_now,
                solid,
                located_volume,
                slabs,
            };
            // writes and liggghtsCommands need the particles of step k and the fluid's clock
            let at_once = !self.overlap
                || write_now
                || commands
                    .commands
                    .iter()
                    .any(|c| c.may_be_due(k, steps, write_now));
            if !at_once {
                open = Some(o);
                continue;
            }
            fluid.finish_advance().map_err(RunError::Fluid)?;
            let step = out.close(o, dem, fluid, coupler.ranks(), events)?;
            coupler.recycle(step);
            if stop_now && k < steps {
                events(Event::Message(format!(
                    "stopped at t = {} s after step {k}; that time is written",
                    fluid.inner.time()
                )));
                return Ok((true, held_max));
            }
        }
        // the last step writes, so it has closed at once
        debug_assert!(open.is_none());
        Ok((false, held_max))
    }

    /// The end of the run: the fluid finishes, CFDEM's logs and clock, the per-rank report,
    /// the population's balance and the checks.
    fn finish(mut self, end: End, events: &mut dyn FnMut(Event)) -> Result<RunReport, RunError> {
        let End {
            monitors,
            samples,
            profiles,
            slabs,
            output_seconds,
            t_loop,
            stopped,
            held_max,
        } = end;
        let rank = self.rank;
        if let Some(line) = self.fluid.inner.report() {
            events(Event::Message(line));
        }
        self.fluid.inner.finish().map_err(RunError::Fluid)?;
        let loop_seconds = t_loop.elapsed().as_secs_f64();
        if rank == 0 {
            monitors.write_logs()?;
        }
        self.report_ranks(held_max, samples.len() as u64, events)?;
        let particles_at_end = {
            let mut n = [self.dem.state().len() as f64];
            self.coupler.ranks().all_sum(&mut n);
            n[0] as usize
        };
        let population = self.coupler.population_total();
        if population != couple::PopulationChange::default() {
            events(Event::Message(population_summary(
                self.n_particles,
                particles_at_end,
                &population,
                self.initial_volume,
                samples.last().map(|s| s.particle_volume),
            )));
        }
        let (dem_seconds, fluid_seconds) = (self.dem.seconds, self.fluid.seconds);
        let n_steps = samples.len() as u64;
        let coupling_seconds =
            (loop_seconds - dem_seconds - fluid_seconds - output_seconds).max(0.0);
        let sections = [
            ("Global", loop_seconds, 1),
            ("DEM", dem_seconds, n_steps),
            ("Flow", fluid_seconds, n_steps),
            ("Coupling", coupling_seconds, n_steps),
            ("Output", output_seconds, n_steps),
        ];
        if rank == 0 {
            for line in monitors
                .clock(&self.plan.layout.cfd, &sections)?
                .unwrap_or_default()
            {
                events(Event::Message(line));
            }
        }
        let checks = match !stopped && rank == 0 {
            true => self.checks(&samples, &profiles, &slabs, events)?,
            false => Vec::new(),
        };
        Ok(RunReport {
            rank,
            steps: samples.len() as u64,
            time: samples.last().map_or(self.schedule.start, |s| s.time),
            stopped,
            particles: self.n_particles,
            particles_at_end,
            population,
            cells: self.whole_cells(),
            init_seconds: self.init_seconds,
            loop_seconds,
            dem_seconds,
            fluid_seconds,
            output_seconds,
            checks,
            samples,
        })
    }

    /// `postProcessing/ranks.csv` (and its table on N ranks): per-rank particles, cells and
    /// bytes.
    fn report_ranks(
        &self,
        held_max: usize,
        n_steps: u64,
        events: &mut dyn FnMut(Event),
    ) -> Result<(), RunError> {
        let local = crate::ranks_report::Local {
            particles: self.dem.state().len(),
            particles_max: held_max,
            cells_touched: (self.n_ranks > 1).then(|| self.coupler.touched_cells()),
            solver_traffic: self.owned.then(|| self.coupler.owner_traffic()),
            cells_held: self.coupler.voidage_mesh().n_cells(),
            mesh_cuts: self.coupler.part().map(|p| p.cuts),
            held: self.held(),
        };
        let per_rank = crate::ranks_report::gather(self.coupler.ranks(), local, n_steps);
        if self.rank == 0 {
            let file = self.plan.layout.post_processing().join("ranks.csv");
            crate::ranks_report::write_csv(&file, &per_rank).map_err(io_err(&file))?;
            if self.n_ranks > 1 {
                for line in crate::ranks_report::table(&per_rank) {
                    events(Event::Message(line));
                }
            }
        }
        Ok(())
    }

    /// What this rank's coupler and sides hold for the cells and for the particles.
    fn held(&self) -> couple::HeldBytes {
        let sides = couple::HeldBytes {
            mesh: self.fluid.held_bytes().unwrap_or(0) + self.whole.map_or(0, |w| w.held_bytes()),
            particles: self.dem.held_bytes().unwrap_or(0),
        };
        self.coupler.held_bytes() + sides
    }

    /// The case's checks (`validationDict`), written to `postProcessing/validation.json`.
    fn checks(
        &self,
        samples: &[crate::sample::Sample],
        profiles: &crate::heating_run::Profiles,
        slabs: &crate::slab_profile::Record,
        events: &mut dyn FnMut(Event),
    ) -> Result<Vec<crate::validation::Check>, RunError> {
        let post: PathBuf = self.plan.layout.post_processing();
        if let Some(file) = crate::heat_plot::temperatures(samples, &post)? {
            events(Event::Message(format!(
                "temperature histories: {}",
                file.display()
            )));
        }
        let Some(spec) = &self.plan.layout.validation else {
            return Ok(Vec::new());
        };
        let mut notes = Vec::new();
        let checks = checks::evaluate(
            spec,
            &self.plan.settings,
            samples,
            checks::Recorded {
                heating: profiles,
                slabs,
            },
            &post,
            self.schedule.dt_c,
            &mut notes,
        )?;
        for note in notes {
            events(Event::Message(note));
        }
        let file = post.join("validation.json");
        write_json(&file, &checks).map_err(io_err(&file))?;
        Ok(checks)
    }
}
