//! In-process LIGGGHTS (feature `link`, full tier) with the settling case's deck, whose force
//! fix is the explicit `couple/cfd/force`: β(u_f − v) is frozen at each exchange's velocity.
#![cfg(feature = "link")]

use couple::ParticleSide;
use liggghts::{ForceMode, LiggghtsDem};
use std::path::Path;

#[test]
fn explicit_force_fix_freezes_the_drag_at_the_exchange() {
    if !testkit::tool("liggghts") {
        return;
    }
    let deck = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../openfoam-cases/settling/DEM/in.liggghts_run");
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("post")).unwrap();
    let universe = mpi::initialize().expect("MPI initialised once");
    let mut lig = LiggghtsDem::open(&universe.world(), &deck, dir.path(), &[]).unwrap();
    assert_eq!(lig.force_mode(), ForceMode::FrozenAtExchange);
    let m = 3000.0 * std::f64::consts::PI / 6.0 * 1e-12; // d = 0.1 mm
    let beta = m / 0.005;
    let u = mesh::v3::V3::new(0.0, 0.1, 0.0);
    let dt = lig.time_step();
    let t = 100.0 * dt;
    let mut v0 = lig.state().velocity[0];
    assert_eq!(v0, mesh::v3::V3::zeros());
    let mut f_old = None;
    for _ in 0..3 {
        lig.set_forces(&[mesh::v3::V3::zeros()], &[beta], &[u])
            .unwrap();
        lig.advance(100).unwrap();
        let v = lig.state().velocity[0];
        // constant force F over the interval: v = v0 + (g + F/m) t (velocity Verlet is exact),
        // F = β(u − v0); after the first run (`pre no`) the first half kick still uses the
        // force of the previous step, F_old: + (dt/2)(F_old − F)/m
        let f = beta * (u[1] - v0[1]);
        let lag = f_old.map_or(0.0, |fo: f64| 0.5 * dt * (fo - f) / m);
        let expected = v0[1] + (-9.81 + f / m) * t + lag;
        f_old = Some(f);
        assert!(
            approx::abs_diff_eq!(v[1], expected, epsilon = 1e-12 * expected.abs()),
            "{v:?} vs {expected}"
        );
        assert_eq!([v[0], v[2]], [0.0, 0.0]);
        v0 = v;
    }
}
