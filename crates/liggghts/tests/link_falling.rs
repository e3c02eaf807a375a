//! In-process LIGGGHTS (feature `link`, full tier): three spheres under gravity with
//! prescribed coupling forces, against the closed form and the native DEM given the same
//! forces.
#![cfg(feature = "link")]

use couple::ParticleSide;
use liggghts::{ForceMode, LiggghtsDem};
use std::path::Path;

const G: f64 = 9.81;
const STEPS: u64 = 100;
const EXCHANGES: usize = 20;

/// v(t) of m dv/dt = m g + F + β(u − v) from v0 (one component):
/// v = u + (m g + F)/β + (v0 − u − (m g + F)/β) e^{−βt/m}; v0 + (g + F/m) t for β = 0.
fn closed_form(v0: f64, u: f64, g: f64, f: f64, beta: f64, m: f64, t: f64) -> f64 {
    if beta == 0.0 {
        return v0 + (g + f / m) * t;
    }
    let vt = u + (m * g + f) / beta;
    vt + (v0 - vt) * (-beta * t / m).exp()
}

#[test]
fn falling_spheres_follow_the_closed_form_and_the_native_dem() {
    if !testkit::tool("liggghts") {
        return;
    }
    let universe = mpi::initialize().expect("MPI initialised once");
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/decks/falling.in");
    let dir = tempfile::tempdir().unwrap();
    let mut lig = LiggghtsDem::open(&universe.world(), &deck, dir.path(), &[]).unwrap();
    assert_eq!(lig.force_mode(), ForceMode::Implicit);
    assert_eq!(lig.skipped_runs().len(), 1);
    assert_eq!(lig.skipped_runs()[0].command, "run 2000");
    // the native DEM on the same deck without its trailing run (the coupler runs the steps)
    let stripped = liggghts::CouplingDeck::read(&deck, &[])
        .unwrap()
        .without_runs();
    let d = liggghts_deck::Deck::parse(&stripped, &deck, &[]).unwrap();
    let mut native = dem::Simulation::from_deck(&d, dir.path()).unwrap();
    native.clear_coupling();

    let m = 2000.0 * std::f64::consts::PI / 6.0 * 1e-9; // kg
    let beta_1 = m / 0.01; // τ = m/β = 10 ms
                           // particle 1: implicit drag towards an upward u_f; 2: explicit force only (β = 0);
                           // 3: both, with a sideways u_f
    let beta = [beta_1, 0.0, 0.5 * beta_1];
    let u_f = [[0.0, 0.0, 0.05], [0.0; 3], [0.02, 0.0, 0.01]].map(mesh::v3::V3::from);
    let f_ext = [[0.0; 3], [1e-6, 0.0, 2e-6], [0.0, -3e-6, 5e-6]].map(mesh::v3::V3::from);
    {
        let s = lig.state();
        assert_eq!(s.ids, [1, 2, 3]);
        assert_eq!(s.position[1], mesh::v3::V3::new(0.0, 0.0, 0.02));
        assert_eq!(s.radius, [0.0005; 3]);
        assert_eq!(s.density, [2000.0; 3]);
    }
    lig.set_forces(&f_ext, &beta, &u_f).unwrap();
    native.set_coupling(&f_ext, &beta, &u_f).unwrap();
    let dt = lig.time_step();
    assert_eq!(dt, 1e-5);
    let (mut worst_closed, mut worst_native) = (0.0f64, 0.0f64);
    for k in 1..=EXCHANGES {
        lig.advance(STEPS).unwrap();
        native.run(STEPS).unwrap();
        let t = k as f64 * STEPS as f64 * dt;
        assert!(
            approx::abs_diff_eq!(lig.time(), t, epsilon = 1e-12),
            "time {} vs {t}",
            lig.time()
        );
        let s = lig.state();
        for i in 0..3 {
            for c in 0..3 {
                let g = if c == 2 { -G } else { 0.0 };
                let exact = closed_form(0.0, u_f[i][c], g, f_ext[i][c], beta[i], m, t);
                let v = s.velocity[i][c];
                // velocity Verlet evaluates the drag with the half-step velocity: a lag of
                // dt/2 in the exponential, |Δv| ≤ (β dt / 2m)·|v0 − v_term| (+ round-off)
                let tol = if beta[i] == 0.0 {
                    1e-12
                } else {
                    let v_term = u_f[i][c] + (m * g + f_ext[i][c]) / beta[i];
                    beta[i] * dt / (2.0 * m) * v_term.abs() + 1e-12
                };
                let err = (v - exact).abs();
                worst_closed = worst_closed.max(err / tol);
                assert!(
                    err <= tol,
                    "particle {} comp {c} t {t}: {v} vs {exact}",
                    i + 1
                );
                let vn = native.particles.v[i][c];
                let xn = native.particles.x[i][c];
                worst_native = worst_native
                    .max((v - vn).abs())
                    .max((s.position[i][c] - xn).abs());
            }
        }
    }
    eprintln!("worst error / tolerance vs closed form {worst_closed:.3e}; worst |LIGGGHTS − native| {worst_native:.3e}");
    assert!(
        worst_native < 1e-12,
        "LIGGGHTS vs native DEM: {worst_native}"
    );
}
