//! The cell-size study: every grid × voidage method × velocity of a frozen bed, against the
//! references, with the voidage spread and the Grid Convergence Index.
//!
//! **Cell size.** The option `dx_over_d` is the dimensionless cell size Δx/d₃₂ — the cell edge
//! over the Sauter-mean diameter of the packed bed (Volk et al. 2018's preferred definition;
//! the issue's `--cells-per-d` is its inverse, d/Δx, and is not used here). For each value the
//! grid has n_a = max(1, round(L_a / (Δx/d₃₂ · d₃₂))) cells along each box edge L_a; the
//! reported sizes are those of the grid made, h = (V/N)^(1/3) (Celik et al. 2008 eq. 1),
//! over the number-mean, Sauter-mean and largest diameters ([`crate::diameters`]).
//!
//! **Velocities** are given as fractions of the minimum fluidisation velocity U_mf of the
//! measured bed (the smaller of Ergun–Sauter's and the Gidaspow model's, [`crate::reference`]),
//! each in (0, 1): the bed stays fixed.
//!
//! **Target quantity** of the errors and of the GCI: the total fluid force on the bed along
//! the axis, F ([`crate::run`]), as a pressure F/A; its error is F/(A·Δp_Gidaspow) − 1 against
//! Gidaspow's drag law on the measured bed ([`crate::reference`]); the same against
//! Ergun–Sauter is reported too.
//!
//! Outputs ([`write_outputs`]): `cellsize.csv` (one row per run), `cellsize.json` (the whole
//! [`StudyReport`]) and PNG plots: the error against Δx/d for each of the three diameters
//! (one plot per velocity), and the voidage spread against Δx/d₃₂.

use crate::diameters::{CellSize, Diameters};
use crate::error::{io_err, StudyError};
use crate::pack::{packed_bed, PackedBed};
use crate::reference::{
    ergun_pressure_drop, gidaspow_pressure_drop, minimum_fluidisation, FluidProps,
};
use crate::run::{RunContext, RunResult};
use crate::steady::SteadyCriterion;
use crate::template::Template;
use closures::model::ModelType;
use couple::CouplerSettings;
use mesh::v3::{unit, V3};
use runner::bed::Bed;
use runner::layout::CaseLayout;
use runner::plot::{LinePlot, Series, Style};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use voidage::Method;

/// What to run (module docs).
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// Dimensionless cell sizes Δx/d₃₂ (> 0).
    pub dx_over_d: Vec<f64>,
    /// Voidage methods.
    pub methods: Vec<Method>,
    /// Superficial velocities as fractions of U_mf, each in (0, 1).
    pub velocities: Vec<f64>,
    /// When a run is steady.
    pub criterion: SteadyCriterion,
    /// Largest number of fluid steps per run.
    pub max_steps: u64,
    /// Output directory (default `CASE/postProcessing/cellsize`).
    pub output: Option<PathBuf>,
    /// Pack the bed again even if the packed file exists.
    pub repack: bool,
    /// `-var NAME VALUE` for the init deck.
    pub init_vars: Vec<(String, String)>,
    /// Inlet patch name.
    pub inlet: String,
    /// Outlet patch name.
    pub outlet: String,
}

impl Default for StudyOptions {
    /// Volk et al.'s range of cell sizes, the five methods defined on every mesh
    /// ([`Method::ANY_MESH`]), 0.5 and 0.9 U_mf.
    fn default() -> Self {
        StudyOptions {
            dx_over_d: vec![1.0, 1.5, 2.0, 3.0, 4.0, 6.0],
            methods: Method::ANY_MESH.to_vec(),
            velocities: vec![0.5, 0.9],
            criterion: SteadyCriterion::default(),
            max_steps: 4000,
            output: None,
            repack: false,
            init_vars: Vec::new(),
            inlet: "inlet".into(),
            outlet: "outlet".into(),
        }
    }
}

/// What a study reports as it goes.
#[derive(Clone, Debug)]
pub enum StudyEvent {
    /// A log line.
    Message(String),
    /// A run finished (`done` of `total`).
    Run {
        /// Runs finished.
        done: usize,
        /// Runs in total.
        total: usize,
        /// Its outcome.
        result: Box<StudyRow>,
    },
}

