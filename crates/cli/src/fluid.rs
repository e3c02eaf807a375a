//! `foamgrain fluid CASE`: the native fluid alone on a plain OpenFOAM case (pisoFoam, icoFoam).

use clap::Args;
use runner::fluid_case::{run_fluid, FluidEvent};
use std::path::PathBuf;

/// Arguments of `foamgrain fluid`.
#[derive(Args, Debug)]
pub struct FluidArgs {
    /// The OpenFOAM case directory (system/, constant/, the start time's directory).
    pub case: PathBuf,
    /// Number of threads (default: all cores).
    #[arg(long)]
    pub np: Option<usize>,
    /// Stop at this simulated time instead of the controlDict's endTime (s).
    #[arg(long)]
    pub end_time: Option<f64>,
    /// Print OpenFOAM's per-step log lines (Courant number, each solve's residuals and
    /// iterations) instead of a progress bar.
    #[arg(long)]
    pub log: bool,
}

/// Runs the command.
pub fn run(a: &FluidArgs) -> anyhow::Result<()> {
    crate::args::set_threads(a.np, "--np")?;
    let bar = match a.log {
        true => None,
        false => crate::args::progress_bar(
            1,
            "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} steps, t = {msg} (ETA {eta})",
        ),
    };
    let mut on_event = |e: FluidEvent<'_>| match e {
        FluidEvent::Opened {
            cells,
            steps,
            delta_t,
            end_time,
        } => {
            let line = format!("{cells} cells, {steps} steps of {delta_t} s to t = {end_time} s");
            match &bar {
                Some(b) => {
                    b.set_length(steps as u64);
                    b.println(line);
                }
                None => eprintln!("{line}"),
            }
        }
        FluidEvent::Warning(w) => match &bar {
            Some(b) => b.println(format!("warning: {w}")),
            None => eprintln!("warning: {w}"),
        },
        FluidEvent::Step {
            index,
            time,
            courant,
            report,
            ..
        } => match &bar {
            Some(b) => {
                b.set_position(index as u64);
                b.set_message(format!("{time:.6}"));
            }
            None if a.log => {
                println!("Time = {}\n", foam::case::time_name(time));
                println!(
                    "Courant Number mean: {:.6} max: {:.6}",
                    courant.mean, courant.max
                );
                let line = |name: &str, s: &fv::linsolve::SolveStats| {
                    println!(
                        "{name}: Initial residual = {:e}, Final residual = {:e}, No Iterations {}",
                        s.initial, s.last, s.iterations
                    )
                };
                for (s, c) in report.momentum.iter().zip(["Ux", "Uy", "Uz"]) {
                    line(c, s);
                }
                for s in &report.pressure {
                    line("p", s);
                }
                for (s, c) in report.turbulence.iter().zip(["epsilon", "k"]) {
                    line(c, s);
                }
                println!();
            }
            None => {}
        },
        FluidEvent::Wrote { name } => match &bar {
            Some(b) => b.println(format!("wrote {name}")),
            None => eprintln!("wrote {name}"),
        },
    };
    keep_freed_memory();
    // The run on one of the pool's threads: its parallel loops then split among the pool's
    // threads directly, not handed over from outside the pool (a wake-up and a sleep of
    // this thread per loop, hundreds per time step in the multigrid cycles).
    let done = rayon::scope(|_| run_fluid(&a.case, a.end_time, &mut on_event))?;
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let it = done.iterations;
    eprintln!(
        "{} steps on {} cells in {:.2} s; linear-solver iterations: U {}, p {}, k and epsilon {}",
        done.steps,
        done.cells,
        done.loop_time.as_secs_f64(),
        it.u,
        it.p,
        it.turbulence
    );
    Ok(())
}

/// Asks glibc's allocator to keep freed memory instead of returning it to the kernel: a time
/// step allocates and frees field-sized vectors (0.8 MB at 10⁵ cells) many times, and each
/// one taken from fresh pages costs a page fault and the kernel's zeroing per 4 KiB (measured
/// with `perf`: 4 % of the 320² cavity's run in `clear_page_erms`). Blocks below 32 MiB (glibc's
/// largest mmap threshold) come from the heap, and its top is never trimmed.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only changes the allocator's tuning parameters; any values are valid.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
    }
}
