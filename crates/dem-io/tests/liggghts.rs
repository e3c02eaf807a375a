//! Tests against real output of Debian's LIGGGHTS 3.8.0 (decks and dumps in
//! `tests/fixtures/liggghts/`), and — when `liggghts` is installed — against a fresh run.

#![allow(clippy::needless_range_loop)] // parallel arrays read clearer by index

mod common;

use std::f64::consts::PI;
use std::path::Path;
use std::process::Command;

use approx::{abs_diff_eq, assert_abs_diff_eq, assert_relative_eq};
use common::{assert_same_values, fixtures, read_all};
use dem_io::{read_snapshot, Boundary, DumpReader, ErrorKind, ReadOptions, Selection, Snapshot};

const SETTLE_COLUMNS: [&str; 13] = [
    "id", "type", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "radius", "mass",
];
const TRICLINIC_COLUMNS: [&str; 15] = [
    "id", "type", "x", "y", "z", "xs", "ys", "zs", "xu", "yu", "zu", "vx", "vy", "vz", "radius",
];
const TWOPROC_COLUMNS: [&str; 9] = ["id", "type", "x", "y", "z", "vx", "vy", "vz", "radius"];

fn bin_options(columns: &[&str]) -> ReadOptions {
    ReadOptions::default().with_binary_columns(columns)
}

/// Text (full precision) and binary dumps of the same run hold bit-identical values, and the
/// headers agree (text box bounds are `%g`).
fn assert_text_equals_binary(dir: &Path, stem: &str, columns: &[&str], steps: &[u64]) {
    let text = read_all(&dir.join(format!("{stem}.txt")), &ReadOptions::default());
    let bin = read_all(&dir.join(format!("{stem}.bin")), &bin_options(columns));
    assert_eq!(text.len(), steps.len());
    assert_eq!(bin.len(), steps.len());
    for ((t, b), &step) in text.iter().zip(&bin).zip(steps) {
        assert_eq!(t.timestep, step);
        assert_eq!(t.column_names(), columns);
        assert_same_values(t, b);
        assert_eq!(t.bounds.boundary, b.bounds.boundary);
        assert_eq!(t.bounds.tilt.is_some(), b.bounds.tilt.is_some());
        for k in 0..3 {
            assert_relative_eq!(
                t.bounds.lo[k],
                b.bounds.lo[k],
                epsilon = 0.0,
                max_relative = 5e-6
            );
            assert_relative_eq!(
                t.bounds.hi[k],
                b.bounds.hi[k],
                epsilon = 0.0,
                max_relative = 5e-6
            );
            if let (Some(tt), Some(bt)) = (t.bounds.tilt, b.bounds.tilt) {
                assert_relative_eq!(tt[k], bt[k], epsilon = 0.0, max_relative = 5e-6);
            }
        }
    }
}

#[test]
fn settle_text_and_binary_are_identical() {
    assert_text_equals_binary(&fixtures(), "settle", &SETTLE_COLUMNS, &[3000, 6000]);
}

#[test]
fn triclinic_text_and_binary_are_identical() {
    assert_text_equals_binary(&fixtures(), "triclinic", &TRICLINIC_COLUMNS, &[0, 5]);
}

#[test]
fn two_rank_text_and_binary_are_identical() {
    assert_text_equals_binary(&fixtures(), "twoproc", &TWOPROC_COLUMNS, &[0, 50, 100]);
    // The binary file really has two chunks per snapshot: the i32 after
    // step(8) natoms(8) triclinic(4) boundary(24) box(48) ncols(4) is the chunk count.
    let bytes = std::fs::read(fixtures().join("twoproc.bin")).unwrap();
    assert_eq!(i32::from_le_bytes(bytes[96..100].try_into().unwrap()), 2);
}

