//! A write time as one unit, so that a run killed at any moment (SIGKILL of a rank, a node
//! lost) leaves the last complete write to continue from.
//!
//! Every file is written to a temporary name and renamed when complete (`atomic-write`), but a
//! write time is many files by several writers: the fluid's time directory (grainPisoFoam's
//! OpenFOAM writer fills `CFD/T` or `CFD/processorN/T` file by file), the exchange fields, the
//! particle pieces of every rank, `integrals.csv`, and the DEM's restart file of CFDEM's
//! `writeLiggghts`, which LIGGGHTS writes in place. The journal `CFD/foamgrain.write` (JSON,
//! written atomically by rank 0) makes them one unit:
//!
//! 1. `writing T`, with the renames planned: a `write_restart FILE` of the step's
//!    liggghtsCommands writes `FILE.writing` instead, so the previous `FILE` stays whole;
//! 2. every rank writes its part (the run waits for all ranks and for the solver's reply);
//! 3. `written T`, then the renames `FILE.writing` → `FILE`.
//!
//! [`recover`], before a run reads its case, finishes what a killed run left: in state
//! `writing T`, the time directories `T` (of the case and of each `processorN`) are moved aside
//! to `T.incomplete` (OpenFOAM ignores such names, so `startFrom latestTime` finds the last
//! complete write) and the temporary restart files are removed; in state `written T`, the
//! renames not yet done are done. [`check_start`] then refuses a restart whose DEM file was
//! written at another time than the fluid starts from.

use crate::error::{io_err, setup_err, RunError};
use crate::layout::lexically_normal;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The journal's file name in `CFD/`.
pub const JOURNAL: &str = "foamgrain.write";

/// The suffix of a DEM restart file being written.
const WRITING: &str = ".writing";

/// The suffix a half-written time directory is moved aside to.
const INCOMPLETE: &str = ".incomplete";

/// The journal's content.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct Entry {
    /// The write time's directory name (`couple::output::time_name`).
    time: String,
    /// `false` while the write is under way, `true` once every part is complete.
    complete: bool,
    /// Temporary file → final name, done after `complete`.
    renames: Vec<(PathBuf, PathBuf)>,
}

/// One write time under way (rank 0 holds it; the other ranks' is inert).
pub(crate) struct WriteJournal {
    path: PathBuf,
    entry: Entry,
}

impl WriteJournal {
    /// Starts the write of time `name` in `cfd`, with the planned `renames` (temporary →
    /// final). `record` false (ranks other than 0) touches nothing.
    pub(crate) fn begin(
        cfd: &Path,
        name: &str,
        renames: Vec<(PathBuf, PathBuf)>,
        record: bool,
    ) -> Result<WriteJournal, RunError> {
        let j = WriteJournal {
            path: cfd.join(JOURNAL),
            entry: Entry {
                time: name.to_owned(),
                complete: false,
                renames,
            },
        };
        if record {
            j.store()?;
        }
        Ok(j)
    }

    /// Marks the write complete (every rank has written its part) and renames the temporary
    /// files to their names. `record` as in [`WriteJournal::begin`].
    pub(crate) fn commit(mut self, record: bool) -> Result<(), RunError> {
        if !record {
            return Ok(());
        }
        self.entry.complete = true;
        self.store()?;
        rename_all(&self.entry.renames)
    }

    fn store(&self) -> Result<(), RunError> {
        let text = serde_json::to_string_pretty(&self.entry).expect("plain data");
        atomic_write::write_atomically(&self.path, |w| {
            use std::io::Write;
            writeln!(w, "{text}")
        })
        .map_err(io_err(&self.path))
    }
}

/// The temporary name a `write_restart FILE` of a write time writes to, and the rename that
/// completes it: `Some((command, (temporary, final)))` for `write_restart PATH` with one plain
/// path (no `*` or `%`, which LIGGGHTS expands itself, and no further keywords); `dem` is the
/// directory the path is relative to.
pub(crate) fn staged_restart(cmd: &str, dem: &Path) -> Option<(String, (PathBuf, PathBuf))> {
    let words: Vec<&str> = cmd.split_whitespace().collect();
    let [verb, path] = words[..] else {
        return None;
    };
    if verb != "write_restart" || path.contains(['*', '%']) {
        return None;
    }
    let tmp = format!("{path}{WRITING}");
    Some((
        format!("write_restart {tmp}"),
        (dem.join(&tmp), dem.join(path)),
    ))
}

