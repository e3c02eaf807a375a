//! Helpers shared by the integration tests: a small deterministic RNG, fixture loading,
//! hand-built single-cell meshes, and an independent divergence-theorem volume.
#![allow(dead_code)]

use foam::{FieldValues, Label, PolyMesh, VolField};
use mesh::build::single_cell;
use std::path::PathBuf;

/// SplitMix64: deterministic pseudo-random numbers for reproducible tests (testkit's).
#[allow(unused_imports)]
pub use testkit::SplitMix as Rng;

/// Relative difference |a − b| / max(|b|, floor).
pub fn rel(a: f64, b: f64, floor: f64) -> f64 {
    (a - b).abs() / b.abs().max(floor)
}

pub fn fixture_dir(case: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/fixtures/mesh")
        .join(case)
}

/// The polyMesh of a fixture case, read by the foam crate.
pub fn fixture_mesh(case: &str) -> PolyMesh {
    foam::read_poly_mesh(&fixture_dir(case).join("constant/polyMesh"))
        .unwrap_or_else(|e| panic!("reading fixture {case}: {e}"))
}

/// OpenFOAM's cell volumes (0/V) of a fixture.
pub fn fixture_volumes(case: &str, n_cells: usize) -> Vec<f64> {
    let f = VolField::read(&fixture_dir(case).join("0/V")).expect("reading V");
    match f.internal(n_cells).expect("V internal field") {
        FieldValues::Scalar(v) => v,
        other => panic!("V is not scalar: {:?}", other.kind()),
    }
}

/// OpenFOAM's cell centres (0/C) of a fixture.
pub fn fixture_centres(case: &str, n_cells: usize) -> Vec<[f64; 3]> {
    let f = VolField::read(&fixture_dir(case).join("0/C")).expect("reading C");
    match f.internal(n_cells).expect("C internal field") {
        FieldValues::Vector(v) => v,
        other => panic!("C is not vector: {:?}", other.kind()),
    }
}

/// checkMesh's "Total volume = …" of a fixture (printed with 17 digits).
pub fn fixture_checkmesh_total_volume(case: &str) -> f64 {
    let log = std::fs::read_to_string(fixture_dir(case).join("checkMesh.log")).unwrap();
    let tail = log
        .split("Total volume = ")
        .nth(1)
        .expect("Total volume line");
    let num = tail.split(|c: char| c.is_whitespace()).next().unwrap();
    num.trim_end_matches('.').parse().unwrap()
}

/// The tetrahedron (a, b, c, d), positively oriented input expected.
pub fn tet_mesh(p: [[f64; 3]; 4]) -> PolyMesh {
    // Outward faces of a positively oriented tet (a, b, c, d).
    single_cell(
        p.to_vec(),
        &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[0, 3, 2]],
    )
}

/// A prism: base triangle (0, 1, 2) counter-clockwise seen from +z side, top = base + `shift`.
pub fn prism_mesh(base: [[f64; 3]; 3], shift: [f64; 3]) -> PolyMesh {
    let mut pts = base.to_vec();
    for b in base {
        pts.push([b[0] + shift[0], b[1] + shift[1], b[2] + shift[2]]);
    }
    single_cell(
        pts,
        &[
            &[0, 2, 1],
            &[3, 4, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ],
    )
}

/// The hexahedron with the eight given corners in blockMesh order (0-3 bottom counter-clockwise
/// seen from above, 4-7 above them).
pub fn hex_mesh(p: [[f64; 3]; 8]) -> PolyMesh {
    single_cell(
        p.to_vec(),
        &[
            &[0, 4, 7, 3],
            &[1, 2, 6, 5],
            &[0, 1, 5, 4],
            &[3, 7, 6, 2],
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
        ],
    )
}

/// Volume and centroid of a closed surface given as triangles (outward), by the divergence
/// theorem with tets from the origin — independent of any cell-centre estimate.
pub fn closed_surface_volume_centroid(tris: &[[[f64; 3]; 3]]) -> (f64, [f64; 3]) {
    let mut v = 0.0;
    let mut m = [0.0; 3];
    for t in tris {
        let [a, b, c] = *t;
        let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]);
        let vt = det / 6.0;
        v += vt;
        for (k, mk) in m.iter_mut().enumerate() {
            *mk += vt * (a[k] + b[k] + c[k]) / 4.0;
        }
    }
    (v, [m[0] / v, m[1] / v, m[2] / v])
}

/// The boundary triangles of cell `cell`: each face fanned from the given face apex, oriented
/// out of the cell.
pub fn cell_surface(mesh: &PolyMesh, apex: &[mesh::v3::V3], cell: Label) -> Vec<[[f64; 3]; 3]> {
    let mut tris = Vec::new();
    for (f, face) in mesh.faces.iter().enumerate() {
        let own = mesh.owner[f] == cell;
        let nei = mesh.neighbour.get(f) == Some(&cell);
        if !own && !nei {
            continue;
        }
        let n = face.len();
        for i in 0..n {
            let p = mesh.points[face[i] as usize];
            let q = mesh.points[face[(i + 1) % n] as usize];
            let a = apex[f].into();
            tris.push(if own { [a, p, q] } else { [a, q, p] });
        }
    }
    tris
}
