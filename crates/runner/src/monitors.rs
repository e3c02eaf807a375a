//! CFDEM's observing models during a run ([`couple::config::Monitors`]), writing what CFDEM
//! writes, under the OpenFOAM case `CFD/` as CFDEM's solvers (which run there) do:
//! * `particleCellVolume`: each coupling step, the particle volume in the cells whose ε lies
//!   between the thresholds, those cells' volume, the mean solid fraction and ε's range — in
//!   the log (`verbose`) and `postProcessing/particleCellVolume/<start>/particleCellVolume.txt`
//!   (`writeToFile`); the uniform fields `particleCellVolume` and `cellVolume` at write times;
//! * `volWeightedAverage`: each coupling step, the volume-weighted average of each named field,
//!   in the log and `postProcessing/volWeightedAverage/<start>/volWeightedAverage.txt`; the
//!   uniform fields `volAverage_<name>` at write times;
//! * `fieldVolWeighted` (its CFDEM source was never published; what foamgrain chose is in
//!   `couple::config::monitors`): each coupling step from `startTime`, the volume-weighted
//!   average of each named field over every cell, in
//!   `postProcessing/fieldVolWeighted/<start>/fieldVolWeighted.txt` (volWeightedAverage's
//!   layout);
//! * `fieldStore`: `stored_<name>` copies of the named fields at write times;
//! * `fieldTimeAverage`: `timeAverage_<name>` at write times, the mean of the field over the
//!   coupling steps from `startTime` (CFDEM: the fields' `AUTO_WRITE`);
//! * `particleVolume`: each coupling step from `startTime`, `<time> <volume>` in
//!   `postProcessing/particleVolume/<start>/particleVolume.txt` (`writeToFile`; CFDEM's
//!   `particleVolume.C` writes `time << " " << VsTot`) and the log line `Total particle volume
//!   (located in domain) = V` (`verbose`);
//! * `totalMomentumExchange`: each coupling step, `<time> (Fx Fy Fz) (Ix Iy Iz) (Ex Ey Ez)`,
//!   the total, implicit and explicit force of the fluid on the particles (N), in
//!   `postProcessing/totalMomentumExchange/<start>/totalMomentumExchange.txt` (CFDEM's source
//!   of this model is not public — only its header, which reads the Ksl, U, Us, explicit-force
//!   and density field names and `verbous`; the file follows its siblings' layout);
//! * `IOModel basicIO`: `<time>/lagrangian/particleCloud/{positions, v, r}` at write times,
//!   the particles inside the mesh; `sophIO` adds `voidfractions` (ε of the particle's cell),
//!   `impForces` (the drag handed to the fluid through Ksl, β_fluid (u_f − v)), `expForces`
//!   (the force handed to it through f) and `DEMForces` (the explicit force the DEM gets),
//!   `trackIO` also `id` (CFDEM-PUBLIC's `sophIO.C`, `trackIO.C`);
//! * `clockModel standardClock`: the timing table at the end, in the log and
//!   `clockData/timeEval.txt`.
//!
//! A value that cannot be computed (no cell between the thresholds) is written `NaN` in the
//! text files, never as a number (CFDEM writes 0 there): an empty column would shift the
//! columns after it, and the tutorials' octave scripts `load` these files, which reads `NaN`.
//! The text files are rewritten whole (atomically) at each write time and at the end.

use crate::error::RunError;
use couple::config::monitors::{
    ParticleCellVolume, ParticleIo, TotalMomentumExchange, VolWeightedAverage,
};
use couple::config::Monitors;
use couple::monitor::{
    accumulate_mean, particle_cell_volume, total_momentum_exchange, vol_weighted_scalar,
    vol_weighted_vector,
};
use couple::output::write_cell_field;
use couple::{CouplingStep, FluidState, ParticleState};
use foam::{FieldValues, Format, PolyMesh};
use mesh::v3::V3;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The cell fields of one coupling step, by CFDEM's names.
pub(crate) struct StepFields<'a> {
    /// ε after the step.
    pub eps: &'a [f64],
    /// (ε − ε_before)/Δt_c, 1/s.
    pub ddt_eps: &'a [f64],
    /// The fluid's U and p.
    pub fluid: FluidState<'a>,
    /// The exchange fields.
    pub step: &'a CouplingStep,
    /// Fluid density ρ.
    pub rho: f64,
}

