//! The coupler on several ranks: each rank couples the particles its DEM rank owns, rank 0
//! holds the fluid.
//!
//! A parallel run (`mpirun -np N foamgrain run …` with LIGGGHTS on the N ranks) gives every
//! coupler rank the particles LIGGGHTS owns there, and no rank ever holds them all. A particle is
//! owned by one rank, so its volume, β and force are deposited once. What crosses ranks per
//! coupling step is sparse, proportional to the cells a rank's particles touch:
//!
//! 1. each rank sends rank 0 the solid volume its particles put in each cell it touches
//!    ([`Ranks::sum_to_root`]); rank 0 sums them (in rank order) into the global deposit, and
//!    computes ε with the `alphaMin` floor;
//! 2. rank 0 sends each rank ε, U, p, ∇p and ∇·τ of the cells that rank touches
//!    ([`Ranks::scatter_from_root`]);
//! 3. each rank computes its particles' forces, and sends rank 0 its Σ w β, Σ w β v and
//!    Σ w F per touched cell, which rank 0 turns into Ksl, Us and f for the fluid.
//!
//! Rank 0 may hold a part of the mesh too ([`crate::part`]; the native fluid on N ranks,
//! [`crate::Coupler::set_root_volumes`]): it then places its own particles on its part and takes
//! their forces from its touched cells as the other ranks do, and sums the ranks' cells (its own
//! first) into whole-length arrays with the whole mesh's cell volumes.
//!
//! The volume and force accounting (particles, volume outside the mesh, clipped volume,
//! β and force outside the mesh) is summed over ranks, so nothing lost on one rank goes
//! unreported. [`Serial`] is the one-rank case (nothing to exchange); an MPI implementation
//! lives with the MPI crates (`runner`'s `ranks` module), so this crate stays free of MPI.
//!
//! Sums over ranks run in rank order: a run is deterministic for a fixed rank count, and
//! differs from the one-rank run by round-off only (the order of the per-cell additions).
//!
//! # The fluid's cells elsewhere: [`CellOwners`]
//!
//! When the fluid is grainPisoFoam on its own ranks, rank 0 does not relay: each coupler rank
//! exchanges the touched cells' values straight with the solver ranks that own them
//! ([`crate::Coupler::set_owners`]; the MPI implementation is crate foam-link's). Then, on
//! every coupler rank:
//!
//! 1. the rank gives the owners its solid volume per touched cell ([`CellOwners::deposit`]) and
//!    gets back, per touched cell, the solid volume summed over all coupler ranks (in rank
//!    order), whether it is the lowest rank touching the cell, and U, p, ∇p, ∇·τ;
//! 2. it computes ε of its touched cells from the summed volume with the same kernel as rank
//!    0 would ([`voidage::voidage_field`], `alphaMin` floor), so every rank touching a cell
//!    gets the same ε; the clipping statistics count each cell on its lowest rank only and are
//!    summed over ranks;
//! 3. it computes its particles' forces and gives the owners ε, Σ Ksl, Σ Ksl·Us and Σ f per
//!    touched cell ([`CellOwners::exchange`]); the owners form Ksl, Us and f as rank 0 does
//!    ([`Ranks::sum_to_root`] then the division of Σ Ksl·Us by Σ Ksl).
//!
//! No coupler rank then holds a whole field: bytes per rank scale with its particles' cells.
//!
//! With heat ([`crate::heat`]) round 1 also returns T per touched cell, each rank computes its
//! particles' q from ε, U and T of its touched cells, and round 2 also gives its share of
//! Tsource per touched cell ([`OWNER_HEAT_WIDTH`]); the heat account's parts are summed over
//! the ranks. `maxSource` is refused there: its cut needs a cell's Tsource summed over the
//! ranks, which only the owners hold.

use crate::error::SideError;
use foam::Label;

