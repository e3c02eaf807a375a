//! Time per step of the native solver against Debian's `pisoFoam` (laminar) on the same mesh:
//! the lid-driven cavity of `tests/fixtures/fv/cavity-re100` refined to N×N cells (default 100),
//! Δt for a Courant number of 0.5, 40 steps, both solvers with the same fvSolution (PCG/DIC
//! for p with relTol 0.05 and 0 in the final corrector, smoothSolver/symGaussSeidel 1e-5 for U,
//! 2 correctors). The two run back to back `R` times (default 3); the best-of and the median
//! are printed with the load average before each pair and the linear-solver iterations per step
//! of both (so a speed difference can be told apart from a convergence difference).
//!
//! pisoFoam's time per step is the difference of its `ExecutionTime` (process CPU time) between
//! the first and the last step; ours is measured over steps 2..40 both as CPU time (all threads
//! of the process, from `/proc/self/task/*/schedstat`, comparable with pisoFoam's under load)
//! and as wall time (which also counts the waiting a loaded machine causes). The ratio is
//! CPU time over CPU time.
//!
//! `cargo run --release -p fv --example bench_vs_pisofoam -- [N] [R] [PCG|GAMG|both]` (needs
//! pisoFoam and blockMesh). The third argument picks the p solver of both programs: `PCG`
//! (DIC, the default), `GAMG` (pisoFoam: OpenFOAM's GAMG with Gauss–Seidel; fv: CG
//! preconditioned by its aggregation multigrid, [`fv::amg`]), or `both`, which runs the four
//! back to back in each repetition.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

const STEPS: usize = 40;

