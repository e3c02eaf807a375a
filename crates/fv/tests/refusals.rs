//! Settings the native solver does not support are refused with an error naming the file and
//! the key (never silently replaced): each case edits one entry of a copy of the Re 10 cavity
//! (`tests/fixtures/fv/cavity-re10`) and checks the error.

use fv::FvError;

/// (file, text to replace, replacement, the file named by the error, the key named by it).
type Edit = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
);

const EDITS: &[Edit] = &[
    (
        "system/controlDict",
        "stopAt          endTime;",
        "stopAt writeNow;",
        "system/controlDict",
        "stopAt",
    ),
    (
        "system/controlDict",
        "startFrom       startTime;",
        "startFrom now;",
        "system/controlDict",
        "startFrom",
    ),
    (
        "system/controlDict",
        "writeControl    timeStep;",
        "writeControl cpuTime;",
        "system/controlDict",
        "writeControl",
    ),
    (
        "system/controlDict",
        "deltaT          0.005;",
        "deltaT 0.005; adjustTimeStep yes;",
        "system/controlDict",
        "adjustTimeStep",
    ),
    (
        "system/controlDict",
        "writeFormat     ascii;",
        "writeFormat hdf5;",
        "system/controlDict",
        "writeFormat",
    ),
    (
        "system/controlDict",
        "startTime       0;",
        "startTime 0.1;",
        "system/controlDict",
        "startTime",
    ),
    (
        "system/fvSchemes",
        "default         Euler;",
        "default localEuler;",
        "system/fvSchemes",
        "ddtSchemes.default",
    ),
    (
        "system/fvSchemes",
        "default         Euler;",
        "default CrankNicolson 1.5;",
        "system/fvSchemes",
        "ddtSchemes.default",
    ),
    (
        "system/fvSchemes",
        "default         Euler;",
        "default Euler; ddt(U) localEuler;",
        "system/fvSchemes",
        "ddtSchemes.ddt(U)",
    ),
    (
        "system/fvSchemes",
        "default         Gauss linear orthogonal;",
        "default Gauss linear orthogonal; laplacian((1|A(U)),p) Gauss linear corrected;",
        "system/fvSchemes",
        "laplacianSchemes.laplacian((1|A(U)),p)",
    ),
    (
        "system/fvSchemes",
        "div(phi,U)      Gauss linear;",
        "div(phi,U) Gauss vanLeerV;",
        "system/fvSchemes",
        "divSchemes.div(phi,U)",
    ),
    (
        "system/fvSchemes",
        "div(phi,U)      Gauss linear;",
        "div(phi,U) Gauss limitedLinear 1.5;",
        "system/fvSchemes",
        "divSchemes.div(phi,U)",
    ),
    // linearUpwind's gradient is the gradSchemes entry it names.
    (
        "system/fvSchemes",
        "    grad(p)         Gauss linear;\n}\n\ndivSchemes\n{\n    default         none;\n    div(phi,U)      Gauss linear;",
        "    grad(p) Gauss linear; limitedGrad cellLimited Gauss linear 1;\n}\ndivSchemes\n{\n    div(phi,U) Gauss linearUpwind limitedGrad;",
        "system/fvSchemes",
        "gradSchemes.limitedGrad",
    ),
    // limitedLinear's limiter takes the gradient of |U|² (`grad(magSqr(U))`, here `default`).
    (
        "system/fvSchemes",
        "    default         Gauss linear;\n    grad(p)         Gauss linear;\n}\n\ndivSchemes\n{\n    default         none;\n    div(phi,U)      Gauss linear;",
        "    default leastSquares; grad(U) Gauss linear; grad(p) Gauss linear;\n}\ndivSchemes\n{\n    div(phi,U) Gauss limitedLinear 1;",
        "system/fvSchemes",
        "gradSchemes.default",
    ),
    (
        "system/fvSchemes",
        "default         Gauss linear orthogonal;",
        "default Gauss harmonic corrected;",
        "system/fvSchemes",
        "laplacianSchemes.default",
    ),
    (
        "system/fvSchemes",
        "grad(p)         Gauss linear;",
        "grad(p) leastSquares;",
        "system/fvSchemes",
        "gradSchemes.grad(p)",
    ),
    (
        "system/fvSchemes",
        "grad(p)         Gauss linear;",
        "grad(p) Gauss linear; grad(U) cellLimited Gauss linear 1;",
        "system/fvSchemes",
        "gradSchemes.grad(U)",
    ),
    (
        "system/fvSchemes",
        "default         linear;",
        "default cubic;",
        "system/fvSchemes",
        "interpolationSchemes.default",
    ),
    (
        "system/fvSolution",
        "solver          PCG;",
        "solver diagonal;",
        "system/fvSolution",
        "solvers.p.solver",
    ),
    (
        "system/fvSolution",
        "solver          PCG;",
        "solver GAMG; smoother SOR;",
        "system/fvSolution",
        "solvers.p.smoother",
    ),
    (
        "system/fvSolution",
        "solver          PCG;",
        "solver GAMG; nCellsInCoarsestLevel 10;",
        "system/fvSolution",
        "solvers.p.smoother",
    ),
    (
        "system/fvSolution",
        "preconditioner  DIC;",
        "preconditioner { preconditioner GAMG; smoother Jacobi; }",
        "system/fvSolution",
        "solvers.p.preconditioner.smoother",
    ),
    (
        "system/fvSolution",
        "preconditioner  DIC;",
        "preconditioner FDIC;",
        "system/fvSolution",
        "solvers.p.preconditioner",
    ),
    (
        "system/fvSolution",
        "smoother        symGaussSeidel;",
        "smoother Jacobi;",
        "system/fvSolution",
        "solvers.U.smoother",
    ),
    (
        "system/fvSolution",
        "smoother        symGaussSeidel;",
        "smoother symGaussSeidel; nSweeps 0;",
        "system/fvSolution",
        "solvers.U.nSweeps",
    ),
    (
        "system/fvSolution",
        "        $p;\n        relTol          0;",
        "        solver bogus;",
        "system/fvSolution",
        "solvers.pFinal.solver",
    ),
    (
        "system/fvSolution",
        "PISO\n{",
        "relaxationFactors { fields { p 0.3; } equations { \"U.*\" 0.7; } }\nPISO\n{",
        "system/fvSolution",
        "relaxationFactors.equations.U",
    ),
    (
        "system/fvSolution",
        "PISO\n{",
        "relaxationFactors { U 0.9; }\nPISO\n{",
        "system/fvSolution",
        "relaxationFactors.U",
    ),
    (
        "system/fvSolution",
        "nCorrectors     2;",
        "nCorrectors 1.5;",
        "system/fvSolution",
        "PISO.nCorrectors",
    ),
    (
        "system/fvSolution",
        "pRefCell        0;",
        "pRefCell 400;",
        "system/fvSolution",
        "PISO.pRefCell",
    ),
    (
        "system/fvSolution",
        "PISO\n{",
        "PIMPLE\n{\n    nOuterCorrectors 3;",
        "system/fvSolution",
        "PIMPLE.nOuterCorrectors",
    ),
    (
        "constant/transportProperties",
        "nu              0.01;",
        "transportModel CrossPowerLaw; nu 0.01;",
        "constant/transportProperties",
        "transportModel",
    ),
    (
        "constant/transportProperties",
        "nu              0.01;",
        "nu -0.01;",
        "constant/transportProperties",
        "nu",
    ),
    (
        "0/U",
        "type            noSlip;",
        "type codedFixedValue;",
        "0/U",
        "boundaryField.fixedWalls.type",
    ),
    (
        "0/U",
        "type            fixedValue;\n        value           uniform (1 0 0);",
        "type uniformFixedValue; uniformValue table ((0 (0 0 0)) (0 (1 0 0)));",
        "0/U",
        "boundaryField.movingWall.uniformValue",
    ),
    (
        "0/U",
        "value           uniform (1 0 0);",
        "value nonuniform List<vector> 2((1 0 0) (1 0 0));",
        "0/U",
        "boundaryField.movingWall.value",
    ),
    (
        "0/U",
        "type            empty;",
        "type zeroGradient;",
        "0/U",
        "boundaryField.frontAndBack.type",
    ),
    (
        "0/p",
        "movingWall\n    {\n        type            zeroGradient;\n    }",
        "",
        "0/p",
        "boundaryField.movingWall",
    ),
];

