//! STL mesh walls of the native DEM against Debian's LIGGGHTS 3.8.0 on the same decks
//! (`liggghts-inputs/mesh_bounce.in`, `mesh_pour.in`; LIGGGHTS's output in
//! `tests/fixtures/dem/`, see the README there).
//!
//! Fast tier: the native runs against the committed LIGGGHTS dumps — one sphere bouncing and
//! rolling on a tilted plane of 8 triangles (deterministic: the whole trajectory), and 300
//! spheres poured into an STL box (statistical: bed top, solid fraction, centre of mass, all
//! inside). Full tier: LIGGGHTS reruns both decks and reproduces the committed dumps.

mod common;

use std::path::Path;
use std::process::Command;

use common::{bed, last_snapshot, meshes, snapshots};
use dem::trimesh::stl::ascii_stl;
use dem_io::Snapshot;

/// The committed STL files are the generated geometries (`FOAMGRAIN_WRITE_MESHES=1` writes
/// them).
#[test]
fn committed_meshes_are_the_generated_ones() {
    let dir = testkit::liggghts_input("meshes");
    for (name, tris) in [("plane", meshes::plane()), ("box", meshes::open_box())] {
        let text = ascii_stl(name, &tris);
        let path = dir.join(format!("{name}.stl"));
        if std::env::var_os("FOAMGRAIN_WRITE_MESHES").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text, "{path:?}");
    }
}

/// A working directory with the decks' meshes and `post/`.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("post")).unwrap();
    std::fs::create_dir_all(dir.path().join("meshes")).unwrap();
    for m in ["plane.stl", "box.stl"] {
        std::fs::copy(
            testkit::liggghts_input("meshes").join(m),
            dir.path().join("meshes").join(m),
        )
        .unwrap();
    }
    dir
}

