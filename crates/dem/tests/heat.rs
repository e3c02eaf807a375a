//! Particle heat (`fix heat/gran`, `couple/cfd/convection`) against Debian's LIGGGHTS 3.8.0
//! and closed forms.
//!
//! `liggghts-inputs/heat_conduction.in`: six touching spheres of two materials in a line
//! between two walls, three of them set to other temperatures; LIGGGHTS's dumps of every 100th
//! of 2000 steps (17 significant digits, contact areas `overlap` and `projection`) and its log
//! are in `tests/fixtures/dem/` (README there). Fast tier: the native runs against the
//! committed files; full tier: LIGGGHTS reruns the deck and must reproduce them exactly (a
//! serial LIGGGHTS run is deterministic).

mod common;

use std::path::Path;
use std::process::Command;

use dem_io::{read_snapshot, ReadOptions, Selection, Snapshot};

/// Snapshots in a dump (steps 0, 100, …, 2000).
const SNAPSHOTS: usize = 21;

/// Relative agreement with LIGGGHTS of temperatures and heat flows (of the column's largest
/// magnitude): the same arithmetic, but each particle's two contacts are summed in another
/// order (LIGGGHTS's neighbour list, the native spatial order), which may differ in the last
/// bits of the forces and heat flows (measured over 2000 steps: T within 6e-14 K of 600 K,
/// heat flows within 3e-15 W of 0.8 W, positions identical).
const TOL: f64 = 1e-12;

/// Relative agreement with LIGGGHTS continuing its own restart file: its set-up evaluates the
/// forces again (`dem::deck::restart`'s notes), the native one as it does, with the last bits
/// of the contact sums in another order (measured: vx within 6e-15 m/s of 4.5e-3 m/s, T within
/// 6e-14 K of 426 K, heat flows within 4e-16 W of 0.07 W).
const TOL_RESTART: f64 = 1e-10;

fn snapshots(path: &Path) -> Vec<Snapshot> {
    (0..SNAPSHOTS)
        .map(|k| read_snapshot(path, &ReadOptions::default(), Selection::Index(k)).unwrap())
        .collect()
}

fn setup(dir: &Path) {
    std::fs::create_dir_all(dir.join("post")).unwrap();
    for f in ["heat_conduction.in", "heat_line.data"] {
        std::fs::copy(testkit::liggghts_input(f), dir.join(f)).unwrap();
    }
}

/// Runs the deck natively in `dir` with `vars`; returns the simulation and its dump.
fn native(dir: &Path, vars: &[(String, String)]) -> (dem::Simulation, Vec<Snapshot>) {
    setup(dir);
    let deck = liggghts_deck::Deck::read_with_vars(dir.join("heat_conduction.in"), vars).unwrap();
    let sim = dem::Simulation::from_deck(&deck, dir).unwrap();
    assert_eq!(sim.particles.len(), 6);
    (sim, snapshots(&dir.join("post/heat_conduction.txt")))
}

/// Every listed column of every snapshot within [`TOL`] of the column's largest magnitude.
fn assert_same(native: &[Snapshot], reference: &[Snapshot]) {
    assert_eq!(native.len(), reference.len());
    for c in ["x", "vx", "f_Temp[0]", "f_ht[0]"] {
        common::assert_column_close(native, reference, c, TOL);
    }
    // the heat flows from the first step on: at a run's set-up LIGGGHTS's wall fixes evaluate
    // once more and add their wall heat to the flows the last step left (so its set-up snapshot
    // shows them summed over the set-ups, here those of `run 0` and `run 2000`), which the
    // temperatures never use (the next step resets the flows first); the native set-up leaves
    // them as the last step left them
    common::assert_column_close(&native[1..], &reference[1..], "f_heatFlux[0]", TOL);
    for (a, b) in native.iter().zip(reference) {
        assert_eq!(a.timestep, b.timestep);
        assert_eq!(a.column("id").unwrap(), b.column("id").unwrap());
    }
    // the test covers what it claims: heat flowed (the hot end cooled by > 100 K)
    let t = |s: &Snapshot| s.column("f_Temp[0]").unwrap().to_vec();
    let (first, last) = (t(&reference[0]), t(reference.last().unwrap()));
    assert_eq!(first[0], 600.0);
    assert!(first[0] - last[0] > 100.0, "{first:?} → {last:?}");
}

