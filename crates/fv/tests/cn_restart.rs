//! Restarts with OpenFOAM's `CrankNicolson 0.9` (`fv::cn_files`): the Re 100 cavity (20×20,
//! the fixture) run 0 → 0.1 s (20 steps of 0.005 s) with a write at 0.05 s, and continued from
//! that write.
//!
//! - pisoFoam restarted from its own 0.05 writes the uninterrupted run's 0.1 bit for bit (the
//!   reference behaviour; full tier);
//! - the native fluid restarted from its own 0.05 is the uninterrupted native run bit for bit;
//!   without the `ddt0` files it restarts with an Euler step and differs;
//! - the native fluid restarted from pisoFoam's 0.05 ends where pisoFoam ends, and pisoFoam
//!   restarted from the native 0.05 too (round-off, bound 1e-10 of the lid speed, as the
//!   uninterrupted comparison in `schemes.rs`; full tier);
//! - a restart directory with some of the files, or a file of the wrong size, is an error
//!   naming the file;
//! - after `hold` (`solveFlow off`) the fluid continues as a run started from the held state.

use foam::{FieldValues, VolField};
use std::path::Path;

fn edit(path: &Path, from: &str, to: &str) {
    let s = std::fs::read_to_string(path).unwrap();
    assert!(s.contains(from), "{}: `{from}` not found", path.display());
    std::fs::write(path, s.replacen(from, to, 1)).unwrap();
}

/// The cavity fixture as a pisoFoam case with `CrankNicolson 0.9`, 0 → 0.1 s, writing at
/// 0.05 and 0.1.
fn make_case(dir: &Path) {
    testkit::copy_dir(&testkit::fixture("fv/cavity-re100"), dir);
    std::fs::remove_dir_all(dir.join("0.5")).unwrap();
    let _ = std::fs::remove_file(dir.join("log.icoFoam"));
    let cd = dir.join("system/controlDict");
    edit(&cd, "endTime         0.5;", "endTime 0.1;");
    edit(&cd, "writeInterval   100;", "writeInterval 10;");
    edit(
        &dir.join("constant/transportProperties"),
        "nu              0.001;",
        "transportModel Newtonian;\nnu 0.001;",
    );
    std::fs::write(
        dir.join("constant/turbulenceProperties"),
        "FoamFile { version 2.0; format ascii; class dictionary; object turbulenceProperties; }\nsimulationType laminar;\n",
    )
    .unwrap();
    let sch = dir.join("system/fvSchemes");
    edit(&sch, "default         Euler;", "default CrankNicolson 0.9;");
    edit(
        &sch,
        "div(phi,U)      Gauss linear;",
        "div(phi,U) Gauss linear;\n    div((nuEff*dev2(T(grad(U))))) Gauss linear;",
    );
}

/// `dir` made to start at 0.05 s, without its 0.1 s.
fn restart_from_half(dir: &Path) {
    let _ = std::fs::remove_dir_all(dir.join("0.1"));
    edit(
        &dir.join("system/controlDict"),
        "startTime       0;",
        "startTime 0.05;",
    );
}

fn u_at(dir: &Path, time: &str, n: usize) -> Vec<[f64; 3]> {
    match VolField::read(&dir.join(time).join("U"))
        .unwrap()
        .internal(n)
        .unwrap()
    {
        FieldValues::Vector(v) => v,
        FieldValues::Scalar(_) => panic!("vector field expected"),
    }
}

fn max_diff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| (x[k] - y[k]).abs()))
        .fold(0.0, f64::max)
}

const N: usize = 400;

fn run_native(dir: &Path) {
    fv::Fluid::from_case(dir).unwrap().run().unwrap();
}

#[test]
fn the_native_fluid_restarts_crank_nicolson_from_its_own_files_exactly() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    make_case(&full);
    run_native(&full);
    for f in [
        "ddt0(U)",
        "ddtCorrDdt0(U)",
        "ddtCorrDdt0(phi)",
        "U_0",
        "phi_0",
    ] {
        assert!(full.join("0.05").join(f).is_file(), "{f} not written");
    }
    let reference = u_at(&full, "0.1", N);
    let restarted = tmp.path().join("restarted");
    testkit::copy_dir(&full, &restarted);
    restart_from_half(&restarted);
    let euler = tmp.path().join("euler");
    testkit::copy_dir(&restarted, &euler);
    run_native(&restarted);
    let d = max_diff(&u_at(&restarted, "0.1", N), &reference);
    for f in ["p", "phi", "ddt0(U)", "ddtCorrDdt0(phi)"] {
        let a = std::fs::read(restarted.join("0.1").join(f)).unwrap();
        let b = std::fs::read(full.join("0.1").join(f)).unwrap();
        assert!(a == b, "{f} differs from the uninterrupted run's");
    }
    // without the scheme's files: an Euler step, as OpenFOAM restarts then
    for f in ["ddt0(U)", "ddtCorrDdt0(U)", "ddtCorrDdt0(phi)"] {
        std::fs::remove_file(euler.join("0.05").join(f)).unwrap();
    }
    run_native(&euler);
    let d_euler = max_diff(&u_at(&euler, "0.1", N), &reference);
    eprintln!(
        "native restart vs uninterrupted: max|ΔU| {d:e}; restarted without ddt0: {d_euler:.2e}"
    );
    assert_eq!(d, 0.0);
    assert!(d_euler > 1e-8, "{d_euler:e}");
}

