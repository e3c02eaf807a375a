//! The models on meshes: conservation for every method, independent outside volumes, symmetry,
//! continuity across faces, cells smaller than the particles, the general-mesh path against the
//! grid path and against rotated meshes, Monte Carlo on a sheared mesh, errors and clipping.

mod common;

use approx::assert_abs_diff_eq;
use approx::assert_relative_eq;
use common::*;
use mesh::build::{affine, hex_grid, map_points, rotation, uniform_box};
use mesh::v3::V3;
use std::f64::consts::PI;
use voidage::*;

const NO_GRID: MeshOptions = MeshOptions {
    axis_aligned_fast_path: false,
};

/// Solid volume per cell of one particle.
fn shares(vm: &VoidageMesh, method: Method, c: impl Into<V3>, r: f64) -> (Vec<f64>, f64) {
    let d = vm
        .deposit(method, &ParticleSet::new(&[c.into()], &[r]))
        .unwrap();
    (d.solid, d.outside_volume)
}

/// Random particles with centres in the box [lo, hi] and radii in [rmin, rmax].
fn particles(
    rng: &mut Rng,
    n: usize,
    lo: impl Into<V3>,
    hi: impl Into<V3>,
    rmin: f64,
    rmax: f64,
) -> (Vec<V3>, Vec<f64>) {
    let (lo, hi) = (lo.into(), hi.into());
    let pos = (0..n).map(|_| rng.point(lo, hi)).collect();
    let rad = (0..n).map(|_| rng.uniform(rmin, rmax)).collect();
    (pos, rad)
}

#[test]
fn method_names() {
    for m in Method::ALL {
        assert_eq!(m.name().parse::<Method>().unwrap(), m);
        assert_eq!(m.to_string(), m.name());
    }
    assert_eq!("dividedVoidFraction".parse::<Method>(), Ok(Method::Divided));
    assert_eq!(Method::Centre.cfdem_name(), Some("centre"));
    assert_eq!("trilinear".parse::<Method>(), Ok(Method::Trilinear));
    assert_eq!(
        "trilinearVoidFraction".parse::<Method>(),
        Ok(Method::Trilinear)
    );
    assert_eq!(Method::Trilinear.cfdem_name(), Some("trilinear"));
    assert!(!Method::ANY_MESH.contains(&Method::Trilinear));
    assert_eq!(Method::Exact.cfdem_name(), None);
    assert_eq!("bigParticle".parse::<Method>(), Ok(Method::BigParticle));
    assert_eq!("GaussVoidFraction".parse::<Method>(), Ok(Method::Gauss));
    let e = "IBVoidFraction".parse::<Method>().unwrap_err().to_string();
    for m in Method::ALL {
        assert!(e.contains(m.name()), "{e}");
    }
    assert!(e.contains("IBVoidFraction"));
}

#[test]
fn bad_particles_are_typed_errors() {
    let vm = VoidageMesh::new(&uniform_box([0.0; 3], [1.0; 3], [2, 2, 2])).unwrap();
    let pos = [[0.5; 3], [f64::NAN, 0.5, 0.5], [0.5; 3]].map(V3::from);
    let ids = [10, 11, 12];
    let set = ParticleSet {
        positions: &pos,
        radii: &[0.1, 0.1, -0.1],
        ids: Some(&ids),
    };
    match vm.deposit(Method::Exact, &set) {
        Err(VoidageError::InvalidParticle {
            index: 1,
            id: Some(11),
            problem: ParticleProblem::NonFinitePosition(_),
        }) => {}
        other => panic!("{other:?}"),
    }
    let pos = [V3::repeat(0.5); 3];
    let set = ParticleSet {
        positions: &pos,
        ..set
    };
    let e = vm.deposit(Method::Cube, &set).unwrap_err();
    assert!(matches!(
        e,
        VoidageError::InvalidParticle {
            index: 2,
            id: Some(12),
            problem: ParticleProblem::BadRadius(_)
        }
    ));
    assert!(e.to_string().contains("particle 2 (id 12)"), "{e}");
    let e = vm
        .deposit(Method::Centre, &ParticleSet::new(&pos, &[0.1]))
        .unwrap_err();
    assert!(matches!(
        e,
        VoidageError::LengthMismatch { what: "radii", .. }
    ));
    let d = vm
        .deposit(Method::Centre, &ParticleSet::new(&pos, &[0.1; 3]))
        .unwrap();
    assert!(matches!(
        vm.voidage(&d, Some(1.0)),
        Err(VoidageError::BadAlphaMin(_))
    ));
    assert!(vm.voidage(&d, Some(f64::NAN)).is_err());
    // A radius whose volume overflows, and an infinite coordinate.
    let e = vm.deposit(Method::Exact, &ParticleSet::new(&pos[..1], &[1e200]));
    assert!(matches!(
        e,
        Err(VoidageError::InvalidParticle {
            index: 0,
            id: None,
            ..
        })
    ));
    let far = [V3::new(f64::INFINITY, 0.0, 0.0)];
    assert!(vm
        .deposit(Method::Centre, &ParticleSet::new(&far, &[0.1]))
        .is_err());
}

