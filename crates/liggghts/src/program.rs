//! Stage 1 with real LIGGGHTS: running a deck with the `liggghts` binary (Debian's
//! `liggghts` package) in the DEM directory, as CFDEM's tutorials run `in.liggghts_init`, and
//! turning its failure into an error that carries the tail of its log.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::error::LiggghtsError;

/// The LIGGGHTS program (on `PATH`).
pub const LIGGGHTS_PROGRAM: &str = "liggghts";

/// Lines of a log shown in errors.
pub const TAIL_LINES: usize = 20;

/// A finished run of the binary.
#[derive(Debug, Clone)]
pub struct ProgramRun {
    /// Its log (`-log`).
    pub log: PathBuf,
    /// Its screen output (`-screen`).
    pub screen: PathBuf,
    /// Wall time.
    pub elapsed: Duration,
}

/// LIGGGHTS 3.8.0's switch that turns its random-seed check (a seed must be a prime ≥ 10000,
/// and an insertion's seeds must differ; `random.cpp`, `fix_insert.cpp`) from an error into a
/// warning in its log. CFDEM-PFM's tutorials (`bubblingFluidizedBed`: `particledistribution/
/// discrete 681573`, `insert/pack seed 4763687`) use seeds its own LIGGGHTS takes and Debian's
/// refuses; foamgrain's native DEM takes any seed.
pub const SEED_TOLERANT: &str = "-seedtolerant";

/// The command line `liggghts -in DECK -var … -log LOG -screen SCREEN -seedtolerant` (paths
/// as given; [`SEED_TOLERANT`]), as a program of its own: without the variables by which
/// `mpirun` tells its ranks which job they belong to ([`alone`]).
pub fn command(deck: &Path, vars: &[(String, String)], log: &Path, screen: &Path) -> Command {
    let mut c = Command::new(LIGGGHTS_PROGRAM);
    alone(&mut c);
    c.arg(SEED_TOLERANT);
    c.arg("-in").arg(deck);
    for (k, v) in vars {
        c.arg("-var").arg(k).arg(v);
    }
    c.arg("-log").arg(log).arg("-screen").arg(screen);
    c
}

/// The ranks a deck's `processors Px Py Pz` grid fixes (their product; 1 without the command
/// or with a `*`, where LIGGGHTS fits the grid to the ranks it has): LIGGGHTS stops with
/// "Specified processors != physical processors" on any other count, as CFDEM's
/// `packedBedTemp` init deck (`processors 1 1 2`) would as a singleton.
fn grid_ranks(deck: &Path, vars: &[(String, String)]) -> Result<usize, LiggghtsError> {
    let d = liggghts_deck::Deck::read_with_vars(deck, vars)?;
    Ok(match d.processors()? {
        Some(p) if p.grid.iter().all(Option::is_some) => p.grid.iter().flatten().product(),
        _ => 1,
    })
}

/// `c` (a [`command`]) launched on `n` ranks by `mpirun -np n --oversubscribe`, itself started
/// without the job variables of the process that launches it ([`alone`]).
fn on_ranks(n: usize, c: Command) -> Command {
    let mut m = Command::new("mpirun");
    alone(&mut m);
    m.args(["--oversubscribe", "-np", &n.to_string()]);
    // Open MPI refuses root without its two permission variables; a user running foamgrain as
    // root has not necessarily set them
    let root = {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0)
    };
    if root {
        m.arg("--allow-run-as-root");
    }
    m.arg(c.get_program()).args(c.get_args());
    m
}

/// Removes from `c`'s environment what `mpirun` sets for its ranks (Open MPI's `OMPI_*` but
/// the run-as-root permissions, PMIx's `PMIX_*`, PMI's `PMI_*`): a `liggghts` started by a
/// foamgrain rank would otherwise take itself for a rank of foamgrain's job and fail in
/// `MPI_Init` ("ompi_rte_init failed"). Started so, it is an MPI singleton of its own.
pub fn alone(c: &mut Command) {
    for (key, _) in std::env::vars_os() {
        let Some(k) = key.to_str() else { continue };
        let launcher = ["OMPI_", "PMIX_", "PMI_"].iter().any(|p| k.starts_with(p));
        if launcher && !k.starts_with("OMPI_ALLOW_RUN_AS_ROOT") {
            c.env_remove(&key);
        }
    }
}

