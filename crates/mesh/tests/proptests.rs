//! Property tests: random affine maps of random graded Cartesian grids.

use mesh::build::{affine, graded_planes, hex_grid, map_points};
use mesh::{Locator, MeshError, MeshGeometry};
use proptest::prelude::*;

fn det3(a: &[[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

fn matrix() -> impl Strategy<Value = [[f64; 3]; 3]> {
    prop::array::uniform3(prop::array::uniform3(-0.6f64..0.6)).prop_map(|mut a| {
        for (i, row) in a.iter_mut().enumerate() {
            row[i] += 1.5;
        }
        a
    })
}

fn grid() -> impl Strategy<Value = (Vec<f64>, Vec<f64>, Vec<f64>)> {
    let axis = (1usize..5, 0.2f64..5.0, -3.0f64..3.0, 0.1f64..4.0)
        .prop_map(|(n, ratio, x0, len)| graded_planes(x0, x0 + len, n, ratio));
    (axis.clone(), axis.clone(), axis)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn affine_maps_scale_volumes_by_the_determinant(
        (xs, ys, zs) in grid(),
        a in matrix(),
        b in prop::array::uniform3(-10.0f64..10.0),
    ) {
        let m0 = hex_grid(&xs, &ys, &zs);
        let g0 = MeshGeometry::new(&m0).unwrap();
        let det = det3(&a);
        prop_assume!(det > 0.05);
        let map = affine(a, b);
        let m1 = map_points(&m0, &map);
        let g1 = MeshGeometry::new(&m1).unwrap();
        let box_volume = (xs[xs.len() - 1] - xs[0]) * (ys[ys.len() - 1] - ys[0]) * (zs[zs.len() - 1] - zs[0]);
        let scale = g1.bounds.extent().iter().cloned().fold(0.0, f64::max);
        prop_assert!((g1.total_volume() - det * box_volume).abs() <= 1e-12 * det * box_volume);
        for c in 0..m0.n_cells {
            let v = det * g0.cell_volumes[c];
            prop_assert!((g1.cell_volumes[c] - v).abs() <= 1e-11 * v, "cell {}", c);
            let expected = map(g0.cell_centres[c].into());
            for (x, y) in g1.cell_centres[c].iter().zip(expected) {
                prop_assert!((x - y).abs() <= 1e-12 * scale);
            }
        }
        // The same map with a mirror inverts every cell.
        let mirrored = map_points(&m1, |p| [-p[0], p[1], p[2]]);
        let inverted = matches!(MeshGeometry::new(&mirrored), Err(MeshError::InvertedCell { .. }));
        prop_assert!(inverted);
    }

    #[test]
    fn located_cell_is_the_cell_of_the_pre_image(
        (xs, ys, zs) in grid(),
        a in matrix(),
        q in prop::collection::vec(prop::array::uniform3(0.0f64..1.0), 32),
    ) {
        prop_assume!(det3(&a) > 0.05);
        let m0 = hex_grid(&xs, &ys, &zs);
        let map = affine(a, [0.3, -0.2, 0.1]);
        let m1 = map_points(&m0, &map);
        let g1 = MeshGeometry::new(&m1).unwrap();
        let loc = Locator::new(&m1, &g1).unwrap();
        let lerp = |pl: &[f64], t: f64| pl[0] + t * (pl[pl.len() - 1] - pl[0]);
        let idx = |pl: &[f64], x: f64| pl.windows(2).position(|w| w[0] <= x && x < w[1]);
        for t in q {
            let p0 = [lerp(&xs, t[0]), lerp(&ys, t[1]), lerp(&zs, t[2])];
            let near = [&xs, &ys, &zs].iter().zip(p0).any(|(pl, x)| pl.iter().any(|&y| (x - y).abs() < 1e-9));
            if near {
                continue;
            }
            let (i, j, k) = (idx(&xs, p0[0]).unwrap(), idx(&ys, p0[1]).unwrap(), idx(&zs, p0[2]).unwrap());
            let cell = (i + (xs.len() - 1) * (j + (ys.len() - 1) * k)) as u32;
            prop_assert_eq!(loc.locate(map(p0).into()), Some(cell));
        }
    }
}