/// Every method conserves volume on a grid (both paths) and a rotated copy, for particles
/// inside, across the boundary and outside; the outside volume of exact and cube matches an
/// independent single-box computation.
#[test]
fn conservation_every_method() {
    let lo = [0.0, -1.0, 2.0];
    let hi = [3.0, 1.0, 4.5];
    let box_mesh = uniform_box(lo, hi, [6, 4, 5]);
    let rot = affine(rotation([1.0, 2.0, 0.5], 0.7), [0.1, 0.2, 0.3]);
    let rotated = map_points(&box_mesh, &rot);
    let mut rng = Rng::new(1);
    for (rmin, rmax) in [(0.05, 0.2), (0.3, 0.9)] {
        // Centres up to 2·rmax beyond the mesh: inside, across the boundary and outside.
        let (pos, rad) = particles(
            &mut rng,
            300,
            lo.map(|x| x - 2.0 * rmax),
            hi.map(|x| x + 2.0 * rmax),
            rmin,
            rmax,
        );
        let vol: f64 = rad.iter().map(|&r| ball_volume(r)).sum();
        let exact_outside: f64 = pos
            .iter()
            .zip(&rad)
            .map(|(&c, &r)| ball_volume(r) - sphere_box_volume(c, r, lo, hi))
            .sum();
        let cube_outside: f64 = pos
            .iter()
            .zip(&rad)
            .map(|(&c, &r)| ball_volume(r) * (1.0 - cube_fraction(c, r, lo, hi)))
            .sum();
        for (name, vm) in [
            ("grid", VoidageMesh::new(&box_mesh).unwrap()),
            (
                "general",
                VoidageMesh::with_options(&box_mesh, NO_GRID).unwrap(),
            ),
        ] {
            assert_eq!(vm.axis_grid().is_some(), name == "grid");
            for m in Method::ALL {
                let d = vm.deposit(m, &ParticleSet::new(&pos, &rad)).unwrap();
                assert_relative_eq!(
                    d.particle_volume,
                    vol,
                    epsilon = 1e-14 * vol,
                    max_relative = 1e-14
                );
                assert!(d.conservation_error() < 1e-12, "{name} {m}");
                assert!(d.solid.iter().all(|&s| s >= 0.0));
                assert!(d.particles_outside > 0);
                assert!(!m.is_continuous() || d.particles_partly_outside > 0);
                match m {
                    Method::Exact => assert!(
                        approx::abs_diff_eq!(
                            d.outside_volume,
                            exact_outside,
                            epsilon = 1e-12 * vol
                        ),
                        "{name}: {} vs {exact_outside}",
                        d.outside_volume
                    ),
                    Method::Cube => {
                        assert_abs_diff_eq!(d.outside_volume, cube_outside, epsilon = 1e-12 * vol)
                    }
                    _ => {}
                }
            }
        }
        // The rotated mesh with the rotated particles: exact is rotation-invariant.
        let vm = VoidageMesh::new(&rotated).unwrap();
        assert!(vm.axis_grid().is_none());
        let rpos: Vec<V3> = pos.iter().map(|&p| V3::from(rot(p.into()))).collect();
        for m in Method::ALL.into_iter().filter(|&m| defined_on(&vm, m)) {
            let d = vm.deposit(m, &ParticleSet::new(&rpos, &rad)).unwrap();
            assert!(d.conservation_error() < 1e-12, "rotated {m}");
            if m == Method::Exact {
                assert_abs_diff_eq!(d.outside_volume, exact_outside, epsilon = 1e-12 * vol);
            }
        }
    }
}

