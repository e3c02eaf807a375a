//! Test support shared by foamgrain's crates (a dev-dependency only).
//!
//! - [`fixture`]: the path of a committed fixture under `tests/fixtures/`.
//! - [`tool`]: the test tiers. The fast tier (`cargo test --workspace`) needs nothing but Rust;
//!   tests that compare with Debian's OpenFOAM or LIGGGHTS call `tool("blockMesh")` and return
//!   early with a printed note when the program is absent. With `FOAMGRAIN_FULL=1` (the full
//!   tier that CI runs after installing the packages) a missing program is a test failure, so
//!   the full tier can never pass by skipping.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `tests/fixtures/<rel>` in the repository.
pub fn fixture(rel: &str) -> PathBuf {
    repo_root().join("tests/fixtures").join(rel)
}

/// True when the full tier is requested (`FOAMGRAIN_FULL=1`).
pub fn full_tier() -> bool {
    std::env::var("FOAMGRAIN_FULL").is_ok_and(|v| v == "1")
}

/// Whether the external program `name` can be run. In the full tier a missing program panics;
/// otherwise the caller should skip (a note is printed so the skip is visible with
/// `--nocapture`).
pub fn tool(name: &str) -> bool {
    let found = std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(name).is_file()));
    if !found {
        assert!(
            !full_tier(),
            "FOAMGRAIN_FULL=1 but `{name}` is not installed (see .ci/run for the packages)"
        );
        eprintln!("note: `{name}` not found: skipping the comparison with it (fast tier)");
    }
    found
}

/// A command for an OpenFOAM utility with `WM_PROJECT_DIR` set as Debian's OpenFOAM needs.
pub fn openfoam(name: &str) -> Command {
    let mut c = Command::new(name);
    c.env(
        "WM_PROJECT_DIR",
        std::env::var("WM_PROJECT_DIR").unwrap_or_else(|_| "/usr/share/openfoam".into()),
    );
    c
}

/// Runs a command in `dir`, panicking with its output if it fails; returns stdout.
pub fn run_ok(mut c: Command, dir: &Path) -> String {
    let out = c
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {c:?}: {e}"));
    assert!(
        out.status.success(),
        "{c:?} failed in {}:\n{}\n{}",
        dir.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Copies a directory tree (fixtures are copied before tools write into them).
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}
