//! CFDEM's `trilinear` model against closed forms and hand-worked cases: cell centres, grid
//! nodes and face centres; trilinear weights computed here from the grid planes; CFDEM's choice
//! of the corner cell at the lower walls (every case, against the rule worked out by hand from
//! its search) and the clamp at the upper walls; volume accounting at the boundary; the meshes
//! it refuses; CFDEM's voidfractionTest tutorial check on a case of our own; and its ε against
//! the exact method for random packings.

mod common;

use approx::assert_abs_diff_eq;
use common::*;
use mesh::build::{affine, graded_planes, hex_grid, map_points, rotation, uniform_box};
use mesh::v3::V3;
use std::f64::consts::PI;
use voidage::*;

const T: Method = Method::Trilinear;

/// The solid volume per cell and the outside volume of one particle.
fn one(vm: &VoidageMesh, p: impl Into<V3>, r: f64) -> (Vec<f64>, f64) {
    let d = vm.deposit(T, &ParticleSet::new(&[p.into()], &[r])).unwrap();
    (d.solid, d.outside_volume)
}

/// The expected solid volume per cell of weights `w` at grid slots, times `v`.
fn expected(vm: &VoidageMesh, w: &[([usize; 3], f64)], v: f64) -> Vec<f64> {
    let g = vm.axis_grid().unwrap();
    let mut s = vec![0.0; vm.n_cells()];
    for &([i, j, k], x) in w {
        s[g.cell(i, j, k) as usize] += x * v;
    }
    s
}

/// The 8 trilinear pairs (slot, weight) from lower corner `base` and fractions `t`, written
/// out term by term.
fn corner_weights(base: [usize; 3], t: [f64; 3]) -> Vec<([usize; 3], f64)> {
    let [i, j, k] = base;
    let [x, y, z] = t;
    vec![
        ([i, j, k], (1.0 - x) * (1.0 - y) * (1.0 - z)),
        ([i + 1, j, k], x * (1.0 - y) * (1.0 - z)),
        ([i, j + 1, k], (1.0 - x) * y * (1.0 - z)),
        ([i + 1, j + 1, k], x * y * (1.0 - z)),
        ([i, j, k + 1], (1.0 - x) * (1.0 - y) * z),
        ([i + 1, j, k + 1], x * (1.0 - y) * z),
        ([i, j + 1, k + 1], (1.0 - x) * y * z),
        ([i + 1, j + 1, k + 1], x * y * z),
    ]
    .into_iter()
    .filter(|e| e.1 != 0.0)
    .collect()
}

fn assert_cells(got: &[f64], want: &[f64], tol: f64, what: &str) {
    for (c, (a, b)) in got.iter().zip(want).enumerate() {
        assert!((a - b).abs() <= tol, "{what}: cell {c}: {a} vs {b}");
    }
}

/// A non-cubic uniform grid: h = (0.25, 0.4, 0.5) on [0, 1] × [0, 2] × [0, 1.5].
fn box_grid() -> VoidageMesh {
    VoidageMesh::new(&uniform_box([0.0; 3], [1.0, 2.0, 1.5], [4, 5, 3])).unwrap()
}

#[test]
fn a_particle_at_a_cell_centre_stays_in_that_cell() {
    let vm = box_grid();
    let r = 0.1;
    let v = ball_volume(r);
    for cell in 0..vm.n_cells() {
        let c = vm.geometry().cell_centres[cell];
        let (s, out) = one(&vm, c, r);
        assert!(out.abs() <= 1e-15 * v);
        assert_abs_diff_eq!(s[cell], v, epsilon = 1e-15 * v);
        assert!(s
            .iter()
            .enumerate()
            .all(|(k, &x)| k == cell || x.abs() <= 1e-15 * v));
    }
}

