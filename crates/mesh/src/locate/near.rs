//! Points around a located centre ([`Locator::locate_near`]), such as a particle's marker
//! points, tested only against the faces whose planes pass near the centre, of its cell and of
//! the cells across them, and the clearance of such a cluster
//! ([`Locator::locate_near_clearance`]).

use super::Locator;
use crate::nearest::face_distance;
use crate::v3::V3;
use foam::Label;

/// Most near faces [`Locator::locate_near`] keeps in one call (of the centre's cell and the
/// cells across its faces): a cell with more faces is not tested by near faces.
const NEAR_MAX: usize = 32;

/// No cell.
const NO_LABEL: Label = Label::MAX;

/// A face of a cell whose plane passes near a centre ([`Locator::locate_near`]): outward unit
/// normal, signed distance of the centre (positive outside), certainty margin over the ball
/// around the centre, face label.
#[derive(Clone, Copy, Debug, Default)]
struct NearFace {
    normal: V3,
    d: f64,
    margin: f64,
    face: usize,
}

impl NearFace {
    /// How far the point centre + `scale`·`o` may lie beyond the face's fan triangles
    /// (negative: surely on the inner side).
    #[inline]
    fn excess(&self, scale: f64, o: &V3) -> f64 {
        self.d + scale * o.dot(&self.normal) + self.margin
    }
}

impl Locator {
    /// The cells holding the points `offsets` × `scale` + `centre`, each point within
    /// `radius` of `centre`, which lies in cell `cell` (e.g. the marker points of a particle):
    /// `f(i, cell)` for the i-th point, with the answers of [`Locator::locate`]. The distances of
    /// `centre` from the cell's face planes are computed once; a point is then tested only
    /// against the faces whose planes come within `radius` of `centre`, and is given `cell`
    /// when it lies on their inner side by more than the rounding ([`Locator::cell_surely_holds`]).
    /// A point beyond one of them is tested the same way against the cell across that face
    /// (whose near faces are computed once per call too), and given that cell when surely
    /// inside it; the others are located from there by [`Locator::locate_from`].
    ///
    /// [`Locator::locate_near_clearance`] also returns how far the cluster may move with every
    /// answer unchanged.
    pub fn locate_near(
        &self,
        cell: Label,
        centre: V3,
        scale: f64,
        offsets: &[V3],
        f: impl FnMut(usize, Option<Label>),
    ) {
        self.near::<false>(cell, centre, scale, offsets, f);
    }

    /// [`Locator::locate_near`], returning a **clearance** (m): every point lies on the inner
    /// side of every fan-triangle
    /// plane of the cell it was given by more than this distance, so moving all of them by the
    /// same vector of length below it leaves every answer unchanged (a point surely inside a
    /// cell's kernel is in that cell under any tie rule). For a point given by the face tests it
    /// is the least of −(d + s·o·n̂ + margin) over the near faces of its cell (the computed bound
    /// on its fan-triangle distances, the face's certainty margin, which already covers the rounding) and
    /// −(d + radius + margin) over the other faces; for a point located by a walk, how far it
    /// lies from its cell's boundary (`clearance_at`); 0 when a point lies outside the mesh or
    /// no bound applies.
    pub fn locate_near_clearance(
        &self,
        cell: Label,
        centre: V3,
        scale: f64,
        offsets: &[V3],
        f: impl FnMut(usize, Option<Label>),
    ) -> f64 {
        self.near::<true>(cell, centre, scale, offsets, f)
    }