#[test]
fn unsupported_settings_are_refused_naming_file_and_key() {
    let fixture = testkit::fixture("fv/cavity-re10");
    for &(file, from, to, err_file, err_key) in EDITS {
        let dir = tempfile::tempdir().unwrap();
        testkit::copy_dir(&fixture, dir.path());
        let path = dir.path().join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(from), "{file}: `{from}` not found");
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        let err = match fv::Fluid::from_case(dir.path()) {
            Ok(_) => panic!("{file}: `{to}` was accepted"),
            Err(e) => e,
        };
        let message = err.to_string();
        match &err {
            FvError::Setting { file: f, key, .. } => {
                assert!(
                    f.ends_with(err_file) && key == err_key,
                    "{file}: `{to}`: expected {err_file} `{err_key}`, got {message}"
                );
            }
            other => panic!("{file}: `{to}`: not a setting error: {other}"),
        }
        assert!(
            message.contains(err_file) && message.contains(err_key),
            "{message}"
        );
    }
}

/// totalPressure's `rho`: with a kinematic p OpenFOAM ignores it (CFDEM's tutorials name
/// `rho rho;`) and so does fv; with p in Pa it would be the compressible form: refused.
#[test]
fn total_pressure_rho_follows_the_dimensions_of_p() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
    let path = dir.path().join("0/p");
    let text = std::fs::read_to_string(&path).unwrap().replacen(
        "movingWall\n    {\n        type            zeroGradient;",
        "movingWall\n    {\n        type totalPressure; p0 uniform 0; rho rho;",
        1,
    );
    std::fs::write(&path, &text).unwrap();
    fv::Fluid::from_case(dir.path()).expect("kinematic p: `rho` is ignored");
    let pascal = text.replacen("[0 2 -2 0 0 0 0]", "[1 -1 -2 0 0 0 0]", 1);
    assert_ne!(pascal, text);
    std::fs::write(&path, pascal).unwrap();
    match fv::Fluid::from_case(dir.path()) {
        Err(FvError::Setting { file, key, msg }) => {
            assert!(
                file.ends_with("0/p") && key == "boundaryField.movingWall.rho",
                "{key}"
            );
            assert!(msg.contains("kinematic"), "{msg}");
        }
        Ok(_) => panic!("p in Pa with `rho rho` was accepted"),
        Err(other) => panic!("not a setting error: {other}"),
    }
}