fn rename_all(renames: &[(PathBuf, PathBuf)]) -> Result<(), RunError> {
    for (from, to) in renames {
        if from.exists() {
            std::fs::rename(from, to).map_err(io_err(from))?;
        }
    }
    Ok(())
}

fn read(cfd: &Path) -> Result<Option<Entry>, RunError> {
    let path = cfd.join(JOURNAL);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(io_err(&path)(e)),
    };
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| setup_err(&path, format!("not a foamgrain write journal: {e}")))
}

/// Finishes what a run killed during a write time left in the case whose fluid folder is
/// `cfd` (see the module doc); returns what it did, one line each. Run by rank 0 before the
/// case is read.
pub fn recover(cfd: &Path) -> Result<Vec<String>, RunError> {
    let done = finish_journal(cfd)?;
    // a decomposed grainPisoFoam that was killed did not reconstruct its complete writes (a
    // folder without `constant/` is no OpenFOAM case: the run's reading of it names that)
    #[cfg(feature = "mpi")]
    if cfd.join("processor0").is_dir() && cfd.join("constant").is_dir() {
        foam_link::case_setup::reconstruct(cfd)
            .map_err(|e| RunError::Backend(format!("restart: reconstructPar: {e}")))?;
    }
    Ok(done)
}

fn finish_journal(cfd: &Path) -> Result<Vec<String>, RunError> {
    let Some(entry) = read(cfd)? else {
        return Ok(Vec::new());
    };
    let mut done = Vec::new();
    if entry.complete {
        let pending: Vec<_> = entry
            .renames
            .iter()
            .filter(|(from, _)| from.exists())
            .cloned()
            .collect();
        rename_all(&pending)?;
        for (_, to) in &pending {
            done.push(format!(
                "restart: completed the write of {} at t = {} (the run ended before renaming it)",
                to.display(),
                entry.time
            ));
        }
        return Ok(done);
    }
    for half in time_roots(cfd)?
        .iter()
        .filter_map(|dir| same_time(dir, &entry.time))
    {
        let aside = half.with_file_name(format!(
            "{}{INCOMPLETE}",
            half.file_name().unwrap_or_default().to_string_lossy()
        ));
        if aside.exists() {
            std::fs::remove_dir_all(&aside).map_err(io_err(&aside))?;
        }
        std::fs::rename(&half, &aside).map_err(io_err(&half))?;
        done.push(format!(
            "restart: {} was being written when the run ended ({}): moved aside to {}",
            half.display(),
            cfd.join(JOURNAL).display(),
            aside.display()
        ));
    }
    for (from, _) in &entry.renames {
        if from.exists() {
            std::fs::remove_file(from).map_err(io_err(from))?;
            done.push(format!(
                "restart: removed {}, half written when the run ended",
                from.display()
            ));
        }
    }
    // the last complete write is now the latest time; the journal no longer names one
    std::fs::remove_file(cfd.join(JOURNAL)).map_err(io_err(&cfd.join(JOURNAL)))?;
    Ok(done)
}

/// The time directory in `dir` named `time`, or whose name is the same time to a relative
/// 10⁻⁹ (grainPisoFoam names its directory by its own sum of the time steps).
fn same_time(dir: &Path, time: &str) -> Option<PathBuf> {
    let exact = dir.join(time);
    if exact.is_dir() {
        return Some(exact);
    }
    let t: f64 = time.parse().ok()?;
    std::fs::read_dir(dir)
        .ok()?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| {
            p.is_dir()
                && p.file_name()
                    .and_then(|n| n.to_str())
                    .and_then(|n| n.parse::<f64>().ok())
                    .is_some_and(|x| (x - t).abs() <= 1e-9 * t.abs())
        })
}

/// The folders holding time directories: `cfd` and each `processorN`.
fn time_roots(cfd: &Path) -> Result<Vec<PathBuf>, RunError> {
    let mut roots = vec![cfd.to_owned()];
    for e in std::fs::read_dir(cfd).map_err(io_err(cfd))? {
        let p = e.map_err(io_err(cfd))?.path();
        let is_proc = p
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_prefix("processor"))
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
        if is_proc && p.is_dir() {
            roots.push(p);
        }
    }
    roots.sort();
    Ok(roots)
}

