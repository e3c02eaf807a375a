//! The vocabulary of CFDEMcoupling's cfdemSolverPiso tutorials in `system/fvSchemes` and
//! `system/fvSolution` (written here in our own files, with the entries those tutorials use):
//! entries for fields the laminar native solver never solves (k, epsilon, R, nuTilda,
//! voidfraction, …), `fluxRequired`, `wallDist`, `interpolate(U)`, pattern keys for solvers,
//! `$p` and `$U` inheritance, a PIMPLE dictionary next to PISO, relaxation factors of 1 and a
//! GAMG entry with all its tuning keys are accepted and read to the settings they mean.

use fv::linsolve::{Method, Preconditioner};
use fv::settings::{Convection, Settings};

const FV_SCHEMES: &str = r#"FoamFile { version 2.0; format ascii; class dictionary; object fvSchemes; }
ddtSchemes { default Euler; }
gradSchemes { default Gauss linear; grad(p) Gauss linear; grad(U) Gauss linear; }
divSchemes
{
    default         Gauss linear;
    div(phi,U)      Gauss limitedLinearV 1;
    div(phi,k)      Gauss limitedLinear 1;
    div(phi,epsilon) Gauss limitedLinear 1;
    div(phi,R)      Gauss limitedLinear 1;
    div(R)          Gauss linear;
    div(phi,nuTilda) Gauss limitedLinear 1;
    div((viscousTerm*dev(grad(U).T()))) Gauss linear;
    div((nuEff*dev(grad(U).T()))) Gauss linear;
    div(phi,T)      bounded Gauss upwind;
}
laplacianSchemes
{
    default         Gauss linear corrected;
    laplacian((voidfraction2|A(U)),p) Gauss linear corrected;
    laplacian(DkEff,k) Gauss linear corrected;
}
interpolationSchemes { default linear; interpolate(U) linear; }
snGradSchemes { default corrected; }
fluxRequired { default no; p ; }
wallDist { method meshWave; }
"#;

const FV_SOLUTION: &str = r#"FoamFile { version 2.0; format ascii; class dictionary; object fvSolution; }
solvers
{
    p
    {
        solver          GAMG;
        smoother        DICGaussSeidel;
        tolerance       1e-06;
        relTol          0.1;
        cacheAgglomeration true;
        nCellsInCoarsestLevel 10;
        agglomerator    faceAreaPair;
        mergeLevels     1;
        nPreSweeps      0;
        nPostSweeps     2;
        nFinestSweeps   2;
        directSolveCoarsest false;
        maxIter         200;
        minIter         1;
    }
    pFinal { $p; relTol 0; }
    "(U|k|epsilon|omega|R|nuTilda)"
    {
        solver          PBiCG;
        preconditioner  DILU;
        tolerance       1e-05;
        relTol          0;
    }
    "(U|k|epsilon|omega|R|nuTilda)Final" { $U; relTol 0; }
    "(voidfraction|Us|Ksl|dSmoothing|UsNext|voidfractionNext)"
    {
        solver          PCG;
        preconditioner  DIC;
        tolerance       1e-05;
        relTol          0;
    }
}
PISO { nCorrectors 4; nNonOrthogonalCorrectors 1; pRefCell 0; pRefValue 0; }
PIMPLE { nOuterCorrectors 1; nCorrectors 4; nNonOrthogonalCorrectors 0; }
relaxationFactors { fields { p 1.0; } equations { "U.*" 1.; "k.*" 1.; "epsilon.*" 1.; } }
"#;

#[test]
fn the_tutorials_vocabulary_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
    std::fs::write(dir.path().join("system/fvSchemes"), FV_SCHEMES).unwrap();
    std::fs::write(dir.path().join("system/fvSolution"), FV_SOLUTION).unwrap();
    let s = Settings::read(&foam::Case::open(dir.path()).unwrap()).unwrap();
    assert_eq!(s.convection, Convection::LimitedLinearV(1.0));
    assert!(!s.bounded_convection);
    assert_eq!((s.n_correctors, s.n_non_orth, s.p_ref), (4, 1, (0, 0.0)));
    assert_eq!(s.p_solver.method, Method::Gamg);
    assert_eq!(
        (s.p_solver.controls.tolerance, s.p_solver.controls.rel_tol),
        (1e-6, 0.1)
    );
    assert_eq!(
        (s.p_solver.controls.max_iter, s.p_solver.controls.min_iter),
        (200, 1)
    );
    assert_eq!(s.p_final.method, Method::Gamg);
    assert_eq!(s.p_final.controls.rel_tol, 0.0);
    assert_eq!(s.u_solver.method, Method::BiCg(Preconditioner::Dic));
    assert_eq!(s.u_solver.controls.tolerance, 1e-5);
    // And the case runs.
    let mut fluid = fv::Fluid::from_case(dir.path()).unwrap();
    for _ in 0..3 {
        fluid.advance(0.005).unwrap();
    }
    assert!(fluid.u().iter().any(|u| u.norm() > 0.01));
}

/// `preconditioner { preconditioner GAMG; … }` in a PCG entry runs CG with the multigrid.
#[test]
fn gamg_as_a_preconditioner_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
    let path = dir.path().join("system/fvSolution");
    let text = std::fs::read_to_string(&path).unwrap().replacen(
        "preconditioner  DIC;",
        "preconditioner { preconditioner GAMG; smoother GaussSeidel; nCellsInCoarsestLevel 10; }",
        1,
    );
    std::fs::write(&path, text).unwrap();
    let s = Settings::read(&foam::Case::open(dir.path()).unwrap()).unwrap();
    assert_eq!(s.p_solver.method, Method::Pcg(Preconditioner::Amg));
}

/// `default none` with the Laplacians named (CFDEM's fillCylinder writes them so): only the
/// names the solver looks up are needed, and each named one is checked.
#[test]
fn named_laplacians_without_a_default_are_accepted_and_checked() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
    let path = dir.path().join("system/fvSchemes");
    let original = std::fs::read_to_string(&path).unwrap();
    let from = "default         Gauss linear orthogonal;";
    assert!(original.contains(from));
    let named = "default none; laplacian(nuEff,U) Gauss linear orthogonal; \
                 laplacian((1|A(U)),p) Gauss linear orthogonal;";
    std::fs::write(&path, original.replacen(from, named, 1)).unwrap();
    let s = Settings::read(&foam::Case::open(dir.path()).unwrap()).unwrap();
    assert_eq!(s.sn_grad, fv::settings::SnGrad::Orthogonal);
    let bad = format!("{named} laplacian(viscousTerm,U) Gauss harmonic corrected;");
    std::fs::write(&path, original.replacen(from, &bad, 1)).unwrap();
    let e = Settings::read(&foam::Case::open(dir.path()).unwrap())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("laplacianSchemes.laplacian(viscousTerm,U)"),
        "{e}"
    );
}
