//! CFDEM-PFM's `wallHeatTransferYagi` (`couple::wall_heat`):
//! * a uniform state: each wall face's heat is h A (T_w − T) with h from Yagi's correlation
//!   evaluated by hand, nothing above `voidfractionMax`, `maxSource` cuts counted;
//! * through the coupler, with a heat transfer model on a random bed, the walls' heat is in
//!   Tsource and in the account: Σ_c Tsource ρ c_p V (summed here from the field handed to the
//!   fluid) = −Σ q_p + from_wall to round-off — no heat is lost;
//! * bad input (no wall temperature file, T not zeroGradient on a heated wall, a value that is
//!   not one temperature per face) is an error naming the file and the patch.

mod common;
use couple::wall_heat::{WallFluid, WallHeat, WallProperties};
use couple::{Coupler, CouplerSettings, FluidState, ParticleState};
use mesh::build::uniform_box;
use mesh::v3::V3;
use std::path::Path;
use voidage::Method;

use common::{CP, LAMBDA, NU, RHO};
const PATCHES: [&str; 6] = ["xMin", "xMax", "yMin", "yMax", "zMin", "zMax"];

/// A volScalarField file `name` in `dir`: internal value `internal`, `xMin` as `wall`, the
/// other patches zeroGradient.
fn field(dir: &Path, name: &str, internal: f64, wall: &str) {
    let mut s = format!(
        "FoamFile {{ version 2.0; format ascii; class volScalarField; object {name}; }}\n\
         dimensions [0 0 0 1 0 0 0];\ninternalField uniform {internal};\nboundaryField\n{{\n"
    );
    for p in PATCHES {
        let entry = if p == "xMin" {
            wall
        } else {
            "type zeroGradient;"
        };
        s.push_str(&format!("    {p} {{ {entry} }}\n"));
    }
    s.push_str("}\n");
    std::fs::write(dir.join(name), s).unwrap();
}

/// The walls of a 0.3 m box of 3 × 3 × 3 cells heated on xMin at 400 K (T zeroGradient).
fn walls(dir: &Path, max_source: Option<f64>) -> (foam::PolyMesh, WallHeat) {
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(0.3), [3, 3, 3]);
    field(dir, "Twall", 300.0, "type fixedValue; value uniform 400;");
    field(dir, "T", 300.0, "type zeroGradient;");
    let w = WallHeat::read(dir, "Twall", &mesh, 0.9, max_source).unwrap();
    (mesh, w)
}

fn props() -> WallProperties {
    WallProperties {
        rho: RHO,
        nu: NU,
        lambda: LAMBDA,
        cp: CP,
    }
}

/// Uniform ε = 0.4, U = 1 m/s, d_p = 3 mm, T = 300 K, T_w = 400 K: G = ρ ε U = 0.48
/// kg/(m² s), Re = d_p G/(ρ ν) = 120, Pr = c_p ρ ν/λ = 0.47203125, j_H = 0.2 Re^−0.2 =
/// 0.0767703899274755, h = j_H c_p G/Pr^0.666 = 61.17865628826572 W/(m² K) (by hand, python,
/// PFM's wallHeatTransferYagi.C), so each 0.01 m² face of xMin gives h·0.01·100 =
/// 61.17865628826572 W to its cell; ε = 0.95 > voidfractionMax 0.9 gives nothing; `maxSource`
/// 40000 W/m³ (40 W per 1e-3 m³ cell) cuts each to 40 W and counts the rest.
#[test]
fn a_uniform_state_gets_yagis_heat_flux() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, w) = walls(dir.path(), None);
    assert_eq!(w.faces.len(), 9);
    let n = 27;
    let (u, t, dp) = (
        vec![V3::new(1.0, 0.0, 0.0); n],
        vec![300.0; n],
        vec![3e-3; n],
    );
    let volumes = voidage::VoidageMesh::new(&mesh)
        .unwrap()
        .cell_volumes()
        .to_vec();
    let fluid = |eps: &'static [f64]| WallFluid {
        eps,
        u: &u,
        t: &t,
        dp: &dp,
        volumes: &volumes,
    };
    let eps = Box::leak(vec![0.4; n].into_boxed_slice());
    let flow = w.flow(fluid(eps), props()).unwrap();
    let q = 61.178_656_288_265_72;
    let wall_cells: Vec<usize> = w.faces.iter().map(|f| f.cell).collect();
    for (c, &got) in flow.per_cell.iter().enumerate() {
        let want = if wall_cells.contains(&c) { q } else { 0.0 };
        assert!((got - want).abs() <= 1e-12 * q, "cell {c}: {got} vs {want}");
    }
    assert!((flow.total - 9.0 * q).abs() <= 1e-12 * q);
    assert_eq!(flow.clipped, 0.0);
    let dilute = Box::leak(vec![0.95; n].into_boxed_slice());
    assert_eq!(w.flow(fluid(dilute), props()).unwrap().total, 0.0);
    let (_, cut) = walls(dir.path(), Some(4e4));
    let flow = cut.flow(fluid(eps), props()).unwrap();
    assert!((flow.total - 9.0 * 40.0).abs() < 1e-9, "{}", flow.total);
    assert!(
        (flow.clipped - 9.0 * (q - 40.0)).abs() < 1e-9,
        "{}",
        flow.clipped
    );
}

fn settings() -> CouplerSettings {
    common::gunn_settings(Method::Divided)
}