/// The measured bed and its fluidisation.
#[derive(Clone, Debug, Serialize)]
pub struct BedSummary {
    /// Number of particles.
    pub particles: usize,
    /// Number-mean, Sauter-mean and largest diameters, m.
    pub diameters: Diameters,
    /// Bed floor (lowest sphere bottom) along the axis, m.
    pub floor: f64,
    /// Bed height ([`runner::bed::Bed`]: mean of the highest tops over bins of 2 d₃₂), m.
    pub height: f64,
    /// Mean voidage 1 − V_p/(A L).
    pub voidage: f64,
    /// Cross-section, m².
    pub area: f64,
    /// Buoyant weight per area, Pa.
    pub weight_per_area: f64,
    /// U_mf from Ergun–Sauter, m/s.
    pub u_mf_ergun: f64,
    /// U_mf from Gidaspow per particle, m/s.
    pub u_mf_gidaspow: f64,
    /// Fluid density and viscosity.
    pub fluid: FluidProps,
}

/// The references at one velocity.
#[derive(Clone, Debug, Serialize)]
pub struct VelocityReference {
    /// Fraction of U_mf.
    pub fraction: f64,
    /// Superficial velocity, m/s.
    pub velocity: f64,
    /// Gidaspow on the measured bed, Pa.
    pub gidaspow_dp: f64,
    /// Ergun–Sauter on the measured bed, Pa.
    pub ergun_dp: f64,
}

/// One run with its cell sizes and errors.
#[derive(Clone, Debug, Serialize)]
pub struct StudyRow {
    /// The Δx/d₃₂ asked for.
    pub target: f64,
    /// The grid's cell size and its three dimensionless forms.
    pub cell_size: CellSize,
    /// Fraction of U_mf.
    pub fraction: f64,
    /// The run.
    pub run: RunResult,
    /// The total fluid force per cross-section F/A, Pa.
    pub force_per_area: f64,
    /// F/(A Δp_Gidaspow) − 1.
    pub error: f64,
    /// Δp/Δp_Gidaspow − 1 (patch pressures).
    pub error_pressure_drop: f64,
    /// F/(A Δp_Ergun) − 1.
    pub error_ergun: f64,
}

/// A run that failed (the solver diverged or refused its input); the study goes on without it.
#[derive(Clone, Debug, Serialize)]
pub struct RunFailure {
    /// Voidage method.
    pub method: String,
    /// Fraction of U_mf.
    pub fraction: f64,
    /// The Δx/d₃₂ asked for.
    pub target: f64,
    /// Cells per direction.
    pub n: [usize; 3],
    /// The error.
    pub message: String,
}

/// GCI of one method at one velocity over the grids (target: F/A, Pa).
#[derive(Clone, Debug, Serialize)]
pub struct GciSeries {
    /// Voidage method.
    pub method: String,
    /// Fraction of U_mf.
    pub fraction: f64,
    /// Successive triplets (finest first), or why there are none.
    pub triplets: Vec<gci::Triplet>,
    /// Set when the analysis could not run (fewer than three grids, equal sizes).
    pub note: Option<String>,
}

/// Everything a study found.
#[derive(Clone, Debug, Serialize)]
pub struct StudyReport {
    /// The case.
    pub case: PathBuf,
    /// The bed.
    pub bed: BedSummary,
    /// References per velocity.
    pub references: Vec<VelocityReference>,
    /// One row per run, in the order run (velocity, method, grid).
    pub rows: Vec<StudyRow>,
    /// Runs whose fluid solve failed (not in `rows`).
    pub failures: Vec<RunFailure>,
    /// GCI per method and velocity.
    pub gci: Vec<GciSeries>,
    /// The steady-state criterion used.
    pub criterion: SteadyCriterion,
    /// Wall-clock seconds: packing (0 if reused) and the runs.
    pub pack_seconds: f64,
    /// Seconds of all runs.
    pub run_seconds: f64,
}

