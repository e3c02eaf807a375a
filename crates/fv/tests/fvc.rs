//! `fv::fvc` against independent references: OpenFOAM v1912's own `postProcess -func
//! "grad(p)"` / `"grad(U)"` output (fixtures in `tests/fixtures/fv/grad/`), closed-form
//! gradients of linear fields, and the closed-form viscous-stress divergence of a quadratic
//! velocity field.

use approx::assert_abs_diff_eq;
use foam::{Case, FieldValues, Item, VolField};
use fv::fvc::{self, Field};
use fv::testfields::{length_scale, linear_scalar, smooth_vector};
use fv::FvGeometry;
use mesh::build;
use mesh::v3::{from_arrays, V3};

fn geometry(case: &Case) -> FvGeometry {
    FvGeometry::new(&case.read_mesh().unwrap()).unwrap()
}

/// Cell values and boundary-face values of a field file `0/name` whose patches are
/// `fixedValue` with a nonuniform `value` (faces of `empty` patches get the owner's value;
/// they are never read).
fn read(case: &Case, g: &FvGeometry, name: &str) -> (FieldValues, FieldValues) {
    let f = VolField::read(&case.time_path("0").join(name)).unwrap();
    let cells = f.internal(g.n_cells).unwrap();
    let mut b = match &cells {
        FieldValues::Scalar(c) => FieldValues::Scalar(
            g.owner[g.n_internal..]
                .iter()
                .map(|&o| c[o as usize])
                .collect(),
        ),
        FieldValues::Vector(c) => FieldValues::Vector(
            g.owner[g.n_internal..]
                .iter()
                .map(|&o| c[o as usize])
                .collect(),
        ),
    };
    for p in g.patches.iter().filter(|p| !p.is_empty()) {
        let s = f.boundary().dict(&p.name).unwrap().stream("value").unwrap();
        let r = p.boundary_range(g.n_internal);
        match (&mut b, s.get(2)) {
            (FieldValues::Scalar(b), Some(Item::Scalars(v))) => b[r].copy_from_slice(v),
            (FieldValues::Vector(b), Some(Item::Vectors(v))) => b[r].copy_from_slice(v),
            _ => panic!("{name}: nonuniform value list expected on {}", p.name),
        }
    }
    (cells, b)
}

fn read_scalar(case: &Case, g: &FvGeometry, name: &str) -> (Vec<f64>, Vec<f64>) {
    let (FieldValues::Scalar(c), FieldValues::Scalar(b)) = read(case, g, name) else {
        panic!("{name}: scalar field expected")
    };
    (c, b)
}

fn read_vector(case: &Case, g: &FvGeometry, name: &str) -> (Vec<V3>, Vec<V3>) {
    let (FieldValues::Vector(c), FieldValues::Vector(b)) = read(case, g, name) else {
        panic!("{name}: vector field expected")
    };
    (from_arrays(&c), from_arrays(&b))
}

/// OpenFOAM's cell values of a tensor field (9 components per cell).
fn read_tensor_cells(case: &Case, name: &str) -> Vec<f64> {
    let f = foam::parse_file(&case.time_path("0").join(name)).unwrap();
    let s = f.body.stream("internalField").unwrap();
    match s.get(2) {
        Some(Item::Tuples {
            values,
            components: 9,
            ..
        }) => values.clone(),
        other => panic!("tensor list expected, got {other:?}"),
    }
}

const CASES: [&str; 3] = ["cavity", "skewed_blocks", "poly_dual"];

/// Asserts |ours − OpenFOAM| ≤ 1e-12 · max|OpenFOAM| component by component (flattened).
fn assert_close(name: &str, what: &str, ours: &[f64], of: &[f64]) {
    assert_eq!(ours.len(), of.len(), "{name} {what}: lengths");
    let scale = of.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (i, (a, b)) in ours.iter().zip(of).enumerate() {
        assert!(
            approx::abs_diff_eq!(a, b, epsilon = 1e-12 * scale),
            "{name} {what} component {i}: ours {a} OpenFOAM {b}"
        );
    }
}

