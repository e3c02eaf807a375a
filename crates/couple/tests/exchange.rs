//! Interpolation, exchange fields and blending against hand-computed values, and momentum
//! conservation (Σ over cells = Σ over particles to round-off) for every voidage method.

#![allow(clippy::needless_range_loop)]

use couple::blend::{blend_scalar, blend_vector, fraction};
use couple::exchange::exchange;
use couple::{Interpolation, Placement};
use mesh::build::{hex_grid, uniform_box};
use mesh::v3::V3;
use voidage::{Method, ParticleSet, VoidageMesh};

fn place(vm: &VoidageMesh, m: Method, pos: &[V3], rad: &[f64]) -> Placement {
    let mut centre = vec![None; pos.len()];
    let (shares, _) = vm
        .shares_with_cells(m, &ParticleSet::new(pos, rad), &mut centre)
        .unwrap();
    Placement { centre, shares }
}

#[test]
fn two_cells_by_hand() {
    // Cells [0,1]³ and [1,2]×[0,1]², 1 m³ each; centre method.
    let vm = VoidageMesh::new(&uniform_box(
        V3::repeat(0.0),
        V3::new(2.0, 1.0, 1.0),
        [2, 1, 1],
    ))
    .unwrap();
    let pos = [
        V3::new(0.3, 0.5, 0.5),
        V3::new(0.7, 0.5, 0.5),
        V3::new(1.5, 0.5, 0.5),
        V3::new(5.0, 0.5, 0.5),
    ];
    let rad = [0.1; 4];
    let p = place(&vm, Method::Centre, &pos, &rad);
    let beta = [2.0, 6.0, 3.0, 7.0];
    let v = [
        V3::new(1.0, 0.0, 0.0),
        V3::new(0.0, 1.0, 0.0),
        V3::new(0.0, 0.0, 2.0),
        V3::repeat(9.0),
    ];
    let f = [
        V3::new(1.0, 2.0, 3.0),
        V3::new(0.5, 0.0, 0.0),
        V3::new(0.0, 0.0, -4.0),
        V3::repeat(1.0),
    ];
    let ex = exchange(&p, vm.cell_volumes(), &beta, &v, &f);
    assert_eq!(ex.ksl, vec![8.0, 3.0]);
    assert_eq!(
        ex.us,
        vec![V3::new(0.25, 0.75, 0.0), V3::new(0.0, 0.0, 2.0)]
    );
    assert_eq!(
        ex.f,
        vec![V3::new(-1.5, -2.0, -3.0), V3::new(0.0, 0.0, 4.0)]
    );
    assert_eq!(ex.outside.particles, 1);
    assert_eq!(ex.outside.beta, 7.0);
    assert_eq!(ex.outside.force, V3::repeat(1.0));
}

#[test]
fn smooth_interpolation_on_a_node_averages_the_eight_cells() {
    let vm = VoidageMesh::new(&uniform_box(V3::repeat(0.0), V3::repeat(2.0), [2, 2, 2])).unwrap();
    let field: Vec<f64> = (0..8).map(|c| (c * c) as f64).collect();
    let p = place(
        &vm,
        Method::Exact,
        &[V3::repeat(1.0), V3::repeat(0.5)],
        &[0.3, 0.3],
    );
    let smooth = p.value_at(&field, 0, Interpolation::Smooth).unwrap();
    let mean = field.iter().sum::<f64>() / 8.0;
    assert!(
        approx::abs_diff_eq!(smooth, mean, epsilon = 1e-12 * mean),
        "{smooth} vs {mean}"
    );
    // The ball at (0.5, 0.5, 0.5) lies in cell 0: both rules give its value.
    assert_eq!(p.value_at(&field, 1, Interpolation::Smooth), Some(0.0));
    assert_eq!(p.value_at(&field, 1, Interpolation::Cell), Some(0.0));
    // The cell rule on the node takes the cell of the centre (half-open rule: the upper one).
    let c = p.centre[0].unwrap() as usize;
    assert_eq!(p.value_at(&field, 0, Interpolation::Cell), Some(field[c]));
    assert_eq!(c, 7);
}

#[test]
fn uniform_fields_are_reproduced_and_outside_is_none() {
    let vm = VoidageMesh::new(&uniform_box(V3::repeat(0.0), V3::repeat(1.0), [3, 4, 5])).unwrap();
    let u = vec![V3::new(0.1, -0.2, 0.3); vm.n_cells()];
    let pos = [
        V3::new(0.5, 0.5, 0.99),
        V3::new(0.1, 0.2, 0.3),
        V3::new(2.0, 0.0, 0.0),
    ];
    for m in Method::ALL {
        let p = place(&vm, m, &pos, &[0.15, 0.05, 0.1]);
        for rule in [Interpolation::Cell, Interpolation::Smooth] {
            for i in 0..2 {
                let x = p.value_at(&u, i, rule).unwrap();
                for a in 0..3 {
                    assert!(
                        approx::abs_diff_eq!(x[a], u[0][a], epsilon = 1e-15),
                        "{m} {rule}: {x:?}"
                    );
                }
            }
            assert_eq!(p.value_at(&u, 2, rule), None);
        }
    }
}