/// The settle deck: 200 spheres, radius 0.5 mm (ρ 2500) or 0.7 mm (ρ 2000), in
/// [-0.01, 0.01]² × [0, 0.03] with `boundary m m f`, falling onto a wall at z = 0.
#[test]
fn settle_matches_the_deck() {
    let path = fixtures().join("settle.txt");
    let snaps = read_all(&path, &ReadOptions::default());
    for snap in &snaps {
        // `m` (shrink-wrap with minimum) lets x and y grow beyond ±0.01, never shrink.
        let b = snap.bounds;
        assert!(b.lo[0] <= -0.01 && b.lo[1] <= -0.01 && b.hi[0] >= 0.01 && b.hi[1] >= 0.01);
        assert_eq!((b.lo[2], b.hi[2]), (0.0, 0.03));
        assert_eq!(b.tilt, None);
        let m = Boundary::ShrinkMin;
        let f = Boundary::Fixed;
        assert_eq!(b.boundary, [[m, m], [m, m], [f, f]]);

        let p = snap.particles().unwrap();
        assert_eq!(p.len(), 200);
        let mut ids = p.id.clone();
        ids.sort_unstable();
        assert_eq!(ids, (1..=200).collect::<Vec<u64>>());
        assert!(p.atom_type.iter().all(|&t| t == 1));
        assert!(p.force.is_none() && p.density.is_none());
        let mass = p.mass.as_ref().unwrap();
        for i in 0..p.len() {
            let r = p.radius[i];
            let rho = if r == 0.0005 {
                2500.0
            } else {
                assert_eq!(r, 0.0007);
                2000.0
            };
            assert_relative_eq!(
                mass[i],
                rho * 4.0 / 3.0 * PI * r.powi(3),
                epsilon = 0.0,
                max_relative = 1e-12
            );
            let x = p.position[i];
            // Shrink-wrapped faces follow the particles only at re-neighbouring, so a
            // particle may be up to the neighbour skin (0.5 mm) outside.
            let skin = 0.0005;
            assert!(
                (0..2).all(|k| x[k] > b.lo[k] - skin && x[k] < b.hi[k] + skin),
                "{x:?}"
            );
            // On or above the floor (Hertz overlaps are tiny) and below the fill region top.
            assert!(x[2] > 0.9 * r && x[2] < 0.03, "z = {}", x[2]);
        }
    }
    // By step 6000 (0.06 s) the bed has reached the floor.
    let last = snaps.last().unwrap().positions().unwrap();
    let min_z = last.iter().map(|x| x[2]).fold(f64::INFINITY, f64::min);
    assert!(min_z < 0.00051, "lowest centre {min_z}");
}

/// The `%g` dump of the same run, with scaled coordinates, `density` and a label, agrees with
/// the exact binary dump to `%g` precision (6 significant digits: relative error ≤ 5e-6).
#[test]
fn default_precision_text_with_scaled_coordinates() {
    let g = read_all(&fixtures().join("settle_g.txt"), &ReadOptions::default());
    let bin = read_all(
        &fixtures().join("settle.bin"),
        &bin_options(&SETTLE_COLUMNS),
    );
    assert_eq!(g.len(), bin.len());
    for (g, b) in g.iter().zip(&bin) {
        assert_eq!(g.label.as_deref(), Some("SETTLE"));
        assert_eq!(b.label, None);
        assert_eq!(g.column_names()[2..5], ["xs", "ys", "zs"]);
        let pg = g.particles().unwrap();
        let pb = b.particles().unwrap();
        assert_eq!(pg.id, pb.id);
        let density = pg.density.as_ref().unwrap();
        for i in 0..pg.len() {
            for k in 0..3 {
                // x = lo + xs·(hi − lo) with lo, hi and xs each carrying the %g rounding
                // (relative 5e-6 for lo and hi, absolute 5e-7 for xs ∈ [0.1, 1)).
                let (lo, hi) = (g.bounds.lo[k], g.bounds.hi[k]);
                let tol = 5e-6 * (lo.abs() + hi.abs()) + 5e-7 * (hi - lo);
                assert!(
                    abs_diff_eq!(pg.position[i][k], pb.position[i][k], epsilon = tol),
                    "step {} id {} axis {k}: {} vs {}",
                    g.timestep,
                    pg.id[i],
                    pg.position[i][k],
                    pb.position[i][k]
                );
                assert_relative_eq!(
                    pg.velocity[i][k],
                    pb.velocity[i][k],
                    epsilon = 1e-300,
                    max_relative = 5e-6
                );
            }
            assert_relative_eq!(
                pg.radius[i],
                pb.radius[i],
                epsilon = 0.0,
                max_relative = 5e-6
            );
            let expected = if pb.radius[i] == 0.0005 {
                2500.0
            } else {
                2000.0
            };
            assert_eq!(density[i], expected);
        }
    }
}

