//! The run's observers and outputs as coupling steps close: the integrals of a step
//! ([`Observer`]), the steps whose fluid side may still be advancing ([`Open`]), and what is
//! written when a step closes ([`Outputs`]: samples, monitors, probes, time directories,
//! particle files); the end-of-run population line.

use crate::error::{io_err, setup_err, RunError};
use crate::fluid::RunFluid;
use crate::layout::CaseLayout;
use crate::monitors::{RunMonitors, StepFields};
use crate::report::Event;
use crate::sample::{write_csv, Sample};
use crate::timed::Timed;
use couple::{CouplingStep, ParticleSide};
use liggghts_deck::Deck;
use mesh::v3::{as_arrays, V3};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The column the integrals are measured in: axis, floor and cross-section.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Column {
    pub(crate) axis: V3,
    pub(crate) floor: f64,
    pub(crate) area: f64,
}

impl Column {
    pub(crate) fn of(mesh: &foam::PolyMesh, volume: f64, axis: V3) -> Column {
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

pub(crate) struct Observer {
    pub(crate) column: Column,
    pub(crate) rho: f64,
    pub(crate) g: f64,
    pub(crate) inlet: Option<String>,
    pub(crate) outlet: Option<String>,
    /// A conveyor case: its zones and the outlet whose outflow is sampled.
    pub(crate) conveyor: Option<crate::conveyor::ConveyorSpec>,
    /// The full conveyor's cells whose air velocity is sampled ([`crate::branch`]).
    pub(crate) air_cells: Option<crate::branch::AirCells>,
    /// The outlet patch's cells and face areas (m²), for the outlet gas temperature.
    pub(crate) outlet_cells: Vec<(usize, f64)>,
    /// A packed-bed heating case: the bins of its temperature profiles.
    pub(crate) heating: Option<crate::heating_run::Profiler>,
    /// A fluidised bed's voidage profiles across the width (`voidageProfiles`).
    pub(crate) slabs: Option<crate::slab_profile::Profiler>,
}

impl Observer {
    /// `particleVolume`'s value at a step: Σ 4πr³/3 over the particles whose centre is in
    /// the mesh, summed over the ranks (collective on N ranks).
    pub(crate) fn located_volume<P: ParticleSide>(
        dem: &P,
        step: &CouplingStep,
        ranks: &dyn couple::Ranks,
    ) -> f64 {
        let ps = dem.state();
        let centre = &step.placement.centre;
        let mut v = [couple::monitor::located_particle_volume(ps.radius, |i| {
            centre.get(i).is_some_and(Option::is_some)
        })];
        ranks.all_sum(&mut v);
        v[0]
    }

    /// The step's integrals. Collective on N ranks (each gives its own particles); rank 0's
    /// sample is the run's.
    ///
    /// The particle side's part only: [`Observer::observe_fluid`] adds the time and the
    /// fluid's, once the fluid has advanced the step's interval.
    ///
    /// `evacuation` follows a conveyor's bed by id (rank 0 keeps it; the others pass theirs
    /// unused).
    pub(crate) fn sample<P: ParticleSide>(
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
        let particle_temperature = ps.temperature.map(|t| {
            let mut sums = [0.0, 0.0];
            for (i, ti) in t.iter().enumerate() {
                let m = ps.density[i] * voidage::sphere_box::ball_volume(ps.radius[i]);
                sums[0] += m * ti;
                sums[1] += m;
            }
            ranks.all_sum(&mut sums);
            sums[0] / sums[1]
        });
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
        let branched = self.conveyor.as_ref().and_then(|spec| {
            let b = spec.branch.as_ref()?;
            let z = crate::branch::BranchZones::measure(b, spec.tube_from, ax, ps.position);
            let mut sums = [z.past as f64, z.vent as f64, z.secondary as f64];
            ranks.all_sum(&mut sums);
            Some(sums.map(|c| c as usize))
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
            heat_to_particles: step.heat.as_ref().map(|h| h.account.to_particles),
            heat_from_fluid: step.heat.as_ref().map(|h| h.account.from_fluid),
            heat_clipped: step.heat.as_ref().map(|h| h.account.clipped),
            heat_from_wall: None,
            particle_temperature: particle_temperature.filter(|t| t.is_finite()),
            outlet_temperature: None,
            branch_particles: branched.map(|b| b[0]),
            vent_leg_particles: branched.map(|b| b[1]),
            secondary_particles: branched.map(|b| b[2]),
            tube_air_velocity: None,
            tube_air_peak: None,
            vent_air_velocity: None,
            vent_air_peak: None,
        }
    }

    /// The fluid's part of a step's sample (rank 0's is the run's): its time and, from the
    /// patches, Δp between inlet and outlet, the inflow velocity and a conveyor's outflow.
    pub(crate) fn observe_fluid<F: RunFluid>(&self, sample: &mut Sample, fluid: &F) {
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
        let air = self
            .conveyor
            .as_ref()
            .and_then(|c| Some((c.branch.as_ref()?, self.air_cells.as_ref()?)))
            .and_then(|(b, cells)| match fluid.watched() {
                // rank 0 in grainPisoFoam's sparse exchange: the solver ranks sent these cells
                Some(w) => cells.measure_listed(b, self.column.axis, w.u),
                None => cells.measure(b, self.column.axis, fluid.state().u),
            });
        sample.tube_air_velocity = air.map(|a| a.tube_mean);
        sample.tube_air_peak = air.map(|a| a.tube_peak);
        sample.vent_air_velocity = air.map(|a| a.vent_mean);
        sample.vent_air_peak = air.map(|a| a.vent_peak);
        sample.outlet_temperature = fluid.state().temperature.and_then(|t| {
            let area: f64 = self.outlet_cells.iter().map(|&(_, a)| a).sum();
            let sum: f64 = self.outlet_cells.iter().map(|&(c, a)| a * t[c]).sum();
            (area > 0.0).then(|| sum / area)
        });
    }
}

/// A coupling step whose particle side is done (advanced, sampled) while the fluid may still
/// be advancing its interval: with grainPisoFoam the run starts the next DEM interval before
/// it waits for the fluid, then closes this step ([`Outputs::close`]) with the fluid's time,
/// patches and state after the interval, as the sequential order would. Steps that write, stop
/// or may run liggghtsCommands close before the DEM goes on (they need the particles of the
/// step and the fluid's clock).
pub(crate) struct Open {
    /// The step's number (1-based).
    pub(crate) k: u64,
    pub(crate) step: CouplingStep,
    /// Its particle side's part.
    pub(crate) sample: Sample,
    /// The step writes a time (write interval, last step or stop).
    pub(crate) write_now: bool,
    /// At a heating case's sample time: the solid temperature profile (over all ranks).
    pub(crate) solid: Option<crate::heating::Profile>,
    /// `particleVolume`: the volume of the particles inside the mesh, m³ (over all ranks).
    pub(crate) located_volume: Option<f64>,
    /// A fluidised bed's slab solid fractions (over all ranks).
    pub(crate) slabs: Option<Vec<f64>>,
}

/// What the run writes as its steps close: samples, monitors, time directories, particles.
pub(crate) struct Outputs<'a> {
    pub(crate) layout: &'a CaseLayout,
    pub(crate) observer: &'a Observer,
    pub(crate) monitors: RunMonitors,
    /// `checkCouplingInterval` (at the exchange, collective over the ranks).
    pub(crate) interval_checks: Option<crate::interval_check::IntervalChecks>,
    /// `probeModel particleProbe` (one rank; sampled at the exchange).
    pub(crate) particle_probes: Option<crate::particle_probe::ParticleProbes>,
    /// The controlDict's `probes` on the native fluid (grainPisoFoam runs OpenFOAM's own).
    pub(crate) probes: crate::probes::Probes,
    /// The controlDict's `surfaceFieldValue`s on the native fluid (likewise).
    pub(crate) surface: crate::surface_values::SurfaceValues,
    pub(crate) commands: &'a couple::config::LiggghtsCommands,
    /// How often each command has run (`readLiggghtsData` numbers its files by it).
    pub(crate) command_runs: Vec<u64>,
    pub(crate) csv: PathBuf,
    pub(crate) kept_rows: Vec<String>,
    pub(crate) samples: Vec<Sample>,
    pub(crate) vtp: Vec<(f64, PathBuf)>,
    /// ε of the last step (for ∂ε/∂t) and ∂ε/∂t, per cell.
    pub(crate) eps_before: Vec<f64>,
    pub(crate) ddt_eps: Vec<f64>,
    pub(crate) cell_volumes: Vec<f64>,
    pub(crate) mesh: &'a foam::PolyMesh,
    pub(crate) rho: f64,
    /// Write times so far.
    pub(crate) writes: u64,
    pub(crate) output_seconds: f64,
    pub(crate) start: f64,
    pub(crate) end: f64,
    pub(crate) dt_c: f64,
    pub(crate) steps: u64,
    pub(crate) rank: usize,
    pub(crate) n_ranks: usize,
    /// A heating case's profiles at its sample times (rank 0).
    pub(crate) profiles: crate::heating_run::Profiles,
    /// A fluidised bed's slab profiles, one row per step (rank 0).
    pub(crate) slabs: crate::slab_profile::Record,
}

impl Outputs<'_> {
    /// Closes step `o` once the fluid has advanced its interval: the fluid's part of the
    /// sample, the monitors, and at a write step (then `dem` still holds the step's particles)
    /// liggghtsCommands and the outputs, as one unit of [`crate::journal`]. Returns the step
    /// for [`Coupler::recycle`]. Collective on N ranks at write steps only (every rank's
    /// particle piece is written before the write is complete).
    pub(crate) fn close<P: ParticleSide, F: RunFluid>(
        &mut self,
        o: Open,
        dem: &mut Timed<P>,
        fluid: &mut Timed<F>,
        ranks: &dyn couple::Ranks,
        events: &mut dyn FnMut(Event),
    ) -> Result<CouplingStep, RunError> {
        let Open {
            k,
            mut step,
            mut sample,
            write_now,
            solid,
            located_volume,
            slabs,
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
        if let (Some(solid), Some(bins), Some(t)) = (
            solid,
            &self.observer.heating,
            fluid.inner.state().temperature,
        ) {
            self.profiles.snapshots.push(crate::heating::Snapshot {
                time,
                gas: bins.gas(t),
                solid,
            });
        }
        self.samples.push(sample);
        if let Some(phi) = slabs {
            self.slabs.rows.push((time, phi));
        }
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
            let volumes = &self.cell_volumes;
            for line in self
                .monitors
                .observe(time, volumes, &fields, located_volume)
            {
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
        self.command_runs.resize(self.commands.commands.len(), 0);
        let mut due = Vec::new();
        for (c, runs) in self.commands.commands.iter().zip(&mut self.command_runs) {
            if let Some(cmd) = c.due_after(now, *runs) {
                due.push(cmd);
                *runs += 1;
            }
        }
        let name = couple::output::time_name(self.start + k as f64 * self.dt_c);
        // a write time is one unit (crate::journal): a restart file goes to a temporary name
        let mut renames = Vec::new();
        if write_now {
            for cmd in &mut due {
                if let Some((staged, rename)) =
                    crate::journal::staged_restart(cmd, &self.layout.dem)
                {
                    *cmd = staged;
                    renames.push(rename);
                }
            }
        }
        let journal = write_now
            .then(|| {
                crate::journal::WriteJournal::begin(&self.layout.cfd, &name, renames, rank == 0)
            })
            .transpose()?;
        for cmd in &due {
            run_command(dem, cmd, self.layout, events)?;
        }
        if let Some(journal) = journal {
            let t = Instant::now();
            let pieces = Pieces {
                rank,
                ranks: self.n_ranks,
                name,
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
                let file = self.csv.with_file_name("voidage_profiles.csv");
                self.slabs.write_csv(&file)?;
            }
            if !self.monitors.is_empty() && rank == 0 {
                let fields = StepFields::new(&step, &self.ddt_eps, fluid.inner.state(), self.rho);
                let dir = self.layout.cfd.join(&name);
                let particles = dem.state();
                let particles = (self.n_ranks == 1).then_some(&particles);
                self.monitors
                    .write_time(&dir, &name, self.mesh, &fields, particles)?;
            }
            // every rank's part is written (the solver replied to its write before)
            ranks.meet();
            journal.commit(rank == 0)?;
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
pub(crate) fn population_summary(
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

/// Which particle file a rank writes at an output time: one `particles_<time>.vtp` alone; on N
/// ranks each rank its own particles as `particles_<time>_<rank>.vtp`, the parts of that time
/// in `particles.pvd` (written by rank 0).
pub(crate) struct Pieces {
    pub(crate) rank: usize,
    pub(crate) ranks: usize,
    /// The output time's name from the coupling clock (the same on every rank).
    pub(crate) name: String,
}

/// Writes one output time: fluid U and p, the exchange fields and the particles.
pub(crate) fn write_time<F: RunFluid>(
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
    let mut arrays = vec![
        vtk::DataArray::int64("id", &ids),
        vtk::DataArray::scalar("radius", ps.radius),
        vtk::DataArray::vector("velocity", as_arrays(ps.velocity)),
        vtk::DataArray::vector("fluidForce", as_arrays(&fluid_force)),
    ];
    // with heat: LIGGGHTS's per-particle names, temperature (K) and convective flux (W)
    if let Some(t) = ps.temperature {
        arrays.push(vtk::DataArray::scalar("Temp", t));
    }
    if let Some(h) = &step.heat {
        arrays.push(vtk::DataArray::scalar("convectiveHeatFlux", &h.q));
    }
    vtk::write_vtp(&file, as_arrays(ps.position), &arrays)?;
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
pub(crate) fn pvd_entries_until(path: &Path, start: f64) -> Vec<(f64, PathBuf)> {
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

/// Runs one of `liggghtsCommands`' commands on the particle side. The folder of a file it
/// writes (`write_restart`, `write_data`, `write_dump`; resolved against `DEM/` like the deck's
/// paths, which is CFDEM's `CFD/` for paths starting `../DEM/`) is created first: LIGGGHTS
/// would stop the process on a missing one.
pub(crate) fn run_command<P: ParticleSide>(
    dem: &mut P,
    cmd: &str,
    layout: &CaseLayout,
    events: &mut dyn FnMut(Event),
) -> Result<(), RunError> {
    let source = layout.cfd.join("constant/liggghtsCommands");
    // a command the deck reader cannot read is left to the DEM, which names what is wrong
    let written = Deck::parse(cmd, &source, &[]).map_or(Vec::new(), |d| d.written_files());
    for file in written.iter().filter(|f| f.command.starts_with("write_")) {
        if let Some(dir) = layout.dem.join(&file.path).parent() {
            std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        }
    }
    events(Event::Message(format!("liggghtsCommands: {cmd}")));
    dem.command(cmd)
        .map_err(|e| setup_err(&source, format!("`{cmd}`: {e}")))
}
