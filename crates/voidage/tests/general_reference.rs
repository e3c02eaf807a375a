//! Every method on general meshes against a straightforward reference path, particle by
//! particle: brute-force point location (every cell whose bounding box holds the point, by its
//! tets), cube ∩ cell by clipping each tet of every cell near the particle, ball ∩ cell by the
//! tet kernel over every cell near the particle. Meshes: the Ergun case's O-grid (the
//! benchmark's mesh), OpenFOAM's skewed blocks with a warped face and its polyhedral dual
//! mesh, and a rotated grid. The fast paths (face terms shared between cells, whole-cell and
//! whole-particle short cuts, marker location from the centre's cell, the candidate walk) must
//! give the reference shares to round-off.

mod common;

use common::*;
use foam::Label;
use mesh::build::{affine, map_points, rotation, uniform_box};
use mesh::v3::V3;
use std::collections::BTreeMap;
use voidage::*;

fn meshes() -> Vec<(&'static str, VoidageMesh)> {
    let read = |dir: std::path::PathBuf| VoidageMesh::new(&foam::read_poly_mesh(&dir).unwrap());
    let f = affine(rotation([1.0, 2.0, 3.0], 0.6), [0.1, 0.2, 0.3]);
    let rotated = map_points(&uniform_box([0.0; 3], [1.0; 3], [5, 4, 3]), &f);
    let list = vec![
        (
            "ergun",
            read(testkit::repo_root().join("openfoam-cases/ergun/CFD/constant/polyMesh")).unwrap(),
        ),
        (
            "skewed_blocks",
            read(testkit::fixture("mesh/skewed_blocks/constant/polyMesh")).unwrap(),
        ),
        (
            "poly_dual",
            read(testkit::fixture("mesh/poly_dual/constant/polyMesh")).unwrap(),
        ),
        ("rotated", VoidageMesh::new(&rotated).unwrap()),
    ];
    for (name, vm) in &list {
        assert!(vm.axis_grid().is_none(), "{name} is a general mesh");
    }
    list
}

/// Particles in and around the mesh bounds, radii from 0.1 to 1 mean cell size (a quarter of
/// them at h/4, the benchmark's h = 2d).
fn particles(vm: &VoidageMesh, rng: &mut Rng, n: usize) -> (Vec<V3>, Vec<f64>) {
    let b = vm.geometry().bounds;
    let h = (vm.geometry().total_volume() / vm.n_cells() as f64).cbrt();
    let ext = b.extent();
    let pos = (0..n)
        .map(|_| {
            rng.point(
                V3::from_fn(|a, _| b.min[a] - 0.05 * ext[a]),
                V3::from_fn(|a, _| b.max[a] + 0.05 * ext[a]),
            )
        })
        .collect();
    let rad = (0..n)
        .map(|i| {
            if i % 4 == 0 {
                0.25 * h
            } else {
                h * rng.uniform(0.1, 1.0)
            }
        })
        .collect();
    (pos, rad)
}

/// The cell holding `p` by brute force.
fn locate_ref(vm: &VoidageMesh, p: V3) -> Option<Label> {
    let loc = vm.locator();
    let found: Vec<Label> = (0..vm.n_cells() as Label)
        .filter(|&c| loc.cell_bounds()[c as usize].contains(p) && loc.tets().cell_contains(c, p))
        .collect();
    assert!(found.len() <= 1, "{p:?} in {found:?}");
    found.first().copied()
}

/// The cells whose bounding box meets the box `lo`..`hi`.
fn near(vm: &VoidageMesh, lo: V3, hi: V3) -> Vec<Label> {
    let b = vm.locator().cell_bounds();
    (0..vm.n_cells() as Label)
        .filter(|&c| (0..3).all(|a| b[c as usize].max[a] > lo[a] && b[c as usize].min[a] < hi[a]))
        .collect()
}

