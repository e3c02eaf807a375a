//! Per-particle cell shares ([`VoidageMesh::shares`]): they are what the deposit adds up
//! (bit for bit), each particle's shares equal a deposit of that particle alone, exact shares
//! on a grid equal ball ∩ box volumes by quadrature, and volume outside the mesh is the
//! particle volume minus its shares.

mod common;

use approx::assert_abs_diff_eq;
use approx::assert_relative_eq;
use common::*;
use mesh::build::{affine, map_points, rotation, uniform_box};
use mesh::v3::V3;
use voidage::*;

const NO_GRID: MeshOptions = MeshOptions {
    axis_aligned_fast_path: false,
};

fn cloud(seed: u64, n: usize) -> (Vec<V3>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    // Centres up to one radius beyond the unit box, so some particles are partly outside.
    let pos = (0..n).map(|_| rng.point([-0.1; 3], [1.1; 3])).collect();
    let rad = (0..n).map(|_| rng.uniform(0.05, 0.2)).collect();
    (pos, rad)
}

fn meshes() -> Vec<VoidageMesh> {
    let grid = uniform_box([0.0; 3], [1.0; 3], [5, 4, 6]);
    let rot = map_points(
        &uniform_box([0.0; 3], [1.0; 3], [4, 4, 4]),
        affine(rotation([1.0, 2.0, 3.0], 0.4), [0.0; 3]),
    );
    vec![
        VoidageMesh::new(&grid).unwrap(),
        VoidageMesh::with_options(&grid, NO_GRID).unwrap(),
        VoidageMesh::new(&rot).unwrap(),
    ]
}

#[test]
fn shares_add_up_to_the_deposit_bit_for_bit() {
    let (pos, rad) = cloud(7, 3000);
    let set = ParticleSet::new(&pos, &rad);
    for vm in meshes() {
        for m in Method::ALL.into_iter().filter(|&m| defined_on(&vm, m)) {
            let (sh, dep) = vm.shares(m, &set).unwrap();
            let plain = vm.deposit(m, &set).unwrap();
            assert_eq!(dep, plain, "{m}");
            assert_eq!(sh.particles(), pos.len());
            assert_eq!(*sh.offsets.last().unwrap(), sh.cells.len());
            let mut solid = vec![0.0; vm.n_cells()];
            for (&c, &v) in sh.cells.iter().zip(&sh.volumes) {
                solid[c as usize] += v;
            }
            assert_eq!(solid, dep.solid, "{m}: shares summed in order");
            let outside: f64 = (0..sh.particles())
                .map(|i| ball_volume(rad[i]) - sh.inside_volume(i))
                .sum();
            assert!(
                approx::abs_diff_eq!(
                    outside,
                    dep.outside_volume,
                    epsilon = 1e-12 * dep.particle_volume
                ),
                "{m}: {outside} vs {}",
                dep.outside_volume
            );
            for i in 0..sh.particles() {
                let (cells, _) = sh.of(i);
                let mut sorted = cells.to_vec();
                sorted.sort_unstable();
                sorted.dedup();
                assert_eq!(
                    sorted.len(),
                    cells.len(),
                    "{m}: particle {i} repeats a cell"
                );
            }
        }
    }
}

#[test]
fn shares_into_a_reused_set_equal_fresh_shares() {
    let (pos, rad) = cloud(5, 400);
    let vm = &meshes()[0];
    let mut reused = vm
        .shares(Method::Exact, &ParticleSet::new(&pos, &rad))
        .unwrap()
        .0;
    // Fewer and more particles than the set held, and another method.
    for (n, m) in [
        (100, Method::Centre),
        (400, Method::Divided),
        (250, Method::Exact),
    ] {
        let set = ParticleSet::new(&pos[..n], &rad[..n]);
        let (mut hint_a, mut hint_b) = (vec![None; n], vec![None; n]);
        let fresh = vm.shares_with_cells(m, &set, &mut hint_a).unwrap();
        let dep = vm
            .shares_with_cells_into(m, &set, &mut hint_b, &mut reused)
            .unwrap();
        assert_eq!((&reused, &dep), (&fresh.0, &fresh.1), "{m}, {n} particles");
        assert_eq!(hint_a, hint_b);
    }
}

/// Shares of many particles (several batches of the engine's pipeline) against their serial sum
/// in particle order and against 1 and 3 threads, on `vm` with `methods`.
fn check_batches(vm: &VoidageMesh, methods: &[Method], n: usize, r: std::ops::Range<f64>) {
    let (pos, _) = cloud(9, n);
    let mut rng = Rng::new(10);
    let rad: Vec<f64> = (0..n).map(|_| rng.uniform(r.start, r.end)).collect();
    let set = ParticleSet::new(&pos, &rad);
    for &m in methods {
        let (sh, dep) = vm.shares(m, &set).unwrap();
        let mut solid = vec![0.0; vm.n_cells()];
        let mut volume = 0.0;
        for (i, r) in rad.iter().enumerate() {
            volume += ball_volume(*r);
            for (&c, &v) in sh.of(i).0.iter().zip(sh.of(i).1) {
                solid[c as usize] += v;
            }
        }
        assert_eq!(solid, dep.solid, "{m}: serial sum in particle order");
        assert!(
            approx::abs_diff_eq!(dep.particle_volume, volume, epsilon = 1e-13 * volume),
            "{m}"
        );
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let again = pool.install(|| vm.shares(m, &set).unwrap());
            assert_eq!((&again.0, &again.1), (&sh, &dep), "{m}, {threads} threads");
        }
    }
}