/// Refuses a restart whose DEM starts from `dem_file` (the coupled deck's `read_restart`)
/// when the last complete write put that file at another time than `start` (s), the time the
/// fluid starts from: the two sides would continue from different moments.
pub fn check_start(cfd: &Path, start: f64, dem_file: &Path) -> Result<(), RunError> {
    let Some(entry) = read(cfd)? else {
        return Ok(());
    };
    let file = lexically_normal(dem_file);
    let names_it = entry
        .renames
        .iter()
        .any(|(_, to)| lexically_normal(to) == file);
    let Ok(written) = entry.time.parse::<f64>() else {
        return Ok(());
    };
    if entry.complete && names_it && (written - start).abs() > 1e-9 * start.abs().max(1e-300) {
        return Err(setup_err(
            dem_file,
            format!(
                "holds the particles written at t = {} s ({}), but the fluid starts at t = {start} \
                 s: restart the fluid from the same time (startFrom latestTime and that time \
                 directory)",
                entry.time,
                cfd.join(JOURNAL).display()
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case() -> (tempfile::TempDir, PathBuf) {
        let tmp = tempfile::tempdir().unwrap();
        let cfd = tmp.path().join("CFD");
        for d in ["0.005", "0.01", "processor0/0.005", "processor0/0.01"] {
            std::fs::create_dir_all(cfd.join(d)).unwrap();
            std::fs::write(cfd.join(d).join("U"), "x").unwrap();
        }
        std::fs::create_dir_all(tmp.path().join("DEM/post")).unwrap();
        (tmp, cfd)
    }

    #[test]
    fn a_write_under_way_is_moved_aside_and_its_restart_file_removed() {
        let (tmp, cfd) = case();
        let dem = tmp.path().join("DEM");
        let (cmd, rename) = staged_restart("write_restart post/r", &dem).unwrap();
        assert_eq!(cmd, "write_restart post/r.writing");
        std::fs::write(&rename.0, "half").unwrap();
        std::fs::write(&rename.1, "whole, at 0.005").unwrap();
        let j = WriteJournal::begin(&cfd, "0.01", vec![rename.clone()], true).unwrap();
        drop(j); // killed here
        let done = recover(&cfd).unwrap();
        assert_eq!(done.len(), 3, "{done:?}");
        assert!(!cfd.join("0.01").exists() && cfd.join("0.01.incomplete/U").is_file());
        assert!(cfd.join("processor0/0.01.incomplete/U").is_file());
        assert!(cfd.join("0.005/U").is_file());
        assert!(!rename.0.exists());
        assert_eq!(
            std::fs::read_to_string(&rename.1).unwrap(),
            "whole, at 0.005"
        );
        assert!(!cfd.join(JOURNAL).exists());
        // nothing left to do the second time
        assert!(recover(&cfd).unwrap().is_empty());
    }

    #[test]
    fn a_complete_write_finishes_its_renames_and_names_its_time() {
        let (tmp, cfd) = case();
        let dem = tmp.path().join("DEM");
        let (_, rename) = staged_restart("write_restart post/r", &dem).unwrap();
        std::fs::write(&rename.0, "whole, at 0.01").unwrap();
        std::fs::write(&rename.1, "whole, at 0.005").unwrap();
        let mut j = WriteJournal::begin(&cfd, "0.01", vec![rename.clone()], true).unwrap();
        j.entry.complete = true;
        j.store().unwrap(); // killed before the renames
        let done = recover(&cfd).unwrap();
        assert_eq!(done.len(), 1, "{done:?}");
        assert_eq!(
            std::fs::read_to_string(&rename.1).unwrap(),
            "whole, at 0.01"
        );
        assert!(cfd.join("0.01/U").is_file());
        // the DEM file is at 0.01: a fluid from 0.01 fits, one from 0.005 does not
        let read_by_deck = dem.join("../DEM/post/r");
        check_start(&cfd, 0.01, &read_by_deck).unwrap();
        let e = check_start(&cfd, 0.005, &read_by_deck)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("written at t = 0.01 s") && e.contains("starts at t = 0.005"),
            "{e}"
        );
        // another file is not the journal's concern
        check_start(&cfd, 0.005, &dem.join("post/other")).unwrap();
    }

    #[test]
    fn only_a_plain_write_restart_is_staged() {
        let dem = Path::new("/c/DEM");
        assert!(staged_restart("write_restart post/r*", dem).is_none());
        assert!(staged_restart("write_restart post/r.% fileper 2", dem).is_none());
        assert!(staged_restart("write_data post/r", dem).is_none());
        let (_, (from, to)) = staged_restart("write_restart ../DEM/r", dem).unwrap();
        assert_eq!(from, Path::new("/c/DEM/../DEM/r.writing"));
        assert_eq!(to, Path::new("/c/DEM/../DEM/r"));
    }
}
