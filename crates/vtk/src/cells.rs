//! From OpenFOAM's face-based cells to VTK cells.
//!
//! Each cell's faces are gathered and oriented outward (a face keeps its order in its owner and
//! is reversed in its neighbour). The cell is then matched against VTK's linear 3-D cells —
//! tetrahedron, hexahedron, pyramid — by mapping the VTK reference cell's outward faces
//! onto the cell's faces: one reference face is laid onto one cell face, every other reference
//! point follows from shared edges, and the match is accepted only if every reference face then
//! coincides with a distinct cell face, point for point and with the same orientation. Anything
//! that does not match exactly (split faces, extra points on edges, repeated faces) becomes a
//! `VTK_POLYHEDRON` with an explicit outward face stream, which is always correct.
//!
//! Prisms are deliberately written as polyhedra, not as `VTK_WEDGE`: VTK changed the wedge's
//! orientation convention between versions. With VTK 9.1 (Debian bookworm's `python3-vtk9`) a
//! wedge whose base triangle 0,1,2 has its right-hand normal pointing *away* from 3,4,5 (the
//! documented convention, and what `foamToVTK` writes) has positive volume in
//! `vtkCellSizeFilter`; with VTK 9.7 that same wedge has negative volume and `vtkWedge::GetFace`
//! returns its faces inward (checked with both, see `tests/check_vtk.py`). No single point
//! order is right for every ParaView, and a polyhedron is.

use foam::{Label, PolyMesh, TopologyError};

/// The VTK cell types this crate writes (values of VTK's `VTKCellType`).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CellType {
    /// `VTK_TETRA`: points 0,1,2 form the base, ordered so that its right-hand normal points
    /// towards apex 3.
    Tetra = 10,
    /// `VTK_HEXAHEDRON`: base 0,1,2,3 with right-hand normal towards the top face 4,5,6,7;
    /// point `i + 4` is joined to point `i`.
    Hexahedron = 12,
    /// `VTK_PYRAMID`: base 0,1,2,3 with right-hand normal towards apex 4.
    Pyramid = 14,
    /// `VTK_POLYHEDRON`: any closed cell, described by its face stream.
    Polyhedron = 42,
}

/// Outward faces of VTK's reference cells in local point numbers, as listed by `vtkTetra`,
/// `vtkHexahedron` and `vtkPyramid`. The first face of each is the one laid onto a
/// cell face to start the match; every rotation of the shape maps it onto each face of the same
/// size, so any such face and any starting point will do.
const TETRA: &[&[usize]] = &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[2, 0, 3]];
const HEXAHEDRON: &[&[usize]] = &[
    &[0, 3, 2, 1],
    &[4, 5, 6, 7],
    &[0, 4, 7, 3],
    &[1, 2, 6, 5],
    &[0, 1, 5, 4],
    &[3, 7, 6, 2],
];
const PYRAMID: &[&[usize]] = &[
    &[0, 3, 2, 1],
    &[0, 1, 4],
    &[1, 2, 4],
    &[2, 3, 4],
    &[3, 0, 4],
];

/// A mesh's cells in VTK's unstructured-grid layout (the arrays of the `<Cells>` element).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct VtkCells {
    /// Point ids of all cells, cell after cell (for a polyhedron: its distinct points).
    pub connectivity: Vec<i64>,
    /// End of each cell in `connectivity` (VTK XML convention: no leading zero).
    pub offsets: Vec<i64>,
    /// The type of each cell.
    pub types: Vec<CellType>,
    /// Face streams of the polyhedra: per polyhedron the number of faces, then per face the
    /// number of points and the point ids, faces oriented outward. Empty without polyhedra.
    pub faces: Vec<i64>,
    /// End of each cell's face stream in `faces`, `-1` for cells that are not polyhedra.
    /// Empty without polyhedra.
    pub face_offsets: Vec<i64>,
}

