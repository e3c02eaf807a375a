//! Which cells live on which solver rank: the global ↔ (rank, local) maps built from the
//! handshakes (each rank's `cellProcAddressing`, the identity serially).

/// The decomposition of the mesh over the solver ranks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RankMap {
    /// Per rank, the global cell of each local cell (the rank's local order).
    local_to_global: Vec<Vec<u32>>,
    /// Per global cell, (rank, local index).
    global_to_local: Vec<(u32, u32)>,
}

impl RankMap {
    /// Builds the maps from each rank's local → global list; every global cell of a mesh of
    /// `n_cells` cells must belong to exactly one rank. `Err((rank, message))` names the rank
    /// whose list is wrong.
    pub fn new(n_cells: usize, local_to_global: Vec<Vec<u32>>) -> Result<RankMap, (usize, String)> {
        const NONE: (u32, u32) = (u32::MAX, u32::MAX);
        let mut global_to_local = vec![NONE; n_cells];
        for (rank, cells) in local_to_global.iter().enumerate() {
            for (local, &g) in cells.iter().enumerate() {
                let slot = global_to_local.get_mut(g as usize).ok_or_else(|| {
                    (
                        rank,
                        format!("local cell {local} maps to cell {g}; the mesh has {n_cells}"),
                    )
                })?;
                if *slot != NONE {
                    return Err((
                        rank,
                        format!(
                            "local cell {local} maps to cell {g}, which rank {} already holds",
                            slot.0
                        ),
                    ));
                }
                *slot = (rank as u32, local as u32);
            }
        }
        if let Some(g) = global_to_local.iter().position(|&s| s == NONE) {
            return Err((
                local_to_global.len().saturating_sub(1),
                format!(
                    "cell {g} of the mesh is on no rank ({} cells over the ranks, {n_cells} in the mesh)",
                    local_to_global.iter().map(Vec::len).sum::<usize>()
                ),
            ));
        }
        Ok(RankMap {
            local_to_global,
            global_to_local,
        })
    }

    /// The one-rank map (serial run).
    pub fn serial(n_cells: usize) -> RankMap {
        let all = (0..n_cells as u32).collect();
        RankMap::new(n_cells, vec![all]).expect("the identity is a decomposition")
    }

    /// Number of ranks.
    pub fn ranks(&self) -> usize {
        self.local_to_global.len()
    }

    /// Cells of the whole mesh.
    pub fn n_cells(&self) -> usize {
        self.global_to_local.len()
    }

    /// The global cells of `rank` in its local order.
    pub fn cells_of(&self, rank: usize) -> &[u32] {
        &self.local_to_global[rank]
    }

    /// (rank, local index) of a global cell.
    pub fn locate(&self, global: usize) -> (usize, usize) {
        let (r, l) = self.global_to_local[global];
        (r as usize, l as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_ranks_cover_the_mesh_once() {
        let map = RankMap::new(5, vec![vec![4, 0, 2], vec![1, 3]]).unwrap();
        assert_eq!(map.ranks(), 2);
        assert_eq!(map.locate(2), (0, 2));
        assert_eq!(map.locate(3), (1, 1));
        assert_eq!(map.cells_of(1), [1, 3]);
        for g in 0..5 {
            let (r, l) = map.locate(g);
            assert_eq!(map.cells_of(r)[l] as usize, g);
        }
        assert_eq!(RankMap::serial(3).cells_of(0), [0, 1, 2]);
    }

    #[test]
    fn overlaps_gaps_and_out_of_range_cells_name_the_rank() {
        let (rank, msg) = RankMap::new(3, vec![vec![0, 1], vec![1, 2]]).unwrap_err();
        assert_eq!(rank, 1);
        assert!(msg.contains("rank 0 already holds"), "{msg}");
        let (_, msg) = RankMap::new(3, vec![vec![0], vec![2]]).unwrap_err();
        assert!(msg.contains("cell 1 of the mesh is on no rank"), "{msg}");
        let (rank, msg) = RankMap::new(3, vec![vec![0, 1, 2], vec![7]]).unwrap_err();
        assert_eq!(rank, 1);
        assert!(msg.contains("maps to cell 7"), "{msg}");
    }
}
