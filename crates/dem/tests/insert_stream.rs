//! `fix insert/stream` (`liggghts-inputs/stream.in`) against Debian's LIGGGHTS 3.8.0 and closed
//! forms.
//!
//! The deck inserts 20 spheres (R 1 mm) every 1000 steps from step 1000 on behind a 16 × 16 mm
//! face at z = 0.05 m, extruded 5 mm upwards (insert_every 1000 × Δt 1e-5 s × 0.5 m/s); they
//! are carried down at 0.5 m/s to the face, released there with 0.5 m/s, fall freely and are
//! lost through the open bottom z = 0. Checked:
//! - every thermo row's inserted number and mass equal LIGGGHTS's (its committed log,
//!   `tests/fixtures/dem/stream_liggghts.log`); the atom count equals LIGGGHTS's until the
//!   first sphere can leave;
//! - the inflow–outflow count: with the overlap check a centre is placed at a depth d uniform
//!   in [R, L + R] behind the face, carried ⌊d/(vΔt)⌋ steps, then falls from the face in
//!   T = (√(v² + 2gh) − v)/g; so a sphere stays in the box for an age uniform in
//!   [R/(vΔt) + T/Δt, (L + R)/(vΔt) + T/Δt], and both counts follow that expectation within
//!   the binomial scatter, to the steady state of ~143 spheres;
//! - where each batch is placed (the dumps at the insertion steps, LIGGGHTS's committed in
//!   `stream_batches_liggghts.txt`): every centre inside the extruded face (|x|, |y| ≤ 8 mm,
//!   z ∈ [51, 56] mm), no two spheres of a batch overlapping, each coordinate uniform
//!   (Kolmogorov–Smirnov at the 0.1 % level), the native and LIGGGHTS means equal within their
//!   scatter; spheres still carried move at exactly −0.5 m/s without spin or gravity.
//!
//! Full tier: LIGGGHTS reruns the deck and reproduces the log's rows and the batches exactly.

use std::path::Path;
use std::process::Command;

use dem::deck::exec::DeckEvent;
use liggghts_deck::Deck;

mod common;
use common::inflow::{compare, rows, Row};

const G: f64 = 9.81;
const V: f64 = 0.5;
const DT: f64 = 1e-5;
const R: f64 = 1e-3;
/// Extrusion length (m): 1000 steps × Δt × v.
const L: f64 = 1000.0 * DT * V;
const FACE_Z: f64 = 0.05;
const HALF: f64 = 0.008;
const EVERY: u64 = 1000;

/// Steps from release at the face to leaving through z = 0.
fn fall_steps() -> f64 {
    ((V * V + 2.0 * G * FACE_Z).sqrt() - V) / G / DT
}

/// Probability that a sphere inserted `age` steps ago is still in the box.
fn staying(age: f64) -> f64 {
    let (lo, hi) = (
        R / (V * DT) + fall_steps(),
        (L + R) / (V * DT) + fall_steps(),
    );
    ((hi - age) / (hi - lo)).clamp(0.0, 1.0)
}

/// Expected atoms at `step` and its binomial variance (20 inserted at 1000, 2000, …).
fn expected(step: u64) -> (f64, f64) {
    let (mut mean, mut var) = (0.0, 0.0);
    for at in (EVERY..=step).step_by(EVERY as usize) {
        let p = staying((step - at) as f64);
        mean += 20.0 * p;
        var += 20.0 * p * (1.0 - p);
    }
    (mean, var)
}

/// A working directory with `meshes/plane.stl` and `post/`.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("post")).unwrap();
    std::fs::create_dir_all(dir.path().join("meshes")).unwrap();
    std::fs::copy(
        testkit::liggghts_input("meshes").join("plane.stl"),
        dir.path().join("meshes/plane.stl"),
    )
    .unwrap();
    dir
}

/// `(step, id, x, vz·|ω|…)` records of the dumps `post/stream_*.dump`: per dump step, all
/// spheres as `(id, x, v)`.
type Snapshot = (u64, Vec<(u64, [f64; 3], [f64; 3])>);