/// Values per touched cell [`CellOwners::deposit`] returns: Σ solid volume (m³), lowest-rank
/// flag (1 or 0), U (3, m/s), p (m²/s²), ∇p (3, m/s²), ∇·τ (3, m/s²).
pub const OWNER_REPLY_WIDTH: usize = 12;
/// Values per touched cell [`CellOwners::exchange`] takes: ε, Σ Ksl (kg/(m³ s)), Σ Ksl·Us (3),
/// Σ f (3, N/m³).
pub const OWNER_SUMS_WIDTH: usize = 8;

/// Values per touched cell that heat adds at the end of each record (heat transfer on,
/// [`crate::heat`]): to the reply of [`CellOwners::deposit`] the fluid's T (K), to the sums of
/// [`CellOwners::exchange`] this rank's share of the heat source, −Σ_p w_pc q_p / (ρ c_p V_c)
/// (K/s; the owners add the ranks' shares, in rank order, into the cell's Tsource). Without
/// heat no record grows.
pub const OWNER_HEAT_WIDTH: usize = 1;

/// Values per touched cell of [`CellOwners::deposit`]'s reply: [`OWNER_REPLY_WIDTH`], plus
/// [`OWNER_HEAT_WIDTH`] (T) when `heat`.
pub const fn owner_reply_width(heat: bool) -> usize {
    OWNER_REPLY_WIDTH + if heat { OWNER_HEAT_WIDTH } else { 0 }
}

/// Values per touched cell [`CellOwners::exchange`] takes: [`OWNER_SUMS_WIDTH`], plus
/// [`OWNER_HEAT_WIDTH`] (the Tsource share) when `heat`, plus
/// [`crate::ksl::CFDEM_SUMS_WIDTH`] when `cfdem_ksl` (CFDEM's Ksl form, [`crate::ksl`]: this
/// rank's Σ w β (u_p − v) (3, N), Σ w, and Σ w v (3, m/s; with `dilute` the last particle's
/// v) after the heat column; the owners sum them in rank order and form Ksl and Us with their
/// U, ε and V as [`crate::ksl::form_cfdem`] does). Without either no record grows.
pub const fn owner_sums_width(heat: bool, cfdem_ksl: bool) -> usize {
    OWNER_SUMS_WIDTH
        + if heat { OWNER_HEAT_WIDTH } else { 0 }
        + if cfdem_ksl {
            crate::ksl::CFDEM_SUMS_WIDTH
        } else {
            0
        }
}

/// The fluid's cells held by other processes (grainPisoFoam's ranks), reached from every
/// coupler rank (module docs). Both methods are collective over the coupler's ranks and the
/// owners: every rank calls them every coupling step, in this order, with possibly no cells.
pub trait CellOwners {
    /// Round 1: this rank's solid volume (m³) per touched cell (`cells` increasing, no
    /// repeats); returns [`owner_reply_width`] values per cell (heat on or not, as the owners
    /// were started), in `cells`' order.
    fn deposit(&mut self, cells: &[Label], solid: &[f64]) -> Result<Vec<f64>, SideError>;
    /// Round 2: [`owner_sums_width`] values per cell of the last [`CellOwners::deposit`].
    fn exchange(&mut self, sums: &[f64]) -> Result<(), SideError>;
    /// Payload bytes this rank has sent to and received from the owners so far.
    fn traffic(&self) -> (u64, u64);
}