#[test]
fn gauss_gradients_match_openfoam_postprocess() {
    for name in CASES {
        let case = Case::open(testkit::fixture(&format!("fv/grad/{name}"))).unwrap();
        let g = geometry(&case);
        let (p, pb) = read_scalar(&case, &g, "p");
        let ours: Vec<f64> = fvc::grad_scalar(&g, &p, &pb)
            .iter()
            .flat_map(|v| v.iter().copied())
            .collect();
        let (of, _) = read_vector(&case, &g, "grad(p)");
        let of: Vec<f64> = of.iter().flat_map(|v| v.iter().copied()).collect();
        assert_close(name, "grad(p)", &ours, &of);
        let (u, ub) = read_vector(&case, &g, "U");
        // OpenFOAM's tensor order: xx xy xz yx … (row by row)
        let ours: Vec<f64> = fvc::grad_vector(&g, &u, &ub)
            .iter()
            .flat_map(|t| (0..3).flat_map(move |i| (0..3).map(move |j| t[(i, j)])))
            .collect();
        assert_close(name, "grad(U)", &ours, &read_tensor_cells(&case, "grad(U)"));
    }
}

/// The skewed fixtures really are skewed: Gauss linear is not exact there for a linear field,
/// while the least-squares gradient is (to round-off), on every fixture mesh.
#[test]
fn least_squares_gradient_is_exact_for_linear_fields_on_skewed_meshes() {
    let gvec = [1.5, -2.0, 0.75];
    for rel in [
        "foam/cavity",
        "mesh/skewed_blocks",
        "mesh/poly_dual",
        "mesh/box_blocks",
    ] {
        let case = Case::open(testkit::fixture(rel)).unwrap();
        let g = geometry(&case);
        let l = length_scale(&g);
        let gl = gvec.map(|x| x / l);
        let cells: Vec<f64> =
            g.c.iter()
                .map(|&x| linear_scalar(x, 3.0, gl.into()))
                .collect();
        let bnd: Vec<f64> = g.cf[g.n_internal..]
            .iter()
            .map(|&x| linear_scalar(x, 3.0, gl.into()))
            .collect();
        let two_d = g.patches.iter().any(|p| p.is_empty());
        let ls = fvc::grad_least_squares(&g, &cells, &bnd);
        for (c, v) in ls.iter().enumerate() {
            for k in 0..3 {
                // In a 2-D case the component across the empty direction is zero by design
                // unless the mesh has several cell layers in it.
                let want = gl[k];
                let err = (v[k] - want).abs();
                assert!(
                    err <= 1e-9 * gl.iter().fold(0.0f64, |m, x| m.max(x.abs()))
                        || (two_d && k == 2),
                    "{rel} cell {c} comp {k}: {} vs {want}",
                    v[k]
                );
            }
        }
        if rel == "mesh/skewed_blocks" {
            let gauss = fvc::grad_scalar(&g, &cells, &bnd);
            let worst = gauss
                .iter()
                .flat_map(|v| (0..3).map(move |k| (v[k] - gl[k]).abs()))
                .fold(0.0, f64::max);
            assert!(
                worst > 1e-6 / l,
                "skewed_blocks should show a skewness error, got {worst}"
            );
        }
    }
}

