//! The tetrahedral decomposition of the cells that underlies the cell volumes, point location and
//! (downstream) exact sphere ∩ cell volumes.
//!
//! # Decomposition
//! Every cell is split into tetrahedra with apex at OpenFOAM's estimated cell centre cEst (the
//! mean of its face centres, see [`crate::MeshGeometry::cell_centre_estimates`]):
//! * a face with n > 3 points is split into the fan of triangles (f_c, pᵢ, pᵢ₊₁), f_c its face
//!   centre, giving tets (cEst, f_c, pᵢ, pᵢ₊₁) — `fan` index i;
//! * a triangular face gives the single tet (cEst, p₀, p₁, p₂) — `fan` index 0.
//!
//! On the neighbour side the two base points are swapped, so every tet of a valid (star-shaped)
//! cell is positively oriented. Because the fan's triangle area vectors sum to OpenFOAM's face
//! area vector A whatever the fan apex, the tets of one face sum to OpenFOAM's pyramid
//! ⅓A·(f_c − cEst) and the tets of a cell sum to the cell volume (up to rounding). Owner and
//! neighbour share the face fan, so the tets of all cells tile the mesh without gaps or overlaps.
//!
//! The fan apex is OpenFOAM's face centre with one refinement: a coordinate that is *exactly* the
//! same at all points of the face (an axis-aligned planar face) is copied to the apex, so that an
//! axis-aligned face's fan lies exactly in its plane despite the rounding of the centroid. This
//! moves the apex within the face plane only (≤ 1 ulp), which changes no tet-sum.
//!
//! # The containment predicate and the tie rule
//! A point is inside a tet when it lies strictly on the inner side of all four face planes. Each
//! side test is evaluated in floating point with a forward error bound and, when the bound
//! cannot certify the sign, exactly (expansion arithmetic, Shewchuk 1997), so the signs are
//! exact. For a valid mesh (every tet positively oriented, i.e. star-shaped cells) the tets tile
//! space, and every point lies in at most one tet. A point exactly on a face plane (an exactly
//! zero test) is resolved by *symbolic perturbation*: the point is treated as p + ε(1, δ, δ²) with
//! 0 < δ ≪ ε infinitesimal. In words: **a point on a shared boundary belongs to the side in the
//! +x direction; if the boundary is parallel to x, to the +y side; if parallel to x and y, to the
//! +z side.** On an axis-aligned grid this is exactly the half-open rule
//! x ∈ [xᵢ, xᵢ₊₁), y ∈ [yⱼ, yⱼ₊₁), z ∈ [z_k, z_k₊₁): points on the lower domain boundary are
//! inside, points on the upper domain boundary are outside.

use crate::error::MeshError;
use crate::exact::orient_exact;
use crate::geometry::MeshGeometry;
use crate::locate::AxisGrid;
use crate::v3::V3;
use foam::{FaceList, Label, PolyMesh};
use rayon::prelude::*;

/// Identifies one tet of the decomposition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TetId {
    /// The cell.
    pub cell: Label,
    /// The face of the cell whose fan holds the tet's base.
    pub face: Label,
    /// Fan index: base (f_c, pᵢ, pᵢ₊₁) for faces with more than three points, 0 for triangles.
    pub fan: Label,
}

/// One tet: its id and its four vertices, positively oriented for valid cells
/// (`points[0]` is the cell's cEst).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tet {
    /// Which tet.
    pub id: TetId,
    /// Vertices (apex cEst first), m.
    pub points: [V3; 4],
    /// Canonical vertex keys (mesh point label; face apex n_points + face; cell apex
    /// n_points + n_faces + cell) fixing the evaluation order of the containment test.
    pub keys: [u64; 4],
}

impl Tet {
    /// True when the tet contains `p`, under the tie rule of this module (module docs).
    #[inline]
    pub fn contains(&self, p: V3) -> bool {
        tet_sides(&self.points, &self.keys, &p)
            .iter()
            .all(|&s| s > 0.0)
    }

    /// Signed volume, m³: (b−a)·((c−a)×(d−a)) / 6.
    pub fn volume(&self) -> f64 {
        tet_volume(&self.points)
    }
}

