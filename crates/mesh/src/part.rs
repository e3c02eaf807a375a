//! A rank's part of a mesh: the cells around a box, each keeping its label in the whole mesh.
//!
//! A coupler rank locates, deposits and forces only the particles its DEM rank owns, so it
//! needs only the cells those particles touch ([issue 29], `docs/scaling.md`). [`MeshPart`]
//! cuts from a [`PolyMesh`] the cells whose bounding box meets a region, as a mesh of its own:
//!
//! * the kept cells in increasing whole-mesh order, so that a sorted list of local labels maps
//!   to a sorted list of whole-mesh labels ([`MeshPart::global`]);
//! * a face between two kept cells stays internal, in the whole mesh's order (so the part's
//!   internal faces are upper-triangular as OpenFOAM's); a boundary face of a kept cell stays in
//!   its patch (every patch is kept, possibly with no faces, so patch indices do not change);
//! * a face between a kept and a dropped cell becomes a boundary face of the patch
//!   [`CUT_PATCH`], appended last, owned by the kept cell: as it was when the kept cell owned
//!   it, reversed (points in the opposite order, so that its area vector points out of the kept
//!   cell) when the kept cell was the neighbour;
//! * the points the kept faces use, in increasing whole-mesh order.
//!
//! A cell none of whose faces is cut has the same faces, point for point, as in the whole mesh,
//! so its centre, volume and tetrahedra ([`crate::MeshGeometry`], [`crate::TetDecomposition`])
//! are the whole mesh's to the last bit. A cell with a cut face (an *edge* cell,
//! [`MeshPart::edge`]) may differ by round-off (its reversed faces' centres sum their points in
//! another order), and a sphere touching it may reach beyond the part: the coupler therefore
//! treats a particle touching an edge cell as a sign that the part is too small and cuts a
//! larger one (`couple::part`).
//!
//! A mesh with `cyclic` patches is not cut ([`MeshPart::cut`] refuses it): a cyclic face's
//! partner may lie outside the region, and the periodic images need both.
//!
//! [issue 29]: ../../../docs/scaling.md

use crate::geometry::Aabb;
use crate::v3::V3;
use foam::{FaceList, Label, Patch, PolyMesh};

/// The patch of the faces between a kept and a dropped cell.
pub const CUT_PATCH: &str = "foamgrainPartCut";

/// The cells of a mesh around a region, as a mesh of their own (module docs).
#[derive(Clone, Debug)]
pub struct MeshPart {
    /// The part as a mesh: its own labels for cells, faces and points.
    pub mesh: PolyMesh,
    /// The whole mesh's label of each of the part's cells (increasing).
    pub global: Vec<Label>,
    /// Whether each of the part's cells has a face on [`CUT_PATCH`].
    pub edge: Vec<bool>,
    /// Cells of the whole mesh.
    pub whole_cells: usize,
}

/// The bounding box of each cell's points (m).
pub fn cell_bounds(mesh: &PolyMesh) -> Vec<Aabb> {
    let mut bounds = vec![Aabb::EMPTY; mesh.n_cells];
    let n_internal = mesh.n_internal_faces();
    for (f, face) in mesh.faces.iter().enumerate() {
        let mut b = Aabb::EMPTY;
        for &p in face {
            b.include(V3::from(mesh.points[p as usize]));
        }
        let o = mesh.owner[f] as usize;
        bounds[o] = bounds[o].union(&b);
        if f < n_internal {
            let n = mesh.neighbour[f] as usize;
            bounds[n] = bounds[n].union(&b);
        }
    }
    bounds
}

/// Whether two closed boxes share a point.
fn meet(a: &Aabb, b: &Aabb) -> bool {
    (0..3).all(|i| a.min[i] <= b.max[i] && b.min[i] <= a.max[i])
}

impl MeshPart {
    /// The cells of `mesh` whose bounding box meets `region` (closed boxes), and one layer
    /// more: every face neighbour of those. A cell that meets the region is therefore never an
    /// edge cell, so a sphere inside the region touches no edge cell. An empty region (a rank
    /// without particles) keeps cell 0 and its layer, so that a part is never empty. `None`
    /// when the mesh has `cyclic` patches (module docs), or when every cell is kept (the part
    /// would be the whole mesh).
    pub fn around(mesh: &PolyMesh, region: &Aabb) -> Option<MeshPart> {
        let mut inside: Vec<bool> = cell_bounds(mesh).iter().map(|b| meet(b, region)).collect();
        if !inside.iter().any(|&k| k) {
            if let Some(first) = inside.first_mut() {
                *first = true;
            }
        }
        let mut keep = inside.clone();
        for (&o, &n) in mesh.owner.iter().zip(&mesh.neighbour) {
            let (o, n) = (o as usize, n as usize);
            if inside[o] || inside[n] {
                keep[o] = true;
                keep[n] = true;
            }
        }
        if keep.iter().all(|&k| k) {
            return None;
        }
        MeshPart::cut(mesh, &keep)
    }

