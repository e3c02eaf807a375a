//! `foamgrain fluid CASE`: the native fluid alone on a plain OpenFOAM case (a pisoFoam or
//! icoFoam case, no particles), so that anyone can put it side by side with OpenFOAM.
//!
//! The case is read as OpenFOAM reads it: `system/controlDict` (times, writes, `purgeWrite`,
//! function objects), `fvSchemes`, `fvSolution`, `constant/transportProperties` and
//! `turbulenceProperties` — what `fv` does not support is an error naming the file and key
//! ([`fv::settings`]). The run writes time directories as OpenFOAM does (`U`, `p`, `phi`,
//! with k–ε also `k`, `epsilon`, `nut`) at the controlDict's write times. Function objects:
//! `probes` (of `p`, `U`, and with k–ε `k`, `epsilon`, `nut`; [`crate::probes`]); any other
//! is refused by name. `application`, when given, must be `pisoFoam` or `icoFoam`: the two
//! solvers whose equations `fv` solves (icoFoam's has only the Laplacian stress, which `fv`
//! takes from `turbulenceProperties`' absence, as icoFoam has none).

use crate::error::RunError;
use crate::monitors::Field;
use crate::plan::ControlDict;
use crate::probes::Probes;
use fv::{Fluid, StepReport};
use std::borrow::Cow;
use std::path::Path;
use std::time::{Duration, Instant};

/// The applications whose cases `foamgrain fluid` runs.
pub const APPLICATIONS: [&str; 2] = ["pisoFoam", "icoFoam"];

/// The function objects `foamgrain fluid` runs (others are refused by name).
pub const FUNCTION_OBJECTS: [&str; 1] = ["probes"];

/// What a plain fluid run reports as it goes.
#[derive(Debug)]
pub enum FluidEvent<'a> {
    /// The case is open: its cell count, the number of steps, Δt (s) and the end time (s).
    Opened {
        /// Cells of the mesh.
        cells: usize,
        /// Steps to run.
        steps: usize,
        /// Time step, s.
        delta_t: f64,
        /// End time, s.
        end_time: f64,
    },
    /// A warning (a probe point or field left out, as OpenFOAM leaves them out).
    Warning(String),
    /// Step `index` of `of` done, at `time` (s), with its Courant number and solves.
    Step {
        /// 1-based.
        index: usize,
        /// Steps of the run.
        of: usize,
        /// Time reached, s.
        time: f64,
        /// The step's Courant number (OpenFOAM's `CourantNo.H`, from the new fluxes).
        courant: fv::courant::Courant,
        /// The step's linear solves.
        report: &'a StepReport,
    },
    /// A time directory was written.
    Wrote {
        /// Its name.
        name: &'a str,
    },
}

/// Linear-solver iterations summed over a run, per equation (what a side-by-side comparison
/// with OpenFOAM's log puts next to each other).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Iterations {
    /// Momentum (all components).
    pub u: usize,
    /// Pressure (all correctors).
    pub p: usize,
    /// k and ε.
    pub turbulence: usize,
}

/// A finished plain fluid run.
#[derive(Debug)]
pub struct FluidRun {
    /// Steps run.
    pub steps: usize,
    /// Cells of the mesh.
    pub cells: usize,
    /// Time directories written, in order (those `purgeWrite` removed included).
    pub written: Vec<String>,
    /// Linear-solver iterations.
    pub iterations: Iterations,
    /// Wall time of the time loop (reading the case excluded).
    pub loop_time: Duration,
}

