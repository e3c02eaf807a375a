//! In-process LIGGGHTS on two MPI ranks (feature `link`, full tier): runs
//! `examples/two_ranks.rs` under `mpirun -np 2` (each rank fills a disjoint share of the
//! forces; the state is complete on both).
#![cfg(feature = "link")]

use std::process::Command;

#[test]
fn two_ranks_fill_disjoint_shares() {
    if !testkit::tool("liggghts") || !testkit::tool("mpirun") {
        return;
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
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("rank 0 of 2: share 0..1, ids [1, 2, 3]"),
        "{stdout}"
    );
    assert!(
        stdout.contains("rank 1 of 2: share 1..3, ids [1, 2, 3]"),
        "{stdout}"
    );
}