impl VtkCells {
    /// Converts the cells of `mesh`. The mesh must pass [`PolyMesh::check`] (list lengths,
    /// labels in range, patches covering the boundary faces, cells of at least four faces); the
    /// first inconsistency is returned instead of a panic.
    pub fn from_poly_mesh(mesh: &PolyMesh) -> Result<Self, TopologyError> {
        mesh.check()?;
        let cell_faces = mesh.cell_faces();
        let mut out = VtkCells {
            connectivity: Vec::with_capacity(8 * mesh.n_cells),
            offsets: Vec::with_capacity(mesh.n_cells),
            types: Vec::with_capacity(mesh.n_cells),
            ..Default::default()
        };
        let mut any_polyhedron = false;
        let mut oriented = OrientedFaces::default();
        let mut points = Vec::new();
        for cell in 0..mesh.n_cells {
            oriented.gather(mesh, cell, cell_faces.face(cell));
            let t = classify(&oriented, &mut points);
            out.types.push(t);
            out.connectivity.extend(points.iter().map(|&p| p as i64));
            out.offsets.push(out.connectivity.len() as i64);
            if t == CellType::Polyhedron {
                if !any_polyhedron {
                    any_polyhedron = true;
                    out.face_offsets = vec![-1; cell];
                }
                out.faces.push(oriented.len() as i64);
                for f in oriented.iter() {
                    out.faces.push(f.len() as i64);
                    out.faces.extend(f.iter().map(|&p| p as i64));
                }
                out.face_offsets.push(out.faces.len() as i64);
            } else if any_polyhedron {
                out.face_offsets.push(-1);
            }
        }
        Ok(out)
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.types.len()
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    /// The point ids of cell `i` (for a polyhedron: its distinct points).
    pub fn cell_points(&self, i: usize) -> &[i64] {
        let start = if i == 0 {
            0
        } else {
            self.offsets[i - 1] as usize
        };
        &self.connectivity[start..self.offsets[i] as usize]
    }
}

/// The faces of one cell, oriented outward, in one reusable buffer.
#[derive(Default)]
struct OrientedFaces {
    labels: Vec<Label>,
    ends: Vec<usize>,
}

impl OrientedFaces {
    fn gather(&mut self, mesh: &PolyMesh, cell: usize, faces: &[Label]) {
        self.labels.clear();
        self.ends.clear();
        for &f in faces {
            let face = mesh.faces.face(f as usize);
            if mesh.owner[f as usize] as usize == cell {
                self.labels.extend_from_slice(face);
            } else {
                // Neighbour side: reverse, keeping the first point (OpenFOAM's reverseFace).
                self.labels.push(face[0]);
                self.labels.extend(face[1..].iter().rev());
            }
            self.ends.push(self.labels.len());
        }
    }

    fn len(&self) -> usize {
        self.ends.len()
    }

    fn face(&self, i: usize) -> &[Label] {
        let start = if i == 0 { 0 } else { self.ends[i - 1] };
        &self.labels[start..self.ends[i]]
    }

    fn iter(&self) -> impl Iterator<Item = &[Label]> + '_ {
        (0..self.len()).map(|i| self.face(i))
    }
}

/// Decides the type of a cell and writes its VTK point list into `points`.
fn classify(faces: &OrientedFaces, points: &mut Vec<Label>) -> CellType {
    let (mut tris, mut quads) = (0, 0);
    for f in faces.iter() {
        match f.len() {
            3 => tris += 1,
            4 => quads += 1,
            _ => {}
        }
    }
    let candidate = match (faces.len(), tris, quads) {
        (4, 4, 0) => Some((CellType::Tetra, TETRA, 4)),
        (6, 0, 6) => Some((CellType::Hexahedron, HEXAHEDRON, 8)),
        (5, 4, 1) => Some((CellType::Pyramid, PYRAMID, 5)),
        _ => None,
    };
    if let Some((t, model, n)) = candidate {
        if match_model(model, n, faces, points) {
            return t;
        }
    }
    points.clear();
    for f in faces.iter() {
        for &p in f {
            if !points.contains(&p) {
                points.push(p);
            }
        }
    }
    CellType::Polyhedron
}

/// True when `face` contains the directed edge `a → b`; returns the position of `a`.
fn find_edge(face: &[Label], a: Label, b: Label) -> Option<usize> {
    let n = face.len();
    (0..n).find(|&k| face[k] == a && face[(k + 1) % n] == b)
}

