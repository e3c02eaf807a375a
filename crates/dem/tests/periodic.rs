//! Periodic boxes (`boundary p f f`) against Debian's LIGGGHTS 3.8.0 on the same deck
//! (`liggghts-inputs/periodic.in`): two spheres collide obliquely across the periodic x face,
//! and one of them crosses x = 0 afterwards (image counter ix = −1). LIGGGHTS's dump of every
//! 100th step (17 significant digits) is `tests/fixtures/dem/periodic_liggghts.txt`.
//!
//! Fast tier: the native run against that file. Full tier: LIGGGHTS reruns the deck and must
//! reproduce it exactly (a serial LIGGGHTS run is deterministic).

use std::path::Path;
use std::process::Command;

use dem_io::{read_snapshot, ReadOptions, Selection, Snapshot};

/// Snapshots in the dump (steps 0, 100, …, 6000).
const SNAPSHOTS: usize = 61;

/// Relative agreement with LIGGGHTS: the same Hertz–Mindlin arithmetic, except that LIGGGHTS
/// measures a pair across the face from a ghost copy on each side (`newton off`), so the last
/// bits of a contact's force differ (measured 1e-14 of the velocity scale, 4e-14 of ω).
const TOL: f64 = 1e-11;

fn snapshots(path: &Path) -> Vec<Snapshot> {
    (0..SNAPSHOTS)
        .map(|k| read_snapshot(path, &ReadOptions::default(), Selection::Index(k)).unwrap())
        .collect()
}

/// Runs the deck natively in `dir` (a copy of `liggghts-inputs`' two files and `post/`).
fn native(dir: &Path) -> Vec<Snapshot> {
    setup(dir);
    let deck = liggghts_deck::Deck::read(dir.join("periodic.in")).unwrap();
    let sim = dem::Simulation::from_deck(&deck, dir).unwrap();
    assert_eq!(sim.particles.len(), 2);
    assert_eq!(sim.lost(), 0);
    snapshots(&dir.join("post/periodic.txt"))
}

fn setup(dir: &Path) {
    std::fs::create_dir_all(dir.join("post")).unwrap();
    for f in ["periodic.in", "periodic_pair.data"] {
        std::fs::copy(testkit::liggghts_input(f), dir.join(f)).unwrap();
    }
}

/// Every column of every snapshot within [`TOL`] of the column's largest magnitude; the
/// image counters equal.
fn assert_same(native: &[Snapshot], reference: &[Snapshot]) {
    assert_eq!(native.len(), reference.len());
    let cols = [
        "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz",
    ];
    for c in cols {
        let values = |s: &[Snapshot]| -> Vec<Vec<f64>> {
            s.iter().map(|x| x.column(c).unwrap().to_vec()).collect()
        };
        let (a, b) = (values(native), values(reference));
        let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = a
            .iter()
            .flatten()
            .zip(b.iter().flatten())
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        eprintln!("{c}: largest difference {worst:.3e} of scale {scale:.3e}");
        assert!(worst <= TOL * scale, "{c}: {worst} > {TOL} × {scale}");
    }
    for (a, b) in native.iter().zip(reference) {
        assert_eq!(a.timestep, b.timestep);
        for c in ["id", "ix", "iy", "iz"] {
            assert_eq!(a.column(c).unwrap(), b.column(c).unwrap(), "{c} at step {}", a.timestep);
        }
    }
    // the test covers what it claims: a contact (spin) and a crossing (ix = −1 at the end)
    let last = reference.last().unwrap();
    assert!(last.column("omegaz").unwrap().iter().all(|w| w.abs() > 10.0));
    assert_eq!(last.column("ix").unwrap()[0], -1.0);
}

#[test]
fn collision_across_the_periodic_face_matches_liggghts() {
    let dir = tempfile::tempdir().unwrap();
    let reference = snapshots(&testkit::fixture("dem/periodic_liggghts.txt"));
    assert_same(&native(dir.path()), &reference);
}

#[test]
fn liggghts_reproduces_the_periodic_fixture() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let mut c = Command::new("liggghts");
    c.args(["-in", "periodic.in", "-screen", "s.screen", "-log", "s.log"]);
    testkit::run_ok(c, dir.path());
    let fresh = std::fs::read(dir.path().join("post/periodic.txt")).unwrap();
    let committed = std::fs::read(testkit::fixture("dem/periodic_liggghts.txt")).unwrap();
    assert!(fresh == committed, "LIGGGHTS's periodic.txt differs from the fixture");
}
