//! The general-mesh path on meshes written by OpenFOAM v1912 (committed fixtures): graded,
//! skewed hex blocks with a warped face, and a polyhedral dual mesh with pentagonal faces.
//! Exact shares against the tet kernel cell by cell and against Monte Carlo, whole cells and
//! the whole mesh inside a large ball against OpenFOAM's volumes, conservation for every method.

mod common;

use approx::assert_abs_diff_eq;
use common::*;
use mesh::v3::V3;
use voidage::*;

fn load(case: &str) -> VoidageMesh {
    let dir = testkit::fixture(&format!("mesh/{case}/constant/polyMesh"));
    let mesh = foam::read_poly_mesh(&dir).unwrap();
    let vm = VoidageMesh::new(&mesh).unwrap();
    assert!(vm.axis_grid().is_none());
    vm
}

/// Random particles around the mesh bounds, radii from 0.2 to 3 mean cell sizes.
fn particles(vm: &VoidageMesh, rng: &mut Rng, n: usize) -> (Vec<V3>, Vec<f64>) {
    let b = vm.geometry().bounds;
    let h = (vm.geometry().total_volume() / vm.n_cells() as f64).cbrt();
    let pos = (0..n)
        .map(|_| {
            let ext = b.extent();
            rng.point(
                V3::from_fn(|a, _| b.min[a] - 0.1 * ext[a]),
                V3::from_fn(|a, _| b.max[a] + 0.1 * ext[a]),
            )
        })
        .collect();
    let rad = (0..n).map(|_| h * rng.uniform(0.2, 3.0)).collect();
    (pos, rad)
}

#[test]
fn exact_shares_equal_tet_sums() {
    for case in ["skewed_blocks", "poly_dual"] {
        let vm = load(case);
        let mut rng = Rng::new(40);
        let (pos, rad) = particles(&vm, &mut rng, 25);
        for (&c, &r) in pos.iter().zip(&rad) {
            let d = vm
                .deposit(Method::Exact, &ParticleSet::new(&[c], &[r]))
                .unwrap();
            let v = ball_volume(r);
            let mut sum = 0.0;
            for (cell, &x) in d.solid.iter().enumerate() {
                let by_tets = tet_sum(&vm, cell, c, r);
                assert!(
                    approx::abs_diff_eq!(x, by_tets, epsilon = 1e-12 * v),
                    "{case} cell {cell}: {x} vs {by_tets}"
                );
                sum += by_tets;
            }
            assert_abs_diff_eq!(d.outside_volume, (v - sum), epsilon = 1e-12 * v);
        }
    }
}

#[test]
fn whole_cells_and_whole_mesh_get_openfoam_volumes() {
    for case in ["skewed_blocks", "poly_dual"] {
        let vm = load(case);
        let g = vm.geometry();
        let b = g.bounds;
        let c: V3 = V3::from_fn(|a, _| 0.5 * (b.min[a] + b.max[a]));
        let diag = b.extent().iter().map(|x| x * x).sum::<f64>().sqrt();
        // A ball holding the whole mesh: every cell full, the rest outside.
        let r = diag;
        let d = vm
            .deposit(Method::Exact, &ParticleSet::new(&[c], &[r]))
            .unwrap();
        for (x, v) in d.solid.iter().zip(&g.cell_volumes) {
            assert_eq!(x, v);
        }
        let total = g.total_volume();
        assert_abs_diff_eq!(
            d.outside_volume,
            (ball_volume(r) - total),
            epsilon = 1e-14 * ball_volume(r)
        );
        // A ball just larger than one cell, around its centre: the cell's OpenFOAM volume.
        let cell = vm.n_cells() / 2;
        let cc = g.cell_centres[cell];
        let rc = 1.01
            * vm.locator()
                .tets()
                .cell_tets(cell as u32)
                .flat_map(|t| t.points)
                .map(|p| (0..3).map(|a| (p[a] - cc[a]).powi(2)).sum::<f64>().sqrt())
                .fold(0.0, f64::max);
        let d = vm
            .deposit(Method::Exact, &ParticleSet::new(&[cc], &[rc]))
            .unwrap();
        assert_eq!(d.solid[cell], g.cell_volumes[cell]);
    }
}

#[test]
fn exact_matches_monte_carlo() {
    for case in ["skewed_blocks", "poly_dual"] {
        let vm = load(case);
        let g = vm.geometry();
        let h = (g.total_volume() / vm.n_cells() as f64).cbrt();
        let mut rng = Rng::new(41);
        let n = 100_000;
        // One particle near a corner of the mesh (part outside), one inside.
        let b = g.bounds;
        for (c, r) in [
            (b.min.map(|x| x + 0.5 * h), 1.2 * h),
            (g.cell_centres[7], 2.0 * h),
        ] {
            check_exact_against_monte_carlo(&vm, &mut rng, c, r, n);
        }
    }
}

#[test]
fn every_method_conserves_volume() {
    for case in ["skewed_blocks", "poly_dual"] {
        let vm = load(case);
        let mut rng = Rng::new(42);
        let (pos, rad) = particles(&vm, &mut rng, 300);
        for m in Method::ALL.into_iter().filter(|&m| defined_on(&vm, m)) {
            let d = vm.deposit(m, &ParticleSet::new(&pos, &rad)).unwrap();
            assert!(d.conservation_error() < 1e-12, "{case} {m}");
            assert!(d.solid.iter().all(|&s| s >= 0.0));
            assert!(d.deposited_volume > 0.0 && d.outside_volume > 0.0);
        }
    }
}