fn read_dumps(dir: &Path) -> Vec<Snapshot> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir.join("post")).unwrap() {
        let text = std::fs::read_to_string(e.unwrap().path()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let step: u64 = lines[1].trim().parse().unwrap();
        let at = lines
            .iter()
            .position(|l| l.starts_with("ITEM: ATOMS"))
            .unwrap();
        let atoms = lines[at + 1..]
            .iter()
            .map(|l| {
                let v: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
                (v[0] as u64, [v[1], v[2], v[3]], [v[4], v[5], v[6]])
            })
            .collect();
        out.push((step, atoms));
    }
    out.sort_by_key(|s| s.0);
    out
}

/// Each insertion step's new spheres `(step, id, x)`: the ids above the previous batches'.
fn batches(snaps: &[Snapshot]) -> Vec<(u64, u64, [f64; 3])> {
    let mut out = Vec::new();
    for (step, atoms) in snaps {
        let before = 20 * (step / EVERY).saturating_sub(1);
        for (id, x, _) in atoms.iter().filter(|a| a.0 > before) {
            out.push((*step, *id, *x));
        }
    }
    out
}

fn committed_batches() -> Vec<(u64, u64, [f64; 3])> {
    let text =
        std::fs::read_to_string(testkit::fixture("dem/stream_batches_liggghts.txt")).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            (v[0] as u64, v[1] as u64, [v[2], v[3], v[4]])
        })
        .collect()
}

fn committed_rows() -> Vec<Row> {
    let log = std::fs::read_to_string(testkit::fixture("dem/stream_liggghts.log")).unwrap();
    rows(log.lines())
}

