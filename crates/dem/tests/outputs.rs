//! The run-time outputs CFDEM decks use (`tests/fixtures/dem/outputs.in`): equal-style
//! variables of thermo keywords, per-atom values by tag and compute references, `compute com`,
//! `compute reduce`, `fix print` and thermo columns naming them.
//!
//! Fast tier: against closed forms — the free-falling sphere's velocity −0.2 − g t and height
//! (velocity Verlet is exact for a constant force), the bouncing sphere's horizontal velocity
//! (0.1 m/s until it touches the floor). Full tier: Debian's LIGGGHTS runs the same deck and
//! its `fix print` file agrees with the native one line by line to round-off (both spheres'
//! motion is deterministic: one wall contact, no particle contacts).

use std::path::Path;
use std::process::Command;

const G: f64 = 9.81;
const DT: f64 = 1e-5;

fn rows(path: &Path) -> (String, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let title = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect();
    (title, rows)
}

fn run_native(dir: &Path) -> Vec<String> {
    let deck = liggghts_deck::Deck::read(testkit::fixture("dem/outputs.in")).unwrap();
    let mut out = Vec::new();
    let mut warnings = Vec::new();
    dem::Simulation::from_deck_observed(&deck, dir, &mut |e| match e {
        dem::deck::exec::DeckEvent::Output(l) => out.push(l),
        dem::deck::exec::DeckEvent::Warning { message, .. } => warnings.push(message),
        _ => {}
    })
    .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    out
}

#[test]
fn fix_print_and_thermo_follow_the_closed_forms() {
    let dir = tempfile::tempdir().unwrap();
    let screen = run_native(dir.path());
    let (title, rows) = rows(&dir.path().join("post/outputs.txt"));
    assert_eq!(title, "# time vz1 zcom 2ke vzsum zmin");
    // every 250 steps after the run starts, to step 2000
    assert_eq!(rows.len(), 8);
    let m = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.01f64.powi(3);
    for (k, r) in rows.iter().enumerate() {
        let t = (k as f64 + 1.0) * 250.0 * DT;
        assert!((r[0] - t).abs() < 1e-15, "time {} vs {t}", r[0]);
        // sphere 2 falls freely from 0.15 m at −0.2 m/s; sphere 1 sits on the floor (its
        // velocity is whatever the contact makes it: bounded by the fall speed)
        let vz2 = -0.2 - G * t;
        let z2 = 0.15 - 0.2 * t - 0.5 * G * t * t;
        assert!(r[1].abs() <= 0.2 + G * t + 1e-12, "vz1 {}", r[1]);
        // Σvz = vz1 + vz2, z_com = (z1 + z2)/2 (equal masses): recover sphere 1 both ways
        let vz1 = r[4] - vz2;
        assert!(
            (vz1 - r[1]).abs() < 1e-12,
            "Σvz {} − vz2 {vz2} vs vz1 {}",
            r[4],
            r[1]
        );
        let z1 = 2.0 * r[2] - z2;
        assert!(
            (r[5] - z1.min(z2)).abs() < 1e-12,
            "zmin {} vs {}",
            r[5],
            z1.min(z2)
        );
        // sphere 1 bounces (e = 0.5) no higher than its start plus v²/2g
        assert!(
            (0.0..0.0105 + 0.04 / (2.0 * G)).contains(&z1),
            "sphere 1 at z = {z1}"
        );
        // 2 ke: both spheres' m|v|² — the free one's part is known, the rest is sphere 1's
        let free = m * (0.1 * 0.1 + vz2 * vz2);
        assert!(
            r[3] >= free * (1.0 - 1e-12),
            "2ke {} < free sphere's {free}",
            r[3]
        );
    }
    // thermo: header once per run, rows at 0, 500, …, 2000 with the named columns
    let header = screen.iter().find(|l| l.contains("Step")).unwrap();
    assert_eq!(
        header.split_whitespace().collect::<Vec<_>>(),
        [
            "Step",
            "Atoms",
            "KinEng",
            "rke",
            "centerOfMass[3]",
            "vsum[3]",
            "time"
        ]
    );
    let thermo: Vec<Vec<f64>> = screen
        .iter()
        .filter_map(|l| {
            let v: Vec<f64> = l
                .split_whitespace()
                .map(|w| w.parse().ok())
                .collect::<Option<_>>()?;
            (v.len() == 7).then_some(v)
        })
        .collect();
    assert_eq!(
        thermo.iter().map(|r| r[0]).collect::<Vec<_>>(),
        [0.0, 500.0, 1000.0, 1500.0, 2000.0]
    );
    for r in &thermo[1..] {
        assert!((r[6] - r[0] * DT).abs() < 1e-15);
        let p = rows.iter().find(|p| (p[0] - r[6]).abs() < 1e-12).unwrap();
        // the thermo row and the print of the same step see the same state (%.8g vs %.15g)
        assert!(
            (r[4] - p[2]).abs() <= 1e-7 * p[2].abs(),
            "{} vs {}",
            r[4],
            p[2]
        );
        assert!(
            (r[5] - p[4]).abs() <= 1e-7 * p[4].abs(),
            "{} vs {}",
            r[5],
            p[4]
        );
        assert!(
            (2.0 * r[2] - p[3]).abs() <= 1e-7 * p[3],
            "{} vs {}",
            r[2],
            p[3]
        );
    }
}