/// An orthogonal box whose cell size is not a binary fraction (0.1 m / 48) leaves round-off in
/// k = n̂ − d·δ (≈ 3e-14 before it was zeroed): every correction vector is exactly zero and the
/// mesh counts as orthogonal; the same box sheared by 1e-5 (x += 1e-5 y) keeps the correction
/// of its tilted faces, whose size is the shear to first order (|k| = sin of the tilt), and
/// the round-off of its other faces (OpenFOAM's arithmetic).
#[test]
fn round_off_correction_vectors_are_zero_and_real_ones_are_kept() {
    let boxed = build::uniform_box([0.0; 3], [0.1, 0.1, 0.1], [48, 20, 3]);
    let g = FvGeometry::new(&boxed).unwrap();
    assert!(g.corr_vec.iter().all(|k| k.iter().all(|&x| x == 0.0)));
    assert!(g.orthogonal);
    let shear = 1e-5;
    let sheared = build::map_points(&boxed, |p| [p[0] + shear * p[1], p[1], p[2]]);
    let g = FvGeometry::new(&sheared).unwrap();
    assert!(!g.orthogonal);
    let largest = g.corr_vec.iter().map(|k| k.amax()).fold(0.0, f64::max);
    assert!(
        (largest - shear).abs() < 1e-3 * shear,
        "largest correction {largest:e} against the shear {shear:e}"
    );
    assert!(fv::geometry::ROUNDOFF_K < 1e-3 * shear);
    let round_off = g
        .corr_vec
        .iter()
        .filter(|k| k.amax() > 0.0 && k.amax() < 1e-12);
    assert!(
        round_off.count() > 0,
        "the untilted faces keep their round-off"
    );
}

/// A sheared and rotated uniform grid is non-orthogonal but unskewed (face centres are the
/// midpoints of the cell centres): Gauss linear is exact there for a linear field.
#[test]
fn gauss_gradient_is_exact_for_linear_fields_on_non_orthogonal_unskewed_meshes() {
    let shear = [[1.0, 0.6, 0.2], [0.0, 1.0, -0.4], [0.0, 0.0, 0.8]];
    let rot = build::rotation([1.0, 2.0, 3.0], 0.7);
    let mut a = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            a[i][j] = (0..3).map(|k| rot[i][k] * shear[k][j]).sum();
        }
    }
    let m = build::map_points(
        &build::uniform_box([0.0; 3], [1.0, 2.0, 0.5], [5, 6, 4]),
        build::affine(a, [0.3, -1.0, 2.0]),
    );
    let g = FvGeometry::new(&m).unwrap();
    let gl = [0.4, -1.3, 2.2];
    let cells: Vec<f64> =
        g.c.iter()
            .map(|&x| linear_scalar(x, -1.0, gl.into()))
            .collect();
    let bnd: Vec<f64> = g.cf[g.n_internal..]
        .iter()
        .map(|&x| linear_scalar(x, -1.0, gl.into()))
        .collect();
    let gr = fvc::grad_scalar(&g, &cells, &bnd);
    let nonorth = g.corr_vec.iter().map(|k| (*k).norm()).fold(0.0, f64::max);
    assert!(nonorth > 0.1, "mesh must be non-orthogonal ({nonorth})");
    for (c, v) in gr.iter().enumerate() {
        for k in 0..3 {
            assert!(
                approx::abs_diff_eq!(v[k], gl[k], epsilon = 1e-12),
                "cell {c}: {v:?} vs {gl:?}"
            );
        }
    }
    // The vector gradient of U = (φ, 2φ, −φ) has rows ∂_i U = gl_i (1, 2, −1).
    let u: Vec<V3> = cells.iter().map(|&p| V3::new(p, 2.0 * p, -p)).collect();
    let ub: Vec<V3> = bnd.iter().map(|&p| V3::new(p, 2.0 * p, -p)).collect();
    for t in fvc::grad_vector(&g, &u, &ub) {
        for i in 0..3 {
            for (j, f) in [1.0, 2.0, -1.0].iter().enumerate() {
                assert_abs_diff_eq!(t[(i, j)], gl[i] * f, epsilon = 1e-12);
            }
        }
    }
}

