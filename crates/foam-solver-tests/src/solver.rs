//! Building grainPisoFoam for the tests.

use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;

/// The `build.sh` of the solver in this repository.
pub fn build_script() -> PathBuf {
    testkit::repo_root().join("openfoam-cases/solver/build.sh")
}

/// The path of a freshly built (or up-to-date) grainPisoFoam, or `None` when OpenFOAM is not
/// installed (fast tier; with `FOAMGRAIN_FULL=1` a missing OpenFOAM fails the test).
///
/// The build runs once per process; `build.sh` itself serialises concurrent builds with a
/// lock file. A failed build panics with the script's output.
pub fn grain_piso_foam() -> Option<PathBuf> {
    if !(testkit::tool("pisoFoam") && testkit::tool("blockMesh")) {
        return None;
    }
    static SOLVER: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    match SOLVER.get_or_init(build) {
        Ok(path) => Some(path.clone()),
        Err(msg) => panic!("{msg}"),
    }
}

fn build() -> Result<PathBuf, String> {
    let script = build_script();
    let out = Command::new("bash")
        .arg(&script)
        .output()
        .map_err(|e| format!("cannot run {}: {e}", script.display()))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!(
            "{} failed ({}):\n{stdout}\n{stderr}",
            script.display(),
            out.status
        ));
    }
    stdout
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix("grainPisoFoam="))
        .map(PathBuf::from)
        .ok_or_else(|| {
            format!(
                "{} printed no `grainPisoFoam=` line:\n{stdout}\n{stderr}",
                script.display()
            )
        })
}
