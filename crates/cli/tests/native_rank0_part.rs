//! Full tier: with the native fluid on several coupler ranks (`mpirun -np 2 foamgrain run CASE
//! --dem liggghts`), coupler rank 0 holds a part of the mesh as the other ranks do
//! (`couple::Coupler::set_root_volumes`, `runner::mesh_part::native_on_part`): fewer cells than
//! the whole mesh in `postProcessing/ranks.csv`, and the run is the one-rank run (whole mesh,
//! one LIGGGHTS rank) within round-off.
//!
//! The case is the restart fixture's suspended bed (`testkit::restart`, `Bed::Suspended`:
//! nine layers of two spheres falling through a viscous liquid in the settling case's 320
//! cells, without contacts, spread by LIGGGHTS over its ranks along the column), 30 coupling
//! steps of 1 ms. The reference is the one-rank run, whose coupler holds the whole mesh: the
//! two runs sum the cells' shares in another order and LIGGGHTS integrates the spheres on one
//! rank or two, so they agree to round-off, not bit for bit (measured: 2.4e-15 of a column's
//! scale at most; 1e-12 asked).
//!
//! Needs the cargo features `mpi` and `liggghts`, Open MPI and LIGGGHTS.

#![cfg(all(feature = "mpi", feature = "liggghts"))]

use std::path::{Path, PathBuf};
use std::process::Command;
use testkit::restart::{restart_case_with, set_control, Bed};

mod common;

/// The whole mesh's cells.
const CELLS: usize = 320;

/// A copy of the suspended bed in `dir/name`, to 0.03 s.
fn fixture(dir: &Path, name: &str) -> PathBuf {
    let case = dir.join(name);
    testkit::copy_inputs(&testkit::repo_root().join("openfoam-cases/settling"), &case);
    restart_case_with(&case, Bed::Suspended);
    testkit::restart::viscous_liquid(&case);
    set_control(&case, "startTime", "0.03", "0.01");
    case
}

/// `foamgrain run CASE --dem liggghts` on `np` ranks; panics with its log unless it succeeds.
fn run(case: &Path, np: usize) -> String {
    let exe = env!("CARGO_BIN_EXE_foamgrain");
    let mut c = match np {
        1 => Command::new(exe),
        _ => {
            let mut c = Command::new("mpirun");
            c.args(["--oversubscribe", "-np", &np.to_string(), exe]);
            c
        }
    };
    c.arg("run").arg(case).args(["--dem", "liggghts"]);
    let out = common::cosim_env(&mut c).output().unwrap();
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.status.success(),
        "{} on {np} ranks failed:\n{log}",
        case.display()
    );
    log
}

/// `integrals.csv`: the header and the rows.
fn integrals(case: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(case.join("postProcessing/integrals.csv")).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    (head, rows)
}

#[test]
fn rank_0_holds_a_part_with_the_native_fluid_and_the_run_is_the_one_rank_run() {
    // the native fluid: no grainPisoFoam needed
    if !["mpirun", "liggghts"].iter().all(|t| testkit::tool(t)) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let one = fixture(tmp.path(), "one");
    let two = fixture(tmp.path(), "two");
    run(&one, 1);
    let log = run(&two, 2);
    assert!(
        log.contains("2 ranks: LIGGGHTS on each"),
        "not a 2-rank run:\n{log}"
    );

    // rank 0's coupler holds a part: fewer cells than the mesh, cut at least once
    let (held, cuts, text) = common::rank_0_part(&two);
    assert!(
        held < CELLS,
        "rank 0 holds {held} of the {CELLS} cells:\n{text}"
    );
    assert!(cuts >= 1, "{text}");
    eprintln!("rank 0 holds {held} of the {CELLS} cells ({cuts} cuts)");

    // the one-rank run's integrals, column by column, within round-off of each column's scale
    let (head1, rows1) = integrals(&one);
    let (head2, rows2) = integrals(&two);
    assert_eq!(head1, head2);
    assert_eq!(rows1.len(), rows2.len());
    assert!(rows1.len() >= 30, "{} rows", rows1.len());
    let mut worst = (0.0, String::new());
    for (j, name) in head1.iter().enumerate() {
        let scale = rows1.iter().map(|r| r[j].abs()).fold(0.0, f64::max);
        for (a, b) in rows1.iter().zip(&rows2) {
            let (a, b) = (a[j], b[j]);
            if a.is_nan() && b.is_nan() {
                continue;
            }
            let d = if scale > 0.0 {
                (a - b).abs() / scale
            } else {
                (a - b).abs()
            };
            assert!(
                d <= 1e-12,
                "{name}: {a} on one rank, {b} on two ({d:e} of {scale})"
            );
            if d > worst.0 {
                worst = (d, name.clone());
            }
        }
    }
    eprintln!(
        "largest difference from the one-rank run: {:e} of {}'s scale",
        worst.0, worst.1
    );
}
