//! In-process LIGGGHTS on two MPI ranks (feature `link`, full tier): runs
//! `examples/two_ranks.rs` under `mpirun -np 2`: each rank holds and forces only the particles
//! its LIGGGHTS rank owns (the three spheres lie at x = −0.02, 0, 0.02 m in a box LIGGGHTS cuts
//! in two), every tag on exactly one rank.
#![cfg(feature = "link")]

use std::process::Command;

/// Runs `examples/two_ranks` under `mpirun -np 2` with `extra` arguments; its stdout, or
/// `None` when LIGGGHTS or mpirun is missing (fast tier).
fn two_ranks(extra: &[&str]) -> Option<String> {
    if !testkit::tool("liggghts") || !testkit::tool("mpirun") {
        return None;
    }
    // the example is built next to this test's binary (target/debug/examples)
    let exe = std::env::current_exe().unwrap();
    let example = exe
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("examples/two_ranks");
    assert!(example.is_file(), "{} not built", example.display());
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new("mpirun")
        .args(["-np", "2", "--oversubscribe"])
        .arg(&example)
        .arg(dir.path())
        .args(extra)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(stdout)
}

#[test]
fn each_rank_holds_and_forces_only_its_own_particles() {
    let Some(stdout) = two_ranks(&[]) else {
        return;
    };
    for rank in 0..2 {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("rank {rank} of 2: ids [")))
            .unwrap_or_else(|| panic!("no line of rank {rank}: {stdout}"));
        assert!(line.ends_with("owners per tag [1, 1, 1]"), "{line}");
        // neither rank holds all three particles, and neither is empty
        assert!(
            !line.contains("ids [1, 2, 3]") && !line.contains("ids []"),
            "{line}"
        );
    }
}

#[test]
fn each_rank_heats_only_its_own_particles() {
    let Some(stdout) = two_ranks(&["heat"]) else {
        return;
    };
    // both ranks report, each with its own (non-empty) share of the three particles; the
    // example exits 1 when a temperature misses T0 + q t/(m c)
    for rank in 0..2 {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("rank {rank}: heat ids [")))
            .unwrap_or_else(|| panic!("no line of rank {rank}: {stdout}"));
        assert!(!line.contains("ids []"), "{line}");
    }
}