/// An active fvOptions source of a type the native solver does not apply would change the
/// flow: refused, naming it (the mean-velocity sources are `tests/periodic.rs`'s).
#[test]
fn an_fv_options_source_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
    let file = dir.path().join("system/fvOptions");
    let source = "FoamFile { version 2.0; format ascii; class dictionary; object fvOptions; }\n\
                  momentumSource { type semiImplicitSource; active yes; }\n";
    std::fs::write(&file, source).unwrap();
    match fv::Fluid::from_case(dir.path()) {
        Err(FvError::Setting { file, key, msg }) => {
            assert!(
                file.ends_with("system/fvOptions") && key == "momentumSource.type",
                "{key}"
            );
            assert!(msg.contains("semiImplicitSource"), "{msg}");
        }
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted"),
    }
    std::fs::write(&file, source.replace("active yes", "active no")).unwrap();
    fv::Fluid::from_case(dir.path()).unwrap();
}

/// A scheme with a number in it (CFDEM's tutorials write `Gauss limitedLinearV 1`) is named
/// whole with the supported ones, not refused as "not words".
#[test]
fn an_unsupported_convection_scheme_is_named_with_the_supported_ones() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
    let path = dir.path().join("system/fvSchemes");
    let text = std::fs::read_to_string(&path).unwrap();
    let from = "div(phi,U)      Gauss linear;";
    assert!(text.contains(from));
    for (to, named) in [
        ("div(phi,U) Gauss vanLeerV;", "`Gauss vanLeerV`"),
        ("div(phi,U) Gauss limitedCubic 1;", "`Gauss limitedCubic 1`"),
        ("div(phi,U) bounded Gauss QUICK;", "`bounded Gauss QUICK`"),
        ("div(phi,U) Gauss linearUpwind;", "`Gauss linearUpwind`"),
    ] {
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        let message = fv::Fluid::from_case(dir.path()).err().unwrap().to_string();
        assert!(
            message.contains(named)
                && message.contains(fv::convection::SUPPORTED)
                && message.contains("div(phi,U)"),
            "{message}"
        );
    }
    // The list names every scheme the solver runs.
    for scheme in [
        "Gauss linear,",
        "Gauss upwind",
        "Gauss limitedLinear ψ",
        "Gauss limitedLinearV ψ",
        "Gauss linearUpwind <grad>",
        "Gauss linearUpwindV <grad>",
        "bounded",
    ] {
        assert!(fv::convection::SUPPORTED.contains(scheme), "{scheme}");
    }
}

