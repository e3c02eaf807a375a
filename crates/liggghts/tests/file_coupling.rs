//! File coupling with the `liggghts` binary (full tier): two exchanges of three falling
//! spheres against the native DEM given the same forces, and a LIGGGHTS that dies while the
//! coupler waits. LIGGGHTS polls for files every 10 s, so this takes about 25 s.

use approx::assert_abs_diff_eq;
use couple::ParticleSide;
use liggghts::{FileDem, FileOptions, ForceMode};
use std::path::Path;

fn falling_deck() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/decks/falling.in")
}

#[test]
fn two_exchanges_match_the_native_dem() {
    if !testkit::tool("liggghts") {
        return;
    }
    let deck = falling_deck();
    let dir = tempfile::tempdir().unwrap();
    let mut lig = FileDem::open(&deck, dir.path(), &[], FileOptions::new(200)).unwrap();
    assert_eq!(lig.force_mode(), ForceMode::Implicit);
    assert_eq!(lig.rewritten().line, 27);
    let copy = std::fs::read_to_string(&lig.rewritten().copy).unwrap();
    assert!(copy.contains(&format!(
        "couple/cfd couple_every 100 file {}",
        lig.rewritten().prefix
    )));
    // the initial state comes from the full-precision dump, ordered by tag
    {
        let s = lig.state();
        assert_eq!(s.ids, [1, 2, 3]);
        assert_eq!(s.position[2], mesh::v3::V3::new(0.02, 0.0, 0.02));
        assert_eq!(s.density, [2000.0; 3]);
    }
    let stripped = liggghts::CouplingDeck::read(&deck, &[])
        .unwrap()
        .without_runs();
    let d = liggghts_deck::Deck::parse(&stripped, &deck, &[]).unwrap();
    let mut native = dem::Simulation::from_deck(&d, dir.path()).unwrap();
    let m = 2000.0 * std::f64::consts::PI / 6.0 * 1e-9;
    let beta = [m / 0.01, 0.0, 0.5 * m / 0.01];
    let u_f = [[0.0, 0.0, 0.05], [0.0; 3], [0.02, 0.0, 0.01]].map(mesh::v3::V3::from);
    let f_ext = [[0.0; 3], [1e-6, 0.0, 2e-6], [0.0, -3e-6, 5e-6]].map(mesh::v3::V3::from);
    // LIGGGHTS takes forces only at exchanges: the first 100 steps fall freely
    native.clear_coupling();
    for k in 0..2 {
        lig.advance(100).unwrap();
        native.run(100).unwrap();
        assert_abs_diff_eq!(lig.time(), (k + 1) as f64 * 1e-3, epsilon = 1e-15);
        let s = lig.state();
        assert_eq!(s.ids, [1, 2, 3]);
        for i in 0..3 {
            for c in 0..3 {
                // the files carry 6 significant digits
                let (v, vn) = (s.velocity[i][c], native.particles.v[i][c]);
                assert!(
                    approx::abs_diff_eq!(v, vn, epsilon = 5e-6 * vn.abs() + 1e-15),
                    "v {v} vs {vn}"
                );
                let (x, xn) = (s.position[i][c], native.particles.x[i][c]);
                assert!(
                    approx::abs_diff_eq!(x, xn, epsilon = 5e-6 * xn.abs() + 1e-15),
                    "x {x} vs {xn}"
                );
            }
        }
        lig.set_forces(&f_ext, &beta, &u_f).unwrap();
        native.set_coupling(&f_ext, &beta, &u_f).unwrap();
    }
    assert_eq!(lig.exchanges(), 2);
    lig.finish().unwrap();
}

#[test]
fn a_liggghts_that_dies_is_an_error_with_its_log() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(falling_deck()).unwrap().replace(
        "fix             integr all nve/sphere",
        "fix integr all nve/nonsense",
    );
    let deck = dir.path().join("in.broken");
    std::fs::write(&deck, text).unwrap();
    let mut lig = FileDem::open(&deck, dir.path(), &[], FileOptions::new(200)).unwrap();
    let t = std::time::Instant::now();
    let e = lig.advance(100).unwrap_err().to_string();
    assert!(e.contains("exited with status"), "{e}");
    assert!(e.contains("ERROR"), "{e}");
    assert!(t.elapsed().as_secs() < 30);
}
