//! In-process LIGGGHTS (feature `link`, full tier) with particle heat: `fix heat/gran` holds
//! each particle's `Temp`, `fix couple/cfd/convection` adds the flux the coupler hands over
//! (`convectiveHeatFlux`, W) to `heatFlux` every step. Spheres that touch nothing then heat as
//! dT/dt = q/(m c) exactly: T = T0 + q t/(m c) after t = N Δt (the explicit update of
//! LIGGGHTS's scalar transport equation is exact for a constant flux).
#![cfg(feature = "link")]

use couple::ParticleSide;
use liggghts::LiggghtsDem;
use mesh::v3::V3;
use std::path::Path;

#[test]
fn a_constant_convective_flux_heats_each_particle_linearly() {
    if !testkit::tool("liggghts") {
        return;
    }
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/decks/heated.in");
    let dir = tempfile::tempdir().unwrap();
    let universe = mpi::initialize().expect("MPI initialised once");
    let mut lig = LiggghtsDem::open(&universe.world(), &deck, dir.path(), &[]).unwrap();
    let n = lig.state().len();
    assert_eq!(n, 3);
    assert_eq!(lig.state().temperature, Some(&[300.0; 3][..]));
    let m = 2000.0 * std::f64::consts::PI / 6.0 * 1e-9; // d = 1 mm
    let c = 500.0;
    let q = [1e-3, -2e-3, 0.0];
    let dt = lig.time_step();
    let zeros = vec![V3::zeros(); n];
    let mut expected = [300.0; 3];
    for round in 0..3 {
        lig.set_forces(&zeros, &[0.0; 3], &zeros).unwrap();
        // the flux changes between exchanges: each interval uses the one handed over last
        let scaled: Vec<f64> = q.iter().map(|x| x * (round + 1) as f64).collect();
        lig.set_heat_flux(&scaled).unwrap();
        lig.advance(100).unwrap();
        for (e, s) in expected.iter_mut().zip(&scaled) {
            *e += s * 100.0 * dt / (m * c);
        }
        let t = lig.state().temperature.unwrap().to_vec();
        for i in 0..n {
            assert!(
                (t[i] - expected[i]).abs() <= 1e-12 * expected[i],
                "round {round}, particle {i}: {} K vs {} K",
                t[i],
                expected[i]
            );
        }
    }
    // the heating is measurable, not round-off: 0.0030 W for 3 ms on 1 mg
    assert!(expected[0] - 300.0 > 1e-3, "{expected:?}");
    // a flux per particle of the wrong length or a non-finite one is refused, naming it
    assert!(lig.set_heat_flux(&[0.0; 2]).is_err());
    let e = lig.set_heat_flux(&[0.0, f64::NAN, 0.0]).unwrap_err();
    assert!(e.to_string().contains("particle 2"), "{e}");
}