/// The set-up lines the small decks of these tests share.
const PREAMBLE: &str = "\
atom_style granular
atom_modify map array
boundary f f f
newton off
units si
";

/// The material (one type) and contact model of the small decks.
const MATERIALS: &str = "\
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.45
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style gran model hertz tangential history
pair_coeff * *
";

fn vars(area: &str) -> Vec<(String, String)> {
    vec![("area".to_string(), area.to_string())]
}

/// The deck's variants and LIGGGHTS's dumps of them: contact areas `overlap` and
/// `projection`, and walls at 350 K that conduct too.
const VARIANTS: [(&str, &str, &str); 3] = [
    ("overlap", "-1", "dem/heat_conduction_liggghts.txt"),
    (
        "projection",
        "-1",
        "dem/heat_conduction_projection_liggghts.txt",
    ),
    ("overlap", "350", "dem/heat_conduction_walls_liggghts.txt"),
];

fn variant(area: &str, wall_t: &str) -> Vec<(String, String)> {
    let mut v = vars(area);
    v.push(("wallT".to_string(), wall_t.to_string()));
    v
}

#[test]
fn conduction_matches_liggghts() {
    for (area, wall_t, file) in VARIANTS {
        let dir = tempfile::tempdir().unwrap();
        let (_, ours) = native(dir.path(), &variant(area, wall_t));
        eprintln!("contact_area {area}, walls at {wall_t} K:");
        assert_same(&ours, &snapshots(&testkit::fixture(file)));
    }
}

/// Conduction moves heat between particles and conserves Σ m c T to round-off; LIGGGHTS's log
/// prints the same total (8 digits).
#[test]
fn conduction_conserves_thermal_energy() {
    let dir = tempfile::tempdir().unwrap();
    let (mut sim, _) = native(dir.path(), &vars("overlap"));
    let e0 = sim.heat_energy().unwrap();
    let log =
        std::fs::read_to_string(testkit::fixture("dem/heat_conduction_liggghts.log")).unwrap();
    let printed = log
        .lines()
        .nth(1)
        .unwrap()
        .split_whitespace()
        .nth(3)
        .unwrap();
    assert_eq!(liggghts_deck::format::format_g(e0, 8), printed, "{e0}");
    let spread = |s: &dem::Simulation| {
        let t = s.temperature().unwrap();
        t.iter().copied().fold(f64::MIN, f64::max) - t.iter().copied().fold(f64::MAX, f64::min)
    };
    let before = spread(&sim);
    sim.run(3000).unwrap();
    let e1 = sim.heat_energy().unwrap();
    assert!(
        spread(&sim) < 0.01 * before,
        "no equalisation: {}",
        spread(&sim)
    );
    assert!((e1 - e0).abs() <= 1e-13 * e0, "Σ m c T {e0} → {e1}");
}

/// The same run on 1 and 2 threads gives the same temperatures bit for bit.
#[test]
fn heat_is_the_same_on_every_thread_count() {
    let run = |threads: usize| {
        common::on_threads(threads, || {
            let dir = tempfile::tempdir().unwrap();
            let (sim, _) = native(dir.path(), &vars("overlap"));
            sim.temperature().unwrap().to_vec()
        })
    };
    assert_eq!(run(1), run(2));
}