/// Signed volume of the tet (a, b, c, d), m³: (b−a)·((c−a)×(d−a)) / 6.
#[inline]
pub fn tet_volume(t: &[V3; 4]) -> f64 {
    (t[1] - t[0]).dot(&(t[2] - t[0]).cross(&(t[3] - t[0]))) / 6.0
}

/// Which side of the oriented triangle (a, b, c) the point p is on: positive when p lies on the
/// side opposite to the normal (b−a)×(c−a), i.e. `det[a−p, b−p, c−p] > 0`. The value is
/// −N·(p−a) evaluated on the vertices sorted by their keys (times the permutation sign), so
/// it is antisymmetric under swapping vertices. When the floating-point value cannot certify
/// its sign (|value| within the rounding-error bound) the sign is computed exactly; an exact
/// zero is resolved by the symbolic perturbation p + ε(1, δ, δ²) and returned as
/// ±`f64::MIN_POSITIVE`. Degenerate triangles
/// (N = 0) return +`f64::MIN_POSITIVE`. Never returns zero.
#[inline]
pub(crate) fn side(v: [(&V3, u64); 3], p: &V3) -> f64 {
    let [mut a, mut b, mut c] = v;
    let mut s = 1.0;
    if b.1 < a.1 {
        std::mem::swap(&mut a, &mut b);
        s = -s;
    }
    if c.1 < b.1 {
        std::mem::swap(&mut b, &mut c);
        s = -s;
        if b.1 < a.1 {
            std::mem::swap(&mut a, &mut b);
            s = -s;
        }
    }
    let (a, b, c) = (a.0, b.0, c.0);
    let u = *b - *a;
    let v = *c - *a;
    let w = *p - *a;
    let n = u.cross(&v);
    let d = -n.dot(&w);
    // Forward error bound of the evaluation above (Shewchuk's orient3d bound A).
    let permanent = w[0].abs() * ((u[1] * v[2]).abs() + (u[2] * v[1]).abs())
        + w[1].abs() * ((u[2] * v[0]).abs() + (u[0] * v[2]).abs())
        + w[2].abs() * ((u[0] * v[1]).abs() + (u[1] * v[0]).abs());
    if d.abs() > 1e-15 * permanent && permanent > 1e-280 {
        return s * d;
    }
    let (exact, n_sign) = orient_exact(a, b, c, p);
    if exact != 0.0 {
        return s * exact * d.abs().max(f64::MIN_POSITIVE);
    }
    // Exactly on the plane: the perturbation p + ε(1, δ, δ²) moves p by −N·(1, δ, δ²).
    match n_sign.iter().find(|&&x| x != 0.0) {
        Some(&g) => -s * g * f64::MIN_POSITIVE,
        None => f64::MIN_POSITIVE,
    }
}

/// The four side tests of p against the tet (v0, v1, v2, v3) with vertex keys `k`: entry m is
/// positive when p is on the inner side of the face opposite vertex m (for a positively oriented
/// tet).
#[inline]
pub(crate) fn tet_sides(t: &[V3; 4], k: &[u64; 4], p: &V3) -> [f64; 4] {
    let v = |i: usize| (&t[i], k[i]);
    [
        side([v(1), v(2), v(3)], p),
        side([v(0), v(3), v(2)], p),
        side([v(0), v(1), v(3)], p),
        side([v(0), v(2), v(1)], p),
    ]
}

/// The tet decomposition of a mesh: the data needed to enumerate the tets of any cell (an owned
/// copy of points, faces and addressing plus the apex points).
#[derive(Clone, Debug)]
pub struct TetDecomposition {
    pub(crate) points: Vec<V3>,
    pub(crate) faces: FaceList,
    pub(crate) owner: Vec<Label>,
    pub(crate) neighbour: Vec<Label>,
    pub(crate) cell_faces: FaceList,
    pub(crate) cell_apex: Vec<V3>,
    pub(crate) face_apex: Vec<V3>,
    pub(crate) grid: Option<AxisGrid>,
}

