//! The kernels against independent references: closed-form caps and symmetric pieces, 1-D
//! quadrature of exact cross-section areas, Monte Carlo with binomial error bars, the two exact
//! formulas against each other (corner form for boxes, face-flux form for polyhedra), and the
//! numbers printed in Khawaja et al. (2012).

mod common;

use approx::assert_abs_diff_eq;
use approx::assert_relative_eq;
use common::*;
use mesh::v3::V3;
use std::f64::consts::PI;
use voidage::*;

const V1: f64 = 4.0 / 3.0 * PI;

#[test]
fn cap_half_quarter_octant() {
    let r = 1.3;
    let c = [0.2, -0.4, 0.7];
    let v = ball_volume(r);
    let big = 10.0;
    // Caps of every height, cut by a plane normal to each axis, from both sides.
    for a in 0..3 {
        for k in 0..=20 {
            let h = 2.0 * r * k as f64 / 20.0;
            let mut lo = [c[0] - big, c[1] - big, c[2] - big];
            let mut hi = [c[0] + big, c[1] + big, c[2] + big];
            lo[a] = c[a] + r - h;
            let cap = cap_volume(r, h);
            assert!(
                approx::relative_eq!(
                    sphere_box_volume(c, r, lo, hi),
                    cap,
                    epsilon = 1e-14 * v,
                    max_relative = 1e-14
                ),
                "cap h={h}"
            );
            hi[a] = c[a] - r + h;
            lo[a] = c[a] - big;
            assert_relative_eq!(
                sphere_box_volume(c, r, lo, hi),
                cap,
                epsilon = 1e-14 * v,
                max_relative = 1e-14
            );
        }
    }
    // Half, quarter, octant through the centre.
    let half = sphere_box_volume(c, r, [c[0], -big, -big], [big; 3]);
    let quarter = sphere_box_volume(c, r, [c[0], c[1], -big], [big; 3]);
    let octant = sphere_box_volume(c, r, c, [big; 3]);
    assert_relative_eq!(half, v / 2.0, epsilon = 1e-15 * v, max_relative = 1e-15);
    assert_relative_eq!(quarter, v / 4.0, epsilon = 1e-15 * v, max_relative = 1e-15);
    assert_relative_eq!(octant, v / 8.0, epsilon = 1e-15 * v, max_relative = 1e-15);
    assert_relative_eq!(
        corner_volume(r, 0.0, 0.0, 0.0),
        v / 8.0,
        epsilon = 1e-15 * v,
        max_relative = 1e-15
    );
    // Quarter cap G(0, 0, c) = π(R − c)²(2R + c)/12, every argument position and sign.
    for t in [-0.9, -0.3, 0.0, 0.4, 1.1] {
        let q = PI * (r - t) * (r - t) * (2.0 * r + t) / 12.0;
        for (a, b, cc) in [(t, 0.0, 0.0), (0.0, t, 0.0), (0.0, 0.0, t)] {
            assert!(
                approx::relative_eq!(
                    corner_volume(r, a, b, cc),
                    q,
                    epsilon = 1e-14 * v,
                    max_relative = 1e-14
                ),
                "t={t}"
            );
        }
    }
    // Whole ball and beyond.
    assert_eq!(corner_volume(r, -r, -r, -r), v);
    assert_relative_eq!(
        corner_volume(r, -2.0 * r, -5.0, -r),
        v,
        epsilon = 1e-15 * v,
        max_relative = 1e-15
    );
    assert_eq!(corner_volume(r, r, 0.0, 0.0), 0.0);
    assert_eq!(corner_volume(r, 0.8, 0.8, 0.8), 0.0);
}

#[test]
fn corner_values_match_quadrature_of_exact_cross_sections() {
    let nodes = gauss_legendre(48);
    let mut rng = Rng::new(7);
    let mut worst = 0.0f64;
    for _ in 0..300 {
        let lo: V3 = V3::from_fn(|_, _| rng.uniform(-1.2, 1.0));
        let hi: V3 = V3::from_fn(|a, _| lo[a] + rng.uniform(0.01, 1.5));
        let reference = ball_box_by_quadrature(1.0, lo, hi, &nodes);
        let exact = sphere_box_volume([0.0; 3], 1.0, lo, hi);
        worst = worst.max((exact - reference).abs());
    }
    // Absolute, in units of the unit ball's volume.
    assert!(worst / V1 < 1e-12, "worst {worst:e}");
}

