//! The watch ([`crate::protocol`], version 3): what coupler rank 0 samples of U on the whole
//! mesh in the sparse exchange of several coupler ranks, where no cell field reaches it after
//! an advance (the solver ranks reply with the patch sums only). [`crate::OpenFoamFluid::watch`]
//! names the cells once; every solver rank then appends their U (and, when asked, max |U|/∛V
//! over its cells) to each reply, which [`Watch::take`] reads.

use mesh::v3::V3;

/// The watched values after the last advance.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Watched {
    /// U of the watched cells (m/s), in the order they were named.
    pub u: Vec<V3>,
    /// max |U|/∛V over every cell of the mesh (1/s), when asked for: the fluid's Courant
    /// number per unit time step (`checkCouplingInterval`'s CFL is this × Δt_CFD).
    pub u_by_size: Option<f64>,
}

/// A watch: which solver rank holds which of the watched cells, and the values.
#[derive(Clone, Debug)]
pub(crate) struct Watch {
    /// Per solver rank, the positions (in the named list) of its cells, in the order sent.
    groups: Vec<Vec<usize>>,
    pub(crate) values: Watched,
}

impl Watch {
    /// A watch of `n` cells whose positions `groups` are on each solver rank; `cfl`: the
    /// replies carry max |U|/∛V.
    pub(crate) fn new(groups: Vec<Vec<usize>>, n: usize, cfl: bool) -> Watch {
        Watch {
            groups,
            values: Watched {
                u: vec![V3::zeros(); n],
                u_by_size: cfl.then_some(0.0),
            },
        }
    }

    /// Starts reading a new reply (max |U|/∛V is the largest of the ranks').
    pub(crate) fn clear(&mut self) {
        if let Some(x) = self.values.u_by_size.as_mut() {
            *x = 0.0;
        }
    }

    /// Reads solver rank `rank`'s watch block `block` (after [`Watch::clear`]). `Err` when
    /// its length does not fit the rank's watched cells.
    pub(crate) fn take(&mut self, rank: usize, block: &[f64]) -> Result<(), String> {
        let group = &self.groups[rank];
        let c = usize::from(self.values.u_by_size.is_some());
        if block.len() != c + 3 * group.len() {
            return Err(format!(
                "watch block of {} values, expected {} ({} watched cells{})",
                block.len(),
                c + 3 * group.len(),
                group.len(),
                if c == 1 { " and max |U|/∛V" } else { "" }
            ));
        }
        let (head, u) = block.split_at(c);
        if let (Some(most), Some(&x)) = (self.values.u_by_size.as_mut(), head.first()) {
            *most = most.max(x);
        }
        for (&k, v) in group.iter().zip(u.chunks_exact(3)) {
            self.values.u[k] = V3::new(v[0], v[1], v[2]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_land_in_the_named_order_and_the_largest_ratio_wins() {
        // cells named 0, 1, 2: rank 0 holds positions 2 and 0, rank 1 position 1
        let mut w = Watch::new(vec![vec![2, 0], vec![1]], 3, true);
        w.clear();
        w.take(0, &[5.0, 1., 2., 3., 4., 5., 6.]).unwrap();
        w.take(1, &[7.0, -1., -2., -3.]).unwrap();
        assert_eq!(
            w.values.u,
            [
                V3::new(4., 5., 6.),
                V3::new(-1., -2., -3.),
                V3::new(1., 2., 3.)
            ]
        );
        assert_eq!(w.values.u_by_size, Some(7.0));
        // the next reply starts again: a smaller largest ratio is taken
        w.clear();
        w.take(0, &[2.0, 0., 0., 0., 0., 0., 0.]).unwrap();
        w.take(1, &[1.0, 0., 0., 0.]).unwrap();
        assert_eq!(w.values.u_by_size, Some(2.0));
        // a block of the wrong length is refused, naming what was expected
        let err = w.take(1, &[1.0, 0., 0.]).unwrap_err();
        assert!(err.contains("expected 4"), "{err}");
    }

    #[test]
    fn without_the_ratio_the_block_is_the_velocities() {
        let mut w = Watch::new(vec![vec![0], vec![]], 1, false);
        w.clear();
        w.take(0, &[1., 2., 3.]).unwrap();
        w.take(1, &[]).unwrap();
        assert_eq!(w.values.u, [V3::new(1., 2., 3.)]);
        assert_eq!(w.values.u_by_size, None);
        assert!(w.take(0, &[9.0, 1., 2., 3.]).is_err());
    }
}
