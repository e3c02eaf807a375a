//! Every cell's face planes as seen from the cell ([`CellPlane`]), and the tests of a body
//! against a cell: a ball or cube in the cell's kernel, a cell inside a ball.

use crate::engine::VoidageMesh;
use crate::vec3::V3;
use foam::Label;

/// The plane of one face of a cell, as seen from the cell.
#[derive(Clone, Copy, Debug)]
pub(in crate::engine) struct CellPlane {
    /// Unit normal out of the cell (zero for a warped face).
    pub(super) n: V3,
    /// n · (fan apex); NaN for a warped face, whose fan triangles have planes of their own.
    pub(super) k: f64,
    /// The face.
    pub(super) face: Label,
    /// The cell across the face ([`NO_CELL`] for a boundary face): kept here so that a walk
    /// does not look up the face's owner and neighbour.
    pub(super) across: Label,
    /// True when the cell owns the face (its terms, computed in the owner's orientation,
    /// enter with a + sign).
    pub(super) own: bool,
}

/// [`CellPlane::across`] of a boundary face.
pub(super) const NO_CELL: Label = Label::MAX;

impl CellPlane {
    /// The table of every cell's face planes and each cell's first entry (one more for the
    /// end).
    pub(in crate::engine) fn table(
        tets: &mesh::TetDecomposition,
        owner: &[Label],
        neighbour: &[Label],
        face_planes: &[(V3, f64)],
        planar: &[bool],
    ) -> (Vec<CellPlane>, Vec<u32>) {
        // one plane per (cell, face): exact, so that no unused capacity is allocated
        let mut planes = Vec::with_capacity(owner.len() + neighbour.len());
        let mut start = Vec::with_capacity(tets.n_cells() + 1);
        for cell in 0..tets.n_cells() as Label {
            start.push(planes.len() as u32);
            for &f in tets.cell_faces(cell) {
                let (n, k) = face_planes[f as usize];
                let own = owner[f as usize] == cell;
                let across = match neighbour.get(f as usize) {
                    None => NO_CELL,
                    Some(&nb) if own => nb,
                    Some(_) => owner[f as usize],
                };
                let (n, k) = if !planar[f as usize] {
                    (V3::zeros(), f64::NAN)
                } else if own {
                    (n, k)
                } else {
                    (-n, -k)
                };
                planes.push(CellPlane {
                    n,
                    k,
                    face: f,
                    across,
                    own,
                });
            }
        }
        start.push(planes.len() as u32);
        (planes, start)
    }

    /// Signed distance of `p` from the plane, positive outside the cell (NaN for a warped face).
    #[inline]
    pub(super) fn outside(&self, p: V3) -> f64 {
        self.n.dot(&p) - self.k
    }
}

impl VoidageMesh {
    /// True when a body centred at `c` lies in the kernel of `cell`: on the inner side of the
    /// plane of every fan triangle of its faces (of the whole face for planar faces) by at
    /// least its support `support(n)` along the plane's normal `n` (not normalised): r·|n| for
    /// a ball, r·(|n_x| + |n_y| + |n_z|) for the cube of half-side r. The kernel lies in the
    /// cell, so the body does too.
    pub(super) fn body_in_cell(&self, cell: Label, c: V3, support: impl Fn(V3) -> f64) -> bool {
        let tets = self.locator.tets();
        let points = tets.points();
        let apexes = tets.face_apexes();
        for plane in self.planes_of(cell) {
            if plane.k.is_finite() {
                if !(-plane.outside(c) >= support(plane.n)) {
                    return false;
                }
                continue;
            }
            let f = plane.face as usize;
            let face = self.faces.face(f);
            let sign = if self.owner[f] == cell { 1.0 } else { -1.0 };
            let inside = |a: V3, nrm: V3| sign * (a - c).dot(&nrm) >= support(nrm);
            let p = |i: usize| points[face[i] as usize];
            let tri = |a: V3, b: V3, d: V3| (b - a).cross(&(d - a));
            let n = face.len();
            if n == 3 {
                if !inside(p(0), tri(p(0), p(1), p(2))) {
                    return false;
                }
                continue;
            }
            for i in 0..n {
                let q = p(if i + 1 == n { 0 } else { i + 1 });
                if !inside(apexes[f], tri(apexes[f], p(i), q)) {
                    return false;
                }
            }
        }
        true
    }

    /// The face planes of `cell` ([`CellPlane`]).
    #[inline]
    pub(super) fn planes_of(&self, cell: Label) -> &[CellPlane] {
        let i = cell as usize;
        &self.cell_planes[self.cell_plane_start[i] as usize..self.cell_plane_start[i + 1] as usize]
    }

    /// True when every point of `cell` lies in the ball (centre `c`, radius `r`), hence the
    /// whole cell (its tets' other vertices, face and cell centres, are averages of its points).
    pub(super) fn cell_in_ball(&self, cell: Label, c: V3, r: f64) -> bool {
        let points = self.locator.tets().points();
        self.locator.tets().cell_faces(cell).iter().all(|&f| {
            self.faces
                .face(f as usize)
                .iter()
                .all(|&p| (points[p as usize] - c).norm_squared() <= r * r)
        })
    }

    /// [`VoidageMesh::body_in_cell`] for the ball of radius `r`.
    pub(super) fn ball_in_cell(&self, cell: Label, c: V3, r: f64) -> bool {
        self.body_in_cell(cell, c, |n| r * n.norm())
    }
}