#[test]
fn grid_nodes_give_an_eighth_and_face_centres_a_half() {
    let vm = box_grid();
    let g = vm.axis_grid().unwrap().clone();
    let (r, v) = (0.3, ball_volume(0.3));
    let [nx, ny, nz] = g.dims();
    let pl = |a: usize, i: usize| g.planes(a)[i];
    let mid = |a: usize, i: usize| 0.5 * (pl(a, i) + pl(a, i + 1));
    // Interior nodes: 1/8 to each of the 8 cells around them.
    for k in 1..nz {
        for j in 1..ny {
            for i in 1..nx {
                let (s, out) = one(&vm, [pl(0, i), pl(1, j), pl(2, k)], r);
                let w = corner_weights([i - 1, j - 1, k - 1], [0.5; 3]);
                assert!(w.iter().all(|e| e.1 == 0.125));
                assert_cells(&s, &expected(&vm, &w, v), 1e-15 * v, "node");
                assert!(out.abs() <= 1e-15 * v);
            }
        }
    }
    // Interior faces normal to x: 1/2 to each side. (y and z are those of the cell's own
    // centre: a rounding below it would count as "below the centre" at the lower walls.)
    for k in 0..nz {
        for j in 0..ny {
            for i in 1..nx {
                let c = vm.geometry().cell_centres[g.cell(i, j, k) as usize];
                let (s, _) = one(&vm, [pl(0, i), c[1], c[2]], r);
                let w = [([i - 1, j, k], 0.5), ([i, j, k], 0.5)];
                assert_cells(&s, &expected(&vm, &w, v), 1e-15 * v, "x face");
            }
        }
    }
    // A face normal to z, away from the walls.
    let (s, _) = one(&vm, [mid(0, 2), mid(1, 3), pl(2, 1)], r);
    let w = [([2, 3, 0], 0.5), ([2, 3, 1], 0.5)];
    assert_cells(&s, &expected(&vm, &w, v), 1e-15 * v, "z face");
}

/// Shares at random points between the first and last cell centres equal trilinear weights
/// computed from the plane positions (s = (p − x₀)/h − ½, i = ⌊s⌋, t = s − i); they sum to the
/// particle volume, and do not depend on the radius.
#[test]
fn shares_are_trilinear_in_the_position() {
    let vm = box_grid();
    let h = [0.25, 0.4, 0.5];
    let mut rng = Rng::new(31);
    for _ in 0..200 {
        let p = rng.point([0.125, 0.2, 0.25], [0.875, 1.8, 1.25]);
        let r = rng.uniform(0.01, 1.0);
        let v = ball_volume(r);
        let mut base = [0usize; 3];
        let mut t = [0.0; 3];
        for a in 0..3 {
            let s = p[a] / h[a] - 0.5;
            base[a] = s.floor() as usize;
            t[a] = s - s.floor();
        }
        let (s, out) = one(&vm, p, r);
        assert_cells(
            &s,
            &expected(&vm, &corner_weights(base, t), v),
            1e-13 * v,
            "random",
        );
        let total: f64 = s.iter().sum();
        assert_abs_diff_eq!(total, v, epsilon = 1e-14 * v);
        assert!(out.abs() <= 1e-14 * v);
    }
    // The kernel's weights sum to 1 and are the products.
    for _ in 0..100 {
        let t = [rng.unit(), rng.unit(), rng.unit()];
        let w = trilinear_weights(t);
        assert_abs_diff_eq!(w.iter().sum::<f64>(), 1.0, epsilon = 1e-15);
        assert_abs_diff_eq!(w[5], t[0] * (1.0 - t[1]) * t[2], epsilon = 1e-16);
    }
    // Linear in each coordinate inside one lattice box: along a segment parallel to an axis
    // the midpoint's shares are the mean of the ends'.
    let a = V3::new(0.4, 0.7, 0.3);
    for (axis, b) in [(0, 0.6), (1, 0.95), (2, 0.7)] {
        let mut end = a;
        end[axis] = b;
        let (sa, _) = one(&vm, a, 0.2);
        let (sb, _) = one(&vm, end, 0.2);
        let (sm, _) = one(&vm, (a + end) * 0.5, 0.2);
        let mean: Vec<f64> = sa.iter().zip(&sb).map(|(x, y)| 0.5 * (x + y)).collect();
        assert_cells(&sm, &mean, 1e-16, "midpoint");
    }
}

