//! Particles per second of every voidage method: an axis-aligned 60³ hex mesh with cell size
//! h = 1, 3, 5 particle diameters (2·10⁵ particles, centres uniform in the mesh), and the same
//! mesh rotated (general, non-axis-aligned path; 30³ cells, 5·10⁴ particles). Each iteration
//! is one `VoidageMesh::deposit` (locate + deposit + reduction), so particles/s = N / time.
//! Run: `cargo bench -p voidage`.

use divan::counter::ItemsCount;
use mesh::build::{affine, map_points, rotation, uniform_box};
use std::sync::OnceLock;
use voidage::{Method, ParticleSet, VoidageMesh};

const METHODS: [&str; 5] = ["centre", "divided", "cube", "corrected-cube", "exact"];

fn main() {
    divan::main();
}

/// `n` points spread uniformly over the unit cube: the additive recurrence x_k = frac(s + k·α)
/// with α = (1/φ₃, 1/φ₃², 1/φ₃³), φ₃ the plastic number (Roberts' R3 sequence).
fn points(seed: u64, n: usize) -> Vec<[f64; 3]> {
    let phi = 1.324_717_957_244_746_f64;
    let alpha = [1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi)];
    let s = 0.5 + seed as f64 * 0.1;
    (0..n)
        .map(|k| alpha.map(|a| (s + k as f64 * a).fract()))
        .collect()
}

struct Case {
    vm: VoidageMesh,
    pos: Vec<mesh::v3::V3>,
    h: f64,
}

fn grid() -> &'static Case {
    static C: OnceLock<Case> = OnceLock::new();
    C.get_or_init(|| {
        let n = 60;
        let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [n; 3])).unwrap();
        assert!(vm.axis_grid().is_some());
        Case {
            vm,
            pos: mesh::v3::from_arrays(&points(1, 200_000)),
            h: 1.0 / n as f64,
        }
    })
}

fn rotated() -> &'static Case {
    static C: OnceLock<Case> = OnceLock::new();
    C.get_or_init(|| {
        let n = 30;
        let f = affine(rotation([1.0, 2.0, 3.0], 0.6), [0.1, 0.2, 0.3]);
        let vm =
            VoidageMesh::new(&map_points(&uniform_box([0.0; 3], [1.0; 3], [n; 3]), &f)).unwrap();
        assert!(vm.axis_grid().is_none());
        Case {
            vm,
            pos: points(2, 50_000).into_iter().map(|p| f(p).into()).collect(),
            h: 1.0 / n as f64,
        }
    })
}

fn run<const H_OVER_D: usize>(b: divan::Bencher, case: &Case, method: &str) {
    let method: Method = method.parse().unwrap();
    let r = 0.5 * case.h / H_OVER_D as f64;
    let rad = vec![r; case.pos.len()];
    let set = ParticleSet::new(&case.pos, &rad);
    b.counter(ItemsCount::new(case.pos.len()))
        .bench(|| case.vm.deposit(method, &set).unwrap());
}

#[divan::bench(consts = [1, 3, 5], args = METHODS, sample_count = 5)]
fn axis_aligned<const H_OVER_D: usize>(b: divan::Bencher, method: &str) {
    run::<H_OVER_D>(b, grid(), method);
}

#[divan::bench(consts = [1, 3, 5], args = METHODS, sample_count = 3)]
fn rotated_general<const H_OVER_D: usize>(b: divan::Bencher, method: &str) {
    run::<H_OVER_D>(b, rotated(), method);
}
