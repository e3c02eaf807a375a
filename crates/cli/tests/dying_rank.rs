//! Full tier: a rank killed (SIGKILL) in the middle of a run, as a node lost or the OOM killer
//! would, and the run started again.
//!
//! The case is the restart fixture (`testkit::restart`: the settling box with 18 spheres —
//! landing on each other on the native stack, suspended in a 0.1 Pa·s liquid in the
//! co-simulation —
//! CFDEM's `writeLiggghts` at every write time, a deck that reads what it wrote), run to
//! [`END`] writing every [`WRITE`]. Each death kills one process once the first write is
//! complete (coupler rank 0: while the second write is under way), then checks:
//!
//! * every process of the run ends within [`BOUND`] of the kill (measured and printed), and
//!   the survivors' output names the cause;
//! * no process is left: none whose command line names the case;
//! * no time directory is half-written: each one the run left is complete (every field of
//!   the reference run's directory, each readable), but for the one the write journal names as
//!   under way (`CFD/foamgrain.write`), which the next run moves aside;
//! * `foamgrain run` started again as CFDEM's ErgunTestMPI_restart's second half (the deck that
//!   reads `writeLiggghts`' file, `startFrom latestTime`) continues from the last complete write
//!   to the uninterrupted run's result: bit for bit on the native stack, to the solvers'
//!   tolerance as a co-simulation (grainPisoFoam restarts from fields written with 10 digits).
//!
//! Co-simulations run as users launch them, `mpirun -np 4 --oversubscribe foamgrain run CASE
//! --fluid openfoam --dem liggghts --np 2`: LIGGGHTS in-process on the 4 coupler ranks,
//! grainPisoFoam on 2 ranks of its own. Needs the cargo features `mpi` and `liggghts`, Open
//! MPI, LIGGGHTS and grainPisoFoam (`openfoam-cases/solver/build.sh`); the native test needs
//! nothing.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use testkit::restart::{restart_case_with, set_control, use_restart_deck, Bed};

/// The run's end (s) and write interval (s): 30 coupling steps of 1 ms, a write every 10.
const END: &str = "0.03";
const WRITE: &str = "0.01";

/// How long after the kill every process of the run must have ended.
const BOUND: Duration = Duration::from_secs(30);

/// A copy of the restart fixture with `bed` in `dir/name`, to [`END`].
fn fixture(dir: &Path, name: &str, bed: Bed) -> PathBuf {
    let case = dir.join(name);
    testkit::copy_inputs(&testkit::repo_root().join("openfoam-cases/settling"), &case);
    restart_case_with(&case, bed);
    if bed == Bed::Suspended {
        // a viscous liquid: the spheres sink 0.4 mm in the run, a creeping flow in which a
        // perturbation decays (in the settling case's gas a restart's 10-digit fields grow
        // from 1e-7 to 1e-1 of the flow in 10 steps)
        testkit::restart::viscous_liquid(&case);
    }
    set_control(&case, "startTime", END, WRITE);
    case
}

/// How a run is launched: the native stack in one process, or the co-simulation on 4 ranks.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Stack {
    Native,
    #[cfg_attr(not(all(feature = "mpi", feature = "liggghts")), allow(dead_code))]
    CoSim,
}

/// The file a run's output goes to: `CASE.log`, `CASE.restart.log` for the run started again.
fn log_of(case: &Path) -> PathBuf {
    let again = case.join("CFD/system/controlDict");
    let restarted = std::fs::read_to_string(again).is_ok_and(|t| t.contains("latestTime"));
    case.with_extension(if restarted { "restart.log" } else { "log" })
}

/// Starts `foamgrain run CASE` on `stack`, its output in [`log_of`].
fn start(case: &Path, stack: Stack) -> Child {
    let exe = env!("CARGO_BIN_EXE_foamgrain");
    let mut c = match stack {
        Stack::Native => {
            let mut c = Command::new(exe);
            c.arg("run").arg(case).args(["--np", "1"]);
            c
        }
        Stack::CoSim => {
            let mut c = Command::new("mpirun");
            c.args(["--oversubscribe", "-np", "4", exe, "run"])
                .arg(case)
                .args(["--fluid", "openfoam", "--dem", "liggghts", "--np", "2"]);
            c
        }
    };
    let log = std::fs::File::create(log_of(case)).unwrap();
    c.env(
        "WM_PROJECT_DIR",
        std::env::var("WM_PROJECT_DIR").unwrap_or_else(|_| "/usr/share/openfoam".into()),
    )
    .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
    .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
    .stdout(Stdio::from(log.try_clone().unwrap()))
    .stderr(Stdio::from(log))
    .spawn()
    .unwrap()
}