#[test]
fn many_batches_sum_in_particle_order_with_any_thread_count() {
    // 150 000 particles: several batches of the engine's pipeline.
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [10, 10, 10])).unwrap();
    check_batches(&vm, &[Method::Centre, Method::Divided], 150_000, 0.05..0.2);
}

/// On a general mesh the particles of a batch are computed in the order of their cells; the
/// shares must still come out, and add up, in particle order.
#[test]
fn many_batches_on_a_general_mesh_sum_in_particle_order() {
    let rot = map_points(
        &uniform_box([0.0; 3], [1.0; 3], [8, 8, 8]),
        affine(rotation([1.0, 2.0, 3.0], 0.4), [0.0; 3]),
    );
    let vm = VoidageMesh::new(&rot).unwrap();
    assert!(vm.axis_grid().is_none());
    check_batches(
        &vm,
        &[Method::Divided, Method::Cube, Method::Exact],
        140_000,
        0.01..0.05,
    );
}

#[test]
fn each_particle_matches_a_deposit_of_it_alone() {
    let (pos, rad) = cloud(11, 60);
    for vm in meshes() {
        for m in Method::ALL.into_iter().filter(|&m| defined_on(&vm, m)) {
            let (sh, _) = vm.shares(m, &ParticleSet::new(&pos, &rad)).unwrap();
            for i in 0..pos.len() {
                let one = vm
                    .deposit(m, &ParticleSet::new(&pos[i..=i], &rad[i..=i]))
                    .unwrap();
                let mut alone: Vec<(u32, f64)> = one
                    .solid
                    .iter()
                    .enumerate()
                    .filter(|(_, &v)| v != 0.0)
                    .map(|(c, &v)| (c as u32, v))
                    .collect();
                let (cells, vols) = sh.of(i);
                let mut mine: Vec<(u32, f64)> = cells
                    .iter()
                    .zip(vols)
                    .filter(|(_, &v)| v != 0.0)
                    .map(|(&c, &v)| (c, v))
                    .collect();
                alone.sort_by_key(|e| e.0);
                mine.sort_by_key(|e| e.0);
                assert_eq!(mine, alone, "{m}: particle {i}");
            }
        }
    }
}

#[test]
fn exact_grid_shares_are_ball_box_volumes() {
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [4, 4, 4])).unwrap();
    let c = V3::new(0.26, 0.49, 0.52);
    let r = 0.3;
    let (sh, _) = vm
        .shares(Method::Exact, &ParticleSet::new(&[c], &[r]))
        .unwrap();
    let g = vm.axis_grid().unwrap();
    let nodes = gauss_legendre(24);
    let (cells, vols) = sh.of(0);
    assert!(cells.len() > 8);
    for (&cell, &v) in cells.iter().zip(vols) {
        let [i, j, k] = g.ijk(cell);
        let lo = [i, j, k].map(|n| n as f64 * 0.25);
        let rel_lo = V3::from_fn(|a, _| lo[a] - c[a]);
        let rel_hi = V3::from_fn(|a, _| lo[a] + 0.25 - c[a]);
        let reference = ball_box_by_quadrature(r, rel_lo, rel_hi, &nodes);
        assert!(
            approx::abs_diff_eq!(v, reference, epsilon = 1e-13),
            "cell {cell}: {v} vs {reference}"
        );
    }
}

#[test]
fn divided_shares_are_multiples_of_a_29th() {
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [2, 2, 2])).unwrap();
    // A ball centred on the middle node: its markers spread over all 8 cells, each share a
    // whole number of markers of V/29.
    let r = 0.2;
    let (sh, dep) = vm
        .shares(Method::Divided, &ParticleSet::new(&[V3::repeat(0.5)], &[r]))
        .unwrap();
    let each = ball_volume(r) / 29.0;
    let (_, vols) = sh.of(0);
    assert_eq!(vols.len(), 8);
    let total: f64 = vols.iter().sum();
    for &v in vols {
        let k = v / each;
        assert!(approx::abs_diff_eq!(k, k.round(), epsilon = 1e-12), "{k}");
    }
    assert_abs_diff_eq!(total, ball_volume(r), epsilon = 1e-15);
    assert_eq!(dep.outside_volume, 0.0);
}

#[test]
fn particles_outside_have_no_shares() {
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [2, 2, 2])).unwrap();
    let pos = [[0.5; 3], [3.0, 0.5, 0.5], [0.5; 3]].map(V3::from);
    let rad = [0.1, 0.1, 0.0];
    for m in Method::ALL {
        let (sh, dep) = vm.shares(m, &ParticleSet::new(&pos, &rad)).unwrap();
        assert!(!sh.of(0).0.is_empty());
        assert!(sh.of(1).0.is_empty(), "{m}");
        assert!(sh.of(2).0.is_empty(), "{m}: zero radius");
        assert_eq!(dep.particles_outside, 1);
        assert_relative_eq!(
            dep.outside_volume,
            ball_volume(0.1),
            epsilon = 0.0,
            max_relative = 1e-15
        );
    }
}
