//! Time consistency of grainPisoFoam's implicit drag on porous faces (full tier): the drag
//! relaxation of `crates/fv/tests/coupled_time.rs` (a), run by grainPisoFoam on the column
//! template made periodic (its inlet and outlet a cyclic pair): ε = 0.6, Ksl = 60 kg/(m³ s)
//! (k = Ksl/ρ = 6 1/s with ρ = 10 kg/m³), Us = (0 0 0.01) m/s, everywhere and constant, the fluid
//! at rest at t = 0. With no pressure gradient and no convection (uniform U),
//! ε dU/dt = −k (U − Us): U(t) = Us (1 − e^(−k t/ε)), and the face flux is φ = ε U·S.
//!
//! Every face is porous (ε < 1), so the face flux comes from the porous faces' own momentum
//! balance (porousFaces.H, porousTimeFlux.H). The error of the cells and of the face fluxes at
//! T = 0.2 s must fall with Δt for each time scheme; before porousTimeFlux.H the face flux with
//! `CrankNicolson 0.9` stayed 24 % off at every Δt (the faces' inertia 1.9 times
//! the cells').
//!
//! And ∂ε/∂t of continuity (fv's test (c)): the column with its inlet closed (U = 0) and its
//! outlet open (p = 0), ε(t) = 0.6 + 0.02 sin(10 t) everywhere, prescribed in every time
//! directory (`couplingSource prescribed`): ∂ε/∂t + ∂(εu)/∂z = 0 with εu = 0 at the inlet gives
//! the face flux φ = −ε′(t) z S, exact on the mesh. Before grainPisoFoam evaluated
//! `fvc::ddt(voidfraction)` once per step, `CrankNicolson 1` updated its stored derivative on
//! each of the step's four calls and the flux error did not fall with Δt.

use foam::Item;
use foam_solver_tests::{grain_piso_foam, TestCase};

const EPS: f64 = 0.6;
const K: f64 = 6.0;
const RHO: f64 = 10.0;
const T: f64 = 0.2;
/// The particle velocity (m/s); small, so that the Courant number stays below 1 at 10 steps
/// (the template's Gauss–Seidel U solver needs a diagonally dominant matrix).
const US: f64 = 0.01;
/// Face area of the column (2 mm × 2 mm), m².
const AREA: f64 = 4e-6;

/// `steps` steps to T with the time scheme `ddt`, written at T only.
fn time_control(case: &TestCase, ddt: &str, steps: usize) {
    case.edit(
        "system/controlDict",
        "endTime         0.02;",
        &format!("endTime         {T};"),
    );
    case.edit(
        "system/controlDict",
        "deltaT          0.001;",
        &format!("deltaT          {};", T / steps as f64),
    );
    case.edit(
        "system/controlDict",
        "writeInterval   20;",
        &format!("writeInterval   {steps};"),
    );
    case.edit(
        "system/fvSchemes",
        "ddtSchemes      { default Euler; }",
        &format!("ddtSchemes      {{ default {ddt}; }}"),
    );
}

/// The periodic column with the drag set-up, `ddt` and `steps` steps to T.
fn relaxation_case(ddt: &str, steps: usize) -> TestCase {
    let case = TestCase::template("column");
    case.edit(
        "system/blockMeshDict",
        "inlet  { type patch; faces ((0 3 2 1)); }",
        "inlet  { type cyclic; neighbourPatch outlet; faces ((0 3 2 1)); }",
    );
    case.edit(
        "system/blockMeshDict",
        "outlet { type patch; faces ((4 5 6 7)); }",
        "outlet { type cyclic; neighbourPatch inlet; faces ((4 5 6 7)); }",
    );
    for field in ["U", "p", "Ksl", "Us", "f", "voidfraction"] {
        let path = case.dir.join("0").join(field);
        let text = std::fs::read_to_string(&path).unwrap();
        let text: Vec<String> = text
            .lines()
            .map(|l| match l.trim_start() {
                s if s.starts_with("inlet ") => "    inlet { type cyclic; }".to_string(),
                s if s.starts_with("outlet ") => "    outlet { type cyclic; }".to_string(),
                s if s.starts_with("internalField") => match field {
                    "U" => "internalField uniform (0 0 0);".into(),
                    "Ksl" => format!("internalField uniform {};", K * RHO),
                    "Us" => format!("internalField uniform (0 0 {US});"),
                    "voidfraction" => format!("internalField uniform {EPS};"),
                    _ => l.to_string(),
                },
                _ => l.to_string(),
            })
            .collect();
        std::fs::write(&path, text.join("\n") + "\n").unwrap();
    }
    time_control(&case, ddt, steps);
    case.edit(
        "system/fvSolution",
        "nNonOrthogonalCorrectors 0;",
        "nNonOrthogonalCorrectors 0;\n    pRefCell 0;\n    pRefValue 0;",
    );
    case.block_mesh();
    case
}