/// Runs `foamgrain run CASE` to its end; panics with its log unless it succeeds.
fn run(case: &Path, stack: Stack) -> String {
    let status = start(case, stack).wait().unwrap();
    let log = std::fs::read_to_string(log_of(case)).unwrap();
    assert!(
        status.success(),
        "{} failed ({status}):\n{log}",
        case.display()
    );
    log
}

/// The processes whose command line names `case` (the run's ranks, grainPisoFoam's ranks and
/// the shells that started them): pid, name, command line and `OMPI_COMM_WORLD_RANK`.
fn processes_of(case: &Path) -> Vec<(u32, String, String, Option<usize>)> {
    let key = case.to_string_lossy().into_owned();
    let mut found = Vec::new();
    let me = std::process::id();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Some(pid) = e.file_name().to_str().and_then(|n| n.parse::<u32>().ok()) else {
            continue;
        };
        if pid == me {
            continue;
        }
        let Ok(cmd) = std::fs::read(e.path().join("cmdline")) else {
            continue;
        };
        let cmd = String::from_utf8_lossy(&cmd).replace('\0', " ");
        if !cmd.contains(&key) {
            continue;
        }
        let name = std::fs::read_to_string(e.path().join("comm"))
            .unwrap_or_default()
            .trim()
            .to_owned();
        let rank = std::fs::read(e.path().join("environ"))
            .ok()
            .and_then(|env| {
                env.split(|&b| b == 0)
                    .filter_map(|v| std::str::from_utf8(v).ok())
                    .find_map(|v| v.strip_prefix("OMPI_COMM_WORLD_RANK="))
                    .and_then(|r| r.parse().ok())
            });
        found.push((pid, name, cmd, rank));
    }
    found
}

