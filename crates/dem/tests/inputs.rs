//! The standalone decks of `liggghts-inputs/` show what its README says, natively (fast tier)
//! and with Debian's LIGGGHTS 3.8.0 (full tier), against their closed forms.
//! (`pour.in` is compared with LIGGGHTS in `tests/liggghts.rs`.)

use std::path::Path;
use std::process::Command;

use dem_io::{read_snapshot, ReadOptions, Selection};

fn vars(e: f64, v: f64) -> Vec<(String, String)> {
    vec![
        ("e".to_string(), e.to_string()),
        ("v".to_string(), v.to_string()),
    ]
}

/// The sphere's vz after the contact, from the deck's dump of step 6000 in `dir`.
fn rebound_velocity(dir: &Path) -> f64 {
    let s = read_snapshot(
        dir.join("post/restitution_6000.txt"),
        &ReadOptions::default(),
        Selection::Last,
    )
    .unwrap();
    s.column("vz").unwrap()[0]
}

fn native_rebound(e: f64, v: f64) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    let deck =
        liggghts_deck::Deck::read_with_vars(testkit::liggghts_input("restitution.in"), &vars(e, v))
            .unwrap();
    dem::Simulation::from_deck(&deck, dir.path()).unwrap();
    rebound_velocity(dir.path())
}

/// `restitution.in`: rebound speed / impact speed = the e set, at 0.2 and 2 m/s (LIGGGHTS's
/// Hertz damping; the deck's time step is 1/4000 of Hertz's contact time, where the analytic
/// test finds e within 2·10⁻⁴).
#[test]
fn restitution_deck_rebounds_with_the_e_set() {
    for e in [0.3, 0.9] {
        for v in [0.2, 2.0] {
            let ratio = native_rebound(e, v) / v;
            assert!(
                approx::abs_diff_eq!(ratio / e, 1.0, epsilon = 1e-3),
                "e {e}, v {v}: measured {ratio}"
            );
        }
    }
}

/// Full tier: Debian's LIGGGHTS on the same deck gives the same rebound (both integrate the
/// same damped Hertz contact with the same velocity Verlet steps: measured identical to the
/// last bit at e = 0.5, v = 2 m/s; the bound allows for round-off).
#[test]
fn restitution_deck_matches_liggghts() {
    if !testkit::tool("liggghts") {
        return;
    }
    let (e, v) = (0.5, 2.0);
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("post")).unwrap();
    let mut c = Command::new("liggghts");
    c.arg("-in")
        .arg(testkit::liggghts_input("restitution.in"))
        .args(["-log", "none", "-screen", "screen.txt"]);
    for (k, x) in vars(e, v) {
        c.args(["-var", &k, &x]);
    }
    testkit::run_ok(c, dir.path());
    let theirs = rebound_velocity(dir.path());
    let ours = native_rebound(e, v);
    assert!(
        approx::abs_diff_eq!(theirs / v / e, 1.0, epsilon = 1e-3),
        "LIGGGHTS: {theirs}"
    );
    assert!(
        approx::abs_diff_eq!(ours, theirs, epsilon = 1e-9 * v),
        "native {ours} vs LIGGGHTS {theirs}"
    );
}