fn run(cmd: &str, dir: &Path) -> String {
    let out = Command::new(cmd)
        .current_dir(dir)
        .env("WM_PROJECT_DIR", "/usr/share/openfoam")
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd}: {e}"));
    assert!(
        out.status.success(),
        "{cmd} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The ExecutionTime (s) printed after each step of an OpenFOAM log.
fn execution_times(log: &str) -> Vec<f64> {
    log.lines()
        .filter_map(|l| l.strip_prefix("ExecutionTime = "))
        .filter_map(|l| l.split_whitespace().next()?.parse().ok())
        .collect()
}

/// Total iterations of the solves whose log line contains `what` (e.g. "Solving for p").
fn log_iterations(log: &str, what: &str) -> usize {
    log.lines()
        .filter(|l| l.contains(what))
        .filter_map(|l| {
            l.rsplit("No Iterations ")
                .next()?
                .trim()
                .parse::<usize>()
                .ok()
        })
        .sum()
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

/// CPU time of this process so far (s): the run time of all its threads, in ns.
fn cpu_seconds() -> f64 {
    let mut ns = 0u64;
    for t in std::fs::read_dir("/proc/self/task").expect("/proc/self/task") {
        let stat = std::fs::read_to_string(t.unwrap().path().join("schedstat")).unwrap_or_default();
        ns += stat
            .split_whitespace()
            .next()
            .and_then(|x| x.parse::<u64>().ok())
            .unwrap_or(0);
    }
    ns as f64 * 1e-9
}

/// One timed run: CPU ms per step, wall ms per step, p iterations per step, U iterations per
/// step.
struct Sample {
    ms: f64,
    wall: f64,
    p_iter: f64,
    u_iter: f64,
}

fn pisofoam(dir: &Path) -> Sample {
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        if name != "0" && name.parse::<f64>().is_ok() {
            std::fs::remove_dir_all(e.path()).unwrap();
        }
    }
    let log = run("pisoFoam", dir);
    std::fs::write(dir.join("log.pisoFoam"), &log).unwrap();
    let t = execution_times(&log);
    assert_eq!(t.len(), STEPS, "pisoFoam steps");
    let ms = 1e3 * (t[STEPS - 1] - t[0]) / (STEPS - 1) as f64;
    Sample {
        ms,
        wall: f64::NAN,
        p_iter: log_iterations(&log, "Solving for p") as f64 / STEPS as f64,
        u_iter: log_iterations(&log, "Solving for U") as f64 / STEPS as f64,
    }
}

fn native(dir: &Path, dt: f64) -> Sample {
    let mut fluid = fv::Fluid::from_case(dir).expect("native solver set-up");
    let mut p_iter = 0;
    let mut u_iter = 0;
    let mut count = |r: &fv::StepReport| {
        p_iter += r.pressure.iter().map(|s| s.iterations).sum::<usize>();
        u_iter += r.momentum.iter().map(|s| s.iterations).sum::<usize>();
    };
    count(&fluid.advance(dt).unwrap());
    let t0 = Instant::now();
    let cpu0 = cpu_seconds();
    for _ in 1..STEPS {
        let r = fluid.advance(dt).unwrap();
        count(&r);
    }
    let cpu = cpu_seconds() - cpu0;
    Sample {
        ms: 1e3 * cpu / (STEPS - 1) as f64,
        wall: 1e3 * t0.elapsed().as_secs_f64() / (STEPS - 1) as f64,
        p_iter: p_iter as f64 / STEPS as f64,
        u_iter: u_iter as f64 / STEPS as f64,
    }
}

/// The pressure solvers the benchmark can compare: name and the `solver …` text replacing
/// the fixture's `PCG`/`DIC` entry of p (pFinal inherits it with `$p`).
const SOLVERS: &[(&str, &str)] = &[
    ("PCG", "solver          PCG;\n        preconditioner  DIC;"),
    (
        "GAMG",
        "solver GAMG;\n        smoother GaussSeidel;\n        cacheAgglomeration true;\n        nCellsInCoarsestLevel 10;\n        agglomerator faceAreaPair;\n        mergeLevels 1;",
    ),
];

/// Writes the pisoFoam case (meshed) and its copy for the native solver under
/// `tmp/<solver>/`; returns (pisoFoam case, native case).
fn prepare(root: &Path, tmp: &Path, n: usize, dt: f64, solver: &str) -> (PathBuf, PathBuf) {
    let of = tmp.join(solver).join("pisoFoam");
    testkit::copy_dir(root, &of);
    let _ = std::fs::remove_dir_all(of.join("0.5"));
    let _ = std::fs::remove_dir_all(of.join("constant/polyMesh"));
    let _ = std::fs::remove_file(of.join("log.icoFoam"));
    edit(
        &of.join("system/blockMeshDict"),
        "(20 20 1)",
        &format!("({n} {n} 1)"),
    );
    let cd = of.join("system/controlDict");
    edit(
        &cd,
        "endTime         0.5;",
        &format!("endTime {};", dt * STEPS as f64),
    );
    edit(&cd, "deltaT          0.005;", &format!("deltaT {dt};"));
    edit(&cd, "writeInterval   100;", "writeInterval 100000;");
    edit(&cd, "icoFoam", "pisoFoam");
    edit(
        &of.join("system/fvSchemes"),
        "div(phi,U)      Gauss linear;",
        "div(phi,U)      Gauss linear;\n    div((nuEff*dev2(T(grad(U))))) Gauss linear;",
    );
    let entry = SOLVERS
        .iter()
        .find(|s| s.0 == solver)
        .unwrap_or_else(|| panic!("solver {solver}: one of PCG, GAMG"))
        .1;
    edit(&of.join("system/fvSolution"), SOLVERS[0].1, entry);
    std::fs::write(
        of.join("constant/turbulenceProperties"),
        "FoamFile { version 2.0; format ascii; class dictionary; object turbulenceProperties; }\nsimulationType laminar;\n",
    )
    .unwrap();
    edit(
        &of.join("constant/transportProperties"),
        "nu ",
        "transportModel Newtonian;\nnu ",
    );
    run("blockMesh", &of);
    let ours = tmp.join(solver).join("fv");
    testkit::copy_dir(&of, &ours);
    (of, ours)
}

fn main() {
    let arg = |i: usize, default: usize| {
        std::env::args()
            .nth(i)
            .map_or(default, |s| s.parse().expect("a whole number"))
    };
    let n = arg(1, 100);
    let reps = arg(2, 3).max(1);
    let solvers: Vec<String> = match std::env::args().nth(3).as_deref() {
        None | Some("PCG") => vec!["PCG".into()],
        Some("both") => vec!["PCG".into(), "GAMG".into()],
        Some(other) => vec![other.to_string()],
    };
    let dt = 0.5 * 0.1 / n as f64;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/fv/cavity-re100");
    let tmp = std::env::temp_dir().join(format!("fv-bench-{n}"));
    let _ = std::fs::remove_dir_all(&tmp);
    let cases: Vec<(PathBuf, PathBuf)> = solvers
        .iter()
        .map(|s| prepare(&root, &tmp, n, dt, s))
        .collect();

    println!(
        "cavity {n}x{n} ({} cells), {STEPS} steps of {dt:e} s, {} rayon threads",
        n * n,
        rayon::current_num_threads()
    );
    println!(
        "rep  p solver  load(1/5/15 min)   pisoFoam CPU ms/step (p it, U it)   fv CPU ms/step, wall (p it, U it)"
    );
    let mut piso = vec![Vec::new(); solvers.len()];
    let mut fv = vec![Vec::new(); solvers.len()];
    let mut fv_wall = vec![Vec::new(); solvers.len()];
    for rep in 0..reps {
        for (k, (of, ours)) in cases.iter().enumerate() {
            let load = load_average();
            let a = pisofoam(of);
            let b = native(ours, dt);
            println!(
                "{rep:>3}  {:<8}  {load:<17}  {:>8.2} ({:>6.1}, {:>4.1})              {:>8.2}, {:>6.2} ({:>6.1}, {:>4.1})",
                solvers[k], a.ms, a.p_iter, a.u_iter, b.ms, b.wall, b.p_iter, b.u_iter
            );
            piso[k].push(a.ms);
            fv[k].push(b.ms);
            fv_wall[k].push(b.wall);
        }
    }
    let best = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    for (k, solver) in solvers.iter().enumerate() {
        let (bp, bf) = (best(&piso[k]), best(&fv[k]));
        let (mp, mf) = (median(&mut piso[k]), median(&mut fv[k]));
        println!(
            "p {solver}, best of {reps}: pisoFoam {bp:.2} ms/step, fv {bf:.2} ms/step (wall {:.2}), ratio {:.2}; median ratio {:.2}",
            best(&fv_wall[k]),
            bf / bp,
            mf / mp
        );
    }
}

fn edit(path: &Path, from: &str, to: &str) {
    let s = std::fs::read_to_string(path).unwrap();
    assert!(s.contains(from), "{}: `{from}` not found", path.display());
    std::fs::write(path, s.replace(from, to)).unwrap();
}
