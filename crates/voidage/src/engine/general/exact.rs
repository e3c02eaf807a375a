//! `exact` on a general mesh: the whole ball in its centre's cell when it lies in the cell's
//! kernel, else the cap form by a walk across the faces that meet the ball, else the cap or
//! flux form over the candidate cells (module docs of [`crate::engine`]).

use super::candidates::Query;
use super::cells::NO_CELL;
use crate::engine::{Ball, Scratch, VoidageMesh};
use crate::sphere_box::interval_dist2;
use foam::Label;

/// How a walk over the cells a ball meets ended ([`VoidageMesh::exact_walk`]).
enum CapWalk {
    /// Every cell found; the volume outside the mesh.
    Done(f64),
    /// The ball crosses a boundary face: the candidates must come from the bins.
    Incomplete,
    /// A face cannot tell the side of the centre: the flux form must be used.
    Tie,
}

impl VoidageMesh {
    pub(in crate::engine) fn general_exact(
        &self,
        b: Ball,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> f64 {
        let Ball { c, r, v, cell } = b;
        if let Some(c0) = cell {
            // A cell of planar faces needs no kernel test: its face planes all miss a ball in
            // its kernel, so the walk below visits it alone and adds no term.
            let planar = self.planes_of(c0).iter().all(|p| p.k.is_finite());
            if !planar && self.ball_in_cell(c0, c, r) {
                out.push((c0, v));
                return 0.0;
            }
        }
        let q = Query {
            lo: c.map(|x| x - r),
            hi: c.map(|x| x + r),
            ball: Some((c, r)),
        };
        let start = out.len();
        s.faces.clear();
        let caps = match cell {
            Some(c0) => match self.exact_walk(b, c0, s, out) {
                CapWalk::Done(outside) => return outside,
                CapWalk::Incomplete => true,
                CapWalk::Tie => false,
            },
            None => true,
        };
        out.truncate(start);
        self.candidates(&q, cell, s);
        if caps {
            if let Some(outside) = self.exact_shares(b, true, s, out) {
                return outside;
            }
            out.truncate(start);
        }
        s.faces.clear();
        self.exact_shares(b, false, s, out)
            .expect("the flux form has a value for every face")
    }

    /// The exact shares in the cap form by a walk from the centre's cell `c0` across the faces
    /// that meet the ball (nonzero cap term): for a ball that crosses no boundary face every
    /// cell it meets is reached this way (the segment from the centre to any point of the ball
    /// in the mesh crosses only faces meeting the ball), and only those cells are visited.
    fn exact_walk(
        &self,
        b: Ball,
        c0: Label,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> CapWalk {
        let Ball { c, r, v, .. } = b;
        let r3 = r * r * r;
        s.visited.clear();
        s.queue.clear();
        s.queue.push(c0);
        s.visited.insert(c0, ());
        let mut sum = 0.0;
        while let Some(cell) = s.queue.pop() {
            let mut unit = 0.0;
            for plane in self.planes_of(cell) {
                if plane.outside(c).abs() >= r {
                    // The plane misses the ball: no term.
                    continue;
                }
                let f = plane.face;
                let term = match s.faces.get(f) {
                    Some(x) => x,
                    None => match self.face_cap_unit(f as usize, c, r, &mut s.polygon) {
                        Some(x) => {
                            s.faces.insert(f, x);
                            x
                        }
                        None => return CapWalk::Tie,
                    },
                };
                unit += if plane.own { term } else { -term };
                if term != 0.0 {
                    let next = plane.across;
                    if next == NO_CELL {
                        return CapWalk::Incomplete;
                    }
                    if s.visited.insert(next, ()) {
                        s.queue.push(next);
                    }
                }
            }
            let vol = self.cap_cell_volume(cell, c0 == cell, unit * r3, b);
            if vol > 0.0 {
                out.push((cell, vol));
                sum += vol;
            }
        }
        CapWalk::Done(v - sum)
    }

    /// The share of `cell` from its cap-form sum `caps` (m³; plus the ball if `centre_cell`),
    /// clamped to [0, min(cell volume, ball volume)], and exactly the cell volume for a cell
    /// inside the ball: the cap form adds the ball and takes the caps off, a rounding of order
    /// ulp(v) that the flux form's clamp at the cell volume removes.
    fn cap_cell_volume(&self, cell: Label, centre_cell: bool, caps: f64, b: Ball) -> f64 {
        let cv = self.geom.cell_volumes[cell as usize];
        let vol = if centre_cell { b.v + caps } else { caps };
        if vol >= cv - 1e-9 * b.v && self.cell_in_ball(cell, b.c, b.r) {
            cv
        } else {
            vol.clamp(0.0, cv.min(b.v))
        }
    }

    /// The exact shares of the candidate cells (module docs), in the cap form (`caps`: face
    /// terms [`VoidageMesh::face_cap_unit`] plus the whole ball for the centre's cell; `None`
    /// when a face cannot tell the side of the centre) or in the flux form
    /// ([`VoidageMesh::face_flux_unit`]), the face terms cached in `s.faces` (which must hold
    /// terms of the same form). Returns the volume outside the mesh.
    fn exact_shares(
        &self,
        b: Ball,
        caps: bool,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> Option<f64> {
        let Ball { c, r, v, cell: c0 } = b;
        let inv_r = 1.0 / r;
        let r3 = r * r * r;
        let tets = self.locator.tets();
        let mut sum = 0.0;
        for &cell in &s.candidates {
            let bb = &self.cell_bounds[cell as usize];
            let far: f64 = (0..3)
                .map(|a| interval_dist2(bb.min[a] - c[a], bb.max[a] - c[a]).1)
                .sum();
            let cv = self.geom.cell_volumes[cell as usize];
            let vol = if far <= r * r {
                cv
            } else {
                let mut unit = 0.0;
                for &f in tets.cell_faces(cell) {
                    let term = match s.faces.get(f) {
                        Some(x) => x,
                        None => {
                            let x = if caps {
                                self.face_cap_unit(f as usize, c, r, &mut s.polygon)?
                            } else {
                                self.face_flux_unit(f as usize, c, inv_r)
                            };
                            s.faces.insert(f, x);
                            x
                        }
                    };
                    unit += if self.owner[f as usize] == cell {
                        term
                    } else {
                        -term
                    };
                }
                if caps {
                    self.cap_cell_volume(cell, c0 == Some(cell), unit * r3, b)
                } else {
                    (unit * r3).clamp(0.0, cv.min(v))
                }
            };
            if vol > 0.0 {
                out.push((cell, vol));
                sum += vol;
            }
        }
        Some(v - sum)
    }
}