#[test]
fn sphere_box_matches_monte_carlo() {
    let mut rng = Rng::new(11);
    let n = 200_000;
    for _ in 0..20 {
        let (c, r, lo, hi) =
            random_case(&mut rng, [-0.5, 0.5], [0.2, 0.9], [-0.8, 0.3], [0.1, 1.0]);
        let exact = sphere_box_volume(c, r, lo, hi);
        let (mc, se) = monte_carlo(&mut rng, lo, hi, n, |p| {
            (0..3).map(|a| (p[a] - c[a]).powi(2)).sum::<f64>() < r * r
        });
        assert!(
            approx::abs_diff_eq!(exact, mc, epsilon = 4.5 * se),
            "exact {exact} mc {mc} ± {se}"
        );
    }
}

#[test]
fn box_kernel_matches_face_flux_kernel() {
    // Two independent exact formulas: corner values G vs the divergence theorem over the 12
    // boundary triangles of the box.
    let mut rng = Rng::new(3);
    let mut worst = 0.0f64;
    for _ in 0..2000 {
        let (c, r, lo, hi) =
            random_case(&mut rng, [-1.0, 1.0], [0.05, 2.0], [-1.5, 1.0], [0.01, 2.0]);
        let a = sphere_box_volume(c, r, lo, hi);
        let b = sphere_polyhedron_volume(c, r, &box_triangles(lo, hi));
        worst = worst.max((a - b).abs() / ball_volume(r));
    }
    assert!(worst < 1e-13, "worst {worst:e}");
}

/// A random ball (centre coordinates in `c`, radius in `r`) and box (lower corner coordinates
/// in `lo`, edge lengths in `size`).
fn random_case(
    rng: &mut Rng,
    c: [f64; 2],
    r: [f64; 2],
    lo: [f64; 2],
    size: [f64; 2],
) -> (V3, f64, V3, V3) {
    let centre = V3::from_fn(|_, _| rng.uniform(c[0], c[1]));
    let radius = rng.uniform(r[0], r[1]);
    let l: V3 = V3::from_fn(|_, _| rng.uniform(lo[0], lo[1]));
    let h = V3::from_fn(|a, _| l[a] + rng.uniform(size[0], size[1]));
    (centre, radius, l, h)
}

/// The 12 outward triangles of a box.
fn box_triangles(lo: V3, hi: V3) -> Vec<[V3; 3]> {
    let p = |i: usize, j: usize, k: usize| {
        V3::new(
            if i == 0 { lo[0] } else { hi[0] },
            if j == 0 { lo[1] } else { hi[1] },
            if k == 0 { lo[2] } else { hi[2] },
        )
    };
    let quads = [
        [p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0)],
        [p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)],
        [p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0)],
        [p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)],
        [p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)],
        [p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)],
    ];
    quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect()
}

/// The 6 tets (Kuhn subdivision along the main diagonal) of a box, positively oriented.
fn box_tets(lo: V3, hi: V3) -> Vec<[V3; 4]> {
    let p = |b: usize| {
        V3::new(
            if b & 1 == 0 { lo[0] } else { hi[0] },
            if b & 2 == 0 { lo[1] } else { hi[1] },
            if b & 4 == 0 { lo[2] } else { hi[2] },
        )
    };
    let mut tets = vec![];
    for perm in [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ] {
        let mut b = 0;
        let mut v = [p(0); 4];
        for (k, &axis) in perm.iter().enumerate() {
            b |= 1 << axis;
            v[k + 1] = p(b);
        }
        if mesh::tet_volume(&v) < 0.0 {
            v.swap(2, 3);
        }
        tets.push(v);
    }
    tets
}

