//! Time directories written by the native solver (`U`, `p` and the face fluxes `phi`) restart
//! a run — ours or OpenFOAM's — exactly where it stopped: the Re 100 cavity (20×20) run to
//! t = 0.25 s, written, and continued to 0.5 s from the files matches icoFoam's uninterrupted
//! run (the fixture `tests/fixtures/fv/cavity-re100/0.5`) to round-off. Without `phi` the
//! restart recomputes the fluxes from U (the Rhie–Chow part is lost) and drifts away.

use foam::{FieldValues, VolField};
use mesh::v3::V3;
use std::path::Path;

fn read_u(path: &Path, n: usize) -> Vec<V3> {
    match VolField::read(path).unwrap().internal(n).unwrap() {
        FieldValues::Vector(v) => mesh::v3::from_arrays(&v),
        FieldValues::Scalar(_) => panic!("vector field expected"),
    }
}

fn max_diff(a: &[V3], b: &[V3]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(a, b)| (0..3).map(move |k| (a[k] - b[k]).abs()))
        .fold(0.0, f64::max)
}

fn edit(path: &Path, from: &str, to: &str) {
    let s = std::fs::read_to_string(path).unwrap();
    assert!(s.contains(from), "{}: `{from}` not found", path.display());
    std::fs::write(path, s.replacen(from, to, 1)).unwrap();
}

/// The cavity run by the native solver to 0.25 s (written there), in `dir`.
fn first_half(dir: &Path) {
    testkit::copy_dir(&testkit::fixture("fv/cavity-re100"), dir);
    std::fs::remove_dir_all(dir.join("0.5")).unwrap();
    edit(
        &dir.join("system/controlDict"),
        "endTime         0.5;",
        "endTime 0.25;",
    );
    let mut fluid = fv::Fluid::from_case(dir).unwrap();
    assert_eq!(fluid.run().unwrap(), 50);
    // What was written is what the solver holds.
    let phi = fv::fields::read_phi(&dir.join("0.25/phi"), fluid.geometry()).unwrap();
    assert_eq!(phi, fluid.phi());
    edit(
        &dir.join("system/controlDict"),
        "endTime 0.25;",
        "endTime 0.5;",
    );
    edit(
        &dir.join("system/controlDict"),
        "startTime       0;",
        "startTime 0.25;",
    );
}

#[test]
fn the_native_solver_restarts_from_its_own_files_exactly() {
    let reference = testkit::fixture("fv/cavity-re100/0.5/U");
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first");
    first_half(&first);
    let mut diffs = Vec::new();
    for keep_phi in [true, false] {
        let case = dir.path().join(format!("restart-{keep_phi}"));
        testkit::copy_dir(&first, &case);
        if !keep_phi {
            std::fs::remove_file(case.join("0.25/phi")).unwrap();
        }
        let mut fluid = fv::Fluid::from_case(&case).unwrap();
        assert_eq!(fluid.run().unwrap(), 50);
        let n = fluid.geometry().n_cells;
        diffs.push(max_diff(fluid.u(), &read_u(&reference, n)));
    }
    eprintln!(
        "cavity restarted at 0.25 s vs icoFoam's uninterrupted run at 0.5 s: max |ΔU|/U_lid = {:.3e} with phi, {:.3e} without",
        diffs[0], diffs[1]
    );
    assert!(diffs[0] < 1e-12, "{diffs:?}");
    assert!(diffs[1] > 1e3 * diffs[0].max(1e-16), "{diffs:?}");
}

/// Full tier: icoFoam continues from the native solver's 0.25 s files (reading its `phi`) and
/// reaches its own uninterrupted result.
#[test]
fn icofoam_restarts_from_the_native_solvers_files() {
    if !testkit::tool("icoFoam") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    first_half(dir.path());
    // OpenFOAM counts write intervals from its restart (no `uniform/time` here).
    edit(
        &dir.path().join("system/controlDict"),
        "writeInterval   100;",
        "writeInterval 50;",
    );
    let log = testkit::run_ok(testkit::openfoam("icoFoam"), dir.path());
    assert!(
        dir.path().join("0.5/U").is_file(),
        "icoFoam wrote no 0.5:\n{log}"
    );
    let n = 400;
    let theirs = read_u(&dir.path().join("0.5/U"), n);
    let reference = read_u(&testkit::fixture("fv/cavity-re100/0.5/U"), n);
    let d = max_diff(&theirs, &reference);
    eprintln!("icoFoam restarted from fv's 0.25 s files: max |ΔU|/U_lid = {d:.3e}");
    assert!(d < 1e-12, "{d}");
}
