//! Periodic boxes (`boundary p f f`) against Debian's LIGGGHTS 3.8.0 on the same deck
//! (`liggghts-inputs/periodic.in`): two spheres collide obliquely across the periodic x face,
//! and one of them crosses x = 0 afterwards (image counter ix = −1). LIGGGHTS's dump of every
//! 100th step (17 significant digits) is `tests/fixtures/dem/periodic_liggghts.txt`.
//!
//! A pour in a box periodic in x and y (`periodic_pour.in`) is compared with LIGGGHTS's
//! statistically.
//!
//! Fast tier: the native runs against the committed LIGGGHTS files. Full tier: LIGGGHTS reruns
//! the decks and must reproduce them exactly (a serial LIGGGHTS run is deterministic).

mod common;

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
        common::assert_column_close(native, reference, c, TOL);
    }
    for (a, b) in native.iter().zip(reference) {
        assert_eq!(a.timestep, b.timestep);
        for c in ["id", "ix", "iy", "iz"] {
            assert_eq!(
                a.column(c).unwrap(),
                b.column(c).unwrap(),
                "{c} at step {}",
                a.timestep
            );
        }
    }
    // the test covers what it claims: a contact (spin) and a crossing (ix = −1 at the end)
    let last = reference.last().unwrap();
    assert!(last
        .column("omegaz")
        .unwrap()
        .iter()
        .all(|w| w.abs() > 10.0));
    assert_eq!(last.column("ix").unwrap()[0], -1.0);
}

#[test]
fn collision_across_the_periodic_face_matches_liggghts() {
    let dir = tempfile::tempdir().unwrap();
    let reference = snapshots(&testkit::fixture("dem/periodic_liggghts.txt"));
    assert_same(&native(dir.path()), &reference);
}

#[test]
fn liggghts_reproduces_the_periodic_fixtures() {
    if !testkit::tool("liggghts") {
        return;
    }
    for (deck, out, fixture) in [
        (
            "periodic.in",
            "post/periodic.txt",
            "dem/periodic_liggghts.txt",
        ),
        (
            "periodic_pour.in",
            "post/periodic_pour_15000.txt",
            "dem/periodic_pour_liggghts.txt",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        setup(dir.path());
        std::fs::copy(testkit::liggghts_input(deck), dir.path().join(deck)).unwrap();
        let mut c = Command::new("liggghts");
        c.args(["-in", deck, "-screen", "s.screen", "-log", "s.log"]);
        testkit::run_ok(c, dir.path());
        let fresh = std::fs::read(dir.path().join(out)).unwrap();
        let committed = std::fs::read(testkit::fixture(fixture)).unwrap();
        assert!(
            fresh == committed,
            "LIGGGHTS's {out} differs from {fixture}"
        );
    }
}

/// Bed measures of a settled periodic pour (box `W` wide in x and y): mean top of the highest
/// 10 % of the spheres, mean centre height (m), contacts in all and across a periodic face, the
/// largest overlap (m), all through the nearest image.
#[derive(Debug)]
struct PourBed {
    top: f64,
    mean_z: f64,
    contacts: usize,
    across: usize,
    max_overlap: f64,
}

/// The width of `periodic_pour.in`'s box in x and y (m) and its sphere diameter (m).
const POUR_W: f64 = 0.008;
const POUR_D: f64 = 0.001;

fn pour_bed(s: &Snapshot) -> PourBed {
    let x = s.positions().unwrap();
    let n = x.len();
    let mut z: Vec<f64> = x.iter().map(|p| p[2]).collect();
    z.sort_by(f64::total_cmp);
    let k = n / 10;
    let (mut contacts, mut across, mut max_overlap) = (0, 0, 0.0f64);
    for i in 0..n {
        for j in i + 1..n {
            let d: Vec<f64> = (0..3).map(|a| x[i][a] - x[j][a]).collect();
            let image = |v: f64| v - POUR_W * (v / POUR_W).round();
            let (sx, sy) = (image(d[0]), image(d[1]));
            let overlap = POUR_D - (sx * sx + sy * sy + d[2] * d[2]).sqrt();
            if overlap > 0.0 {
                contacts += 1;
                across += usize::from(sx != d[0] || sy != d[1]);
                max_overlap = max_overlap.max(overlap);
            }
        }
    }
    PourBed {
        top: z[n - k..].iter().sum::<f64>() / k as f64,
        mean_z: z.iter().sum::<f64>() / n as f64,
        contacts,
        across,
        max_overlap,
    }
}

/// A pour of 400 spheres in a box periodic in x and y (`liggghts-inputs/periodic_pour.in`)
/// against LIGGGHTS's bed (`tests/fixtures/dem/periodic_pour_liggghts.txt`, step 15000): the
/// two insertions draw different random packs, so the beds agree statistically (measured: top
/// −0.4 %, mean height −1.2 %, 884 vs 907 contacts, 100 vs 114 across the faces, largest
/// overlap 1.7 vs 1.9 µm). Contacts across the periodic faces hold the bed as the interior
/// ones do: a missed image would let spheres sink into each other there.
#[test]
fn periodic_pour_matches_liggghts_statistically() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("post")).unwrap();
    let deck = liggghts_deck::Deck::read(testkit::liggghts_input("periodic_pour.in")).unwrap();
    let sim = dem::Simulation::from_deck(&deck, dir.path()).unwrap();
    assert_eq!((sim.particles.len(), sim.lost()), (400, 0));
    let native = pour_bed(
        &read_snapshot(
            dir.path().join("post/periodic_pour_15000.txt"),
            &ReadOptions::default(),
            Selection::Last,
        )
        .unwrap(),
    );
    let reference = pour_bed(
        &read_snapshot(
            testkit::fixture("dem/periodic_pour_liggghts.txt"),
            &ReadOptions::default(),
            Selection::Last,
        )
        .unwrap(),
    );
    eprintln!("native {native:?}\nLIGGGHTS {reference:?}");
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    assert!(rel(native.top, reference.top) < 0.03);
    assert!(rel(native.mean_z, reference.mean_z) < 0.03);
    assert!(rel(native.contacts as f64, reference.contacts as f64) < 0.1);
    assert!(native.across > 50 && reference.across > 50);
    assert!(native.max_overlap < 2.0 * reference.max_overlap);
}