/// Shares of every cell on the grid path equal the single-box kernel, and on the general path
/// the sum of the tet kernel over the cell's tets (two independent routes).
#[test]
fn exact_shares_match_kernels_cell_by_cell() {
    let m = hex_grid(
        &[0.0, 0.3, 0.5, 1.2, 1.3],
        &[0.0, 0.4, 0.45, 1.0],
        &[-0.2, 0.1, 0.7, 0.9],
    );
    let grid = VoidageMesh::new(&m).unwrap();
    let general = VoidageMesh::with_options(&m, NO_GRID).unwrap();
    let g = grid.axis_grid().unwrap().clone();
    let mut rng = Rng::new(2);
    for _ in 0..60 {
        let c = rng.point([-0.2, -0.2, -0.4], [1.5, 1.2, 1.1]);
        let r = rng.uniform(0.05, 0.6);
        let v = ball_volume(r);
        let (a, _) = shares(&grid, Method::Exact, c, r);
        let (b, _) = shares(&general, Method::Exact, c, r);
        for cell in 0..a.len() {
            let [i, j, k] = g.ijk(cell as u32);
            let lo = [g.planes(0)[i], g.planes(1)[j], g.planes(2)[k]];
            let hi = [g.planes(0)[i + 1], g.planes(1)[j + 1], g.planes(2)[k + 1]];
            let single = sphere_box_volume(c, r, lo, hi);
            assert!(
                approx::abs_diff_eq!(a[cell], single, epsilon = 1e-13 * v),
                "grid cell {cell}"
            );
            let by_tets = tet_sum(&general, cell, c, r);
            assert!(
                approx::abs_diff_eq!(b[cell], by_tets, epsilon = 1e-13 * v),
                "general cell {cell} {} {} {} c={c:?} r={r}",
                b[cell],
                by_tets,
                a[cell]
            );
            assert_abs_diff_eq!(a[cell], b[cell], epsilon = 1e-13 * v);
        }
    }
}

/// The general path on an axis-aligned mesh gives the grid path's shares for every method
/// (particles away from the mesh boundary, where the corrected cube's outside pieces differ by
/// definition).
#[test]
fn general_path_matches_grid_path() {
    let m = uniform_box([0.0; 3], [2.0; 3], [5, 4, 6]);
    let grid = VoidageMesh::new(&m).unwrap();
    let general = VoidageMesh::with_options(&m, NO_GRID).unwrap();
    let mut rng = Rng::new(3);
    let (pos, rad) = particles(&mut rng, 200, [0.6; 3], [1.4; 3], 0.05, 0.55);
    for method in Method::ALL {
        let a = grid.deposit(method, &ParticleSet::new(&pos, &rad)).unwrap();
        let b = general
            .deposit(method, &ParticleSet::new(&pos, &rad))
            .unwrap();
        let worst = a
            .solid
            .iter()
            .zip(&b.solid)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12 * a.particle_volume, "{method}: {worst:e}");
    }
}

#[test]
fn exact_is_invariant_under_rotation_of_mesh_and_particles() {
    let m = hex_grid(
        &[0.0, 0.25, 0.6, 1.0],
        &[0.0, 0.5, 0.7, 1.0],
        &[0.0, 0.3, 1.0],
    );
    let grid = VoidageMesh::new(&m).unwrap();
    let mut rng = Rng::new(4);
    for _ in 0..10 {
        let axis = rng.point([-1.0; 3], [1.0; 3]);
        let f = affine(rotation(axis, rng.uniform(0.0, 2.0 * PI)), [5.0, -3.0, 1.0]);
        let rotated = VoidageMesh::new(&map_points(&m, &f)).unwrap();
        for _ in 0..10 {
            let c = rng.point([-0.2; 3], [1.2; 3]);
            let r = rng.uniform(0.05, 0.5);
            let (a, oa) = shares(&grid, Method::Exact, c, r);
            let (b, ob) = shares(&rotated, Method::Exact, f(c.into()), r);
            let v = ball_volume(r);
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    approx::abs_diff_eq!(x, y, epsilon = 1e-12 * v),
                    "{x} vs {y}"
                );
            }
            assert_abs_diff_eq!(oa, ob, epsilon = 1e-12 * v);
        }
    }
}