/// Tries to number the cell's points as the reference cell `model` (outward faces in local
/// numbers, `n` points). On success `points[local] = global` and every model face coincides with
/// a distinct cell face, with the same orientation.
fn match_model(
    model: &[&[usize]],
    n: usize,
    faces: &OrientedFaces,
    points: &mut Vec<Label>,
) -> bool {
    let mut map: Vec<Option<Label>> = vec![None; n];
    // Seed: the first model face onto the first cell face of its size, starting at its point 0.
    let seed = model[0];
    let Some(first) = faces.iter().find(|f| f.len() == seed.len()) else {
        return false;
    };
    for (&local, &global) in seed.iter().zip(first) {
        map[local] = Some(global);
    }
    // Propagate: a model face with a mapped directed edge lies on the cell face that has that
    // directed edge (unique on a closed, consistently oriented surface).
    let mut progress = true;
    while progress && map.iter().any(Option::is_none) {
        progress = false;
        for m in model {
            if m.iter().all(|&l| map[l].is_some()) {
                continue;
            }
            let k = m.len();
            let Some((j, pos, face)) = (0..k).find_map(|j| {
                let (a, b) = (map[m[j]]?, map[m[(j + 1) % k]]?);
                faces
                    .iter()
                    .find_map(|f| find_edge(f, a, b).map(|pos| (j, pos, f)))
            }) else {
                continue;
            };
            if face.len() != k {
                return false;
            }
            for i in 0..k {
                let global = face[(pos + i) % k];
                match map[m[(j + i) % k]] {
                    None => map[m[(j + i) % k]] = Some(global),
                    Some(g) if g != global => return false,
                    Some(_) => {}
                }
            }
            progress = true;
        }
    }
    points.clear();
    for m in &map {
        match m {
            Some(g) if !points.contains(g) => points.push(*g),
            _ => return false,
        }
    }
    // Verify: each model face is a distinct cell face, cyclically equal, same orientation.
    let mut used = vec![false; faces.len()];
    for m in model {
        let mapped = || m.iter().map(|&l| points[l]);
        let found = faces.iter().enumerate().position(|(i, f)| {
            !used[i]
                && f.len() == m.len()
                && find_edge(f, points[m[0]], points[m[1 % m.len()]]).is_some_and(|pos| {
                    mapped()
                        .enumerate()
                        .all(|(i, g)| f[(pos + i) % f.len()] == g)
                })
        });
        match found {
            Some(i) => used[i] = true,
            None => return false,
        }
    }
    used.iter().all(|&u| u)
}

#[cfg(test)]
mod tests {
    use super::*;
    use foam::{FaceList, Patch};

    fn patch(start_face: usize, n_faces: usize) -> Vec<Patch> {
        vec![Patch {
            name: "walls".into(),
            patch_type: "wall".into(),
            n_faces,
            start_face,
            extra: vec![],
        }]
    }

    /// Converts a one-cell mesh, checks its type and returns its VTK point order.
    fn single(m: &PolyMesh, t: CellType) -> Vec<usize> {
        let c = VtkCells::from_poly_mesh(m).unwrap();
        assert_eq!(c.types, [t]);
        c.cell_points(0).iter().map(|&i| i as usize).collect()
    }

    /// A one-cell mesh from outward faces (all faces owned by cell 0, boundary).
    fn one_cell(points: Vec<[f64; 3]>, faces: &[&[Label]]) -> PolyMesh {
        let mut fl = FaceList::new();
        for f in faces {
            fl.push(f);
        }
        PolyMesh {
            points,
            owner: vec![0; faces.len()],
            faces: fl,
            neighbour: vec![],
            boundary: patch(0, faces.len()),
            n_cells: 1,
        }
    }

    fn cube_points() -> Vec<[f64; 3]> {
        vec![
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [1., 1., 1.],
            [0., 1., 1.],
        ]
    }

    /// OpenFOAM's hex model faces, outward.
    const HEX_FACES: [[Label; 4]; 6] = [
        [0, 4, 7, 3],
        [1, 2, 6, 5],
        [0, 1, 5, 4],
        [3, 7, 6, 2],
        [0, 3, 2, 1],
        [4, 5, 6, 7],
    ];