/// The write journal's time and whether that write is complete.
fn journal(case: &Path) -> Option<(String, bool)> {
    let text = std::fs::read_to_string(case.join("CFD/foamgrain.write")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some((v["time"].as_str()?.to_owned(), v["complete"].as_bool()?))
}

/// Which process a test kills.
#[derive(Clone, Copy, Debug)]
enum Victim {
    /// The native stack's only process.
    Native,
    /// A foamgrain rank (LIGGGHTS runs in-process on every rank; rank 0 also couples).
    #[cfg_attr(not(all(feature = "mpi", feature = "liggghts")), allow(dead_code))]
    Coupler(usize),
    /// A grainPisoFoam rank.
    #[cfg_attr(not(all(feature = "mpi", feature = "liggghts")), allow(dead_code))]
    Solver(usize),
}

/// Starts `case`, kills `victim` once the first write is complete and the run has gone on
/// (`during_write`: while the second write is under way), waits for every process to end; returns the run's output and the seconds from the kill to
/// the last process's end.
fn kill_mid_run(case: &Path, stack: Stack, victim: Victim, during_write: bool) -> (String, f64) {
    let mut child = start(case, stack);
    let waited = Instant::now();
    let pid = loop {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before the kill:\n{}",
            std::fs::read_to_string(log_of(case)).unwrap()
        );
        assert!(
            waited.elapsed() < Duration::from_secs(600),
            "no write in 10 min"
        );
        let written = journal(case).is_some_and(|(t, done)| t == WRITE && done);
        let target = processes_of(case)
            .into_iter()
            .find(|(pid, name, _, rank)| match victim {
                Victim::Native => *pid == child.id(),
                Victim::Coupler(r) => name == "foamgrain" && *rank == Some(r),
                Victim::Solver(r) => name == "grainPisoFoam" && *rank == Some(r),
            });
        match target {
            Some((pid, ..)) if written => break pid,
            _ => std::thread::sleep(Duration::from_millis(20)),
        }
    };
    if during_write {
        // the second write under way (the journal says `writing`); a write missed between two
        // polls is killed after instead (the test then says so)
        let second = "0.02";
        loop {
            match journal(case) {
                Some((t, false)) if t == second => break,
                Some((t, true)) if t == second => {
                    eprintln!("{victim:?}: the write of {second} was missed; killed after it");
                    break;
                }
                _ if child.try_wait().unwrap().is_some() => panic!("the run ended first"),
                _ => std::thread::sleep(Duration::from_micros(200)),
            }
        }
    } else {
        // a little into the next interval, so that the kill falls inside a step
        std::thread::sleep(Duration::from_millis(30));
    }
    let killed = Instant::now();
    unsafe {
        libc::kill(pid as i32, libc::SIGKILL);
    }
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if killed.elapsed() > BOUND {
            let _ = child.kill();
            panic!("{victim:?}: the run did not end within {BOUND:?} of the kill");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut left = processes_of(case);
    while !left.is_empty() && killed.elapsed() <= BOUND {
        std::thread::sleep(Duration::from_millis(100));
        left = processes_of(case);
    }
    let seconds = killed.elapsed().as_secs_f64();
    let log = std::fs::read_to_string(log_of(case)).unwrap();
    for (pid, ..) in &left {
        unsafe {
            libc::kill(*pid as i32, libc::SIGKILL);
        }
    }
    assert!(
        left.is_empty(),
        "{victim:?}: processes left {seconds:.1} s after the kill: {left:?}\n{log}"
    );
    assert!(!status.success(), "{victim:?}: the killed run succeeded");
    eprintln!("{victim:?}: every process ended {seconds:.2} s after the kill ({status})");
    (log, seconds)
}

/// The time directories `cfd` holds (names parsing as times > 0).
fn times(cfd: &Path) -> Vec<String> {
    let mut t: Vec<String> = std::fs::read_dir(cfd)
        .map(|d| {
            d.flatten()
                .filter_map(|e| e.file_name().into_string().ok())
                .filter(|n| n.parse::<f64>().is_ok_and(|x| x > 0.0))
                .collect()
        })
        .unwrap_or_default();
    t.sort_by(|a, b| a.parse::<f64>().unwrap().total_cmp(&b.parse().unwrap()));
    t
}

/// Every time directory of `case` (and of its `processorN`) is complete — the fields of the
/// reference's first write, each readable — but the one the journal names as under way.
fn no_half_written(case: &Path, reference: &Path) {
    let fields: Vec<String> = std::fs::read_dir(reference.join("CFD").join(WRITE))
        .unwrap()
        .flatten()
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().into_string().unwrap())
        .collect();
    let under_way = journal(case).and_then(|(t, done)| (!done).then_some(t));
    let cfd = case.join("CFD");
    let mut roots = vec![(cfd.clone(), fields.clone())];
    for e in std::fs::read_dir(&cfd).unwrap().flatten() {
        let n = e.file_name().into_string().unwrap();
        if n.starts_with("processor") {
            // a processor's directory holds what grainPisoFoam writes (U, p, phi …)
            let first = e.path().join(WRITE);
            let own: Vec<String> = std::fs::read_dir(&first)
                .map(|d| {
                    d.flatten()
                        .filter(|e| e.path().is_file())
                        .map(|e| e.file_name().into_string().unwrap())
                        .collect()
                })
                .unwrap_or_default();
            roots.push((e.path(), own));
        }
    }
    for (root, expected) in roots {
        for t in times(&root) {
            if under_way.as_deref() == Some(t.as_str()) {
                continue;
            }
            for f in &expected {
                let p = root.join(&t).join(f);
                assert!(p.is_file(), "{} missing: a half-written time", p.display());
                if !f.contains('(') && !f.ends_with("_0") {
                    foam::parse_file(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                }
            }
        }
    }
}

/// Starts the killed case again as ErgunTestMPI_restart's second half.
fn restart(case: &Path, stack: Stack) -> String {
    use_restart_deck(case);
    set_control(case, "latestTime", END, WRITE);
    let log = run(case, stack);
    assert!(log.contains("restart: the fluid starts at t = "), "{log}");
    log
}

/// `integrals.csv` as numbers, one row per coupling step.
fn rows(case: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(case.join("postProcessing/integrals.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|c| c.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect()
}

/// The particles of the last LIGGGHTS restart file: (tag, x, v), by tag.
fn particles(case: &Path) -> Vec<(u64, [f64; 3], [f64; 3])> {
    let r =
        dem_io::restart::read_restart(case.join("DEM/post/restart/liggghts.restartCFDEM")).unwrap();
    let mut p: Vec<_> = r.atoms.iter().map(|a| (a.tag, a.x, a.v)).collect();
    p.sort_by_key(|a| a.0);
    p
}

/// The native stack: the one process killed after the first write, started again from it:
/// the same fields (text), particles and rows, bit for bit.
#[test]
fn native_run_killed_and_started_again_is_the_uninterrupted_run() {
    let dir = tempfile::tempdir().unwrap();
    let whole = fixture(dir.path(), "whole", Bed::Landing);
    run(&whole, Stack::Native);
    let killed = fixture(dir.path(), "killed", Bed::Landing);
    kill_mid_run(&killed, Stack::Native, Victim::Native, false);
    no_half_written(&killed, &whole);
    let log = restart(&killed, Stack::Native);
    eprintln!(
        "{}",
        log.lines()
            .filter(|l| l.starts_with("restart"))
            .collect::<Vec<_>>()
            .join("\n")
    );
    for f in ["U", "p", "phi", "voidfraction", "Ksl", "Us", "f"] {
        let read = |c: &Path| std::fs::read_to_string(c.join("CFD").join(END).join(f)).unwrap();
        assert!(read(&whole) == read(&killed), "CFD/{END}/{f} differs");
    }
    let (p, q) = (particles(&whole), particles(&killed));
    assert_eq!(p, q, "the particles differ");
    let (a, b) = (rows(&whole), rows(&killed));
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!((x[0] - y[0]).abs() < 1e-15, "time {} vs {}", x[0], y[0]);
        for (u, w) in x[1..].iter().zip(&y[1..]) {
            assert!(u == w || (u.is_nan() && w.is_nan()), "{x:?}\n{y:?}");
        }
    }
}

#[cfg(all(feature = "mpi", feature = "liggghts"))]
mod common;

#[cfg(all(feature = "mpi", feature = "liggghts"))]
mod cosim {
    use super::*;

    /// The settling mesh's cells (4 × 20 × 4).
    const N_CELLS: usize = 320;

    /// The largest difference of `restarted` from `whole` relative to each quantity's scale, and
    /// where: the integrals' columns, the particles' positions (scale 1 cm, the box) and velocities,
    /// and the end time's U and p.
    fn largest_difference(whole: &Path, restarted: &Path) -> (f64, String) {
        let (a, b) = (rows(whole), rows(restarted));
        assert_eq!(a.len(), b.len(), "integrals.csv: rows of the restarted run");
        let mut worst = (0.0, String::new());
        let mut rel = |x: f64, y: f64, scale: f64, what: &dyn Fn() -> String| {
            let d = (x - y).abs() / scale.max(1e-300);
            if x.is_nan() && y.is_nan() {
                return;
            }
            if d.is_nan() || d > worst.0 {
                worst = (d, what());
            }
        };
        let header = std::fs::read_to_string(whole.join("postProcessing/integrals.csv")).unwrap();
        let names: Vec<&str> = header.lines().next().unwrap().split(',').collect();
        for c in 0..a[0].len() {
            let scale = a
                .iter()
                .map(|r| r[c].abs())
                .filter(|x| x.is_finite())
                .fold(0.0, f64::max);
            for (i, (x, y)) in a.iter().zip(&b).enumerate() {
                if scale > 0.0 {
                    rel(x[c], y[c], scale, &|| {
                        format!("integrals.csv row {i} {}: {} vs {}", names[c], x[c], y[c])
                    });
                }
            }
        }
        let (p, q) = (particles(whole), particles(restarted));
        assert_eq!(p.len(), q.len());
        let vmax = p.iter().flat_map(|a| a.2).map(f64::abs).fold(0.0, f64::max);
        for (x, y) in p.iter().zip(&q) {
            assert_eq!(x.0, y.0);
            for k in 0..3 {
                rel(x.1[k], y.1[k], 0.01, &|| format!("particle {} x[{k}]", x.0));
                rel(x.2[k], y.2[k], vmax, &|| format!("particle {} v[{k}]", x.0));
            }
        }
        for f in ["U", "p"] {
            let read = |c: &Path| -> Vec<f64> {
                let field = foam::VolField::read(&c.join("CFD").join(END).join(f)).unwrap();
                match field.internal(N_CELLS).unwrap() {
                    foam::FieldValues::Scalar(v) => v,
                    foam::FieldValues::Vector(v) => v.into_iter().flatten().collect(),
                }
            };
            let (x, y) = (read(whole), read(restarted));
            let scale = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
            for (i, (u, w)) in x.iter().zip(&y).enumerate() {
                rel(*u, *w, scale, &|| format!("CFD/{END}/{f} value {i}"));
            }
        }
        worst
    }

    /// Kills `victim` of a 4-rank co-simulation of `killed` (a copy of the fixture that `whole`
    /// ran uninterrupted), checks the end and the files, starts the run again and compares it
    /// with the uninterrupted one; `cause` is what the survivors' output must say.
    fn killed_and_started_again(
        whole: &Path,
        killed: &Path,
        victim: Victim,
        cause: &[&str],
        during_write: bool,
    ) {
        // the same packed bed (stage 1 ran in the first run only)
        let packed = "DEM/post/restart/liggghts.restart";
        std::fs::create_dir_all(killed.join(packed).parent().unwrap()).unwrap();
        std::fs::copy(whole.join(packed), killed.join(packed)).unwrap();
        let (log, seconds) = kill_mid_run(killed, Stack::CoSim, victim, during_write);
        let half = journal(killed).and_then(|(t, done)| (!done).then_some(t));
        assert!(seconds <= BOUND.as_secs_f64());
        // each entry must be said; `a|b`: a or b
        let said: Vec<&str> = log
            .lines()
            .filter(|l| {
                cause
                    .iter()
                    .flat_map(|c| c.split('|'))
                    .any(|c| l.contains(c))
            })
            .collect();
        eprintln!("{victim:?}: the survivors say:\n  {}", said.join("\n  "));
        for c in cause {
            assert!(
                c.split('|').any(|c| log.contains(c)),
                "{victim:?}: the output does not say `{c}`:\n{log}"
            );
        }
        no_half_written(killed, whole);
        let again = restart(killed, Stack::CoSim);
        if let Some(t) = half {
            // the write under way was moved aside and the run continued from the one before
            assert!(
                again.contains(&format!("/{t} was being written when the run ended")),
                "{again}"
            );
            let aside = |d: &str| killed.join(format!("CFD/{d}{t}.incomplete")).is_dir();
            assert!(aside("") || aside("processor0/"));
            eprintln!(
                "{victim:?}: killed while {t} was being written; restarted from the write before"
            );
        }
        let (d, at) = largest_difference(whole, killed);
        eprintln!(
            "{victim:?}: restarted against uninterrupted: largest difference {d:.2e} of the \
             scale ({at})"
        );
        // grainPisoFoam restarts from fields written with 10 significant digits
        // (writePrecision 10): measured 1.5e-10 of U's scale after 20 steps
        assert!(
            d < 1e-8,
            "{victim:?}: restarted run differs by {d:e} ({at})"
        );
    }

    /// With grainPisoFoam on several coupler ranks, coupler rank 0 holds a part of the mesh as
    /// the other ranks do (`runner::mesh_part::foam_on_part`): fewer cells than the mesh's 320
    /// and at least one cut, in `postProcessing/ranks.csv`.
    fn rank_zero_holds_a_part(case: &Path) {
        let (held, cuts, text) = super::common::rank_0_part(case);
        assert!(held < 320, "rank 0 holds {held} of the 320 cells:\n{text}");
        assert!(cuts >= 1, "{text}");
        eprintln!("rank 0 holds {held} of the 320 cells ({cuts} cuts)");
    }

    /// The three deaths, each against one uninterrupted run: a LIGGGHTS rank (coupler rank 2;
    /// LIGGGHTS runs in-process on every rank), one of grainPisoFoam's 2 ranks, and coupler
    /// rank 0 (LIGGGHTS, the coupling and the run's outputs).
    #[test]
    fn a_killed_rank_ends_the_run_and_the_run_restarts() {
        if !super::common::cosim_ready(&["mpirun", "liggghts"]) {
            return;
        }
        let tmp = tempfile::tempdir().unwrap();
        let whole = fixture(tmp.path(), "whole", Bed::Suspended);
        run(&whole, Stack::CoSim);
        rank_zero_holds_a_part(&whole);
        let deaths: [(Victim, &[&str]); 3] = [
            (Victim::Coupler(2), &["process rank 2", "signal 9"]),
            // foam-link's pid check or mpirun, whichever notices first
            (
                Victim::Solver(1),
                &["grainPisoFoam rank 1 (pid|process rank 1 with PID"],
            ),
            (Victim::Coupler(0), &["process rank 0", "signal 9"]),
        ];
        for (n, (victim, cause)) in deaths.into_iter().enumerate() {
            let killed = fixture(tmp.path(), &format!("killed{n}"), Bed::Suspended);
            // rank 0 is killed while the second write is under way
            let during_write = n == 2;
            killed_and_started_again(&whole, &killed, victim, cause, during_write);
        }
    }
}
