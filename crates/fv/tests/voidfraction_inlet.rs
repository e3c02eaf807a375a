//! CFDEMcoupling's inlet condition `uniformFixedValueVoidfraction` (`libfiniteVolumeCFDEM`,
//! `uniformFixedValueVoidfractionFvPatchField.C`, `updateCoeffs`: U_b = u(t)/ε_b), in a 1-D
//! column whose inlet lies in a packed layer. Closed forms:
//! * the inlet's face velocity is the table's u(t), linearly interpolated, divided by the face
//!   voidage ε_b (the owner cell's with a zeroGradient `voidfraction`, the fixed value where
//!   the `voidfraction` file fixes one);
//! * continuity ∇·(εU) = 0 in a column with slip walls makes the superficial flux uniform:
//!   every face's φ/S equals ε_b U_b = u(t) (−u(t) at the inlet, whose normal points out),
//!   whatever the voidage along the column.

mod common;
use common::{write_case, CaseSpec, PatchSpec};

/// The inlet table: u(t) = 0.002 + 0.28 t m/s along x for 0 ≤ t ≤ 0.1 s.
const TABLE: &str = "table ((0 (0.002 0 0)) (0.1 (0.03 0 0)))";

fn u_of(t: f64) -> f64 {
    0.002 + (0.03 - 0.002) * t / 0.1
}

/// A column of `n` cells along x, ε = 0.45 in its first third (the inlet's layer) and 1
/// above; `voidfraction_inlet` the `voidfraction` file's inlet entry (None: no file).
fn column(voidfraction_inlet: Option<&str>) -> (tempfile::TempDir, fv::Fluid, Vec<f64>) {
    let n = 12;
    let dir = tempfile::tempdir().unwrap();
    let m = mesh::build::uniform_box([0.0; 3], [0.06, 0.01, 0.01], [n, 1, 1]);
    let slip = "type slip;";
    let zg = "type zeroGradient;";
    let inlet = format!("type uniformFixedValueVoidfraction; uniformValue {TABLE};");
    let wall = |name| PatchSpec {
        name,
        patch_type: "wall",
        u: slip,
        p: zg,
    };
    let patches = [
        PatchSpec {
            name: "xMin",
            patch_type: "patch",
            u: &inlet,
            p: zg,
        },
        PatchSpec {
            name: "xMax",
            patch_type: "patch",
            u: zg,
            p: "type fixedValue; value uniform 0;",
        },
        wall("yMin"),
        wall("yMax"),
        wall("zMin"),
        wall("zMax"),
    ];
    let spec = CaseSpec {
        nu: 1.5e-4,
        rho: 10.0,
        delta_t: 1e-3,
        end_time: 0.1,
        ddt: "Euler",
        div: "Gauss upwind",
        n_correctors: 2,
        u_internal: [0.0; 3],
    };
    write_case(dir.path(), m, &patches, &spec);
    if let Some(entry) = voidfraction_inlet {
        let text = format!(
            "FoamFile\n{{\n    version 2.0;\n    format ascii;\n    class volScalarField;\n    \
             location \"0\";\n    object voidfraction;\n}}\ndimensions [0 0 0 0 0 0 0];\n\
             internalField uniform 1;\nboundaryField\n{{\n    xMin {{ {entry} }}\n    \
             \".*\" {{ type zeroGradient; }}\n}}\n"
        );
        std::fs::write(dir.path().join("0/voidfraction"), text).unwrap();
    }
    let mut fluid = fv::Fluid::from_case(dir.path()).unwrap();
    let g = fluid.geometry().clone();
    let eps: Vec<f64> =
        g.c.iter()
            .map(|c| if c[0] < 0.02 { 0.45 } else { 1.0 })
            .collect();
    fluid.set_voidage(&eps, &eps).unwrap();
    (dir, fluid, eps)
}