#[test]
fn tets_of_a_box_sum_to_the_box_kernel() {
    let mut rng = Rng::new(5);
    for _ in 0..500 {
        let (c, r, lo, hi) =
            random_case(&mut rng, [-1.0, 1.0], [0.1, 1.5], [-1.5, 1.0], [0.05, 2.0]);
        let tets = box_tets(lo, hi);
        let vol: f64 = tets.iter().map(mesh::tet_volume).sum();
        let bv: f64 = (0..3).map(|a| hi[a] - lo[a]).product();
        assert_relative_eq!(vol, bv, epsilon = 1e-14 * bv, max_relative = 1e-14);
        let sum: f64 = tets.iter().map(|t| sphere_tet_volume(c, r, t)).sum();
        let reference = sphere_box_volume(c, r, lo, hi);
        assert!(
            approx::abs_diff_eq!(sum, reference, epsilon = 1e-13 * ball_volume(r)),
            "{sum} vs {reference}"
        );
    }
}

#[test]
fn sphere_tet_matches_monte_carlo() {
    let mut rng = Rng::new(99);
    let n = 200_000;
    for _ in 0..15 {
        let t = random_tet(&mut rng);
        let c = rng.point([-0.5; 3], [0.5; 3]);
        let r = rng.uniform(0.3, 1.0);
        let exact = sphere_tet_volume(c, r, &t);
        // Sample the tet's bounding box, count points in both tet and ball.
        let lo = V3::from_fn(|a, _| t.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min));
        let hi = V3::from_fn(|a, _| t.iter().map(|p| p[a]).fold(f64::NEG_INFINITY, f64::max));
        let (mc, se) = monte_carlo(&mut rng, lo, hi, n, |p| {
            in_tet(&t, p) && (0..3).map(|a| (p[a] - c[a]).powi(2)).sum::<f64>() < r * r
        });
        assert!(
            approx::abs_diff_eq!(exact, mc, epsilon = 4.5 * se),
            "exact {exact} mc {mc} ± {se}"
        );
    }
}

/// A random positively oriented tet in [−1, 1]³.
fn random_tet(rng: &mut Rng) -> [V3; 4] {
    let mut t: [V3; 4] = std::array::from_fn(|_| rng.point([-1.0; 3], [1.0; 3]));
    if mesh::tet_volume(&t) < 0.0 {
        t.swap(1, 2);
    }
    t
}

fn in_tet(t: &[V3; 4], p: V3) -> bool {
    TET_FACES.iter().enumerate().all(|(opp, f)| {
        let mut q = *t;
        q[opp] = p;
        let _ = f;
        mesh::tet_volume(&q) >= 0.0
    })
}

