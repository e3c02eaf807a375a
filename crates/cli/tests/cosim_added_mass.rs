//! Full tier: added mass and lift in a co-simulation, grainPisoFoam with LIGGGHTS in-process
//! (issue 28, item 1). The settling tutorial with `virtualMassForce` (CFDEM-PFM's unsplit form,
//! which needs only U from the fluid) runs to its end and passes its settling checks; with
//! `MeiLift` and the split `virtualMassForce` (which need ∇ × U and DU/Dt, sent by
//! grainPisoFoam when the coupler asks) the co-simulation runs and its settling history equals
//! the native stack's (native fluid and DEM) on the same case within 1 % of the terminal
//! speed. Needs the cargo features `mpi` and `liggghts`, OpenMPI, Debian's LIGGGHTS and
//! grainPisoFoam (`openfoam-cases/solver/build.sh`; `FOAMGRAIN_SOLVER` names another build).

#![cfg(all(feature = "mpi", feature = "liggghts"))]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

fn run(case: &Path) -> Output {
    run_on(case, "openfoam", "liggghts")
}

fn run_on(case: &Path, fluid: &str, dem: &str) -> Output {
    common::cosim_env(
        Command::new(env!("CARGO_BIN_EXE_foamgrain"))
            .arg("run")
            .arg(case)
            .args(["--fluid", fluid, "--dem", dem]),
    )
    .output()
    .unwrap()
}

/// The settling case with `models` added to `forceModels` and `props` after the list.
fn settling(models: &str, props: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("settling");
    testkit::copy_inputs(&testkit::repo_root().join("openfoam-cases/settling"), &case);
    let file = case.join("CFD/constant/couplingProperties");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("    Archimedes\n);"));
    let text = text.replace(
        "    Archimedes\n);",
        &format!("    Archimedes\n{models}\n);\n{props}\n"),
    );
    std::fs::write(&file, text).unwrap();
    (dir, case)
}

#[test]
fn settling_with_added_mass_on_grainpisofoam_and_liggghts() {
    if !common::cosim_ready(&["mpirun", "liggghts"]) {
        return;
    }
    let (_dir, case) = settling(
        "    virtualMassForce",
        "virtualMassForceProps\n{\n    velFieldName \"U\";\n    phiFieldName \"phi\";\n    \
         splitUrelCalculation false;\n    Cadd 0.5;\n}",
    );
    let out = run(&case);
    let log = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "exit {:?}:\n{stdout}\n{log}",
        out.status
    );
    let json = std::fs::read_to_string(case.join("postProcessing/validation.json")).unwrap();
    eprintln!("{json}");
    assert!(json.contains("settling speed"), "{json}");
}

/// (time, first particle's axial velocity) of every row of `postProcessing/integrals.csv`.
fn settling_history(case: &Path) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(case.join("postProcessing/integrals.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "first_axial_velocity")
        .unwrap();
    lines
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            (v[0], v[col])
        })
        .collect()
}

/// `MeiLift` (CFDEM's documented props) and the split `virtualMassForce` on grainPisoFoam and
/// LIGGGHTS against the native stack on the same case: the settling histories agree within 1 %
/// of the terminal speed at every coupling step (the two stacks' own difference: different
/// DEMs and fluid solvers; the lift's and added mass's fields come from each fluid).
#[test]
fn mei_lift_and_split_added_mass_on_grainpisofoam_match_the_native_stack() {
    if !common::cosim_ready(&["mpirun", "liggghts"]) {
        return;
    }
    let models = "    virtualMassForce\n    MeiLift";
    let props =
        "virtualMassForceProps\n{\n    velFieldName \"U\";\n    phiFieldName \"phi\";\n    \
                 splitUrelCalculation true;\n    Cadd 0.5;\n}\nMeiLiftProps\n{\n    \
                 velFieldName \"U\";\n    useSecondOrderTerms;\n    interpolation true;\n}";
    let (_cosim_dir, cosim) = settling(models, props);
    let (_native_dir, native) = settling(models, props);
    let out = run(&cosim);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "co-simulation exit {:?}:\n{log}",
        out.status
    );
    let out = run_on(&native, "native", "native");
    assert!(
        out.status.success(),
        "native exit {:?}:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    let (a, b) = (settling_history(&cosim), settling_history(&native));
    assert_eq!(a.len(), b.len());
    assert!(a.len() >= 200, "{} rows", a.len());
    let terminal = b.last().unwrap().1.abs();
    let mut worst = (0.0, 0.0);
    for ((ta, va), (tb, vb)) in a.iter().zip(&b) {
        assert!((ta - tb).abs() < 1e-9, "times {ta} {tb}");
        let d = (va - vb).abs() / terminal;
        if d > worst.1 {
            worst = (*ta, d);
        }
    }
    eprintln!(
        "MeiLift + split virtualMassForce: terminal {:.5} (co-simulation) vs {:.5} m/s \
         (native); largest difference {:.2e} of it at t = {} s",
        a.last().unwrap().1.abs(),
        terminal,
        worst.1,
        worst.0
    );
    assert!(
        worst.1 < 0.01,
        "largest difference {:e} at t = {}",
        worst.1,
        worst.0
    );
    let json = std::fs::read_to_string(cosim.join("postProcessing/validation.json")).unwrap();
    assert!(json.contains("settling speed"), "{json}");
}