/// Exact shares on a sheared, non-axis-aligned hex mesh against Monte Carlo points located in
/// the mesh.
#[test]
fn exact_on_sheared_mesh_matches_monte_carlo() {
    let base = uniform_box([0.0; 3], [1.0; 3], [3, 3, 3]);
    let shear = affine(
        [[1.0, 0.3, 0.1], [0.0, 1.0, -0.2], [0.05, 0.0, 1.0]],
        [0.0; 3],
    );
    let m = map_points(&base, &shear);
    let vm = VoidageMesh::new(&m).unwrap();
    assert!(vm.axis_grid().is_none());
    let mut rng = Rng::new(5);
    let n = 100_000;
    for (c, r) in [
        ([0.7, 0.5, 0.6], 0.3),
        ([0.35, 0.3, 0.35], 0.2),
        ([1.2, 0.2, 0.1], 0.4),
    ] {
        check_exact_against_monte_carlo(&vm, &mut rng, c.into(), r, n);
    }
}

#[test]
fn symmetric_positions_give_mirrored_shares() {
    // A mesh symmetric under x ↦ −x (planes mirrored), graded in y and z.
    let xs = [-1.0, -0.6, -0.1, 0.1, 0.6, 1.0];
    let m = hex_grid(&xs, &[0.0, 0.2, 0.5, 1.0], &[0.0, 0.4, 0.6, 1.0]);
    let nx = xs.len() - 1;
    let mut rng = Rng::new(6);
    for opts in [MeshOptions::default(), NO_GRID] {
        let vm = VoidageMesh::with_options(&m, opts).unwrap();
        for _ in 0..20 {
            let c = rng.point([-0.9, 0.1, 0.1], [0.9, 0.9, 0.9]);
            let r = rng.uniform(0.05, 0.45);
            let mirrored = [-c[0], c[1], c[2]];
            for method in [Method::Cube, Method::CorrectedCube, Method::Exact] {
                let (a, _) = shares(&vm, method, c, r);
                let (b, _) = shares(&vm, method, mirrored, r);
                for (cell, &x) in a.iter().enumerate() {
                    let (i, rest) = (cell % nx, cell / nx);
                    let y = b[(nx - 1 - i) + nx * rest];
                    assert!(
                        approx::abs_diff_eq!(x, y, epsilon = 1e-13 * ball_volume(r)),
                        "{method} {x} {y}"
                    );
                }
            }
        }
    }
    // A particle centred on a grid node splits equally over the 8 cells around it.
    let vm = VoidageMesh::new(&uniform_box([-1.0; 3], [1.0; 3], [2, 2, 2])).unwrap();
    for method in [Method::Cube, Method::CorrectedCube, Method::Exact] {
        let (s, out) = shares(&vm, method, [0.0; 3], 0.3);
        let v = ball_volume(0.3);
        assert!(out.abs() < 1e-15 * v);
        assert!(
            s.iter().all(|&x| (x - v / 8.0).abs() < 1e-15 * v),
            "{method}"
        );
    }
}