/// A deck with `couple/cfd/convection` only (no conduction): with a constant convective heat
/// flow q per particle, T = T₀ + q t/(m c) exactly as explicit Euler sums a constant (to the
/// round-off of n additions).
#[test]
fn constant_convection_heats_linearly() {
    let dir = tempfile::tempdir().unwrap();
    let deck_text = PREAMBLE.to_string()
        + "\
region box block -1 1 -1 1 -1 1 units box
create_box 1 box
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 0.5 0 0 units box
set group all diameter 0.1 density 2000
" + MATERIALS
        + "\
fix tca all property/global thermalCapacity peratomtype 800.
timestep 0.001
fix integr all nve/sphere
fix cfd all couple/cfd couple_every 10 mpi
fix conv all couple/cfd/convection T0 293.15
dump d all custom 100 post/conv.txt id f_Temp[0] f_heatFlux[0] f_convectiveHeatFlux[0]
run 0
";
    std::fs::create_dir_all(dir.path().join("post")).unwrap();
    let path = dir.path().join("in.conv");
    std::fs::write(&path, deck_text).unwrap();
    let deck = liggghts_deck::Deck::read(&path).unwrap();
    let mut sim = dem::Simulation::from_deck(&deck, dir.path()).unwrap();
    assert_eq!(sim.temperature().unwrap(), &[293.15, 293.15]);
    let q = [2.5, -1.25];
    sim.set_convective_heat_flux(&q).unwrap();
    let n = 1000;
    sim.run(n).unwrap();
    let m = 4.0 / 3.0 * std::f64::consts::PI * 0.05f64.powi(3) * 2000.0;
    let t = n as f64 * sim.dt();
    for (i, &qi) in q.iter().enumerate() {
        let want = 293.15 + qi * t / (m * 800.0);
        let got = sim.temperature().unwrap()[i];
        assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
        assert_eq!(sim.heat().unwrap().flux[i], qi);
    }
    // the dump carries the values
    let s = read_snapshot(
        dir.path().join("post/conv.txt"),
        &ReadOptions::default(),
        Selection::Last,
    )
    .unwrap();
    assert_eq!(s.column("f_convectiveHeatFlux[0]").unwrap(), &q);
    // Σ m c T grew by Σ q t
    let e = sim.heat_energy().unwrap();
    let e0 = 2.0 * m * 800.0 * 293.15;
    assert!((e - e0 - (q[0] + q[1]) * t).abs() < 1e-9 * e0);
}

/// Without a convection fix the coupler's call is refused, naming what the deck needs.
#[test]
fn convective_flux_needs_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let (mut sim, _) = native(dir.path(), &vars("overlap"));
    let e = sim
        .set_convective_heat_flux(&[0.0; 6])
        .unwrap_err()
        .to_string();
    assert!(e.contains("couple/cfd/convection"), "{e}");
}

/// Unsupported `heat/gran` options are refused naming the line.
#[test]
fn unknown_heat_gran_keyword_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let text = std::fs::read_to_string(dir.path().join("heat_conduction.in"))
        .unwrap()
        .replace("contact_area ${area}", "radiation yes");
    std::fs::write(dir.path().join("bad.in"), text).unwrap();
    let deck = liggghts_deck::Deck::read(dir.path().join("bad.in")).unwrap();
    let e = dem::Simulation::from_deck(&deck, dir.path())
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.in:") && e.contains("radiation"), "{e}");
}

/// Full tier: LIGGGHTS reruns the deck and reproduces the committed dumps byte for byte.
#[test]
fn liggghts_reproduces_the_heat_fixtures() {
    if !testkit::full_tier() || !testkit::tool("liggghts") {
        eprintln!("skipped: full tier with liggghts only");
        return;
    }
    for (area, wall_t, file) in VARIANTS {
        let dir = tempfile::tempdir().unwrap();
        setup(dir.path());
        let mut c = Command::new("liggghts");
        c.args(["-in", "heat_conduction.in", "-var", "area", area])
            .args(["-var", "wallT", wall_t])
            .args(["-log", "log.liggghts", "-screen", "none"])
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
        testkit::run_ok(c, dir.path());
        let fresh = std::fs::read(dir.path().join("post/heat_conduction.txt")).unwrap();
        assert_eq!(
            fresh,
            std::fs::read(testkit::fixture(file)).unwrap(),
            "{area}"
        );
        let (_, ours) = native(&dir.path().join("native"), &variant(area, wall_t));
        assert_same(
            &ours,
            &snapshots(&dir.path().join("post/heat_conduction.txt")),
        );
    }
}

