//! The `divided` memo ([`voidage::memo`]): a deposit that reuses the markers' cells of the
//! last one where a particle has not moved past their clearance is bit for bit the deposit
//! without a memo — shares, cells and solid volumes — over random walks of every step size,
//! with radii that change, particles that leave and re-enter the mesh and a population whose
//! order changes without the memo being re-keyed. The reference is the same deposit computed
//! afresh every step.

mod common;

use common::Rng;
use foam::PolyMesh;
use mesh::build::{affine, map_points, rotation, uniform_box};
use mesh::v3::V3;
use voidage::{CellShares, DividedMemo, Method, ParticleSet, VoidageMesh};

fn fixture(case: &str) -> PolyMesh {
    foam::read_poly_mesh(&testkit::fixture(&format!("mesh/{case}/constant/polyMesh"))).unwrap()
}

fn empty_shares() -> CellShares {
    CellShares {
        method: Method::Divided,
        offsets: Vec::new(),
        cells: Vec::new(),
        volumes: Vec::new(),
    }
}

/// Walks `n` particles for `steps` steps on `mesh` and compares each step's memo deposit with
/// a fresh one; returns (particles reused, particle-steps).
fn walk(mesh: &PolyMesh, n: usize, steps: usize, seed: u64) -> (usize, usize) {
    let vm = VoidageMesh::new(mesh).unwrap();
    assert!(vm.axis_grid().is_none(), "a general mesh");
    let b = vm.geometry().bounds;
    let size = (b.max - b.min).amax();
    let h = (vm.geometry().total_volume() / vm.n_cells() as f64).cbrt();
    let mut rng = Rng::new(seed);
    // Nine in ten centres within half a cell of a cell centre, the others anywhere in the
    // bounding box enlarged by 5 % (outside the mesh or partly); radii 0.1–0.6 h.
    let centres = &vm.geometry().cell_centres;
    let mut pos: Vec<V3> = (0..n)
        .map(|i| {
            if i % 10 == 9 {
                rng.point(
                    V3::from_fn(|a, _| b.min[a] - 0.05 * size),
                    V3::from_fn(|a, _| b.max[a] + 0.05 * size),
                )
            } else {
                let c = V3::from(centres[(rng.next() % centres.len() as u64) as usize]);
                c + V3::from_fn(|_, _| 0.5 * h * rng.uniform(-1.0, 1.0))
            }
        })
        .collect();
    let mut rad: Vec<f64> = (0..n).map(|_| rng.uniform(0.1, 0.6) * h).collect();
    let mut memo = DividedMemo::new();
    let (mut hints_memo, mut hints_fresh) = (vec![None; n], vec![None; n]);
    let (mut with, mut fresh) = (empty_shares(), empty_shares());
    let (mut reused, mut total) = (0, 0);
    for step in 0..steps {
        // Step sizes from 1e-6 h to 0.3 h, different per particle and per step: every other
        // particle creeps (at most 1e-3 h per step, as in a packed bed).
        for (i, x) in pos.iter_mut().enumerate() {
            let top = if i % 2 == 0 { -3.0 } else { -0.5 };
            let size = h * 10f64.powf(rng.uniform(-6.0, top));
            *x += V3::from_fn(|_, _| size * rng.uniform(-1.0, 1.0));
        }
        if step % 7 == 3 {
            // Some radii change (the memo must not reuse across a new radius).
            for r in rad.iter_mut().step_by(5) {
                *r *= 1.0 + 1e-9;
            }
        }
        if step % 11 == 5 {
            // A new order that nobody tells the memo about: it may only lose reuse.
            pos.reverse();
            rad.reverse();
            hints_memo.reverse();
            hints_fresh.reverse();
        }
        let set = ParticleSet::new(&pos, &rad);
        let dep_memo = vm
            .shares_with_memo_into(Method::Divided, &set, &mut hints_memo, &mut memo, &mut with)
            .unwrap();
        let dep_fresh = vm
            .shares_with_cells_into(Method::Divided, &set, &mut hints_fresh, &mut fresh)
            .unwrap();
        assert_eq!(hints_memo, hints_fresh, "step {step}: centre cells");
        assert_eq!(with, fresh, "step {step}: shares");
        assert_eq!(dep_memo, dep_fresh, "step {step}: deposit");
        if step == 0 {
            assert_eq!(memo.reused(), 0);
        }
        reused += memo.reused();
        total += n;
    }
    (reused, total)
}

#[test]
fn memo_deposits_equal_fresh_ones_bit_for_bit() {
    let rotated = map_points(
        &uniform_box([0.0; 3], [1.0; 3], [6, 5, 4]),
        affine(rotation([1.0, 2.0, 3.0], 0.4), [0.0; 3]),
    );
    for (name, mesh) in [
        ("rotated box", rotated),
        ("skewed_blocks (warped faces)", fixture("skewed_blocks")),
        ("poly_dual (polyhedra)", fixture("poly_dual")),
    ] {
        let (reused, total) = walk(&mesh, 1500, 40, 3);
        eprintln!("{name}: {reused} of {total} particle-steps reused the memo");
        // The creeping half mostly stays within its clearance: the memo is exercised.
        assert!(reused * 4 > total, "{name}: {reused} of {total} reused");
    }
}

/// A particle that does not move reuses its entry every step, and one that jumps by more than
/// a cell never does; either way the deposit is the fresh one (checked in `walk`'s way).
#[test]
fn a_resting_particle_reuses_and_a_jumping_one_does_not() {
    let mesh = fixture("skewed_blocks");
    let vm = VoidageMesh::new(&mesh).unwrap();
    let g = vm.geometry();
    let h = (g.total_volume() / vm.n_cells() as f64).cbrt();
    let centres: Vec<V3> = g.cell_centres.iter().map(|c| V3::from(*c)).collect();
    let mut memo = DividedMemo::new();
    let mut shares = empty_shares();
    let pos = vec![centres[7]];
    let rad = vec![0.4 * h];
    let mut cells = vec![None];
    let mut deposit = |pos: &[V3], memo: &mut DividedMemo, shares: &mut CellShares| {
        vm.shares_with_memo_into(
            Method::Divided,
            &ParticleSet::new(pos, &rad),
            &mut cells,
            memo,
            shares,
        )
        .unwrap();
    };
    for step in 0..3 {
        deposit(&pos, &mut memo, &mut shares);
        assert_eq!(memo.reused(), usize::from(step > 0), "step {step}");
    }
    for (step, &c) in centres.iter().enumerate().skip(20).step_by(13) {
        let pos = vec![c];
        deposit(&pos, &mut memo, &mut shares);
        let (fresh, _) = vm
            .shares(Method::Divided, &ParticleSet::new(&pos, &rad))
            .unwrap();
        assert_eq!(memo.reused(), 0, "jump {step}");
        assert_eq!(shares, fresh, "jump {step}");
    }
}