/// The triclinic deck: prism 0.01³ with tilt xy 0.002, xz −0.001, yz 0.0015, `p p f`.
#[test]
fn triclinic_box_and_scaled_coordinates() {
    let snaps = read_all(
        &fixtures().join("triclinic.bin"),
        &bin_options(&TRICLINIC_COLUMNS),
    );
    for snap in &snaps {
        let b = snap.bounds;
        assert_eq!(b.tilt, Some([0.002, -0.001, 0.0015]));
        let p = Boundary::Periodic;
        let f = Boundary::Fixed;
        assert_eq!(b.boundary, [[p, p], [p, p], [f, f]]);
        let cell = b.cell();
        for k in 0..3 {
            assert_abs_diff_eq!(cell.origin[k], 0.0, epsilon = 1e-18);
            assert_relative_eq!(cell.edges[k][k], 0.01, epsilon = 0.0, max_relative = 1e-14);
        }
        assert_eq!(cell.edges[1][0], 0.002);
        assert_eq!(cell.edges[2][0], -0.001);
        assert_eq!(cell.edges[2][1], 0.0015);

        let x = snap.vectors(["x", "y", "z"]).unwrap();
        let xs = snap.vectors(["xs", "ys", "zs"]).unwrap();
        let xu = snap.vectors(["xu", "yu", "zu"]).unwrap();
        assert_eq!(x.len(), 27);
        for i in 0..x.len() {
            let from_scaled = b.scaled_to_cartesian(xs[i]);
            for k in 0..3 {
                assert!(
                    abs_diff_eq!(from_scaled[k], x[i][k], epsilon = 1e-15),
                    "{from_scaled:?} {:?}",
                    x[i]
                );
            }
        }
        // Without x y z the particle view falls back to unwrapped, then scaled coordinates.
        let (names, data) = snap.clone().into_columns();
        let keep = |drop: &[&str]| {
            let (n, d): (Vec<String>, Vec<Vec<f64>>) = names
                .iter()
                .cloned()
                .zip(data.iter().cloned())
                .filter(|(n, _)| !drop.contains(&n.as_str()))
                .unzip();
            Snapshot::new(snap.timestep, b, n, d).unwrap()
        };
        assert_eq!(keep(&["x", "y", "z"]).positions().unwrap(), xu);
        let scaled = keep(&["x", "y", "z", "xu", "yu", "zu"])
            .positions()
            .unwrap();
        for (s, x) in scaled.iter().zip(&x) {
            assert!((0..3).all(|k| abs_diff_eq!(s[k], x[k], epsilon = 1e-15)));
        }
    }
    // In the text dump the bounds are the %g-printed bounding box.
    let t = read_snapshot(
        fixtures().join("triclinic.txt"),
        &ReadOptions::default(),
        Selection::Index(0),
    )
    .unwrap();
    assert_eq!(t.bounds.lo, [-0.001, 0.0, 0.0]);
    assert_eq!(t.bounds.hi, [0.012, 0.0115, 0.01]);
}

