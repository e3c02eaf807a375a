//! The Ergun bed with frozen coupling fields: grainPisoFoam and the native solver (`fv`, with
//! and without `harmonic_faces`) run to steady state on the same ε, Ksl, Us, f, and their
//! pressure drops are compared with the Darcy drop of those fields
//! (`foam_solver_tests::darcy`).
//!
//! ```sh
//! cargo run -p foam-solver-tests --example frozen_ergun -- [FIELDS_DIR] [STEPS]
//! ```
//!
//! FIELDS_DIR holds `voidfraction Ksl Us f` (and optionally `U p`) on the mesh of
//! `openfoam-cases/ergun/CFD` (default: the committed `fixtures/ergun-bed`); STEPS (default 80)
//! steps of the case's Δt = 5e-4 s are run with the inlet held at 0.002 m/s. grainPisoFoam
//! runs only when OpenFOAM is installed.

#[path = "common/native.rs"]
mod native;

use foam_solver_tests::frozen_bed::{self, FrozenBed, RHO};
use foam_solver_tests::grain_piso_foam;
use std::path::PathBuf;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let src = args.first().map_or_else(frozen_bed::fixture, PathBuf::from);
    let steps: usize = args.get(1).map_or(80, |s| s.parse().expect("STEPS"));
    let frozen = FrozenBed::new(&src, steps);
    let reference = frozen.reference();
    let uniform = RHO * reference.uniform_flux;
    println!(
        "Darcy drop of the frozen fields (Pa): rows at uniform pressure {:.4} (lower bound), \
         columns without cross-flow {:.4} (upper bound), uniform flux {uniform:.4}; \
         max|Us| = {:.2e} m/s",
        RHO * reference.lower,
        RHO * reference.upper,
        frozen
            .us
            .iter()
            .map(|v| v.iter().map(|x| x * x).sum::<f64>().sqrt())
            .fold(0.0, f64::max),
    );
    println!(
        "per-row uniform-flux drop (Pa): {:.3?}",
        frozen.bed.row_drops(frozen_bed::U_IN, RHO)
    );
    let report = |who: &str, history: &[f64], p: &[f64]| {
        let dp = *history.last().unwrap();
        println!(
            "{who}: Δp = {dp:.4} Pa ({:+.2} % of uniform flux), history {history:.4?}",
            100.0 * (dp / uniform - 1.0)
        );
        let rows: Vec<f64> = frozen.bed.row_means(p).iter().map(|x| RHO * x).collect();
        println!("  row means ρp (Pa): {rows:.3?}");
    };

    for harmonic in [false, true] {
        let (history, p) =
            native::run_native(&frozen, steps, harmonic, fv::PorousTimeFlux::Consistent);
        report(&format!("native harmonic_faces={harmonic}"), &history, &p);
    }

    if let Some(solver) = grain_piso_foam() {
        let (history, p) = frozen.run_grain_piso_foam(&solver);
        report("grainPisoFoam", &history, &p);
    }
}
