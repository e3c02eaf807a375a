//! Heat through the link (issue 27): grainPisoFoam spawned with `SpawnOptions { heat: true }`
//! takes Tsource with each exchange and returns T.
//!
//! * A closed box (the cavity, lid 1 m/s) at uniform ε = 0.5 with a uniform Tsource S: every
//!   spatial term vanishes for a uniform T (the conservative convection minus T∇·φ, the
//!   laplacian), so ε dT/dt = S and T = T0 + S t/ε exactly (Euler is exact for a linear
//!   history). The fluid's heat ε ρ c_p V T grows by S ρ c_p V per second.
//! * The heat channel with a porous, cooled block on 2 solver ranks equals 1 rank.
//! * Heat on and off are checked against each other's API: a missing Tsource, a Tsource
//!   without heat and a case without `0/T` are clear errors. (Heat over several coupler
//!   ranks: `link_sparse_heat.rs`.)

mod common;
use common::*;
use foam_link::{protocol::FieldsIn, OpenFoamFluid, SpawnOptions};
use foam_solver_tests::TestCase;
use mesh::v3::V3;

const HEAT: SpawnOptions = SpawnOptions {
    heat: true,
    cfdem_ksl: None,
    vorticity: false,
    ddt_u: false,
};

#[test]
fn heat_through_the_link() {
    let Some(solver) = tools() else {
        return;
    };
    let universe = universe();
    let world = universe.world();
    closed_box_heats_as_s_over_eps(&world, &solver);
    two_ranks_equal_one_rank(&world, &solver);
    misuse_is_refused(&world, &solver);
}

/// The cavity with T (zeroGradient everywhere, 300 K), Pr and a T solver.
fn heated_cavity() -> TestCase {
    let case = TestCase::new("cavity");
    std::fs::write(
        case.dir.join("0/T"),
        "FoamFile { version 2.0; format ascii; class volScalarField; object T; }\n\
         dimensions [0 0 0 1 0 0 0];\ninternalField uniform 300;\nboundaryField\n{\n\
         movingWall { type zeroGradient; }\nfixedWalls { type zeroGradient; }\n\
         frontAndBack { type empty; }\n}\n",
    )
    .unwrap();
    append(&case, "constant/transportProperties", "Pr 0.7;\n");
    case.edit(
        "system/fvSchemes",
        "div(phi,U)",
        "div(phi,T)      Gauss limitedLinear 1;\n    div(phi,U)",
    );
    case.edit(
        "system/fvSolution",
        "U { solver smoothSolver;",
        "T { solver PBiCGStab; preconditioner DILU; tolerance 1e-14; relTol 0; }\n    \
         U { solver smoothSolver;",
    );
    case
}

fn append(case: &TestCase, rel: &str, text: &str) {
    let path = case.dir.join(rel);
    let old = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, old + text).unwrap();
}

/// T = T0 + S t/ε in every cell (module docs): 300 K, S = 2 K/s, ε = 0.5, two intervals of
/// 5 steps of 5 ms → 300.2 K, to 1e-10 K (T solved to 1e-14).
fn closed_box_heats_as_s_over_eps(
    world: &mpi::topology::SimpleCommunicator,
    solver: &std::path::Path,
) {
    let case = heated_cavity();
    let mut fluid = OpenFoamFluid::spawn_with(world, &case.dir, 1, solver, HEAT).unwrap();
    assert!(fluid.heat());
    let start = couple::FluidSide::state(&fluid)
        .temperature
        .expect("T with heat on");
    assert!(start.iter().all(|&t| t == 300.0), "the start T is 0/T");
    let n = start.len();
    let eps = vec![0.5; n];
    let zeros = vec![0.0; n];
    let zeros_v = vec![V3::zeros(); n];
    let s = vec![2.0; n];
    let fields = FieldsIn {
        eps_old: &eps,
        eps_new: &eps,
        ksl: &zeros,
        us: &zeros_v,
        f: &zeros_v,
    };
    for _ in 0..2 {
        fluid.set_fields_with_heat(&fields, Some(&s)).unwrap();
        fluid.advance_interval(0.025).unwrap();
    }
    let t = fluid.temperature().unwrap();
    let expected = 300.0 + 2.0 * 0.05 / 0.5;
    let worst = t.iter().map(|x| (x - expected).abs()).fold(0.0, f64::max);
    eprintln!(
        "closed box: T {:.12} K, expected {expected} K, max error {worst:.2e} K",
        t[0]
    );
    assert!(worst < 1e-10, "max |T − T0 − S t/ε| = {worst:e} K");
    // The lid moved the fluid: the uniform T survived a real flux.
    let u = couple::FluidSide::state(&fluid).u;
    assert!(u.iter().any(|v| v.norm() > 0.1));
    let (sent, received) = foam_link::protocol::advance_bytes_with(n, 1, 3, true);
    let stats = fluid.stats();
    assert_eq!(stats.bytes_sent, 2 * sent as u64);
    assert_eq!(stats.bytes_received, 2 * received as u64);

    fluid.write().unwrap();
    fluid.finish().unwrap();
    let written = case.scalars("0.05", "T");
    assert!(written.iter().all(|x| (x - expected).abs() < 1e-10));
    assert!(case.dir.join("0.05/Tsource").is_file() && case.dir.join("0.05/alphat").is_file());
    falling_voidage_keeps_the_rate_s_over_eps(world, solver);
}