#[test]
fn selection_by_last_index_and_timestep() {
    for (name, opts) in [
        ("settle.txt", ReadOptions::default()),
        ("settle.bin", bin_options(&SETTLE_COLUMNS)),
    ] {
        let path = fixtures().join(name);
        let all = read_all(&path, &opts);
        let last = read_snapshot(&path, &opts, Selection::Last).unwrap();
        assert_eq!(last.timestep, 6000);
        assert_same_values(&last, &all[1]);
        let first = read_snapshot(&path, &opts, Selection::Timestep(3000)).unwrap();
        assert_same_values(&first, &all[0]);
        let second = read_snapshot(&path, &opts, Selection::Index(1)).unwrap();
        assert_same_values(&second, &all[1]);

        let err = read_snapshot(&path, &opts, Selection::Timestep(4000)).unwrap_err();
        assert!(matches!(err.kind, ErrorKind::NotFound(_)), "{err}");
        assert!(err.to_string().contains(name), "{err}");
        let err = read_snapshot(&path, &opts, Selection::Index(2)).unwrap_err();
        assert!(matches!(err.kind, ErrorKind::NotFound(_)), "{err}");

        let mut reader = DumpReader::open(&path, &opts).unwrap();
        let headers = reader.headers().unwrap();
        let steps: Vec<u64> = headers.iter().map(|h| h.timestep).collect();
        assert_eq!(steps, [3000, 6000]);
        assert!(headers.iter().all(|h| h.natoms == 200));
        assert_eq!(headers[0].offset, 0);
    }
}

#[test]
fn binary_with_wrong_column_names_is_rejected() {
    let path = fixtures().join("settle.bin");
    let err = read_snapshot(&path, &ReadOptions::default(), Selection::Last).unwrap_err();
    match &err.kind {
        ErrorKind::ColumnCountMismatch { in_file, given, .. } => {
            assert_eq!((*in_file, *given), (13, 9));
        }
        other => panic!("unexpected {other:?}"),
    }
    // The count sits after step, natoms, triclinic flag, boundary codes and box.
    assert_eq!(err.location, dem_io::Location::Byte(92));
    assert!(err.to_string().starts_with(&path.display().to_string()));
}

/// Full tier: rerun the decks with the installed LIGGGHTS and compare with the fixtures.
/// Returns early (with a note) when `liggghts` is not on PATH, except in the full tier.
#[test]
fn fresh_liggghts_run_matches_fixtures() {
    // Prints a note and skips when LIGGGHTS is absent; fails instead under FOAMGRAIN_FULL=1.
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for deck in ["settle", "triclinic"] {
        std::fs::copy(
            fixtures().join(format!("{deck}.in")),
            dir.path().join(format!("{deck}.in")),
        )
        .unwrap();
        let status = Command::new("liggghts")
            .args(["-in", &format!("{deck}.in")])
            .args(["-screen", &format!("{deck}.screen")])
            .args(["-log", &format!("{deck}.log")])
            .current_dir(dir.path())
            .status()
            .unwrap();
        assert!(status.success(), "liggghts failed on {deck}.in: {status}");
    }
    assert_text_equals_binary(dir.path(), "settle", &SETTLE_COLUMNS, &[3000, 6000]);
    assert_text_equals_binary(dir.path(), "triclinic", &TRICLINIC_COLUMNS, &[0, 5]);
    // A serial LIGGGHTS 3.8.0 run is deterministic: the fresh dumps equal the committed ones.
    for (file, opts) in [
        ("settle.txt", ReadOptions::default()),
        ("settle_g.txt", ReadOptions::default()),
        ("settle.bin", bin_options(&SETTLE_COLUMNS)),
        ("triclinic.bin", bin_options(&TRICLINIC_COLUMNS)),
    ] {
        let fresh = read_all(&dir.path().join(file), &opts);
        let committed = read_all(&fixtures().join(file), &opts);
        assert_eq!(fresh.len(), committed.len());
        for (a, b) in fresh.iter().zip(&committed) {
            assert_same_values(a, b);
            assert_eq!(a.label, b.label);
        }
    }
}
