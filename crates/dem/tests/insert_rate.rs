//! Continuous insertion and outflow (`liggghts-inputs/outflow.in`) against Debian's LIGGGHTS
//! 3.8.0 and the closed form of free fall.
//!
//! The deck inserts 20 spheres every 1000 steps (an integer count per insertion, so LIGGGHTS's
//! counts are deterministic) at the top of a box whose bottom face is fixed and open; the
//! spheres fall freely (same velocity, no overlap at insertion: they never touch) and are lost
//! through the bottom. Checked: the inserted number and mass of every thermo row equal
//! LIGGGHTS's (its committed log, `tests/fixtures/dem/outflow_liggghts.log`); the atom count
//! equals LIGGGHTS's on every row before the first sphere can reach the bottom; afterwards
//! both counts follow the expectation of the free-fall exit times of centres uniform in the
//! insertion region (a sphere inserted at height z₀ with downward speed v₀ leaves after
//! t = (√(v₀² + 2gz₀) − v₀)/g), within the binomial scatter; `lost error` stops the run at the
//! first lost sphere naming it. Full tier: LIGGGHTS reruns the deck and reproduces the log's
//! rows exactly, and stops with "Lost atoms" under `lost error`.

use std::process::Command;

use dem::deck::exec::DeckEvent;
use dem::Simulation;
use liggghts_deck::Deck;

mod common;
use common::inflow::{compare, rows, Row};

fn native(vars: &[(&str, &str)]) -> (Result<Simulation, dem::DemError>, Vec<String>) {
    let vars: Vec<(String, String)> = vars
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    let deck = Deck::read_with_vars(testkit::liggghts_input("outflow.in"), &vars).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut lines = Vec::new();
    let sim = Simulation::from_deck_observed(&deck, dir.path(), &mut |e| {
        if let DeckEvent::Output(l) = e {
            lines.push(l)
        }
    });
    (sim, lines)
}

const G: f64 = 9.81;
const V0: f64 = 0.5;
const DT: f64 = 1e-5;
/// Centre heights of the insertion region with `all_in yes` (region 0.04–0.055 m, R 1 mm).
const Z: (f64, f64) = (0.041, 0.054);

/// The fall time (steps) from centre height z.
fn exit_steps(z: f64) -> f64 {
    ((V0 * V0 + 2.0 * G * z).sqrt() - V0) / G / DT
}

/// Probability that a sphere inserted `age` steps ago is still in the box (z₀ uniform).
fn staying(age: f64) -> f64 {
    if age <= exit_steps(Z.0) {
        return 1.0;
    }
    if age >= exit_steps(Z.1) {
        return 0.0;
    }
    // the height whose exit time is `age`: z = v₀t + ½gt²
    let t = age * DT;
    let z = V0 * t + 0.5 * G * t * t;
    (Z.1 - z) / (Z.1 - Z.0)
}

/// Expected atoms at `step` (20 inserted at steps 1, 1001, …, 9001), and its binomial variance.
fn expected(step: u64) -> (f64, f64) {
    let (mut mean, mut var) = (0.0, 0.0);
    for b in 0..10 {
        let at = 1 + 1000 * b;
        if step >= at {
            let p = staying((step - at) as f64);
            mean += 20.0 * p;
            var += 20.0 * p * (1.0 - p);
        }
    }
    (mean, var)
}

/// The rows of one run against LIGGGHTS's rows and the expectation.
fn compare_outflow(ours: &[Row], theirs: &[Row]) {
    let first_exit = exit_steps(Z.0) as u64;
    let (area_ours, area_theirs, area_expected) = compare(ours, theirs, first_exit, expected);
    // Σ atoms over the rows ∝ the mean residence time of the 200 spheres: its scatter is the
    // exit times' spread (~370 steps) / √200 ≈ 0.5 % of the mean (~5900 steps)
    let rel = |x: f64| x / area_expected - 1.0;
    eprintln!(
        "residence (Σ atoms over rows): native {area_ours}, LIGGGHTS {area_theirs}, \
         expected {area_expected:.1}: {:+.4} and {:+.4}",
        rel(area_ours),
        rel(area_theirs)
    );
    assert!(rel(area_ours).abs() < 0.02 && rel(area_theirs).abs() < 0.025);
    assert_eq!(ours.last().unwrap().1, 0);
    assert_eq!(theirs.last().unwrap().1, 0);
}

