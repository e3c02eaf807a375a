//! The pressure solvers on a model problem: the 5-point Laplacian of an N×N×Nz grid on
//! [0, 1]² × [0, 0.1] (one Dirichlet-like cell), solved to OpenFOAM's normalised residual 1e-6
//! from zero by PCG/DIC and by `GAMG` (CG preconditioned by [`fv::amg`]); prints the multigrid
//! set-up and cycle cost, a matrix–vector product for scale, and iterations and CPU time per
//! solve (best of repeated runs, CPU time of the process from /proc).
//!
//! `cargo run --release -p fv --example amg_vs_dic -- [N] [Nz] [DEPTH]` (default 100 1 0.1).

use fv::ldu::{Ldu, RowMatrix};
use fv::linsolve::{self, Method, Preconditioner, SolverControls};
/// CPU time of this process so far (s).
fn cpu() -> f64 {
    let mut ns = 0u64;
    for t in std::fs::read_dir("/proc/self/task").unwrap() {
        let stat = std::fs::read_to_string(t.unwrap().path().join("schedstat")).unwrap_or_default();
        ns += stat
            .split_whitespace()
            .next()
            .and_then(|x| x.parse::<u64>().ok())
            .unwrap_or(0);
    }
    ns as f64 * 1e-9
}
/// The least CPU milliseconds per call of `f` over `reps` runs of `inner` calls.
fn best(reps: usize, inner: usize, mut f: impl FnMut()) -> f64 {
    (0..reps)
        .map(|_| {
            let t = cpu();
            for _ in 0..inner {
                f();
            }
            (cpu() - t) * 1e3 / inner as f64
        })
        .fold(f64::INFINITY, f64::min)
}
fn main() {
    let n: usize = std::env::args().nth(1).map_or(100, |s| s.parse().unwrap());
    let nz: usize = std::env::args().nth(2).map_or(1, |s| s.parse().unwrap());
    // A third argument: the depth of the box (default 0.1; 1 with Nz = N: cubic cells).
    let depth: f64 = std::env::args().nth(3).map_or(0.1, |s| s.parse().unwrap());
    let m = mesh::build::uniform_box([0.0; 3], [1.0, 1.0, depth], [n, n, nz]);
    let g = fv::FvGeometry::new(&m).unwrap();
    let mut a = Ldu::zeros(&g);
    for f in 0..g.n_internal {
        let c = g.mag_sf[f] * g.delta_coeff[f];
        a.upper[f] = -c;
        a.lower[f] = -c;
        a.diag[g.owner[f] as usize] += c;
        a.diag[g.neighbour[f] as usize] += c;
    }
    a.diag[0] *= 2.0;
    let b: Vec<f64> = (0..g.n_cells).map(|i| ((i as f64) * 0.37).sin()).collect();
    let rm = RowMatrix::new(&a, &g);
    println!(
        "setup {:.3} ms",
        best(5, 10, || {
            let _ = fv::amg::Amg::new(&rm);
        })
    );
    let amg = fv::amg::Amg::new(&rm);
    println!("levels {:?}", amg.sizes());
    let mut z = vec![0.0; g.n_cells];
    println!("vcycle {:.3} ms", best(5, 50, || amg.apply(&b, &mut z)));
    let mut y = vec![0.0; g.n_cells];
    println!("matvec {:.4} ms", best(5, 200, || rm.mul(&b, &mut y)));
    for (name, method) in [
        ("PCG DIC", Method::Pcg(Preconditioner::Dic)),
        ("GAMG", Method::Gamg),
    ] {
        let c = SolverControls {
            tolerance: 1e-6,
            rel_tol: 0.0,
            ..SolverControls::default()
        };
        let mut it = 0;
        let mut wall = f64::INFINITY;
        let t = best(3, 3, || {
            let mut x = vec![0.0; g.n_cells];
            let t0 = std::time::Instant::now();
            it = linsolve::solve(method, &a, &g, &b, &mut x, &c, "p")
                .unwrap()
                .iterations;
            wall = wall.min(t0.elapsed().as_secs_f64() * 1e3);
        });
        println!("{name}: {it} iterations, {t:.3} CPU ms/solve, {wall:.3} wall ms (best)");
    }
}