#[test]
fn sphere_tet_special_positions() {
    // Regular tet with its inscribed ball: the whole ball; a ball around a vertex, edge, face.
    let s = 1.0 / 2f64.sqrt();
    let mut t = [
        [1.0, 0.0, -s],
        [-1.0, 0.0, -s],
        [0.0, 1.0, s],
        [0.0, -1.0, s],
    ]
    .map(V3::from);
    if mesh::tet_volume(&t) < 0.0 {
        t.swap(0, 1);
    }
    let vol = mesh::tet_volume(&t);
    let centroid = V3::zeros();
    // Inradius = 3V / total face area; face area of a regular tet of edge 2: √3.
    let r_in = 3.0 * vol / (4.0 * 3f64.sqrt());
    let v_in = ball_volume(r_in);
    assert_relative_eq!(
        sphere_tet_volume(centroid, r_in, &t),
        v_in,
        epsilon = 1e-14 * v_in,
        max_relative = 1e-14
    );
    assert_relative_eq!(
        sphere_tet_volume(centroid, 0.5 * r_in, &t),
        ball_volume(0.5 * r_in),
        epsilon = 1e-14 * 1.0,
        max_relative = 1e-14
    );
    // A huge ball holds the tet; a far ball misses it.
    assert_relative_eq!(
        sphere_tet_volume(centroid, 1e6, &t),
        vol,
        epsilon = 1e-15 * vol,
        max_relative = 1e-15
    );
    assert_eq!(sphere_tet_volume([10.0, 0.0, 0.0], 1.0, &t), 0.0);
    // A small ball at a vertex holds the vertex's solid-angle fraction of the ball; at an edge
    // midpoint the dihedral fraction; at a face centre half the ball.
    let r = 0.05;
    let v = ball_volume(r);
    // Solid angle at a vertex of a regular tet: spherical excess 3·acos(1/3) − π = acos(23/27).
    let omega_vertex = 3.0 * (1.0f64 / 3.0).acos() - PI;
    assert_abs_diff_eq!(omega_vertex, (23.0f64 / 27.0).acos(), epsilon = 1e-15);
    let at_vertex = sphere_tet_volume(t[0], r, &t);
    assert!(
        approx::relative_eq!(
            at_vertex,
            v * omega_vertex / (4.0 * PI),
            epsilon = 1e-13 * v,
            max_relative = 1e-13
        ),
        "{at_vertex}"
    );
    let dihedral = (1.0f64 / 3.0).acos();
    let mid: V3 = V3::from_fn(|a, _| 0.5 * (t[0][a] + t[1][a]));
    let at_edge = sphere_tet_volume(mid, r, &t);
    assert_relative_eq!(
        at_edge,
        v * dihedral / (2.0 * PI),
        epsilon = 1e-13 * v,
        max_relative = 1e-13
    );
    let fc: V3 = V3::from_fn(|a, _| (t[1][a] + t[2][a] + t[3][a]) / 3.0);
    assert_relative_eq!(
        sphere_tet_volume(fc, r, &t),
        v / 2.0,
        epsilon = 1e-13 * v,
        max_relative = 1e-13
    );
    // Negative orientation gives the negative volume.
    let mut neg = t;
    neg.swap(2, 3);
    assert_relative_eq!(
        sphere_tet_volume(fc, r, &neg),
        -v / 2.0,
        epsilon = 1e-13 * v,
        max_relative = 1e-13
    );
}

#[test]
fn sphere_tet_is_rotation_invariant() {
    let mut rng = Rng::new(21);
    for _ in 0..200 {
        let t = random_tet(&mut rng);
        let c = rng.point([-0.7; 3], [0.7; 3]);
        let r = rng.uniform(0.1, 1.2);
        let axis = rng.point([-1.0; 3], [1.0; 3]);
        let m = mesh::build::rotation(axis, rng.uniform(0.0, 2.0 * PI));
        let affine = mesh::build::affine(m, [0.3, -2.0, 5.0]);
        let f = |p: V3| V3::from(affine(p.into()));
        let a = sphere_tet_volume(c, r, &t);
        let b = sphere_tet_volume(f(c), r, &t.map(f));
        assert!(
            approx::abs_diff_eq!(a, b, epsilon = 1e-13 * ball_volume(r)),
            "{a} vs {b}"
        );
    }
}

#[test]
fn grid_shares_sum_to_ball_and_match_single_boxes() {
    let mut rng = Rng::new(17);
    let mut scratch = GridScratch::default();
    let mut out = vec![];
    let mut worst_sum = 0.0f64;
    let mut worst_box = 0.0f64;
    for _ in 0..300 {
        // Random planes around a unit ball, the outer ones beyond ±1.
        let planes: [Vec<f64>; 3] = std::array::from_fn(|_| {
            let n = 1 + (rng.unit() * 6.0) as usize;
            let mut p: Vec<f64> = (0..n).map(|_| rng.uniform(-1.0, 1.0)).collect();
            p.push(-1.0 - rng.unit());
            p.push(1.0 + rng.unit());
            p.sort_by(f64::total_cmp);
            p
        });
        let r = rng.uniform(0.1, 3.0);
        let r3 = r * r * r;
        sphere_grid_volumes(
            r3,
            [&planes[0], &planes[1], &planes[2]],
            &mut out,
            &mut scratch,
        );
        let sum: f64 = out.iter().sum();
        worst_sum = worst_sum.max(rel(sum, ball_volume(r), 1.0));
        let n = [planes[0].len() - 1, planes[1].len() - 1];
        for (idx, &v) in out.iter().enumerate() {
            let (i, j, k) = (idx % n[0], (idx / n[0]) % n[1], idx / (n[0] * n[1]));
            let lo = [planes[0][i] * r, planes[1][j] * r, planes[2][k] * r];
            let hi = [
                planes[0][i + 1] * r,
                planes[1][j + 1] * r,
                planes[2][k + 1] * r,
            ];
            let single = sphere_box_volume([0.0; 3], r, lo, hi);
            worst_box = worst_box.max((single - v).abs() / ball_volume(r));
        }
    }
    assert!(worst_sum < 1e-12, "sum {worst_sum:e}");
    assert!(worst_box < 1e-13, "box {worst_box:e}");
}

