//! The tests on a cell's face planes: each face's plane with the margin by which its fan
//! triangles' planes may differ from it ([`FaceCertainty`]), every cell's faces in one record
//! each ([`CellFace`]), and the tests that settle a point without the exact tet predicates
//! ([`super::Locator::cell_surely_holds`], [`super::Locator::cell_surely_lacks`]).

use super::Locator;
use crate::tets::TetDecomposition;
use crate::v3::V3;
use foam::Label;

/// A face is planar when its points lie within this fraction of its size (largest distance of a
/// point from the fan apex) of the plane through the apex normal to the area vector.
const PLANAR_WARP: f64 = 1e-12;

/// How far the planes of a face's fan triangles can be from the face plane P (through the fan
/// apex a, unit normal n̂): a fan triangle's plane through its vertex v with unit normal n_t is
/// at signed distance (x − a)·n̂ + (x − a)·(n_t − n̂) + (a − v)·n_t from P's, so by at most
/// `tilt`·|x − a|₁ + `offset`, with `tilt` = max |n_t − n̂|∞ and `offset` = max |(a − v)·n_t|
/// (degenerate triangles, which bound no tet, are skipped); `offset` also holds the rounding of
/// p − a.
#[derive(Clone, Copy, Debug)]
pub(super) struct FaceCertainty {
    tilt: f64,
    offset: f64,
}

impl FaceCertainty {
    /// The margin at x − a = `x`, for points up to `reach` (L1) farther from the apex; it also
    /// covers the rounding of the distance (1e-12 of |x − a|₁).
    #[inline]
    fn margin(&self, x: V3, reach: f64) -> f64 {
        let l1 = x.abs().sum() + reach;
        self.tilt * l1 + self.offset + 1e-12 * l1
    }

    /// The bounds of face `f` and whether it is planar ([`Locator::face_is_planar`]).
    pub(super) fn of(tets: &TetDecomposition, f: usize, n: V3) -> (FaceCertainty, bool) {
        let face = tets.faces.face(f);
        let apex = tets.face_apex[f];
        let p = |i: usize| tets.points[face[i] as usize];
        let (mut warp, mut size) = (0.0f64, 0.0f64);
        for i in 0..face.len() {
            let d = p(i) - apex;
            warp = warp.max(d.dot(&n).abs());
            size = size.max(d.norm());
        }
        let planar = n != V3::zeros() && warp <= PLANAR_WARP * size;
        let mut c = FaceCertainty {
            tilt: 0.0,
            offset: 0.0,
        };
        let mut add = |t: [V3; 3]| {
            let nt = (t[1] - t[0]).cross(&(t[2] - t[0]));
            let m = nt.norm();
            if m > 0.0 {
                let nt = nt / m;
                c.tilt = c.tilt.max((nt - n).amax());
                c.offset = c.offset.max((apex - t[0]).dot(&nt).abs());
            }
        };
        if n == V3::zeros() {
            c.tilt = f64::INFINITY;
        } else if face.len() == 3 {
            add([p(0), p(1), p(2)]);
        } else {
            for i in 0..face.len() {
                add([apex, p(i), p((i + 1) % face.len())]);
            }
        }
        // The rounding of p − a relative to the magnitude of a.
        c.offset += 1e-14 * apex.abs().sum();
        (c, planar)
    }
}

/// A face of a cell for the cell's plane tests: the unit normal out of the cell, the fan apex
/// and the face's [`FaceCertainty`].
#[derive(Clone, Copy, Debug)]
pub(super) struct CellFace {
    pub(super) n: V3,
    pub(super) apex: V3,
    pub(super) certainty: FaceCertainty,
}

