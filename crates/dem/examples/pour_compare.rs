//! Runs a pour deck natively and compares the settled bed with LIGGGHTS's dump of the same
//! deck: bed top, core solid fraction, packed height, and time per particle-step.
//!
//! ```text
//! cargo run --release -p dem --example pour_compare -- \
//!     liggghts-inputs/pour.in tests/fixtures/dem/pour_liggghts.txt \
//!     [--log tests/fixtures/dem/pour_liggghts.log] [--half-width 0.01] [-var NAME VALUE]…
//! ```
//! The native run happens in a temporary directory; its dump of the same step as the LIGGGHTS
//! dump is measured.

#[path = "../tests/common/bed.rs"]
mod bed;

use std::path::{Path, PathBuf};
use std::time::Instant;

use dem_io::{read_snapshot, ReadOptions, Selection};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// Sum of LIGGGHTS's `Loop time of T on P procs for S steps with N atoms` lines:
/// (seconds, particle-steps).
fn liggghts_loop_time(log: &Path) -> Result<(f64, f64), String> {
    let text = std::fs::read_to_string(log).map_err(|e| format!("{}: {e}", log.display()))?;
    let mut secs = 0.0;
    let mut work = 0.0;
    for l in text.lines().filter(|l| l.starts_with("Loop time of")) {
        let w: Vec<&str> = l.split_whitespace().collect();
        let num = |k: usize| w.get(k).and_then(|s| s.parse::<f64>().ok());
        if let (Some(t), Some(s), Some(n)) = (num(3), num(8), num(11)) {
            secs += t;
            work += s * n;
        }
    }
    Ok((secs, work))
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        return Err(
            "usage: pour_compare DECK LIGGGHTS_DUMP [--log LOG] [--half-width W] [-var N V]…"
                .into(),
        );
    }
    let deck_path = PathBuf::from(&args[0]);
    let reference = PathBuf::from(&args[1]);
    let mut vars = Vec::new();
    let mut log = None;
    let mut w = 0.01;
    let mut k = 2;
    while k < args.len() {
        match args[k].as_str() {
            "-var" if k + 2 < args.len() => {
                vars.push((args[k + 1].clone(), args[k + 2].clone()));
                k += 3;
            }
            "--log" if k + 1 < args.len() => {
                log = Some(PathBuf::from(&args[k + 1]));
                k += 2;
            }
            "--half-width" if k + 1 < args.len() => {
                w = args[k + 1].parse()?;
                k += 2;
            }
            o => return Err(format!("unexpected argument `{o}`").into()),
        }
    }
    let opts = ReadOptions::default();
    let lig = read_snapshot(&reference, &opts, Selection::Last)?;
    let deck = liggghts_deck::Deck::read_with_vars(&deck_path, &vars)?;
    let dir = tempfile::tempdir()?;
    let t0 = Instant::now();
    let sim = dem::Simulation::from_deck(&deck, dir.path())?;
    let secs = t0.elapsed().as_secs_f64();
    for warning in sim.warnings() {
        println!("warning: {warning}");
    }
    let name = reference
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or("bad reference name")?;
    println!(
        "reference {name}: step {}, {} particles",
        lig.timestep,
        lig.len()
    );
    let native_dump = std::fs::read_dir(dir.path().join("post"))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| {
            read_snapshot(p, &opts, Selection::Last).is_ok_and(|s| s.timestep == lig.timestep)
        })
        .ok_or("the native run wrote no dump of the reference's step")?;
    let nat = read_snapshot(&native_dump, &opts, Selection::Last)?;
    let bed_of = |s: &dem_io::Snapshot| -> Result<bed::Bed, dem_io::DumpError> {
        Ok(bed::measure(&s.positions()?, &s.radii()?, w))
    };
    let b_lig = bed_of(&lig)?;
    let b_nat = bed_of(&nat)?;
    println!("LIGGGHTS: {b_lig:?}");
    println!("native:   {b_nat:?}");
    let [top, phi, slab, h] = bed::relative(&b_nat, &b_lig);
    println!(
        "native vs LIGGGHTS: top {:+.2} %, core solid fraction {:+.2} %, slab solid fraction \
         {:+.2} %, packed height {:+.2} %",
        100.0 * top,
        100.0 * phi,
        100.0 * slab,
        100.0 * h
    );
    let steps = sim.step() as f64;
    let per = secs / (steps * sim.particles.len() as f64);
    println!(
        "native: {} steps, {} particles, {:.2} s wall ({} threads): {:.3} µs per particle-step",
        sim.step(),
        sim.particles.len(),
        secs,
        rayon::current_num_threads(),
        per * 1e6
    );
    if let Some(log) = log {
        let (t, work) = liggghts_loop_time(&log)?;
        println!(
            "LIGGGHTS: {t:.2} s loop time (1 process): {:.3} µs per particle-step; native/LIGGGHTS = {:.2}",
            t / work * 1e6,
            per / (t / work)
        );
    }
    Ok(())
}