pub(crate) enum Field<'a> {
    Scalar(std::borrow::Cow<'a, [f64]>),
    Vector(&'a [V3]),
}

impl<'a> StepFields<'a> {
    /// The fields of `step` (its ε), with ∂ε/∂t, the fluid's U and p, and ρ (kg/m³).
    pub(crate) fn new(
        step: &'a CouplingStep,
        ddt_eps: &'a [f64],
        fluid: FluidState<'a>,
        rho: f64,
    ) -> Self {
        StepFields {
            eps: &step.voidage.epsilon,
            ddt_eps,
            fluid,
            step,
            rho,
        }
    }

    pub(crate) fn get(&self, name: &str) -> Field<'a> {
        use std::borrow::Cow::{Borrowed, Owned};
        match name {
            "voidfraction" => Field::Scalar(Borrowed(self.eps)),
            "ddtVoidfraction" => Field::Scalar(Borrowed(self.ddt_eps)),
            "p" => Field::Scalar(Borrowed(self.fluid.p)),
            "Ksl" => Field::Scalar(Borrowed(&self.step.exchange.ksl)),
            "rho" => Field::Scalar(Owned(vec![self.rho; self.eps.len()])),
            "U" => Field::Vector(self.fluid.u),
            "Us" => Field::Vector(&self.step.exchange.us),
            "f" => Field::Vector(&self.step.exchange.f),
            // probed only in runs with heat (`probes::HEAT_FIELDS`); NaN would be an
            // unmeasured value, never printed as 0
            "T" => Field::Scalar(match self.fluid.temperature {
                Some(t) => Borrowed(t),
                None => Owned(vec![f64::NAN; self.eps.len()]),
            }),
            "Tsource" => Field::Scalar(match &self.step.heat {
                Some(h) if h.tsource.len() == self.eps.len() => Borrowed(&h.tsource),
                _ => Owned(vec![f64::NAN; self.eps.len()]),
            }),
            // the config refuses other names (monitors::SCALAR_FIELDS, VECTOR_FIELDS)
            other => unreachable!("field `{other}` passed couplingProperties' check"),
        }
    }
}

/// OpenFOAM's dimensions of the fields a monitor may name.
fn dimensions(name: &str) -> [i32; 7] {
    match name {
        "ddtVoidfraction" => [0, 0, -1, 0, 0, 0, 0],
        "p" => [0, 2, -2, 0, 0, 0, 0],
        "Ksl" => [1, -3, -1, 0, 0, 0, 0],
        "rho" => [1, -3, 0, 0, 0, 0, 0],
        "U" | "Us" => [0, 1, -1, 0, 0, 0, 0],
        "f" => [1, -2, -2, 0, 0, 0, 0],
        "T" => [0, 0, 0, 1, 0, 0, 0],
        "Tsource" => [0, 0, -1, 1, 0, 0, 0],
        _ => [0; 7],
    }
}

/// A text file kept in memory and rewritten whole.
struct TextLog {
    path: PathBuf,
    text: String,
}

impl TextLog {
    fn write(&self) -> Result<(), RunError> {
        let io = |source| RunError::Io {
            path: self.path.clone(),
            source,
        };
        if let Some(dir) = self.path.parent() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        atomic_write::write_atomically(&self.path, |w| w.write_all(self.text.as_bytes()))
            .map_err(io)
    }
}

/// The last values, written into fields at the write times.
#[derive(Default)]
struct Last {
    cell_volume: Option<(f64, f64)>,
    averages: Vec<(String, Option<FieldValuesOne>)>,
}

#[derive(Clone, Copy)]
enum FieldValuesOne {
    Scalar(f64),
    Vector(V3),
}

/// One running mean of `fieldTimeAverage`.
enum Mean {
    Scalar(Vec<f64>),
    Vector(Vec<V3>),
}

