//! The convection schemes and linear solvers CFDEMcoupling's tutorials name, against Debian's
//! pisoFoam v1912 (full tier): a lid-driven cavity at Re 1000 on a skewed, graded 20×20 mesh
//! (so the limiters act, the face weights are not ½ and the non-orthogonal correction is on),
//! run for 40 steps at Courant number ≈ 0.5 by pisoFoam (laminar) and by the native fluid with
//! the same fvSchemes and fvSolution; U and p at the end are compared.
//!
//! With the same linear solvers (PCG/DIC for p, smoothSolver/symGaussSeidel for U) the native
//! face loops reproduce OpenFOAM's, so the fields agree to round-off: the bound is 1e-10 of
//! the lid speed and of max |p|, measured 4e-16 … 1.3e-15 (U) and 1.4e-15 … 7.4e-15 (p).
//!
//! Each scheme is also compared with pisoFoam's `Gauss linear` run: the difference must be far
//! above the agreement bound, so the test would notice a scheme silently run as another.

use foam::{FieldValues, VolField};
use std::path::{Path, PathBuf};

const STEPS: usize = 40;
const DT: f64 = 0.0025;

fn edit(path: &Path, from: &str, to: &str) {
    let s = std::fs::read_to_string(path).unwrap();
    assert!(s.contains(from), "{}: `{from}` not found", path.display());
    std::fs::write(path, s.replacen(from, to, 1)).unwrap();
}

/// The Re 100 cavity fixture made a pisoFoam (laminar) case at Re 1000 on a skewed, graded
/// mesh, with `div(phi,U)` = `div` and the entries of fvSolution's `solvers` = `solvers`.
fn make_case(dir: &Path, div: &str, solvers: &str) {
    testkit::copy_dir(&testkit::fixture("fv/cavity-re100"), dir);
    for d in ["0.5", "constant/polyMesh"] {
        std::fs::remove_dir_all(dir.join(d)).unwrap();
    }
    let _ = std::fs::remove_file(dir.join("log.icoFoam"));
    let bmd = dir.join("system/blockMeshDict");
    edit(&bmd, "(1 1 0)", "(1.2 1 0)");
    edit(&bmd, "(0 1 0)", "(0.2 1 0)");
    edit(&bmd, "(1 1 0.1)", "(1.2 1 0.1)");
    edit(&bmd, "(0 1 0.1)", "(0.2 1 0.1)");
    edit(&bmd, "simpleGrading (1 1 1)", "simpleGrading (2 0.5 1)");
    let cd = dir.join("system/controlDict");
    edit(&cd, "icoFoam", "pisoFoam");
    edit(
        &cd,
        "endTime         0.5;",
        &format!("endTime {};", DT * STEPS as f64),
    );
    edit(&cd, "deltaT          0.005;", &format!("deltaT {DT};"));
    edit(
        &cd,
        "writeInterval   100;",
        &format!("writeInterval {STEPS};"),
    );
    edit(
        &dir.join("constant/transportProperties"),
        "nu              0.001;",
        "transportModel Newtonian;\nnu 0.0001;",
    );
    std::fs::write(
        dir.join("constant/turbulenceProperties"),
        "FoamFile { version 2.0; format ascii; class dictionary; object turbulenceProperties; }\nsimulationType laminar;\n",
    )
    .unwrap();
    let sch = dir.join("system/fvSchemes");
    edit(
        &sch,
        "div(phi,U)      Gauss linear;",
        &format!("div(phi,U) {div};\n    div((nuEff*dev2(T(grad(U))))) Gauss linear;"),
    );
    edit(
        &sch,
        "default         Gauss linear orthogonal;",
        "default Gauss linear corrected;",
    );
    edit(&sch, "default         orthogonal;", "default corrected;");
    let sol = dir.join("system/fvSolution");
    let text = std::fs::read_to_string(&sol).unwrap();
    let start = text.find("solvers\n{").unwrap() + "solvers\n{".len();
    let end = text.find("PISO\n{").unwrap();
    let text = format!("{}\n{solvers}\n}}\n\n{}", &text[..start], &text[end..]);
    std::fs::write(&sol, text).unwrap();
    edit(
        &sol,
        "nNonOrthogonalCorrectors 0;",
        "nNonOrthogonalCorrectors 1;",
    );
    testkit::run_ok(testkit::openfoam("blockMesh"), dir);
}

/// The momentum solver of the icoFoam tutorial.
const U_GS: &str =
    "    U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-05; relTol 0; }";

const P_PCG: &str = "    p { solver PCG; preconditioner DIC; tolerance 1e-06; relTol 0.05; }
    pFinal { $p; relTol 0; }";

const P_GAMG: &str = "    p { solver GAMG; smoother GaussSeidel; tolerance 1e-08; relTol 0;
        cacheAgglomeration true; nCellsInCoarsestLevel 10; agglomerator faceAreaPair;
        mergeLevels 1; }
    pFinal { $p; relTol 0; }";

