//! Point location against brute force over every tet, against the pre-image on affine-mapped
//! grids, and fast path against general path (including points exactly on grid planes).

mod common;

use approx::assert_relative_eq;
use common::*;
use foam::{Label, PolyMesh};
use mesh::build::{affine, graded_planes, hex_grid, map_points};
use mesh::v3::V3;
use mesh::{Locator, LocatorOptions, MeshGeometry, TetDecomposition};

fn locator(m: &PolyMesh, fast: bool) -> Locator {
    let g = MeshGeometry::new(m).unwrap();
    Locator::with_options(
        m,
        &g,
        LocatorOptions {
            axis_aligned_fast_path: fast,
        },
    )
    .unwrap()
}

/// Every cell whose tets contain `p`, by testing all tets of all cells.
fn brute_force(t: &TetDecomposition, p: V3) -> Vec<Label> {
    (0..t.n_cells() as Label)
        .filter(|&c| t.cell_contains(c, p))
        .collect()
}

fn random_points(rng: &mut Rng, b: &mesh::Aabb, n: usize, grow: f64) -> Vec<V3> {
    let e = b.extent();
    (0..n)
        .map(|_| V3::from_fn(|a, _| rng.range(b.min[a] - grow * e[a], b.max[a] + grow * e[a])))
        .collect()
}

fn sheared_grid() -> (PolyMesh, impl Fn([f64; 3]) -> [f64; 3]) {
    let m = hex_grid(
        &graded_planes(0.0, 1.0, 6, 2.5),
        &graded_planes(0.0, 1.0, 5, 0.4),
        &graded_planes(0.0, 1.0, 4, 1.0),
    );
    let map = affine(
        [[0.8, 0.3, -0.2], [-0.25, 0.9, 0.35], [0.1, -0.2, 1.1]],
        [0.5, -1.0, 2.0],
    );
    (map_points(&m, &map), map)
}

fn check_against_brute_force(m: &PolyMesh, n: usize, seed: u64) -> (usize, usize) {
    let loc = locator(m, true);
    let g = MeshGeometry::new(m).unwrap();
    let mut rng = Rng(seed);
    let pts = random_points(&mut rng, &g.bounds, n, 0.1);
    let got = loc.locate_all(&pts);
    let mut inside = 0;
    for (p, &c) in pts.iter().zip(&got) {
        let bf = brute_force(loc.tets(), *p);
        assert!(bf.len() <= 1, "{p:?} in several cells {bf:?}");
        assert_eq!(c, bf.first().copied(), "point {p:?}");
        inside += bf.len();
    }
    (inside, n - inside)
}

#[test]
fn locate_equals_brute_force_on_openfoam_meshes() {
    for (case, seed) in [("skewed_blocks", 1), ("poly_dual", 2), ("box_blocks", 3)] {
        let (inside, outside) = check_against_brute_force(&fixture_mesh(case), 1500, seed);
        assert!(
            inside > 250 && outside > 150,
            "{case}: {inside} in, {outside} out"
        );
    }
}

#[test]
fn locate_equals_brute_force_and_pre_image_on_a_sheared_grid() {
    let (m, _) = sheared_grid();
    check_against_brute_force(&m, 1500, 4);
    // Independent reference: map random points of the unit cube and find the original cell.
    let orig = hex_grid(
        &graded_planes(0.0, 1.0, 6, 2.5),
        &graded_planes(0.0, 1.0, 5, 0.4),
        &graded_planes(0.0, 1.0, 4, 1.0),
    );
    let go = MeshGeometry::new(&orig).unwrap();
    let grid = Locator::new(&orig, &go).unwrap();
    let grid = grid.axis_grid().expect("the unmapped grid is axis-aligned");
    let (_, map) = sheared_grid();
    let loc = locator(&m, true);
    assert!(loc.axis_grid().is_none());
    let mut rng = Rng(5);
    for _ in 0..5000 {
        let q: V3 = V3::from_fn(|_, _| rng.unit());
        let near_plane = (0..3).any(|a| grid.planes(a).iter().any(|&x| (x - q[a]).abs() < 1e-9));
        if near_plane {
            continue;
        }
        assert_eq!(
            loc.locate(map(q.into()).into()),
            grid.locate(q),
            "pre-image {q:?}"
        );
    }
}

