//! The wall distance y of the wall functions, as OpenFOAM v1912's `nearWallDist` defines it
//! (`turbulenceModel::y()`, used by `nutkWallFunction` and `epsilonWallFunction`).
//!
//! For each face of a `wall` patch, y (m) is the smallest Euclidean distance from the centre of
//! the face's owner cell to the faces of the *same patch* that share a point with that face, the
//! face itself included; each distance is to the face polygon (its fan of triangles about the
//! face centre, [`mesh::nearest::face_distance`]). Faces of other patches, walls or not, are not
//! searched. In a cell away from corners the face itself is nearest and y is the normal
//! distance n̂·(C_f − C_P) (up to round-off); in a cell touching two faces of one wall patch
//! (a duct's corner) y is the distance to the nearer of the two walls, for both faces.
//! Faces of patches that are not `wall` get y = 0, as OpenFOAM gives them.
//!
//! Computed once from the mesh (a static mesh: OpenFOAM recomputes it only when points move).

use crate::geometry::FvGeometry;
use foam::PolyMesh;
use mesh::nearest::face_distance;
use mesh::v3::as_vectors;
use std::collections::HashMap;

/// y (m) of every boundary face (indexed by face − `g.n_internal`): `nearWallDist` on `wall`
/// patches, 0 elsewhere. `mesh` is the polyMesh `g` was built from.
pub fn near_wall_distances(mesh: &PolyMesh, g: &FvGeometry) -> Vec<f64> {
    let points = as_vectors(&mesh.points);
    let mut y = vec![0.0; g.n_boundary()];
    for p in g.patches.iter().filter(|p| p.patch_type == "wall") {
        let mesh_face = |i: usize| mesh.faces.face(p.mesh_faces.start + i);
        let point_faces = point_faces(p.mesh_faces.len(), mesh_face);
        // Each face on its own (on the team in blocks of 1024 faces: the same values).
        let nearest = crate::team::collect(p.mesh_faces.len(), 1024, |i| {
            let centre = g.c[g.owner[p.faces.start + i] as usize];
            mesh_face(i)
                .iter()
                .flat_map(|pt| &point_faces[pt])
                .map(|&j| face_distance(centre, points, mesh_face(j), g.cf[p.faces.start + j]))
                .fold(f64::INFINITY, f64::min)
        });
        let first = p.faces.start - g.n_internal;
        y[first..first + nearest.len()].copy_from_slice(&nearest);
    }
    y
}

/// For each point of a patch's `n` faces (`face(i)`, mesh point labels), the patch faces that
/// use it (patch-local face indices).
fn point_faces<'a>(
    n: usize,
    face: impl Fn(usize) -> &'a [foam::Label],
) -> HashMap<foam::Label, Vec<usize>> {
    let mut map: HashMap<foam::Label, Vec<usize>> = HashMap::new();
    for i in 0..n {
        for &pt in face(i) {
            map.entry(pt).or_default().push(i);
        }
    }
    map
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `hex_grid`'s patches xMin, xMax, yMin, yMax (consecutive faces) joined into one `wall`
    /// patch `walls`, or with `split` into `xWalls` and `yWalls`; zMin, zMax stay `patch`.
    fn wall_patches(mut m: PolyMesh, split: bool) -> PolyMesh {
        let b = std::mem::take(&mut m.boundary);
        let join = |name: &str, ps: &[foam::Patch], t: &str| foam::Patch {
            name: name.into(),
            patch_type: t.into(),
            n_faces: ps.iter().map(|p| p.n_faces).sum(),
            start_face: ps[0].start_face,
            extra: Vec::new(),
        };
        m.boundary = if split {
            vec![
                join("xWalls", &b[0..2], "wall"),
                join("yWalls", &b[2..4], "wall"),
            ]
        } else {
            vec![join("walls", &b[0..4], "wall")]
        };
        m.boundary.push(join("zMin", &b[4..5], "patch"));
        m.boundary.push(join("zMax", &b[5..6], "patch"));
        m
    }

    /// A 2×2×1 box of cells, x, y ∈ [0, 1] graded (cells 0.3 and 0.7 wide in x, 0.2 and 0.8 in
    /// y), z ∈ [0, 1]; walls on x = 0, x = 1, y = 0, y = 1 (patch "walls"), z faces "ends".
    /// Cell (0, 0) has centre (0.15, 0.1, 0.5): its face on y = 0 and its face on x = 0 both get
    /// y = min(0.15, 0.1) = 0.1 (the nearer wall); the cell at (1, 1), centre (0.65, 0.6, 0.5),
    /// y = min(0.35, 0.4) = 0.35 on both its wall faces. With the x walls a patch of their own,
    /// each face keeps its normal distance.
    #[test]
    fn corner_cells_take_the_nearer_wall_of_their_patch() {
        let xs = [0.0, 0.3, 1.0];
        let ys = [0.0, 0.2, 1.0];
        let zs = [0.0, 1.0];
        let check = |split: bool| {
            let m = mesh::build::hex_grid(&xs, &ys, &zs);
            let m = wall_patches(m, split);
            let g = FvGeometry::new(&m).unwrap();
            let y = near_wall_distances(&m, &g);
            for p in &g.patches {
                for f in p.faces.clone() {
                    let c = g.c[g.owner[f] as usize];
                    let n = g.nhat(f);
                    let normal = n.dot(&(g.cf[f] - c)).abs();
                    let b = f - g.n_internal;
                    let want = if p.patch_type != "wall" {
                        0.0
                    } else if split {
                        normal
                    } else {
                        // the corner cells: the distance to the nearer of x = 0|1 and y = 0|1
                        let dx = c.x.min(1.0 - c.x);
                        let dy = c.y.min(1.0 - c.y);
                        dx.min(dy)
                    };
                    assert!(
                        (y[b] - want).abs() < 1e-15,
                        "{} face {f} at {:?}: y {} vs {want}",
                        p.name,
                        g.cf[f],
                        y[b]
                    );
                }
            }
            y
        };
        let joined = check(false);
        let split = check(true);
        // The closed forms named in the doc: cell (0, 0) 0.1, cell (1, 1) 0.35.
        assert!(joined.iter().any(|&v| (v - 0.1).abs() < 1e-15));
        assert!(joined.iter().any(|&v| (v - 0.35).abs() < 1e-15));
        assert!(split.iter().any(|&v| (v - 0.15).abs() < 1e-15));
    }
}