fn read_vectors(path: &Path, n: usize) -> Vec<[f64; 3]> {
    match VolField::read(path).unwrap().internal(n).unwrap() {
        FieldValues::Vector(v) => v,
        FieldValues::Scalar(_) => panic!("{}: vector field expected", path.display()),
    }
}

fn read_scalars(path: &Path, n: usize) -> Vec<f64> {
    match VolField::read(path).unwrap().internal(n).unwrap() {
        FieldValues::Scalar(v) => v,
        FieldValues::Vector(_) => panic!("{}: scalar field expected", path.display()),
    }
}

/// U and p of a case at the end time.
struct Fields {
    u: Vec<[f64; 3]>,
    p: Vec<f64>,
}

fn end_fields(dir: &Path, n: usize) -> Fields {
    let t = dir.join(format!("{}", DT * STEPS as f64));
    Fields {
        u: read_vectors(&t.join("U"), n),
        p: read_scalars(&t.join("p"), n),
    }
}

/// (max |ΔU| / U_lid, max |Δp| / max |p|).
fn difference(a: &Fields, b: &Fields) -> (f64, f64) {
    let du =
        a.u.iter()
            .zip(&b.u)
            .flat_map(|(x, y)| (0..3).map(move |k| (x[k] - y[k]).abs()))
            .fold(0.0, f64::max);
    let pmax = b.p.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let dp =
        a.p.iter()
            .zip(&b.p)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
    (du, dp / pmax)
}

/// Runs pisoFoam and the native fluid on copies of one case; returns both end fields.
fn run_both(root: &Path, name: &str, div: &str, solvers: &str) -> (Fields, Fields) {
    run_both_with_ddt(root, name, div, solvers, "Euler")
}

/// [`run_both`] with the time scheme `ddt` (`ddtSchemes default`).
fn run_both_with_ddt(
    root: &Path,
    name: &str,
    div: &str,
    solvers: &str,
    ddt: &str,
) -> (Fields, Fields) {
    let of: PathBuf = root.join(format!("{name}-pisoFoam"));
    let ours: PathBuf = root.join(format!("{name}-fv"));
    make_case(&of, div, solvers);
    if ddt != "Euler" {
        edit(
            &of.join("system/fvSchemes"),
            "default         Euler;",
            &format!("default {ddt};"),
        );
    }
    testkit::copy_dir(&of, &ours);
    testkit::run_ok(testkit::openfoam("pisoFoam"), &of);
    let mut fluid = fv::Fluid::from_case(&ours).unwrap_or_else(|e| panic!("{div}: {e}"));
    assert_eq!(fluid.run().unwrap(), STEPS);
    let n = fluid.geometry().n_cells;
    (end_fields(&of, n), end_fields(&ours, n))
}

