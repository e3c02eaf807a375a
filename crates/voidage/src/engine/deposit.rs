//! The deposits of [`VoidageMesh`]: locate the centres, compute the particles in batches of
//! parallel work items ([`super::batch`]) and add their shares into the cells in particle
//! order while the next batch is computed, keeping the shares and renewing the `divided` memo
//! when asked (module docs of [`crate::engine`], "Parallelism and determinism").

use super::batch::{BatchOut, BATCH, CHUNK};
use super::{CellShares, Deposit, ParticleSet, VoidageMesh};
use crate::error::VoidageError;
use crate::memo::{DividedMemo, MemoEntry};
use crate::method::Method;
use foam::Label;

impl VoidageMesh {
    /// Deposits the particles' volumes with `method` (module docs), locating the centres
    /// without hints.
    pub fn deposit(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
    ) -> Result<Deposit, VoidageError> {
        let mut cells = vec![None; particles.len()];
        self.deposit_with_cells(method, particles, &mut cells)
    }

    /// Deposits the particles' volumes with `method`. `cells[i]` is a hint for the cell of
    /// particle i on entry (e.g. from the previous coupling step; `None`: no hint) and the cell
    /// holding its centre on return (`None` outside the mesh).
    pub fn deposit_with_cells(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
    ) -> Result<Deposit, VoidageError> {
        self.run(method, particles, cells, None, None)
    }

    /// The (cell, volume) shares each particle deposits with `method`, together with the
    /// deposit they add up to: the same code path as [`VoidageMesh::deposit_with_cells`], so
    /// `deposit.solid[c]` is the sum of the shares of cell c (in the same order, hence
    /// bit-identical to a plain deposit). `cells` is a hint and the result as there.
    pub fn shares_with_cells(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
    ) -> Result<(CellShares, Deposit), VoidageError> {
        let mut shares = CellShares {
            method,
            offsets: Vec::new(),
            cells: Vec::new(),
            volumes: Vec::new(),
        };
        let dep = self.shares_with_cells_into(method, particles, cells, &mut shares)?;
        Ok((shares, dep))
    }

    /// [`VoidageMesh::shares_with_cells`] into `shares`, whose previous contents are replaced
    /// and whose allocations are reused: a coupling loop that hands back the shares of the
    /// last step writes 20 bytes per share into memory already mapped instead of fresh pages.
    /// On error `shares` is left empty or partly filled.
    pub fn shares_with_cells_into(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
        shares: &mut CellShares,
    ) -> Result<Deposit, VoidageError> {
        shares.restart(method, particles.len());
        self.run(method, particles, cells, Some(shares), None)
    }

    /// [`VoidageMesh::shares_with_cells_into`] that reuses the `divided` markers' cells kept
    /// in `memo` where the particle has not moved past their clearance, and keeps this
    /// deposit's for the next ([`crate::memo`]). The result is bit for bit the one without a
    /// memo, whatever the memo holds; `memo` is only read and written by `divided` on a general
    /// mesh. Entry i belongs to particle i ([`DividedMemo::reorder`] follows a changed order).
    pub fn shares_with_memo_into(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
        memo: &mut DividedMemo,
        shares: &mut CellShares,
    ) -> Result<Deposit, VoidageError> {
        shares.restart(method, particles.len());
        self.run(method, particles, cells, Some(shares), Some(memo))
    }

    /// [`VoidageMesh::shares_with_cells`] without a cell hint.
    pub fn shares(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
    ) -> Result<(CellShares, Deposit), VoidageError> {
        let mut cells = vec![None; particles.len()];
        self.shares_with_cells(method, particles, &mut cells)
    }

