//! Geometry against OpenFOAM v1912's own numbers (fixtures made by blockMesh, polyDualMesh,
//! `postProcess -func writeCellVolumes/writeCellCentres`, checkMesh; see
//! tests/fixtures/mesh/README.md).

mod common;

use common::*;
use mesh::v3::V3;
use mesh::{MeshGeometry, TetDecomposition};

const CASES: [&str; 3] = ["skewed_blocks", "poly_dual", "box_blocks"];

/// Largest relative deviations (volume, centre) of our geometry from OpenFOAM's for one case.
fn deviations(case: &str) -> (f64, f64, usize) {
    let m = fixture_mesh(case);
    let g = MeshGeometry::new(&m).unwrap();
    let v = fixture_volumes(case, m.n_cells);
    let c = fixture_centres(case, m.n_cells);
    let size = g.bounds.extent().iter().cloned().fold(0.0, f64::max);
    let mut dv = 0.0f64;
    let mut dc = 0.0f64;
    let mut bit_identical = 0;
    for i in 0..m.n_cells {
        dv = dv.max(rel(g.cell_volumes[i], v[i], 0.0));
        for (x, y) in g.cell_centres[i].iter().zip(&c[i]) {
            dc = dc.max((x - y).abs() / size);
        }
        if g.cell_volumes[i] == v[i] && g.cell_centres[i] == V3::from(c[i]) {
            bit_identical += 1;
        }
    }
    (dv, dc, bit_identical)
}

#[test]
fn cell_volumes_and_centres_match_openfoam() {
    for case in CASES {
        let (dv, dc, same) = deviations(case);
        let n = fixture_mesh(case).n_cells;
        println!("{case}: {n} cells, max rel volume dev {dv:e}, max centre dev/size {dc:e}, bit-identical {same}/{n}");
        assert!(dv <= 1e-12, "{case}: volume deviation {dv:e}");
        assert!(dc <= 1e-12, "{case}: centre deviation {dc:e}");
    }
}

#[test]
fn total_volume_matches_checkmesh() {
    for case in CASES {
        let m = fixture_mesh(case);
        let g = MeshGeometry::new(&m).unwrap();
        let reference = fixture_checkmesh_total_volume(case);
        let d = rel(g.total_volume(), reference, 0.0);
        println!(
            "{case}: total {} vs checkMesh {reference}: {d:e}",
            g.total_volume()
        );
        assert!(d <= 1e-12, "{case}: {d:e}");
    }
}

#[test]
fn fixtures_are_what_they_claim() {
    // The skewed case has warped faces, the dual case non-quadrilateral faces: otherwise the
    // comparison above would not exercise the fan formula.
    let m = fixture_mesh("skewed_blocks");
    let g = MeshGeometry::new(&m).unwrap();
    let warped = m.faces.iter().enumerate().any(|(f, face)| {
        let n = g.face_areas[f];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        face.iter().any(|&q| {
            let p = m.points[q as usize];
            let d: f64 = (0..3)
                .map(|k| (p[k] - g.face_centres[f][k]) * n[k] / len)
                .sum();
            d.abs() > 1e-3 * len.sqrt()
        })
    });
    assert!(warped);
    let dual = fixture_mesh("poly_dual");
    assert!(dual.faces.iter().any(|f| f.len() > 4));
    assert!(mesh::AxisGrid::detect(&fixture_mesh("box_blocks")).is_some());
    assert!(mesh::AxisGrid::detect(&m).is_none());
}

#[test]
fn tets_tile_openfoam_cells() {
    for case in CASES {
        let m = fixture_mesh(case);
        let g = MeshGeometry::new(&m).unwrap();
        let tets = TetDecomposition::new(&m, &g).unwrap();
        let mut worst = 0.0f64;
        for c in 0..m.n_cells as u32 {
            let s: f64 = tets.cell_tets(c).map(|t| t.volume()).sum();
            worst = worst.max(rel(s, g.cell_volumes[c as usize], 0.0));
            assert!(
                tets.cell_tets(c).all(|t| t.volume() > 0.0),
                "{case} cell {c}"
            );
        }
        assert!(worst < 1e-12, "{case}: {worst:e}");
    }
}