    /// [`Locator::locate_near`] and, with `CLEAR`, the clearance of
    /// [`Locator::locate_near_clearance`] (without, 0 where a point needed a walk: the bound
    /// from its cell's fan triangles is what costs).
    // `!(x < 0.0)` is used on purpose: it is also true for NaN (a face that cannot certify).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn near<const CLEAR: bool>(
        &self,
        cell: Label,
        centre: V3,
        scale: f64,
        offsets: &[V3],
        mut f: impl FnMut(usize, Option<Label>),
    ) -> f64 {
        /// Neighbour cells whose near faces one call keeps.
        const CELLS: usize = 8;
        if cell as usize >= self.tets.n_cells() {
            for (i, o) in offsets.iter().enumerate() {
                f(i, self.locate(V3::from_fn(|a, _| centre[a] + scale * o[a])));
            }
            return 0.0;
        }
        let radius = scale
            * offsets
                .iter()
                .map(|o| o.norm_squared())
                .fold(0.0, f64::max)
                .sqrt();
        // The near faces of `cell` first, then those of the neighbours met (`nb`: cell, range
        // and the far faces' clearance), as long as they fit.
        let mut near = [NearFace::default(); NEAR_MAX];
        let own = self.near_faces(cell, centre, radius, true, &mut near);
        let mut nb = [(NO_LABEL, 0usize, 0usize, 0.0f64); CELLS];
        let mut nb_len = 0;
        let mut used = own.map_or(0, |(n, _)| n);
        let mut clearance = f64::INFINITY;
        for (i, o) in offsets.iter().enumerate() {
            let p = V3::from_fn(|a, _| centre[a] + scale * o[a]);
            let Some((n, far)) = own else {
                f(i, self.walked::<CLEAR>(p, cell, &mut clearance));
                continue;
            };
            // The face the point lies farthest beyond (or not surely inside), and the largest
            // excess over all near faces.
            let mut worst: Option<(f64, usize)> = None;
            let mut top = f64::NEG_INFINITY;
            for nf in &near[..n] {
                let e = nf.excess(scale, o);
                if CLEAR {
                    top = top.max(e);
                }
                if !(e < 0.0) && worst.is_none_or(|w| e > w.0) {
                    worst = Some((e, nf.face));
                }
            }
            let Some((_, face)) = worst else {
                clearance = clearance.min(-top).min(far);
                f(i, Some(cell));
                continue;
            };
            let Some(next) = self.tets.across(face, cell) else {
                f(i, self.walked::<CLEAR>(p, cell, &mut clearance));
                continue;
            };
            let range = match nb[..nb_len].iter().find(|e| e.0 == next) {
                Some(&(_, a, b, far)) => Some((a, b, far)),
                None if nb_len < CELLS => {
                    let got = self.near_faces(next, centre, radius, false, &mut near[used..]);
                    got.map(|(k, far)| {
                        nb[nb_len] = (next, used, used + k, far);
                        nb_len += 1;
                        used += k;
                        (used - k, used, far)
                    })
                }
                None => None,
            };
            // Surely in `next`: inside all its near faces; then the largest excess among them.
            let next_top = range.and_then(|(a, b, far)| {
                let mut top = f64::NEG_INFINITY;
                for nf in &near[a..b] {
                    let e = nf.excess(scale, o);
                    if !(e < 0.0) {
                        return None;
                    }
                    top = top.max(e);
                }
                Some((top, far))
            });
            match next_top {
                Some((top, far)) => {
                    clearance = clearance.min(-top).min(far);
                    f(i, Some(next));
                }
                None => f(i, self.walked::<CLEAR>(p, next, &mut clearance)),
            }
        }
        clearance
    }

    /// [`Locator::locate_from`] for a point of [`Locator::near`]'s cluster that the face tests
    /// did not settle, lowering `clearance` to the point's own (`clearance_at`; 0 without
    /// `CLEAR`).
    #[inline]
    fn walked<const CLEAR: bool>(&self, p: V3, from: Label, clearance: &mut f64) -> Option<Label> {
        let got = self.locate_from(p, from);
        *clearance = clearance.min(if CLEAR {
            self.clearance_at(got, p)
        } else {
            0.0
        });
        got
    }

    /// How far `p`, which lies in cell `cell` (`None`: outside the mesh), may move and surely
    /// stay in it: for each face, −(d + margin) when `p` lies inside the planes of all its fan
    /// triangles by that much ([`Locator::cell_surely_holds`]'s bound), else, in a cell whose
    /// tets are all positively oriented (star-shaped: the tets fill the region the fan
    /// triangles enclose), the distance from `p` to the face's fan triangles less 10⁻¹² of
    /// the coordinates' size for rounding; the least over the faces. 0 outside the mesh, or
    /// where neither bound applies.
    // `!(x > 0.0)` is used on purpose: it is also true for NaN (a face that cannot certify).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn clearance_at(&self, cell: Option<Label>, p: V3) -> f64 {
        let Some(cell) = cell else { return 0.0 };
        let mut clearance = f64::INFINITY;
        let faces = self.tets.cell_faces(cell);
        for (&face, cf) in faces.iter().zip(self.faces_of(cell)) {
            let (d, margin) = cf.outward_distance(p, 0.0);
            let inside = -(d + margin);
            let bound = if inside > 0.0 {
                inside
            } else if self.cell_star[cell as usize] {
                let f = face as usize;
                let dist = face_distance(
                    p,
                    self.tets.points(),
                    self.tets.faces.face(f),
                    self.tets.face_apex[f],
                );
                dist - 1e-12 * (p.amax() + dist)
            } else {
                0.0
            };
            if !(bound > 0.0) {
                return 0.0;
            }
            clearance = clearance.min(bound);
        }
        clearance
    }

    /// The faces of `cell` whose planes may pass within `radius` of `centre` ([`NearFace`]),
    /// into `near`, their number and the least −(d + radius + margin) of the other faces (how
    /// far inside those faces' fan-triangle planes every point within `radius` of `centre`
    /// lies; infinite when every face is near); `None` when the cell has more faces than `near`
    /// holds, or, with `centre_inside`, when `centre` is not surely on the inner side of one of
    /// them.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn near_faces(
        &self,
        cell: Label,
        centre: V3,
        radius: f64,
        centre_inside: bool,
        near: &mut [NearFace],
    ) -> Option<(usize, f64)> {
        let faces = self.tets.cell_faces(cell);
        if faces.len() > near.len() {
            return None;
        }
        let reach = 3f64.sqrt() * radius;
        let mut n = 0;
        let mut far = f64::INFINITY;
        for (&face, cf) in faces.iter().zip(self.faces_of(cell)) {
            let (d, margin) = cf.outward_distance(centre, reach);
            let beyond = d + radius + margin;
            if !(beyond < 0.0) {
                if centre_inside && !(d + margin < 0.0) {
                    return None;
                }
                near[n] = NearFace {
                    normal: cf.n,
                    d,
                    margin,
                    face: face as usize,
                };
                n += 1;
            } else {
                far = far.min(-beyond);
            }
        }
        Some((n, far))
    }
}