#[test]
fn tiny_and_huge_boxes() {
    let r = 1.0;
    let v = ball_volume(r);
    let h = 1e-6;
    // Tiny box inside: its own volume to the last digits.
    let b = sphere_box_volume([0.0; 3], r, [0.3, 0.2, 0.1], [0.3 + h, 0.2 + h, 0.1 + h]);
    assert!(
        approx::relative_eq!(b, h * h * h, epsilon = 0.0, max_relative = 1e-9),
        "{b:e}"
    );
    // Tiny box outside: exactly 0.
    assert_eq!(
        sphere_box_volume([0.0; 3], r, [1.0, 0.0, 0.0], [1.0 + h, h, h]),
        0.0
    );
    // Small boxes straddling the surface: every share carries an absolute error of a few ulps
    // of the ball volume, so against the quadrature reference the agreement is 1e-14·V, which
    // for h = 1e-3 R (box 1e-9 R³) is 1e-5 of the box volume.
    let nodes = gauss_legendre(48);
    for h in [1e-2, 1e-3] {
        let lo = [0.6 - 0.3 * h, 0.48 - 0.5 * h, 0.64 - 0.5 * h];
        let hi = lo.map(|x| x + h);
        let s = sphere_box_volume([0.0; 3], r, lo, hi);
        let q = ball_box_by_quadrature(r, lo.into(), hi.into(), &nodes);
        assert!(s > 0.1 * h * h * h && s < 0.9 * h * h * h, "h={h}: {s:e}");
        assert!(
            approx::abs_diff_eq!(s, q, epsilon = 1e-14 * v),
            "h={h}: {s:e} vs {q:e}"
        );
    }
    // A box of 1e-6 R straddling the surface: its share stays within [0, h³].
    let s = sphere_box_volume(
        [0.0; 3],
        r,
        [1.0 - h / 2.0, 0.0, 0.0],
        [1.0 + h / 2.0, h, h],
    );
    assert!((0.0..=h * h * h).contains(&s), "{s:e}");
    // Tiny ball in a box, and a tiny ball far from the origin (absolute coordinates 1e3).
    let tiny = 1e-6;
    assert_eq!(
        sphere_box_volume([0.5; 3], tiny, [0.0; 3], [1.0; 3]),
        ball_volume(tiny)
    );
    let c = [1000.0, 1000.0, 1000.0];
    let half = sphere_box_volume(c, tiny, [1000.0, 0.0, 0.0], [2000.0; 3]);
    assert_relative_eq!(
        half,
        ball_volume(tiny) / 2.0,
        epsilon = 0.0,
        max_relative = 1e-9
    );
    // Huge box (1e6 R) with the ball inside, cut by one face, at a corner.
    let big = 1e6;
    assert_eq!(sphere_box_volume([0.0; 3], r, [-big; 3], [big; 3]), v);
    let half = sphere_box_volume([0.0; 3], r, [0.0, -big, -big], [2.0 * big, big, big]);
    assert_relative_eq!(half, v / 2.0, epsilon = 1e-15 * v, max_relative = 1e-15);
    let oct = sphere_box_volume([0.0; 3], r, [0.0; 3], [big; 3]);
    assert_relative_eq!(oct, v / 8.0, epsilon = 1e-15 * v, max_relative = 1e-15);
    // Huge ball (1e6 × the box) holding a unit box.
    assert_eq!(sphere_box_volume([0.0; 3], 1e6, [0.0; 3], [1.0; 3]), 1.0);
    // Degenerate input.
    assert_eq!(sphere_box_volume([0.0; 3], 0.0, [-1.0; 3], [1.0; 3]), 0.0);
    assert_eq!(sphere_box_volume([0.0; 3], 1.0, [1.0; 3], [-1.0; 3]), 0.0);
}

