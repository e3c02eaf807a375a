//! Three or more grids: sorted fine to coarse and analysed as successive triplets
//! (1,2,3), (2,3,4), … — Celik et al. (2008) treat three grids; with more, each consecutive
//! triple is a study of its own (as Volk et al. 2018 do over their cell-size series).

use crate::error::GciError;
use crate::triplet::{analyse, Settings, Triplet};
use serde::Serialize;

/// One grid of a study.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Grid {
    /// Representative cell size h (> 0).
    pub h: f64,
    /// The value φ on this grid.
    pub value: f64,
}

/// Sorts `grids` by h (finest first) and analyses every consecutive triplet; each
/// [`Triplet::grids`] holds the positions of its grids in `grids`. Needs at least
/// three grids with distinct h > 0 and finite values ([`crate::table::GridTable`] checks these
/// with file and line before this is called; here a violation is a [`GciError::TooFewGrids`] or
/// [`GciError::Grids`] without a location).
pub fn analyse_study(grids: &[Grid], settings: &Settings) -> Result<Vec<Triplet>, GciError> {
    if grids.len() < 3 {
        return Err(GciError::TooFewGrids {
            input: "study".into(),
            found: grids.len(),
            last_line: 0,
        });
    }
    let mut order: Vec<usize> = (0..grids.len()).collect();
    order.sort_by(|&a, &b| grids[a].h.total_cmp(&grids[b].h));
    order
        .windows(3)
        .map(|w| {
            let [f, m, c] = [w[0], w[1], w[2]].map(|i| grids[i]);
            let mut t = analyse([f.h, m.h, c.h], [f.value, m.value, c.value], settings)?;
            t.grids = [w[0], w[1], w[2]];
            Ok(t)
        })
        .collect()
}