/// The coupler's ranks (module docs). Every method is collective: all ranks call it, in the
/// same order.
pub trait Ranks {
    /// This rank (0 holds the fluid).
    fn rank(&self) -> usize;
    /// Number of coupler ranks.
    fn size(&self) -> usize;
    /// Per-cell sums onto rank 0: each rank gives the cells it touches (`cells`, increasing,
    /// no repeats) and `width` values per cell (`values.len() == cells.len() * width`); rank 0
    /// gets in `root` (`n_cells × width`, overwritten) the sums over ranks, zero for cells no
    /// rank touches. `root` is left alone on the other ranks. Each rank's list is kept for the
    /// next [`Ranks::scatter_from_root`].
    fn sum_to_root(&mut self, cells: &[Label], values: &[f64], width: usize, root: &mut [f64]);
    /// Rank 0 sends each rank `width` values per cell of the list that rank gave to the last
    /// [`Ranks::sum_to_root`], which `value(cell, buffer)` appends (called on rank 0 only);
    /// every other rank gets its values in `out`, in its list's order (rank 0's `out` is left
    /// alone: it reads its own fields).
    fn scatter_from_root(
        &mut self,
        width: usize,
        value: &dyn Fn(Label, &mut Vec<f64>),
        out: &mut Vec<f64>,
    );
    /// Element-wise sum of `x` over ranks, on every rank.
    fn all_sum(&self, x: &mut [f64]);
    /// Element-wise maximum of `x` over ranks, on every rank.
    fn all_max(&self, x: &mut [f64]);
    /// Rank 0's `x` on every rank.
    fn broadcast(&self, x: &mut [f64]);
    /// Every rank's `x` on rank 0, in rank order (empty on the other ranks).
    fn gather(&self, x: &[f64]) -> Vec<Vec<f64>>;
    /// Bytes this rank has sent and received through these operations so far (0 alone).
    fn traffic(&self) -> (u64, u64) {
        (0, 0)
    }
    /// Returns once every rank has called it; a rank that waits sleeps rather than spins (a
    /// barrier before the ranks go on to blocking collectives while one works alone). Nothing
    /// alone.
    fn meet(&self) {}
}

/// One rank: every operation is the identity.
#[derive(Clone, Copy, Debug, Default)]
pub struct Serial {
    cells: usize,
}

impl Ranks for Serial {
    fn rank(&self) -> usize {
        0
    }

    fn size(&self) -> usize {
        1
    }

    fn sum_to_root(&mut self, cells: &[Label], values: &[f64], width: usize, root: &mut [f64]) {
        root.fill(0.0);
        scatter_add(cells, values, width, root);
        self.cells = cells.len();
    }

    fn scatter_from_root(
        &mut self,
        _width: usize,
        _value: &dyn Fn(Label, &mut Vec<f64>),
        _out: &mut Vec<f64>,
    ) {
    }

    fn all_sum(&self, _x: &mut [f64]) {}

    fn all_max(&self, _x: &mut [f64]) {}

    fn broadcast(&self, _x: &mut [f64]) {}

    fn gather(&self, x: &[f64]) -> Vec<Vec<f64>> {
        vec![x.to_vec()]
    }
}

/// Adds `width` values per cell of `cells` into the dense `dense` (`n_cells × width`).
pub fn scatter_add(cells: &[Label], values: &[f64], width: usize, dense: &mut [f64]) {
    for (k, &c) in cells.iter().enumerate() {
        let c = c as usize;
        for j in 0..width {
            dense[c * width + j] += values[k * width + j];
        }
    }
}

/// `width` values per cell of `cells` taken from the dense `dense` (`n_cells × width`),
/// appended to `out`.
pub fn pick(cells: &[Label], dense: &[f64], width: usize, out: &mut Vec<f64>) {
    for &c in cells {
        let c = c as usize;
        out.extend_from_slice(&dense[c * width..(c + 1) * width]);
    }
}

/// The cells a rank's particles touch: their shares' cells and their centre cells, increasing.
pub(crate) fn touched_cells(shares: &voidage::CellShares, centre: &[Option<Label>]) -> Vec<Label> {
    let mut cells: Vec<Label> = shares.cells.clone();
    cells.extend(centre.iter().flatten());
    cells.sort_unstable();
    cells.dedup();
    cells
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scatter_add_and_pick_are_inverse_on_the_listed_cells() {
        let cells = [1, 3];
        let values = [1.0, 2.0, 3.0, 4.0];
        let mut dense = vec![0.0; 8];
        scatter_add(&cells, &values, 2, &mut dense);
        assert_eq!(dense, [0.0, 0.0, 1.0, 2.0, 0.0, 0.0, 3.0, 4.0]);
        let mut out = Vec::new();
        pick(&cells, &dense, 2, &mut out);
        assert_eq!(out, values);
        let mut s = Serial::default();
        let mut root = vec![9.0; 8];
        s.sum_to_root(&cells, &values, 2, &mut root);
        assert_eq!(root, dense);
    }
}