/// Runs `deck` (of `tests/fixtures/dem/restart/`) natively in `dir` next to `restart` (copied as
/// `heat.1000`); returns the simulation and its dump.
fn continued(
    dir: &Path,
    deck: &str,
    restart: &Path,
    dump: &str,
) -> (dem::Simulation, Vec<Snapshot>) {
    std::fs::create_dir_all(dir.join("post")).unwrap();
    if restart != dir.join("heat.1000") {
        std::fs::copy(restart, dir.join("heat.1000")).unwrap();
    }
    std::fs::copy(
        testkit::fixture(&format!("dem/restart/{deck}")),
        dir.join(deck),
    )
    .unwrap();
    let deck = liggghts_deck::Deck::read(dir.join(deck)).unwrap();
    let sim = dem::Simulation::from_deck(&deck, dir).unwrap();
    let snaps = (0..11)
        .map(|k| {
            let path = dir.join("post").join(dump);
            read_snapshot(path, &ReadOptions::default(), Selection::Index(k)).unwrap()
        })
        .collect();
    (sim, snaps)
}

fn fixture_snapshots(file: &str) -> Vec<Snapshot> {
    (0..11)
        .map(|k| {
            let path = testkit::fixture(&format!("dem/restart/{file}"));
            read_snapshot(path, &ReadOptions::default(), Selection::Index(k)).unwrap()
        })
        .collect()
}

/// LIGGGHTS's restart file (step 1000 of `heat_conduction.in`) carries `Temp` and `heatFlux`;
/// a deck defining `heat/gran` before its first run takes them up and continues as LIGGGHTS
/// continues it (`heat_continued_2000.txt`); defined after a `run 0` (CFDEM's packedBedTemp),
/// the temperatures start at initial_temperature in both, with a warning here.
#[test]
fn liggghts_restart_carries_the_temperatures() {
    let restart = testkit::fixture("dem/restart/heat.1000");
    let dir = tempfile::tempdir().unwrap();
    let (sim, ours) = continued(
        dir.path(),
        "heat_continue.in",
        &restart,
        "heat_continued.txt",
    );
    let reference = fixture_snapshots("heat_continued_2000.txt");
    // the file's values exactly at the set-up (step 1000), then the run
    let first = |s: &Snapshot, c: &str| s.column(c).unwrap().to_vec();
    let pack = snapshots(&testkit::fixture("dem/heat_conduction_liggghts.txt"));
    assert_eq!(first(&ours[0], "f_Temp[0]"), first(&pack[10], "f_Temp[0]"));
    assert_eq!(
        first(&ours[0], "f_heatFlux[0]"),
        first(&pack[10], "f_heatFlux[0]")
    );
    for c in ["x", "vx", "f_Temp[0]", "f_heatFlux[0]"] {
        common::assert_column_close(&ours, &reference, c, TOL_RESTART);
    }
    assert!(sim.warnings().is_empty(), "{:?}", sim.warnings());

    let dir = tempfile::tempdir().unwrap();
    let deck = "heat_continue_late.in";
    std::fs::create_dir_all(dir.path().join("post")).unwrap();
    std::fs::copy(&restart, dir.path().join("heat.1000")).unwrap();
    std::fs::copy(
        testkit::fixture(&format!("dem/restart/{deck}")),
        dir.path().join(deck),
    )
    .unwrap();
    let mut warnings = Vec::new();
    let d = liggghts_deck::Deck::read(dir.path().join(deck)).unwrap();
    dem::Simulation::from_deck_observed(&d, dir.path(), &mut |e| {
        if let dem::deck::exec::DeckEvent::Warning { message, .. } = e {
            warnings.push(message);
        }
    })
    .unwrap();
    assert!(warnings.iter().any(|w| w.contains("Temp")), "{warnings:?}");
    let late: Vec<Snapshot> = (0..11)
        .map(|k| {
            let path = dir.path().join("post/heat_continued_late.txt");
            read_snapshot(path, &ReadOptions::default(), Selection::Index(k)).unwrap()
        })
        .collect();
    let reference = fixture_snapshots("heat_continued_late_2000.txt");
    assert!(first(&late[0], "f_Temp[0]").iter().all(|&t| t == 300.0));
    for c in ["x", "vx", "f_Temp[0]", "f_heatFlux[0]"] {
        common::assert_column_close(&late, &reference, c, TOL_RESTART);
    }
}