    /// The cells `keep` marks (`mesh.n_cells` long) as a mesh (module docs); `None` when the
    /// mesh has `cyclic` patches.
    pub fn cut(mesh: &PolyMesh, keep: &[bool]) -> Option<MeshPart> {
        if mesh
            .boundary
            .iter()
            .any(|p| p.patch_type.contains("cyclic"))
        {
            return None;
        }
        let mut local = vec![Label::MAX; mesh.n_cells];
        let mut global = Vec::new();
        for (c, _) in keep.iter().enumerate().filter(|(_, &k)| k) {
            local[c] = global.len() as Label;
            global.push(c as Label);
        }
        let kept = |c: Label| local[c as usize] != Label::MAX;
        let n_internal = mesh.n_internal_faces();
        // Faces of the part in its order, as (whole-mesh face, reversed, part owner).
        let mut faces: Vec<(usize, bool, Label)> = Vec::new();
        let mut neighbour = Vec::new();
        let mut cut = Vec::new();
        for f in 0..n_internal {
            let (o, n) = (mesh.owner[f], mesh.neighbour[f]);
            match (kept(o), kept(n)) {
                (true, true) => {
                    faces.push((f, false, local[o as usize]));
                    neighbour.push(local[n as usize]);
                }
                (true, false) => cut.push((f, false, local[o as usize])),
                (false, true) => cut.push((f, true, local[n as usize])),
                (false, false) => {}
            }
        }
        let mut boundary = Vec::with_capacity(mesh.boundary.len() + 1);
        for p in &mesh.boundary {
            let start = faces.len();
            for f in p.faces() {
                if kept(mesh.owner[f]) {
                    faces.push((f, false, local[mesh.owner[f] as usize]));
                }
            }
            boundary.push(Patch {
                start_face: start,
                n_faces: faces.len() - start,
                ..p.clone()
            });
        }
        let mut edge = vec![false; global.len()];
        for &(_, _, c) in &cut {
            edge[c as usize] = true;
        }
        boundary.push(Patch {
            name: CUT_PATCH.into(),
            patch_type: "patch".into(),
            n_faces: cut.len(),
            start_face: faces.len(),
            extra: Vec::new(),
        });
        faces.extend(cut);
        // the points the kept faces use, in increasing whole-mesh order
        let mut point_local = vec![Label::MAX; mesh.points.len()];
        for &(f, _, _) in &faces {
            for &p in mesh.faces.face(f) {
                point_local[p as usize] = 0;
            }
        }
        let mut points = Vec::new();
        for (p, slot) in point_local.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = points.len() as Label;
                points.push(mesh.points[p]);
            }
        }
        let labels: usize = faces
            .iter()
            .map(|&(f, _, _)| mesh.faces.face(f).len())
            .sum();
        let mut list = FaceList::with_capacity(faces.len(), labels);
        let mut owner = Vec::with_capacity(faces.len());
        let mut buf = Vec::new();
        for &(f, reversed, o) in &faces {
            buf.clear();
            buf.extend(mesh.faces.face(f).iter().map(|&p| point_local[p as usize]));
            if reversed {
                // OpenFOAM's face::reverseFace: keep the first point, reverse the rest
                buf[1..].reverse();
            }
            list.push(&buf);
            owner.push(o);
        }
        // the arrays built by pushes hold only what they keep (the part's bytes are counted
        // by capacity, `foam::HeapBytes`)
        global.shrink_to_fit();
        points.shrink_to_fit();
        neighbour.shrink_to_fit();
        Some(MeshPart {
            mesh: PolyMesh {
                points,
                faces: list,
                owner,
                neighbour,
                boundary,
                n_cells: global.len(),
            },
            global,
            edge,
            whole_cells: mesh.n_cells,
        })
    }
}

impl foam::HeapBytes for MeshPart {
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        self.mesh.heap_bytes() + flat(&self.global) + flat(&self.edge)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::uniform_box;
    use crate::MeshGeometry;