/// Continuous methods have no jumps as a particle crosses a face; centre jumps by V, divided by
/// a multiple of V/29.
#[test]
fn continuity_across_a_face() {
    let m = hex_grid(&[0.0, 1.0, 2.0], &[0.0, 0.7, 2.0], &[0.0, 2.0]);
    for opts in [MeshOptions::default(), NO_GRID] {
        let vm = VoidageMesh::with_options(&m, opts).unwrap();
        for r in [0.3, 0.8, 1.5] {
            let v = ball_volume(r);
            let (y, z) = (0.9, 1.1);
            // The graded mesh refuses trilinear (its continuity is tested in trilinear.rs).
            for method in Method::ALL.into_iter().filter(|&m| defined_on(&vm, m)) {
                let jump = |x0: f64, x1: f64| {
                    let (a, _) = shares(&vm, method, [x0, y, z], r);
                    let (b, _) = shares(&vm, method, [x1, y, z], r);
                    a.iter()
                        .zip(&b)
                        .map(|(p, q)| (p - q).abs())
                        .fold(0.0, f64::max)
                };
                // Across the face x = 1 (the centre crosses it).
                let d = 1e-9;
                let across = jump(1.0 - d, 1.0 + d);
                match method {
                    Method::Centre => assert_abs_diff_eq!(across, v, epsilon = 1e-12 * v),
                    Method::Divided => {
                        let k = across / (v / 29.0);
                        assert!(k > 0.5 && (k - k.round()).abs() < 1e-9, "{k}");
                    }
                    // cells enter and leave as their centres do (tests/big_particle.rs,
                    // tests/gauss.rs)
                    Method::BigParticle | Method::Gauss => {}
                    _ => assert!(across < 1e-7 * v, "{method} r={r}: {across:e}"),
                }
                // The sphere's edge crossing a face (x = 1 − r, when inside the mesh).
                if r < 1.0 && method.is_continuous() {
                    let x = 2.0 - r;
                    assert!(jump(x - d, x + d) < 1e-7 * v, "{method} edge");
                }
            }
        }
    }
}

/// Cells smaller than the particle (h = d/4 and d/1.5): every method conserves and gives sane
/// shares; exact and cube match their kernels cell by cell.
#[test]
fn cells_smaller_than_particles() {
    let lo = [0.0; 3];
    let hi = [1.0; 3];
    let m = uniform_box(lo, hi, [12, 12, 12]);
    let h = 1.0 / 12.0;
    let grid = VoidageMesh::new(&m).unwrap();
    let general = VoidageMesh::with_options(&m, NO_GRID).unwrap();
    let g = grid.axis_grid().unwrap().clone();
    let mut rng = Rng::new(8);
    for d_over_h in [4.0, 1.5] {
        let r = 0.5 * d_over_h * h;
        let (pos, rad) = particles(&mut rng, 30, [r; 3], [1.0 - r; 3], r, r);
        for method in Method::ALL {
            for vm in [&grid, &general] {
                let d = vm.deposit(method, &ParticleSet::new(&pos, &rad)).unwrap();
                assert!(d.conservation_error() < 1e-12);
                assert!(
                    d.outside_volume.abs() < 1e-12 * d.particle_volume,
                    "{method}"
                );
            }
        }
        for &c in &pos[..5] {
            let v = ball_volume(r);
            let (e, _) = shares(&grid, Method::Exact, c, r);
            let (q, _) = shares(&grid, Method::Cube, c, r);
            let (eg, _) = shares(&general, Method::Exact, c, r);
            for cell in 0..e.len() {
                let [i, j, k] = g.ijk(cell as u32);
                let clo = [i as f64 * h, j as f64 * h, k as f64 * h];
                let chi = clo.map(|x| x + h);
                assert_abs_diff_eq!(
                    e[cell],
                    sphere_box_volume(c, r, clo, chi),
                    epsilon = 1e-13 * v
                );
                assert_abs_diff_eq!(eg[cell], e[cell], epsilon = 1e-12 * v);
                assert_abs_diff_eq!(
                    q[cell],
                    v * cube_fraction(c, r, clo, chi),
                    epsilon = 1e-14 * v
                );
            }
        }
    }
}

