//! Repeated `insert/pack … insert_every K` (`liggghts-inputs/pack_every.in`) against Debian's
//! LIGGGHTS 3.8.0 (its committed log, `tests/fixtures/dem/pack_every_liggghts.log`).
//!
//! The deck is built so that the counts do not depend on where the random positions fall:
//! `drop` can place one sphere per insertion (its region holds one with `all_in yes`) though
//! it wants 4, at steps 1, 2001, …, 8001; `fill`, defined at step 30000 when those five rest
//! on the floor inside its region, wants 12 − 5 = 7 at step 30001 and nothing at 33001 and
//! 36001. The runs end at the insertion steps, so the thermo rows at the steps before and at
//! each insertion step pin it. Checked: every thermo row (step, atoms, inserted so far) equals
//! LIGGGHTS's, and the committed log's own insertion lines are those counts at those steps.
//! Full tier: LIGGGHTS reruns the deck and reproduces the rows exactly.

use std::process::Command;

use dem::deck::exec::DeckEvent;
use dem::Simulation;
use liggghts_deck::Deck;

/// A thermo row: step, atoms, the insertion fix's inserted count (absent between the fixes).
type Row = (u64, u64, Option<u64>);

/// The rows of a LIGGGHTS log or of the native output: lines of two or three integers.
fn rows<'a>(lines: impl Iterator<Item = &'a str>) -> Vec<Row> {
    lines
        .filter_map(|l| {
            let w: Vec<u64> = (l.split_whitespace())
                .map(|x| x.parse().ok())
                .collect::<Option<_>>()?;
            match w[..] {
                [s, n] => Some((s, n, None)),
                [s, n, k] => Some((s, n, Some(k))),
                _ => None,
            }
        })
        .collect()
}

/// LIGGGHTS's "INFO: Particle insertion ID: inserted N particle templates … at step S".
fn insertions(log: &str) -> Vec<(String, u64, u64)> {
    log.lines()
        .filter_map(|l| {
            let rest = l.strip_prefix("INFO: Particle insertion ")?;
            let (id, rest) = rest.split_once(": inserted ")?;
            let n = rest.split_whitespace().next()?.parse().ok()?;
            let step = rest.rsplit_once("at step ")?.1.trim().parse().ok()?;
            Some((id.to_string(), n, step))
        })
        .collect()
}

fn committed() -> String {
    std::fs::read_to_string(testkit::fixture("dem/pack_every_liggghts.log")).unwrap()
}

#[test]
fn repeated_pack_inserts_what_liggghts_inserts_at_its_steps() {
    let deck = Deck::read(testkit::liggghts_input("pack_every.in")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut lines = Vec::new();
    let sim = Simulation::from_deck_observed(&deck, dir.path(), &mut |e| {
        if let DeckEvent::Output(l) = e {
            lines.push(l)
        }
    })
    .unwrap();
    let ours = rows(lines.iter().map(String::as_str));
    let log = committed();
    let theirs = rows(log.lines());
    assert_eq!(theirs.len(), 54, "LIGGGHTS's thermo rows");
    assert_eq!(ours, theirs);
    // the log's insertion lines: `drop` 1 of 4 wanted each time, `fill` 7 = 12 − 5 once
    let mut want: Vec<(String, u64, u64)> =
        (0..5).map(|k| ("drop".into(), 1, 1 + 2000 * k)).collect();
    want.push(("fill".into(), 7, 30001));
    assert_eq!(insertions(&log), want);
    assert_eq!(log.matches("Less insertions than requested").count(), 5);
    // `fill` has run its empty insertions at 33001 and 36001 and goes on every 3000 steps
    let fill = &sim.rate_insertions()[0];
    assert_eq!(fill.spec().name, "fill");
    assert_eq!(fill.stats().inserted, 7);
    assert_eq!(fill.stats().short, 0);
    assert_eq!(fill.next_step(), Some(39001));
    assert_eq!(sim.particles.len(), 12);
}

#[test]
fn liggghts_reproduces_its_pack_every_log() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("pack_every.in");
    std::fs::copy(testkit::liggghts_input("pack_every.in"), deck).unwrap();
    let mut c = Command::new("liggghts");
    c.args([
        "-in",
        "pack_every.in",
        "-screen",
        "s.screen",
        "-log",
        "s.log",
    ]);
    testkit::run_ok(c, dir.path());
    let log = std::fs::read_to_string(dir.path().join("s.log")).unwrap();
    let committed = committed();
    assert_eq!(rows(log.lines()), rows(committed.lines()));
    assert_eq!(insertions(&log), insertions(&committed));
}