    /// Locates, deposits and reduces; keeps the per-particle shares when `keep` is given, and
    /// uses and renews the `divided` memo when `memo` is.
    fn run(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
        mut keep: Option<&mut CellShares>,
        memo: Option<&mut DividedMemo>,
    ) -> Result<Deposit, VoidageError> {
        self.check_method(method)?;
        particles.check()?;
        if cells.len() != particles.len() {
            return Err(VoidageError::LengthMismatch {
                what: "cells",
                expected: particles.len(),
                found: cells.len(),
            });
        }
        self.locator
            .locate_all_from(particles.positions, &mut cells[..]);
        let mut solid = vec![0.0; self.n_cells()];
        let mut dep = Deposit {
            method,
            solid: vec![],
            particles: particles.len(),
            particle_volume: 0.0,
            deposited_volume: 0.0,
            outside_volume: 0.0,
            particles_outside: 0,
            particles_partly_outside: 0,
        };
        let n = particles.len();
        let batches: Vec<std::ops::Range<usize>> = (0..n)
            .step_by(CHUNK * BATCH)
            .map(|s| s..(s + CHUNK * BATCH).min(n))
            .collect();
        let cells: &[Option<Label>] = cells;
        // The memo's entries of the last deposit (read by the work items) and this one's
        // (written in particle order with the shares).
        let mut memo = memo.filter(|_| method == Method::Divided && self.grid.is_none());
        let (mut kept, mut renewed) = (Vec::new(), Vec::new());
        if let Some(m) = memo.as_deref_mut() {
            kept = std::mem::take(&mut m.entries);
            if kept.len() != n {
                kept.clear();
                kept.resize(n, MemoEntry::EMPTY);
            }
            renewed = std::mem::take(&mut m.spare);
            renewed.clear();
            renewed.resize(n, MemoEntry::EMPTY);
        }
        let mut reused = 0;
        let kept_all = kept;
        let kept = memo.is_some().then_some(&kept_all[..]);
        // On a general mesh the particles of a batch are computed in the order of their
        // centre's cell, so that consecutive particles read the same mesh data (random particle
        // orders otherwise wait on memory); the shares are still added in particle order.
        let sort = self.grid.is_none() && method != Method::Centre && n <= u32::MAX as usize;
        // A two-stage pipeline: while the threads compute batch b + 1, one of them adds batch
        // b to the solid volumes and the shares, in particle order.
        let mut done: Option<BatchOut> = None;
        for batch in batches.iter().map(Some).chain([None]) {
            let (next, ()) = rayon::join(
                || batch.map(|b| self.batch(method, particles, cells, kept, b.clone(), sort)),
                || {
                    let Some(out) = done.take() else { return };
                    let mut add = |shares: &[(Label, f64)], counts: &[u32]| {
                        for &(c, v) in shares {
                            solid[c as usize] += v;
                        }
                        if let Some(k) = keep.as_deref_mut() {
                            k.append(shares, counts);
                        }
                    };
                    if kept.is_some() {
                        for (k, o) in out.chunks.iter().enumerate() {
                            reused += o.reused;
                            for (j, &e) in o.memo.iter().enumerate() {
                                let i = match &out.order {
                                    None => out.start + k * CHUNK + j,
                                    Some(order) => order[k * CHUNK + j] as usize,
                                };
                                renewed[i] = e;
                            }
                        }
                    }
                    match &out.order {
                        None => {
                            for o in &out.chunks {
                                add(&o.shares, &o.counts);
                            }
                        }
                        Some(order) => {
                            // Where each particle's shares are: (work item, first, count).
                            let mut at = vec![(0u32, 0u32, 0u32); order.len()];
                            for (k, o) in out.chunks.iter().enumerate() {
                                let mut first = 0u32;
                                for (j, &count) in o.counts.iter().enumerate() {
                                    let i = order[k * CHUNK + j] as usize - out.start;
                                    at[i] = (k as u32, first, count);
                                    first += count;
                                }
                            }
                            for &(k, first, count) in &at {
                                let shares = &out.chunks[k as usize].shares;
                                add(&shares[first as usize..(first + count) as usize], &[count]);
                            }
                        }
                    }
                    for o in &out.chunks {
                        dep.outside_volume += o.outside;
                        dep.particle_volume += o.volume;
                        dep.particles_outside += o.fully_outside;
                        dep.particles_partly_outside += o.partly_outside;
                    }
                },
            );
            done = next;
        }
        if let Some(m) = memo {
            m.entries = renewed;
            m.spare = kept_all;
            m.reused = reused;
        }
        dep.deposited_volume = solid.iter().sum();
        dep.solid = solid;
        Ok(dep)
    }
}