#[test]
fn exact_matches_monte_carlo_on_grid() {
    let m = hex_grid(&[0.0, 0.4, 1.0], &[0.0, 0.5, 1.0], &[0.0, 0.45, 1.0]);
    let vm = VoidageMesh::new(&m).unwrap();
    let g = vm.axis_grid().unwrap().clone();
    let mut rng = Rng::new(9);
    let c = [0.42, 0.55, 0.4];
    let r = 0.3;
    let (s, _) = shares(&vm, Method::Exact, c, r);
    for (cell, &x) in s.iter().enumerate() {
        let [i, j, k] = g.ijk(cell as u32);
        let lo = [g.planes(0)[i], g.planes(1)[j], g.planes(2)[k]];
        let hi = [g.planes(0)[i + 1], g.planes(1)[j + 1], g.planes(2)[k + 1]];
        let (mc, se) = monte_carlo(&mut rng, lo, hi, 100_000, |p| {
            (0..3).map(|a| (p[a] - c[a]).powi(2)).sum::<f64>() < r * r
        });
        assert!(
            approx::abs_diff_eq!(x, mc, epsilon = 4.5 * se),
            "cell {cell}: {x} vs {mc} ± {se}"
        );
    }
}

#[test]
fn divided_markers_outside_go_to_the_centre_cell() {
    let m = uniform_box([0.0; 3], [1.0; 3], [2, 2, 2]);
    for opts in [MeshOptions::default(), NO_GRID] {
        let vm = VoidageMesh::with_options(&m, opts).unwrap();
        // Centre at (0.05, 0.25, 0.25): the outer −x marker at x = 0.05 − 0.2·0.9085 < 0 goes
        // to the centre cell, all others are inside cell 0 too.
        let r = 0.2;
        let (s, out) = shares(&vm, Method::Divided, [0.05, 0.25, 0.25], r);
        assert_eq!(out, 0.0);
        assert_abs_diff_eq!(s[0], ball_volume(r), epsilon = 1e-15);
        // Centre outside: everything outside.
        let (s, out) = shares(&vm, Method::Divided, [-0.01, 0.25, 0.25], r);
        assert_eq!(out, ball_volume(r));
        assert!(s.iter().all(|&x| x == 0.0));
        // Markers spread over two cells: 1 + 2 (the +x axis markers) + 8 (the +x diagonal
        // markers at x offset r/2·shell) cross x = 0.5 when the centre is just below it.
        let c = [0.5 - 0.3 * r, 0.25, 0.25];
        let (s, _) = shares(&vm, Method::Divided, c, r);
        let k = s[1] / (ball_volume(r) / 29.0);
        let (ri, ro) = divided_radii();
        let expected = [ri, ro]
            .iter()
            .map(|&rr| 1 + if 0.5 * rr > 0.3 { 4 } else { 0 })
            .sum::<usize>();
        assert!(
            approx::abs_diff_eq!(k, expected as f64, epsilon = 1e-12),
            "{k} vs {expected}"
        );
    }
}

#[test]
fn hints_threads_and_clipping() {
    let m = uniform_box([0.0; 3], [1.0; 3], [4, 4, 4]);
    let mut rng = Rng::new(10);
    let (pos, rad) = particles(&mut rng, 5000, [-0.1; 3], [1.1; 3], 0.02, 0.1);
    for opts in [MeshOptions::default(), NO_GRID] {
        let vm = VoidageMesh::with_options(&m, opts).unwrap();
        for method in Method::ALL {
            let set = ParticleSet::new(&pos, &rad);
            let a = vm.deposit(method, &set).unwrap();
            // Hints from the first call, and some wrong hints.
            let mut cells = vec![None; pos.len()];
            vm.deposit_with_cells(method, &set, &mut cells).unwrap();
            for (i, c) in cells.iter_mut().enumerate() {
                if i % 3 == 0 {
                    *c = Some((i % 64) as u32);
                }
            }
            let b = vm.deposit_with_cells(method, &set, &mut cells).unwrap();
            assert_eq!(a, b);
            let located = vm.locator().locate_all(&pos);
            assert_eq!(cells, located);
            // One thread gives the same bits.
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            let c = pool.install(|| vm.deposit(method, &set).unwrap());
            assert_eq!(a, c);
        }
    }
    // Clipping: the centre method overfills cells; the clipped volume is reported.
    let vm = VoidageMesh::new(&m).unwrap();
    let d = vm
        .deposit(Method::Centre, &ParticleSet::new(&pos, &rad))
        .unwrap();
    let free = vm.voidage(&d, None).unwrap();
    assert!(free.negative_cells > 0 && free.min_epsilon < 0.0);
    let alpha = 0.3;
    let clipped = vm.voidage(&d, Some(alpha)).unwrap();
    let mut expect = 0.0;
    let mut n = 0;
    for (cell, &e) in free.epsilon.iter().enumerate() {
        let v = vm.cell_volumes()[cell];
        assert_abs_diff_eq!(e, (1.0 - d.solid[cell] / v), epsilon = 1e-15);
        if e < alpha {
            expect += (alpha - e) * v;
            n += 1;
            assert_eq!(clipped.epsilon[cell], alpha);
        } else {
            assert_eq!(clipped.epsilon[cell], e);
        }
    }
    assert!(n > 0);
    assert_eq!(clipped.clipped_cells, n);
    assert_abs_diff_eq!(
        clipped.clipped_volume,
        expect,
        epsilon = 1e-15 * expect.max(1e-300)
    );
    // Solid kept + clipped = deposited.
    let kept: f64 = clipped
        .epsilon
        .iter()
        .zip(vm.cell_volumes())
        .map(|(e, v)| (1.0 - e) * v)
        .sum();
    assert_relative_eq!(
        kept + clipped.clipped_volume,
        d.deposited_volume,
        epsilon = 1e-12 * 1.0,
        max_relative = 1e-12
    );
}

