//! `foamgrain run`: a coupled case on the native stack (native fluid + native DEM).
//!
//! 1. Stage 1 (packing): when the coupled deck starts from a file (`read_data FILE`, or CFDEM's
//!    `read_restart FILE`) that does not exist and `DEM/in.liggghts_init` does, the init deck
//!    is run first (natively, or with the liggghts binary for the LIGGGHTS backends); it writes
//!    that file.
//! 2. Stage 2: the coupled deck builds the DEM, `CFD/` the fluid, `couplingProperties` the
//!    coupler; `(endTime − startTime) / (couplingInterval · dt_DEM)` coupling steps follow.
//! 3. After every step the integral quantities ([`Sample`]) are recorded; at the case's write
//!    times the fluid (U, p), the exchange fields (voidfraction, Ksl, Us, f) and the particles
//!    (`CASE/postProcessing/particles/*.vtp` + `.pvd`) are written, and the CSV
//!    (`postProcessing/integrals.csv`) is rewritten.
//! 4. A stop request (Ctrl-C) ends the loop after the current step; that step's time is then
//!    written completely.
//! 5. The case's `validationDict` decides the checks ([`crate::checks`]); they go to
//!    `postProcessing/validation.json` with PNG plots.

use crate::backend::{DemBackend, FluidBackend};
use crate::checks;
use crate::fluid::RunFluid;
use crate::layout::{CaseLayout, LayoutError, ValidationSpec};
use crate::monitors::{RunMonitors, StepFields};
use crate::sample::{write_csv, Sample};
use crate::timed::Timed;
use crate::validation::{write_json, Check};
use closures::model::ModelType;
use couple::{Coupler, CouplerSettings, CouplingConfig, CouplingStep, FluidSide, ParticleSide};
use liggghts_deck::Deck;
use mesh::v3::{as_arrays, unit, V3};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Errors of a run; each names the file or the side it comes from.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The case layout or validationDict.
    #[error(transparent)]
    Layout(#[from] LayoutError),
    /// The coupling configuration or a coupling step.
    #[error(transparent)]
    Couple(#[from] couple::CoupleError),
    /// A LIGGGHTS deck that cannot be read (file, line).
    #[error(transparent)]
    Deck(#[from] liggghts_deck::DeckError),
    /// The native DEM (deck, setup, run).
    #[error(transparent)]
    Dem(#[from] dem::DemError),
    /// The native fluid.
    #[error("fluid: {0}")]
    Fluid(couple::SideError),
    /// A setting that cannot work together with another.
    #[error("{file}: {message}")]
    Setup {
        /// The file with the offending setting.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Writing an output.
    #[error("{}: {source}", path.display())]
    Io {
        /// The output.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Writing a field.
    #[error(transparent)]
    Foam(#[from] foam::FoamError),
    /// Writing particles.
    #[error(transparent)]
    Vtk(#[from] vtk::VtkError),
    /// Drawing a plot.
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// A backend that is not available or failed to start.
    #[error("{0}")]
    Backend(String),
}

/// Options of a run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Stop at this simulated time instead of `endTime`.
    pub end_time: Option<f64>,
    /// Variables for the init deck (`-var NAME VALUE`, e.g. a smaller particle count).
    pub init_vars: Vec<(String, String)>,
    /// Pack again even if the packed-bed file exists.
    pub repack: bool,
    /// The fluid backend.
    pub fluid: FluidBackend,
    /// The particle backend.
    pub dem: DemBackend,
    /// MPI ranks of the fluid solver (OpenFOAM backend; 0: `numberOfSubdomains` of the case's
    /// `system/decomposeParDict`, 1 without one).
    pub fluid_ranks: usize,
    /// Advance the fluid and the DEM one after the other even where the fluid computes in
    /// processes of its own (grainPisoFoam), whose advance otherwise runs during the next DEM
    /// interval; the results are the same bit for bit.
    pub no_overlap: bool,
}

/// What a run reports as it goes.
#[derive(Clone, Debug)]
pub enum Event {
    /// A log line.
    Message(String),
    /// Progress after a coupling step.
    Step {
        /// Simulated time, s.
        time: f64,
        /// End time, s.
        end: f64,
        /// Steps done.
        step: u64,
        /// Steps in total.
        steps: u64,
        /// The step's integrals.
        sample: Box<Sample>,
    },
}

/// The outcome of a run.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// This process's rank in an `mpirun -np N` run (0 alone); only rank 0's report holds
    /// the samples and checks.
    pub rank: usize,
    /// Coupling steps done.
    pub steps: u64,
    /// Simulated time reached, s.
    pub time: f64,
    /// True when a stop request ended the run early.
    pub stopped: bool,
    /// Particles at the start of the coupled stage (over all ranks).
    pub particles: usize,
    /// Particles at its end (over all ranks).
    pub particles_at_end: usize,
    /// What entered and left during the coupled stage ([`couple::population`]).
    pub population: couple::PopulationChange,
    /// Fluid cells.
    pub cells: usize,
    /// Wall-clock seconds of stage 1 (packing; 0 when skipped).
    pub init_seconds: f64,
    /// Wall-clock seconds of the coupled loop (stage 2).
    pub loop_seconds: f64,
    /// Of which in the DEM's advance.
    pub dem_seconds: f64,
    /// Of which in the fluid's advance.
    pub fluid_seconds: f64,
    /// Of which in output writing.
    pub output_seconds: f64,
    /// The checks (empty without validationDict or when stopped early).
    pub checks: Vec<Check>,
    /// The samples of every step.
    pub samples: Vec<Sample>,
}

impl RunReport {
    /// Wall-clock seconds of the coupler itself (locate, voidage, forces, exchange):
    /// the loop minus DEM, fluid and output.
    pub fn coupling_seconds(&self) -> f64 {
        (self.loop_seconds - self.dem_seconds - self.fluid_seconds - self.output_seconds).max(0.0)
    }
}

/// The column the integrals are measured in: axis, floor and cross-section.
#[derive(Clone, Copy, Debug)]
struct Column {
    axis: V3,
    floor: f64,
    area: f64,
}

impl Column {
    fn of(mesh: &foam::PolyMesh, volume: f64, axis: V3) -> Column {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in &mesh.points {
            let h = V3::from(*p).dot(&axis);
            lo = lo.min(h);
            hi = hi.max(h);
        }
        Column {
            axis,
            floor: lo,
            area: volume / (hi - lo),
        }
    }
}

/// The file a coupled deck starts from — `read_data FILE` or `read_restart FILE` (CFDEM's
/// decks) — resolved against the deck's directory, and whether it exists (a `*` in a restart
/// name stands for any step, as LIGGGHTS reads the latest).
fn start_file(deck: &Deck, dem_dir: &Path) -> Option<(PathBuf, bool)> {
    let c = deck.commands.iter().find(|c| {
        matches!(
            c.words.first().map(String::as_str),
            Some("read_data" | "read_restart")
        )
    })?;
    let path = dem_dir.join(c.words.get(1)?);
    let exists = match path.file_name().and_then(|n| n.to_str()) {
        Some(name) if name.contains('*') => {
            let (head, tail) = name.split_once('*').unwrap_or((name, ""));
            path.parent()
                .and_then(|d| std::fs::read_dir(d).ok())
                .is_some_and(|entries| {
                    entries.flatten().any(|e| {
                        let n = e.file_name().to_string_lossy().into_owned();
                        n.len() >= head.len() + tail.len()
                            && n.starts_with(head)
                            && n.ends_with(tail)
                    })
                })
        }
        _ => path.exists(),
    };
    Some((path, exists))
}

fn setup_err(file: &Path, message: String) -> RunError {
    RunError::Setup {
        file: file.to_owned(),
        message,
    }
}

struct Observer {
    column: Column,
    rho: f64,
    g: f64,
    inlet: Option<String>,
    outlet: Option<String>,
    /// A conveyor case: its zones and the outlet whose outflow is sampled.
    conveyor: Option<crate::conveyor::ConveyorSpec>,
}

impl Observer {
    /// The step's integrals. Collective on N ranks (each gives its own particles); rank 0's
    /// sample is the run's.
    ///
    /// The particle side's part only: [`Observer::observe_fluid`] adds the time and the
    /// fluid's, once the fluid has advanced the step's interval.
    ///
    /// `evacuation` follows a conveyor's bed by id (rank 0 keeps it; the others pass theirs
    /// unused).
    fn sample<P: ParticleSide>(
        &self,
        dem: &P,
        step: &CouplingStep,
        ranks: &dyn couple::Ranks,
        evacuation: Option<&mut crate::conveyor::Evacuation>,
    ) -> Sample {
        let ps = dem.state();
        let ax = self.column.axis;
        let bed = crate::bed::Bed::measure_on(
            ranks,
            ps.position,
            ax,
            ps.radius,
            ps.density,
            self.column.floor,
            self.column.area,
        );
        let mut ke = 0.0;
        let mut axial = 0.0;
        for i in 0..ps.len() {
            let r = ps.radius[i];
            let m = ps.density[i] * voidage::sphere_box::ball_volume(r);
            ke += 0.5 * m * ps.velocity[i].dot(&ps.velocity[i]);
            axial += ps.velocity[i].dot(&ax);
        }
        let force: f64 = step.forces.particles.iter().map(|c| c.total.dot(&ax)).sum();
        let mut sums = [ke, axial, force, ps.len() as f64];
        ranks.all_sum(&mut sums);
        let [ke, axial, force, count] = sums;
        let count = count as usize;
        // the first particle: the lowest id over all ranks (the same particle however the
        // ranks or the DEM order their particles)
        let first = (0..ps.len())
            .min_by_key(|&i| ps.ids[i])
            .map(|i| [ps.ids[i] as f64, ps.velocity[i].dot(&ax)]);
        let first_axial_velocity = ranks
            .gather(first.as_ref().map_or(&[][..], |f| &f[..]))
            .iter()
            .filter(|v| v.len() == 2)
            .min_by(|a, b| a[0].total_cmp(&b[0]))
            .map_or(0.0, |v| v[1]);
        let zones = self.conveyor.as_ref().map(|spec| {
            let z = crate::conveyor::Zones::measure(spec, ax, ps.position, ps.velocity);
            let mut sums = [
                z.tube as f64,
                z.tube_axial_sum,
                z.chamber as f64,
                z.annulus as f64,
            ];
            ranks.all_sum(&mut sums);
            sums
        });
        let evacuated = match (&self.conveyor, evacuation) {
            (Some(spec), Some(ev)) => {
                let ids = crate::conveyor::annulus_ids(spec, ax, ps.position, ps.ids);
                let all: Vec<u64> = ranks
                    .gather(&ids)
                    .iter()
                    .flatten()
                    .map(|&id| id as u64)
                    .collect();
                (ranks.rank() == 0).then(|| ev.update(&all))
            }
            _ => None,
        };
        Sample {
            time: f64::NAN,
            inlet_velocity: None,
            pressure_drop: None,
            bed_height: bed.map(|b| b.height),
            bed_voidage: bed.map(|b| b.voidage),
            kinetic_energy: ke,
            mean_axial_velocity: if count == 0 {
                0.0
            } else {
                axial / count as f64
            },
            first_axial_velocity,
            fluid_force_axial: force,
            particle_volume: step.deposit.particle_volume,
            deposited_volume: step.deposit.deposited_volume,
            outside_volume: step.deposit.outside_volume,
            clipped_volume: step.voidage.clipped_volume,
            min_voidage: step.voidage.min_epsilon,
            particles: count,
            sauter_diameter: bed.map(|b| b.sauter_diameter),
            mean_density: bed.map(|b| b.mass / b.solid_volume),
            weight_per_area: bed.map(|b| b.weight_per_area(self.rho, self.g, self.column.area)),
            particles_in: step.population.entered,
            particles_out: step.population.left,
            volume_in: step.population.volume_in,
            volume_out: step.population.volume_out,
            momentum_in: step.population.momentum_in.into(),
            momentum_out: step.population.momentum_out.into(),
            outlet_velocity: None,
            tube_particles: zones.map(|z| z[0] as usize),
            tube_axial_velocity: zones.and_then(|z| (z[0] > 0.0).then(|| z[1] / z[0])),
            chamber_particles: zones.map(|z| z[2] as usize),
            annulus_particles: zones.map(|z| z[3] as usize),
            bed_particles: evacuated.map(|e| e.bed),
            bed_never_left: evacuated.map(|e| e.never_left),
            annulus_returned: evacuated.map(|e| e.returned),
        }
    }

    /// The fluid's part of a step's sample (rank 0's is the run's): its time and, from the
    /// patches, Δp between inlet and outlet, the inflow velocity and a conveyor's outflow.
    fn observe_fluid<F: RunFluid>(&self, sample: &mut Sample, fluid: &F) {
        let p_mean = |name: &Option<String>| name.as_deref().and_then(|n| fluid.patch_pressure(n));
        sample.time = fluid.time();
        sample.pressure_drop = match (p_mean(&self.inlet), p_mean(&self.outlet)) {
            (Some(a), Some(b)) => Some(self.rho * (a - b)),
            _ => None,
        };
        sample.inlet_velocity = self.inlet.as_deref().and_then(|n| fluid.inflow_velocity(n));
        sample.outlet_velocity = self
            .conveyor
            .as_ref()
            .and_then(|spec| fluid.inflow_velocity(&spec.outlet))
            .map(|u| -u);
    }
}

/// A coupling step whose particle side is done (advanced, sampled) while the fluid may still
/// be advancing its interval: with grainPisoFoam the run starts the next DEM interval before
/// it waits for the fluid, then closes this step ([`Outputs::close`]) with the fluid's time,
/// patches and state after the interval, as the sequential order would. Steps that write, stop
/// or may run liggghtsCommands close before the DEM goes on (they need the particles of the
/// step and the fluid's clock).
struct Open {
    /// The step's number (1-based).
    k: u64,
    step: CouplingStep,
    /// Its particle side's part.
    sample: Sample,
    /// The step writes a time (write interval, last step or stop).
    write_now: bool,
}

/// What the run writes as its steps close: samples, monitors, time directories, particles.
struct Outputs<'a> {
    layout: &'a CaseLayout,
    observer: &'a Observer,
    monitors: RunMonitors,
    /// The controlDict's `probes` on the native fluid (grainPisoFoam runs OpenFOAM's own).
    probes: crate::probes::Probes,
    /// The controlDict's `surfaceFieldValue`s on the native fluid (likewise).
    surface: crate::surface_values::SurfaceValues,
    commands: &'a couple::config::LiggghtsCommands,
    csv: PathBuf,
    kept_rows: Vec<String>,
    samples: Vec<Sample>,
    vtp: Vec<(f64, PathBuf)>,
    /// ε of the last step (for ∂ε/∂t) and ∂ε/∂t, per cell.
    eps_before: Vec<f64>,
    ddt_eps: Vec<f64>,
    cell_volumes: Vec<f64>,
    mesh: &'a foam::PolyMesh,
    rho: f64,
    /// Write times so far.
    writes: u64,
    output_seconds: f64,
    start: f64,
    end: f64,
    dt_c: f64,
    steps: u64,
    rank: usize,
    n_ranks: usize,
}

impl Outputs<'_> {
    /// Closes step `o` once the fluid has advanced its interval: the fluid's part of the
    /// sample, the monitors, and at a write step (then `dem` still holds the step's particles)
    /// liggghtsCommands and the outputs. Returns the step for [`Coupler::recycle`]. Not
    /// collective on N ranks (only the particle files are written per rank).
    fn close<P: ParticleSide, F: RunFluid>(
        &mut self,
        o: Open,
        dem: &mut Timed<P>,
        fluid: &mut Timed<F>,
        events: &mut dyn FnMut(Event),
    ) -> Result<CouplingStep, RunError> {
        let Open {
            k,
            mut step,
            mut sample,
            write_now,
        } = o;
        if let Some(h) = fluid.inner.held_exchange() {
            // the cells' owners formed the whole fields (rank 0 holds only its own particles')
            step.voidage.epsilon = h.eps.to_vec();
            step.exchange.ksl = h.ksl.to_vec();
            step.exchange.us = h.us.to_vec();
            step.exchange.f = h.f.to_vec();
        }
        self.observer.observe_fluid(&mut sample, &fluid.inner);
        let time = sample.time;
        self.samples.push(sample);
        let rank = self.rank;
        if !self.monitors.is_empty() && rank == 0 {
            let eps = &step.voidage.epsilon;
            if self.monitors.needs_ddt {
                for ((d, e), b) in self.ddt_eps.iter_mut().zip(eps).zip(&self.eps_before) {
                    *d = (e - b) / self.dt_c;
                }
                self.eps_before.clone_from(eps);
            }
            let fields = StepFields::new(&step, &self.ddt_eps, fluid.inner.state(), self.rho);
            for line in self.monitors.observe(time, &self.cell_volumes, &fields) {
                events(Event::Message(line));
            }
        }
        if !self.probes.is_empty() {
            let fields = StepFields::new(&step, &self.ddt_eps, fluid.inner.state(), self.rho);
            self.probes.sample(time, write_now, &fields)?;
        }
        if !self.surface.is_empty() {
            self.surface.sample(time, write_now, &fluid.inner)?;
        }
        if write_now {
            self.writes += 1;
        }
        let now = couple::config::commands::Moment {
            step: k,
            steps: self.steps,
            time,
            elapsed: time - self.start,
            dt_c: self.dt_c,
            write: write_now,
            writes: self.writes,
        };
        for c in &self.commands.commands {
            if let Some(cmd) = c.due(now) {
                run_command(dem, &cmd, self.layout, events)?;
            }
        }
        if write_now {
            let t = Instant::now();
            let pieces = Pieces {
                rank,
                ranks: self.n_ranks,
                name: couple::output::time_name(self.start + k as f64 * self.dt_c),
            };
            let name = write_time(
                self.layout,
                &mut fluid.inner,
                self.mesh,
                &dem.state(),
                &step,
                &mut self.vtp,
                &pieces,
            )?;
            if rank == 0 {
                write_csv(&self.csv, &self.kept_rows, &self.samples).map_err(io_err(&self.csv))?;
            }
            if !self.monitors.is_empty() && rank == 0 {
                let fields = StepFields::new(&step, &self.ddt_eps, fluid.inner.state(), self.rho);
                let dir = self.layout.cfd.join(&name);
                let particles = dem.state();
                let particles = (self.n_ranks == 1).then_some(&particles);
                self.monitors
                    .write_time(&dir, &name, self.mesh, &fields, particles)?;
            }
            self.output_seconds += t.elapsed().as_secs_f64();
        }
        events(Event::Step {
            time,
            end: self.end,
            step: k,
            steps: self.steps,
            sample: Box::new(*self.samples.last().expect("pushed above")),
        });
        Ok(step)
    }
}

/// The end-of-run line of a changing population: particles and volume at the start, what
/// entered and left, at the end, and the balance V_end − V_start − (V_in − V_out) (round-off).
fn population_summary(
    start: usize,
    end: usize,
    c: &couple::PopulationChange,
    v_start: f64,
    v_end: Option<f64>,
) -> String {
    let v_end = v_end.unwrap_or(v_start);
    let p = |v: V3| format!("({:.6e}, {:.6e}, {:.6e})", v[0], v[1], v[2]);
    format!(
        "particles: {start} at the start ({v_start:.6e} m³), {} entered ({:.6e} m³, momentum {} \
         kg·m/s), {} left ({:.6e} m³, momentum {} kg·m/s), {end} at the end ({v_end:.6e} m³); \
         volume balance end − start − (in − out) = {:.3e} m³",
        c.entered,
        c.volume_in,
        p(c.momentum_in),
        c.left,
        c.volume_out,
        p(c.momentum_out),
        v_end - v_start - (c.volume_in - c.volume_out)
    )
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Which particle file a rank writes at an output time: one `particles_<time>.vtp` alone; on N
/// ranks each rank its own particles as `particles_<time>_<rank>.vtp`, the parts of that time
/// in `particles.pvd` (written by rank 0).
struct Pieces {
    rank: usize,
    ranks: usize,
    /// The output time's name from the coupling clock (the same on every rank).
    name: String,
}

/// Writes one output time: fluid U and p, the exchange fields and the particles.
fn write_time<F: RunFluid>(
    layout: &CaseLayout,
    fluid: &mut F,
    mesh: &foam::PolyMesh,
    ps: &couple::ParticleState<'_>,
    step: &CouplingStep,
    vtp: &mut Vec<(f64, PathBuf)>,
    pieces: &Pieces,
) -> Result<String, RunError> {
    let name = fluid
        .write_time(&layout.cfd, mesh, step)
        .map_err(RunError::Fluid)?;
    let pdir = layout.post_processing().join("particles");
    std::fs::create_dir_all(&pdir).map_err(io_err(&pdir))?;
    let piece = |r: usize| {
        if pieces.ranks == 1 {
            format!("particles_{name}.vtp")
        } else {
            format!("particles_{}_{r}.vtp", pieces.name)
        }
    };
    let file = pdir.join(piece(pieces.rank));
    let ids: Vec<i64> = ps.ids.iter().map(|&i| i as i64).collect();
    let fluid_force: Vec<V3> = step.forces.particles.iter().map(|c| c.total).collect();
    vtk::write_vtp(
        &file,
        as_arrays(ps.position),
        &[
            vtk::DataArray::int64("id", &ids),
            vtk::DataArray::scalar("radius", ps.radius),
            vtk::DataArray::vector("velocity", as_arrays(ps.velocity)),
            vtk::DataArray::vector("fluidForce", as_arrays(&fluid_force)),
        ],
    )?;
    if pieces.rank == 0 {
        for r in 0..pieces.ranks {
            vtp.push((fluid.time(), PathBuf::from(piece(r))));
        }
        vtk::write_pvd(pdir.join("particles.pvd"), vtp)?;
    }
    Ok(name)
}

/// The entries of a `.pvd` series written by an earlier run ([`vtk::write_pvd`]) up to time
/// `start` (s, to a relative 10⁻⁹): (time, file name) of each `<DataSet>`; none without the
/// file.
fn pvd_entries_until(path: &Path, start: f64) -> Vec<(f64, PathBuf)> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Vec::new();
    };
    let attr = |line: &str, key: &str| -> Option<String> {
        let from = line.find(&format!(" {key}=\""))? + key.len() + 3;
        let len = line[from..].find('"')?;
        Some(line[from..from + len].to_owned())
    };
    let until = start + 1e-9 * start.abs();
    text.lines()
        .filter(|l| l.trim_start().starts_with("<DataSet"))
        .filter_map(|l| {
            let time = attr(l, "timestep")?.parse::<f64>().ok()?;
            let file = attr(l, "file")?;
            (time <= until && !file.contains('&')).then(|| (time, PathBuf::from(file)))
        })
        .collect()
}

/// Runs the case at `case` (CFDEM layout) natively. `stop` is polled after every coupling step;
/// `events` receives log lines and progress.
pub fn run(
    case: &Path,
    opts: &RunOptions,
    stop: &AtomicBool,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let launch = crate::backend::Launch::init(opts.fluid, opts.dem)?;
    // On N ranks only rank 0 speaks (the others' log lines would repeat it N times), and an
    // error on any rank ends every rank with its cause (no rank waits for a dead one).
    let mut quiet = |_: Event| {};
    let events: &mut dyn FnMut(Event) = if launch.rank() > 0 {
        &mut quiet
    } else {
        events
    };
    let result = run_launched(case, opts, stop, &launch, events);
    if launch.size() > 1 {
        return result.map_err(|e| launch.fail_together(e));
    }
    result
}

/// [`run`] in the process layout `launch`.
fn run_launched(
    case: &Path,
    opts: &RunOptions,
    stop: &AtomicBool,
    launch: &crate::backend::Launch,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let layout = CaseLayout::open(case)?;
    let config = CouplingConfig::read_case(&layout.cfd)?;
    for w in &config.warnings {
        events(Event::Message(format!("warning: {w}")));
    }
    let settings = config.coupler_settings(&layout.cfd)?;
    let commands = couple::config::LiggghtsCommands::read_case(&layout.cfd)?;
    for w in &commands.warnings {
        events(Event::Message(format!("warning: {w}")));
    }
    if opts.fluid == FluidBackend::Native {
        for w in crate::native::control_dict_warnings(&layout.cfd) {
            events(Event::Message(format!("warning: {w}")));
        }
    }

    // Stage 1: the packed bed.
    let run_deck = Deck::read(&layout.run_deck)?;
    // On N ranks rank 0 packs alone; the others wait for it (and learn if it failed).
    let stage1 = |events: &mut dyn FnMut(Event)| -> Result<f64, RunError> {
        let mut init_seconds = 0.0;
        if let Some((data, exists)) = start_file(&run_deck, &layout.dem) {
            if opts.repack || !exists {
                let Some(init) = &layout.init_deck else {
                    return Err(setup_err(
                        &layout.run_deck,
                        format!("reads {} which does not exist, and there is no DEM/in.liggghts_init to make it", data.display()),
                    ));
                };
                let t = Instant::now();
                let packed = if opts.dem == DemBackend::Native {
                    events(Event::Message(format!(
                        "stage 1: running {} natively (writes {})",
                        init.display(),
                        data.display()
                    )));
                    let deck = Deck::read_with_vars(init, &opts.init_vars)?;
                    let dem = crate::native::run_native_deck(&deck, &layout.dem, &mut |w| {
                        events(Event::Message(format!("warning: {w}")))
                    })?;
                    format!("{} particles packed", dem.sim().particles.len())
                } else {
                    events(Event::Message(format!(
                        "stage 1: running {} with the liggghts binary (writes {})",
                        init.display(),
                        data.display()
                    )));
                    crate::backend::pack_with_liggghts(init, &layout.dem, &opts.init_vars)?;
                    "packed by LIGGGHTS".to_owned()
                };
                init_seconds = t.elapsed().as_secs_f64();
                if !start_file(&run_deck, &layout.dem).is_some_and(|(_, exists)| exists) {
                    return Err(setup_err(
                        init,
                        format!(
                            "ran, but did not write {} (needs `write_data` or `write_restart`)",
                            data.display()
                        ),
                    ));
                }
                events(Event::Message(format!(
                    "stage 1: {packed} in {init_seconds:.1} s"
                )));
            } else {
                events(Event::Message(format!(
                    "stage 1: using the existing {} (--repack to pack again)",
                    data.display()
                )));
            }
        }
        Ok(init_seconds)
    };
    let packed = if launch.rank() == 0 {
        stage1(events)
    } else {
        Ok(0.0)
    };
    if !launch.all_ok(packed.is_ok()) && packed.is_ok() {
        return Err(RunError::Backend(
            "rank 0 failed in stage 1 (its error is above)".into(),
        ));
    }
    let init_seconds = packed?;

    // Stage 2: the coupled run.
    let deck_coupling = run_deck.coupling().ok_or_else(|| {
        setup_err(
            &layout.run_deck,
            "is not coupled: it needs `fix ... couple/cfd couple_every N ...`".into(),
        )
    })?;
    if deck_coupling.couple_every != config.coupling_interval
        && opts.dem != DemBackend::LiggghtsFile
    {
        // CFDEM's twoWayMPI exchanges every couplingInterval DEM steps whatever the deck's
        // couple_every says; only LIGGGHTS's file coupling is driven by couple_every.
        events(Event::Message(format!(
            "warning: {}: couple_every {} differs from couplingInterval {} in {}; the coupling \
             interval is couplingInterval (as CFDEM's twoWayMPI)",
            layout.run_deck.display(),
            deck_coupling.couple_every,
            config.coupling_interval,
            config.file.display()
        )));
    } else if deck_coupling.couple_every != config.coupling_interval {
        return Err(setup_err(
            &layout.run_deck,
            format!(
                "couple_every {} differs from couplingInterval {} in {} (LIGGGHTS's file \
                 coupling exchanges every couple_every steps: make them equal)",
                deck_coupling.couple_every,
                config.coupling_interval,
                config.file.display()
            ),
        ));
    }
    let model = match config.model {
        ModelType::A => fv::Model::A,
        _ => fv::Model::B,
    };
    let fluid_settings = fv::settings::Settings::read(&foam::Case::open(&layout.cfd)?)
        .map_err(|e| RunError::Fluid(Box::new(e)))?;
    if fluid_settings.start_time > 0.0 {
        // a restart: each side starts from what its own input names
        let dem_start = start_file(&run_deck, &layout.dem).map_or_else(
            || "the state its deck builds".to_owned(),
            |(f, _)| f.display().to_string(),
        );
        events(Event::Message(format!(
            "restart: the fluid starts at t = {} s from {} (system/controlDict), the particles \
             from {dem_start} ({})",
            fluid_settings.start_time,
            layout
                .cfd
                .join(couple::output::time_name(fluid_settings.start_time))
                .display(),
            layout.run_deck.display(),
        )));
    }
    let ctx = LoopContext {
        layout: &layout,
        settings,
        fluid_settings,
        coupling_interval: config.coupling_interval,
        model_name: config.model.name(),
        monitors: config.monitors.clone(),
        solve_flow: config.solve_flow,
        ddt_voidage: config.ddt_voidage,
        smoothing: config.smoothing,
        commands,
        opts,
        stop,
        init_seconds,
        ranks: None,
        owners: None,
    };
    crate::backend::run_pair(ctx, &run_deck, model, opts.fluid, opts.dem, launch, events)
}

/// Coupling intervals of `dt_c` seconds from `start` to `end` (the last one may end past
/// `end`; a rounding error of 1e-9 intervals does not add one).
pub(crate) fn coupling_steps(start: f64, end: f64, dt_c: f64) -> u64 {
    ((end - start) / dt_c - 1e-9).ceil().max(0.0) as u64
}

/// Everything the coupled loop needs besides its two sides.
pub(crate) struct LoopContext<'a> {
    pub(crate) layout: &'a CaseLayout,
    pub(crate) settings: CouplerSettings,
    pub(crate) fluid_settings: fv::settings::Settings,
    pub(crate) coupling_interval: u64,
    pub(crate) model_name: &'static str,
    /// CFDEM's observing models.
    pub(crate) monitors: couple::config::Monitors,
    /// `solveFlow`.
    pub(crate) solve_flow: bool,
    /// `useDDTvoidfraction`.
    pub(crate) ddt_voidage: bool,
    /// `smoothingModel constDiffSmoothing`, if on.
    pub(crate) smoothing: Option<couple::smoothing::SmoothingSettings>,
    /// CFDEM's `liggghtsCommands`.
    pub(crate) commands: couple::config::LiggghtsCommands,
    pub(crate) opts: &'a RunOptions,
    pub(crate) stop: &'a AtomicBool,
    pub(crate) init_seconds: f64,
    /// The coupler's ranks on N ranks (`None`: one process).
    pub(crate) ranks: Option<Box<dyn couple::Ranks>>,
    /// On N ranks with grainPisoFoam: the straight link to the solver ranks owning the cells
    /// ([`couple::ranks::CellOwners`]).
    pub(crate) owners: Option<Box<dyn couple::ranks::CellOwners>>,
}

/// Runs one of `liggghtsCommands`' commands on the particle side. The folder of a file it
/// writes (`write_restart`, `write_data`, `write_dump`; resolved against `DEM/` like the deck's
/// paths, which is CFDEM's `CFD/` for paths starting `../DEM/`) is created first: LIGGGHTS
/// would stop the process on a missing one.
fn run_command<P: ParticleSide>(
    dem: &mut P,
    cmd: &str,
    layout: &CaseLayout,
    events: &mut dyn FnMut(Event),
) -> Result<(), RunError> {
    let words: Vec<&str> = cmd.split_whitespace().collect();
    if let ["write_restart" | "write_data" | "write_dump", file, ..] = words.as_slice() {
        if let Some(dir) = layout.dem.join(file).parent() {
            std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        }
    }
    events(Event::Message(format!("liggghtsCommands: {cmd}")));
    dem.command(cmd).map_err(|e| {
        setup_err(
            &layout.cfd.join("constant/liggghtsCommands"),
            format!("`{cmd}`: {e}"),
        )
    })
}

/// Stage 2 on any pair of sides: the schedule, the samples, the outputs and the checks.
pub(crate) fn couple_loop<P: ParticleSide, F: RunFluid>(
    ctx: LoopContext<'_>,
    dem: P,
    fluid: F,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let LoopContext {
        layout,
        settings,
        fluid_settings,
        coupling_interval,
        model_name,
        monitors,
        commands,
        opts,
        stop,
        init_seconds,
        ranks,
        owners,
        smoothing,
        ..
    } = ctx;
    let mesh = fluid.mesh().clone();
    let cfd_dt = fluid_settings.delta_t;
    let mut dem = Timed::new(dem);
    let mut fluid = Timed::new(fluid);
    let owned = owners.is_some();
    if owned && monitors.needs_fields() {
        // the monitors read whole fields on rank 0, which no coupler rank holds otherwise
        fluid.inner.want_held();
    }
    let dt_c = coupling_interval as f64 * dem.time_step();
    let ratio = dt_c / cfd_dt;
    if (ratio - ratio.round()).abs() > 1e-6 * ratio || ratio.round() < 1.0 {
        return Err(setup_err(
            &layout.cfd.join("system/controlDict"),
            format!(
                "deltaT {cfd_dt} s must divide the coupling interval {} × {} s = {dt_c} s",
                coupling_interval,
                dem.time_step()
            ),
        ));
    }
    let start = fluid.inner.time();
    let end = opts.end_time.unwrap_or(fluid_settings.end_time);
    let steps = coupling_steps(start, end, dt_c);
    let write_every = match fluid_settings.write {
        fv::settings::WriteControl::RunTime(t) => (t / dt_c).round().max(1.0) as u64,
        fv::settings::WriteControl::TimeStep(n) => {
            ((n as f64 * cfd_dt) / dt_c).round().max(1.0) as u64
        }
    };
    let method_name = settings.method.name();
    let mut coupler = Coupler::new(&mesh, settings)?;
    if let Some(ranks) = ranks {
        coupler.set_ranks(ranks);
    }
    if let Some(owners) = owners {
        coupler.set_owners(owners);
    }
    if let Some(s) = smoothing {
        coupler.set_smoothing(couple::smoothing::ConstDiffSmoothing::new(&mesh, s)?);
    }
    let (rank, n_ranks) = (coupler.ranks().rank(), coupler.ranks().size());
    // The voidage of the initial particles, so that the first coupling interval blends from it
    // (not from an empty domain, which would make ∂ε/∂t a spurious source).
    let initial_volume = coupler
        .exchange(&dem.state(), &fluid.state())?
        .deposit
        .particle_volume;
    let n_particles = {
        let mut n = [dem.state().len() as f64];
        coupler.ranks().all_sum(&mut n);
        n[0] as usize
    };
    if n_ranks > 1 {
        events(Event::Message(if owned {
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
        if monitors.basic_io {
            events(Event::Message(
                "warning: basicIO's particle files are not written on several ranks (no rank \
                 holds all particles); the deck's dumps have them"
                    .into(),
            ));
        }
    }
    events(Event::Message(format!(
        "stage 2: {n_particles} particles, {} cells, {steps} coupling steps of {dt_c} s ({} DEM + {} fluid steps each), model {model_name}, voidage {method_name}",
        mesh.n_cells,
        coupling_interval,
        ratio.round(),
    )));

    let spec = layout.validation.clone();
    let axis = match &spec {
        Some(ValidationSpec::ErgunPackedBed { axis, .. }) => *axis,
        _ => unit(-settings.physics.gravity).unwrap_or(V3::z()),
    };
    let volume: f64 = coupler.voidage_mesh().geometry().cell_volumes.iter().sum();
    let (inlet, outlet) = match &spec {
        Some(
            ValidationSpec::ErgunPackedBed { inlet, outlet, .. }
            | ValidationSpec::FluidisedBed { inlet, outlet, .. },
        ) => (Some(inlet.clone()), Some(outlet.clone())),
        Some(ValidationSpec::PneumaticConveying(c)) => {
            (Some(c.inlet.clone()), Some(c.outlet.clone()))
        }
        _ => {
            // without a validationDict, the patches the start fields make inlet and outlet
            let found = crate::patches::find(&layout.cfd, &couple::output::time_name(start), &mesh);
            for note in &found.notes {
                events(Event::Message(format!("monitoring: {note}")));
            }
            if let (Some(i), Some(o)) = (&found.inlet, &found.outlet) {
                events(Event::Message(format!(
                    "monitoring: Δp between the inlet `{i}` and the outlet `{o}`"
                )));
            }
            (found.inlet, found.outlet)
        }
    };
    let observer = Observer {
        column: Column::of(&mesh, volume, axis),
        rho: settings.physics.rho,
        g: settings
            .physics
            .gravity
            .dot(&settings.physics.gravity)
            .sqrt(),
        inlet,
        outlet,
        conveyor: match &spec {
            Some(ValidationSpec::PneumaticConveying(c)) => Some(c.clone()),
            _ => None,
        },
    };

    let post = layout.post_processing();
    let csv = post.join("integrals.csv");
    // A run started from a later time (`startFrom latestTime`, a restart) continues the
    // earlier run's series: its rows and particle files up to the start time are kept.
    let restart = start > 0.0;
    let (kept_rows, vtp) = match restart {
        true => (
            crate::sample::rows_until(&csv, start),
            pvd_entries_until(&post.join("particles/particles.pvd"), start),
        ),
        false => (Vec::new(), Vec::new()),
    };
    if restart {
        events(Event::Message(format!(
            "restart at t = {start} s: {} rows of integrals.csv and {} particle files kept",
            kept_rows.len(),
            vtp.len()
        )));
    }
    // grainPisoFoam computes in its own processes: its advance of step k runs while the
    // particles advance interval k + 1 (which needs only the forces of step k), and step k's
    // fluid-side outputs wait for it (module docs of `Open`).
    let overlap = !opts.no_overlap && fluid.inner.runs_apart();
    if overlap {
        events(Event::Message(
            "overlap: the fluid's advance runs during the next DEM interval (not at write \
             times or liggghtsCommands; --no-overlap for the sequential order)"
                .into(),
        ));
    }
    let mut stopped = false;
    let t_loop = Instant::now();
    let start_name = couple::output::time_name(start);
    let mut probes = crate::probes::Probes::default();
    let mut surface = crate::surface_values::SurfaceValues::default();
    if opts.fluid == FluidBackend::Native && rank == 0 {
        let locator = coupler.voidage_mesh().locator();
        let (p, warnings) = crate::probes::Probes::read(&layout.cfd, &start_name, &|x| {
            locator.locate(x).map(|c| c as usize)
        })?;
        for w in warnings {
            events(Event::Message(format!("warning: {w}")));
        }
        probes = p;
        let patches: Vec<String> = mesh.boundary.iter().map(|p| p.name.clone()).collect();
        let (s, warnings) =
            crate::surface_values::SurfaceValues::read(&layout.cfd, &start_name, &patches)?;
        for w in warnings {
            events(Event::Message(format!("warning: {w}")));
        }
        surface = s;
    }
    let cell_volumes = coupler.voidage_mesh().geometry().cell_volumes.clone();
    let mut out = Outputs {
        layout,
        observer: &observer,
        monitors: RunMonitors::new(&monitors, &layout.cfd, &start_name),
        probes,
        surface,
        commands: &commands,
        csv,
        kept_rows,
        samples: Vec::with_capacity(steps as usize),
        vtp,
        eps_before: coupler.voidage().to_vec(),
        ddt_eps: vec![0.0; mesh.n_cells],
        cell_volumes,
        mesh: &mesh,
        rho: settings.physics.rho,
        writes: 0,
        output_seconds: 0.0,
        start,
        end,
        dt_c,
        steps,
        rank,
        n_ranks,
    };
    let mut held_max = 0;
    let mut evacuation = observer
        .conveyor
        .as_ref()
        .map(|_| crate::conveyor::Evacuation::default());
    let mut open: Option<Open> = None;
    for k in 1..=steps {
        coupler.advance_particles(&mut dem)?;
        if let Some(o) = open.take() {
            fluid.finish_advance().map_err(RunError::Fluid)?;
            let step = out.close(o, &mut dem, &mut fluid, events)?;
            coupler.recycle(step);
        }
        let (step, dt) = coupler.hand_over(&mut dem, &mut fluid)?;
        fluid.start_advance(dt).map_err(RunError::Fluid)?;
        held_max = held_max.max(dem.state().len());
        let sample = observer.sample(&dem, &step, coupler.ranks(), evacuation.as_mut());
        // every rank stops at the same step (a signal reaches the ranks at different steps)
        let stop_now = {
            let mut s = [f64::from(u8::from(stop.load(Ordering::SeqCst)))];
            coupler.ranks().all_max(&mut s);
            s[0] > 0.0
        };
        let write_now = k % write_every == 0 || k == steps || stop_now;
        let o = Open {
            k,
            step,
            sample,
            write_now,
        };
        // writes and liggghtsCommands need the particles of step k and the fluid's clock
        let at_once = !overlap
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
        let step = out.close(o, &mut dem, &mut fluid, events)?;
        coupler.recycle(step);
        if stop_now && k < steps {
            stopped = true;
            events(Event::Message(format!(
                "stopped at t = {} s after step {k}; that time is written",
                fluid.inner.time()
            )));
            break;
        }
    }
    // the last step writes, so it has closed at once
    debug_assert!(open.is_none());
    let Outputs {
        monitors,
        samples,
        output_seconds,
        ..
    } = out;
    if let Some(line) = fluid.inner.report() {
        events(Event::Message(line));
    }
    fluid.inner.finish().map_err(RunError::Fluid)?;
    let loop_seconds = t_loop.elapsed().as_secs_f64();
    if rank == 0 {
        monitors.write_logs()?;
    }
    {
        let per_rank = crate::ranks_report::gather(
            coupler.ranks(),
            dem.state().len(),
            held_max,
            (n_ranks > 1).then(|| coupler.touched_cells()),
            owned.then(|| coupler.owner_traffic()),
            samples.len() as u64,
        );
        if rank == 0 {
            let file = post.join("ranks.csv");
            crate::ranks_report::write_csv(&file, &per_rank).map_err(io_err(&file))?;
            if n_ranks > 1 {
                for line in crate::ranks_report::table(&per_rank) {
                    events(Event::Message(line));
                }
            }
        }
    }
    let particles_at_end = {
        let mut n = [dem.state().len() as f64];
        coupler.ranks().all_sum(&mut n);
        n[0] as usize
    };
    let population = coupler.population_total();
    if population != couple::PopulationChange::default() {
        events(Event::Message(population_summary(
            n_particles,
            particles_at_end,
            &population,
            initial_volume,
            samples.last().map(|s| s.particle_volume),
        )));
    }
    let n_steps = samples.len() as u64;
    let coupling_seconds = (loop_seconds - dem.seconds - fluid.seconds - output_seconds).max(0.0);
    let sections = [
        ("Global", loop_seconds, 1),
        ("DEM", dem.seconds, n_steps),
        ("Flow", fluid.seconds, n_steps),
        ("Coupling", coupling_seconds, n_steps),
        ("Output", output_seconds, n_steps),
    ];
    let clock = if rank == 0 {
        monitors.clock(&layout.cfd, &sections)?
    } else {
        None
    };
    if let Some(lines) = clock {
        for line in lines {
            events(Event::Message(line));
        }
    }

    let mut checks = Vec::new();
    if !stopped && rank == 0 {
        if let Some(spec) = &spec {
            let mut notes = Vec::new();
            checks = checks::evaluate(spec, &settings, &samples, &post, dt_c, &mut notes)?;
            for note in notes {
                events(Event::Message(note));
            }
            write_json(&post.join("validation.json"), &checks)
                .map_err(io_err(&post.join("validation.json")))?;
        }
    }
    Ok(RunReport {
        rank,
        steps: samples.len() as u64,
        time: samples.last().map_or(start, |s| s.time),
        stopped,
        particles: n_particles,
        particles_at_end,
        population,
        cells: mesh.n_cells,
        init_seconds,
        loop_seconds,
        dem_seconds: dem.seconds,
        fluid_seconds: fluid.seconds,
        output_seconds,
        checks,
        samples,
    })
}