#[test]
fn every_cell_centre_is_located_in_its_cell() {
    let meshes = [
        fixture_mesh("skewed_blocks"),
        fixture_mesh("poly_dual"),
        fixture_mesh("box_blocks"),
        sheared_grid().0,
    ];
    for m in &meshes {
        let g = MeshGeometry::new(m).unwrap();
        for fast in [true, false] {
            let loc = locator(m, fast);
            let got = loc.locate_all(&g.cell_centres);
            for (c, &l) in got.iter().enumerate() {
                assert_eq!(l, Some(c as Label), "fast {fast} cell {c} of {}", m.n_cells);
            }
        }
    }
}

#[test]
fn points_outside_return_none() {
    for m in [fixture_mesh("skewed_blocks"), fixture_mesh("poly_dual")] {
        let g = MeshGeometry::new(&m).unwrap();
        let loc = locator(&m, true);
        let b = g.bounds;
        let e = b.extent();
        for p in [
            [
                b.min[0] - 0.01 * e[0],
                g.cell_centres[0][1],
                g.cell_centres[0][2],
            ],
            [b.max[0] + 1e-12, b.max[1], b.max[2]],
            [f64::NAN, 0.0, 0.0],
            [1e300, -1e300, 0.0],
        ]
        .map(V3::from)
        {
            assert_eq!(loc.locate(p), None, "{p:?}");
            assert_eq!(loc.locate_from(p, 0), None, "{p:?}");
        }
        // Beyond each boundary face centre, along its outward normal.
        for patch in &m.boundary {
            for f in patch.faces() {
                let n = g.face_areas[f];
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                let p: V3 =
                    V3::from_fn(|a, _| g.face_centres[f][a] + 1e-3 * e[a].max(e[0]) * n[a] / len);
                assert_eq!(loc.locate(p), None);
                assert!(brute_force(loc.tets(), p).is_empty());
            }
        }
    }
}

/// The warped, polyhedral and sheared meshes of the general path's tests.
fn general_meshes() -> [PolyMesh; 3] {
    [
        fixture_mesh("skewed_blocks"),
        fixture_mesh("poly_dual"),
        sheared_grid().0,
    ]
}

#[test]
fn locate_from_any_hint_agrees_with_locate() {
    for m in general_meshes() {
        let g = MeshGeometry::new(&m).unwrap();
        let loc = locator(&m, true);
        let mut rng = Rng(6);
        let pts = random_points(&mut rng, &g.bounds, 2000, 0.05);
        let plain = loc.locate_all(&pts);
        let mut hinted: Vec<Option<Label>> = (0..pts.len())
            .map(|i| (i % 5 != 0).then(|| rng.below(m.n_cells) as Label))
            .collect();
        let hints = hinted.clone();
        loc.locate_all_from(&pts, &mut hinted);
        assert_eq!(hinted, plain);
        for ((p, h), c) in pts.iter().zip(&hints).zip(&plain) {
            if let Some(h) = h {
                assert_eq!(loc.locate_from(*p, *h), *c);
            }
        }
        assert_eq!(loc.locate_from(pts[0], u32::MAX), plain[0]);
    }
}

/// Random points of which many have coordinates exactly on grid planes (including the lower
/// and upper domain boundaries), plus some outside.
fn grid_points(rng: &mut Rng, planes: [&[f64]; 3], n: usize) -> Vec<V3> {
    (0..n)
        .map(|_| {
            V3::from_fn(|a, _| {
                let pl = planes[a];
                let (lo, hi) = (pl[0], pl[pl.len() - 1]);
                match rng.below(3) {
                    0 => pl[rng.below(pl.len())],
                    _ => rng.range(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo)),
                }
            })
        })
        .collect()
}

