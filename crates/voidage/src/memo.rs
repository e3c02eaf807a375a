//! The `divided` markers' cells kept from one deposit to the next.
//!
//! In a coupling loop most particles move far less per coupling step than the distance of
//! their nearest marker from a face of the cell holding it.
//! [`mesh::Locator::locate_near_clearance`] returns that distance, the **clearance**: each
//! marker lies on the inner side of every fan-triangle plane of its cell by more than it (the
//! bound is the locator's own certainty margin, which covers the rounding), or, for a marker
//! found by a walk, at least that far from its cell's fan triangles. Moving the ball by a
//! vector δ moves every marker by δ, so while |δ| stays below the clearance each marker is
//! still surely inside the same cell, where [`mesh::Locator::locate`] — and hence `divided` —
//! puts it under any tie rule. A
//! [`DividedMemo`] keeps, per particle, the centre and radius at which the markers were last
//! located, the clearance and the cells with their marker counts; the next deposit reuses them
//! when
//!
//! * the radius is the same (bit for bit),
//! * the centre's cell, located afresh, is the kept one (the centre marker's cell), and
//! * |c − c_kept| + τ < clearance, with τ = 10⁻¹² (|c|∞ + r) for the rounding of the marker
//!   positions c + r·o (≈ 10⁻¹⁶ of those magnitudes).
//!
//! The shares then come out of the same arithmetic as a fresh location (the same cells in the
//! same order, V/29 times the same counts), so a deposit with a memo is bit for bit the one
//! without. The memo is purely geometric: an entry is valid for any ball that passes the test,
//! whichever particle it was kept for, so a memo that is not re-keyed after the population
//! changes costs only the reuse, never the answer. Entries are dropped (kept empty) where a
//! marker needed a walk, lies outside the mesh, or the markers fall in more than
//! [`MEMO_CELLS`] cells. Only the general-mesh path keeps entries (on an axis-aligned grid the
//! markers are located by arithmetic).
//!
//! Memory: an entry is 88 bytes, and a memo holds two per particle (the last deposit's, read,
//! and this one's, written), 176 MB for 10⁶ particles.

use crate::vec3::V3;
use foam::Label;

/// Most distinct cells one entry holds (a ball of diameter d over cells of size h ≥ d meets at
/// most 8 hexahedra).
pub const MEMO_CELLS: usize = 8;

/// One particle's markers: where they were located and what was found (88 bytes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoEntry {
    /// Centre at which the markers were located, m.
    pub(crate) centre: V3,
    /// Radius, m.
    pub(crate) radius: f64,
    /// How far the centre may move with every marker in the same cell, m (0: no entry).
    pub(crate) clearance: f64,
    /// Number of cells used in `cells` and `counts`.
    pub(crate) len: u8,
    /// The cells in the order `divided` found them (the centre's cell first).
    pub(crate) cells: [Label; MEMO_CELLS],
    /// Markers in each cell (29 in all).
    pub(crate) counts: [u8; MEMO_CELLS],
}

const _: () = assert!(std::mem::size_of::<MemoEntry>() == 88);

impl MemoEntry {
    /// No entry.
    pub const EMPTY: MemoEntry = MemoEntry {
        centre: V3::new(0.0, 0.0, 0.0),
        radius: 0.0,
        clearance: 0.0,
        len: 0,
        cells: [0; MEMO_CELLS],
        counts: [0; MEMO_CELLS],
    };

    /// An entry for the markers `found` ((cell, count), centre's cell first) of the ball
    /// (`centre`, `radius`) with `clearance`; empty when there is nothing to keep.
    pub(crate) fn new(centre: V3, radius: f64, clearance: f64, found: &[(Label, u32)]) -> Self {
        if !(clearance > 0.0) || found.is_empty() || found.len() > MEMO_CELLS {
            return MemoEntry::EMPTY;
        }
        let mut e = MemoEntry {
            centre,
            radius,
            clearance,
            len: found.len() as u8,
            ..MemoEntry::EMPTY
        };
        for (k, &(c, n)) in found.iter().enumerate() {
            e.cells[k] = c;
            e.counts[k] = n as u8;
        }
        e
    }

    /// Whether the kept cells hold for the ball (`centre`, `radius`) whose centre lies in
    /// `cell` (module docs).
    #[inline]
    pub(crate) fn holds(&self, centre: V3, radius: f64, cell: Label) -> bool {
        if self.len == 0 || self.radius.to_bits() != radius.to_bits() || self.cells[0] != cell {
            return false;
        }
        let tau = 1e-12 * (centre.amax() + radius);
        let room = self.clearance - tau;
        room > 0.0 && (centre - self.centre).norm_squared() < room * room
    }

    /// The kept (cell, marker count) pairs.
    pub(crate) fn found(&self) -> impl Iterator<Item = (Label, u32)> + '_ {
        (0..self.len as usize).map(|k| (self.cells[k], u32::from(self.counts[k])))
    }
}

/// Per particle, the `divided` markers' cells of the last deposit ([`MemoEntry`], module
/// docs), for [`crate::VoidageMesh::shares_with_memo_into`].
#[derive(Clone, Debug, Default)]
pub struct DividedMemo {
    pub(crate) entries: Vec<MemoEntry>,
    /// The previous deposit's entries' allocation, reused for the next.
    pub(crate) spare: Vec<MemoEntry>,
    /// Particles of the last deposit whose kept cells were used.
    pub(crate) reused: usize,
}

impl DividedMemo {
    /// An empty memo (the first deposit locates every marker).
    pub fn new() -> Self {
        Self::default()
    }

    /// Particles of the last deposit whose markers were not located again.
    pub fn reused(&self) -> usize {
        self.reused
    }

    /// Re-keys the memo to a new particle order: particle i of the next deposit takes the
    /// entry of particle `from[i]` of the last one (`None`: a new particle). Without it a
    /// changed population only loses reuse, never correctness (module docs).
    pub fn reorder(&mut self, from: &[Option<usize>]) {
        let old = std::mem::take(&mut self.entries);
        self.entries = from
            .iter()
            .map(|k| {
                k.and_then(|k| old.get(k).copied())
                    .unwrap_or(MemoEntry::EMPTY)
            })
            .collect();
    }
}

impl foam::HeapBytes for DividedMemo {
    fn heap_bytes(&self) -> usize {
        foam::heap::flat(&self.entries) + foam::heap::flat(&self.spare)
    }
}