/// CFDEM's search for the corner cell (`cfdem_lower_corner`, written as its filters), against
/// the rule worked out by hand from it, for every sign pattern and every set of missing lower
/// neighbours: with B_a = "negative offset along a and no cell below", none blocked → the
/// corner below along every negative axis; x blocked → the cell itself; y blocked → the cell
/// below along x (if negative) when z has no cell below, else the cell itself; z blocked → the
/// cells below along x and y only.
#[test]
fn cfdem_corner_search_matches_the_worked_out_rule() {
    for signs in 0..8 {
        for lower in 0..8 {
            let neg: [bool; 3] = std::array::from_fn(|a| (signs >> a) & 1 == 1);
            let has_lower: [bool; 3] = std::array::from_fn(|a| (lower >> a) & 1 == 1);
            let offset = neg.map(|n| if n { -0.1 } else { 0.1 });
            let blocked: [bool; 3] = std::array::from_fn(|a| neg[a] && !has_lower[a]);
            let want = if !neg.iter().any(|&n| n) || blocked[0] {
                [false; 3]
            } else if blocked[1] {
                if has_lower[2] {
                    [false; 3]
                } else {
                    [neg[0], false, false]
                }
            } else if blocked[2] {
                [neg[0], neg[1], false]
            } else {
                neg
            };
            assert_eq!(
                cfdem_lower_corner(offset, has_lower),
                want,
                "offset {offset:?}, lower neighbours {has_lower:?}"
            );
        }
    }
    // OpenFOAM's SMALL: an offset of −1e-16 m counts as "at or above" in the first test only.
    assert_eq!(
        cfdem_lower_corner([-1e-16, 0.1, 0.1], [true; 3]),
        [false; 3]
    );
    assert_eq!(
        cfdem_lower_corner([-1e-16, -0.1, 0.1], [true; 3]),
        [true, true, false]
    );
}

/// Boundary cases on a 4³ grid of the unit cube (h = 0.25, centres 0.125 + 0.25 i), each
/// worked out by hand from CFDEM's search: mirrored shares at the lower walls, clamped at the
/// upper walls, and a jump where the search changes.
#[test]
fn lower_walls_mirror_upper_walls_clamp() {
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [4, 4, 4])).unwrap();
    let (r, v) = (0.05, ball_volume(0.05));
    let c = |i: usize| 0.125 + 0.25 * i as f64;
    let t = [0.2, 0.3, 0.1];
    let d = [0.05, 0.075, 0.025]; // t · h
                                  // (what, particle centre, lower corner cell, fractions t)
    type Case = (&'static str, [f64; 3], [usize; 3], [f64; 3]);
    let cases: [Case; 6] = [
        // In cell (0, 1, 2) below the x centre: x mirrored (0.2 to layer i = 1).
        (
            "x below the first centre",
            [c(0) - d[0], c(1) + d[1], c(2) + d[2]],
            [0, 1, 2],
            t,
        ),
        // Also below the y centre, where a cell below exists: y mirrored too (to j = 2).
        (
            "x blocked mirrors y",
            [c(0) - d[0], c(1) - d[1], c(2) + d[2]],
            [0, 1, 2],
            t,
        ),
        // In cell (3, 1, 2) above the last x centre: t_x = 0, nothing beyond the mesh.
        (
            "x above the last centre",
            [c(3) + d[0], c(1) + d[1], c(2) + d[2]],
            [3, 1, 2],
            [0.0, 0.3, 0.1],
        ),
        // In cell (2, 0, 2) below every centre; y blocked and z has a cell below: all three
        // mirrored from the cell itself.
        (
            "y blocked",
            [c(2) - d[0], c(0) - d[1], c(2) - d[2]],
            [2, 0, 2],
            t,
        ),
        // In cell (2, 2, 0) below every centre; z blocked: x, y proper, z mirrored.
        (
            "z blocked",
            [c(2) - d[0], c(2) - d[1], c(0) - d[2]],
            [1, 1, 0],
            [0.8, 0.7, 0.1],
        ),
        // Interior, below every centre: the proper corner.
        (
            "interior",
            [c(2) - d[0], c(2) - d[1], c(2) - d[2]],
            [1, 1, 1],
            [0.8, 0.7, 0.9],
        ),
    ];
    for (what, p, base, t) in cases {
        let (s, out) = one(&vm, p, r);
        assert_cells(
            &s,
            &expected(&vm, &corner_weights(base, t), v),
            1e-14 * v,
            what,
        );
        assert!(out.abs() <= 1e-15 * v, "{what}");
    }
    // The jump: in cell (0, 1, 2) with p_y below its centre, p_x crossing the x centre moves the
    // y share 0.3 from layer j = 2 (mirrored) to layer j = 0 (proper corner).
    let layer = |s: &[f64], j: usize| -> f64 {
        let g = vm.axis_grid().unwrap();
        (0..vm.n_cells())
            .filter(|&cell| g.ijk(cell as u32)[1] == j)
            .map(|cell| s[cell])
            .sum::<f64>()
            / v
    };
    let (below, _) = one(&vm, [c(0) - 1e-9, c(1) - d[1], c(2) + d[2]], r);
    let (above, _) = one(&vm, [c(0) + 1e-9, c(1) - d[1], c(2) + d[2]], r);
    assert_abs_diff_eq!(layer(&below, 2), 0.3, epsilon = 1e-12);
    assert_abs_diff_eq!(layer(&below, 0), 0.0, epsilon = 1e-12);
    assert_abs_diff_eq!(layer(&above, 0), 0.3, epsilon = 1e-12);
    assert_abs_diff_eq!(layer(&above, 2), 0.0, epsilon = 1e-12);
}