#[test]
fn fast_path_and_general_path_agree_including_points_on_grid_planes() {
    let programmatic = hex_grid(
        &graded_planes(-1.0, 2.0, 9, 4.0),
        &graded_planes(0.1, 0.7, 6, 0.3),
        &graded_planes(5.0, 5.5, 5, 1.0),
    );
    for m in [programmatic, fixture_mesh("box_blocks")] {
        let fast = locator(&m, true);
        let general = locator(&m, false);
        let grid = fast.axis_grid().expect("axis-aligned grid detected");
        assert!(general.axis_grid().is_none());
        let planes = [grid.planes(0), grid.planes(1), grid.planes(2)];
        let mut rng = Rng(7);
        let pts = grid_points(&mut rng, planes, 20000);
        let (mut on_plane, mut outside) = (0, 0);
        for p in &pts {
            let f = fast.locate(*p);
            assert_eq!(f, general.locate(*p), "{p:?}");
            assert_eq!(f, general.locate_general(*p), "{p:?}");
            // Independent half-open reference by linear scan of the planes.
            let idx = |a: usize| {
                planes[a]
                    .windows(2)
                    .position(|w| w[0] <= p[a] && p[a] < w[1])
            };
            let reference = match (idx(0), idx(1), idx(2)) {
                (Some(i), Some(j), Some(k)) => Some(grid.cell(i, j, k)),
                _ => None,
            };
            assert_eq!(f, reference, "{p:?}");
            on_plane += (0..3).any(|a| planes[a].contains(&p[a])) as usize;
            outside += f.is_none() as usize;
        }
        assert!(on_plane > 10000 && outside > 1000, "{on_plane} {outside}");
        // Corners of the grid: lower corner inside, upper faces outside.
        let n = grid.dims();
        let lo = V3::new(planes[0][0], planes[1][0], planes[2][0]);
        assert_eq!(general.locate(lo), Some(grid.cell(0, 0, 0)));
        let hi = V3::new(planes[0][n[0]], planes[1][0], planes[2][0]);
        assert_eq!(general.locate(hi), None);
        // A grid node in the interior belongs to the cell above it in x, y and z.
        let node = V3::new(planes[0][2], planes[1][1], planes[2][1]);
        assert_eq!(general.locate(node), Some(grid.cell(2, 1, 1)));
        assert_eq!(fast.locate(node), Some(grid.cell(2, 1, 1)));
    }
}

#[test]
fn multi_block_grid_map_matches_cell_geometry() {
    let m = fixture_mesh("box_blocks");
    let g = MeshGeometry::new(&m).unwrap();
    let loc = Locator::new(&m, &g).unwrap();
    let grid = loc.axis_grid().unwrap();
    assert_eq!(grid.dims(), [9, 3, 2]);
    let mut seen = vec![false; m.n_cells];
    for k in 0..2 {
        for j in 0..3 {
            for i in 0..9 {
                let c = grid.cell(i, j, k);
                assert!(!seen[c as usize]);
                seen[c as usize] = true;
                assert_eq!(grid.ijk(c), [i, j, k]);
                let box_vol = (grid.planes(0)[i + 1] - grid.planes(0)[i])
                    * (grid.planes(1)[j + 1] - grid.planes(1)[j])
                    * (grid.planes(2)[k + 1] - grid.planes(2)[k]);
                assert_relative_eq!(
                    box_vol,
                    g.cell_volumes[c as usize],
                    epsilon = 0.0,
                    max_relative = 1e-12
                );
            }
        }
    }
    // Block 0 cells come first in blockMesh numbering, so the map is not the identity.
    assert_ne!(grid.cells(), (0..54).collect::<Vec<Label>>());
}