/// ∇·(ν(∇U + ∇Uᵀ)) of the quadratic U of `testfields::smooth_vector` is ν(2, 0, 2)/L²
/// (∇²U = (2, 0, 2)/L², ∇·U = −1/L is uniform). On a uniform grid the discretisation is exact
/// in cells whose neighbours are all interior; on a smoothly distorted grid (non-orthogonal and
/// skewed, faces slightly warped) the interior error converges at second order.
#[test]
fn viscous_stress_divergence_of_a_quadratic_field() {
    let nu = 1.5e-4;
    let run = |n: usize, shear: f64| {
        let base = build::uniform_box([0.0; 3], [1.0, 1.0, 1.0], [n, n, n]);
        let tau = std::f64::consts::TAU;
        let m = build::map_points(&base, |p| {
            [
                p[0] + shear * (tau * p[1]).sin(),
                p[1] + shear * (tau * p[2]).sin(),
                p[2] + shear * (tau * p[0]).sin(),
            ]
        });
        let g = FvGeometry::new(&m).unwrap();
        let l = 1.0;
        let u: Vec<V3> = g.c.iter().map(|&x| smooth_vector(x, l)).collect();
        let ub: Vec<V3> = g.cf[g.n_internal..]
            .iter()
            .map(|&x| smooth_vector(x, l))
            .collect();
        let nuc = vec![nu; g.n_cells];
        let nub = vec![nu; g.n_boundary()];
        let d = fvc::div_viscous_stress(&g, Field::new(&nuc, &nub), Field::new(&u, &ub));
        let want = [2.0 * nu, 0.0, 2.0 * nu];
        let mut worst = 0.0f64;
        for (c, dc) in d.iter().enumerate() {
            // cells two layers away from the boundary
            let far = g.faces_of(c).iter().all(|&f| {
                let f = f as usize;
                f < g.n_internal
                    && g.faces_of(g.other(c, f))
                        .iter()
                        .all(|&h| (h as usize) < g.n_internal)
            });
            if far {
                for k in 0..3 {
                    worst = worst.max((dc[k] - want[k]).abs());
                }
            }
        }
        worst / (2.0 * nu)
    };
    assert!(run(6, 0.0) < 1e-10, "uniform grid: exact in the interior");
    let (e1, e2) = (run(12, 0.05), run(24, 0.05));
    let order = (e1 / e2).log2();
    assert!(
        e1 > 1e-8,
        "the sheared case must have a discretisation error ({e1})"
    );
    assert!(order > 1.8, "interior error {e1} → {e2}: order {order}");
}

/// `reconstruct` returns a uniform vector from its face fluxes φ_f = a·S_f exactly (to
/// round-off) on skewed and polyhedral meshes, and on a uniform grid the cell-centre value of a
/// linear field from the face-centre fluxes.
#[test]
fn reconstruct_recovers_uniform_and_linear_fields() {
    let a = V3::new(0.3, -1.2, 0.7);
    for name in ["skewed_blocks", "poly_dual"] {
        let case = Case::open(testkit::fixture(&format!("fv/grad/{name}"))).unwrap();
        let g = geometry(&case);
        let phi: Vec<f64> = g.sf.iter().map(|s| a.dot(s)).collect();
        let r = fvc::reconstruct(&g, &phi);
        let err = r
            .iter()
            .flat_map(|v| (0..3).map(move |i| (v[i] - a[i]).abs()))
            .fold(0.0, f64::max);
        assert!(err < 1e-12, "{name}: {err}");
    }
    let g = FvGeometry::new(&build::uniform_box([0.0; 3], [1.0, 2.0, 0.5], [5, 4, 3])).unwrap();
    let u = |x: V3| V3::new(1.0 + 2.0 * x[1], x[0] - x[2], 3.0 * x[0] + x[1]);
    let phi: Vec<f64> = (0..g.n_faces())
        .map(|f| (u(g.cf[f])).dot(&g.sf[f]))
        .collect();
    let r = fvc::reconstruct(&g, &phi);
    let err = r
        .iter()
        .zip(&g.c)
        .flat_map(|(v, c)| {
            let e = u(*c);
            (0..3).map(move |i| (v[i] - e[i]).abs())
        })
        .fold(0.0, f64::max);
    assert!(err < 1e-12, "linear field: {err}");
}
