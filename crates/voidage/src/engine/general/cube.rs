//! `cube` and `corrected-cube` on a general mesh: the clipped-cube volume of every candidate
//! cell from its face terms, as fractions of the cube, and Khawaja's correction with one piece
//! for the part outside the mesh.

use super::candidates::Query;
use crate::cube::khawaja_correction;
use crate::engine::{Ball, Scratch, VoidageMesh};
use crate::vec3::V3;
use foam::Label;

impl VoidageMesh {
    pub(in crate::engine) fn general_cube(
        &self,
        b: Ball,
        corrected: bool,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> f64 {
        let Ball { c, r, v, cell } = b;
        if let Some(c0) = cell {
            let cube_support = |n: V3| r * (n[0].abs() + n[1].abs() + n[2].abs());
            if self.body_in_cell(c0, c, cube_support) {
                out.push((c0, v));
                return 0.0;
            }
        }
        let lo = c.map(|x| x - r);
        let hi = c.map(|x| x + r);
        let q = Query { lo, hi, ball: None };
        self.candidates(&q, cell, s);
        let cube = 8.0 * r * r * r;
        s.fractions.clear();
        s.faces.clear();
        let mut total = 0.0;
        for &cell in &s.candidates {
            let b = &self.cell_bounds[cell as usize];
            let cv = self.geom.cell_volumes[cell as usize];
            let vol = if (0..3).all(|a| b.min[a] >= lo[a] && b.max[a] <= hi[a]) {
                cv
            } else {
                let mut sum = 0.0;
                for &f in self.locator.tets().cell_faces(cell) {
                    let flux = match s.faces.get(f) {
                        Some(x) => x,
                        None => {
                            let x =
                                self.face_cube_flux(f as usize, c, r, &mut s.polygon, &mut s.clip);
                            s.faces.insert(f, x);
                            x
                        }
                    };
                    sum += if self.owner[f as usize] == cell {
                        flux
                    } else {
                        -flux
                    };
                }
                sum.clamp(0.0, cv)
            };
            let phi = (vol / cube).min(1.0);
            s.fractions.push(phi);
            total += phi;
        }
        let mut sum = 0.0;
        if corrected {
            let outside_piece = khawaja_correction((1.0 - total).clamp(0.0, 1.0));
            let mut wsum = outside_piece;
            for f in &mut s.fractions {
                *f = khawaja_correction(*f);
                wsum += *f;
            }
            let scale = if wsum > 0.0 { v / wsum } else { 0.0 };
            for (&cell, &w) in s.candidates.iter().zip(&s.fractions) {
                if w > 0.0 {
                    out.push((cell, w * scale));
                    sum += w * scale;
                }
            }
        } else {
            for (&cell, &phi) in s.candidates.iter().zip(&s.fractions) {
                if phi > 0.0 {
                    out.push((cell, phi * v));
                    sum += phi * v;
                }
            }
        }
        v - sum
    }
}
