//! `foamgrain run CASE`: runs a coupled case and checks it against its references.

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use runner::run::{Event, RunOptions};
use runner::validation::summary;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The fluid backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FluidBackend {
    /// The native Rust VANS PISO solver.
    Native,
    /// grainPisoFoam over MPI (Debian's OpenFOAM v1912; a build with feature `mpi`).
    Openfoam,
}

/// The particle backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DemBackend {
    /// The native Rust DEM.
    Native,
    /// LIGGGHTS in-process (Debian's libliggghts; a build with feature `liggghts`).
    Liggghts,
    /// LIGGGHTS as a child process coupled through files (slow: LIGGGHTS polls every 10 s).
    LiggghtsFile,
}

/// Arguments of `foamgrain run`.
///
/// Parallel: `mpirun -np N foamgrain run CASE --dem liggghts [--fluid openfoam|native]` runs
/// LIGGGHTS in-process on the N ranks (the deck's `processors` grid, or LIGGGHTS's choice), each
/// rank coupling only the particles its LIGGGHTS rank owns. The native fluid runs on rank 0
/// with threads (the ranks' touched cells are summed there); grainPisoFoam is spawned on
/// `--np` ranks of its own and every coupler rank exchanges the cells it touches straight with
/// the solver ranks owning them. The native DEM runs on one process (threads), not under
/// mpirun.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// The case directory (CFDEM layout: CFD/ with constant/couplingProperties, DEM/ with
    /// in.liggghts_run and optionally in.liggghts_init, validationDict).
    pub case: PathBuf,
    /// Fluid backend.
    #[arg(long, value_enum, default_value = "native")]
    pub fluid: FluidBackend,
    /// Particle backend.
    #[arg(long, value_enum, default_value = "native")]
    pub dem: DemBackend,
    /// Number of threads of the native backends (default: all cores) and MPI ranks of
    /// grainPisoFoam (default: `numberOfSubdomains` of CFD/system/decomposeParDict, else 1).
    #[arg(long)]
    pub np: Option<usize>,
    /// Stop at this simulated time instead of the controlDict's endTime (s).
    #[arg(long)]
    pub end_time: Option<f64>,
    /// A variable for the packing deck, NAME=VALUE (as LIGGGHTS's `-var NAME VALUE`), e.g.
    /// `--var np=2000`; repeatable.
    #[arg(long = "var", value_name = "NAME=VALUE")]
    pub vars: Vec<String>,
    /// Run the packing deck again even if its output exists.
    #[arg(long)]
    pub repack: bool,
    /// With `--fluid openfoam`: wait for grainPisoFoam's advance before the next DEM interval
    /// instead of running the two at once (the results are the same bit for bit; for timing
    /// comparisons).
    #[arg(long)]
    pub no_overlap: bool,
}

fn parse_vars(vars: &[String]) -> anyhow::Result<Vec<(String, String)>> {
    vars.iter()
        .map(|v| match v.split_once('=') {
            Some((k, x)) if !k.is_empty() => Ok((k.to_owned(), x.to_owned())),
            _ => bail!("--var {v}: expected NAME=VALUE"),
        })
        .collect()
}

/// Runs the command.
pub fn run(a: &RunArgs) -> anyhow::Result<()> {
    crate::args::set_threads(a.np, "--np")?;
    let opts = RunOptions {
        end_time: a.end_time,
        init_vars: parse_vars(&a.vars)?,
        repack: a.repack,
        fluid: match a.fluid {
            FluidBackend::Native => runner::backend::FluidBackend::Native,
            FluidBackend::Openfoam => runner::backend::FluidBackend::OpenFoam,
        },
        dem: match a.dem {
            DemBackend::Native => runner::backend::DemBackend::Native,
            DemBackend::Liggghts => runner::backend::DemBackend::Liggghts,
            DemBackend::LiggghtsFile => runner::backend::DemBackend::LiggghtsFile,
        },
        fluid_ranks: a.np.unwrap_or(0),
        no_overlap: a.no_overlap,
    };
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || {
            if stop.swap(true, Ordering::SeqCst) {
                // A second Ctrl-C: leave at once.
                std::process::exit(130);
            }
        })
        .context("installing the Ctrl-C handler")?;
    }
    let mut progress = crate::progress::Progress::new();
    let mut on_event = |e: Event| match e {
        Event::Message(m) => progress.message(&m),
        Event::LoopStarted { steps } => progress.started(steps),
        Event::Step {
            time,
            end,
            step,
            steps,
            sample,
        } => progress.step(
            step,
            steps,
            || {
                format!(
                    "{time:.5} / {end} s, Δp {} Pa",
                    measured(sample.pressure_drop, 2)
                )
            },
            || {
                format!(
                    "t = {time:.6} s, inlet {} m/s, Δp {} Pa, bed {} m, KE {:.3e} J",
                    measured(sample.inlet_velocity, 5),
                    measured(sample.pressure_drop, 3),
                    measured(sample.bed_height, 5),
                    sample.kinetic_energy
                )
            },
        ),
    };
    let report = runner::run::run(&a.case, &opts, &stop, &mut on_event)
        .with_context(|| format!("running {}", a.case.display()))?;
    progress.finish();
    if report.rank > 0 {
        // on N ranks rank 0 reports for the run
        return Ok(());
    }
    let share = |x: f64| {
        if report.loop_seconds > 0.0 {
            100.0 * x / report.loop_seconds
        } else {
            0.0
        }
    };
    eprintln!(
        "{} coupling steps to t = {} s, {} particles at the end, {} cells; packing {:.1} s, coupled loop {:.1} s: DEM {:.1} % fluid {:.1} % coupling {:.1} % output {:.1} %",
        report.steps,
        couple::output::time_name(report.time),
        report.particles_at_end,
        report.cells,
        report.init_seconds,
        report.loop_seconds,
        share(report.dem_seconds),
        share(report.fluid_seconds),
        share(report.coupling_seconds()),
        share(report.output_seconds)
    );
    if report.stopped {
        eprintln!("stopped early: no validation");
        return Ok(());
    }
    print!("{}", summary(&report.checks));
    let failed = report.checks.iter().filter(|c| !c.pass).count();
    if failed > 0 {
        return Err(ChecksFailed(format!(
            "{failed} of {} checks failed (see {})",
            report.checks.len(),
            a.case.join("postProcessing/validation.json").display()
        ))
        .into());
    }
    Ok(())
}

/// A run that completed but failed at least one of its checks: `foamgrain` exits 2 (an error
/// exits 1), so a script can tell a wrong answer from a run that did not finish.
#[derive(Debug)]
pub struct ChecksFailed(String);

impl std::fmt::Display for ChecksFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ChecksFailed {}

/// A measured quantity with `digits` decimals, or `—` when it was not measured.
fn measured(x: Option<f64>, digits: usize) -> String {
    x.map_or("—".to_owned(), |x| format!("{x:.digits$}"))
}