/// ε falls from 0.5 to 0.25 over an interval (blended per step), the flow held at rest
/// (`solveFlow off`, U = 0, φ = 0; the lid-driven box itself does not survive a uniform fall
/// of ε with continuity lacking ∂ε/∂t, heat or not): the −T ∂ε/∂t term keeps the uniform T's
/// rate at S/ε, and Euler on ε dT/dt = S takes ε at the old time, so step k adds S Δt/ε_(k−1),
/// ε_(k−1) = 0.5, 0.45, 0.4, 0.35, 0.3 (without that term T would also change by −T Δε/ε,
/// about +30 K per step here). First an interval at ε = 0.5: 300 K + S·0.025 s/0.5.
fn falling_voidage_keeps_the_rate_s_over_eps(
    world: &mpi::topology::SimpleCommunicator,
    solver: &std::path::Path,
) {
    let case = heated_cavity();
    append(&case, "constant/couplingProperties", "solveFlow off;\n");
    case.edit("0/U", "uniform (1 0 0)", "uniform (0 0 0)");
    let mut fluid = OpenFoamFluid::spawn_with(world, &case.dir, 1, solver, HEAT).unwrap();
    let n = fluid.rank_map().n_cells();
    let (half, quarter) = (vec![0.5; n], vec![0.25; n]);
    let zeros = vec![0.0; n];
    let zeros_v = vec![V3::zeros(); n];
    let s = vec![2.0; n];
    for eps_new in [&half, &quarter] {
        let fields = FieldsIn {
            eps_old: &half,
            eps_new,
            ksl: &zeros,
            us: &zeros_v,
            f: &zeros_v,
        };
        fluid.set_fields_with_heat(&fields, Some(&s)).unwrap();
        fluid.advance_interval(0.025).unwrap();
    }
    let gain: f64 = (0..5).map(|k| 2.0 * 0.005 / (0.5 - 0.05 * k as f64)).sum();
    let expected = 300.0 + 2.0 * 0.025 / 0.5 + gain;
    let t = fluid.temperature().unwrap();
    let worst = t.iter().map(|x| (x - expected).abs()).fold(0.0, f64::max);
    eprintln!(
        "closed box, falling ε: T {:.12} K, expected {expected:.12} K, max error {worst:.2e} K",
        t[0]
    );
    assert!(worst < 1e-10, "falling ε: max error {worst:e} K");
    fluid.finish().unwrap();
}