/// Away from the lower walls the shares are continuous: across faces and centre planes.
#[test]
fn continuous_inside_the_grid() {
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [4, 4, 4])).unwrap();
    let (r, v) = (0.4, ball_volume(0.4));
    let mut rng = Rng::new(32);
    for x in [0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 0.95] {
        for _ in 0..10 {
            let (y, z) = (rng.uniform(0.13, 0.99), rng.uniform(0.13, 0.99));
            let (a, _) = one(&vm, [x - 1e-10, y, z], r);
            let (b, _) = one(&vm, [x + 1e-10, y, z], r);
            let jump = a
                .iter()
                .zip(&b)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(jump < 1e-8 * v, "x = {x}: {jump:e}");
        }
    }
}

/// Every particle whose centre is in the mesh has all its volume in cells, also when its ball
/// reaches beyond the walls; the others have all of theirs outside. Checked per particle
/// against the particles' own positions.
#[test]
fn volume_accounting_at_the_boundary() {
    let (lo, hi) = ([0.0, -1.0, 2.0], [3.0, 1.0, 4.5]);
    let vm = VoidageMesh::new(&uniform_box(lo, hi, [6, 4, 5])).unwrap();
    let mut rng = Rng::new(33);
    let n = 2000;
    let pos: Vec<V3> = (0..n)
        .map(|_| rng.point([-0.5, -1.5, 1.5], [3.5, 1.5, 5.0]))
        .collect();
    let rad: Vec<f64> = (0..n).map(|_| rng.uniform(0.05, 0.8)).collect();
    let (sh, dep) = vm.shares(T, &ParticleSet::new(&pos, &rad)).unwrap();
    let inside = |p: V3| (0..3).all(|a| p[a] >= lo[a] && p[a] < hi[a]);
    let mut outside = 0.0;
    let mut n_out = 0;
    for i in 0..n {
        let v = ball_volume(rad[i]);
        let (cells, vols) = sh.of(i);
        assert!(cells.len() <= 8);
        assert!(vols.iter().all(|&x| x > 0.0));
        if inside(pos[i]) {
            assert_abs_diff_eq!(sh.inside_volume(i), v, epsilon = 1e-14 * v);
        } else {
            assert!(cells.is_empty());
            outside += v;
            n_out += 1;
        }
    }
    assert!(n_out > 100 && n_out < n);
    assert!(dep.conservation_error() < 1e-12);
    assert_abs_diff_eq!(
        dep.outside_volume,
        outside,
        epsilon = 1e-12 * dep.particle_volume
    );
    assert_eq!(dep.particles_outside, n_out);
    assert_eq!(dep.particles_partly_outside, 0);
}