    /// A 6 × 5 × 4 grid of unit cells, slightly sheared so that no two cells are alike.
    fn grid() -> PolyMesh {
        let mut m = uniform_box([0.0; 3], [6.0, 5.0, 4.0], [6, 5, 4]);
        for p in &mut m.points {
            p[0] += 0.05 * p[2] + 0.01 * p[1] * p[1];
        }
        m
    }

    fn region(lo: [f64; 3], hi: [f64; 3]) -> Aabb {
        Aabb {
            min: V3::from(lo),
            max: V3::from(hi),
        }
    }

    #[test]
    fn a_part_is_a_valid_mesh_whose_inner_cells_keep_their_geometry_bit_for_bit() {
        let whole = grid();
        let g = MeshGeometry::new(&whole).unwrap();
        let part = MeshPart::around(&whole, &region([1.5, 1.2, -1.0], [3.2, 3.5, 10.0])).unwrap();
        part.mesh.check().unwrap();
        let pg = MeshGeometry::new(&part.mesh).unwrap();
        assert!(part.global.windows(2).all(|w| w[0] < w[1]));
        assert!(part.mesh.n_cells < whole.n_cells);
        let mut inner = 0;
        for (l, &c) in part.global.iter().enumerate() {
            let c = c as usize;
            let dv = (pg.cell_volumes[l] - g.cell_volumes[c]).abs();
            let dc = (pg.cell_centres[l] - g.cell_centres[c]).norm();
            if part.edge[l] {
                // round-off at most (a reversed face sums its points in another order)
                assert!(dv <= 1e-14 * g.cell_volumes[c], "cell {c}: dV {dv}");
                assert!(dc <= 1e-14, "cell {c}: dC {dc}");
            } else {
                inner += 1;
                assert_eq!(pg.cell_volumes[l], g.cell_volumes[c], "cell {c}");
                assert_eq!(pg.cell_centres[l], g.cell_centres[c], "cell {c}");
            }
        }
        assert!(inner > 0 && inner < part.mesh.n_cells);
    }

    #[test]
    fn the_cut_faces_point_out_of_the_part_and_close_its_cells() {
        let whole = grid();
        let part = MeshPart::around(&whole, &region([2.5, -1.0, -1.0], [2.6, 9.0, 9.0])).unwrap();
        // the cells meeting the region, x from 2 to 3 (the shear moves points by at most
        // 0.2 + 0.25 in x, so the columns x 1..2 and 3..4 do not meet it), and the layer:
        // x from 1 to 4, three columns of 5 × 4 cells; the cut faces are x = 1 and x = 4
        assert_eq!(part.mesh.n_cells, 3 * 5 * 4);
        let cut = part.mesh.boundary.last().unwrap();
        assert_eq!(cut.name, CUT_PATCH);
        assert_eq!(cut.n_faces, 2 * 5 * 4);
        let pg = MeshGeometry::new(&part.mesh).unwrap();
        for f in cut.faces() {
            let o = part.mesh.owner[f] as usize;
            let outward = pg.face_centres[f] - pg.cell_centres[o];
            assert!(pg.face_areas[f].dot(&outward) > 0.0, "face {f}");
        }
        // closed cells: the area vectors of each cell's faces, taken outwards, sum to zero
        let mut sum = vec![V3::zeros(); part.mesh.n_cells];
        for f in 0..part.mesh.n_faces() {
            sum[part.mesh.owner[f] as usize] += pg.face_areas[f];
            if f < part.mesh.n_internal_faces() {
                sum[part.mesh.neighbour[f] as usize] -= pg.face_areas[f];
            }
        }
        assert!(sum.iter().all(|s| s.norm() < 1e-12));
        assert_eq!(part.edge.iter().filter(|&&e| e).count(), 2 * 5 * 4);
        // the whole mesh's patches are all kept, in order, before the cut
        assert_eq!(part.mesh.boundary.len(), whole.boundary.len() + 1);
        for (p, q) in part.mesh.boundary.iter().zip(&whole.boundary) {
            assert_eq!(p.name, q.name);
        }
    }

    #[test]
    fn a_region_holding_every_cell_or_a_cyclic_mesh_gives_no_part() {
        let whole = grid();
        assert!(MeshPart::around(&whole, &region([-1.0; 3], [10.0; 3])).is_none());
        let mut cyc = grid();
        cyc.boundary[0].patch_type = "cyclic".into();
        assert!(MeshPart::around(&cyc, &region([0.0; 3], [1.0; 3])).is_none());
    }
}