/// Particles whose centre lies outside the mesh still deposit the part of their ball inside
/// it (exact, cube) on general meshes, through the bin index.
#[test]
fn centre_outside_general_mesh() {
    let m = map_points(
        &uniform_box([0.0; 3], [1.0; 3], [3, 3, 3]),
        affine(rotation([0.0, 0.0, 1.0], 0.3), [0.0; 3]),
    );
    let vm = VoidageMesh::new(&m).unwrap();
    let unrotate = affine(rotation([0.0, 0.0, 1.0], -0.3), [0.0; 3]);
    let rot = affine(rotation([0.0, 0.0, 1.0], 0.3), [0.0; 3]);
    let c = rot([-0.1, 0.5, 0.5]);
    let r = 0.25;
    assert!(vm.locator().locate(c.into()).is_none());
    let (s, out) = shares(&vm, Method::Exact, c, r);
    let inside = sphere_box_volume(unrotate(c), r, [0.0; 3], [1.0; 3]);
    assert_abs_diff_eq!(
        s.iter().sum::<f64>(),
        inside,
        epsilon = 1e-13 * ball_volume(r)
    );
    assert_abs_diff_eq!(
        out,
        (ball_volume(r) - inside),
        epsilon = 1e-13 * ball_volume(r)
    );
    let (s, _) = shares(&vm, Method::Centre, c, r);
    assert!(s.iter().all(|&x| x == 0.0));
}

/// A hex mesh with jittered points (warped, non-planar faces; the flux goes over the fan
/// triangles) and planar-faced cells alike: exact shares equal Σ ball ∩ tet over the cell's
/// tets, and the volume is conserved.
#[test]
fn warped_faces_match_tets() {
    let mut rng = Rng::new(12);
    let base = uniform_box([0.0; 3], [1.0; 3], [4, 4, 4]);
    let mut m = base.clone();
    for p in &mut m.points {
        let interior = p.iter().all(|&x| x > 0.0 && x < 1.0);
        if interior {
            *p = p.map(|x| x + rng.uniform(-0.04, 0.04));
        }
    }
    let vm = VoidageMesh::new(&m).unwrap();
    assert!(vm.axis_grid().is_none());
    for _ in 0..40 {
        let c = rng.point([0.1; 3], [0.9; 3]);
        let r = rng.uniform(0.05, 0.4);
        let v = ball_volume(r);
        let (s, out) = shares(&vm, Method::Exact, c, r);
        for (cell, &x) in s.iter().enumerate() {
            let by_tets = tet_sum(&vm, cell, c, r);
            assert!(
                approx::abs_diff_eq!(x, by_tets, epsilon = 1e-13 * v),
                "cell {cell}: {x} vs {by_tets}"
            );
        }
        let inside = sphere_box_volume(c, r, [0.0; 3], [1.0; 3]);
        assert_abs_diff_eq!(out, (v - inside), epsilon = 1e-13 * v);
    }
}