#[test]
fn khawaja_table_2() {
    // Figure 4: a sphere of diameter d protruding d/8 past three orthogonal planes: the
    // planes lie 3R/4 from the centre. Octant 1 holds the centre; 2, 4, 5 are across one plane,
    // 3, 6, 8 across two, 7 across all three.
    let r = 1.0;
    let t = 0.75 * r;
    let big = 10.0;
    let side = |k: usize| if k == 0 { (-big, t) } else { (t, big) };
    let mut exact = [[[0.0; 2]; 2]; 2];
    let mut cube = [[[0.0; 2]; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            for k in 0..2 {
                let (lo, hi) = (
                    [side(i).0, side(j).0, side(k).0],
                    [side(i).1, side(j).1, side(k).1],
                );
                exact[i][j][k] = sphere_box_volume([0.0; 3], r, lo, hi) / ball_volume(r);
                cube[i][j][k] = cube_fraction([0.0; 3], r, lo, hi);
            }
        }
    }
    // Exact: 223/256 and 11/256 (caps of height R/4: π h²(3R − h)/3 / V = 11/256).
    assert_abs_diff_eq!(exact[0][0][0], 223.0 / 256.0, epsilon = 1e-14);
    for (i, j, k) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
        assert_abs_diff_eq!(exact[i][j][k], 11.0 / 256.0, epsilon = 1e-14);
    }
    for (i, j, k) in [(1, 1, 0), (1, 0, 1), (0, 1, 1), (1, 1, 1)] {
        assert!(
            exact[i][j][k].abs() < 1e-15,
            "two caps do not overlap: (3/4)²·2 > 1"
        );
    }
    // Cube: (7/8)³, (7/8)²/8, 7/8/64, 1/512 — the paper prints 0.67, 0.096, 0.0137, 0.00195.
    let c = [cube[0][0][0], cube[1][0][0], cube[1][1][0], cube[1][1][1]];
    assert_eq!(c, [0.669921875, 0.095703125, 0.013671875, 0.001953125]);
    assert_eq!(round_to(c[0], 2), 0.67);
    assert_eq!(round_to(c[1], 3), 0.096);
    assert_eq!(round_to(c[2], 4), 0.0137);
    assert_eq!(round_to(c[3], 5), 0.00195);
    let s = [
        exact[0][0][0],
        exact[1][0][0],
        exact[1][1][0],
        exact[1][1][1],
    ];
    assert_eq!(round_to(s[0], 2), 0.87);
    assert_eq!(round_to(s[1], 3), 0.043);
    // Errors φc − φs as printed: −0.2, 0.053, 0.0137, 0.00195.
    assert_eq!(round_to(c[0] - s[0], 1), -0.2);
    assert_eq!(round_to(c[1] - s[1], 3), 0.053);
    // Corrected (eq. 14): 0.615, 0.032, 0.003, 0.000; renormalised over the 8 octants:
    // 0.854, 0.045, 0.004, 0.001 (3 decimals; 0.000506 unrounded).
    let corrected: Vec<f64> = c.iter().map(|&p| khawaja_correction(p)).collect();
    assert_eq!(round_to(corrected[0], 3), 0.615);
    assert_eq!(round_to(corrected[1], 3), 0.032);
    assert_eq!(round_to(corrected[2], 3), 0.003);
    assert_eq!(round_to(corrected[3], 3), 0.000);
    let mut all: Vec<f64> = cube.iter().flatten().flatten().copied().collect();
    assert_abs_diff_eq!(all.iter().sum::<f64>(), 1.0, epsilon = 1e-15);
    correct_and_renormalise(&mut all);
    assert_abs_diff_eq!(all.iter().sum::<f64>(), 1.0, epsilon = 1e-15);
    let n = |i: usize, j: usize, k: usize| all[i * 4 + j * 2 + k];
    let norm = [n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(1, 1, 1)];
    assert_eq!(round_to(norm[0], 3), 0.854);
    assert_eq!(round_to(norm[1], 3), 0.045);
    assert_eq!(round_to(norm[2], 3), 0.004);
    assert_eq!(round_to(norm[3], 4), 0.0005);
    assert_eq!(round_to(norm[3], 3), 0.001);
    // The paper's last column is the difference of its printed (rounded) values:
    // 0.854 − 0.87 = −0.016, 0.045 − 0.043 = 0.002, 0.004, 0.001.
    assert!((round_to(norm[0], 3) - round_to(s[0], 2) - -0.016).abs() < 1e-12);
    assert!((round_to(norm[1], 3) - round_to(s[1], 3) - 0.002).abs() < 1e-12);
    // Unrounded, the main-cell error is −0.0168.
    assert_eq!(round_to(norm[0] - s[0], 4), -0.0168);
}