/// The averages of `volWeightedAverage` (or `fieldVolWeighted`, `model`) of one step: the
/// text of the file's row after the time, and each field's value; the values go to `lines`
/// with `verbose`.
fn averages(
    m: &VolWeightedAverage,
    model: &str,
    volumes: &[f64],
    f: &StepFields<'_>,
    lines: &mut Vec<String>,
) -> (String, Vec<(String, Option<FieldValuesOne>)>) {
    let weights = m.use_volume_fraction.then_some(f.eps);
    let mut row = String::new();
    let mut last = Vec::new();
    for name in m.scalar_fields.iter().chain(&m.vector_fields) {
        let (text, value) = match f.get(name) {
            Field::Scalar(phi) => {
                let a = vol_weighted_scalar(&phi, volumes, weights, m.lower, m.upper);
                (opt(a.average), a.average.map(FieldValuesOne::Scalar))
            }
            Field::Vector(phi) => {
                let a = vol_weighted_vector(phi, volumes, weights, m.lower, m.upper);
                let text = a.average.map_or("(NaN NaN NaN)".into(), |v| {
                    format!("({} {} {})", v.x, v.y, v.z)
                });
                (text, a.average.map(FieldValuesOne::Vector))
            }
        };
        if m.verbose {
            lines.push(match m.lower.is_finite() || m.upper.is_finite() {
                true => format!(
                    "{model}: {name} = {text} over the cells with {} < {name} < {}",
                    m.lower, m.upper
                ),
                false => format!("{model}: {name} = {text} over all cells"),
            });
        }
        let _ = write!(row, " {text}");
        last.push((name.clone(), value));
    }
    (row, last)
}

/// Appends the row `<time><row>` to `log`, if it is kept.
fn push_row(log: &mut Option<TextLog>, time: f64, row: &str) {
    if let Some(log) = log {
        let _ = writeln!(log.text, "{}{row}", couple::output::time_name(time));
    }
}

/// The observing models of one run.
pub(crate) struct RunMonitors {
    cfg: Monitors,
    pcv_log: Option<TextLog>,
    vwa_log: Option<TextLog>,
    fvw_log: Option<TextLog>,
    pv_log: Option<TextLog>,
    tme_log: Option<TextLog>,
    /// `fieldTimeAverage`'s means by field name, and the samples in them.
    means: Vec<(String, Mean)>,
    samples: u64,
    last: Last,
    /// ε before the current step (kept only when `ddtVoidfraction` is observed).
    pub(crate) needs_ddt: bool,
}

/// `v` as text, or `NaN` when it cannot be measured (module docs).
fn opt(v: Option<f64>) -> String {
    v.map_or("NaN".into(), |x| format!("{x}"))
}

impl RunMonitors {
    /// The monitors of `cfg` for the case `cfd`, starting at the time named `start`.
    pub(crate) fn new(cfg: &Monitors, cfd: &Path, start: &str) -> RunMonitors {
        let log = |name: &str, header: &str| TextLog {
            path: cfd
                .join("postProcessing")
                .join(name)
                .join(start)
                .join(format!("{name}.txt")),
            text: header.to_owned(),
        };
        let pcv_log = cfg
            .particle_cell_volume
            .as_ref()
            .filter(|m| m.write_to_file)
            .map(|_| {
                log(
                    "particleCellVolume",
                    "# time | total particle volume in cells | total volume of cells with \
                     particles | average volume fraction | min(voidfraction) | \
                     max(voidfraction)\n",
                )
            });
        let averages_log = |m: &VolWeightedAverage, name: &str| {
            let names: Vec<&str> = m
                .scalar_fields
                .iter()
                .chain(&m.vector_fields)
                .map(String::as_str)
                .collect();
            log(name, &format!("# time | {}\n", names.join(" | ")))
        };
        let vwa_log = cfg
            .vol_weighted_average
            .as_ref()
            .filter(|m| m.write_to_file)
            .map(|m| averages_log(m, "volWeightedAverage"));
        let fvw_log = cfg
            .field_vol_weighted
            .as_ref()
            .map(|m| averages_log(m, "fieldVolWeighted"));
        let pv_log = cfg
            .particle_volume
            .as_ref()
            .filter(|m| m.write_to_file)
            .map(|_| log("particleVolume", ""));
        let tme_log = cfg
            .total_momentum_exchange
            .as_ref()
            .filter(|m| m.write_to_file)
            .map(|_| {
                log(
                    "totalMomentumExchange",
                    "# time | total (Fx Fy Fz) | implicit (Ksl (U - Us)) | explicit (-f), N, \
                     force of the fluid on the particles\n",
                )
            });
        let observed = |names: &[String]| names.iter().any(|n| n == "ddtVoidfraction");
        let needs_ddt = cfg.field_store.iter().any(|s| observed(&s.scalar_fields))
            || cfg
                .vol_weighted_average
                .iter()
                .any(|s| observed(&s.scalar_fields))
            || cfg
                .field_vol_weighted
                .iter()
                .any(|s| observed(&s.scalar_fields))
            || cfg
                .field_time_average
                .iter()
                .any(|s| observed(&s.scalar_fields));
        RunMonitors {
            cfg: cfg.clone(),
            pcv_log,
            vwa_log,
            fvw_log,
            pv_log,
            tme_log,
            means: Vec::new(),
            samples: 0,
            last: Last::default(),
            needs_ddt,
        }
    }

