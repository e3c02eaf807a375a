//! The pneumatic conveyor's contact constructs (openfoam-cases/pneumatic-conveying: Hertz,
//! tangential history, SJKR cohesion between spheres and against its STL walls, the floor
//! screen, the ledge, the lid, the open outlet with `thermo_modify lost ignore`) on the native
//! DEM against Debian's LIGGGHTS 3.8.0 on one deck, `liggghts-inputs/conveyor_walls.in` (12
//! spheres in the case's `DEM/meshes/conveyor.stl`, no air; LIGGGHTS's dump in
//! `tests/fixtures/dem/conveyor_walls_liggghts.txt`, command in the README there).
//!
//! Fast tier: the native trajectories against the committed dump. Full tier: LIGGGHTS reruns
//! the deck and reproduces the dump.

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

mod common;

use common::snapshots;
use dem_io::Snapshot;

const DECK: &str = "conveyor_walls.in";
const DATA: &str = "conveyor_walls.data";
const DUMP: &str = "post/conveyor_walls.txt";

/// Columns compared, with the largest allowed difference relative to the column's largest
/// magnitude over the run. Positions 10⁻⁶, velocities and angular velocities 10⁻⁴; measured
/// (native vs LIGGGHTS): positions 7.6·10⁻⁸, velocities 1.5·10⁻⁵ — both for the cohesive pair
/// 5–6 settling on the screen, whose velocities there are 10⁻⁸ m/s of a 0.44 m/s scale; every
/// free impact (outer wall, core, ledge, lid, corner, the two pairs) within 5·10⁻⁹.
const COLUMNS: [(&str, f64); 9] = [
    ("x", 1e-6),
    ("y", 1e-6),
    ("z", 1e-6),
    ("vx", 1e-4),
    ("vy", 1e-4),
    ("vz", 1e-4),
    ("omegax", 1e-4),
    ("omegay", 1e-4),
    ("omegaz", 1e-4),
];

/// A working directory with the deck, its data file and `post/`.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("post")).unwrap();
    for f in [DECK, DATA] {
        std::fs::copy(testkit::liggghts_input(f), dir.path().join(f)).unwrap();
    }
    dir
}

/// `-var stl`: the case's STL walls, by absolute path.
fn stl() -> String {
    let path =
        testkit::repo_root().join("openfoam-cases/pneumatic-conveying/DEM/meshes/conveyor.stl");
    path.to_str().unwrap().to_string()
}

/// Per snapshot: id → the values of [`COLUMNS`].
fn by_id(s: &Snapshot) -> HashMap<u64, [f64; 9]> {
    let cols: Vec<&[f64]> = COLUMNS.iter().map(|(c, _)| s.column(c).unwrap()).collect();
    s.ids()
        .unwrap()
        .into_iter()
        .enumerate()
        .map(|(i, id)| (id, std::array::from_fn(|c| cols[c][i])))
        .collect()
}

/// Largest difference of each column over every sphere and snapshot, relative to the
/// column's largest magnitude; the same spheres must be present in every snapshot.
fn differences(a: &[Snapshot], b: &[Snapshot]) -> [f64; 9] {
    assert_eq!(a.len(), b.len(), "snapshot counts");
    let mut diff = [0.0f64; 9];
    let mut scale = [0.0f64; 9];
    for (sa, sb) in a.iter().zip(b) {
        assert_eq!(sa.timestep, sb.timestep);
        let (ma, mb) = (by_id(sa), by_id(sb));
        let mut ids: Vec<_> = ma.keys().collect();
        ids.sort();
        let mut other: Vec<_> = mb.keys().collect();
        other.sort();
        assert_eq!(ids, other, "spheres present at step {}", sa.timestep);
        for id in ids {
            for c in 0..9 {
                diff[c] = diff[c].max((ma[id][c] - mb[id][c]).abs());
                scale[c] = scale[c].max(ma[id][c].abs());
            }
        }
    }
    std::array::from_fn(|c| diff[c] / scale[c])
}

fn assert_same(native: &[Snapshot], reference: &[Snapshot]) {
    let d = differences(native, reference);
    for ((name, tol), rel) in COLUMNS.iter().zip(d) {
        eprintln!("{name}: relative difference {rel:.2e} (allowed {tol:.0e})");
        assert!(
            rel < *tol,
            "{name} differs by {rel:.3e} (allowed {tol:.0e})"
        );
    }
    // the sphere sent up the tube (id 7) left through the open top and is gone
    let last = by_id(native.last().unwrap());
    assert!(!last.contains_key(&7) && last.len() == 11);
}

fn run_native(dir: &Path) -> Vec<Snapshot> {
    let deck =
        liggghts_deck::Deck::read_with_vars(dir.join(DECK), &[("stl".to_string(), stl())]).unwrap();
    let sim = dem::Simulation::from_deck(&deck, dir).unwrap();
    assert_eq!(sim.lost(), 1, "one sphere leaves through the outlet");
    snapshots(dir.join(DUMP))
}

#[test]
fn conveyor_contacts_follow_the_liggghts_trajectories() {
    let dir = workdir();
    let native = run_native(dir.path());
    let reference = snapshots(testkit::fixture("dem/conveyor_walls_liggghts.txt"));
    assert_eq!(native.len(), 41);
    assert_same(&native, &reference);
}

/// Full tier: a serial LIGGGHTS run is deterministic and reproduces the committed dump.
#[test]
fn liggghts_reproduces_the_conveyor_walls_fixture() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = workdir();
    let mut c = Command::new("liggghts");
    c.args([
        "-in",
        DECK,
        "-var",
        "stl",
        &stl(),
        "-screen",
        "s.screen",
        "-log",
        "s.log",
    ]);
    testkit::run_ok(c, dir.path());
    let fresh = snapshots(dir.path().join(DUMP));
    let committed = snapshots(testkit::fixture("dem/conveyor_walls_liggghts.txt"));
    assert_eq!(differences(&fresh, &committed), [0.0; 9]);
}