impl TetDecomposition {
    /// Builds the decomposition of `mesh` from its geometry (which must be that of `mesh`).
    ///
    /// If the mesh is an axis-aligned tensor-product grid up to blockMesh's rounding
    /// ([`AxisGrid::detect_snapped`]), the decomposition uses the points moved exactly onto the
    /// grid planes (a change of a few ulps), so that its tets and the grid's half-open boxes are
    /// the same sets.
    pub fn new(mesh: &PolyMesh, geom: &MeshGeometry) -> Result<Self, MeshError> {
        mesh.check()?;
        geom.check_matches(mesh)?;
        let (grid, points) = match AxisGrid::detect_snapped(mesh) {
            Some((g, snapped)) => (Some(g), snapped),
            None => (None, crate::v3::from_arrays(&mesh.points)),
        };
        let mut face_apex = geom.face_centres.clone();
        face_apex
            .par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(f, apex)| {
                let face = mesh.faces.face(f);
                let p0 = points[face[0] as usize];
                for (a, x) in apex.iter_mut().enumerate() {
                    if face.iter().all(|&q| points[q as usize][a] == p0[a]) {
                        *x = p0[a];
                    }
                }
            });
        Ok(Self {
            points,
            faces: mesh.faces.clone(),
            owner: mesh.owner.clone(),
            neighbour: mesh.neighbour.clone(),
            cell_faces: mesh.cell_faces(),
            cell_apex: geom.cell_centre_estimates.clone(),
            face_apex,
            grid,
        })
    }

    /// The axis-aligned grid, if the mesh is one (see [`TetDecomposition::new`]).
    pub fn axis_grid(&self) -> Option<&AxisGrid> {
        self.grid.as_ref()
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.cell_apex.len()
    }

    /// The faces of cell `cell`, ascending.
    pub fn cell_faces(&self, cell: Label) -> &[Label] {
        self.cell_faces.face(cell as usize)
    }

    /// Mesh points (snapped onto the grid planes for an axis-aligned grid), m.
    pub fn points(&self) -> &[V3] {
        &self.points
    }

    /// The fan apex of every face (OpenFOAM's face centre, snapped onto axis-aligned planes), m.
    pub fn face_apexes(&self) -> &[V3] {
        &self.face_apex
    }

    /// The apex of every cell (OpenFOAM's cEst), m.
    pub fn cell_apexes(&self) -> &[V3] {
        &self.cell_apex
    }

    /// Number of tets of face `face` on one side.
    #[inline]
    pub fn face_tets(&self, face: Label) -> usize {
        let n = self.faces.face(face as usize).len();
        if n == 3 {
            1
        } else {
            n
        }
    }

    /// The other cell across face `face` from `cell`, `None` on a boundary face.
    #[inline]
    pub(crate) fn across(&self, face: usize, cell: Label) -> Option<Label> {
        if face >= self.neighbour.len() {
            None
        } else if self.owner[face] == cell {
            Some(self.neighbour[face])
        } else {
            Some(self.owner[face])
        }
    }

    /// The vertices of tet `id`, positively oriented for valid cells.
    #[inline]
    pub fn tet_points(&self, id: TetId) -> [V3; 4] {
        self.tet(id).points
    }

    /// Tet `id` with its vertices and keys.
    #[inline]
    pub fn tet(&self, id: TetId) -> Tet {
        let f = id.face as usize;
        let face = self.faces.face(f);
        let np = self.points.len() as u64;
        let cell_key = np + self.faces.len() as u64 + id.cell as u64;
        let apex = self.cell_apex[id.cell as usize];
        let p = |i: usize| self.points[face[i] as usize];
        let k = |i: usize| face[i] as u64;
        let own = self.owner[f] == id.cell;
        let (points, keys) = if face.len() == 3 {
            if own {
                ([apex, p(0), p(1), p(2)], [cell_key, k(0), k(1), k(2)])
            } else {
                ([apex, p(0), p(2), p(1)], [cell_key, k(0), k(2), k(1)])
            }
        } else {
            let i = id.fan as usize;
            let j = if i + 1 == face.len() { 0 } else { i + 1 };
            let fa = self.face_apex[f];
            let fk = np + f as u64;
            if own {
                ([apex, fa, p(i), p(j)], [cell_key, fk, k(i), k(j)])
            } else {
                ([apex, fa, p(j), p(i)], [cell_key, fk, k(j), k(i)])
            }
        };
        Tet { id, points, keys }
    }

    /// Iterates over the tets of cell `cell`, face by face (ascending), fan index ascending.
    pub fn cell_tets(&self, cell: Label) -> impl Iterator<Item = Tet> + '_ {
        self.cell_faces(cell).iter().flat_map(move |&face| {
            (0..self.face_tets(face) as Label).map(move |fan| self.tet(TetId { cell, face, fan }))
        })
    }

    /// The tet of cell `cell` containing `p` (tie rule of this module), by testing all its tets.
    pub fn cell_tet_containing(&self, cell: Label, p: V3) -> Option<TetId> {
        self.cell_tets(cell).find(|t| t.contains(p)).map(|t| t.id)
    }

    /// True when cell `cell` contains `p` (tie rule of this module).
    pub fn cell_contains(&self, cell: Label, p: V3) -> bool {
        self.cell_tet_containing(cell, p).is_some()
    }

    /// Bounding box of cell `cell`'s points.
    pub fn cell_bounds(&self, cell: Label) -> crate::Aabb {
        let mut b = crate::Aabb::EMPTY;
        for &f in self.cell_faces(cell) {
            for &q in self.faces.face(f as usize) {
                b.include(self.points[q as usize]);
            }
        }
        b
    }

    /// The tet across the triangle of tet `t` opposite its vertex `k` (1..=3), inside the same
    /// cell; `None` if the mesh is not manifold there.
    pub(crate) fn inner_neighbour(&self, t: TetId, k: usize) -> Option<TetId> {
        let f = t.face as usize;
        let face = self.faces.face(f);
        let n = face.len();
        let own = self.owner[f] == t.cell;
        let i = t.fan as usize;
        let j = if i + 1 == n { 0 } else { i + 1 };
        if n > 3 {
            // Vertices: 1 = face apex, 2/3 = (p_i, p_j) on the owner side, (p_j, p_i) otherwise.
            let (v2, v3) = if own { (i, j) } else { (j, i) };
            match k {
                2 | 3 => {
                    // The spoke (cEst, f_c, q) where q is the base point that stays.
                    let q = if k == 2 { v3 } else { v2 };
                    let fan = if q == j { j } else { (i + n - 1) % n };
                    return Some(TetId {
                        fan: fan as Label,
                        ..t
                    });
                }
                _ => return self.edge_neighbour(t, face[i], face[j]),
            }
        }
        // Triangle: vertices 1, 2, 3 are face points 0, 1, 2 (owner) or 0, 2, 1 (neighbour).
        let order = if own { [0, 1, 2] } else { [0, 2, 1] };
        let others: Vec<usize> = (1..4).filter(|&m| m != k).map(|m| order[m - 1]).collect();
        self.edge_neighbour(t, face[others[0]], face[others[1]])
    }

    /// The tet of the other face of `t.cell` holding the edge (u, w), on that face's fan.
    fn edge_neighbour(&self, t: TetId, u: Label, w: Label) -> Option<TetId> {
        for &g in self.cell_faces(t.cell) {
            if g == t.face {
                continue;
            }
            let face = self.faces.face(g as usize);
            let n = face.len();
            for a in 0..n {
                let b = if a + 1 == n { 0 } else { a + 1 };
                if (face[a] == u && face[b] == w) || (face[a] == w && face[b] == u) {
                    let fan = if n == 3 { 0 } else { a as Label };
                    return Some(TetId {
                        cell: t.cell,
                        face: g,
                        fan,
                    });
                }
            }
        }
        None
    }
}

impl foam::HeapBytes for TetDecomposition {
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        flat(&self.points)
            + self.faces.heap_bytes()
            + flat(&self.owner)
            + flat(&self.neighbour)
            + self.cell_faces.heap_bytes()
            + flat(&self.cell_apex)
            + flat(&self.face_apex)
            + self.grid.heap_bytes()
    }
}
