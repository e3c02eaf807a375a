//! Particles per second of every voidage method on a general (non-axis-aligned) mesh: the Ergun
//! case's O-grid (`openfoam-cases/ergun/CFD/constant/polyMesh`, 4480 hexahedra: an axis-aligned
//! core and four ring blocks with arc edges) with 200 000 spheres at random in the cylinder, of
//! diameter d = h/2, h = (mesh volume / cells)^⅓ ≈ 1.95 mm. Each timed call is one
//! `VoidageMesh::deposit` (locate + deposit + reduction), the figure printed is the median of
//! the repeats; particles per CPU-second (all threads) is printed too, being less sensitive to
//! the other load on a shared machine. Run: `cargo bench -p voidage --bench ergun_general`; `ERGUN_N` sets the number
//! of particles, `ERGUN_REPEATS` the repeats (default 5), `ERGUN_METHODS` a comma-separated list.

use mesh::v3::V3;
use std::time::Instant;
use testkit::{cpu_seconds, SplitMix};
use voidage::{Method, ParticleSet, VoidageMesh};

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../openfoam-cases/ergun/CFD/constant/polyMesh");
    let mesh = foam::read_poly_mesh(&dir).expect("the Ergun case's polyMesh");
    let vm = VoidageMesh::new(&mesh).unwrap();
    assert!(vm.axis_grid().is_none(), "the O-grid is a general mesh");
    let g = vm.geometry();
    let h = (g.total_volume() / vm.n_cells() as f64).cbrt();
    let r = 0.25 * h;
    let b = g.bounds;
    let radius = 0.5 * (b.max[0] - b.min[0]);
    let n: usize = env_or("ERGUN_N", 200_000);
    let repeats: usize = env_or("ERGUN_REPEATS", 5);
    let mut rng = SplitMix(17);
    let mut pos = Vec::with_capacity(n);
    while pos.len() < n {
        let x = radius * (2.0 * rng.unit() - 1.0);
        let y = radius * (2.0 * rng.unit() - 1.0);
        if x * x + y * y <= radius * radius {
            pos.push(V3::new(x, y, b.min[2] + (b.max[2] - b.min[2]) * rng.unit()));
        }
    }
    let rad = vec![r; n];
    let set = ParticleSet::new(&pos, &rad);
    let methods = std::env::var("ERGUN_METHODS")
        .unwrap_or_else(|_| "centre,divided,cube,corrected-cube,exact".into());
    println!(
        "Ergun O-grid: {} cells, h = {:.3e} m, d = {:.3e} m, {} particles, {} threads",
        vm.n_cells(),
        h,
        2.0 * r,
        n,
        rayon::current_num_threads()
    );
    for name in methods.split(',') {
        let method: Method = name.parse().unwrap();
        vm.deposit(method, &set).unwrap();
        let (mut times, mut cpu): (Vec<f64>, Vec<f64>) = (0..repeats)
            .map(|_| {
                let (t, c) = (Instant::now(), cpu_seconds());
                let d = vm.deposit(method, &set).unwrap();
                let s = (t.elapsed().as_secs_f64(), cpu_seconds() - c);
                std::hint::black_box(d);
                s
            })
            .unzip();
        times.sort_by(f64::total_cmp);
        cpu.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        println!(
            "{:>15}: {:>10.0} particles/s (wall median {:.4} s, min {:.4} s), {:>10.0} per CPU-s",
            name,
            n as f64 / median,
            median,
            times[0],
            n as f64 / cpu[cpu.len() / 2]
        );
    }
}