    /// True when nothing is observed.
    pub(crate) fn is_empty(&self) -> bool {
        let c = &self.cfg;
        c.field_store.is_none()
            && c.field_time_average.is_none()
            && c.particle_volume.is_none()
            && c.total_momentum_exchange.is_none()
            && c.particle_cell_volume.is_none()
            && c.vol_weighted_average.is_none()
            && c.field_vol_weighted.is_none()
            && !c.clock
            && !c.basic_io
    }

    /// True when `particleVolume` needs the volume of the located particles (summed over
    /// the ranks by the caller, [`couple::monitor::located_particle_volume`]).
    pub(crate) fn wants_located_volume(cfg: &Monitors) -> bool {
        cfg.particle_volume.is_some()
    }

    /// Observes one coupling step at `time`; `located_volume` is the volume of the particles
    /// inside the mesh (m³, over all ranks; `Some` when [`RunMonitors::wants_located_volume`]).
    /// Returns the log lines (`verbose`).
    pub(crate) fn observe(
        &mut self,
        time: f64,
        volumes: &[f64],
        f: &StepFields<'_>,
        located_volume: Option<f64>,
    ) -> Vec<String> {
        let mut lines = Vec::new();
        let start = self.cfg.field_time_average.as_ref().map(|m| m.start_time);
        if start.is_some_and(|s| time >= s) {
            self.average(f);
        }
        if let (Some(m), Some(v)) = (&self.cfg.particle_volume, located_volume) {
            if time >= m.start_time {
                if m.verbose {
                    lines.push(format!("Total particle volume (located in domain) = {v}"));
                }
                if let Some(log) = &mut self.pv_log {
                    let _ = writeln!(log.text, "{} {v}", couple::output::time_name(time));
                }
            }
        }
        if let Some(m) = self.cfg.total_momentum_exchange.clone() {
            self.momentum_exchange(&m, time, volumes, f, &mut lines);
        }
        if let Some(m) = self.cfg.particle_cell_volume.clone() {
            self.cell_volume(&m, time, volumes, f, &mut lines);
        }
        if let Some(m) = self.cfg.vol_weighted_average.clone() {
            if time >= m.start_time {
                let (row, last) = averages(&m, "volWeightedAverage", volumes, f, &mut lines);
                self.last.averages = last;
                push_row(&mut self.vwa_log, time, &row);
            }
        }
        if let Some(m) = &self.cfg.field_vol_weighted {
            if time >= m.start_time {
                let (row, _) = averages(m, "fieldVolWeighted", volumes, f, &mut lines);
                push_row(&mut self.fvw_log, time, &row);
            }
        }
        lines
    }

    /// `fieldTimeAverage`: adds this step's fields to the means.
    fn average(&mut self, f: &StepFields<'_>) {
        let Some(m) = &self.cfg.field_time_average else {
            return;
        };
        let n = self.samples;
        for (i, name) in m.scalar_fields.iter().chain(&m.vector_fields).enumerate() {
            if self.means.len() <= i {
                self.means.push((name.clone(), Mean::Scalar(Vec::new())));
            }
            let mean = &mut self.means[i].1;
            match (f.get(name), mean) {
                (Field::Scalar(x), Mean::Scalar(avg)) => accumulate_mean(avg, n, &x),
                (Field::Vector(x), mean) => {
                    if !matches!(mean, Mean::Vector(_)) {
                        *mean = Mean::Vector(Vec::new());
                    }
                    if let Mean::Vector(avg) = mean {
                        accumulate_mean(avg, n, x);
                    }
                }
                (Field::Scalar(_), Mean::Vector(_)) => unreachable!("a field keeps its kind"),
            }
        }
        self.samples += 1;
    }