fn check_options(o: &StudyOptions) -> Result<(), StudyError> {
    let bad = |m: String| Err(StudyError::Option(m));
    if o.dx_over_d.is_empty() || o.methods.is_empty() || o.velocities.is_empty() {
        return bad("dx_over_d, methods and velocities must each hold at least one value".into());
    }
    if let Some(x) = o.dx_over_d.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
        return bad(format!("cell size Δx/d = {x} is not a positive number"));
    }
    if let Some(x) = o
        .velocities
        .iter()
        .find(|x| !(x.is_finite() && **x > 0.0 && **x < 1.0))
    {
        return bad(format!(
            "velocity fraction {x} of U_mf is not in (0, 1): the bed must stay fixed"
        ));
    }
    if o.max_steps == 0 {
        return bad("max_steps must be at least 1".into());
    }
    Ok(())
}

/// Measures the frozen bed in the template's box (axis +z).
fn summarise(
    bed: &PackedBed,
    template: &Template,
    fluid: FluidProps,
    g: f64,
) -> Result<BedSummary, StudyError> {
    let l = template.lengths();
    let area = l[0] * l[1];
    let axis = V3::z();
    let floor = bed
        .position
        .iter()
        .zip(&bed.radius)
        .map(|(x, r)| x[2] - r)
        .fold(f64::INFINITY, f64::min);
    let measured = Bed::measure(&bed.position, axis, &bed.radius, &bed.density, floor, area)
        .ok_or_else(|| StudyError::Option("the packed bed is empty".into()))?;
    let d = bed.diameters();
    let diameters = Diameters::of(&d)
        .ok_or_else(|| StudyError::Option("the packed bed has a non-positive radius".into()))?;
    let weight = measured.weight_per_area(fluid.rho, g, area);
    let (u_mf_ergun, u_mf_gidaspow) = minimum_fluidisation(
        weight,
        &d,
        measured.voidage,
        diameters.sauter,
        measured.height,
        area,
        fluid,
    );
    Ok(BedSummary {
        particles: bed.len(),
        diameters,
        floor,
        height: measured.height,
        voidage: measured.voidage,
        area,
        weight_per_area: weight,
        u_mf_ergun,
        u_mf_gidaspow,
        fluid,
    })
}

/// The grid for a target Δx/d₃₂ (module docs).
pub fn grid_for(template: &Template, dx_over_d: f64, d32: f64) -> [usize; 3] {
    let dx = dx_over_d * d32;
    template
        .lengths()
        .map(|l| ((l / dx).round() as usize).max(1))
}

/// Runs the study on the case at `case` (module docs); `events` gets progress.
pub fn cellsize(
    case: &Path,
    opts: &StudyOptions,
    events: &mut dyn FnMut(StudyEvent),
) -> Result<StudyReport, StudyError> {
    check_options(opts)?;
    let StudyCase {
        layout,
        template,
        coupling_interval,
        settings,
        model,
        gvec,
        axis,
        fluid,
    } = StudyCase::read(case, events)?;

    let t_pack = Instant::now();
    let mut log = |m: String| events(StudyEvent::Message(m));
    let repacked = opts.repack || !layout.dem.join("post/packed.data").exists();
    let bed = packed_bed(&layout, opts.repack, &opts.init_vars, &mut log)?;
    let pack_seconds = if repacked {
        t_pack.elapsed().as_secs_f64()
    } else {
        0.0
    };
    let summary = summarise(&bed, &template, fluid, gvec.dot(&gvec).sqrt())?;
    let u_mf = summary.u_mf_ergun.min(summary.u_mf_gidaspow);
    events(StudyEvent::Message(format!(
        "bed: {} particles, d10 {:.4e} m, d32 {:.4e} m, dmax {:.4e} m, height {:.4e} m, voidage {:.4}, U_mf {:.4} m/s (Ergun–Sauter {:.4}, Gidaspow {:.4})",
        summary.particles,
        summary.diameters.mean,
        summary.diameters.sauter,
        summary.diameters.largest,
        summary.height,
        summary.voidage,
        u_mf,
        summary.u_mf_ergun,
        summary.u_mf_gidaspow
    )));
    let references = velocity_references(&opts.velocities, u_mf, &bed, &summary);

    let out = opts
        .output
        .clone()
        .unwrap_or_else(|| layout.post_processing().join("cellsize"));
    let work = out.join("work");
    let ctx = RunContext {
        cfd: &layout.cfd,
        template: &template,
        bed: &bed,
        settings,
        model,
        coupling_interval,
        axis,
        inlet: &opts.inlet,
        outlet: &opts.outlet,
        bed_range: (summary.floor, summary.floor + summary.height),
        criterion: opts.criterion,
        max_steps: opts.max_steps,
        work: &work,
    };
    let t_runs = Instant::now();
    let (rows, failures) = run_all(&ctx, opts, &references, &summary, events)?;
    let run_seconds = t_runs.elapsed().as_secs_f64();
    let gci = gci_series(&rows, &references, &opts.methods);
    Ok(StudyReport {
        case: case.to_owned(),
        bed: summary,
        references,
        rows,
        failures,
        gci,
        criterion: opts.criterion,
        pack_seconds,
        run_seconds,
    })
}