/// Kolmogorov–Smirnov distance of `v` from the uniform distribution on [lo, hi].
fn ks_uniform(mut v: Vec<f64>, lo: f64, hi: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len() as f64;
    v.iter()
        .enumerate()
        .map(|(i, x)| {
            let f = (x - lo) / (hi - lo);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

/// The batch checks of the module doc on one run's batches; returns the mean centre.
fn check_batches(who: &str, b: &[(u64, u64, [f64; 3])]) -> [f64; 3] {
    assert_eq!(b.len(), 600, "{who}: 30 batches of 20");
    let (zlo, zhi) = (FACE_Z + R, FACE_Z + L + R);
    for (step, id, x) in b {
        // LIGGGHTS's dump prints 6 digits
        let tol = 1e-8;
        assert!(
            x[0].abs() <= HALF + tol && x[1].abs() <= HALF + tol,
            "{who}: sphere {id} of step {step} outside the face: {x:?}"
        );
        assert!(
            x[2] >= zlo - tol && x[2] <= zhi + tol,
            "{who}: sphere {id} of step {step} outside the extrusion: {x:?}"
        );
        for (s2, id2, y) in b.iter().filter(|o| o.0 == *step && o.1 < *id) {
            let d = ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt();
            assert!(
                d >= 2.0 * R - 1e-7,
                "{who}: {id} and {id2} of step {s2} overlap: {d}"
            );
        }
    }
    // KS at the 0.1 % level: D < 1.95/√n
    let crit = 1.95 / (b.len() as f64).sqrt();
    let coord = |k: usize| b.iter().map(|e| e.2[k]).collect::<Vec<f64>>();
    let d = [
        ks_uniform(coord(0), -HALF, HALF),
        ks_uniform(coord(1), -HALF, HALF),
        ks_uniform(coord(2), zlo, zhi),
    ];
    eprintln!("{who}: KS distances x y z {d:?} (critical {crit:.4})");
    assert!(d.iter().all(|&d| d < crit), "{who}: {d:?}");
    let n = b.len() as f64;
    [0, 1, 2].map(|k| coord(k).iter().sum::<f64>() / n)
}

#[test]
fn stream_insertion_matches_liggghts_and_the_closed_forms() {
    let dir = workdir();
    let deck = Deck::read(testkit::liggghts_input("stream.in")).unwrap();
    let mut lines = Vec::new();
    let sim = dem::Simulation::from_deck_observed(&deck, dir.path(), &mut |e| {
        if let DeckEvent::Output(l) = e {
            lines.push(l)
        }
    })
    .unwrap();
    let ours = rows(lines.iter().map(String::as_str));
    let theirs = committed_rows();
    let first_exit = EVERY + (R / (V * DT) + fall_steps()) as u64;
    let (area_ours, area_theirs, area_expected) = compare(&ours, &theirs, first_exit, expected);
    let rel = |x: f64| x / area_expected - 1.0;
    eprintln!(
        "Σ atoms over rows: native {area_ours}, LIGGGHTS {area_theirs}, expected \
         {area_expected:.1}: {:+.4} and {:+.4}; steady (last row) native {} LIGGGHTS {} \
         expected {:.1}",
        rel(area_ours),
        rel(area_theirs),
        ours.last().unwrap().1,
        theirs.last().unwrap().1,
        expected(30000).0
    );
    assert!(rel(area_ours).abs() < 0.01 && rel(area_theirs).abs() < 0.01);
    // the inserted mass is the count times the sphere's mass
    let m = 4.0 / 3.0 * std::f64::consts::PI * R.powi(3) * 2500.0;
    let ins = &sim.rate_insertions()[0];
    assert_eq!(ins.stats().inserted, 600);
    assert!((ins.stats().mass - 600.0 * m).abs() < 1e-12 * 600.0 * m);
    assert_eq!(ins.every(), 1000);

    let snaps = read_dumps(dir.path());
    let native = check_batches("native", &batches(&snaps));
    let liggghts = check_batches("LIGGGHTS", &committed_batches());
    // means of 600 uniform draws: σ = width/√(12·600)
    for k in 0..3 {
        let width = if k < 2 { 2.0 * HALF } else { L };
        let sigma = width / (12.0f64 * 600.0).sqrt();
        assert!(
            (native[k] - liggghts[k]).abs() < 4.0 * 2f64.sqrt() * sigma,
            "mean {k}: native {} LIGGGHTS {}",
            native[k],
            liggghts[k]
        );
    }
    eprintln!("mean centres: native {native:?}, LIGGGHTS {liggghts:?}");
    // carried spheres (above the face) move at exactly v_n, without spin or gravity; released
    // ones below it fall faster than v
    let mut carried = 0;
    for (_, atoms) in &snaps {
        for (id, x, v) in atoms {
            if x[2] > FACE_Z + 1e-9 {
                assert_eq!(*v, [0.0, 0.0, -V], "sphere {id} at {x:?}");
                carried += 1;
            } else if x[2] < FACE_Z - 1e-3 {
                assert!(v[2] < -V, "sphere {id} at {x:?}: {v:?}");
            }
        }
    }
    assert!(carried > 600, "{carried}");
}

#[test]
fn liggghts_reproduces_its_log_and_batches() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = workdir();
    std::fs::copy(
        testkit::liggghts_input("stream.in"),
        dir.path().join("stream.in"),
    )
    .unwrap();
    let mut c = Command::new("liggghts");
    c.args(["-in", "stream.in", "-screen", "s.screen", "-log", "s.log"]);
    testkit::run_ok(c, dir.path());
    let log = std::fs::read_to_string(dir.path().join("s.log")).unwrap();
    assert_eq!(rows(log.lines()), committed_rows());
    let ours = batches(&read_dumps(dir.path()));
    let theirs = committed_batches();
    assert_eq!(ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(&theirs) {
        assert_eq!((a.0, a.1), (b.0, b.1));
        for k in 0..3 {
            assert!((a.2[k] - b.2[k]).abs() <= 1e-12, "{a:?} {b:?}");
        }
    }
}

/// Errors name LIGGGHTS's conditions: both `insert_every` and `extrude_length`, no face, a
/// region instead of a face, `all_in yes`.
#[test]
fn bad_stream_fixes_are_refused_with_the_reason() {
    let deck = std::fs::read_to_string(testkit::liggghts_input("stream.in")).unwrap();
    let cases = [
        (
            "insert_every 1000 start",
            "insert_every 1000 extrude_length 0.005 start",
            "not both",
        ),
        (
            "insertion_face face",
            "insertion_face nope",
            "no fix mesh/surface `nope`",
        ),
        ("insertion_face face", "", "needs `insertion_face`"),
        (
            "overlapcheck yes",
            "overlapcheck yes all_in yes",
            "mesh/surface/planar",
        ),
    ];
    for (from, to, expect) in cases {
        let dir = workdir();
        let text = deck
            .replacen(from, to, 1)
            .replace("index 30000", "index 10");
        let path = dir.path().join("bad.in");
        std::fs::write(&path, text).unwrap();
        let d = Deck::read(&path).unwrap();
        let e = dem::Simulation::from_deck_observed(&d, dir.path(), &mut |_| {})
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.contains(expect) && e.contains("bad.in:"), "{e}");
    }
}
