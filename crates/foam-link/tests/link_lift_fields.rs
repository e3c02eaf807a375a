//! The fields added mass and lift need, through the link (issue 28): grainPisoFoam spawned with
//! `SpawnOptions { vorticity: true, ddt_u: true }` replies ∇ × U and DU/Dt with every state.
//!
//! Case: `foam-solver-tests`' lid-driven cavity (16 × 16 skewed cells, lid 1 m/s, ν 0.01 m²/s,
//! deltaT 5 ms) from rest, ε = 1, no exchange, three coupling intervals of one PISO step each
//! (pressure solved to relTol 0).
//!
//! * ∇ × U against Gauss's theorem on grainPisoFoam's own U: (1/V) Σ_f S_f × U_f with linear
//!   face values and the cavity's boundary values (lid (1, 0, 0), walls 0; the empty front and
//!   back faces cancel in pairs), [`fv::fvc::curl`]: to 1e-10 of max |ω| (round-off).
//! * At the start (U = 0 inside, the lid moving) ω is that of the lid's layer alone, and
//!   DU/Dt = 0 (no old field: ∂U/∂t = 0; φ = 0).
//! * ∇ × U and DU/Dt against the native solver (`fv`) on the same case with the same steps,
//!   DU/Dt = (U − U°)/Δt + (1/V) Σ_f φ_f U_f as `runner::native::NativeFluid` forms it: the two
//!   solvers' U differ by δ_U (max-norm, relative; printed); ω, a linear function of U, must
//!   agree to 3 δ_U, and DU/Dt — whose ∂U/∂t divides one step's change by Δt — to
//!   3 δ_U · max|U| / max|U − U°| (the relative error of one step's change).
//! * Without the options the messages are the old ones (the byte counts of
//!   [`foam_link::protocol::advance_bytes`]), and a sparse run with them is refused.

mod common;
use common::*;
use foam_link::{protocol::FieldsIn, OpenFoamFluid, SpawnOptions};
use foam_solver_tests::TestCase;
use mesh::v3::V3;

const LIFT: SpawnOptions = SpawnOptions {
    heat: false,
    cfdem_ksl: None,
    vorticity: true,
    ddt_u: true,
};

/// The cavity's boundary values for the cell field `u`: the lid (1, 0, 0), the fixed walls 0,
/// and the owner's value on the empty faces.
fn cavity_boundary(g: &fv::FvGeometry, u: &[V3]) -> Vec<V3> {
    let mut b = vec![V3::zeros(); g.n_boundary()];
    for p in &g.patches {
        for f in p.faces.clone() {
            b[f - g.n_internal] = match p.name.as_str() {
                "movingWall" => V3::new(1.0, 0.0, 0.0),
                "fixedWalls" => V3::zeros(),
                _ => u[g.owner[f] as usize],
            };
        }
    }
    b
}

fn max_norm(v: &[V3]) -> f64 {
    v.iter().map(|x| x.norm()).fold(0.0, f64::max)
}

#[test]
fn vorticity_and_ddt_u_through_the_link() {
    let Some(solver) = tools() else {
        return;
    };
    let universe = universe();
    let world = universe.world();
    let case = TestCase::new("cavity");
    case.edit("system/fvSolution", "relTol 0.01;", "relTol 0;");
    let native_case = case.duplicate();
    let mut fluid = OpenFoamFluid::spawn_with(&world, &case.dir, 1, &solver, LIFT).unwrap();
    let mut native = fv::Fluid::from_case(&native_case.dir).unwrap();
    let g = native.geometry().clone();
    let n = g.n_cells;

    // the start: ω of the lid's layer, DU/Dt = 0
    let start = couple::FluidSide::state(&fluid);
    let w0 = start.vorticity.expect("ω asked for").to_vec();
    let a0 = start.ddt_u.expect("DU/Dt asked for").to_vec();
    let w0_ref = fv::fvc::curl(&g, start.u, &cavity_boundary(&g, start.u));
    assert!(max_norm(&w0_ref) > 1.0);
    assert!(
        rel_diff_v(&w0, &w0_ref) < 1e-10,
        "{:e}",
        rel_diff_v(&w0, &w0_ref)
    );
    assert!(a0.iter().all(|a| a.norm() == 0.0), "DU/Dt at the start");

    let ones = vec![1.0; n];
    let zeros = vec![0.0; n];
    let zeros_v = vec![V3::zeros(); n];
    let fields = FieldsIn {
        eps_old: &ones,
        eps_new: &ones,
        ksl: &zeros,
        us: &zeros_v,
        f: &zeros_v,
    };
    native.set_voidage(&ones, &ones).unwrap();
    for step in 1..=3 {
        fluid.set_fields(&fields).unwrap();
        fluid.advance_interval(DT).unwrap();
        let u_before = native.u().to_vec();
        native.advance(DT).unwrap();
        let (u_n, u_nb) = (native.u(), native.u_boundary());
        let w_native = fv::fvc::curl(&g, u_n, u_nb);
        let mut a_native = fv::fvc::div_flux_linear(&g, native.phi(), u_n, u_nb);
        for ((a, u), b) in a_native.iter_mut().zip(u_n).zip(&u_before) {
            *a += (*u - *b) / DT;
        }
        let s = couple::FluidSide::state(&fluid);
        let (w, a) = (s.vorticity.unwrap(), s.ddt_u.unwrap());
        let w_ref = fv::fvc::curl(&g, s.u, &cavity_boundary(&g, s.u));
        let gauss = rel_diff_v(w, &w_ref);
        let du = rel_diff_v(s.u, u_n);
        let dw = rel_diff_v(w, &w_native);
        let da = rel_diff_v(a, &a_native);
        let change: Vec<V3> = u_n.iter().zip(&u_before).map(|(x, y)| x - y).collect();
        let amplification = max_norm(u_n) / max_norm(&change);
        eprintln!(
            "step {step}: ω vs Gauss on its U {gauss:.2e}; vs native: U {du:.2e}, ω {dw:.2e}, \
             DU/Dt {da:.2e} (max |ω| {:.3} 1/s, max |DU/Dt| {:.3} m/s², U/ΔU {amplification:.2})",
            max_norm(w),
            max_norm(a)
        );
        assert!(gauss < 1e-10, "step {step}: ω vs Gauss {gauss:e}");
        assert!(dw < 3.0 * du, "step {step}: ω {dw:e} vs U {du:e}");
        assert!(
            da < 3.0 * du * amplification,
            "step {step}: DU/Dt {da:e} vs U {du:e} × {amplification}"
        );
    }
    fluid.finish().unwrap();

    // without the options: the old messages
    let plain = case.duplicate();
    let mut fluid = OpenFoamFluid::spawn(&world, &plain.dir, 1, &solver).unwrap();
    assert!(couple::FluidSide::state(&fluid).vorticity.is_none());
    fluid.set_fields(&fields).unwrap();
    fluid.advance_interval(DT).unwrap();
    let (sent, received) = foam_link::protocol::advance_bytes(n, 1, 3);
    assert_eq!(fluid.stats().bytes_sent, sent as u64);
    assert_eq!(fluid.stats().bytes_received, received as u64);
    fluid.finish().unwrap();

    // the sparse exchange does not carry them
    let e = OpenFoamFluid::spawn_ranked_with(&world, &plain.dir, 1, &solver, LIFT)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("sparse exchange"), "{e}");
}