#[test]
fn khawaja_polynomial_ends_and_monotone() {
    assert_eq!(khawaja_correction(0.0), 0.0);
    assert_abs_diff_eq!(khawaja_correction(1.0), 1.0, epsilon = 1e-15);
    let mut prev = 0.0;
    for k in 1..=1000 {
        let v = khawaja_correction(k as f64 / 1000.0);
        assert!(v > prev);
        prev = v;
    }
}

/// The paper's error analysis (section 3): a sphere of diameter d moved over all positions
/// around the common node of 8 cubic cells of side d; the maximum error of the cube fraction is
/// about 20 % of the particle volume and of the corrected, renormalised fraction below 2.5 %.
#[test]
fn khawaja_error_claims_by_sampling() {
    let r = 0.5; // d = 1 = cell side
    let planes = [-1.0, 0.0, 1.0];
    let n = 24; // positions per axis over one octant of offsets (symmetry does the rest)
    let mut max_cube = 0.0f64;
    let mut max_corr = 0.0f64;
    let v = ball_volume(r);
    for a in 0..=n {
        for b in 0..=a {
            for c in 0..=b {
                let p = [a, b, c].map(|k| r * k as f64 / n as f64);
                let mut exact = [0.0; 8];
                let mut cube = [0.0; 8];
                for (m, (e, q)) in exact.iter_mut().zip(cube.iter_mut()).enumerate() {
                    let lo = [0, 1, 2].map(|ax| planes[(m >> ax) & 1]);
                    let hi = [0, 1, 2].map(|ax| planes[((m >> ax) & 1) + 1]);
                    *e = sphere_box_volume(p, r, lo, hi) / v;
                    *q = cube_fraction(p, r, lo, hi);
                }
                let mut corr = cube;
                correct_and_renormalise(&mut corr);
                for m in 0..8 {
                    max_cube = max_cube.max((cube[m] - exact[m]).abs());
                    max_corr = max_corr.max((corr[m] - exact[m]).abs());
                }
            }
        }
    }
    println!("max |φc − φs| = {max_cube:.4}, max |φ'' − φs| = {max_corr:.4}");
    assert!(max_cube > 0.19 && max_cube < 0.23, "cube {max_cube}");
    assert!(max_corr < 0.025, "corrected {max_corr}");
}