#[test]
fn incomplete_or_mismatched_restart_files_are_errors_naming_them() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    make_case(&full);
    run_native(&full);
    restart_from_half(&full);
    let expect_err = |name: &str, prepare: &dyn Fn(&Path), needle: &str| {
        let case = tmp.path().join(name);
        testkit::copy_dir(&full, &case);
        prepare(&case.join("0.05"));
        let err = fv::Fluid::from_case(&case)
            .err()
            .expect("an error")
            .to_string();
        assert!(err.contains(needle), "{name}: {err}");
    };
    expect_err(
        "no-U0",
        &|d| std::fs::remove_file(d.join("U_0")).unwrap(),
        "U_0",
    );
    expect_err(
        "no-corr",
        &|d| std::fs::remove_file(d.join("ddtCorrDdt0(phi)")).unwrap(),
        "ddtCorrDdt0(phi)",
    );
    expect_err(
        "short",
        &|d| {
            let p = d.join("ddt0(U)");
            let s = std::fs::read_to_string(&p).unwrap();
            let (i, j) = (
                s.find("internalField").unwrap(),
                s.find("boundaryField").unwrap(),
            );
            let short = "internalField nonuniform List<vector> 2((0 0 0) (0 0 0));\n";
            std::fs::write(&p, format!("{}{short}{}", &s[..i], &s[j..])).unwrap();
        },
        "ddt0(U)",
    );
}

#[test]
fn after_a_hold_the_fluid_continues_as_a_run_started_from_the_held_state() {
    let tmp = tempfile::tempdir().unwrap();
    let case = tmp.path().join("held");
    make_case(&case);
    let dt = 0.005;
    let mut a = fv::Fluid::from_case(&case).unwrap();
    for _ in 0..5 {
        a.advance(dt).unwrap();
    }
    a.hold(dt);
    a.write("0.03").unwrap();
    // nothing of the scheme is written after a hold: a run from here starts it afresh
    assert!(!case.join("0.03/ddt0(U)").exists());
    for _ in 0..5 {
        a.advance(dt).unwrap();
    }
    edit(
        &case.join("system/controlDict"),
        "startTime       0;",
        "startTime 0.03;",
    );
    let mut b = fv::Fluid::from_case(&case).unwrap();
    for _ in 0..5 {
        b.advance(dt).unwrap();
    }
    let (ua, ub) = (mesh::v3::to_arrays(a.u()), mesh::v3::to_arrays(b.u()));
    assert_eq!(max_diff(&ua, &ub), 0.0);
}

/// pisoFoam's own restart (the reference), and both directions between pisoFoam and the
/// native fluid.
#[test]
fn restarts_between_pisofoam_and_the_native_fluid() {
    if !testkit::tool("pisoFoam") {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let of = tmp.path().join("pisoFoam");
    make_case(&of);
    testkit::run_ok(testkit::openfoam("pisoFoam"), &of);
    let reference = u_at(&of, "0.1", N);
    // (a) pisoFoam from its own 0.05
    let of_rs = tmp.path().join("pisoFoam-restarted");
    testkit::copy_dir(&of, &of_rs);
    restart_from_half(&of_rs);
    testkit::run_ok(testkit::openfoam("pisoFoam"), &of_rs);
    let d_of = max_diff(&u_at(&of_rs, "0.1", N), &reference);
    // (c) the native fluid from pisoFoam's 0.05
    let ours = tmp.path().join("native-from-pisoFoam");
    testkit::copy_dir(&of, &ours);
    restart_from_half(&ours);
    run_native(&ours);
    let d_ours = max_diff(&u_at(&ours, "0.1", N), &reference);
    // pisoFoam from the native 0.05
    let native = tmp.path().join("native");
    make_case(&native);
    run_native(&native);
    restart_from_half(&native);
    testkit::run_ok(testkit::openfoam("pisoFoam"), &native);
    let d_theirs = max_diff(&u_at(&native, "0.1", N), &reference);
    eprintln!(
        "max|ΔU|/U_lid at 0.1 vs pisoFoam uninterrupted: pisoFoam restarted {d_of:e}, native from pisoFoam's 0.05 {d_ours:.2e}, pisoFoam from the native 0.05 {d_theirs:.2e}"
    );
    assert_eq!(d_of, 0.0);
    assert!(
        d_ours < 1e-10 && d_theirs < 1e-10,
        "{d_ours:e} {d_theirs:e}"
    );
}
