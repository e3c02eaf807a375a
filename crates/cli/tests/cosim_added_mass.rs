//! Full tier: added mass and lift in a co-simulation, grainPisoFoam with LIGGGHTS in-process
//! (issue 28, item 1). The settling tutorial with `virtualMassForce` (CFDEM-PFM's unsplit form,
//! which needs only U from the fluid) runs to its end and passes its settling checks; with
//! `MeiLift` the run is refused before grainPisoFoam is spawned, with a message saying that
//! grainPisoFoam does not send the vorticity. Needs the cargo features `mpi` and `liggghts`,
//! OpenMPI, Debian's LIGGGHTS and grainPisoFoam (`openfoam-cases/solver/build.sh`).

#![cfg(all(feature = "mpi", feature = "liggghts"))]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

fn run(case: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foamgrain"))
        .arg("run")
        .arg(case)
        .args(["--fluid", "openfoam", "--dem", "liggghts"])
        .env(
            "WM_PROJECT_DIR",
            std::env::var("WM_PROJECT_DIR").unwrap_or_else(|_| "/usr/share/openfoam".into()),
        )
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
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

#[test]
fn mei_lift_on_grainpisofoam_is_refused_before_the_spawn() {
    if !common::cosim_ready(&["mpirun", "liggghts"]) {
        return;
    }
    let (_dir, case) = settling("    MeiLift", "MeiLiftProps\n{\n    velFieldName \"U\";\n}");
    let out = run(&case);
    let log = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(
        log.contains("grainPisoFoam does not send") && log.contains("vorticity"),
        "{log}"
    );
}