impl CellFace {
    /// The signed distance of `p` from the face plane, positive outside the cell, and the
    /// margin by which its fan triangles' planes may differ there (points up to `reach`
    /// farther from the apex, L1).
    #[inline]
    pub(super) fn outward_distance(&self, p: V3, reach: f64) -> (f64, f64) {
        let x = p - self.apex;
        (x.dot(&self.n), self.certainty.margin(x, reach))
    }
    /// Every cell's faces as its plane tests see them, in the order of `tets.cell_faces`, and
    /// each cell's first entry (one more for the end): [`super::Locator`]'s table.
    pub(super) fn table(
        tets: &TetDecomposition,
        face_normals: &[V3],
        face_certainty: &[FaceCertainty],
    ) -> (Vec<CellFace>, Vec<u32>) {
        // one record per (cell, face): a face's owner and, if internal, its neighbour (exact,
        // so that no unused capacity is allocated)
        let mut cell_faces = Vec::with_capacity(tets.owner.len() + tets.neighbour.len());
        let mut cell_face_start = Vec::with_capacity(tets.n_cells() + 1);
        for c in 0..tets.n_cells() as Label {
            cell_face_start.push(cell_faces.len() as u32);
            for &f in tets.cell_faces(c) {
                let f = f as usize;
                // −(x·n) = x·(−n) exactly: the same distances as from the owner's normal.
                let n = if tets.owner[f] == c {
                    face_normals[f]
                } else {
                    -face_normals[f]
                };
                cell_faces.push(CellFace {
                    n,
                    apex: tets.face_apex[f],
                    certainty: face_certainty[f],
                });
            }
        }
        cell_face_start.push(cell_faces.len() as u32);
        (cell_faces, cell_face_start)
    }
}

/// How far a vertex of the tets of cell `c` (mesh points, fan apexes, the cell apex) lies
/// beyond the plane of one of the cell's faces, at most, plus the margin by which a fan
/// triangle's plane may differ from the face plane at that vertex ([`FaceCertainty`]). A point
/// beyond a face plane by more than this and its own margin is beyond a fan triangle's plane
/// farther than every vertex, so outside the convex hull of the tets, so outside the cell
/// ([`Locator::cell_surely_lacks`]).
pub(super) fn cell_excess(
    tets: &TetDecomposition,
    c: Label,
    normals: &[V3],
    certainty: &[FaceCertainty],
) -> f64 {
    let faces = tets.cell_faces(c);
    let mut excess = 0.0f64;
    for &f in faces {
        let f = f as usize;
        let apex = tets.face_apex[f];
        let n = if tets.owner[f] == c {
            normals[f]
        } else {
            -normals[f]
        };
        let fc = certainty[f];
        if !fc.tilt.is_finite() {
            return f64::INFINITY;
        }
        let mut beyond = |v: V3| {
            let x = v - apex;
            excess = excess.max(x.dot(&n) + fc.margin(x, 0.0));
        };
        beyond(tets.cell_apex[c as usize]);
        for &g in faces {
            beyond(tets.face_apex[g as usize]);
            for &q in tets.faces.face(g as usize) {
                beyond(tets.points[q as usize]);
            }
        }
    }
    excess
}

impl Locator {
    /// True when `p` lies in cell `cell` beyond doubt: on the inner side of the plane of every
    /// fan triangle of its faces, tested on the face planes (six dot products for a hexahedron)
    /// with a margin for how far the fan triangles' planes tilt from them and for rounding;
    /// hence in the kernel of the cell, hence in the cell under any tie rule. False says
    /// nothing.
    #[inline]
    pub fn cell_surely_holds(&self, cell: Label, p: V3) -> bool {
        self.faces_of(cell).iter().all(|cf| {
            let (d, margin) = cf.outward_distance(p, 0.0);
            d + margin < 0.0
        })
    }

    /// The faces of `cell` ([`CellFace`]), in the order of its faces in the tets.
    #[inline]
    pub(super) fn faces_of(&self, cell: Label) -> &[CellFace] {
        let i = cell as usize;
        &self.cell_faces[self.cell_face_start[i] as usize..self.cell_face_start[i + 1] as usize]
    }

    /// True when `p` lies outside cell `cell` beyond doubt: outside its bounding box, or beyond
    /// one of its face planes by more than any vertex of its tets, the tilt of its fan
    /// triangles' planes and the rounding. False says nothing.
    #[inline]
    pub fn cell_surely_lacks(&self, cell: Label, p: V3) -> bool {
        if !self.cell_bounds[cell as usize].contains(p) {
            return true;
        }
        let excess = self.cell_excess[cell as usize];
        self.faces_of(cell).iter().any(|cf| {
            let (d, margin) = cf.outward_distance(p, 0.0);
            d - margin > excess
        })
    }
}