/// A native restart file keeps the heat state: the run continued from it is the uninterrupted
/// run (temperatures to round-off of the contact sums' order, here bit for bit).
#[test]
fn native_restart_continues_the_heat_state() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let v = vec![("nsteps".to_string(), "1000".to_string())];
    let deck = liggghts_deck::Deck::read_with_vars(dir.path().join("heat_conduction.in"), &v);
    let sim = dem::Simulation::from_deck(&deck.unwrap(), dir.path()).unwrap();
    dem::deck::restart::write(&sim, "heat.1000", dir.path()).unwrap();
    let restart = dir.path().join("heat.1000");
    let (cont, ours) = continued(
        dir.path(),
        "heat_continue.in",
        &restart,
        "heat_continued.txt",
    );
    let full = tempfile::tempdir().unwrap();
    let (whole, _) = native(full.path(), &[]);
    assert_eq!(cont.step(), 2000);
    assert_eq!(cont.temperature().unwrap(), whole.temperature().unwrap());
    assert_eq!(cont.heat().unwrap().flux, whole.heat().unwrap().flux);
    assert_eq!(ours.len(), 11);
}

/// Full tier: LIGGGHTS rewrites the restart fixtures (`heat_pack.in`, then both
/// continuations) byte for byte, but for the stale `f_ht[0]` of `heat_continue.in`'s set-up.
#[test]
fn liggghts_reproduces_the_heat_restart_fixtures() {
    if !testkit::full_tier() || !testkit::tool("liggghts") {
        eprintln!("skipped: full tier with liggghts only");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let liggghts = |deck: &str| {
        std::fs::copy(
            testkit::fixture(&format!("dem/restart/{deck}")),
            dir.path().join(deck),
        )
        .unwrap();
        let mut c = Command::new("liggghts");
        c.args(["-in", deck, "-log", "log.liggghts", "-screen", "none"])
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
        testkit::run_ok(c, dir.path());
    };
    liggghts("heat_pack.in");
    let same = |made: &str, fixture: &str| {
        let fresh = std::fs::read(dir.path().join(made)).unwrap();
        let kept = std::fs::read(testkit::fixture(&format!("dem/restart/{fixture}"))).unwrap();
        assert!(fresh == kept, "{made} differs from {fixture}");
    };
    same("post/heat.1000", "heat.1000");
    std::fs::copy(
        dir.path().join("post/heat.1000"),
        dir.path().join("heat.1000"),
    )
    .unwrap();
    liggghts("heat_continue.in");
    // every value but the set-up's `f_ht[0]`, which LIGGGHTS prints from stale memory (README)
    let fresh: Vec<Snapshot> = (0..11)
        .map(|k| {
            let path = dir.path().join("post/heat_continued.txt");
            read_snapshot(path, &ReadOptions::default(), Selection::Index(k)).unwrap()
        })
        .collect();
    let kept = fixture_snapshots("heat_continued_2000.txt");
    for (k, (a, b)) in fresh.iter().zip(&kept).enumerate() {
        for c in [
            "id",
            "type",
            "x",
            "vx",
            "f_Temp[0]",
            "f_heatFlux[0]",
            "f_ht[0]",
        ] {
            if k > 0 || c != "f_ht[0]" {
                assert_eq!(
                    a.column(c).unwrap(),
                    b.column(c).unwrap(),
                    "{c} of snapshot {k}"
                );
            }
        }
    }
    liggghts("heat_continue_late.in");
    same(
        "post/heat_continued_late.txt",
        "heat_continued_late_2000.txt",
    );
}

/// Inserted particles start at T₀; deleted ones take their heat into the tally, so Σ m c T of
/// the remaining particles plus the deleted heat is what it was.
#[test]
fn inserted_particles_start_at_t0_and_deleted_heat_is_counted() {
    let dir = tempfile::tempdir().unwrap();
    let text = PREAMBLE.to_string()
        + "\
region box block 0 0.1 0 0.1 0 0.1 units box
create_box 1 box
"
        + MATERIALS
        + "\
fix tc all property/global thermalConductivity peratomtype 5.
fix tca all property/global thermalCapacity peratomtype 10.
timestep 0.00001
fix ht all heat/gran initial_temperature 263.
fix pts all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 0.005
fix pdd all particledistribution/discrete 15485867 1 pts 1.0
fix ins all insert/pack seed 32452843 distributiontemplate pdd insert_every once overlapcheck yes all_in yes particles_in_region 40 region box
fix integr all nve/sphere
run 1
region half block 0 0.05 0 0.1 0 0.1 units box
set region half property/atom Temp 400.
run 0
";
    let path = dir.path().join("in.ins");
    std::fs::write(&path, text).unwrap();
    let deck = liggghts_deck::Deck::read(&path).unwrap();
    let mut sim = dem::Simulation::from_deck(&deck, dir.path()).unwrap();
    let n = sim.particles.len();
    assert_eq!(n, 40);
    let t = sim.temperature().unwrap();
    let hot = t.iter().filter(|&&x| x == 400.0).count();
    assert!(hot > 0 && hot < n, "{hot} of {n} set");
    assert!(t.iter().all(|&x| x == 400.0 || x == 263.0));
    let before = sim.heat_energy().unwrap();
    let region = dem::region::Region::Block {
        lo: mesh::v3::V3::new(0.0, 0.0, 0.0),
        hi: mesh::v3::V3::new(0.05, 0.1, 0.1),
    };
    let gone = sim.delete_in_region(&region);
    assert!(gone > 0);
    let after = sim.heat_energy().unwrap();
    let deleted = sim.outflow().deleted.heat;
    assert!(deleted > 0.0);
    assert!((after + deleted - before).abs() <= 1e-12 * before);
}

/// CFDEM's packedBedTemp run deck's pattern: `run 0` before `fix nve/sphere` (a run of steps
/// still needs it), the heat fixes after it, a region of `INF` bounds, and the
/// liggghtsCommand `set region total property/atom Temp 600` between runs.
#[test]
fn packed_bed_temp_pattern() {
    let dir = tempfile::tempdir().unwrap();
    let head = PREAMBLE.to_string()
        + "\
region box block 0 0.1 0 0.1 0 0.1 units box
create_box 1 box
create_atoms 1 single 0.05 0.05 0.05 units box
create_atoms 1 single 0.02 0.05 0.05 units box
set group all diameter 0.022 density 2500
" + MATERIALS
        + "\
timestep 0.00001
fix cfd all couple/cfd couple_every 100 mpi
fix cfd2 all couple/cfd/force/implicit
fix ftco all property/global thermalConductivity peratomtype 5.
fix ftca all property/global thermalCapacity peratomtype 0.1
run 0
fix heattransfer all heat/gran initial_temperature 600.
fix cfd3 all couple/cfd/convection T0 600
region total block INF INF INF INF INF INF units box
";
    let read = |text: String| {
        let path = dir.path().join("in.run");
        std::fs::write(&path, text).unwrap();
        liggghts_deck::Deck::read(&path).unwrap()
    };
    let e = dem::Simulation::from_deck(&read(head.clone() + "run 10\n"), dir.path())
        .unwrap_err()
        .to_string();
    assert!(e.contains("nve/sphere") && e.contains("in.run:"), "{e}");
    let deck = read(head + "fix integr all nve/sphere\nrun 0\n");
    let mut s = dem::deck::exec::Session::new(dir.path(), |_| {});
    s.execute(&deck).unwrap();
    let sim = s.simulation().unwrap();
    sim.set_convective_heat_flux(&[1.0, -1.0]).unwrap();
    s.advance(100).unwrap();
    let t = s.sim().unwrap().temperature().unwrap().to_vec();
    assert!(t[0] > 600.0 && t[1] < 600.0, "{t:?}");
    s.command_text(
        "set region total property/atom Temp 600",
        Path::new("liggghtsCommands"),
    )
    .unwrap();
    assert_eq!(s.sim().unwrap().temperature().unwrap(), &[600.0, 600.0]);
}