/// `Locator::cell_surely_holds` never claims a cell that brute force does not give (nor
/// `cell_surely_lacks` rejects one it gives), for points
/// at every scale of distance from the faces (down to 1e-15 of the face size, on both sides),
/// on meshes with warped faces, polyhedra and sheared cells; and it does claim points well
/// inside (the cell centres of hexahedra with planar faces).
#[test]
fn surely_holds_agrees_with_brute_force_near_faces() {
    for m in general_meshes() {
        let g = MeshGeometry::new(&m).unwrap();
        let loc = locator(&m, false);
        let t = loc.tets();
        let mut rng = Rng(11);
        let mut claimed = 0;
        for f in 0..m.n_faces() {
            let apex = t.face_apexes()[f];
            let a = V3::from(g.face_areas[f]);
            let n = a / a.norm();
            let size = a.norm().sqrt();
            for _ in 0..6 {
                let scale = 10f64.powf(rng.range(-15.0, -0.5)) * size;
                let side = if rng.below(2) == 0 { 1.0 } else { -1.0 };
                // A point near the face plane, somewhere over the face.
                let q = m.faces.face(f)[rng.below(m.faces.face(f).len())] as usize;
                let s = rng.range(0.0, 1.0);
                let p = apex + s * (t.points()[q] - apex) + side * scale * n;
                let bf = brute_force(t, p);
                let mut cells = vec![m.owner[f]];
                if f < m.n_internal_faces() {
                    cells.push(m.neighbour[f]);
                }
                for c in cells {
                    if loc.cell_surely_holds(c, p) {
                        assert_eq!(bf, vec![c], "face {f}, point {p:?}");
                        claimed += 1;
                    }
                    if loc.cell_surely_lacks(c, p) {
                        assert!(!bf.contains(&c), "face {f}, point {p:?}");
                    }
                }
            }
        }
        assert!(claimed > 0);
        for (c, centre) in g.cell_centres.iter().enumerate() {
            if loc.cell_surely_holds(c as Label, V3::from(*centre)) {
                assert_eq!(brute_force(t, V3::from(*centre)), vec![c as Label]);
            }
        }
    }
    let (m, _) = sheared_grid();
    let g = MeshGeometry::new(&m).unwrap();
    let loc = locator(&m, false);
    for (c, centre) in g.cell_centres.iter().enumerate() {
        assert!(loc.cell_surely_holds(c as Label, V3::from(*centre)));
    }
}

/// `Locator::locate_near` gives `locate`'s answer for clusters of points around a located
/// centre (marker-like offsets of every size, some reaching outside the mesh or exactly onto
/// face planes of a grid).
#[test]
fn locate_near_agrees_with_locate() {
    let planes = graded_planes(0.0, 1.0, 5, 1.0);
    for m in [
        fixture_mesh("skewed_blocks"),
        fixture_mesh("poly_dual"),
        sheared_grid().0,
        hex_grid(&planes, &planes, &planes),
    ] {
        let g = MeshGeometry::new(&m).unwrap();
        let loc = locator(&m, false);
        let mut rng = Rng(12);
        let h = (g.total_volume() / m.n_cells as f64).cbrt();
        let offsets: Vec<V3> = (0..28)
            .map(|k| {
                if k < 6 {
                    // Axis directions: on a grid of spacing 0.25 these land on planes.
                    let mut v = V3::zeros();
                    v[k / 2] = if k % 2 == 0 { 1.0 } else { -1.0 };
                    v
                } else {
                    V3::from_fn(|_, _| rng.range(-0.6, 0.6))
                }
            })
            .collect();
        let centres = random_points(&mut rng, &g.bounds, 600, 0.0);
        let mut checked = 0;
        for (i, c) in centres.iter().enumerate() {
            // Every third centre on the 1/8 lattice: on the grid, offsets along the axes of
            // 0.25 then end exactly on face planes.
            let c = &if i % 3 == 0 {
                c.map(|x| (x * 8.0).round() / 8.0)
            } else {
                *c
            };
            let Some(cell) = loc.locate(*c) else { continue };
            let scale = if i % 3 == 0 {
                0.25
            } else {
                h * 10f64.powf(rng.range(-3.0, 0.3))
            };
            loc.locate_near(cell, *c, scale, &offsets, |k, got| {
                let p = V3::from_fn(|a, _| c[a] + scale * offsets[k][a]);
                assert_eq!(got, loc.locate(p), "centre {c:?}, offset {k}");
                checked += 1;
            });
        }
        assert!(checked > 1000);
    }
}