/// Meshes that are not grids of equal axis-aligned cells are refused, naming the requirement;
/// a grid written with 6 significant digits, non-cubic cells and the general-mesh option are
/// accepted.
#[test]
fn meshes_it_refuses_and_accepts() {
    let refused = |m: &foam::PolyMesh, what: &str| {
        let vm = VoidageMesh::new(m).unwrap();
        let pos = [V3::repeat(0.5)];
        let e = vm.deposit(T, &ParticleSet::new(&pos, &[0.1])).unwrap_err();
        assert!(matches!(e, VoidageError::UnsupportedMesh { .. }), "{e}");
        let msg = e.to_string();
        assert!(
            msg.contains("trilinear")
                && msg.contains("equal axis-aligned box cells")
                && msg.contains(what),
            "{msg}"
        );
        assert_eq!(vm.check_method(T).unwrap_err(), e);
        assert!(vm.check_method(Method::Exact).is_ok());
    };
    let even = graded_planes(0.0, 1.0, 5, 1.0);
    refused(
        &hex_grid(&even, &graded_planes(0.0, 1.0, 5, 1.1), &even),
        "along y vary",
    );
    let rotated = map_points(
        &uniform_box([0.0; 3], [1.0; 3], [3, 3, 3]),
        affine(rotation([0.0, 0.0, 1.0], 0.1), [0.0; 3]),
    );
    refused(&rotated, "not an axis-aligned structured hex grid");
    // blockMesh coordinates written with 6 digits (`writePrecision 6`): planes off by ≤ 5e-7.
    let m = map_points(&uniform_box([0.0; 3], [1.0; 3], [30, 7, 3]), |p| {
        p.map(|x| format!("{x:.5e}").parse().unwrap())
    });
    let six = VoidageMesh::new(&m).unwrap();
    assert!(six.check_method(T).is_ok());
    // The general-mesh option changes nothing: trilinear always works on the grid.
    let m = uniform_box([0.0; 3], [1.0, 2.0, 1.5], [4, 5, 3]);
    let general = VoidageMesh::with_options(
        &m,
        MeshOptions {
            axis_aligned_fast_path: false,
        },
    )
    .unwrap();
    let mut rng = Rng::new(34);
    let pos: Vec<V3> = (0..300)
        .map(|_| rng.point([-0.1; 3], [1.1, 2.1, 1.6]))
        .collect();
    let rad = vec![0.1; pos.len()];
    let a = box_grid()
        .deposit(T, &ParticleSet::new(&pos, &rad))
        .unwrap();
    let b = general.deposit(T, &ParticleSet::new(&pos, &rad)).unwrap();
    assert_eq!(a, b);
}

/// Random sequential addition of non-overlapping balls of radius `r` with centres in
/// [lo, hi]: up to `n` balls, `tries` attempts.
fn packing(rng: &mut Rng, n: usize, r: f64, lo: [f64; 3], hi: [f64; 3], tries: usize) -> Vec<V3> {
    let cell = 2.0 * r;
    let dims: [usize; 3] = std::array::from_fn(|a| ((hi[a] - lo[a]) / cell).ceil() as usize + 1);
    let mut bins: Vec<Vec<usize>> = vec![vec![]; dims.iter().product()];
    let bin = |p: V3| -> [usize; 3] { std::array::from_fn(|a| ((p[a] - lo[a]) / cell) as usize) };
    let mut pos: Vec<V3> = Vec::with_capacity(n);
    for _ in 0..tries {
        if pos.len() == n {
            break;
        }
        let p = rng.point(lo, hi);
        let b = bin(p);
        let mut free = true;
        'near: for k in b[2].saturating_sub(1)..=(b[2] + 1).min(dims[2] - 1) {
            for j in b[1].saturating_sub(1)..=(b[1] + 1).min(dims[1] - 1) {
                for i in b[0].saturating_sub(1)..=(b[0] + 1).min(dims[0] - 1) {
                    for &q in &bins[i + dims[0] * (j + dims[1] * k)] {
                        if (pos[q] - p).norm() < 2.0 * r {
                            free = false;
                            break 'near;
                        }
                    }
                }
            }
        }
        if free {
            bins[b[0] + dims[0] * (b[1] + dims[1] * b[2])].push(pos.len());
            pos.push(p);
        }
    }
    pos
}

