//! Full tier: grainPisoFoam's advance overlapped with the next DEM interval (the default of
//! `foamgrain run --fluid openfoam`) gives the same outputs, byte for byte, as the sequential
//! order (`--no-overlap`): `postProcessing/integrals.csv`, the particle files and their series,
//! `validation.json`, and every file of the time directories grainPisoFoam writes.
//!
//! Cases: `settling` to t = 0.06 s (60 coupling steps, a write time at step 50 in the middle of
//! overlapped steps, one at the last step), and `ergun` with a small native pack (300 particles)
//! to t = 0.005 s (10 steps; Δp and the inflow from the solver's patch sums in every row).
//! Needs the cargo feature `mpi`, OpenMPI and grainPisoFoam (`openfoam-cases/solver/build.sh`).

#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

/// Runs `foamgrain run CASE ARGS…` with Debian's OpenFOAM environment; panics with its output
/// when it fails for another reason than its checks.
fn run(case: &Path, args: &[&str]) {
    let out = common::cosim_env(
        Command::new(env!("CARGO_BIN_EXE_foamgrain"))
            .arg("run")
            .arg(case)
            .args(["--fluid", "openfoam", "--dem", "native"])
            .args(args),
    )
    .output()
    .unwrap();
    let log = String::from_utf8_lossy(&out.stderr);
    // a short Ergun run ends before its plateaus: its checks fail (exit 2, and they are
    // compared below); an error (exit 1) must not happen
    assert!(
        out.status.success() || out.status.code() == Some(2),
        "foamgrain run {} {args:?} failed:\n{}\n{log}",
        case.display(),
        String::from_utf8_lossy(&out.stdout)
    );
    let overlapped = log.contains("overlap: the fluid's advance runs during the next DEM");
    assert_eq!(
        overlapped,
        !args.contains(&"--no-overlap"),
        "{args:?}: the run's log does not say the expected order:\n{log}"
    );
}

/// The files a run wrote that must not depend on the order: relative path → bytes.
fn outputs(case: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    let post = case.join("postProcessing");
    for rel in ["integrals.csv", "validation.json"] {
        let p = post.join(rel);
        if p.is_file() {
            files.push((PathBuf::from("postProcessing").join(rel), read(&p)));
        }
    }
    collect(case, &post.join("particles"), &mut files);
    for e in std::fs::read_dir(case.join("CFD")).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        if name.parse::<f64>().is_ok_and(|t| t > 0.0) {
            collect(case, &e.path(), &mut files);
        }
    }
    files.sort();
    files
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn collect(root: &Path, dir: &Path, out: &mut Vec<(PathBuf, Vec<u8>)>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries {
        let p = e.unwrap().path();
        if p.is_dir() {
            collect(root, &p, out);
        } else {
            out.push((p.strip_prefix(root).unwrap().to_owned(), read(&p)));
        }
    }
}

/// Runs `case` (a reference case) overlapped and sequentially with `args` and compares.
fn same_both_ways(case: &str, args: &[&str], init: Option<&Path>) {
    let dir = tempfile::tempdir().unwrap();
    let [a, b] = ["overlap", "sequential"].map(|n| dir.path().join(n));
    for c in [&a, &b] {
        testkit::copy_inputs(&testkit::repo_root().join("openfoam-cases").join(case), c);
    }
    let mut seq_args = args.to_vec();
    seq_args.push("--no-overlap");
    run(&a, args);
    if let Some(packed) = init {
        // both runs start from the same pack (stage 1 ran in the first only)
        std::fs::create_dir_all(b.join(packed).parent().unwrap()).unwrap();
        std::fs::copy(a.join(packed), b.join(packed)).unwrap();
    }
    run(&b, &seq_args);
    let (got, want) = (outputs(&a), outputs(&b));
    let names = |v: &[(PathBuf, Vec<u8>)]| v.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
    assert_eq!(
        names(&got),
        names(&want),
        "{case}: the runs wrote different files"
    );
    assert!(
        got.iter()
            .any(|f| f.0.ends_with("integrals.csv") && !f.1.is_empty()),
        "{case}: no integrals.csv"
    );
    assert!(
        got.iter().any(|f| f.0.starts_with("CFD")),
        "{case}: no time directory"
    );
    for ((name, x), (_, y)) in got.iter().zip(&want) {
        assert!(
            x == y,
            "{case}: {} differs between the overlapped and the sequential run",
            name.display()
        );
    }
}

#[test]
fn settling_overlapped_equals_sequential() {
    if common::cosim_ready(&["mpirun"]) {
        same_both_ways("settling", &["--end-time", "0.06"], None);
    }
}

#[test]
fn ergun_overlapped_equals_sequential() {
    if common::cosim_ready(&["mpirun"]) {
        same_both_ways(
            "ergun",
            &[
                "--end-time",
                "0.005",
                "--var",
                "np=300",
                "--var",
                "tsettle=1500",
            ],
            Some(Path::new("DEM/post/packed.data")),
        );
    }
}