/// What a study takes from its case before packing: the directories, the mesh template and
/// the coupling settings with the fluid model, gravity and the fluid's properties.
struct StudyCase {
    layout: CaseLayout,
    template: Template,
    /// `couplingInterval`.
    coupling_interval: u64,
    settings: CouplerSettings,
    model: fv::Model,
    /// Gravity, m/s².
    gvec: V3,
    /// Unit vector up the column (against gravity): +z.
    axis: V3,
    fluid: FluidProps,
}

impl StudyCase {
    /// Reads the case at `case` (its configuration's warnings go to `events`); an error unless
    /// gravity is along −z.
    fn read(case: &Path, events: &mut dyn FnMut(StudyEvent)) -> Result<StudyCase, StudyError> {
        let layout = CaseLayout::open(case)?;
        let template = Template::read(&layout.cfd.join("system/blockMeshDict.template"))?;
        let config = &layout.coupling;
        for w in &config.warnings {
            events(StudyEvent::Message(format!("warning: {w}")));
        }
        let settings = config.coupler_settings(&layout.cfd)?;
        let model = match config.model {
            ModelType::A => fv::Model::A,
            _ => fv::Model::B,
        };
        let gvec = settings.physics.gravity;
        let axis = unit(-gvec).unwrap_or(V3::z());
        if axis.dot(&V3::z()) < 1.0 - 1e-12 {
            return Err(StudyError::Setup {
                file: layout.cfd.join("constant/g"),
                message: "the study needs gravity along −z (the template's column axis is z)"
                    .into(),
            });
        }
        let fluid = FluidProps {
            rho: settings.physics.rho,
            mu: settings.physics.rho * settings.physics.nu,
        };
        let coupling_interval = config.coupling_interval;
        Ok(StudyCase {
            layout,
            template,
            coupling_interval,
            settings,
            model,
            gvec,
            axis,
            fluid,
        })
    }
}

/// The references at each velocity fraction of `u_mf` (m/s): Gidaspow's and Ergun–Sauter's
/// pressure drops on the measured bed.
fn velocity_references(
    fractions: &[f64],
    u_mf: f64,
    bed: &PackedBed,
    summary: &BedSummary,
) -> Vec<VelocityReference> {
    let fluid = summary.fluid;
    let d_all = bed.diameters();
    fractions
        .iter()
        .map(|&f| {
            let u = f * u_mf;
            VelocityReference {
                fraction: f,
                velocity: u,
                gidaspow_dp: gidaspow_pressure_drop(
                    &d_all,
                    summary.voidage,
                    u,
                    summary.area,
                    fluid,
                ),
                ergun_dp: ergun_pressure_drop(
                    u,
                    summary.voidage,
                    summary.diameters.sauter,
                    summary.height,
                    fluid,
                ),
            }
        })
        .collect()
}