/// The reference shares of one particle.
fn reference(vm: &VoidageMesh, method: Method, c: V3, r: f64) -> BTreeMap<Label, f64> {
    let v = ball_volume(r);
    let mut out = BTreeMap::new();
    let lo = c.map(|x| x - r);
    let hi = c.map(|x| x + r);
    let tets = vm.locator().tets();
    match method {
        Method::Centre => {
            if let Some(c0) = locate_ref(vm, c) {
                out.insert(c0, v);
            }
        }
        Method::Divided => {
            if let Some(c0) = locate_ref(vm, c) {
                for off in divided_offsets() {
                    let p = V3::from_fn(|a, _| c[a] + r * off[a]);
                    let m = locate_ref(vm, p).unwrap_or(c0);
                    *out.entry(m).or_insert(0.0) += v / DIVIDED_MARKERS as f64;
                }
            }
        }
        Method::Cube | Method::CorrectedCube => {
            let cube = 8.0 * r * r * r;
            let mut phi = BTreeMap::new();
            for cell in near(vm, lo, hi) {
                let cv = vm.cell_volumes()[cell as usize];
                let vol: f64 = tets
                    .cell_tets(cell)
                    .map(|t| box_tet_by_clipping(lo, hi, &t.points))
                    .sum();
                let f = (vol.clamp(0.0, cv) / cube).min(1.0);
                if f > 0.0 {
                    phi.insert(cell, f);
                }
            }
            if method == Method::Cube {
                out = phi.iter().map(|(&k, &f)| (k, f * v)).collect();
            } else {
                let total: f64 = phi.values().sum();
                let outside = khawaja_correction((1.0 - total).clamp(0.0, 1.0));
                let w: f64 = phi.values().map(|&f| khawaja_correction(f)).sum::<f64>() + outside;
                out = phi
                    .iter()
                    .map(|(&k, &f)| (k, khawaja_correction(f) * v / w))
                    .collect();
            }
        }
        Method::Exact => {
            for cell in near(vm, lo, hi) {
                let cv = vm.cell_volumes()[cell as usize];
                let x = tet_sum(vm, cell as usize, c, r).clamp(0.0, cv.min(v));
                if x > 0.0 {
                    out.insert(cell, x);
                }
            }
        }
        Method::Trilinear => unreachable!("not defined on general meshes"),
        Method::BigParticle | Method::Gauss => {
            unreachable!("not in Method::ANY_MESH (tests/big_particle.rs, tests/gauss.rs)")
        }
    }
    out
}

#[test]
fn every_method_gives_the_reference_shares_on_general_meshes() {
    for (name, vm) in meshes() {
        let mut rng = Rng::new(77);
        let n = if name == "ergun" { 120 } else { 60 };
        let (pos, rad) = particles(&vm, &mut rng, n);
        let set = ParticleSet::new(&pos, &rad);
        for method in Method::ANY_MESH {
            let (shares, dep) = vm.shares(method, &set).unwrap();
            assert!(dep.conservation_error() < 1e-12, "{name} {method}");
            for i in 0..n {
                let v = ball_volume(rad[i]);
                let want = reference(&vm, method, pos[i], rad[i]);
                let (cells, vols) = shares.of(i);
                let mut got = BTreeMap::new();
                for (&c, &x) in cells.iter().zip(vols) {
                    assert!(
                        got.insert(c, x).is_none(),
                        "{name} {method}: cell {c} twice"
                    );
                }
                let tol = 1e-12 * v;
                for (&c, &x) in want.iter().chain(got.iter()) {
                    let (a, b) = (
                        got.get(&c).copied().unwrap_or(0.0),
                        want.get(&c).copied().unwrap_or(0.0),
                    );
                    assert!(
                        (a - b).abs() <= tol,
                        "{name} {method} particle {i} ({:?}, r {}) cell {c}: {a} vs reference \
                         {b} ({x})",
                        pos[i],
                        rad[i]
                    );
                }
            }
        }
    }
}