/// A deterministic cloud, some particles straddling the boundary, some outside.
fn cloud(n: usize) -> (Vec<V3>, Vec<f64>, Vec<V3>) {
    let phi = 1.324_717_957_244_746_f64;
    let alpha = V3::new(1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi));
    let pos = (0..n)
        .map(|k| alpha.map(|a| -0.05 + 1.1 * (0.5 + k as f64 * a).fract()))
        .collect();
    let rad = (0..n)
        .map(|k| 0.02 + 0.03 * ((k * 7919) % 101) as f64 / 100.0)
        .collect();
    let vel = (0..n)
        .map(|k| {
            let s = k as f64;
            V3::new((s * 0.37).sin(), (s * 0.11).cos(), 0.3 - (s * 0.05).sin())
        })
        .collect();
    (pos, rad, vel)
}

#[test]
fn cell_sums_equal_particle_sums_for_every_method() {
    let xs = mesh::build::graded_planes(0.0, 1.0, 7, 1.3);
    let ys = mesh::build::graded_planes(0.0, 1.0, 5, 0.8);
    let zs = mesh::build::graded_planes(0.0, 1.0, 6, 1.0);
    let grid = hex_grid(&xs, &ys, &zs);
    let general = VoidageMesh::with_options(
        &grid,
        voidage::MeshOptions {
            axis_aligned_fast_path: false,
        },
    )
    .unwrap();
    let (pos, rad, vel) = cloud(2000);
    for vm in [VoidageMesh::new(&grid).unwrap(), general] {
        let vols = vm.cell_volumes().to_vec();
        // A non-uniform fluid velocity: U(x) = (x_y, −x_x, x_z²) at the cell centres.
        let centres = &vm.geometry().cell_centres;
        let u: Vec<V3> = centres
            .iter()
            .map(|c| V3::new(c[1], -c[0], c[2] * c[2]))
            .collect();
        // Graded meshes: every method but trilinear (uniform grids only).
        for m in Method::ANY_MESH {
            let p = place(&vm, m, &pos, &rad);
            let beta: Vec<f64> = rad.iter().map(|r| 1e3 * r).collect();
            let force: Vec<V3> = vel.iter().map(|v| V3::new(v[2], v[0], -v[1])).collect();
            let ex = exchange(&p, &vols, &beta, &vel, &force);
            let inside: Vec<usize> = (0..pos.len()).filter(|&i| p.inside(i)).collect();
            assert!(inside.len() < pos.len() && ex.outside.particles == pos.len() - inside.len());
            let sum_beta: f64 = inside.iter().map(|&i| beta[i]).sum();
            assert!(
                approx::abs_diff_eq!(ex.total_ksl(&vols), sum_beta, epsilon = 1e-12 * sum_beta),
                "{m}"
            );
            let ksl_us = ex.total_ksl_us(&vols);
            let total_f = ex.total_f(&vols);
            // Momentum the fluid loses through the implicit term, with u_f smooth.
            let mut cells = V3::repeat(0.0);
            for c in 0..vols.len() {
                for a in 0..3 {
                    cells[a] += vols[c] * ex.ksl[c] * (u[c][a] - ex.us[c][a]);
                }
            }
            let mut parts = V3::repeat(0.0);
            let mut scale = 0.0;
            let mut bv = V3::repeat(0.0);
            let mut fp = V3::repeat(0.0);
            for &i in &inside {
                let uf = p.value_at(&u, i, Interpolation::Smooth).unwrap();
                for a in 0..3 {
                    parts[a] += beta[i] * (uf[a] - vel[i][a]);
                    scale += (beta[i] * (uf[a].abs() + vel[i][a].abs())) / 3.0;
                    bv[a] += beta[i] * vel[i][a];
                    fp[a] += force[i][a];
                }
            }
            for a in 0..3 {
                assert!(
                    approx::abs_diff_eq!(ksl_us[a], bv[a], epsilon = 1e-12 * sum_beta),
                    "{m}: Σ Ksl Us"
                );
                assert!(
                    (total_f[a] + fp[a]).abs() < 1e-12 * inside.len() as f64,
                    "{m}: Σ f"
                );
            }
            for a in 0..3 {
                assert!(
                    approx::abs_diff_eq!(cells[a], parts[a], epsilon = 1e-12 * scale),
                    "{m}: {cells:?} vs {parts:?}"
                );
            }
        }
    }
}

#[test]
fn blending_by_hand() {
    assert_eq!(fraction(0.5, 0.0, 2.0), 0.25);
    assert_eq!(fraction(-1.0, 0.0, 2.0), 0.0);
    assert_eq!(fraction(3.0, 0.0, 2.0), 1.0);
    assert_eq!(fraction(3.0, 0.0, 0.0), 1.0);
    let mut out = Vec::new();
    blend_scalar(&[0.4, 1.0], &[0.8, 0.5], 0.25, &mut out);
    assert_eq!(out, vec![0.5, 0.875]);
    blend_scalar(&[0.4, 1.0], &[0.8, 0.5], 1.0, &mut out);
    assert_eq!(out, vec![0.8, 0.5]);
    let mut outv = Vec::new();
    blend_vector(
        &[V3::new(0.0, 4.0, -1.0)],
        &[V3::new(1.0, 0.0, 1.0)],
        0.75,
        &mut outv,
    );
    assert_eq!(outv, vec![V3::new(0.75, 1.0, 0.5)]);
}