fn vars(v: &[(&str, &str)]) -> Vec<(String, String)> {
    v.iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

fn run_native(deck: &str, v: &[(&str, &str)], dir: &Path) -> dem::Simulation {
    let deck =
        liggghts_deck::Deck::read_with_vars(testkit::liggghts_input(deck), &vars(v)).unwrap();
    dem::Simulation::from_deck(&deck, dir).unwrap()
}

fn run_liggghts(deck: &str, v: &[(&str, &str)], dir: &Path) {
    std::fs::copy(testkit::liggghts_input(deck), dir.join(deck)).unwrap();
    let mut c = Command::new("liggghts");
    c.args(["-in", deck, "-screen", "s.screen", "-log", "s.log"]);
    for (k, val) in v {
        c.args(["-var", k, val]);
    }
    testkit::run_ok(c, dir);
}

const BOUNCE_COLUMNS: [&str; 9] = [
    "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz",
];

/// Largest difference of each column between two trajectories, relative to the column's
/// largest magnitude.
fn trajectory_difference(a: &[Snapshot], b: &[Snapshot]) -> Vec<(&'static str, f64)> {
    assert_eq!(a.len(), b.len());
    BOUNCE_COLUMNS
        .iter()
        .map(|&c| {
            let col = |s: &Snapshot| s.column(c).unwrap()[0];
            let scale = a.iter().map(|s| col(s).abs()).fold(0.0, f64::max);
            let d = a
                .iter()
                .zip(b)
                .map(|(x, y)| {
                    assert_eq!(x.timestep, y.timestep);
                    (col(x) - col(y)).abs()
                })
                .fold(0.0, f64::max);
            (c, d / scale)
        })
        .collect()
}

/// The native trajectory is LIGGGHTS's: positions, velocities and angular velocities every
/// 1000 steps over 80,000 (bounces, then rolling across the shared edges x = 0 and y = 0 and
/// the diagonals) within 10⁻¹⁰ of each column's largest value (measured: 3·10⁻¹² at most, vz). The two differ in round-off only
/// (LIGGGHTS rotates the vertices by quaternion, normalises the contact normal from the
/// distance vector), which the bounces amplify.
fn assert_same_bounce(native: &[Snapshot], reference: &[Snapshot]) {
    let d = trajectory_difference(native, reference);
    eprintln!("bounce, relative differences: {d:?}");
    for (c, rel) in d {
        assert!(rel < 1e-10, "{c} differs by {rel}");
    }
    // the sphere crossed the edge x = 0 between the triangles while rolling
    let x = |s: &Snapshot| s.column("x").unwrap()[0];
    assert!(x(&native[0]) < 0.0 && x(native.last().unwrap()) > 0.001);
}

#[test]
fn bounce_on_a_tilted_mesh_follows_the_liggghts_trajectory() {
    let dir = workdir();
    run_native("mesh_bounce.in", &[], dir.path());
    let native = snapshots(dir.path().join("post/mesh_bounce.txt"));
    let reference = snapshots(testkit::fixture("dem/mesh_bounce_liggghts.txt"));
    assert_eq!(native.len(), 81);
    assert_same_bounce(&native, &reference);
}

const POUR_SMALL: [(&str, &str); 4] = [
    ("np", "300"),
    ("w", "0.004"),
    ("nsteps", "12000"),
    ("zmax", "0.02"),
];

fn measure(s: &Snapshot) -> bed::Bed {
    bed::measure(&s.positions().unwrap(), &s.radii().unwrap(), 0.004)
}

/// Centre of mass (m) of the spheres of a snapshot.
fn centre_of_mass(s: &Snapshot) -> [f64; 3] {
    let (x, r) = (s.positions().unwrap(), s.radii().unwrap());
    let ty = s.types().unwrap();
    let mut sum = [0.0; 3];
    let mut mass = 0.0;
    for ((p, r), t) in x.iter().zip(&r).zip(&ty) {
        let m = r.powi(3) * if *t == 1 { 2500.0 } else { 2000.0 };
        for k in 0..3 {
            sum[k] += m * p[k];
        }
        mass += m;
    }
    sum.map(|v| v / mass)
}

/// Two random loose packs of 300 spheres in the STL box (LIGGGHTS's and the native insertion
/// draw different random streams): the same count, all inside the box, bed top and slab solid
/// fraction within 4 % (the primitive-wall pour's tolerance, `tests/liggghts.rs`), the centre
/// of mass within 2 % in height and 0.1 w off the axis, both settled.
fn assert_same_pour(native: &Snapshot, reference: &Snapshot) {
    let w = 0.004;
    assert_eq!(native.len(), 300);
    assert_eq!(reference.len(), 300);
    for s in [native, reference] {
        let (x, r) = (s.positions().unwrap(), s.radii().unwrap());
        for (p, r) in x.iter().zip(&r) {
            // inside the box, overlapping its faces by less than 5 % of a radius
            assert!(
                p[0].abs() < w - 0.95 * r && p[1].abs() < w - 0.95 * r && p[2] > 0.95 * r,
                "{p:?}"
            );
        }
    }
    let (a, b) = (measure(native), measure(reference));
    let [top, _, slab, _] = bed::relative(&a, &b);
    let (ca, cb) = (centre_of_mass(native), centre_of_mass(reference));
    eprintln!("native {a:?} com {ca:?}\nLIGGGHTS {b:?} com {cb:?}\ntop {top:+.4}, slab {slab:+.4}");
    assert!(top.abs() < 0.04, "bed top differs by {top}");
    assert!(slab.abs() < 0.04, "solid fraction differs by {slab}");
    assert!(
        (ca[2] / cb[2] - 1.0).abs() < 0.02,
        "centre of mass height {} vs {}",
        ca[2],
        cb[2]
    );
    assert!(
        ca[0].abs() < 0.1 * w
            && ca[1].abs() < 0.1 * w
            && cb[0].abs() < 0.1 * w
            && cb[1].abs() < 0.1 * w
    );
    let vmax = |s: &Snapshot| {
        s.vectors(["vx", "vy", "vz"])
            .unwrap()
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .fold(0.0, f64::max)
    };
    // settled: the fastest sphere (a rattler) under 5 % of the insertion speed (measured:
    // 0.018 m/s native, 0.020 m/s LIGGGHTS)
    assert!(
        vmax(native) < 0.025 && vmax(reference) < 0.025,
        "{} {}",
        vmax(native),
        vmax(reference)
    );
}

fn native_pour(dir: &Path) -> Snapshot {
    let sim = run_native("mesh_pour.in", &POUR_SMALL, dir);
    assert_eq!(sim.lost(), 0);
    assert!(sim.warnings().is_empty(), "{:?}", sim.warnings());
    last_snapshot(dir.join("post/mesh_pour_12000.txt"))
}

#[test]
fn pour_into_an_stl_box_matches_the_liggghts_bed() {
    let dir = workdir();
    let native = native_pour(dir.path());
    let reference = last_snapshot(testkit::fixture("dem/mesh_pour_small_liggghts.txt"));
    assert_eq!(reference.timestep, 12000);
    assert_same_pour(&native, &reference);
}

/// Full tier: LIGGGHTS reruns both decks and reproduces the committed dumps (a serial
/// LIGGGHTS run is deterministic), and the native runs agree with the fresh output.
#[test]
fn liggghts_reproduces_the_mesh_fixtures() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = workdir();
    run_liggghts("mesh_bounce.in", &[], dir.path());
    let fresh = snapshots(dir.path().join("post/mesh_bounce.txt"));
    let committed = snapshots(testkit::fixture("dem/mesh_bounce_liggghts.txt"));
    assert_eq!(
        trajectory_difference(&fresh, &committed)
            .iter()
            .map(|d| d.1)
            .fold(0.0, f64::max),
        0.0
    );
    let ndir = workdir();
    run_native("mesh_bounce.in", &[], ndir.path());
    assert_same_bounce(&snapshots(ndir.path().join("post/mesh_bounce.txt")), &fresh);

    let dir = workdir();
    run_liggghts("mesh_pour.in", &POUR_SMALL, dir.path());
    let path = dir.path().join("post/mesh_pour_12000.txt");
    let fresh = last_snapshot(&path);
    let committed = last_snapshot(testkit::fixture("dem/mesh_pour_small_liggghts.txt"));
    assert_eq!(fresh.positions().unwrap(), committed.positions().unwrap());
    let ndir = workdir();
    assert_same_pour(&native_pour(ndir.path()), &fresh);
}