/// Runs `case` (an OpenFOAM case directory) with the native fluid to `end_time` (the
/// controlDict's when `None`), reporting to `observe`.
pub fn run_fluid(
    case: &Path,
    end_time: Option<f64>,
    observe: &mut dyn FnMut(FluidEvent<'_>),
) -> Result<FluidRun, RunError> {
    let control = ControlDict::read(case)?;
    check_application(&control)?;
    check_function_objects(&control)?;
    // the controlDict and the mesh are read once, here, and handed to the fluid
    let foam_case = foam::case::Case::open(case)?;
    let settings = fv::settings::Settings::read_with_control(&foam_case, &control.body)
        .map_err(fluid_error)?;
    let mesh = foam_case.read_mesh()?;
    let mut fluid = Fluid::from_case_with(foam_case, settings, &mesh).map_err(fluid_error)?;
    let cells = fluid.geometry().n_cells;
    // The cell locator of the probes, built only when a probe asks for it (its set-up costs
    // about as much as a few time steps on 10⁵ cells).
    let locator: std::cell::OnceCell<Result<mesh::locate::Locator, String>> =
        std::cell::OnceCell::new();
    let locator_of = || {
        locator.get_or_init(|| {
            let geometry = mesh::geometry::MeshGeometry::new(&mesh).map_err(|e| e.to_string())?;
            mesh::locate::Locator::new(&mesh, &geometry).map_err(|e| e.to_string())
        })
    };
    let turbulent = fluid.turbulence().is_some();
    let available: &[(&str, bool)] = match turbulent {
        true => &[
            ("p", false),
            ("U", true),
            ("k", false),
            ("epsilon", false),
            ("nut", false),
        ],
        false => &[("p", false), ("U", true)],
    };
    let start_name = fluid.time_name();
    let read = Probes::read_fields(case, &control, &start_name, available, &|x| {
        locator_of()
            .as_ref()
            .ok()
            .and_then(|l| l.locate(x).map(|c| c as usize))
    });
    // a mesh the locator refuses is the error, not the probes it could not place
    if let Some(Err(message)) = locator.get() {
        return Err(RunError::Setup {
            file: case.join("constant/polyMesh"),
            message: message.clone(),
        });
    }
    let (mut probes, warnings) = read?;
    for w in warnings {
        observe(FluidEvent::Warning(w));
    }
    let dt = fluid.settings.delta_t;
    let end = end_time.unwrap_or(fluid.settings.end_time);
    observe(FluidEvent::Opened {
        cells,
        steps: ((end - fluid.time()) / dt - 1e-9).ceil().max(0.0) as usize,
        delta_t: dt,
        end_time: end,
    });
    let mut iterations = Iterations::default();
    let mut written = Vec::new();
    let mut probe_error = None;
    let started = Instant::now();
    let steps = fluid
        .run_observed(end_time, |fluid, event| {
            match event {
                fv::fluid::RunEvent::Step {
                    index,
                    of,
                    report,
                    writes,
                } => {
                    count(&mut iterations, report);
                    let courant = fv::courant::courant(fluid.geometry(), fluid.phi(), dt);
                    observe(FluidEvent::Step {
                        index,
                        of,
                        time: fluid.time(),
                        courant,
                        report,
                    });
                    if let Err(e) = sample(&mut probes, fluid, writes) {
                        probe_error.get_or_insert(e);
                    }
                }
                fv::fluid::RunEvent::Wrote { name } => {
                    written.push(name.to_string());
                    observe(FluidEvent::Wrote { name });
                }
            }
            // a probe file that cannot be written ends the run (its error is returned below)
            match probe_error.is_some() {
                true => Err(fv::FvError::Value {
                    what: "probes".into(),
                    msg: "a probe file could not be written".into(),
                }),
                false => Ok(()),
            }
        })
        .map_err(|e| probe_error.take().unwrap_or_else(|| fluid_error(e)))?;
    Ok(FluidRun {
        steps,
        cells,
        written,
        iterations,
        loop_time: started.elapsed(),
    })
}

/// Samples the probes due after a step: those with `writeControl timeStep`, and with `write`
/// (the step ends at a write time) also the write-time ones.
fn sample(probes: &mut Probes, fluid: &Fluid, write: bool) -> Result<(), RunError> {
    if probes.is_empty() {
        return Ok(());
    }
    let get = |name: &str| -> Field<'_> {
        let turbulence = fluid.turbulence();
        match (name, turbulence) {
            ("p", _) => Field::Scalar(Cow::Borrowed(fluid.p())),
            ("U", _) => Field::Vector(fluid.u()),
            ("k", Some(t)) => Field::Scalar(Cow::Borrowed(t.k())),
            ("epsilon", Some(t)) => Field::Scalar(Cow::Borrowed(t.epsilon())),
            ("nut", Some(t)) => Field::Scalar(Cow::Borrowed(t.nut())),
            // Probes::read_fields accepted only the names above
            (other, _) => unreachable!("probe field `{other}` was not offered"),
        }
    };
    probes.sample_with(fluid.time(), write, &get)
}

/// Adds a step's iterations.
fn count(total: &mut Iterations, report: &StepReport) {
    total.u += report.momentum.iter().map(|s| s.iterations).sum::<usize>();
    total.p += report.pressure.iter().map(|s| s.iterations).sum::<usize>();
    total.turbulence += report
        .turbulence
        .iter()
        .map(|s| s.iterations)
        .sum::<usize>();
}

fn fluid_error(e: fv::FvError) -> RunError {
    RunError::Fluid(Box::new(e))
}

/// `application`, when given, is one whose equations `fv` solves.
fn check_application(control: &ControlDict) -> Result<(), RunError> {
    match control.body.word("application") {
        Ok(app) if !APPLICATIONS.contains(&app) => Err(RunError::Setup {
            file: control.path.clone(),
            message: format!(
                "application `{app}` is not run by `foamgrain fluid` (it solves the equations \
                 of {})",
                APPLICATIONS.join(" and ")
            ),
        }),
        _ => Ok(()),
    }
}

/// Every function object is one `foamgrain fluid` runs; the first other is an error naming it.
fn check_function_objects(control: &ControlDict) -> Result<(), RunError> {
    let Some(functions) = control.body.opt_dict("functions") else {
        return Ok(());
    };
    for key in functions.keys() {
        let Some(d) = functions.opt_dict(key) else {
            continue;
        };
        let kind = d.word("type").unwrap_or("(no type)");
        if !FUNCTION_OBJECTS.contains(&kind) {
            return Err(RunError::Setup {
                file: control.path.clone(),
                message: format!(
                    "functions/{key}: function object type `{kind}` is not run by `foamgrain \
                     fluid` (it runs {})",
                    FUNCTION_OBJECTS.join(", ")
                ),
            });
        }
    }
    Ok(())
}