/// A dense random bed in the box, the fluid streaming at 0.5 m/s with T varying in space;
/// the exchange's Tsource, summed here from the field, is the particles' heat taken from the
/// fluid plus the walls' heat (to 1e-12 of the heat moved), from_wall is the walls' heat
/// recomputed from the step's ε and the mean diameters, and it is not small.
#[test]
fn the_walls_heat_is_in_tsource_and_the_account() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, w) = walls(dir.path(), None);
    let n = 6000;
    let phi = 1.324_717_957_244_746_f64;
    let a = V3::new(1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi));
    let pos: Vec<V3> = (0..n)
        .map(|k| a.map(|x| 0.3 * (0.5 + k as f64 * x).fract()))
        .collect();
    let rad: Vec<f64> = (0..n)
        .map(|k| 0.004 + 0.002 * ((k * 7919) % 101) as f64 / 100.0)
        .collect();
    let (vel, ids, den) = (
        vec![V3::zeros(); n],
        (1..=n as u64).collect::<Vec<_>>(),
        vec![2500.0; n],
    );
    let temp: Vec<f64> = (0..n)
        .map(|k| 320.0 + 30.0 * (k as f64 * 0.71).sin())
        .collect();
    let particles = ParticleState {
        ids: &ids,
        position: &pos,
        velocity: &vel,
        radius: &rad,
        density: &den,
        temperature: Some(&temp),
    };
    let vm = voidage::VoidageMesh::new(&mesh).unwrap();
    let centres = vm.geometry().cell_centres.clone();
    let volumes = vm.cell_volumes().to_vec();
    let u = vec![V3::new(0.0, 0.0, 0.5); 27];
    let zero = vec![V3::zeros(); 27];
    let p = vec![0.0; 27];
    let t: Vec<f64> = centres
        .iter()
        .map(|c| 300.0 + 100.0 * c[0] + 50.0 * c[1])
        .collect();
    let fluid = FluidState {
        vorticity: None,
        ddt_u: None,
        turbulence: None,
        u: &u,
        p: &p,
        grad_p: &zero,
        div_tau: &zero,
        temperature: Some(&t),
    };
    let mut c = Coupler::new(&mesh, settings()).unwrap();
    c.set_bed_heat(couple::bed_heat::BedHeat {
        wall: Some(w.clone()),
        inter_grain: None,
    });
    let step = c.exchange(&particles, &fluid).unwrap();
    let h = step.heat.as_ref().unwrap();
    let given: f64 = h
        .tsource
        .iter()
        .zip(&volumes)
        .map(|(s, v)| s * RHO * CP * v)
        .sum();
    let sum_q: f64 = h.q.iter().sum();
    let scale: f64 = h.q.iter().map(|q| q.abs()).sum::<f64>() + h.account.from_wall.abs();
    let a = h.account;
    assert!(a.from_wall > 0.05 * scale, "{a:?}");
    assert!(
        (given - (a.from_wall - sum_q)).abs() <= 1e-12 * scale,
        "{given} vs {a:?}"
    );
    assert!(a.imbalance.abs() <= 1e-12 * scale, "{a:?}");
    // the walls' heat from the step's own ε and mean diameters
    let dp = couple::wall_heat::mean_diameter(&step.placement, &rad, 27);
    // cells without particles (ε = 1 > voidfractionMax) have d_p = 0 and no wall heat
    for (d, e) in dp.iter().zip(&step.voidage.epsilon) {
        assert_eq!(*d > 0.0, *e < 1.0, "{d} {e}");
    }
    let again = w
        .flow(
            WallFluid {
                eps: &step.voidage.epsilon,
                u: &u,
                t: &t,
                dp: &dp,
                volumes: &volumes,
            },
            props(),
        )
        .unwrap();
    assert!((again.total - a.from_wall).abs() <= 1e-12 * scale);
    // without wall heat the same exchange's Tsource lacks exactly the walls' part
    let plain = Coupler::new(&mesh, settings())
        .unwrap()
        .exchange(&particles, &fluid)
        .unwrap()
        .heat
        .unwrap();
    assert_eq!(plain.q, h.q);
    assert_eq!(plain.account.from_wall, 0.0);
    for (cell, (s0, s)) in plain.tsource.iter().zip(&h.tsource).enumerate() {
        let wall = again.per_cell[cell] / (RHO * CP * volumes[cell]);
        assert!(
            (s - s0 - wall).abs() <= 1e-12 * (s.abs() + 1.0),
            "cell {cell}"
        );
    }
}

#[test]
fn bad_wall_input_names_the_file_and_patch() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(0.3), [3, 3, 3]);
    field(dir.path(), "T", 300.0, "type zeroGradient;");
    let e = WallHeat::read(dir.path(), "Twall", &mesh, 0.9, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("Twall") && e.contains("missing"), "{e}");
    field(
        dir.path(),
        "Twall",
        300.0,
        "type fixedValue; value nonuniform List<scalar> 2 (400 410);",
    );
    let e = WallHeat::read(dir.path(), "Twall", &mesh, 0.9, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("boundaryField/xMin/value") && e.contains("9 temperatures"),
        "{e}"
    );
    field(
        dir.path(),
        "Twall",
        300.0,
        "type fixedValue; value uniform 400;",
    );
    field(
        dir.path(),
        "T",
        300.0,
        "type fixedValue; value uniform 350;",
    );
    let e = WallHeat::read(dir.path(), "Twall", &mesh, 0.9, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("/T") && e.contains("boundaryField/xMin") && e.contains("zeroGradient"),
        "{e}"
    );
}