/// Runs `deck` with the `liggghts` binary in `workdir` (relative paths in the deck resolve
/// there), with `-var NAME VALUE` for each of `vars`, writing `log.NAME` and `screen.NAME` in
/// `workdir` (`name` is e.g. `init`). A missing deck or directory, a program that cannot start,
/// a non-zero exit or a signal is an error with the tail of the log.
pub fn run_deck(
    deck: &Path,
    workdir: &Path,
    vars: &[(String, String)],
    name: &str,
) -> Result<ProgramRun, LiggghtsError> {
    if !workdir.is_dir() {
        return Err(LiggghtsError::Parameter(format!(
            "DEM directory {} does not exist",
            workdir.display()
        )));
    }
    let deck_abs = absolute(deck)?;
    if !deck_abs.is_file() {
        return Err(LiggghtsError::Parameter(format!(
            "LIGGGHTS deck {} does not exist",
            deck.display()
        )));
    }
    let refused = crate::deck::refuse_coarse_graining(&liggghts_deck::Deck::read_with_vars(
        &deck_abs, vars,
    )?)?;
    if let Some((line, message)) = refused {
        return Err(LiggghtsError::Deck {
            file: deck.to_path_buf(),
            line,
            message,
        });
    }
    let workdir = absolute(workdir)?;
    let log = workdir.join(format!("log.{name}"));
    let screen = workdir.join(format!("screen.{name}"));
    let ranks = grid_ranks(&deck_abs, vars)?;
    let mut c = match ranks {
        1 => command(&deck_abs, vars, &log, &screen),
        n => on_ranks(n, command(&deck_abs, vars, &log, &screen)),
    };
    c.current_dir(&workdir);
    let start = Instant::now();
    let status = c.status().map_err(|e| LiggghtsError::Program {
        program: describe(&c),
        what: format!("could not be started ({e}; is Debian's `liggghts` package installed?)"),
        log: log.clone(),
        tail: String::new(),
    })?;
    if !status.success() {
        return Err(program_failed(&c, status, &log, &screen));
    }
    Ok(ProgramRun {
        log,
        screen,
        elapsed: start.elapsed(),
    })
}

/// The error for a LIGGGHTS process that ended with `status`: the tail of the log, or of the
/// screen file when the log is empty (a crash before the log was opened or flushed).
pub(crate) fn program_failed(
    c: &Command,
    status: std::process::ExitStatus,
    log: &Path,
    screen: &Path,
) -> LiggghtsError {
    let what = match status.code() {
        Some(code) => format!("exited with status {code}"),
        None => "was killed by a signal (a crash: LIGGGHTS segfaults on some deck errors)".into(),
    };
    let (file, tail) = match log_tail(log, TAIL_LINES) {
        t if !t.trim().is_empty() => (log, t),
        _ => (screen, log_tail(screen, TAIL_LINES)),
    };
    LiggghtsError::Program {
        program: describe(c),
        what,
        log: file.to_path_buf(),
        tail,
    }
}

/// The last `n` lines of a text file (empty if it cannot be read).
pub fn log_tail(path: &Path, n: usize) -> String {
    let text = std::fs::read(path)
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

/// `path` made absolute against the current directory.
pub(crate) fn absolute(path: &Path) -> Result<PathBuf, LiggghtsError> {
    std::path::absolute(path).map_err(|e| LiggghtsError::io(path.to_path_buf(), e))
}

/// The program and its arguments, for messages.
pub(crate) fn describe(c: &Command) -> String {
    std::iter::once(c.get_program())
        .chain(c.get_args())
        .map(|s| s.to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tail_takes_the_last_lines() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("log");
        std::fs::write(&f, "a\nb\nc\nd\n").unwrap();
        assert_eq!(log_tail(&f, 2), "c\nd");
        assert_eq!(log_tail(&f, 10), "a\nb\nc\nd");
        assert_eq!(log_tail(&dir.path().join("none"), 3), "");
    }

    #[test]
    fn missing_inputs_are_errors_before_anything_runs() {
        let dir = tempfile::tempdir().unwrap();
        let e = run_deck(&dir.path().join("in.none"), dir.path(), &[], "x").unwrap_err();
        assert!(e.to_string().contains("does not exist"), "{e}");
        let e = run_deck(Path::new("in.x"), &dir.path().join("no"), &[], "x").unwrap_err();
        assert!(e.to_string().contains("DEM directory"), "{e}");
    }

    #[test]
    fn command_line_as_liggghts_takes_it() {
        let c = command(
            Path::new("in.init"),
            &[("np".into(), "200".into())],
            Path::new("log.init"),
            Path::new("screen.init"),
        );
        assert_eq!(
            describe(&c),
            "liggghts -seedtolerant -in in.init -var np 200 -log log.init -screen screen.init"
        );
    }
}
