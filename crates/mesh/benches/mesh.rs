//! Geometry of a 100³ hex mesh and location of 10⁶ random points (fast path, general path,
//! walks from the previous cell after a small displacement). Points per second = 10⁶ / time.

use foam::{Label, PolyMesh};
use mesh::build::{affine, map_points, uniform_box};
use mesh::v3::{from_arrays, V3};
use mesh::{Locator, MeshGeometry};
use std::sync::OnceLock;

const N: usize = 100;
const POINTS: usize = 1_000_000;

fn main() {
    divan::main();
}

fn rng_points(seed: u64, n: usize) -> Vec<[f64; 3]> {
    let mut r = testkit::SplitMix(seed);
    (0..n).map(|_| [r.unit(), r.unit(), r.unit()]).collect()
}

const SHEAR: [[f64; 3]; 3] = [[0.9, 0.35, -0.2], [-0.3, 0.85, 0.25], [0.15, -0.2, 1.05]];

struct Case {
    mesh: PolyMesh,
    loc: Locator,
    points: Vec<V3>,
}

fn grid() -> &'static Case {
    static C: OnceLock<Case> = OnceLock::new();
    C.get_or_init(|| {
        let mesh = uniform_box([0.0; 3], [1.0; 3], [N; 3]);
        let g = MeshGeometry::new(&mesh).unwrap();
        let loc = Locator::new(&mesh, &g).unwrap();
        assert!(loc.axis_grid().is_some());
        Case {
            mesh,
            loc,
            points: from_arrays(&rng_points(1, POINTS)),
        }
    })
}

fn sheared() -> &'static Case {
    static C: OnceLock<Case> = OnceLock::new();
    C.get_or_init(|| {
        let map = affine(SHEAR, [0.1, 0.2, 0.3]);
        let mesh = map_points(&uniform_box([0.0; 3], [1.0; 3], [N; 3]), &map);
        let g = MeshGeometry::new(&mesh).unwrap();
        let loc = Locator::new(&mesh, &g).unwrap();
        assert!(loc.axis_grid().is_none());
        let points = rng_points(2, POINTS)
            .into_iter()
            .map(|p| V3::from(map(p)))
            .collect();
        Case { mesh, loc, points }
    })
}

#[divan::bench(sample_count = 5)]
fn geometry_100_cubed(b: divan::Bencher) {
    let mesh = &grid().mesh;
    b.bench(|| MeshGeometry::new(mesh).unwrap());
}

#[divan::bench(sample_count = 5)]
fn locate_1e6_axis_aligned_fast_path(b: divan::Bencher) {
    let c = grid();
    b.bench(|| c.loc.locate_all(&c.points));
}

#[divan::bench(sample_count = 5)]
fn locate_1e6_sheared_general_path(b: divan::Bencher) {
    let c = sheared();
    b.bench(|| c.loc.locate_all(&c.points));
}

#[divan::bench(sample_count = 5)]
fn locate_from_1e6_sheared_after_small_move(b: divan::Bencher) {
    let c = sheared();
    let start: Vec<Option<Label>> = c.loc.locate_all(&c.points);
    // Move every point by up to 0.3 cell widths in each direction.
    let h = 0.3 / N as f64;
    let moved: Vec<V3> = c
        .points
        .iter()
        .zip(rng_points(3, POINTS))
        .map(|(p, r)| V3::from_fn(|a, _| p[a] + h * (2.0 * r[a] - 1.0)))
        .collect();
    b.with_inputs(|| start.clone())
        .bench_local_refs(|cells| c.loc.locate_all_from(&moved, cells));
}

#[divan::bench(sample_count = 3)]
fn locator_build_sheared(b: divan::Bencher) {
    let c = sheared();
    let g = MeshGeometry::new(&c.mesh).unwrap();
    b.bench(|| Locator::new(&c.mesh, &g).unwrap());
}
