//! Time per step of the native solver against Debian's `pisoFoam` (laminar) on the same mesh:
//! the lid-driven cavity of `tests/fixtures/fv/cavity-re100` refined to N×N cells (default 200),
//! Δt for a Courant number of 0.5, 40 steps, both solvers with their fvSolution tolerances.
//!
//! `cargo run --release -p fv --example bench_vs_pisofoam -- [N]` (needs pisoFoam, blockMesh).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

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

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map_or(200, |s| s.parse().expect("N"));
    let steps = 40;
    let dt = 0.5 * 0.1 / n as f64;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/fv/cavity-re100");
    let tmp = std::env::temp_dir().join(format!("fv-bench-{n}"));
    let _ = std::fs::remove_dir_all(&tmp);
    let of = tmp.join("pisoFoam");
    testkit::copy_dir(&root, &of);
    let _ = std::fs::remove_dir_all(of.join("0.5"));
    let _ = std::fs::remove_dir_all(of.join("constant/polyMesh"));
    edit(
        &of.join("system/blockMeshDict"),
        "(20 20 1)",
        &format!("({n} {n} 1)"),
    );
    let cd = of.join("system/controlDict");
    edit(
        &cd,
        "endTime         0.5;",
        &format!("endTime {};", dt * steps as f64),
    );
    edit(&cd, "deltaT          0.005;", &format!("deltaT {dt};"));
    edit(&cd, "writeInterval   100;", "writeInterval 100000;");
    edit(&cd, "icoFoam", "pisoFoam");
    edit(
        &of.join("system/fvSchemes"),
        "div(phi,U)      Gauss linear;",
        "div(phi,U)      Gauss linear;\n    div((nuEff*dev2(T(grad(U))))) Gauss linear;",
    );
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
    let ours = tmp.join("fv");
    testkit::copy_dir(&of, &ours);
    let log = run("pisoFoam", &of);
    let t = execution_times(&log);
    assert_eq!(t.len(), steps, "pisoFoam steps");
    // Per step after the first (which includes start-up).
    let piso = (t[steps - 1] - t[0]) / (steps - 1) as f64;

    let mut fluid = fv::Fluid::from_case(&ours).expect("native solver set-up");
    let r = fluid.advance(dt).unwrap();
    if std::env::var_os("FV_BENCH_VERBOSE").is_some() {
        eprintln!("{r:?}");
    }
    let t0 = Instant::now();
    for _ in 1..steps {
        fluid.advance(dt).unwrap();
    }
    let native = t0.elapsed().as_secs_f64() / (steps - 1) as f64;
    println!(
        "cavity {n}x{n} ({} cells), {} steps of {dt:e} s: pisoFoam {:.2} ms/step, fv {:.2} ms/step, ratio {:.2} (threads: {})",
        n * n,
        steps,
        1e3 * piso,
        1e3 * native,
        native / piso,
        rayon::current_num_threads()
    );
}

fn edit(path: &Path, from: &str, to: &str) {
    let s = std::fs::read_to_string(path).unwrap();
    assert!(s.contains(from), "{}: `{from}` not found", path.display());
    std::fs::write(path, s.replace(from, to)).unwrap();
}
