//! The ∂ε/∂t term of continuity, ∂ε/∂t + ∇·φ = 0, and its switch: a block of the 1-D column
//! loses fluid volume in one step (ε 1 → 0.99, prescribed from the `0.001/` directory with the
//! `prescribed` coupling source), and that volume must leave through the outlet.
//!
//! Closed form (volume balance over the column, inlet flux fixed): φ_out = u_in A + Δε V/Δt
//! with A = 4e-6 m², V = 16 cells × 4e-9 m³, Δε = 0.01, Δt = 1e-3 s; without the term
//! (`ddtVoidfraction off`) φ_out = u_in A.

use foam::{FieldValues, Item};
use foam_solver_tests::{grain_piso_foam, TestCase};

const U_IN: f64 = 0.01;
const AREA: f64 = 2e-3 * 2e-3;
const DT: f64 = 1e-3;
const D_EPS: f64 = 0.01;

/// The flux through the outlet face (m³/s) at 0.001 s.
fn outlet_flux(case: &TestCase) -> f64 {
    let path = case.dir.join("0.001/phi");
    let file = foam::parse_file(&path).unwrap_or_else(|e| panic!("{e}"));
    let value = file
        .body
        .dict("boundaryField")
        .and_then(|b| b.dict("outlet"))
        .and_then(|o| o.stream("value"))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match value {
        [Item::Word(w), v] if w == "uniform" => v.as_f64().expect("a number"),
        other => panic!("{}: outlet value {other:?}", path.display()),
    }
}

/// One step of the column whose block changes from ε = 1 to 1 − Δε at t = 0.001 s.
fn shrinking_block(ddt: &str) -> (TestCase, f64) {
    let case = TestCase::new("column");
    case.edit(
        "constant/couplingProperties",
        "couplingInterval 1;",
        &format!(
            "couplingInterval 1;\ngrainPisoFoamProps {{ couplingSource prescribed; ddtVoidfraction {ddt}; }}"
        ),
    );
    case.edit(
        "system/controlDict",
        "endTime         0.02;",
        "endTime         0.001;",
    );
    case.edit(
        "system/controlDict",
        "writeInterval   20;",
        "writeInterval   1;",
    );
    let (_, g) = case.mesh();
    let block: Vec<bool> = g
        .cell_centres
        .iter()
        .map(|c| c[2] > 0.020 && c[2] < 0.036)
        .collect();
    let volume: f64 = block
        .iter()
        .zip(&g.cell_volumes)
        .filter(|(&b, _)| b)
        .map(|(_, v)| v)
        .sum();
    std::fs::create_dir_all(case.dir.join("0.001")).unwrap();
    std::fs::copy(
        case.dir.join("0/voidfraction"),
        case.dir.join("0.001/voidfraction"),
    )
    .unwrap();
    let eps = block
        .iter()
        .map(|&b| if b { 1.0 - D_EPS } else { 1.0 })
        .collect();
    let path = case.dir.join("0.001/voidfraction");
    let mut field = foam::VolField::read(&path).unwrap();
    field.set_internal(FieldValues::Scalar(eps)).unwrap();
    field.write(&path, foam::Format::Ascii).unwrap();
    (case, volume)
}

#[test]
fn a_shrinking_voidfraction_pushes_its_volume_out_only_with_the_ddt_term() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    let (on, volume) = shrinking_block("on");
    assert!(
        approx::abs_diff_eq!(volume, 16.0 * 4e-9, epsilon = 1e-20),
        "block volume {volume}"
    );
    let (off, _) = shrinking_block("off");
    let log = on.run(&solver);
    assert!(log.contains("prescribed coupling fields read"), "{log}");
    off.run(&solver);
    // The new voidage was used and written back at 0.001.
    assert!(on.scalars("0.001", "voidfraction").contains(&(1.0 - D_EPS)));

    let expected_on = U_IN * AREA + D_EPS * volume / DT;
    let expected_off = U_IN * AREA;
    let (phi_on, phi_off) = (outlet_flux(&on), outlet_flux(&off));
    let err_on = (phi_on - expected_on) / expected_on;
    let err_off = (phi_off - expected_off) / expected_off;
    eprintln!(
        "outlet flux: ddt on {phi_on:.6e} m³/s (closed form {expected_on:.6e}, {err_on:+.2e}); \
         off {phi_off:.6e} (closed form {expected_off:.6e}, {err_off:+.2e})"
    );
    assert!(
        err_on.abs() < 1e-8 && err_off.abs() < 1e-8,
        "{err_on:e} {err_off:e}"
    );
}