/// The clearance `Locator::locate_near_clearance` returns is a true bound: moving the centre (and so
/// every point of the cluster) by any vector shorter than it leaves every point in the cell
/// `locate` gave it, checked against `locate` at the moved points in random directions up to
/// 0.999999 of the clearance. Clusters that needed a walk report a clearance too (from their
/// cell's faces at the point), so almost every cluster inside the mesh has one.
#[test]
fn locate_near_clearance_bounds_the_motion_that_keeps_every_answer() {
    for m in general_meshes() {
        let g = MeshGeometry::new(&m).unwrap();
        let loc = locator(&m, false);
        let mut rng = Rng(41);
        let h = (g.total_volume() / m.n_cells as f64).cbrt();
        let offsets = mesh_marker_offsets();
        let centres = random_points(&mut rng, &g.bounds, 800, 0.0);
        let (mut bounded, mut clusters, mut moved, mut beyond) = (0, 0, 0, 0);
        for c in &centres {
            let Some(cell) = loc.locate(*c) else { continue };
            let scale = h * 10f64.powf(rng.range(-1.5, -0.2));
            let mut answers = vec![None; offsets.len()];
            let clearance =
                loc.locate_near_clearance(cell, *c, scale, &offsets, |k, got| answers[k] = got);
            assert!(clearance >= 0.0, "clearance {clearance}");
            if answers.iter().all(|a| a.is_some()) {
                clusters += 1;
            }
            if clearance == 0.0 {
                continue;
            }
            if answers.iter().any(|a| a.is_none()) {
                panic!("a clearance {clearance} with a point outside the mesh, centre {c:?}");
            }
            bounded += 1;
            let room = clearance.min(h);
            for t in [0.5, 0.9, 0.999, 0.999999] {
                for _ in 0..4 {
                    let u = loop {
                        let u = V3::from_fn(|_, _| rng.range(-1.0, 1.0));
                        if u.norm() > 0.1 && u.norm() <= 1.0 {
                            break u / u.norm();
                        }
                    };
                    let c2 = c + t * room * u;
                    for (k, o) in offsets.iter().enumerate() {
                        let p = V3::from_fn(|a, _| c2[a] + scale * o[a]);
                        assert_eq!(
                            loc.locate(p),
                            answers[k],
                            "centre {c:?} moved {} of clearance {clearance}, point {k}",
                            t
                        );
                        moved += 1;
                    }
                }
            }
            // The bound is not vacuous: 20 times farther, some answers change.
            let c2 = c + 20.0 * clearance.min(h) * V3::new(0.48, -0.6, 0.64);
            beyond += offsets
                .iter()
                .zip(&answers)
                .filter(|(o, got)| loc.locate(V3::from_fn(|a, _| c2[a] + scale * o[a])) != **got)
                .count();
        }
        eprintln!("{bounded} of {clusters} clusters inside the mesh have a clearance");
        assert!(
            bounded * 10 > 9 * clusters,
            "{bounded} of {clusters} clusters inside the mesh have a clearance"
        );
        assert!(moved > 10_000);
        assert!(beyond > 0, "moving 20 clearances changed no answer");
    }
}

/// CFDEM's 29 `divided` marker offsets of a unit ball without the centre: 8 diagonal and 6
/// axis directions on two shells (radii 0.6276 and 0.9085, as in the voidage crate).
fn mesh_marker_offsets() -> Vec<V3> {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut dirs = Vec::new();
    for x in [-0.5, 0.5] {
        for y in [-0.5, 0.5] {
            for z in [-s, s] {
                dirs.push(V3::new(x, y, z));
            }
        }
    }
    for a in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut v = V3::zeros();
            v[a] = sign;
            dirs.push(v);
        }
    }
    [0.627607, 0.908528]
        .iter()
        .flat_map(|&r| dirs.iter().map(move |d| r * d))
        .collect()
}
