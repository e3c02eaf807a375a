//! `divided`: CFDEM's 29 markers located on an axis-aligned grid or, on a general mesh, by
//! [`mesh::Locator::locate_near`] from the centre's cell, with or without the memo of the
//! markers' cells from the last deposit ([`crate::memo`]).

use super::{Ball, Scratch, VoidageMesh};
use crate::divided::DIVIDED_MARKERS;
use crate::memo::MemoEntry;
use crate::vec3::V3;
use foam::Label;

impl VoidageMesh {
    /// `divided`'s shares of one particle (module docs).
    pub(super) fn divided(&self, b: Ball, s: &mut Scratch, out: &mut Vec<(Label, f64)>) -> f64 {
        let Ball { c, r, v, cell } = b;
        let Some(c0) = cell else {
            return v;
        };
        s.markers.clear();
        s.markers.push((c0, 1));
        let mut add = |m: Option<Label>| count_marker(&mut s.markers, m.unwrap_or(c0));
        match &self.grid {
            Some(g) => {
                for off in &self.markers[1..] {
                    add(g.locate(V3::from_fn(|a, _| c[a] + r * off[a])));
                }
            }
            None => self
                .locator
                .locate_near(c0, c, r, &self.markers[1..], |_, m| add(m)),
        }
        push_markers(&s.markers, v, out);
        0.0
    }

    /// [`VoidageMesh::divided`] on a general mesh with a memo ([`crate::memo`]): the kept
    /// entry's cells when it holds for the ball, else the markers located afresh with their
    /// clearance; returns the outside volume, the entry for the next deposit and whether the
    /// kept one was used.
    pub(super) fn divided_kept(
        &self,
        b: Ball,
        kept: &MemoEntry,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> (f64, MemoEntry, bool) {
        let Ball { c, r, v, cell } = b;
        let Some(c0) = cell else {
            return (v, MemoEntry::EMPTY, false);
        };
        s.markers.clear();
        if kept.holds(c, r, c0) {
            s.markers.extend(kept.found());
            push_markers(&s.markers, v, out);
            return (0.0, *kept, true);
        }
        s.markers.push((c0, 1));
        let mut add = |m: Option<Label>| count_marker(&mut s.markers, m.unwrap_or(c0));
        let clearance = self
            .locator
            .locate_near_clearance(c0, c, r, &self.markers[1..], |_, m| add(m));
        push_markers(&s.markers, v, out);
        (0.0, MemoEntry::new(c, r, clearance, &s.markers), false)
    }
}

/// Counts one `divided` marker in cell `m` ((cell, count) in the order first met).
fn count_marker(markers: &mut Vec<(Label, u32)>, m: Label) {
    match markers.iter_mut().find(|(cell, _)| *cell == m) {
        Some(e) => e.1 += 1,
        None => markers.push((m, 1)),
    }
}

/// The shares of `divided`'s markers (cell, count), the centre's cell first: the whole volume
/// `v` when every marker is in one cell, else v/29 per marker.
fn push_markers(markers: &[(Label, u32)], v: f64, out: &mut Vec<(Label, f64)>) {
    if let [(m, _)] = markers[..] {
        // Every marker in one cell (no kernel test first: the centre's face distances, which
        // locate_near computes anyway, show most such particles at once).
        out.push((m, v));
        return;
    }
    let each = v / DIVIDED_MARKERS as f64;
    for &(m, k) in markers {
        out.push((m, k as f64 * each));
    }
}