    /// Checks that the VTK ordering is geometrically right: for hexahedra, the base normal
    /// (right-hand, 0→1→2) points at the top and each `i + 4` sits above `i`.
    fn signed_volume_of_tet(p: &[[f64; 3]], a: usize, b: usize, c: usize, d: usize) -> f64 {
        let s = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
        let (u, v, w) = (s(p[b], p[a]), s(p[c], p[a]), s(p[d], p[a]));
        (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))
            / 6.0
    }

    #[test]
    fn unit_cube_is_a_hexahedron_with_vtk_order() {
        let faces: Vec<&[Label]> = HEX_FACES.iter().map(|f| &f[..]).collect();
        let m = one_cell(cube_points(), &faces);
        let c = VtkCells::from_poly_mesh(&m).unwrap();
        assert_eq!(c.types, [CellType::Hexahedron]);
        let p: Vec<usize> = c.cell_points(0).iter().map(|&i| i as usize).collect();
        // Every corner tet of the VTK hex has positive volume: right orientation, i+4 over i.
        let pts = &m.points;
        assert!(signed_volume_of_tet(pts, p[0], p[1], p[2], p[4]) > 0.0);
        for i in 0..4 {
            let (b, t) = (pts[p[i]], pts[p[i + 4]]);
            let d: f64 = (0..3).map(|k| (b[k] - t[k]).powi(2)).sum();
            assert!((d - 1.0).abs() < 1e-12, "edge {i} is not a cube edge");
        }
        assert!(c.faces.is_empty() && c.face_offsets.is_empty());
    }

    #[test]
    fn every_face_and_rotation_of_a_hex_yields_a_valid_order() {
        // Rotate the face list and each face's starting point: the result must always be a
        // hexahedron with positive corner volumes.
        for shift in 0..6 {
            for rot in 0..4 {
                let faces: Vec<Vec<Label>> = (0..6)
                    .map(|i| {
                        let f = HEX_FACES[(i + shift) % 6];
                        (0..4).map(|k| f[(k + rot) % 4]).collect()
                    })
                    .collect();
                let refs: Vec<&[Label]> = faces.iter().map(|f| &f[..]).collect();
                let m = one_cell(cube_points(), &refs);
                let p = single(&m, CellType::Hexahedron);
                for (a, b, cc, d) in [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7)] {
                    assert!(signed_volume_of_tet(&m.points, p[a], p[b], p[cc], p[d]) > 0.0);
                }
            }
        }
    }

    #[test]
    fn inside_out_hex_is_written_faithfully_not_silently_fixed() {
        // All faces reversed (inward) is still a consistently oriented closed surface; the
        // match must reproduce it, i.e. give a mirrored hex whose VTK volume is negative, so
        // that a broken mesh shows up as broken in ParaView.
        let faces: Vec<Vec<Label>> = HEX_FACES
            .iter()
            .map(|f| f.iter().rev().copied().collect())
            .collect();
        let refs: Vec<&[Label]> = faces.iter().map(|f| &f[..]).collect();
        let m = one_cell(cube_points(), &refs);
        let p = single(&m, CellType::Hexahedron);
        assert!(signed_volume_of_tet(&m.points, p[0], p[1], p[2], p[4]) < 0.0);
    }

    #[test]
    fn tet_and_pyramid_are_recognised_with_vtk_orientation_prism_is_a_polyhedron() {
        let pts = vec![
            [0., 0., 0.],
            [1., 0., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [0., 1., 1.],
        ];
        // Tet 0,1,2,3; outward faces.
        let tet = one_cell(
            pts.clone(),
            &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[0, 3, 2]],
        );
        let p = single(&tet, CellType::Tetra);
        assert!(signed_volume_of_tet(&pts, p[0], p[1], p[2], p[3]) > 0.0);

        // Prism (OpenFOAM prism faces, outward): a polyhedron, see the module doc.
        let prism = one_cell(
            pts.clone(),
            &[
                &[0, 2, 1],
                &[3, 4, 5],
                &[0, 1, 4, 3],
                &[1, 2, 5, 4],
                &[0, 3, 5, 2],
            ],
        );
        let p = single(&prism, CellType::Polyhedron);
        assert_eq!(p, [0, 2, 1, 3, 4, 5]);

        // Pyramid over the unit square with apex above.
        let pyr_pts = vec![
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0.5, 0.5, 1.],
        ];
        let pyr = one_cell(
            pyr_pts.clone(),
            &[
                &[0, 3, 2, 1],
                &[0, 1, 4],
                &[1, 2, 4],
                &[2, 3, 4],
                &[3, 0, 4],
            ],
        );
        let p = single(&pyr, CellType::Pyramid);
        assert_eq!(p[4], 4);
        assert!(signed_volume_of_tet(&pyr_pts, p[0], p[1], p[2], p[4]) > 0.0);
    }

    #[test]
    fn hex_with_a_split_face_is_a_polyhedron_with_outward_stream() {
        // Cube whose top face is split into two quads via points 8 (0.5,0,1) and 9 (0.5,1,1);
        // the front and back faces become pentagons.
        let mut pts = cube_points();
        pts.push([0.5, 0., 1.]);
        pts.push([0.5, 1., 1.]);
        let faces: &[&[Label]] = &[
            &[0, 4, 7, 3],
            &[1, 2, 6, 5],
            &[0, 1, 5, 8, 4],
            &[3, 7, 9, 6, 2],
            &[0, 3, 2, 1],
            &[4, 8, 9, 7],
            &[8, 5, 6, 9],
        ];
        let m = one_cell(pts, faces);
        let c = VtkCells::from_poly_mesh(&m).unwrap();
        assert_eq!(c.types, [CellType::Polyhedron]);
        assert_eq!(c.cell_points(0).len(), 10);
        assert_eq!(c.faces[0], 7);
        assert_eq!(c.faces.len(), 1 + 7 + 4 * 5 + 5 * 2);
        assert_eq!(c.face_offsets, [c.faces.len() as i64]);
    }

    #[test]
    fn neighbour_faces_are_reversed_and_polyhedron_offsets_mark_other_cells() {
        // Two cubes side by side in x; cell 1 is made a polyhedron by splitting its +x face.
        let mut pts = Vec::new();
        for z in [0., 1.] {
            for y in [0., 1.] {
                for x in [0., 1., 2.] {
                    pts.push([x, y, z]);
                }
            }
        }
        pts.push([2., 0.5, 0.]);
        pts.push([2., 0.5, 1.]);
        let id = |x: usize, y: usize, z: usize| (x + 3 * y + 6 * z) as Label;
        let mut faces = FaceList::new();
        // Internal face x=1, normal +x (out of cell 0).
        faces.push(&[id(1, 0, 0), id(1, 1, 0), id(1, 1, 1), id(1, 0, 1)]);
        let mut owner = vec![0];
        for c in 0..2 {
            let x0 = c;
            if c == 0 {
                faces.push(&[id(0, 0, 0), id(0, 0, 1), id(0, 1, 1), id(0, 1, 0)]);
            } else {
                // +x face of cell 1 split at y = 0.5 (points 12, 13).
                faces.push(&[id(2, 0, 0), 12, 13, id(2, 0, 1)]);
                faces.push(&[12, id(2, 1, 0), id(2, 1, 1), 13]);
                owner.push(1);
            }
            faces.push(&[
                id(x0, 0, 0),
                id(x0 + 1, 0, 0),
                id(x0 + 1, 0, 1),
                id(x0, 0, 1),
            ]);
            faces.push(&[
                id(x0, 1, 0),
                id(x0, 1, 1),
                id(x0 + 1, 1, 1),
                id(x0 + 1, 1, 0),
            ]);
            faces.push(&[
                id(x0, 0, 0),
                id(x0, 1, 0),
                id(x0 + 1, 1, 0),
                id(x0 + 1, 0, 0),
            ]);
            faces.push(&[
                id(x0, 0, 1),
                id(x0 + 1, 0, 1),
                id(x0 + 1, 1, 1),
                id(x0, 1, 1),
            ]);
            owner.extend([c as Label; 5]);
        }
        let m = PolyMesh {
            points: pts,
            faces,
            owner,
            neighbour: vec![1],
            boundary: patch(1, 11),
            n_cells: 2,
        };
        let c = VtkCells::from_poly_mesh(&m).unwrap();
        assert_eq!(c.types, [CellType::Hexahedron, CellType::Polyhedron]);
        assert_eq!(c.face_offsets[0], -1);
        assert_eq!(*c.face_offsets.last().unwrap(), c.faces.len() as i64);
        // The internal face appears reversed in cell 1's stream (its first face, face 0).
        assert_eq!(&c.faces[..6], &[7, 4, 1, 7, 10, 4]);
    }

    #[test]
    fn inconsistent_meshes_are_errors_not_panics() {
        let faces: Vec<&[Label]> = HEX_FACES.iter().map(|f| &f[..]).collect();
        let mut m = one_cell(cube_points(), &faces);
        m.owner[2] = 5;
        let e = VtkCells::from_poly_mesh(&m).unwrap_err();
        assert!(e.0.contains("cell 5"), "{e}");

        let mut m = one_cell(cube_points(), &faces);
        m.points.truncate(7);
        assert!(VtkCells::from_poly_mesh(&m)
            .unwrap_err()
            .0
            .contains("point 7"));

        let mut m = one_cell(cube_points(), &faces);
        m.owner.pop();
        assert!(VtkCells::from_poly_mesh(&m).is_err());

        let m = one_cell(cube_points(), &faces[..3]);
        assert!(VtkCells::from_poly_mesh(&m)
            .unwrap_err()
            .0
            .contains("3 faces"));
    }
}