#[test]
fn bad_references_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("variable v equal vx[9]", "there is no atom with tag 9"),
        ("variable v equal c_nope[1]", "no compute `nope`"),
        ("variable v equal c_centerOfMass", "name an element"),
        ("variable v equal f_gravi[1]", "couple/cfd/force"),
    ];
    let base = std::fs::read_to_string(testkit::fixture("dem/outputs.in")).unwrap();
    for (var, expect) in cases {
        let src = base
            .replace("variable        vz equal vz[1]", var)
            .replace("${vz}", "${v}")
            .replace("run             2000", "run             300");
        let deck = liggghts_deck::Deck::parse(&src, Path::new("bad.in"), &[]).unwrap();
        let e = dem::Simulation::from_deck(&deck, dir.path())
            .unwrap_err()
            .to_string();
        assert!(e.contains(expect), "{var}: {e}");
        assert!(e.contains("bad.in:"), "{var}: {e}");
    }
}

#[test]
fn liggghts_prints_the_same() {
    if !testkit::tool("liggghts") {
        return;
    }
    let ndir = tempfile::tempdir().unwrap();
    run_native(ndir.path());
    let ldir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(ldir.path().join("post")).unwrap();
    let mut c = Command::new("liggghts");
    c.args(["-in"])
        .arg(testkit::fixture("dem/outputs.in"))
        .args(["-log", "none", "-screen", "none"]);
    testkit::run_ok(c, ldir.path());
    let (nt, native) = rows(&ndir.path().join("post/outputs.txt"));
    let (lt, liggghts) = rows(&ldir.path().join("post/outputs.txt"));
    assert_eq!(nt, lt);
    assert_eq!(native.len(), liggghts.len());
    for (a, b) in native.iter().zip(&liggghts) {
        for (x, y) in a.iter().zip(b) {
            let scale = x.abs().max(y.abs()).max(1e-12);
            assert!(
                (x - y).abs() <= 1e-9 * scale,
                "native {a:?}\nLIGGGHTS {b:?}"
            );
        }
    }
}

/// `dump custom/vtk` (CFDEM-PFM's decks) writes the particles a `dump custom` of the same
/// columns writes: legacy VTK points and arrays equal to the custom dump's values, with a
/// column named twice written once (LIGGGHTS's `type type`).
#[test]
fn custom_vtk_dump_matches_the_custom_dump() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(testkit::fixture("dem/outputs.in"))
        .unwrap()
        .replace(
            "run             2000",
            "dump d1 all custom 1000 post/d_*.txt id type type x y z vx vy vz radius\n\
             dump d2 all custom/vtk 1000 post/d_*.vtk id type type x y z vx vy vz radius\n\
             run 2000",
        );
    let deck = liggghts_deck::Deck::parse(&src, Path::new("vtk.in"), &[]).unwrap();
    dem::Simulation::from_deck(&deck, dir.path()).unwrap();
    let custom = dem_io::read_snapshot(
        dir.path().join("post/d_2000.txt"),
        &dem_io::ReadOptions::default(),
        dem_io::Selection::Last,
    )
    .unwrap();
    let text = std::fs::read_to_string(dir.path().join("post/d_2000.vtk")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "# vtk DataFile Version 2.0");
    assert_eq!(lines[4], "POINTS 2 double");
    let nums = |l: &str| -> Vec<f64> { l.split_whitespace().map(|w| w.parse().unwrap()).collect() };
    let x = custom.require("x").unwrap();
    let z = custom.require("z").unwrap();
    for i in 0..2 {
        let p = nums(lines[5 + i]);
        assert_eq!((p[0], p[2]), (x[i], z[i]));
    }
    // FIELD arrays: id, type (once), v (a vector), radius
    let field = lines.iter().position(|l| l.starts_with("FIELD")).unwrap();
    assert_eq!(lines[field], "FIELD FieldData 4");
    let array = |name: &str| -> Vec<Vec<f64>> {
        let k = lines
            .iter()
            .position(|l| l.starts_with(&format!("{name} ")))
            .unwrap();
        lines[k + 1..k + 3].iter().map(|l| nums(l)).collect()
    };
    let vz = custom.require("vz").unwrap();
    assert_eq!(array("v")[1][2], vz[1]);
    assert_eq!(array("radius")[0][0], custom.require("radius").unwrap()[0]);
    assert_eq!(array("type")[1][0], 1.0);
}
