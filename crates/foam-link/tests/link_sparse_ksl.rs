//! CFDEM's Ksl form over the sparse exchange (issue 28; full tier): 2 coupler ranks × 2
//! grainPisoFoam ranks on the porous cavity (`examples/sparse_ksl.rs` under `mpirun -np 2`)
//! give the ranks' Σ w F, Σ w and Σ w v per cell; the solver ranks' Ksl and Us (read back with
//! the whole state after each of two intervals) equal what the coupler forms itself from the
//! same sums added in rank order (`couple::ksl::form_cfdem`, the dense path with the fluid on
//! rank 0), cell for cell, to round-off — including the cells where KslLimit caps Ksl, and
//! with the conserving Σ Ksl of the records ignored.

mod common;
use common::*;
use foam_solver_tests::TestCase;
use std::process::Command;

#[test]
fn solver_ranks_form_cfdem_ksl_as_the_coupler_does() {
    let Some(solver) = tools() else {
        return;
    };
    let exe = std::env::current_exe().unwrap();
    let example = exe.ancestors().nth(2).unwrap().join("examples/sparse_ksl");
    assert!(example.is_file(), "{} not built", example.display());
    let case = TestCase::new("cavity");
    let copy = case.duplicate();
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("sparse.txt");
    let out = Command::new("mpirun")
        .args(["-np", "2", "--oversubscribe"])
        .arg(&example)
        .arg(&copy.dir)
        .arg(&solver)
        .arg(&out_path)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&out_path).unwrap();
    let (mut cells, mut capped, mut worst_k, mut worst_u) = (0, 0, 0.0f64, 0.0f64);
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let x: Vec<f64> = w[3..].iter().map(|s| s.parse().unwrap()).collect();
        match w[0] {
            "ksl" => {
                cells += 1;
                let (solver, rust) = (x[0], x[1]);
                assert!(rust > 0.0, "{line}");
                if rust == 1000.0 {
                    capped += 1;
                }
                worst_k = worst_k.max((solver - rust).abs() / rust);
            }
            "us" => {
                for a in 0..3 {
                    worst_u = worst_u.max((x[a] - x[a + 3]).abs());
                }
            }
            other => panic!("unexpected line {other}"),
        }
    }
    eprintln!(
        "CFDEM Ksl, 2 coupler × 2 solver ranks: {cells} cell-intervals, {capped} capped; \
         max |ΔKsl|/Ksl {worst_k:.2e}, max |ΔUs| {worst_u:.2e} m/s"
    );
    assert!(cells > 20, "{cells}");
    assert!(capped > 0 && capped < cells, "{capped} of {cells} capped");
    assert!(worst_k <= 1e-12, "{worst_k:e}");
    assert!(worst_u <= 1e-15, "{worst_u:e}");
}