    fn momentum_exchange(
        &mut self,
        m: &TotalMomentumExchange,
        time: f64,
        volumes: &[f64],
        f: &StepFields<'_>,
        lines: &mut Vec<String>,
    ) {
        if time < m.start_time {
            return;
        }
        let e = &f.step.exchange;
        let x = total_momentum_exchange(&e.ksl, f.fluid.u, &e.us, &e.f, volumes, m.explicit);
        let v = |v: V3| format!("({} {} {})", v.x, v.y, v.z);
        if m.verbose {
            lines.push(format!(
                "totalMomentumExchange: force of the fluid on the particles {} N (implicit {}, \
                 explicit {})",
                v(x.total()),
                v(x.implicit),
                v(x.explicit)
            ));
        }
        if let Some(log) = &mut self.tme_log {
            let _ = writeln!(
                log.text,
                "{} {} {} {}",
                couple::output::time_name(time),
                v(x.total()),
                v(x.implicit),
                v(x.explicit)
            );
        }
    }

    fn cell_volume(
        &mut self,
        m: &ParticleCellVolume,
        time: f64,
        volumes: &[f64],
        f: &StepFields<'_>,
        lines: &mut Vec<String>,
    ) {
        if time < m.start_time {
            return;
        }
        let s = particle_cell_volume(f.eps, volumes, m.lower, m.upper);
        self.last.cell_volume = Some((s.particle_volume, s.cell_volume));
        if m.verbose {
            lines.push(format!(
                "particleCellVolume: particle volume {} in the cells with {} < voidfraction < {} \
                 (volume {}), average volume fraction {}, voidfraction from {} to {}",
                s.particle_volume,
                m.lower,
                m.upper,
                s.cell_volume,
                opt(s.average_fraction()),
                opt(s.min),
                opt(s.max)
            ));
        }
        if let Some(log) = &mut self.pcv_log {
            let _ = writeln!(
                log.text,
                "{} {} {} {} {} {}",
                couple::output::time_name(time),
                s.particle_volume,
                s.cell_volume,
                opt(s.average_fraction()),
                opt(s.min),
                opt(s.max)
            );
        }
    }

    /// Writes the monitors' fields into the time directory `dir` (named `time`), the
    /// particles (`basicIO`; `None` on N ranks, where rank 0 does not hold them: the run
    /// warns), and rewrites the text files.
    pub(crate) fn write_time(
        &self,
        dir: &Path,
        time: &str,
        mesh: &PolyMesh,
        f: &StepFields<'_>,
        particles: Option<&ParticleState<'_>>,
    ) -> Result<(), RunError> {
        let n = mesh.n_cells;
        let fmt = Format::Ascii;
        let uniform = |x: f64| FieldValues::Scalar(vec![x; n]);
        if let Some(store) = &self.cfg.field_store {
            for name in store.scalar_fields.iter().chain(&store.vector_fields) {
                let values = match f.get(name) {
                    Field::Scalar(phi) => FieldValues::Scalar(phi.into_owned()),
                    Field::Vector(phi) => FieldValues::Vector(mesh::v3::to_arrays(phi)),
                };
                let stored = format!("stored_{name}");
                write_cell_field(dir, time, mesh, &stored, dimensions(name), values, fmt)?;
            }
        }
        if let Some((particle, cells)) = self.last.cell_volume {
            for (name, v) in [("particleCellVolume", particle), ("cellVolume", cells)] {
                write_cell_field(
                    dir,
                    time,
                    mesh,
                    name,
                    [0, 3, 0, 0, 0, 0, 0],
                    uniform(v),
                    fmt,
                )?;
            }
        }
        for (name, value) in &self.last.averages {
            // an average over no cell is not written as a number: the field is left out
            let Some(value) = value else { continue };
            let values = match value {
                FieldValuesOne::Scalar(x) => uniform(*x),
                FieldValuesOne::Vector(v) => FieldValues::Vector(vec![[v.x, v.y, v.z]; n]),
            };
            let field = format!("volAverage_{name}");
            write_cell_field(dir, time, mesh, &field, dimensions(name), values, fmt)?;
        }
        for (name, mean) in &self.means {
            let values = match mean {
                Mean::Scalar(x) if x.len() == n => FieldValues::Scalar(x.clone()),
                Mean::Vector(x) if x.len() == n => FieldValues::Vector(mesh::v3::to_arrays(x)),
                // no step averaged yet (before startTime): CFDEM's field is still zero
                Mean::Scalar(_) => FieldValues::Scalar(vec![0.0; n]),
                Mean::Vector(_) => FieldValues::Vector(vec![[0.0; 3]; n]),
            };
            let field = format!("timeAverage_{name}");
            write_cell_field(dir, time, mesh, &field, dimensions(name), values, fmt)?;
        }
        if let (true, Some(particles)) = (self.cfg.basic_io, particles) {
            write_basic_io(dir, f.step, particles, self.cfg.particle_io)?;
        }
        self.write_logs()
    }