#[test]
fn convection_schemes_match_pisofoam() {
    if !testkit::tool("pisoFoam") || !testkit::tool("blockMesh") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (linear, linear_fv) = run_both(
        dir.path(),
        "linear",
        "Gauss linear",
        &format!("{P_PCG}\n{U_GS}"),
    );
    let (du, dp) = difference(&linear_fv, &linear);
    eprintln!(
        "{:<34} max|ΔU|/U_lid {du:.2e}  max|Δp|/max|p| {dp:.2e}",
        "Gauss linear"
    );
    assert!(du < 1e-10 && dp < 1e-10, "Gauss linear: {du:e}, {dp:e}");
    let schemes = [
        "Gauss upwind",
        "bounded Gauss upwind",
        "Gauss limitedLinear 1",
        "Gauss limitedLinear 0.3",
        "Gauss limitedLinearV 1",
        "bounded Gauss limitedLinearV 1",
        "Gauss linearUpwind grad(U)",
        "Gauss linearUpwindV grad(U)",
    ];
    let mut failures = Vec::new();
    let mut results = Vec::new();
    for (i, div) in schemes.iter().enumerate() {
        let (theirs, ours) = run_both(
            dir.path(),
            &format!("s{i}"),
            div,
            &format!("{P_PCG}\n{U_GS}"),
        );
        let (du, dp) = difference(&ours, &theirs);
        let (su, sp) = difference(&theirs, &linear);
        eprintln!(
            "{div:<34} max|ΔU|/U_lid {du:.2e}  max|Δp|/max|p| {dp:.2e}   (vs Gauss linear: {su:.1e}, {sp:.1e})"
        );
        if !(du < 1e-10 && dp < 1e-10) {
            failures.push(format!("{div}: ΔU {du:e}, Δp {dp:e}"));
        }
        // The scheme changes the answer (by far more than the agreement bound).
        if su.is_nan() || su <= 1e-4 {
            failures.push(format!("{div}: same as Gauss linear ({su:e})"));
        }
        results.push(theirs);
    }
    // Variants that differ little still differ far above round-off in pisoFoam's results:
    // `bounded` removes (∇·φ)U with ∇·φ at the pressure tolerance, ψ moves the limiter.
    for (a, b) in [(0, 1), (2, 3), (4, 5)] {
        let (du, _) = difference(&results[a], &results[b]);
        eprintln!(
            "pisoFoam `{}` vs `{}`: max|ΔU|/U_lid {du:.1e}",
            schemes[a], schemes[b]
        );
        if du.is_nan() || du <= 1e-12 {
            failures.push(format!("{} and {} give the same U", schemes[a], schemes[b]));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// `GAMG` for p: the native fluid (CG preconditioned by its aggregation multigrid) and
/// pisoFoam (OpenFOAM's GAMG V-cycles) converge every pressure solve to the same tolerance
/// (1e-8, relTol 0) by different iterations, so they agree to that tolerance, not to
/// round-off (measured: max|ΔU|/U_lid 3.8e-10, max|Δp|/max|p| 3.1e-8; bound 1e-6). With a
/// relTol > 0 the intermediate correctors stop at different residuals and the answers differ
/// by more (1.7e-5 of max |p| with relTol 0.05).
#[test]
fn gamg_pressure_solver_matches_pisofoam_to_the_tolerance() {
    if !testkit::tool("pisoFoam") || !testkit::tool("blockMesh") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (theirs, ours) = run_both(
        dir.path(),
        "gamg",
        "Gauss limitedLinearV 1",
        &format!("{P_GAMG}\n{U_GS}"),
    );
    let (du, dp) = difference(&ours, &theirs);
    eprintln!("GAMG, Gauss limitedLinearV 1: max|ΔU|/U_lid {du:.2e}  max|Δp|/max|p| {dp:.2e}");
    assert!(du < 1e-6 && dp < 1e-6, "ΔU {du:e}, Δp {dp:e}");
}

/// The momentum solvers: `smoothSolver` with the Gauss–Seidel and incomplete-factor
/// smoothers, `PBiCGStab` and `PBiCG` (the tutorials' choice, with DILU) reproduce pisoFoam to
/// round-off (the same operations in the same order).
#[test]
fn momentum_solvers_match_pisofoam() {
    if !testkit::tool("pisoFoam") || !testkit::tool("blockMesh") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for (i, (u, bound)) in [
        ("smoother DILU; tolerance 1e-05", 1e-10),
        ("smoother DILUGaussSeidel; tolerance 1e-05", 1e-10),
        ("smoother GaussSeidel; nSweeps 2; tolerance 1e-05", 1e-10),
    ]
    .into_iter()
    .map(|(s, b)| (format!("solver smoothSolver; {s}; relTol 0;"), b))
    .chain([
        (
            "solver PBiCGStab; preconditioner DILU; tolerance 1e-05; relTol 0;".to_string(),
            1e-10,
        ),
        (
            "solver PBiCG; preconditioner DILU; tolerance 1e-05; relTol 0;".to_string(),
            1e-10,
        ),
    ])
    .enumerate()
    {
        let solvers = format!("{P_PCG}\n    U {{ {u} }}");
        let (theirs, ours) = run_both(
            dir.path(),
            &format!("u{i}"),
            "Gauss limitedLinearV 1",
            &solvers,
        );
        let (du, dp) = difference(&ours, &theirs);
        eprintln!("U {{ {u} }}: max|ΔU|/U_lid {du:.2e}  max|Δp|/max|p| {dp:.2e}");
        if !(du < bound && dp < bound) {
            failures.push(format!("{u}: ΔU {du:e}, Δp {dp:e}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// OpenFOAM's `CrankNicolson 0.9` (the pneumatic conveyor's time scheme: the spatial terms
/// implicit, the time derivative (1 + ψ)/Δt (U − U°) − ψ ddt0(U) with ddt0 recursive, Euler on
/// the first step, and ddtCorr with the same coefficients, `fv::ddt::CrankNicolsonDdt0`)
/// against pisoFoam on the skewed cavity with the same solvers as above: round-off, bound
/// 1e-10 as for Euler. Measured 1.6e-15 (U), 3.6e-14 (p) after 40 steps (5e-16, 2e-15 when
/// ddtCorr's stored derivative of U was kept on the faces instead of OpenFOAM's cells), where
/// the θ-scheme with θ = 1 − ψ/2 on convection and diffusion that it replaced differed by
/// 1.3e-3 (U) and 4.2e-3 (p).
#[test]
fn crank_nicolson_matches_pisofoam() {
    if !testkit::tool("pisoFoam") || !testkit::tool("blockMesh") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (theirs, ours) = run_both_with_ddt(
        dir.path(),
        "cn",
        "Gauss limitedLinearV 1",
        &format!("{P_PCG}\n{U_GS}"),
        "CrankNicolson 0.9",
    );
    let (du, dp) = difference(&ours, &theirs);
    eprintln!("CrankNicolson 0.9: max|ΔU|/U_lid {du:.2e}  max|Δp|/max|p| {dp:.2e}");
    assert!(du < 1e-10 && dp < 1e-10, "ΔU {du:e}, Δp {dp:e}");
}