/// The heat channel, a porous block 40 mm < x < 60 mm (ε 0.6, Ksl 500 kg/(m³ s)) cooled by
/// Tsource = −5 K/s, three intervals of 10 steps of 10 ms, on 1 and 2 solver ranks (simple
/// 2 × 1 × 1 cuts through the block): T and U agree to 1e-8 (processor-local
/// preconditioners change the iterates, not the converged solution; as link_parallel).
fn two_ranks_equal_one_rank(world: &mpi::topology::SimpleCommunicator, solver: &std::path::Path) {
    let case = TestCase::new("heat-channel");
    let channel = HeatChannel::new(&case);
    let block = &channel.block;
    let run = |np: usize| -> (Vec<f64>, Vec<V3>, [foam_link::PatchFlow; 2]) {
        let copy = case.duplicate();
        let mut fluid = OpenFoamFluid::spawn_with(world, &copy.dir, np, solver, HEAT).unwrap();
        for i in 0..3 {
            fluid
                .set_fields_with_heat(&channel.fields(i), Some(&channel.tsource))
                .unwrap();
            fluid.advance_interval(0.1).unwrap();
        }
        let t = fluid.temperature().unwrap().to_vec();
        let u = couple::FluidSide::state(&fluid).u.to_vec();
        let patches = [
            fluid.patch("inlet").unwrap(),
            fluid.patch("outlet").unwrap(),
        ];
        fluid.finish().unwrap();
        (t, u, patches)
    };
    let (t1, u1, [inlet, outlet]) = run(1);
    let (t2, u2, [_, outlet2]) = run(2);
    // The inlet's T is fixed at 1 K: its mixing-cup T is 1 (flux −U A = −1e-7 m³/s); the
    // outlet's lies between the coldest and the hottest boundary value, and is the same on
    // 2 ranks.
    let mean_t = |p: &foam_link::PatchFlow| p.t_flux.expect("heat on") / p.flux;
    eprintln!(
        "inlet {inlet:?}; outlet mixing-cup T {} K (2 ranks {} K)",
        mean_t(&outlet),
        mean_t(&outlet2)
    );
    assert!((inlet.flux + 1e-7).abs() < 1e-15, "{inlet:?}");
    assert!((mean_t(&inlet) - 1.0).abs() < 1e-12, "{inlet:?}");
    assert!(
        mean_t(&outlet) > -1.3 && mean_t(&outlet) < 1.0,
        "{outlet:?}"
    );
    assert!((mean_t(&outlet2) - mean_t(&outlet)).abs() < 1e-8);
    let dt = rel_diff(&t2, &t1);
    let du = rel_diff_v(&u2, &u1);
    let cooled = block
        .iter()
        .zip(&t1)
        .filter(|(b, _)| **b)
        .map(|(_, t)| *t)
        .fold(f64::MAX, f64::min);
    eprintln!("heat channel, 2 ranks vs 1: T {dt:.2e}, U {du:.2e}; min T in the block {cooled}");
    // The block is cooled below the initial 0 K by −5 K/s over 0.3 s (÷ ε, minus what flows in).
    assert!(cooled < -0.5, "min T in the block {cooled}");
    assert!(dt < 1e-8 && du < 1e-8, "T {dt:e}, U {du:e}");
}

/// Heat without Tsource, Tsource without heat, heat on a case without `0/T`: each a clear
/// error.
fn misuse_is_refused(world: &mpi::topology::SimpleCommunicator, solver: &std::path::Path) {
    let case = TestCase::new("heat-channel");
    let n = case.mesh().0.n_cells;
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
    let mut fluid = OpenFoamFluid::spawn_with(world, &case.dir, 1, solver, HEAT).unwrap();
    let err = fluid.set_fields(&fields).unwrap_err().to_string();
    assert!(err.contains("Tsource"), "{err}");
    let bad = vec![f64::NAN; n];
    let err = fluid
        .set_fields_with_heat(&fields, Some(&bad))
        .unwrap_err()
        .to_string();
    assert!(err.contains("Tsource"), "{err}");
    fluid.finish().unwrap();

    let plain = TestCase::new("cavity");
    let mut fluid = OpenFoamFluid::spawn(world, &plain.dir, 1, solver).unwrap();
    assert!(couple::FluidSide::state(&fluid).temperature.is_none());
    let m = fluid.rank_map().n_cells();
    let (one, zero, zero_v) = (vec![1.0; m], vec![0.0; m], vec![V3::zeros(); m]);
    let plain_fields = FieldsIn {
        eps_old: &one,
        eps_new: &one,
        ksl: &zero,
        us: &zero_v,
        f: &zero_v,
    };
    let err = fluid
        .set_fields_with_heat(&plain_fields, Some(&zero))
        .unwrap_err()
        .to_string();
    assert!(err.contains("without heat"), "{err}");
    fluid.finish().unwrap();

    let no_t = TestCase::new("heat-channel");
    std::fs::remove_file(no_t.dir.join("0/T")).unwrap();
    let err = OpenFoamFluid::spawn_with(world, &no_t.dir, 1, solver, HEAT)
        .err()
        .expect("heat without 0/T fails")
        .to_string();
    eprintln!("heat without 0/T: {err}");
    assert!(err.contains("0/T"), "{err}");
}