/// The internal face fluxes written at time `time` (m³/s).
fn internal_phi(case: &TestCase, time: &str) -> Vec<f64> {
    let path = case.dir.join(time).join("phi");
    let file = foam::parse_file(&path).unwrap_or_else(|e| panic!("{e}"));
    let s = file
        .body
        .stream("internalField")
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match s {
        [Item::Word(w), Item::Scalars(v)] if w == "nonuniform" => v.clone(),
        [Item::Word(w), Item::Word(_), Item::Scalars(v)] if w == "nonuniform" => v.clone(),
        [Item::Word(w), v] if w == "uniform" => vec![v.as_f64().expect("a number")],
        other => panic!("{}: internalField {other:?}", path.display()),
    }
}

/// Max errors (cells, faces) against the closed form at T, relative to Us.
fn errors(ddt: &str, steps: usize) -> (f64, f64) {
    let solver = grain_piso_foam().expect("grainPisoFoam (full tier)");
    let case = relaxation_case(ddt, steps);
    case.run(&solver);
    let time = format!("{T}");
    let exact = US * (1.0 - (-K * T / EPS).exp());
    let cell = case
        .vectors(&time, "U")
        .iter()
        .map(|u| (u[2] - exact).abs().max(u[0].abs()).max(u[1].abs()))
        .fold(0.0, f64::max);
    let face = internal_phi(&case, &time)
        .iter()
        .map(|phi| (phi / (EPS * AREA) - exact).abs())
        .fold(0.0, f64::max);
    (cell / US, face / US)
}

#[test]
fn drag_relaxation_on_porous_faces_converges_in_time() {
    if grain_piso_foam().is_none() {
        return;
    }
    for ddt in ["Euler", "CrankNicolson 0.9", "backward"] {
        let e: Vec<(f64, f64)> = [10, 20, 40].iter().map(|&n| errors(ddt, n)).collect();
        eprintln!(
            "{ddt:>18}: cells {:.3e} {:.3e} {:.3e}, faces {:.3e} {:.3e} {:.3e}",
            e[0].0, e[1].0, e[2].0, e[0].1, e[1].1, e[2].1
        );
        for (what, a, b) in [("cells", e[0].0, e[2].0), ("faces", e[0].1, e[2].1)] {
            // a consistent scheme: 4× more steps, at least 2.5× smaller error (first order: 4×)
            assert!(b < a / 2.5, "{ddt}, {what}: {e:?}");
        }
    }
}

/// ε(t) of the column (see the header).
fn column_eps(t: f64) -> f64 {
    0.6 + 0.02 * (10.0 * t).sin()
}

/// Max |φ + ε′(T) z S|/(ε S) over the internal faces at T (m/s), `ddt`, `steps` steps.
fn column_flux_error(ddt: &str, steps: usize) -> f64 {
    let solver = grain_piso_foam().expect("grainPisoFoam (full tier)");
    let case = TestCase::template("column");
    case.edit(
        "constant/couplingProperties",
        "couplingInterval 1;",
        "couplingInterval 1;\ngrainPisoFoamProps { couplingSource prescribed; ddtVoidfraction on; }",
    );
    case.edit(
        "0/U",
        "inlet  { type fixedValue; value uniform (0 0 0.01); }",
        "inlet  { type fixedValue; value uniform (0 0 0); }",
    );
    case.edit(
        "0/U",
        "internalField   uniform (0 0 0.01);",
        "internalField   uniform (0 0 0);",
    );
    let dt = T / steps as f64;
    time_control(&case, ddt, steps);
    case.block_mesh();
    let template = case.dir.join("0/voidfraction");
    for i in 0..=steps {
        let t = i as f64 * dt;
        let dir = case.dir.join(foam::case::time_name(t));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("voidfraction");
        let mut field = foam::VolField::read(&template).unwrap();
        field
            .set_internal(foam::FieldValues::Scalar(vec![column_eps(t); 60]))
            .unwrap();
        field.write(&path, foam::Format::Ascii).unwrap();
    }
    case.run(&solver);
    let deps = 0.02 * 10.0 * (10.0 * T).cos();
    // internal face i lies at z = (i + 1) mm (60 cells of 1 mm along z, S = +A ẑ)
    internal_phi(&case, &format!("{T}"))
        .iter()
        .enumerate()
        .map(|(i, phi)| {
            let z = (i + 1) as f64 * 1e-3;
            (phi + deps * z * AREA).abs() / (column_eps(T) * AREA)
        })
        .fold(0.0, f64::max)
}

#[test]
fn continuity_with_voidfraction_changing_in_time_converges_in_time() {
    if grain_piso_foam().is_none() {
        return;
    }
    for ddt in ["Euler", "CrankNicolson 0.9", "CrankNicolson 1", "backward"] {
        let e: Vec<f64> = [20, 40, 80]
            .iter()
            .map(|&n| column_flux_error(ddt, n))
            .collect();
        eprintln!("{ddt:>18}: faces {:.3e} {:.3e} {:.3e}", e[0], e[1], e[2]);
        // 4× more steps: first order gives 4× less, second order 16×
        assert!(e[2] < e[0] / 2.5, "{ddt}: {e:?}");
    }
}