/// Advances 20 steps of 1 ms; at each, the inlet's face values against u(t)/`eps_b` and every
/// face's superficial flux against u(t).
fn check_steps(fluid: &mut fv::Fluid, eps_b: f64) {
    let g = fluid.geometry().clone();
    let inlet = g.patches.iter().find(|p| p.name == "xMin").unwrap().clone();
    for k in 1..=20 {
        fluid.advance(1e-3).unwrap();
        let t = fluid.time();
        assert!((t - 1e-3 * k as f64).abs() < 1e-12);
        let u = u_of(t);
        for f in inlet.faces.clone() {
            let ub = fluid.u_boundary()[f - g.n_internal];
            assert!(
                (ub[0] / (u / eps_b) - 1.0).abs() < 1e-12 && ub[1] == 0.0 && ub[2] == 0.0,
                "t = {t}: U_b = {ub:?}, u(t)/ε_b = {}",
                u / eps_b
            );
            let sup = -fluid.phi()[f] / g.mag_sf[f];
            assert!(
                (sup / u - 1.0).abs() < 1e-12,
                "t = {t}: inlet φ/S {sup} u {u}"
            );
        }
        for f in 0..g.n_internal {
            let sup = fluid.phi()[f] / g.sf[f][0];
            assert!(
                (sup / u - 1.0).abs() < 1e-8,
                "t = {t}: face {f}: φ/S = {sup}, u(t) = {u}"
            );
        }
    }
}

#[test]
fn the_inlet_velocity_is_the_table_over_the_face_voidage() {
    // zeroGradient voidfraction (ErgunTestCG's): ε_b is the inlet cell's 0.45
    let (_dir, mut fluid, eps) = column(None);
    assert_eq!(eps[0], 0.45);
    check_steps(&mut fluid, 0.45);
    let (_dir, mut fluid, _) = column(Some("type zeroGradient;"));
    check_steps(&mut fluid, 0.45);
}

#[test]
fn a_fixed_inlet_voidage_of_one_gives_the_table_itself() {
    // CFDEM's commented alternative, `voidfraction` fixedValue 1 at the inlet: U_b = u(t)
    let (_dir, mut fluid, _) = column(Some("type fixedValue; value uniform 1;"));
    check_steps(&mut fluid, 1.0);
    // and a fixed 0.5: U_b = 2 u(t), the flux still u(t)
    let (_dir, mut fluid, _) = column(Some("type fixedValue; value uniform 0.5;"));
    check_steps(&mut fluid, 0.5);
}

#[test]
fn a_bad_table_is_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let m = mesh::build::uniform_box([0.0; 3], [0.06, 0.01, 0.01], [4, 1, 1]);
    let zg = "type zeroGradient;";
    let bad = "type uniformFixedValueVoidfraction; uniformValue table ((0.1 (0 0 0)) (0 (1 0 0)));";
    let spec = |name, patch_type, u, p| PatchSpec {
        name,
        patch_type,
        u,
        p,
    };
    let patches = [
        spec("xMin", "patch", bad, zg),
        spec("xMax", "patch", zg, "type fixedValue; value uniform 0;"),
        spec("yMin", "wall", "type slip;", zg),
        spec("yMax", "wall", "type slip;", zg),
        spec("zMin", "wall", "type slip;", zg),
        spec("zMax", "wall", "type slip;", zg),
    ];
    let case = CaseSpec {
        nu: 1e-3,
        rho: 1.0,
        delta_t: 1e-3,
        end_time: 0.01,
        ddt: "Euler",
        div: "Gauss upwind",
        n_correctors: 2,
        u_internal: [0.0; 3],
    };
    write_case(dir.path(), m, &patches, &case);
    let e = fv::Fluid::from_case(dir.path())
        .err()
        .expect("refused")
        .to_string();
    assert!(
        e.contains("0/U") && e.contains("boundaryField.xMin.uniformValue"),
        "{e}"
    );
}