/// A restart file keeps the periodic box and the image counters: the collision deck with
/// `write_restart` at its end, read back (LIGGGHTS 3.8.0 reads the same file and dumps
/// ix = −1 for sphere 1, checked by hand), and a deck continuing from it dumps them again.
#[test]
fn restart_files_keep_periodic_images() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let deck_path = dir.path().join("periodic.in");
    let text = std::fs::read_to_string(&deck_path).unwrap();
    std::fs::write(
        &deck_path,
        format!("{text}write_restart post/periodic.restart\n"),
    )
    .unwrap();
    let deck = liggghts_deck::Deck::read(&deck_path).unwrap();
    dem::Simulation::from_deck(&deck, dir.path()).unwrap();
    let file = dem_io::restart::read_restart(dir.path().join("post/periodic.restart")).unwrap();
    assert_eq!(file.header.boundary[0], [dem_io::Boundary::Periodic; 2]);
    let images: Vec<[i32; 3]> = file
        .atoms
        .iter()
        .map(|a| dem::periodic::unpack_image(a.image))
        .collect();
    assert_eq!(images, vec![[-1, 0, 0], [0, 0, 0]]);
    let resume = "atom_style granular\natom_modify map array\nboundary p f f\nnewton off\n\
                  units si\nread_restart post/periodic.restart\nneighbor 0.0005 bin\n\
                  fix m1 all property/global youngsModulus peratomtype 5.e6\n\
                  fix m2 all property/global poissonsRatio peratomtype 0.45\n\
                  fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n\
                  fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
                  pair_style gran model hertz tangential history\npair_coeff * *\n\
                  timestep 0.000001\nfix integr all nve/sphere\n\
                  dump d all custom 1 post/resumed.txt id ix iy iz\nrun 0\n";
    std::fs::write(dir.path().join("resume.in"), resume).unwrap();
    let deck = liggghts_deck::Deck::read(dir.path().join("resume.in")).unwrap();
    dem::Simulation::from_deck(&deck, dir.path()).unwrap();
    let s = read_snapshot(
        dir.path().join("post/resumed.txt"),
        &ReadOptions::default(),
        Selection::Last,
    )
    .unwrap();
    assert_eq!(s.column("ix").unwrap(), &[-1.0, 0.0]);
}