/// Every run of the study, in the order velocity, method, grid: the rows of the runs that
/// finished and the runs whose fluid solve failed (each reported to `events`).
fn run_all(
    ctx: &RunContext<'_>,
    opts: &StudyOptions,
    references: &[VelocityReference],
    summary: &BedSummary,
    events: &mut dyn FnMut(StudyEvent),
) -> Result<(Vec<StudyRow>, Vec<RunFailure>), StudyError> {
    let total = references.len() * opts.methods.len() * opts.dx_over_d.len();
    let mut rows = Vec::with_capacity(total);
    let mut failures = Vec::new();
    for r in references {
        for &method in &opts.methods {
            for &target in &opts.dx_over_d {
                let n = grid_for(ctx.template, target, summary.diameters.sauter);
                let run = match ctx.run(n, method, r.velocity) {
                    Ok(run) => run,
                    Err(e @ (StudyError::Couple(_) | StudyError::Fluid { .. })) => {
                        let message = e.to_string();
                        events(StudyEvent::Message(format!(
                            "warning: {} Δx/d32 {target} at {:.3} U_mf failed: {message}",
                            method.name(),
                            r.fraction
                        )));
                        failures.push(RunFailure {
                            method: method.name().into(),
                            fraction: r.fraction,
                            target,
                            n,
                            message,
                        });
                        continue;
                    }
                    Err(e) => return Err(e),
                };
                let row = study_row(run, target, r, summary, ctx.template);
                if !row.run.steady {
                    events(StudyEvent::Message(format!(
                        "warning: {} Δx/d32 {target} at {:.3} U_mf: not steady after {} steps (change {:.2e})",
                        method.name(),
                        r.fraction,
                        row.run.steps,
                        row.run.last_change
                    )));
                }
                rows.push(row.clone());
                events(StudyEvent::Run {
                    done: rows.len() + failures.len(),
                    total,
                    result: Box::new(row),
                });
            }
        }
    }
    Ok((rows, failures))
}

/// The row of one run for the Δx/d₃₂ `target` at the velocity of `r`: its cell sizes and its
/// errors against the references.
fn study_row(
    run: RunResult,
    target: f64,
    r: &VelocityReference,
    summary: &BedSummary,
    template: &Template,
) -> StudyRow {
    let volume: f64 = template.lengths().iter().product();
    let h = gci::representative_size(volume, run.cells as f64, gci::Dim::Three);
    let p = run.fluid_force / summary.area;
    StudyRow {
        target,
        cell_size: summary.diameters.ratios(h),
        fraction: r.fraction,
        force_per_area: p,
        error: p / r.gidaspow_dp - 1.0,
        error_pressure_drop: run.pressure_drop / r.gidaspow_dp - 1.0,
        error_ergun: p / r.ergun_dp - 1.0,
        run,
    }
}

/// GCI of F/A per method and velocity over the grids run (distinct h only).
fn gci_series(rows: &[StudyRow], refs: &[VelocityReference], methods: &[Method]) -> Vec<GciSeries> {
    let mut out = Vec::new();
    for r in refs {
        for m in methods {
            let mut grids: Vec<gci::Grid> = rows
                .iter()
                .filter(|x| x.fraction == r.fraction && x.run.method == m.name())
                .map(|x| gci::Grid {
                    h: x.cell_size.h,
                    value: x.run.fluid_force,
                })
                .collect();
            grids.sort_by(|a, b| a.h.total_cmp(&b.h));
            grids.dedup_by(|a, b| (a.h - b.h).abs() <= 1e-12 * b.h);
            let (triplets, note) = match gci::analyse_study(&grids, &gci::Settings::default()) {
                Ok(t) => (t, None),
                Err(e) => (Vec::new(), Some(e.to_string())),
            };
            out.push(GciSeries {
                method: m.name().into(),
                fraction: r.fraction,
                triplets,
                note,
            });
        }
    }
    out
}

/// The CSV header of [`write_outputs`]'s `cellsize.csv`.
pub const CSV_HEADER: &str = "method,u_over_umf,velocity_m_s,nx,ny,nz,cells,h_m,dx_over_dmean,dx_over_d32,dx_over_dmax,pressure_drop_pa,drag_n,fluid_force_n,force_per_area_pa,ref_gidaspow_pa,ref_ergun_pa,error,error_pressure_drop,error_ergun,bed_voidage_mean,bed_voidage_std,bed_cells,min_voidage,clipped_volume_m3,steps,steady,last_change,fluctuation,seconds";