/// CFDEM's `tutorials/cfdemSolverPiso/voidfractionTest`, its constructs on a case of our own.
///
/// The tutorial: cubic cells h = 0.01 m (10 × 10 × 100 on 0.1 × 0.1 × 1 m), 1000 spheres of
/// d = 3 mm inserted in the upper half (z > 0.53 m) moving down at 0.3 m/s, solveFlow off,
/// `voidFractionModel trilinear`, coupling every 1 ms. Its octave script plots
/// (1) `particleCellVolume`: Σ (1 − ε) V over the cells with ε > 0, as a percentage of the
/// particles' volume — expected 100 %; (2) `volWeightedAverage` of ddt(ε) (Euler, over one
/// coupling interval) over the cells where it is > 0, each weighted by V·ε, divided by their
/// Σ V — against the "analytic" Vp·(vp Δt/dp) / (8 h³ Δt) = 0.1767 1/s (one particle's volume
/// moving over a diameter within a kernel of 8 cells).
///
/// Here: 0.08 × 0.08 × 0.5 m in cells of 0.01 m (8 × 8 × 50, `mesh::build`), 340 spheres of
/// d = 3 mm by random sequential addition in z > 0.25 m (the tutorial's number density), all
/// moving by −vp Δt = −0.3 mm in z. For trilinear the exact value of (2) for one isolated
/// particle is Vp vp/(4 h⁴) weighted by ε (its z shares move at vp/h from the 4 cells above
/// to the 4 below), i.e. 2 dp / h = 0.6 times the octave's estimate.
#[test]
fn voidfraction_tutorial_check() {
    let (h, n) = (0.01, [8, 8, 50]);
    let hi = [0.08, 0.08, 0.5];
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], hi, n)).unwrap();
    let vols = vm.cell_volumes().to_vec();
    let (dp, vp, dt) = (0.003, 0.3, 0.001);
    let r = 0.5 * dp;
    let v_p = PI / 6.0 * dp * dp * dp;
    let octave = v_p * (dt * vp) / dp / (8.0 * h * h * h * dt);
    assert_abs_diff_eq!(octave, 0.17671458676442586, epsilon = 1e-12);
    // ε of positions `pos` with trilinear.
    let eps = |pos: &[V3]| -> Vec<f64> {
        let rad = vec![r; pos.len()];
        let d = vm.deposit(T, &ParticleSet::new(pos, &rad)).unwrap();
        vm.voidage(&d, None).unwrap().epsilon
    };
    let particle_cell_volume = |e: &[f64]| -> f64 {
        e.iter()
            .zip(&vols)
            .filter(|(&x, _)| x > 0.0 && x < 1e20)
            .map(|(&x, &v)| (1.0 - x) * v)
            .sum()
    };
    let vol_weighted_ddt = |old: &[f64], new: &[f64]| -> (f64, usize) {
        let (mut num, mut den, mut cells) = (0.0, 0.0, 0);
        for c in 0..vols.len() {
            let ddt = (new[c] - old[c]) / dt;
            if ddt > 0.0 && ddt < 1e20 {
                num += ddt * vols[c] * new[c];
                den += vols[c];
                cells += 1;
            }
        }
        (num / den, cells)
    };
    let step =
        |pos: &[V3]| -> Vec<V3> { pos.iter().map(|p| p - V3::new(0.0, 0.0, vp * dt)).collect() };

    // The packing.
    let mut rng = Rng::new(35);
    let pos = packing(
        &mut rng,
        340,
        r,
        [r, r, 0.25],
        [hi[0] - r, hi[1] - r, hi[2] - r],
        1_000_000,
    );
    assert_eq!(pos.len(), 340);
    let total = pos.len() as f64 * v_p;
    let (e0, e1) = (eps(&pos), eps(&step(&pos)));
    for e in [&e0, &e1] {
        let pct = 100.0 * particle_cell_volume(e) / total;
        assert_abs_diff_eq!(pct, 100.0, epsilon = 1e-10);
    }
    // Σ ddt(ε) V = 0: volume moves between cells, none appears or vanishes.
    let net: f64 = (0..vols.len())
        .map(|c| (e1[c] - e0[c]) / dt * vols[c])
        .sum();
    assert!(net.abs() < 1e-9 * total * vp / h, "{net:e}");
    let (packed, cells) = vol_weighted_ddt(&e0, &e1);
    // Every cell losing volume loses at most what the particles around it move: ≤ N Vp vp/h
    // over all of them.
    assert!(packed > 0.0 && packed * cells as f64 * h.powi(3) <= total * vp / h * (1.0 + 1e-9));

    // Isolated particles (kernels 3 cells apart, off the centre planes): the closed form.
    let lone: Vec<V3> = (0..2)
        .flat_map(|i| (0..2).map(move |j| (i, j)))
        .map(|(i, j)| V3::new(0.0137 + 0.04 * i as f64, 0.0219 + 0.04 * j as f64, 0.3333))
        .collect();
    let (l0, l1) = (eps(&lone), eps(&step(&lone)));
    let (isolated, lone_cells) = vol_weighted_ddt(&l0, &l1);
    assert_eq!(lone_cells, 4 * lone.len());
    // Σ over the 4 cells above of (Vp vp/h · w_xy / h³) · h³ · ε, over 4 h³ per particle.
    let mut closed = 0.0;
    for p in &lone {
        let tx = (p[0] / h - 0.5).fract();
        let ty = (p[1] / h - 0.5).fract();
        let tz = (p[2] / h - 0.5).fract();
        let zi = (p[2] / h - 0.5).floor() as usize + 1; // the layer above, being left
        let (i0, j0) = ((p[0] / h - 0.5).floor(), (p[1] / h - 0.5).floor());
        let g = vm.axis_grid().unwrap();
        for (di, wx) in [(0, 1.0 - tx), (1, tx)] {
            for (dj, wy) in [(0, 1.0 - ty), (1, ty)] {
                let cell = g.cell(i0 as usize + di, j0 as usize + dj, zi) as usize;
                let w_new = wx * wy * (tz - vp * dt / h);
                let e_new = 1.0 - v_p * w_new / (h * h * h);
                closed += v_p * vp / h * wx * wy * e_new;
                assert_abs_diff_eq!(l1[cell], e_new, epsilon = 1e-12);
            }
        }
    }
    closed /= 4.0 * lone.len() as f64 * h.powi(3);
    assert_abs_diff_eq!(isolated, closed, epsilon = 1e-9 * closed);
    let ideal = v_p * vp / (4.0 * h.powi(4));
    assert!((isolated / ideal - 1.0).abs() < 1e-2);
    println!(
        "voidfractionTest: particle volume in cells 100 % (CFDEM: 100 %); \
         avg ddt(ε) over cells with ddt > 0: packing {packed:.4} 1/s over {cells} cells, \
         isolated particles {isolated:.4} 1/s (Vp vp/(4h⁴) = {ideal:.4}); \
         octave's analytic {octave:.4} 1/s"
    );
}

