//! Location on a general mesh from a start cell: the face-plane test of the start cell, a
//! cell-to-cell walk by face planes, the visibility walk over the tets with the exact
//! predicates, and, when the walk is lost, the bin's candidate cells one by one.

use super::Locator;
use crate::tets::{tet_sides, TetId};
use crate::v3::V3;
use foam::Label;

/// Walk steps before the walk switches from greedy to randomised exit choice.
const GREEDY_STEPS: usize = 512;

/// Walk steps before giving up and testing candidate cells.
const MAX_STEPS: usize = 8192;

/// Result of a tet walk.
enum Walk {
    Found(TetId),
    /// Left the mesh through a boundary face, did not settle, or met a non-manifold edge.
    Lost,
}

impl Locator {
    pub(super) fn walk_or_search(&self, p: V3, start: Label) -> Option<Label> {
        if self.cell_surely_holds(start, p) {
            return Some(start);
        }
        let start = self.cell_walk(p, start);
        if self.cell_surely_holds(start, p) {
            return Some(start);
        }
        match self.walk(p, start) {
            Walk::Found(t) => Some(t.cell),
            Walk::Lost => self.bins.candidates(p).iter().copied().find(|&c| {
                !self.cell_surely_lacks(c, p)
                    && (self.cell_surely_holds(c, p) || self.tets.cell_contains(c, p))
            }),
        }
    }

    /// A cheap cell-to-cell walk towards `p` by face planes: step across the face of which `p`
    /// lies farthest outside, until `p` is inside all face planes of the cell, a boundary face is
    /// met, or a step limit is reached. Only a starting point for the exact tet walk.
    fn cell_walk(&self, p: V3, start: Label) -> Label {
        let mut c = start;
        for _ in 0..MAX_STEPS / 8 {
            let mut best = (0.0, None);
            for (&f, cf) in self.tets.cell_faces(c).iter().zip(self.faces_of(c)) {
                let d = (p - cf.apex).dot(&cf.n);
                if d > best.0 {
                    best = (d, Some(f as usize));
                }
            }
            match best.1.and_then(|f| self.tets.across(f, c)) {
                Some(n) => c = n,
                None => break,
            }
        }
        c
    }

    /// The tet of cell `cell` to start a walk towards `p`: fan 0 of the face whose centre lies
    /// most in the direction of `p` seen from the cell apex.
    fn start_tet(&self, cell: Label, p: V3) -> TetId {
        let apex = self.tets.cell_apex[cell as usize];
        let d = p - apex;
        let mut best = (f64::NEG_INFINITY, self.tets.cell_faces(cell)[0]);
        for &f in self.tets.cell_faces(cell) {
            let r = self.tets.face_apex[f as usize] - apex;
            let score = d.dot(&r) / r.dot(&r);
            if score > best.0 {
                best = (score, f);
            }
        }
        TetId {
            cell,
            face: best.1,
            fan: 0,
        }
    }

    /// Visibility walk over the tets from a tet of cell `start` to the tet containing `p`.
    fn walk(&self, p: V3, start: Label) -> Walk {
        let mut t = self.start_tet(start, p);
        let mut tet = self.tets.tet(t);
        let mut known_inside: Option<usize> = None;
        let mut rng: u64 = 0x9E37_79B9_7F4A_7C15 ^ p[0].to_bits() ^ p[1].to_bits().rotate_left(21);
        for step in 0..MAX_STEPS {
            let mut s = tet_sides(&tet.points, &tet.keys, &p);
            if let Some(k) = known_inside {
                s[k] = f64::INFINITY;
            }
            let k = if step < GREEDY_STEPS {
                let mut k = 0;
                for m in 1..4 {
                    if s[m] < s[k] {
                        k = m;
                    }
                }
                if s[k] > 0.0 {
                    return Walk::Found(t);
                }
                k
            } else {
                let neg: Vec<usize> = (0..4).filter(|&m| s[m] < 0.0).collect();
                if neg.is_empty() {
                    return Walk::Found(t);
                }
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                neg[(rng % neg.len() as u64) as usize]
            };
            let next = if k == 0 {
                match self.tets.across(t.face as usize, t.cell) {
                    Some(cell) => TetId { cell, ..t },
                    None => return Walk::Lost,
                }
            } else {
                match self.tets.inner_neighbour(t, k) {
                    Some(n) => n,
                    None => return Walk::Lost,
                }
            };
            let new = self.tets.tet(next);
            known_inside = (0..4).find(|&j| {
                !(0..4)
                    .filter(|&m| m != k)
                    .any(|m| tet.keys[m] == new.keys[j])
            });
            t = next;
            tet = new;
        }
        Walk::Lost
    }
}
