//! Issue 17: the steady pressure drop of the frozen Ergun bed (`fixtures/ergun-bed`, inlet
//! held at 0.002 m/s) at Δt = 1e-4, 2.5e-4, 5e-4, 1e-3 s, before and after the
//! time-step-independent face flux, side by side:
//!
//! * `fv` with `harmonic_faces` and `PorousTimeFlux::DdtCorr` (before) / `Consistent` (after);
//! * grainPisoFoam as built from this tree (after) and, when given, an older binary (before:
//!   build main's `openfoam-cases/solver` with another `FOAMGRAIN_CACHE`).
//!
//! ```sh
//! cargo run --release -p foam-solver-tests --example dt_sweep -- [TIME] [OLD_GRAINPISOFOAM]
//! ```
//!
//! TIME (s, default 0.06) is simulated at every Δt from U = 0; Δp is the inlet's area-mean
//! ρp minus the outlet's (Pa); "change" is the relative change over the last quarter of the
//! run. The Darcy bounds of the frozen fields are printed first. grainPisoFoam runs only
//! when OpenFOAM is installed.

#[path = "common/native.rs"]
mod native;

use foam_solver_tests::frozen_bed::{self, FrozenBed, RHO};
use foam_solver_tests::grain_piso_foam;
use std::path::PathBuf;

const TIME_STEPS: [f64; 4] = [1e-4, 2.5e-4, 5e-4, 1e-3];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let time: f64 = args.first().map_or(0.06, |s| s.parse().expect("TIME (s)"));
    let old_solver = args.get(1).map(PathBuf::from);
    let solver = grain_piso_foam();
    let reference = FrozenBed::new(&frozen_bed::fixture(), 4).reference();
    println!(
        "frozen Ergun bed, {time} s simulated per run; Darcy bounds [{:.4}, {:.4}] Pa",
        RHO * reference.lower,
        RHO * reference.upper
    );
    let mut columns = vec!["fv ddtCorr (before)", "fv consistent (after)"];
    if old_solver.is_some() {
        columns.push("grainPisoFoam before");
    }
    if solver.is_some() {
        columns.push("grainPisoFoam after");
    }
    println!("Δt (s)  | {}", columns.join(" | "));
    let mut table: Vec<Vec<f64>> = Vec::new();
    for dt in TIME_STEPS {
        let steps = (time / dt).round() as usize;
        let frozen = FrozenBed::with_time_step(&frozen_bed::fixture(), steps, dt);
        let mut row = Vec::new();
        let mut cells = Vec::new();
        let mut push = |history: &[f64]| {
            let dp = *history.last().unwrap();
            let change = (history[3] - history[2]) / dp;
            row.push(dp);
            cells.push(format!("{dp:.4} Pa (change {change:.0e})"));
        };
        for time_flux in [fv::PorousTimeFlux::DdtCorr, fv::PorousTimeFlux::Consistent] {
            push(&native::run_native(&frozen, steps, true, time_flux).0);
        }
        for s in old_solver.iter().chain(solver.iter()) {
            push(&frozen.run_grain_piso_foam(s).0);
        }
        println!("{dt:.1e} | {}", cells.join(" | "));
        table.push(row);
    }
    let spread: Vec<String> = (0..columns.len())
        .map(|k| {
            let v: Vec<f64> = table.iter().map(|r| r[k]).collect();
            let max = v.iter().copied().fold(f64::MIN, f64::max);
            let min = v.iter().copied().fold(f64::MAX, f64::min);
            format!(
                "{:.3} %",
                100.0 * (max - min) / (v.iter().sum::<f64>() / v.len() as f64)
            )
        })
        .collect();
    println!("spread  | {}", spread.join(" | "));
}