/// Trilinear ε against exact ε for random packings at the tutorial's d/h = 0.3 and at
/// d/h = 1 and 2: both put all of the volume into cells (balls inside the mesh), so
/// Σ (ε_tri − ε_exact) V = 0; per cell, |ε_tri − ε_exact| V is at most the volume of the
/// particles that can reach the cell by either method (centre within max(1.5 h, h/2 + r) of
/// the cell centre along every axis). The spread is printed.
#[test]
fn trilinear_against_exact_for_random_packings() {
    let h = 1.0;
    let n = [8, 8, 8];
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [8.0; 3], n)).unwrap();
    let vols = vm.cell_volumes().to_vec();
    let centres = vm.geometry().cell_centres.clone();
    let mut rng = Rng::new(36);
    for (d_over_h, target) in [(0.3, 0.3), (1.0, 0.3), (2.0, 0.25)] {
        let r = 0.5 * d_over_h * h;
        let v = ball_volume(r);
        let want = (target * 512.0 / v) as usize;
        let pos = packing(&mut rng, want, r, [r; 3], [8.0 - r; 3], 400_000);
        let rad = vec![r; pos.len()];
        let set = ParticleSet::new(&pos, &rad);
        let tri = vm.voidage(&vm.deposit(T, &set).unwrap(), None).unwrap();
        let ex = vm
            .voidage(&vm.deposit(Method::Exact, &set).unwrap(), None)
            .unwrap();
        let solid = pos.len() as f64 * v;
        let net: f64 = (0..vols.len())
            .map(|c| (tri.epsilon[c] - ex.epsilon[c]) * vols[c])
            .sum();
        assert!(net.abs() < 1e-12 * solid, "{net:e}");
        let reach = (1.5 * h).max(0.5 * h + r);
        let (mut max, mut sq) = (0.0f64, 0.0);
        for c in 0..vols.len() {
            let diff = tri.epsilon[c] - ex.epsilon[c];
            max = max.max(diff.abs());
            sq += diff * diff;
            let near = pos
                .iter()
                .filter(|p| (0..3).all(|a| (p[a] - centres[c][a]).abs() < reach))
                .count() as f64;
            assert!(diff.abs() * vols[c] <= near * v * (1.0 + 1e-12), "cell {c}");
        }
        let rms = (sq / vols.len() as f64).sqrt();
        let phi = solid / 512.0;
        println!(
            "d/h = {d_over_h}: {} particles, solid fraction {phi:.3}: |ε_tri − ε_exact| \
             max {max:.4}, rms {rms:.4}; min ε trilinear {:.4}, exact {:.4}",
            pos.len(),
            tri.min_epsilon,
            ex.min_epsilon
        );
    }
}
