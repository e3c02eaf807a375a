//! Test support shared by foamgrain's crates (a dev-dependency only).
//!
//! - [`fixture`]: the path of a committed fixture under `tests/fixtures/`; [`liggghts_input`]:
//!   a standalone deck of `liggghts-inputs/`.
//! - [`tool`]: the test tiers. The fast tier (`cargo test --workspace`) needs nothing but Rust;
//!   tests that compare with Debian's OpenFOAM or LIGGGHTS call `tool("blockMesh")` and return
//!   early with a printed note when the program is absent. With `FOAMGRAIN_FULL=1` (the full
//!   tier that CI runs after installing the packages) a missing program is a test failure, so
//!   the full tier can never pass by skipping.
//! - [`copy_inputs`]: a copy of a reference case's inputs only (what git tracks), never the
//!   outputs a user's earlier run left in the case (README's order: the main job, then the tests).
//! - [`SplitMix`], [`cpu_seconds`]: reproducible random inputs and the process's CPU time for
//!   the benchmarks that print their own figures.

use std::path::{Path, PathBuf};
use std::process::Command;

pub mod restart;

/// The repository root.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `tests/fixtures/<rel>` in the repository.
pub fn fixture(rel: &str) -> PathBuf {
    repo_root().join("tests/fixtures").join(rel)
}

/// `liggghts-inputs/<name>` in the repository: a standalone LIGGGHTS deck.
pub fn liggghts_input(name: &str) -> PathBuf {
    repo_root().join("liggghts-inputs").join(name)
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

/// Copies the inputs of a case or fixture directory: the files git tracks under `from`, as they
/// are in the work tree. Whatever a user's earlier runs wrote there (time directories,
/// `postProcessing/`, `DEM/post/packed.data`, logs, `processor*`) stays behind, so a test sees
/// the case as a fresh clone has it.
///
/// Outside a git checkout (a source archive, or git not installed), or for a directory git does
/// not track yet, every file is copied except the paths [`is_run_output`] names.
pub fn copy_inputs(from: &Path, to: &Path) {
    let tracked = Command::new("git")
        .arg("-C")
        .arg(from)
        .args(["ls-files", "-z", "--", "."])
        .output()
        .ok()
        .filter(|o| o.status.success() && !o.stdout.is_empty());
    let files: Vec<PathBuf> = match tracked {
        Some(out) => out
            .stdout
            .split(|&b| b == 0)
            .filter(|p| !p.is_empty())
            .map(|p| PathBuf::from(String::from_utf8_lossy(p).into_owned()))
            .collect(),
        None => {
            let mut all = Vec::new();
            list_files(from, Path::new(""), &mut all);
            all.retain(|rel| !is_run_output(rel));
            all
        }
    };
    for rel in files {
        let target = to.join(&rel);
        std::fs::create_dir_all(target.parent().unwrap()).unwrap();
        std::fs::copy(from.join(&rel), &target)
            .unwrap_or_else(|e| panic!("copying {}: {e}", from.join(&rel).display()));
    }
}

fn list_files(root: &Path, rel: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(root.join(rel)).unwrap() {
        let e = e.unwrap();
        let r = rel.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            list_files(root, &r, out);
        } else {
            out.push(r);
        }
    }
}

/// Whether `rel` (relative to a CFDEM-layout case or one of its `CFD/`, `DEM/` folders) is
/// something a run writes rather than an input: `postProcessing/…`, `DEM/post/…` (but its
/// `.keep`), a time directory other than `0`, `processorN/…`, `clockData/…` (CFDEM's
/// `standardClock` table), the write journal `foamgrain.write`, or a `log.*` file.
pub fn is_run_output(rel: &Path) -> bool {
    let parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    let Some(name) = parts.last() else {
        return false;
    };
    if name.starts_with("log.") || name == "foamgrain.write" {
        return true;
    }
    parts.iter().enumerate().any(|(k, p)| {
        let last = k + 1 == parts.len();
        p == "postProcessing"
            || p == "clockData"
            || p.starts_with("processor")
            || (!last && p != "0" && p.parse::<f64>().is_ok())
            || (p == "post" && k + 2 == parts.len() && name != ".keep")
            || (p == "post" && k + 2 < parts.len())
    })
}

/// A `blockMeshDict` of a 20 × 20 × 30 mm box (corner (−0.01, −0.01, 0) m) of 10 × 10 × 15
/// cells with one `wall` patch: it holds the LIGGGHTS fixture `liggghts/settle.txt`.
pub const BOX_BLOCK_MESH: &str = r#"FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }
vertices ((-0.01 -0.01 0) (0.01 -0.01 0) (0.01 0.01 0) (-0.01 0.01 0)
          (-0.01 -0.01 0.03) (0.01 -0.01 0.03) (0.01 0.01 0.03) (-0.01 0.01 0.03));
blocks (hex (0 1 2 3 4 5 6 7) (10 10 15) simpleGrading (1 1 1));
boundary ( walls { type wall; faces ((0 4 7 3) (2 6 5 1) (1 5 4 0) (3 7 6 2) (0 3 2 1) (4 5 6 7)); } );
"#;

/// SplitMix64 (Steele, Lea & Flood 2014): reproducible uniform numbers for benchmark inputs.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// The next number, uniform in [0, 1) (the top 53 bits).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// An index in 0..n (n > 0; the modulo bias, < n / 2⁶⁴, is immaterial for tests).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// CPU time of all threads of this process so far, s (Linux `/proc/self/task/*/schedstat`;
/// 0 elsewhere): on a shared machine the wall time of a benchmark depends on the other load,
/// its CPU time much less.
pub fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0.0;
    };
    tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        * 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_outputs_are_told_from_inputs() {
        for out in [
            "postProcessing/integrals.csv",
            "DEM/post/packed.data",
            "DEM/post/restart/liggghts.restart",
            "CFD/clockData/timeEval.txt",
            "CFD/0.02/U",
            "CFD/1e-05/p",
            "CFD/processor1/constant/polyMesh/faces",
            "DEM/log.liggghts",
            "post/dump100.txt",
        ] {
            assert!(is_run_output(Path::new(out)), "{out}");
        }
        for input in [
            "CFD/0/U",
            "CFD/constant/polyMesh/points",
            "CFD/system/controlDict",
            "DEM/in.liggghts_run",
            "DEM/post/.keep",
            "validationDict",
            "reference/packed.data",
        ] {
            assert!(!is_run_output(Path::new(input)), "{input}");
        }
    }

    #[test]
    fn a_case_copy_leaves_a_users_outputs_behind() {
        // The Ergun case as a fresh clone has it, whatever ran in it before (tracked files
        // only): no time directory but 0, nothing in DEM/post but .keep.
        let dir = std::env::temp_dir().join(format!("testkit-copy-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        copy_inputs(&repo_root().join("openfoam-cases/ergun"), &dir);
        let mut names: Vec<String> = std::fs::read_dir(dir.join("CFD"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["0", "constant", "system"]);
        let post: Vec<_> = std::fs::read_dir(dir.join("DEM/post")).unwrap().collect();
        assert_eq!(post.len(), 1);
        assert!(dir.join("DEM/in.liggghts_init").is_file());
        assert!(dir.join("validationDict").is_file());
        assert!(!dir.join("postProcessing").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