/// The report as CSV text (one row per run).
pub fn csv(report: &StudyReport) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in &report.rows {
        let refs = report.references.iter().find(|v| v.fraction == r.fraction);
        let (g, e) = refs.map_or((f64::NAN, f64::NAN), |v| (v.gidaspow_dp, v.ergun_dp));
        let (mean, std, cells) = r
            .run
            .spread
            .map_or((f64::NAN, f64::NAN, 0), |s| (s.mean, s.std, s.cells));
        let c = &r.cell_size;
        let x = &r.run;
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            x.method,
            r.fraction,
            x.velocity,
            x.n[0],
            x.n[1],
            x.n[2],
            x.cells,
            c.h,
            c.over_mean,
            c.over_sauter,
            c.over_largest,
            x.pressure_drop,
            x.drag,
            x.fluid_force,
            r.force_per_area,
            g,
            e,
            r.error,
            r.error_pressure_drop,
            r.error_ergun,
            mean,
            std,
            cells,
            x.min_voidage,
            x.clipped_volume,
            x.steps,
            x.steady,
            x.last_change,
            x.fluctuation,
            x.seconds
        ));
    }
    s
}

fn write_text(path: &Path, text: &str) -> Result<(), StudyError> {
    use std::io::Write;
    atomic_write::write_atomically(path, |w| w.write_all(text.as_bytes())).map_err(io_err(path))
}

/// One line per method through the points `point` gives for the rows at velocity fraction
/// `fraction`, sorted by x.
fn method_series(
    report: &StudyReport,
    methods: &[String],
    fraction: f64,
    point: impl Fn(&StudyRow) -> Option<(f64, f64)>,
) -> Vec<Series> {
    methods
        .iter()
        .map(|m| {
            let mut pts: Vec<(f64, f64)> = report
                .rows
                .iter()
                .filter(|r| r.fraction == fraction && &r.run.method == m)
                .filter_map(&point)
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            Series {
                name: m.clone(),
                points: pts,
                style: Style::Line,
            }
        })
        .collect()
}

/// Writes `cellsize.csv`, `cellsize.json` and the PNG plots into `dir`; returns the files.
pub fn write_outputs(report: &StudyReport, dir: &Path) -> Result<Vec<PathBuf>, StudyError> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    let mut files = Vec::new();
    let csv_path = dir.join("cellsize.csv");
    write_text(&csv_path, &csv(report))?;
    files.push(csv_path);
    let json_path = dir.join("cellsize.json");
    let json = serde_json::to_string_pretty(report)
        .map_err(|e| StudyError::Option(format!("JSON: {e}")))?;
    write_text(&json_path, &json)?;
    files.push(json_path);
    let methods: Vec<String> = {
        let mut m: Vec<String> = report.rows.iter().map(|r| r.run.method.clone()).collect();
        m.dedup();
        let mut seen = Vec::new();
        m.retain(|x| {
            let new = !seen.contains(x);
            seen.push(x.clone());
            new
        });
        m
    };
    type Axis = (&'static str, &'static str, fn(&CellSize) -> f64);
    let axes: [Axis; 3] = [
        ("d32", "Δx / d32 (Sauter mean)", |c| c.over_sauter),
        ("dmean", "Δx / d10 (number mean)", |c| c.over_mean),
        ("dmax", "Δx / dmax (largest)", |c| c.over_largest),
    ];
    for (k, v) in report.references.iter().enumerate() {
        for (tag, label, x_of) in axes {
            let series = method_series(report, &methods, v.fraction, |r| {
                Some((x_of(&r.cell_size), 100.0 * r.error))
            });
            let plot = LinePlot {
                title: format!(
                    "Total fluid force vs Gidaspow on the measured bed, U = {:.2} U_mf",
                    v.fraction
                ),
                x_label: label.into(),
                y_label: "error (%)".into(),
                series,
            };
            let path = dir.join(format!("error_u{k}_{tag}.png"));
            plot.write_png(&path)?;
            files.push(path);
        }
    }
    let first = report.references.first().map_or(f64::NAN, |v| v.fraction);
    let series = method_series(report, &methods, first, |r| {
        r.run.spread.map(|s| (r.cell_size.over_sauter, s.std))
    });
    let plot = LinePlot {
        title: "Standard deviation of the voidage in the bed".into(),
        x_label: "Δx / d32 (Sauter mean)".into(),
        y_label: "std of cell voidage".into(),
        series,
    };
    let path = dir.join("voidage_std.png");
    if plot.series.iter().any(|s| !s.points.is_empty()) {
        plot.write_png(&path)?;
        files.push(path);
    }
    Ok(files)
}
