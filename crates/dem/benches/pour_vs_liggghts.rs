//! Wall time of the whole pour deck (`liggghts-inputs/pour.in`: insertion of a loose pack,
//! then the fall and settling) on the native DEM with 1 and 2 threads, and on Debian's LIGGGHTS
//! with 1 and 2 MPI ranks when `liggghts` (and `mpirun`) are on PATH, printed side by side with
//! the ratios native / LIGGGHTS for the same number of workers, and the bed measures of the
//! two last dumps (`tests/common/bed.rs`).
//!
//! ```text
//! cargo bench -p dem --bench pour_vs_liggghts [-- [--only native|liggghts] [--workers N] [-var NAME VALUE …]]
//! ```
//! `--only` runs one side, `--workers N` only N threads / ranks (both: for profiling and for
//! interleaving two builds' native runs by hand).
//! Without `-var`s it runs issue 17's size, `np 30000 w 0.02 nsteps 10000 zmax 0.05` (about a
//! minute per run; the target there: native ≤ 1.0× LIGGGHTS on 1 worker, ≤ 0.7× on 2).
//! `mpirun` as root needs `OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1` in the
//! environment. The native runs are in-process (the code `foamgrain dem … --threads N` runs).
//! The load average is printed before and after: on a shared machine the figures mean little
//! unless it stays below the number of cores.

#[path = "../tests/common/bed.rs"]
mod bed;

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use dem_io::{read_snapshot, ReadOptions, Selection, Snapshot};

/// Issue 17's pour.
const DEFAULT_VARS: [(&str, &str); 4] = [
    ("np", "30000"),
    ("w", "0.02"),
    ("nsteps", "10000"),
    ("zmax", "0.05"),
];

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

type Error = Box<dyn std::error::Error>;

/// One timed run: wall time (s) and its last dump.
struct Timed {
    secs: f64,
    last: Snapshot,
}

fn run() -> Result<(), Error> {
    let Args {
        vars,
        only,
        workers,
    } = parse_args()?;
    let wanted = |side: &str, n: usize| {
        only.as_deref().is_none_or(|o| o == side) && workers.is_none_or(|w| w == n)
    };
    let deck_path = testkit::liggghts_input("pour.in");
    let text: Vec<String> = vars.iter().map(|(k, v)| format!("{k} {v}")).collect();
    println!(
        "pour.in, -var {}; load average {}",
        text.join(", "),
        load_average()
    );
    let mut rows: Vec<(String, Option<Timed>, usize)> = Vec::new();
    let liggghts = testkit::tool("liggghts");
    for ranks in [1, 2].into_iter().filter(|&n| wanted("liggghts", n)) {
        let label = format!("LIGGGHTS, {ranks} rank{}", if ranks > 1 { "s" } else { "" });
        let timed = if !liggghts || (ranks > 1 && !testkit::tool("mpirun")) {
            println!("{label}: not installed, skipped");
            None
        } else {
            Some(liggghts_run(&deck_path, &vars, ranks)?)
        };
        rows.push((label, timed, ranks));
    }
    for threads in [1, 2].into_iter().filter(|&n| wanted("native", n)) {
        let label = format!(
            "native, {threads} thread{}",
            if threads > 1 { "s" } else { "" }
        );
        rows.push((
            label,
            Some(native_run(&deck_path, &vars, threads)?),
            threads,
        ));
    }
    println!("load average {}", load_average());
    println!();
    println!(
        "{:<22} {:>10} {:>22}",
        "run", "wall (s)", "vs LIGGGHTS, same n"
    );
    for (label, timed, workers) in &rows {
        let Some(t) = timed else { continue };
        let reference = rows
            .iter()
            .find(|(l, r, n)| l.starts_with("LIGGGHTS") && n == workers && r.is_some())
            .and_then(|(_, r, _)| r.as_ref());
        let ratio = match reference {
            Some(r) if !label.starts_with("LIGGGHTS") => format!("{:.2}×", t.secs / r.secs),
            _ => String::new(),
        };
        println!("{label:<22} {:>10.2} {ratio:>22}", t.secs);
    }
    let half_width: f64 = vars
        .iter()
        .find(|(k, _)| k == "w")
        .map_or(Ok(0.01), |(_, v)| v.parse())?;
    let lig = rows.iter().find_map(|(l, t, n)| {
        (l.starts_with("LIGGGHTS") && *n == 1)
            .then_some(t.as_ref())
            .flatten()
    });
    if let Some(lig) = lig {
        println!();
        println!(
            "bed at step {} (tests/common/bed.rs), relative to LIGGGHTS 1 rank:",
            lig.last.timestep
        );
        let reference = measure(&lig.last, half_width)?;
        for (label, timed, _) in rows.iter().filter(|r| r.0.starts_with("native")) {
            let Some(t) = timed else { continue };
            let [top, core, slab, h] = bed::relative(&measure(&t.last, half_width)?, &reference);
            println!(
                "  {label}: top {:+.2} %, core solid fraction {:+.2} %, slab solid fraction \
                 {:+.2} %, packed height {:+.2} %",
                100.0 * top,
                100.0 * core,
                100.0 * slab,
                100.0 * h
            );
        }
    }
    Ok(())
}