/// The fvSchemes entry of the explicit stress term of pisoFoam's laminar model must be
/// `Gauss linear` too when `constant/turbulenceProperties` asks for it.
#[test]
fn the_stress_divergence_scheme_is_checked_with_the_laminar_model() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
    std::fs::write(
        dir.path().join("constant/turbulenceProperties"),
        "FoamFile { version 2.0; format ascii; class dictionary; object turbulenceProperties; }\nsimulationType laminar;\n",
    )
    .unwrap();
    let sch = dir.path().join("system/fvSchemes");
    let text = std::fs::read_to_string(&sch).unwrap().replace(
        "div(phi,U)      Gauss linear;",
        "div(phi,U) Gauss linear;\n    div((nuEff*dev2(T(grad(U))))) Gauss upwind;",
    );
    std::fs::write(&sch, text).unwrap();
    let message = fv::Fluid::from_case(dir.path()).err().unwrap().to_string();
    assert!(
        message.contains("fvSchemes")
            && message.contains("divSchemes.div((nuEff*dev2(T(grad(U)))))"),
        "{message}"
    );
}

/// A start time's `phi` (read at a restart) must be a surfaceScalarField with one value per
/// face; anything else names the file and the entry.
#[test]
fn a_malformed_phi_is_refused() {
    let header = "FoamFile { version 2.0; format ascii; class surfaceScalarField; object phi; }\ndimensions [0 3 -1 0 0 0 0];\n";
    let cases = [
        (
            format!("{header}internalField nonuniform List<scalar> 2(0 0);\nboundaryField {{}}\n"),
            "internalField",
        ),
        (
            format!("{header}internalField uniform 0;\nboundaryField {{ movingWall {{ type calculated; value uniform 0; }} }}\n"),
            "boundaryField.fixedWalls.value",
        ),
        (
            header.replace("surfaceScalarField", "volScalarField")
                + "internalField uniform 0;\nboundaryField {}\n",
            "class",
        ),
    ];
    for (text, key) in cases {
        let dir = tempfile::tempdir().unwrap();
        testkit::copy_dir(&testkit::fixture("fv/cavity-re10"), dir.path());
        std::fs::write(dir.path().join("0/phi"), text).unwrap();
        match fv::Fluid::from_case(dir.path()) {
            Err(FvError::Setting { file, key: k, .. }) => {
                assert!(
                    file.ends_with("0/phi") && k == key,
                    "{k} in {}",
                    file.display()
                )
            }
            Err(e) => panic!("{key}: {e}"),
            Ok(_) => panic!("{key}: accepted"),
        }
    }
}