fn committed() -> Vec<Row> {
    let log = std::fs::read_to_string(testkit::fixture("dem/outflow_liggghts.log")).unwrap();
    rows(log.lines())
}

#[test]
fn insertion_and_outflow_match_liggghts_and_free_fall() {
    let (sim, lines) = native(&[]);
    let sim = sim.unwrap();
    let ours = rows(lines.iter().map(String::as_str));
    compare_outflow(&ours, &committed());
    // every sphere inserted was lost through the bottom, with its mass
    let out = sim.outflow().lost;
    assert_eq!(out.count, 200);
    let m = 4.0 / 3.0 * std::f64::consts::PI * 1e-9 * 2500.0;
    assert!((out.mass - 200.0 * m).abs() < 1e-12);
    let ins = &sim.rate_insertions()[0];
    assert_eq!(ins.stats().inserted, 200);
    assert_eq!(ins.next_step(), None);
    // all left falling: their momentum points down
    assert!(out.momentum[2] < 0.0);
}

#[test]
fn lost_error_names_the_step_and_the_particle() {
    let (sim, _) = native(&[("lost", "error")]);
    let e = sim.unwrap_err().to_string();
    eprintln!("{e}");
    assert!(e.contains("outflow.in:"), "{e}");
    assert!(
        e.contains("particle ") && e.contains("fixed face z−") && e.contains("at step "),
        "{e}"
    );
    // the first sphere leaves after the shortest fall time, later than the fifth insertion
    let step: u64 = e
        .split("at step ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    assert!(
        step as f64 > exit_steps(Z.0) && (step as f64) < exit_steps(Z.1) + 5002.0,
        "{e}"
    );
}

#[test]
fn liggghts_reproduces_its_log_and_stops_on_lost_atoms() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        testkit::liggghts_input("outflow.in"),
        dir.path().join("outflow.in"),
    )
    .unwrap();
    let mut c = Command::new("liggghts");
    c.args(["-in", "outflow.in", "-screen", "s.screen", "-log", "s.log"]);
    testkit::run_ok(c, dir.path());
    let log = std::fs::read_to_string(dir.path().join("s.log")).unwrap();
    assert_eq!(rows(log.lines()), committed());
    let out = Command::new("liggghts")
        .args(["-in", "outflow.in", "-var", "lost", "error"])
        .args(["-screen", "e.screen", "-log", "e.log"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(!out.status.success());
    // LIGGGHTS may leave non-UTF-8 bytes in a screen file it stops writing on an error
    let screen =
        String::from_utf8_lossy(&std::fs::read(dir.path().join("e.screen")).unwrap()).into_owned();
    assert!(screen.contains("ERROR: Lost atoms"), "{screen}");
}

/// `delete_atoms region R` removes the spheres whose centres lie in R and tallies them; the
/// insertion goes on, numbering after the largest id left (`compress yes` renumbers 1…N).
#[test]
fn delete_atoms_removes_the_region_and_insertion_goes_on() {
    let deck = Deck::read_with_vars(
        testkit::liggghts_input("outflow.in"),
        &[("nsteps".to_string(), "1001".to_string())],
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut session = dem::deck::exec::Session::new(dir.path(), |_| {});
    session.execute(&deck).unwrap();
    // 40 spheres: the first 20 have fallen 1000 steps (5.5 mm), the second are at the top
    let sim = session.simulation().unwrap();
    assert_eq!(sim.particles.len(), 40);
    let expected = sim.particles.x.iter().filter(|x| x[2] > 0.04).count();
    assert!(expected >= 20);
    let file = std::path::Path::new("commands");
    session
        .command_text("region low block -0.01 0.01 -0.01 0.01 0.0 0.04 units box\ndelete_atoms region low compress no", file)
        .unwrap();
    let sim = session.simulation().unwrap();
    assert_eq!(sim.particles.len(), expected);
    assert_eq!(sim.outflow().deleted.count, 40 - expected as u64);
    session
        .command_text("delete_atoms region top", file)
        .unwrap();
    let sim = session.simulation().unwrap();
    assert!(sim.particles.is_empty());
    assert_eq!(sim.outflow().deleted.count, 40);
    session.command_text("run 1000", file).unwrap();
    let sim = session.simulation().unwrap();
    assert_eq!(sim.particles.len(), 20);
    assert_eq!(sim.particles.id, (1..=20).collect::<Vec<u64>>());
}