    /// Rewrites the text files.
    pub(crate) fn write_logs(&self) -> Result<(), RunError> {
        for log in [
            &self.pcv_log,
            &self.vwa_log,
            &self.fvw_log,
            &self.pv_log,
            &self.tme_log,
        ]
        .into_iter()
        .flatten()
        {
            log.write()?;
        }
        Ok(())
    }

    /// `clockModel standardClock`: the timing table (`sections` of (name, seconds, runs)) in
    /// `cfd/clockData/timeEval.txt`; returns its lines for the log. `None` when the clock is off.
    pub(crate) fn clock(
        &self,
        cfd: &Path,
        sections: &[(&str, f64, u64)],
    ) -> Result<Option<Vec<String>>, RunError> {
        if !self.cfg.clock {
            return Ok(None);
        }
        let mut lines = vec![
            "Measured time intervals in wall-clock seconds:".to_owned(),
            "Name\tdeltaT\tnOfRuns".to_owned(),
        ];
        for (name, seconds, runs) in sections {
            lines.push(format!("{name}\t{seconds:e}\t{runs}"));
        }
        let log = TextLog {
            path: cfd.join("clockData").join("timeEval.txt"),
            text: format!("Time Evaluation\n{}\n", lines.join("\n")),
        };
        log.write()?;
        Ok(Some(lines))
    }
}

/// CFDEM's basicIO: the particles inside the mesh as `positions` (OpenFOAM's pre-v1706
/// `Cloud<passiveParticle>` form `(x y z) cell`), `v` and `r`, in
/// `dir/lagrangian/particleCloud/`; with `sophIO`/`trackIO` also their files (module docs).
fn write_basic_io(
    dir: &Path,
    step: &CouplingStep,
    particles: &ParticleState<'_>,
    kind: ParticleIo,
) -> Result<(), RunError> {
    let out = dir.join("lagrangian").join("particleCloud");
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| RunError::Io { path, source }
    };
    std::fs::create_dir_all(&out).map_err(io(&out))?;
    let inside: Vec<(usize, usize)> = (0..particles.len())
        .filter_map(|i| step.placement.centre[i].map(|c| (i, c as usize)))
        .collect();
    let location = dir
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let header = |class: &str, object: &str| {
        format!(
            "{}{}\n(\n",
            foam::writer::ascii_header(class, &location, object),
            inside.len()
        )
    };
    let mut positions = header("Cloud<passiveParticle>", "positions");
    let mut v = header("vectorField", "v");
    let mut r = header("scalarField", "r");
    for &(i, cell) in &inside {
        let x = particles.position[i];
        let u = particles.velocity[i];
        let _ = writeln!(positions, "({} {} {}) {cell}", x.x, x.y, x.z);
        let _ = writeln!(v, "({} {} {})", u.x, u.y, u.z);
        let _ = writeln!(r, "{}", particles.radius[i]);
    }
    let mut files = vec![("positions", positions), ("v", v), ("r", r)];
    if kind != ParticleIo::Basic {
        let vector = |name: &'static str, of: &dyn Fn(usize) -> V3| {
            let mut text = header("vectorField", name);
            for &(i, _) in &inside {
                let x = of(i);
                let _ = writeln!(text, "({} {} {})", x.x, x.y, x.z);
            }
            (name, text)
        };
        let c = &step.forces.particles;
        let mut eps = header("scalarField", "voidfractions");
        for &(_, cell) in &inside {
            let _ = writeln!(eps, "{}", step.voidage.epsilon[cell]);
        }
        files.push(("voidfractions", eps));
        let imp = |i: usize| (c[i].u_f - particles.velocity[i]) * c[i].beta_fluid;
        files.push(vector("impForces", &imp));
        files.push(vector("expForces", &|i| c[i].f_fluid));
        files.push(vector("DEMForces", &|i| c[i].f_ext));
    }
    if kind == ParticleIo::Track {
        let mut id = header("scalarField", "id");
        for &(i, _) in &inside {
            let _ = writeln!(id, "{}", particles.ids[i]);
        }
        files.push(("id", id));
    }
    for (name, mut text) in files {
        text.push_str(")\n");
        let path = out.join(name);
        atomic_write::write_atomically(&path, |w| w.write_all(text.as_bytes()))
            .map_err(io(&path))?;
    }
    Ok(())
}