/// The command line after `--`.
struct Args {
    /// `-var NAME VALUE` pairs; issue 17's values where none is given.
    vars: Vec<(String, String)>,
    /// `--only native|liggghts`: one side only.
    only: Option<String>,
    /// `--workers N`: only N threads / ranks.
    workers: Option<usize>,
}

const USAGE: &str =
    "usage: pour_vs_liggghts [--only native|liggghts] [--workers 1|2] [-var NAME VALUE]…";

/// The command line after `--` (cargo bench adds `--bench`, ignored).
fn parse_args() -> Result<Args, Error> {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let mut vars: Vec<(String, String)> = DEFAULT_VARS
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let (mut only, mut workers) = (None, None);
    let mut k = 0;
    while k < args.len() {
        match (args[k].as_str(), args.get(k + 1), args.get(k + 2)) {
            ("--only", Some(side), _) if side == "native" || side == "liggghts" => {
                only = Some(side.clone());
                k += 2;
            }
            ("--workers", Some(n), _) => {
                workers = Some(
                    n.parse()
                        .map_err(|_| format!("--workers {n}: not a number ({USAGE})"))?,
                );
                k += 2;
            }
            ("-var", Some(name), Some(value)) => {
                match vars.iter_mut().find(|(n, _)| n == name) {
                    Some(v) => v.1 = value.clone(),
                    None => vars.push((name.clone(), value.clone())),
                }
                k += 3;
            }
            (other, ..) => return Err(format!("unexpected argument `{other}` ({USAGE})").into()),
        }
    }
    Ok(Args {
        vars,
        only,
        workers,
    })
}

/// The native DEM on `threads` rayon threads, in a temporary directory.
fn native_run(deck_path: &Path, vars: &[(String, String)], threads: usize) -> Result<Timed, Error> {
    let deck = liggghts_deck::Deck::read_with_vars(deck_path, vars)?;
    let dir = tempfile::tempdir()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let t0 = Instant::now();
    pool.install(|| dem::Simulation::from_deck(&deck, dir.path()))?;
    let secs = t0.elapsed().as_secs_f64();
    let last = last_dump(&dir.path().join("post"))?;
    println!(
        "native, {threads} thread(s): {secs:.2} s; last dump's fingerprint {}",
        fingerprint(&last)
    );
    Ok(Timed { secs, last })
}

/// Debian's LIGGGHTS on `ranks` MPI processes, in a temporary directory holding the deck and
/// an empty `post/` (its screen output goes to a file: `-screen none` crashes 3.8.0).
fn liggghts_run(deck_path: &Path, vars: &[(String, String)], ranks: usize) -> Result<Timed, Error> {
    let dir = tempfile::tempdir()?;
    std::fs::copy(deck_path, dir.path().join("pour.in"))?;
    std::fs::create_dir(dir.path().join("post"))?;
    let mut cmd = if ranks == 1 {
        Command::new("liggghts")
    } else {
        let mut c = Command::new("mpirun");
        c.args(["--oversubscribe", "-np", &ranks.to_string(), "liggghts"]);
        c
    };
    cmd.args(["-in", "pour.in", "-screen", "screen.txt", "-log", "log.txt"]);
    for (k, v) in vars {
        cmd.args(["-var", k, v]);
    }
    let t0 = Instant::now();
    let out = cmd.current_dir(dir.path()).output()?;
    let secs = t0.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(format!(
            "{cmd:?} failed:\n{}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
        .into());
    }
    println!("LIGGGHTS, {ranks} rank(s): {secs:.2} s");
    Ok(Timed {
        secs,
        last: last_dump(&dir.path().join("post"))?,
    })
}

/// The dump of the largest step in `post` (the deck writes `pour_STEP.txt`).
fn last_dump(post: &Path) -> Result<Snapshot, Error> {
    let mut best: Option<Snapshot> = None;
    for entry in std::fs::read_dir(post)? {
        let s = read_snapshot(entry?.path(), &ReadOptions::default(), Selection::Last)?;
        if best.as_ref().is_none_or(|b| s.timestep > b.timestep) {
            best = Some(s);
        }
    }
    best.ok_or_else(|| format!("no dump in {}", post.display()).into())
}

/// Σ z and Σ vz of a dump with all digits: two builds whose runs print the same values ran
/// the same dynamics (to the dump's precision), whatever their speed.
fn fingerprint(s: &Snapshot) -> String {
    let sum = |name: &str| s.column(name).map_or(f64::NAN, |c| c.iter().sum::<f64>());
    format!("Σz {:e}, Σvz {:e}", sum("z"), sum("vz"))
}

fn measure(s: &Snapshot, half_width: f64) -> Result<bed::Bed, Error> {
    Ok(bed::measure(&s.positions()?, &s.radii()?, half_width))
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}