#[test]
fn divided_markers() {
    let (r1, r2) = divided_shell_bounds();
    assert_abs_diff_eq!(r1.powi(3), 1.0 / 29.0, epsilon = 1e-16);
    assert_abs_diff_eq!(r2.powi(3), 15.0 / 29.0, epsilon = 1e-15);
    let (ri, ro) = divided_radii();
    assert_eq!(round_to(ri, 6), 0.627607);
    assert_eq!(round_to(ro, 6), 0.908528);
    assert!(r1 < ri && ri < r2 && r2 < ro && ro < 1.0);
    // The radial centroid of a shell by quadrature of r·r² over r² (independent of the formula).
    let nodes = gauss_legendre(20);
    let centroid = |a: f64, b: f64| {
        integrate(&nodes, a, b, |r| r * r * r) / integrate(&nodes, a, b, |r| r * r)
    };
    assert_abs_diff_eq!(centroid(r1, r2), ri, epsilon = 1e-14);
    assert_abs_diff_eq!(centroid(r2, 1.0), ro, epsilon = 1e-14);
    for d in divided_directions() {
        assert_abs_diff_eq!(d.iter().map(|x| x * x).sum::<f64>(), 1.0, epsilon = 1e-15);
    }
    let p = divided_offsets();
    assert_eq!(p.len(), DIVIDED_MARKERS);
    assert_eq!(p[0], V3::zeros());
    let radii: Vec<f64> = p
        .iter()
        .map(|q| q.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    assert_eq!(
        radii.iter().filter(|&&x| (x - ri).abs() < 1e-15).count(),
        14
    );
    assert_eq!(
        radii.iter().filter(|&&x| (x - ro).abs() < 1e-15).count(),
        14
    );
    // Symmetric set: centroid at the centre; all markers distinct.
    for a in 0..3 {
        assert!(p.iter().map(|q| q[a]).sum::<f64>().abs() < 1e-14);
    }
    for i in 0..29 {
        for j in 0..i {
            assert!(p[i] != p[j]);
        }
    }
}

#[test]
fn cube_axis_fraction_cases() {
    assert_eq!(cube_axis_fraction(0.0, 1.0, -5.0, 5.0), 1.0);
    assert_eq!(cube_axis_fraction(0.0, 1.0, 0.0, 5.0), 0.5);
    assert_eq!(cube_axis_fraction(0.0, 1.0, 1.0, 5.0), 0.0);
    assert_eq!(cube_axis_fraction(0.0, 1.0, -0.5, 0.5), 0.5);
    assert_eq!(cube_axis_fraction(0.0, 1.0, 2.0, 1.0), 0.0);
}

#[test]
fn box_tet_clipping_matches_box_overlaps() {
    // The 6 tets of box A clipped by box B sum to |A ∩ B| = Π per-axis overlaps.
    let mut rng = Rng::new(31);
    let mut stack = ClipScratch::default();
    for _ in 0..500 {
        let (_, _, alo, ahi) =
            random_case(&mut rng, [0.0, 0.0], [1.0, 1.0], [-1.0, 1.0], [0.1, 1.5]);
        let (_, _, blo, bhi) =
            random_case(&mut rng, [0.0, 0.0], [1.0, 1.0], [-1.0, 1.0], [0.1, 1.5]);
        let overlap: f64 = (0..3)
            .map(|a| (ahi[a].min(bhi[a]) - alo[a].max(blo[a])).max(0.0))
            .product();
        let clipped: f64 = box_tets(alo, ahi)
            .iter()
            .map(|t| box_tet_volume(blo, bhi, t, &mut stack))
            .sum();
        assert!(
            approx::abs_diff_eq!(clipped, overlap, epsilon = 1e-14),
            "{clipped} vs {overlap}"
        );
    }
    // A tet against a box through its interior, vs Monte Carlo.
    let t = random_tet(&mut rng);
    let (lo, hi) = ([-0.3, -0.5, -0.2], [0.6, 0.4, 0.9]);
    let v = box_tet_volume(lo, hi, &t, &mut stack);
    let (mc, se) = monte_carlo(&mut rng, lo, hi, 200_000, |p| in_tet(&t, p));
    assert!(
        approx::abs_diff_eq!(v, mc, epsilon = 4.5 * se),
        "{v} vs {mc} ± {se}"
    );
    // Negative orientation gives the negative volume.
    let mut neg = t;
    neg.swap(0, 1);
    assert!((box_tet_volume(lo, hi, &neg, &mut stack) + v).abs() < 1e-15);
}
