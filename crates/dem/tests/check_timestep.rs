//! `fix check/timestep/gran` (`liggghts-inputs/timestep.in`: three free spheres of two
//! materials) against Debian's LIGGGHTS 3.8.0 and the closed forms.
//!
//! LIGGGHTS reports "time-step is X % of rayleigh time" with X = 100 Δt / min t_R over the
//! spheres, t_R = πr√(ρ/G)/(0.1631ν + 0.8766), G = E/(2(1 + ν)) (Li, Xu & Thornton 2005; seed
//! 002 eq. 10), and "… of hertz time" with t_H = 2.87 (m*²/(R* Y*² v))^{1/5} (Johnson 1985, eq.
//! 11.24; seed 002 eq. 11, whose printed exponent 2 is a slip for 1/5), evaluated as LIGGGHTS's
//! `calc_rayleigh_hertz_estims` does: m* = m (not m/2), R* = r/2, Y* = E/(2(1 − ν²)) of the
//! type with itself, v = twice the fastest sphere. Checked: the closed forms computed here, the
//! native DEM's warnings and LIGGGHTS's committed log (`tests/fixtures/dem/timestep_liggghts.log`)
//! agree to LIGGGHTS's six printed decimals; full tier, LIGGGHTS reruns and prints the same.

use std::f64::consts::PI;
use std::process::Command;

use liggghts_deck::Deck;

/// (rayleigh %, hertz %) from lines holding LIGGGHTS's words.
fn percents(text: &str) -> (f64, f64) {
    let grab = |what: &str| -> f64 {
        let l = text
            .lines()
            .find(|l| !l.starts_with('#') && l.contains(&format!("% of {what} time")))
            .unwrap_or_else(|| panic!("no {what} line in {text}"));
        let after = l.split("time-step is").nth(1).unwrap();
        after.split_whitespace().next().unwrap().parse().unwrap()
    };
    (grab("rayleigh"), grab("hertz"))
}

/// The spheres of `timestep_spheres.data`: (radius m, density, E Pa, ν, speed m/s).
const SPHERES: [(f64, f64, f64, f64, f64); 3] = [
    (0.001, 2500.0, 1e7, 0.3, 0.3),
    (0.0015, 2000.0, 5e6, 0.45, 1.5),
    (0.0007, 2000.0, 5e6, 0.45, 0.4),
];
const DT: f64 = 1e-5;

fn closed_forms() -> (f64, f64) {
    let vmax = SPHERES.iter().map(|s| s.4).fold(0.0, f64::max);
    let (mut tr, mut th) = (f64::INFINITY, f64::INFINITY);
    for (r, rho, e, nu, _) in SPHERES {
        let g = e / (2.0 * (1.0 + nu));
        tr = tr.min(PI * r * (rho / g).sqrt() / (0.1631 * nu + 0.8766));
        let m = 4.0 / 3.0 * PI * r.powi(3) * rho;
        let y = e / (2.0 * (1.0 - nu * nu));
        th = th.min(2.87 * (m * m / (0.5 * r * y * y * 2.0 * vmax)).powf(0.2));
    }
    (100.0 * DT / tr, 100.0 * DT / th)
}

#[test]
fn native_warnings_are_liggghts_numbers_and_the_closed_forms() {
    let deck = Deck::read(testkit::liggghts_input("timestep.in")).unwrap();
    let sim = dem::Simulation::from_deck(&deck, &testkit::liggghts_input(".")).unwrap();
    let native = percents(&sim.warnings().join("\n"));
    let log = std::fs::read_to_string(testkit::fixture("dem/timestep_liggghts.log")).unwrap();
    let liggghts = percents(&log);
    let exact = closed_forms();
    eprintln!(
        "Rayleigh %, Hertz %: closed form {exact:?}, native {native:?}, LIGGGHTS {liggghts:?}"
    );
    // six decimals printed: 5e-7 of a percent, and round-off
    for (a, b) in [(native, liggghts), (exact, liggghts)] {
        assert!((a.0 - b.0).abs() <= 6e-7, "{a:?} {b:?}");
        assert!((a.1 - b.1).abs() <= 6e-7, "{a:?} {b:?}");
    }
}

#[test]
fn liggghts_reproduces_its_warnings() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for f in ["timestep.in", "timestep_spheres.data"] {
        std::fs::copy(testkit::liggghts_input(f), dir.path().join(f)).unwrap();
    }
    let mut c = Command::new("liggghts");
    c.args(["-in", "timestep.in", "-screen", "s.screen", "-log", "s.log"]);
    testkit::run_ok(c, dir.path());
    let log = std::fs::read_to_string(dir.path().join("s.log")).unwrap();
    let committed = std::fs::read_to_string(testkit::fixture("dem/timestep_liggghts.log")).unwrap();
    assert_eq!(percents(&log), percents(&committed));
}
