//! Aggregation algebraic multigrid: what the native solver runs for fvSolution's `GAMG`.
//!
//! Two hierarchies and two cycles. For `GAMG` on a symmetric matrix (the pressure),
//! [`Amg::gamg`] builds OpenFOAM's hierarchy (one pairing pass per level on the mesh's face
//! weights) and the module `vcycle` applies OpenFOAM's V-cycle on it (as CG's
//! preconditioner). For the K-cycle (`GAMG` as a preconditioner, and the non-symmetric `GAMG`
//! solver's BiCGStab), [`Amg::new`] builds the matrix-based hierarchy below.
//!
//! The hierarchy is built from the matrix alone (Stüben, *A review of algebraic multigrid*,
//! J. Comput. Appl. Math. 128 (2001) 281–309; the pairwise aggregation of Notay, *An
//! aggregation-based algebraic multigrid method*, ETNA 37 (2010) 123–146, as OpenFOAM's
//! `pairGAMGAgglomeration` pairs cells): each level pairs every cell with the free neighbour
//! it is most strongly coupled to (largest |a_ij|), twice (so an aggregate holds about four
//! cells and a level about a quarter of the rows of the one above), and the coarse matrix is
//! the Galerkin product A_c = Pᵀ A P with the piecewise-constant prolongation P
//! (A_c,IJ = Σ_{i∈I, j∈J} a_ij: a coarse row is the sum of its cells' rows). Coarsening stops
//! at [`COARSEST`] rows or when a level would shrink by less than a third; the coarsest system
//! is solved exactly (dense LU with partial pivoting).
//!
//! [`Amg::rebuild`] keeps a hierarchy's aggregates for a new matrix of the same pattern and
//! redoes only the Galerkin products' values (on each level's stored pattern, the same
//! additions in the same order as [`Amg::new`], so the same bits for the same aggregates):
//! [`crate::linsolve`] uses it for the K-cycle's matrices of successive time steps on
//! ≥ [`PAR_MIN`] rows, choosing the aggregates again every [`REAGGREGATE`] set-ups (on the
//! 320² RAS cavity, 20 steps, docs/speed.md third pass, when the K-cycle solved the pressure:
//! 414 iterations against 450 with aggregates chosen every step), and for [`Amg::gamg`]'s
//! hierarchies always (their aggregates follow the mesh).
//!
//! [`Amg::apply`] is one K-cycle from a zero guess (Notay & Vassilevski 2008): forward
//! Gauss–Seidel, the coarse correction, backward Gauss–Seidel, where the coarse problem is
//! solved by one or two flexible-CG steps preconditioned by the next level's cycle (a plain
//! V-cycle with piecewise-constant P loses a factor of about two per level: on the 100×100
//! Laplacian it needs 33 CG iterations to 1e-6 against 13 for the K-cycle). The K-cycle is not
//! a fixed linear operator, so CG uses the flexible (Polak–Ribière) β
//! ([`crate::linsolve::pcg`]); BiCGStab takes it as it is (its right-preconditioned form keeps
//! the preconditioned directions). The tolerances of the fvSolution entry are checked by the
//! Krylov method with OpenFOAM's normalised residual, so the converged answer agrees with any
//! other solver's to that tolerance.
//!
//! Cost (`examples/amg_vs_dic.rs`, CPU time, one core, to OpenFOAM's residual 1e-6 from
//! zero): on the 100×100 Laplacian set-up 1.4 ms (once per matrix), a cycle 0.22 ms (a
//! matrix–vector product 0.015 ms), 13 iterations and 5.7 ms per solve against 144 iterations
//! and 12.8 ms for PCG/DIC; 200×200: 12 iterations, 30 ms against 270 and 98 ms. On a 30³ grid
//! with cells ten times flatter than wide (coefficients 100:1) the pairwise aggregates do not
//! follow the strong direction well enough: 23 iterations, no faster than PCG/DIC (125).
//!
//! In the hierarchy of a matrix of at least [`PAR_MIN`] rows (smaller ones keep the sequential
//! sweeps and their bits), on levels of at least 2 · [`BLOCK_ROWS`] rows the Gauss–Seidel sweeps are the
//! *hybrid* (block-Jacobi / Gauss–Seidel) smoother of Baker, Falgout, Kolev & Yang,
//! *Multigrid smoothers for ultraparallel computing*, SIAM J. Sci. Comput. 33 (2011)
//! 2864–2887, §5: the rows are cut into a fixed number of contiguous blocks (a power of two,
//! from the level's size alone, never from the thread count), each block is swept as
//! Gauss–Seidel in parallel with the others, and a column in another block is read at its value
//! from the sweep's start. The blocks depend on the matrix alone, so the iterates — and the
//! iteration counts — are the same bits on any number of threads. The residual, restriction,
//! prolongation and the K-cycle's products run in parallel over rows with each row's terms in
//! the sequential order (the same bits as one thread). Measured on the first 20 steps of the
//! 320² RAS cavity (benches/fluid-speed, docs/speed.md): 452 pressure iterations in 40 solves,
//! against 449 with the sequential sweeps.

// Row loops index several arrays by the same row or entry, as the equations do.
#![allow(clippy::needless_range_loop)]

use crate::ldu::{RowMatrix, PAR_MIN};
use crate::sweep::Schedule;
use rayon::prelude::*;
use std::sync::Arc;

mod dense;
mod vcycle;
use dense::DenseLu;
pub(crate) use vcycle::CycleWork;

/// Coarsening stops when a level has at most this many rows.
pub const COARSEST: usize = 64;

/// Rows per block of the hybrid Gauss–Seidel sweeps (see the module doc): a level of `n` rows
/// has the largest power of two ≤ n / BLOCK_ROWS blocks, at most [`MAX_BLOCKS`]; a level with
/// one block is swept sequentially. Below about 2000 rows a sweep takes less than handing it
/// to the thread pool.
pub const BLOCK_ROWS: usize = 2048;

/// At most this many blocks per level: each block's boundary rows lag a sweep behind, so more
/// blocks than threads cost iterations for nothing (four serve two to four threads).
pub const MAX_BLOCKS: usize = 4;

/// The rows of each of `nc` aggregates (`agg`: the aggregate of each row), in row order:
/// aggregate `I`'s rows are `members[start[I]..start[I + 1]]`. Returns `(start, members)`.
fn group(agg: &[u32], nc: usize) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; nc + 1];
    for &a in agg {
        start[a as usize + 1] += 1;
    }
    for i in 0..nc {
        start[i + 1] += start[i];
    }
    let mut members = vec![0u32; agg.len()];
    let mut next = start.clone();
    for (i, &a) in agg.iter().enumerate() {
        members[next[a as usize] as usize] = i as u32;
        next[a as usize] += 1;
    }
    (start, members)
}

/// The block boundaries of a level of `n` rows (`nb + 1` ascending row indices from 0 to `n`).
pub(crate) fn block_bounds(n: usize) -> Vec<usize> {
    let q = (n / BLOCK_ROWS).clamp(1, MAX_BLOCKS);
    let nb = 1usize << (usize::BITS - 1 - q.leading_zeros());
    (0..=nb).map(|b| b * n / nb).collect()
}

/// `x` split at the ascending row indices `bounds` (from 0 to `x.len()`), each piece with its
/// first row.
pub(crate) fn split_at_bounds<'x>(
    x: &'x mut [f64],
    bounds: &[usize],
) -> Vec<(usize, &'x mut [f64])> {
    let mut out = Vec::with_capacity(bounds.len() - 1);
    let mut rest = x;
    for w in bounds.windows(2) {
        let (piece, tail) = rest.split_at_mut(w[1] - w[0]);
        out.push((w[0], piece));
        rest = tail;
    }
    out
}

/// A square sparse matrix: compressed rows of off-diagonal entries and a separate diagonal.
#[derive(Clone, Debug)]
struct Csr {
    start: Vec<u32>,
    /// First entry of each row with a column above the row.
    mid: Vec<u32>,
    col: Vec<u32>,
    val: Vec<f64>,
    diag: Vec<f64>,
    /// 1/diag (Gauss–Seidel multiplies instead of dividing).
    inv_diag: Vec<f64>,
    /// Block boundaries of the hybrid Gauss–Seidel sweeps ([`block_bounds`]; one block, a
    /// sequential sweep, unless [`Amg::new`] sets them).
    blocks: Vec<usize>,
    /// The rows that a row of another block reads ([`Csr::set_blocks`]): the values the
    /// hybrid forward sweep of `vcycle` keeps from the sweep's start.
    halo: Vec<u32>,
    /// The sequential sweep on several threads (`crate::sweep::pipeline`), which replaces the
    /// hybrid blocks in the forward sweeps of the levels [`Amg::gamg`] gives one.
    pipeline: Option<Arc<Schedule>>,
}

impl Csr {
    /// A matrix from its rows; the entries of each row are sorted by column (so the columns
    /// below the row come first).
    fn new(start: Vec<u32>, mut col: Vec<u32>, mut val: Vec<f64>, diag: Vec<f64>) -> Csr {
        let n = diag.len();
        let mut mid = vec![0u32; n];
        // Rows in chunks of CHUNK, in parallel when there are several: each row is sorted on
        // its own, so the result does not depend on the chunks.
        const CHUNK: usize = 4096;
        let mut pieces = Vec::with_capacity(n.div_ceil(CHUNK));
        let (mut col_rest, mut val_rest, mut mid_rest) = (&mut col[..], &mut val[..], &mut mid[..]);
        for r0 in (0..n).step_by(CHUNK) {
            let r1 = (r0 + CHUNK).min(n);
            let len = (start[r1] - start[r0]) as usize;
            let (c, ct) = std::mem::take(&mut col_rest).split_at_mut(len);
            let (v, vt) = std::mem::take(&mut val_rest).split_at_mut(len);
            let (m, mt) = std::mem::take(&mut mid_rest).split_at_mut(r1 - r0);
            (col_rest, val_rest, mid_rest) = (ct, vt, mt);
            pieces.push((r0, c, v, m));
        }
        let sort = |(r0, col, val, mid): (usize, &mut [u32], &mut [f64], &mut [u32])| {
            let base = start[r0] as usize;
            let mut pairs: Vec<(u32, f64)> = Vec::new();
            for (il, m) in mid.iter_mut().enumerate() {
                let i = r0 + il;
                let r = start[i] as usize - base..start[i + 1] as usize - base;
                pairs.clear();
                pairs.extend(
                    col[r.clone()]
                        .iter()
                        .copied()
                        .zip(val[r.clone()].iter().copied()),
                );
                pairs.sort_by_key(|p| p.0);
                for (k, p) in r.clone().zip(&pairs) {
                    col[k] = p.0;
                    val[k] = p.1;
                }
                *m = start[i] + pairs.iter().take_while(|p| (p.0 as usize) < i).count() as u32;
            }
        };
        if pieces.len() > 1 {
            crate::team::each(pieces, sort);
        } else {
            pieces.into_iter().for_each(sort);
        }
        let inv_diag = diag.iter().map(|d| 1.0 / d).collect();
        Csr {
            blocks: vec![0, n],
            halo: Vec::new(),
            pipeline: None,
            start,
            mid,
            col,
            val,
            diag,
            inv_diag,
        }
    }

    fn n(&self) -> usize {
        self.diag.len()
    }

    fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.start[i] as usize..self.start[i + 1] as usize
    }

    fn from_rows(m: &RowMatrix<'_>) -> Csr {
        Csr::new(
            m.rows.start.clone(),
            m.rows.col.clone(),
            m.coef.to_vec(),
            m.diag.to_vec(),
        )
    }

    /// Sets the hybrid sweeps' block boundaries and the rows read across them.
    fn set_blocks(&mut self, blocks: Vec<usize>) {
        let mut read = vec![false; self.n()];
        for w in blocks.windows(2) {
            for i in w[0]..w[1] {
                for &j in &self.col[self.row(i)] {
                    if !(w[0]..w[1]).contains(&(j as usize)) {
                        read[j as usize] = true;
                    }
                }
            }
        }
        self.halo = (0..self.n() as u32).filter(|&j| read[j as usize]).collect();
        self.blocks = blocks;
    }

    /// True when the level is swept in parallel blocks.
    fn is_blocked(&self) -> bool {
        self.blocks.len() > 2
    }

    /// r = b − A x (in parallel over rows on a blocked level, each row's terms in order).
    fn residual(&self, b: &[f64], x: &[f64], r: &mut [f64]) {
        let row = |i: usize| {
            let rr = self.row(i);
            let mut s = b[i] - self.diag[i] * x[i];
            for (&j, &v) in self.col[rr.clone()].iter().zip(&self.val[rr]) {
                s -= v * x[j as usize];
            }
            s
        };
        self.each_row(r, row);
    }

    /// out_i = row(i) for every row, in parallel on a blocked level.
    fn each_row(&self, out: &mut [f64], row: impl Fn(usize) -> f64 + Sync) {
        crate::reduce::fill(out, self.is_blocked(), |i, _| row(i));
    }

    /// out = A u (in parallel over rows on a blocked level, each row's terms in order).
    fn mul(&self, u: &[f64], out: &mut [f64]) {
        let row = |i: usize| {
            let mut s = self.diag[i] * u[i];
            for k in self.row(i) {
                s += self.val[k] * u[self.col[k] as usize];
            }
            s
        };
        self.each_row(out, row);
    }

    /// Σ uᵢvᵢ: sequential on an unblocked level, else [`crate::linsolve::dot`]'s fixed blocks
    /// (the same bits on any number of threads).
    fn dot(&self, u: &[f64], v: &[f64]) -> f64 {
        if self.is_blocked() {
            crate::reduce::dot_blocked(u, v)
        } else {
            u.iter().zip(v).map(|(a, b)| a * b).sum()
        }
    }

    /// x split at the block boundaries, each piece with its first row.
    fn split_blocks<'x>(&self, x: &'x mut [f64]) -> Vec<(usize, &'x mut [f64])> {
        split_at_bounds(x, &self.blocks)
    }

    /// Σ_k a_ik x_k over the entries `k` of row i, reading columns inside `lo..lo + xb.len()`
    /// from the block's own values `xb` and the others from `x0`.
    #[inline(always)]
    fn partial_split(&self, k: std::ops::Range<usize>, lo: usize, xb: &[f64], x0: &[f64]) -> f64 {
        let hi = lo + xb.len();
        let mut s = 0.0;
        for (&j, &v) in self.col[k.clone()].iter().zip(&self.val[k]) {
            let j = j as usize;
            s += v * if (lo..hi).contains(&j) {
                xb[j - lo]
            } else {
                x0[j]
            };
        }
        s
    }

    /// The hybrid forward sweep from x = 0 (module doc): each block a forward Gauss–Seidel
    /// sweep of its rows, columns outside it at their value of the sweep's start (zero). The
    /// columns above a row are zero too, so a row reads only its block's rows below it.
    fn gs_forward_blocks_from_zero(&self, b: &[f64], x: &mut [f64]) {
        crate::team::each(self.split_blocks(x), |(lo, xb)| {
            for il in 0..xb.len() {
                let i = lo + il;
                let k = self.start[i] as usize..self.mid[i] as usize;
                let mut s = 0.0;
                for (&j, &v) in self.col[k.clone()].iter().zip(&self.val[k]) {
                    let j = j as usize;
                    if j >= lo {
                        s += v * xb[j - lo];
                    }
                }
                xb[il] = (b[i] - s) * self.inv_diag[i];
            }
        });
    }

    /// The hybrid backward sweep: each block a backward Gauss–Seidel sweep of its rows, columns
    /// outside it at their values of the sweep's start `x0`; the lower part, not yet updated
    /// in the block, reads `x0` throughout.
    fn gs_backward_blocks(&self, b: &[f64], x: &mut [f64]) {
        let x0 = x.to_vec();
        let x0 = &x0[..];
        crate::team::each(self.split_blocks(x), |(lo, xb)| {
            for il in (0..xb.len()).rev() {
                let i = lo + il;
                let (s, m, e) = (
                    self.start[i] as usize,
                    self.mid[i] as usize,
                    self.start[i + 1] as usize,
                );
                let low = b[i] - self.partial(s..m, x0);
                xb[il] = (low - self.partial_split(m..e, lo, xb, x0)) * self.inv_diag[i];
            }
        });
    }

    /// Σ_k a_ik x_k over the entries `k` of row i.
    #[inline(always)]
    fn partial(&self, k: std::ops::Range<usize>, x: &[f64]) -> f64 {
        let mut s = 0.0;
        for (&j, &v) in self.col[k.clone()].iter().zip(&self.val[k]) {
            s += v * x[j as usize];
        }
        s
    }

    /// Forward Gauss–Seidel sweep from x = 0 (as every cycle starts): row i is
    /// (b_i − Σ_{j<i} a_ij x_j) / a_ii, the columns above it being still zero (dropping their
    /// zero products leaves the same bits).
    fn gs_forward_from_zero(&self, b: &[f64], x: &mut [f64]) {
        debug_assert!(x.iter().all(|&v| v == 0.0));
        if self.is_blocked() {
            return self.gs_forward_blocks_from_zero(b, x);
        }
        for i in 0..self.n() {
            let (s, m) = (self.start[i] as usize, self.mid[i] as usize);
            x[i] = (b[i] - self.partial(s..m, x)) * self.inv_diag[i];
        }
    }

    /// Backward Gauss–Seidel sweep (rows in reverse order: each row sums its lower part, not yet updated in this sweep, first).
    fn gs_backward(&self, b: &[f64], x: &mut [f64]) {
        if self.is_blocked() {
            return self.gs_backward_blocks(b, x);
        }
        for i in (0..self.n()).rev() {
            let (s, m, e) = (
                self.start[i] as usize,
                self.mid[i] as usize,
                self.start[i + 1] as usize,
            );
            let low = b[i] - self.partial(s..m, x);
            x[i] = (low - self.partial(m..e, x)) * self.inv_diag[i];
        }
    }

    /// One pass of pairwise aggregation: every cell not yet taken, in row order (`forward`)
    /// or in reverse, is paired with its free neighbour of largest |a_ij| (ties: the first in
    /// column order); a backward pass's aggregate numbers are reversed afterwards, as
    /// OpenFOAM's `pairGAMGAgglomeration` reverses them. A cell with no free
    /// neighbour joins the aggregate of its most strongly coupled neighbour, or stays alone
    /// when it has none. Returns the aggregate of each row and the number of aggregates.
    fn pairwise(&self, forward: bool) -> (Vec<u32>, usize) {
        const FREE: u32 = u32::MAX;
        let n = self.n();
        let mut agg = vec![FREE; n];
        let mut nc = 0u32;
        for ii in 0..n {
            let i = if forward { ii } else { n - 1 - ii };
            if agg[i] != FREE {
                continue;
            }
            let mut best_free: Option<(usize, f64)> = None;
            let mut best_any: Option<(usize, f64)> = None;
            for k in self.row(i) {
                let j = self.col[k] as usize;
                let s = self.val[k].abs();
                if s == 0.0 {
                    continue;
                }
                if agg[j] == FREE && best_free.is_none_or(|(_, b)| s > b) {
                    best_free = Some((j, s));
                }
                if agg[j] != FREE && best_any.is_none_or(|(_, b)| s > b) {
                    best_any = Some((j, s));
                }
            }
            match (best_free, best_any) {
                (Some((j, _)), _) => {
                    agg[i] = nc;
                    agg[j] = nc;
                    nc += 1;
                }
                (None, Some((j, _))) => agg[i] = agg[j],
                (None, None) => {
                    agg[i] = nc;
                    nc += 1;
                }
            }
        }
        if !forward {
            // Aggregates numbered in row order again (OpenFOAM's pairGAMGAgglomeration
            // reverses the map of a backward pass).
            for a in &mut agg {
                *a = nc - 1 - *a;
            }
        }
        (agg, nc as usize)
    }

    /// The Galerkin coarse matrix Pᵀ A P for the piecewise-constant P of `agg` (`nc`
    /// aggregates): coarse row I sums the rows of its cells, entries of the same coarse column
    /// merged, entries inside the aggregate moved to the diagonal.
    fn galerkin(&self, agg: &[u32], nc: usize) -> Csr {
        let (count, members) = group(agg, nc);
        // Coarse rows in chunks, in parallel on large levels: each row is summed exactly as
        // in one sequential pass (its cells in row order, their entries in order), so the
        // bits do not depend on the chunks.
        const CHUNK: usize = 4096;
        let chunk = |rows: std::ops::Range<usize>| {
            let mut diag = Vec::with_capacity(rows.len());
            let mut len = Vec::with_capacity(rows.len());
            let mut col: Vec<u32> = Vec::new();
            let mut val: Vec<f64> = Vec::new();
            // Position of coarse column J in the current coarse row (or u32::MAX).
            let mut pos = vec![u32::MAX; nc];
            for ci in rows {
                let row_start = col.len();
                let mut d = 0.0;
                for &m in &members[count[ci] as usize..count[ci + 1] as usize] {
                    let i = m as usize;
                    d += self.diag[i];
                    for k in self.row(i) {
                        let cj = agg[self.col[k] as usize] as usize;
                        if cj == ci {
                            d += self.val[k];
                        } else if pos[cj] == u32::MAX {
                            pos[cj] = col.len() as u32;
                            col.push(cj as u32);
                            val.push(self.val[k]);
                        } else {
                            val[pos[cj] as usize] += self.val[k];
                        }
                    }
                }
                for &cj in &col[row_start..] {
                    pos[cj as usize] = u32::MAX;
                }
                diag.push(d);
                len.push((col.len() - row_start) as u32);
            }
            (diag, len, col, val)
        };
        let ranges: Vec<std::ops::Range<usize>> = (0..nc)
            .step_by(CHUNK)
            .map(|s| s..(s + CHUNK).min(nc))
            .collect();
        let parts: Vec<_> = if ranges.len() > 1 {
            ranges.into_par_iter().map(chunk).collect()
        } else {
            ranges.into_iter().map(chunk).collect()
        };
        let mut diag = Vec::with_capacity(nc);
        let mut start = Vec::with_capacity(nc + 1);
        start.push(0u32);
        let mut col = Vec::new();
        let mut val = Vec::new();
        for (d, len, c, v) in parts {
            diag.extend(d);
            for l in len {
                start.push(start.last().unwrap() + l);
            }
            col.extend(c);
            val.extend(v);
        }
        Csr::new(start, col, val, diag)
    }
}

/// One level below the finest: its matrix and the aggregate (row of this level) of each row
/// of the level above.
#[derive(Clone, Debug)]
struct Level {
    a: Csr,
    from_fine: Vec<u32>,
    /// The rows of the level above in each aggregate, in row order: aggregate `I`'s are
    /// `members[members_start[I]..members_start[I + 1]]` (the restriction as a gather).
    members_start: Vec<u32>,
    members: Vec<u32>,
    /// For each entry of the level above's matrix: the entry of this level's matrix it is
    /// summed into, or [`ON_DIAG`] for an entry inside its aggregate (the Galerkin product's
    /// pattern, so that [`Amg::rebuild`] redoes only its values).
    target: Vec<u32>,
}

/// [`Level::target`] of an entry that goes to the coarse diagonal.
const ON_DIAG: u32 = u32::MAX;

impl Level {
    fn new(above: &Csr, a: Csr, from_fine: Vec<u32>) -> Level {
        let (members_start, members) = group(&from_fine, a.n());
        // Each fine row's entries on their own (in parallel on large levels).
        let row_targets = |i: usize| -> Vec<u32> {
            let ci = from_fine[i] as usize;
            let cols = &a.col[a.row(ci)];
            above
                .row(i)
                .map(|k| {
                    let cj = from_fine[above.col[k] as usize];
                    if cj as usize == ci {
                        ON_DIAG
                    } else {
                        let p = cols.binary_search(&cj).expect("Galerkin pattern");
                        a.start[ci] + p as u32
                    }
                })
                .collect()
        };
        let target: Vec<u32> = if above.n() >= 2 * BLOCK_ROWS {
            (0..above.n())
                .into_par_iter()
                .flat_map_iter(row_targets)
                .collect()
        } else {
            (0..above.n()).flat_map(row_targets).collect()
        };
        Level {
            a,
            from_fine,
            members_start,
            members,
            target,
        }
    }

    /// The Galerkin product of `above` on this level's pattern: each coarse row the sum of its
    /// cells' rows in row order, their entries in order — the additions of
    /// [`Csr::galerkin`] in the same order, so the same bits for the same aggregates.
    fn galerkin_values(&self, above: &Csr) -> Csr {
        let c = &self.a;
        let mut val = vec![0.0; c.val.len()];
        let mut diag = vec![0.0; c.n()];
        self.galerkin_into(above, &mut val, &mut diag);
        let inv_diag = diag.iter().map(|d| 1.0 / d).collect();
        Csr {
            start: c.start.clone(),
            mid: c.mid.clone(),
            col: c.col.clone(),
            val,
            diag,
            inv_diag,
            blocks: c.blocks.clone(),
            halo: c.halo.clone(),
            pipeline: c.pipeline.clone(),
        }
    }

    /// This level's matrix redone in place for a new `above` (the values of
    /// [`Self::galerkin_values`], without allocating).
    fn refresh_values(&mut self, above: &Csr) {
        let mut a = std::mem::take(&mut self.a.val);
        let mut d = std::mem::take(&mut self.a.diag);
        self.galerkin_into(above, &mut a, &mut d);
        self.a.val = a;
        self.a.diag = d;
        let (diag, inv) = (&self.a.diag, &mut self.a.inv_diag);
        inv.iter_mut().zip(diag).for_each(|(i, d)| *i = 1.0 / d);
    }

    /// The values of [`Self::galerkin_values`] written into `val` (one per entry of this
    /// level's pattern) and `diag`, whatever they held; rows in chunks, in parallel when there
    /// are several (each coarse row is summed on its own, so the chunks do not change the bits).
    fn galerkin_into(&self, above: &Csr, val: &mut [f64], diag: &mut [f64]) {
        // Only the pattern of self.a is read ([`Self::refresh_values`] holds its values).
        let c = &self.a;
        let nc = diag.len();
        const CHUNK: usize = 4096;
        let mut pieces = Vec::with_capacity(nc.div_ceil(CHUNK));
        let (mut val_rest, mut diag_rest) = (val, diag);
        for r0 in (0..nc).step_by(CHUNK) {
            let r1 = (r0 + CHUNK).min(nc);
            let len = (c.start[r1] - c.start[r0]) as usize;
            let (v, vt) = std::mem::take(&mut val_rest).split_at_mut(len);
            let (d, dt) = std::mem::take(&mut diag_rest).split_at_mut(r1 - r0);
            (val_rest, diag_rest) = (vt, dt);
            pieces.push((r0, v, d));
        }
        let sum = |(r0, v, d): (usize, &mut [f64], &mut [f64])| {
            v.fill(0.0);
            let base = c.start[r0] as usize;
            for (il, dc) in d.iter_mut().enumerate() {
                let ci = r0 + il;
                let mut s = 0.0;
                let ms = self.members_start[ci] as usize..self.members_start[ci + 1] as usize;
                for &m in &self.members[ms] {
                    let i = m as usize;
                    s += above.diag[i];
                    for k in above.row(i) {
                        match self.target[k] {
                            ON_DIAG => s += above.val[k],
                            t => v[t as usize - base] += above.val[k],
                        }
                    }
                }
                *dc = s;
            }
        };
        if pieces.len() > 1 {
            crate::team::each(pieces, sum);
        } else {
            pieces.into_iter().for_each(sum);
        }
    }

    /// bc = Pᵀ r: each aggregate's sum of its rows' r, added in row order (the same bits as
    /// scattering r row by row), in parallel over aggregates when `parallel`.
    fn restrict(&self, r: &[f64], bc: &mut [f64], parallel: bool) {
        let sum = |ci: usize| {
            let k = self.members_start[ci] as usize..self.members_start[ci + 1] as usize;
            let mut s = 0.0;
            for &m in &self.members[k] {
                s += r[m as usize];
            }
            s
        };
        crate::reduce::fill(bc, parallel, |ci, _| sum(ci));
    }

    /// x += P xc, in parallel when `parallel`.
    fn prolong(&self, xc: &[f64], x: &mut [f64], parallel: bool) {
        crate::reduce::fill(x, parallel, |i, xi| xi + xc[self.from_fine[i] as usize]);
    }
}

/// The multigrid hierarchy of one matrix (see the module doc).
#[derive(Clone, Debug)]
pub struct Amg {
    fine: Csr,
    coarse: Vec<Level>,
    direct: DenseLu,
    /// Set-ups since the aggregates were chosen ([`Amg::rebuild`]).
    age: usize,
    /// The aggregates follow the mesh, not the matrix ([`Amg::gamg`]): kept for good.
    geometric: bool,
}

/// [`Amg::rebuild`] keeps a hierarchy's aggregates for at most this many set-ups (the
/// pressure matrix of a PISO step changes with 1/A, slowly from step to step; the aggregates
/// follow its strongest couplings, so they are chosen again every so often).
pub const REAGGREGATE: usize = 10;

impl Amg {
    /// Builds the hierarchy of `m`.
    pub fn new(m: &RowMatrix<'_>) -> Amg {
        let fine = Csr::from_rows(m);
        let mut coarse: Vec<Level> = Vec::new();
        loop {
            let a = coarse.last().map_or(&fine, |l| &l.a);
            let n = a.n();
            if n <= COARSEST {
                break;
            }
            // Two pairwise passes: aggregates of up to four cells.
            let (agg1, n1) = a.pairwise(true);
            let a1 = a.galerkin(&agg1, n1);
            let (agg2, n2) = a1.pairwise(true);
            if 3 * n2 > 2 * n {
                break;
            }
            let from_fine: Vec<u32> = agg1.iter().map(|&i| agg2[i as usize]).collect();
            let ac = a.galerkin(&from_fine, n2);
            let level = Level::new(a, ac, from_fine);
            coarse.push(level);
        }
        Amg::finish(fine, coarse)
    }

    /// The hierarchy of `fine` and its `coarse` levels: the coarsest factorised, the hybrid
    /// blocks of every level set on a matrix of ≥ [`PAR_MIN`] rows.
    fn finish(mut fine: Csr, mut coarse: Vec<Level>) -> Amg {
        let direct = DenseLu::new(coarse.last().map_or(&fine, |l| &l.a));
        if fine.n() >= PAR_MIN {
            fine.set_blocks(block_bounds(fine.n()));
            for l in &mut coarse {
                l.a.set_blocks(block_bounds(l.a.n()));
            }
        }
        Amg {
            fine,
            coarse,
            direct,
            age: 0,
            geometric: false,
        }
    }

    /// The hierarchy of `m` with this one's aggregates (the pairwise passes, the sequential
    /// part of [`Amg::new`], skipped): each level's Galerkin product redone on its pattern
    /// (`Level::galerkin_values`), the coarsest factorised again. `None` when `m` has not
    /// the rows of this hierarchy's finest level, or when the aggregates were chosen
    /// [`REAGGREGATE`] set-ups ago (then [`Amg::new`] chooses them again for `m`).
    pub fn rebuild(&self, m: &RowMatrix<'_>) -> Option<Amg> {
        let fine = Csr::from_rows(m);
        let aged = !self.geometric && self.age + 1 >= REAGGREGATE;
        if aged || fine.start != self.fine.start || fine.col != self.fine.col {
            return None;
        }
        let mut fine = fine;
        fine.blocks = self.fine.blocks.clone();
        fine.halo = self.fine.halo.clone();
        fine.pipeline = self.fine.pipeline.clone();
        let mut coarse: Vec<Level> = Vec::with_capacity(self.coarse.len());
        for l in &self.coarse {
            let above = coarse.last().map_or(&fine, |c: &Level| &c.a);
            let a = l.galerkin_values(above);
            coarse.push(Level {
                a,
                from_fine: l.from_fine.clone(),
                members_start: l.members_start.clone(),
                members: l.members.clone(),
                target: l.target.clone(),
            });
        }
        let direct = DenseLu::new(coarse.last().map_or(&fine, |l| &l.a));
        Some(Amg {
            fine,
            coarse,
            direct,
            age: self.age + 1,
            geometric: self.geometric,
        })
    }

    /// [`Self::rebuild`] in place: this hierarchy's values redone for `m` without allocating
    /// (the same bits as [`Self::rebuild`]). False, and the hierarchy left as it was, when
    /// `rebuild` would refuse.
    pub fn refresh(&mut self, m: &RowMatrix<'_>) -> bool {
        if !self.geometric && self.age + 1 >= REAGGREGATE {
            return false;
        }
        let fine = &mut self.fine;
        if m.rows.start == fine.start && m.rows.col == fine.col {
            // m's rows were already in column order: its entries are the level's, in order.
            let parallel = fine.n() >= PAR_MIN;
            crate::reduce::copy_values(&m.coef, &mut fine.val, parallel);
            crate::reduce::copy_values(m.diag, &mut fine.diag, parallel);
        } else {
            let new = Csr::from_rows(m);
            if new.start != fine.start || new.col != fine.col {
                return false;
            }
            fine.val = new.val;
            fine.diag = new.diag;
        }
        let (diag, inv) = (&fine.diag, &mut fine.inv_diag);
        inv.iter_mut().zip(diag).for_each(|(i, d)| *i = 1.0 / d);
        for l in 0..self.coarse.len() {
            let (done, rest) = self.coarse.split_at_mut(l);
            let above = done.last().map_or(&self.fine, |c| &c.a);
            rest[0].refresh_values(above);
        }
        self.direct = DenseLu::new(self.coarse.last().map_or(&self.fine, |l| &l.a));
        self.age += 1;
        true
    }

    /// Number of levels, the finest included.
    pub fn n_levels(&self) -> usize {
        self.coarse.len() + 1
    }

    /// Rows of each level, finest first.
    pub fn sizes(&self) -> Vec<usize> {
        std::iter::once(self.fine.n())
            .chain(self.coarse.iter().map(|l| l.a.n()))
            .collect()
    }

    /// z = M⁻¹ r: one V-cycle from z = 0.
    pub fn apply(&self, r: &[f64], z: &mut [f64]) {
        z.iter_mut().for_each(|v| *v = 0.0);
        self.cycle(0, r, z);
    }

    fn matrix(&self, level: usize) -> &Csr {
        if level == 0 {
            &self.fine
        } else {
            &self.coarse[level - 1].a
        }
    }

    /// One cycle on `level` from x = 0: forward Gauss–Seidel, the coarse correction (exact on
    /// the coarsest level, else [`Self::krylov`] on the next level, or its cycle when that is
    /// the coarsest), backward Gauss–Seidel.
    fn cycle(&self, level: usize, b: &[f64], x: &mut [f64]) {
        let a = self.matrix(level);
        if level == self.coarse.len() {
            self.direct.solve(b, x);
            return;
        }
        a.gs_forward_from_zero(b, x);
        let mut r = vec![0.0; a.n()];
        a.residual(b, x, &mut r);
        let next = &self.coarse[level];
        let mut bc = vec![0.0; next.a.n()];
        next.restrict(&r, &mut bc, a.is_blocked());
        let mut xc = vec![0.0; next.a.n()];
        if level + 1 < self.coarse.len() {
            self.krylov(level + 1, &bc, &mut xc);
        } else {
            self.cycle(level + 1, &bc, &mut xc);
        }
        next.prolong(&xc, x, a.is_blocked());
        a.gs_backward(b, x);
    }

    /// The K-cycle's coarse solve (Notay & Vassilevski, *Recursive Krylov-based multigrid
    /// cycles*, Numer. Linear Algebra Appl. 15 (2008) 473–487, Alg. 2.1): x ≈ A⁻¹ b on `level`
    /// by one or two steps of flexible conjugate gradients preconditioned by that level's
    /// cycle; the second step only when the first leaves more than a quarter of |b|.
    fn krylov(&self, level: usize, b: &[f64], x: &mut [f64]) {
        let a = self.matrix(level);
        let n = a.n();
        let dot = |u: &[f64], v: &[f64]| a.dot(u, v);
        let mul = |u: &[f64], out: &mut [f64]| a.mul(u, out);
        let mut v = vec![0.0; n];
        self.cycle(level, b, &mut v);
        let mut w = vec![0.0; n];
        mul(&v, &mut w);
        let rho1 = dot(&v, b);
        let alpha1 = dot(&v, &w);
        if alpha1 <= 0.0 {
            x.copy_from_slice(&v);
            return;
        }
        let mut r1 = vec![0.0; n];
        a.each_row(&mut r1, |i| b[i] - rho1 / alpha1 * w[i]);
        if dot(&r1, &r1).sqrt() <= 0.25 * dot(b, b).sqrt() {
            a.each_row(x, |i| rho1 / alpha1 * v[i]);
            return;
        }
        let mut v2 = vec![0.0; n];
        self.cycle(level, &r1, &mut v2);
        let mut w2 = vec![0.0; n];
        mul(&v2, &mut w2);
        let gamma = dot(&v2, &w);
        let beta = dot(&v2, &w2);
        let rho2 = dot(&v2, &r1);
        let alpha2 = beta - gamma * gamma / alpha1;
        if alpha2 <= 0.0 {
            a.each_row(x, |i| rho1 / alpha1 * v[i]);
            return;
        }
        let c1 = rho1 / alpha1 - gamma * rho2 / (alpha1 * alpha2);
        let c2 = rho2 / alpha2;
        a.each_row(x, |i| c1 * v[i] + c2 * v2[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::FvGeometry;
    use crate::ldu::Ldu;

    /// The 5-point Laplacian of an nx × ny grid with one Dirichlet side (SPD).
    fn laplacian(nx: usize, ny: usize) -> (FvGeometry, Ldu) {
        laplacian_box([1.0, 1.0, 0.1], [nx, ny, 1])
    }

    /// The Laplacian (|S|/δ per face) of a box of `size` in `n` cells with a Dirichlet wall at
    /// x = 0 (SPD), as the pressure equation of a uniform mesh.
    pub(super) fn laplacian_box(size: [f64; 3], n: [usize; 3]) -> (FvGeometry, Ldu) {
        let m = mesh::build::uniform_box([0.0; 3], size, n);
        let g = FvGeometry::new(&m).unwrap();
        let mut a = Ldu::zeros(&g);
        for f in 0..g.n_internal {
            let c = g.mag_sf[f] * g.delta_coeff[f];
            a.upper[f] = -c;
            a.lower[f] = -c;
            a.diag[g.owner[f] as usize] += c;
            a.diag[g.neighbour[f] as usize] += c;
        }
        for f in g.n_internal..g.n_faces() {
            if g.cf[f][0] < 1e-12 {
                a.diag[g.owner[f] as usize] += g.mag_sf[f] * g.delta_coeff[f];
            }
        }
        (g, a)
    }

    #[test]
    fn coarse_rows_sum_the_fine_rows() {
        let (g, a) = laplacian(13, 9);
        let m = RowMatrix::new(&a, &g);
        let amg = Amg::new(&m);
        let sizes = amg.sizes();
        assert!(amg.n_levels() >= 2 && sizes[0] == 117, "{sizes:?}");
        // Pᵀ A P 1 = Pᵀ (A 1): the coarse row sums are the sums of the fine row sums.
        let fine = &amg.fine;
        let lvl = &amg.coarse[0];
        let mut fine_sums = vec![0.0; lvl.a.n()];
        for i in 0..fine.n() {
            let s: f64 = fine.diag[i] + fine.row(i).map(|k| fine.val[k]).sum::<f64>();
            fine_sums[lvl.from_fine[i] as usize] += s;
        }
        for ci in 0..lvl.a.n() {
            let s: f64 = lvl.a.diag[ci] + lvl.a.row(ci).map(|k| lvl.a.val[k]).sum::<f64>();
            assert!(
                (s - fine_sums[ci]).abs() < 1e-12,
                "{ci}: {s} vs {}",
                fine_sums[ci]
            );
        }
        // Every cell has an aggregate; pairs of pairs, a left-over cell joining a neighbour's.
        let mut size = vec![0; lvl.a.n()];
        for &c in &lvl.from_fine {
            size[c as usize] += 1;
        }
        assert!(size.iter().all(|&s| (1..=9).contains(&s)), "{size:?}");
        // The coarse matrix stays symmetric.
        let c = &lvl.a;
        for i in 0..c.n() {
            for k in c.row(i) {
                let j = c.col[k] as usize;
                let back = c.row(j).find(|&q| c.col[q] as usize == i).unwrap();
                assert!((c.val[k] - c.val[back]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_rebuilt_hierarchy_is_the_galerkin_product_on_the_kept_aggregates() {
        let (g, a) = laplacian(70, 60);
        let m = RowMatrix::new(&a, &g);
        let amg = Amg::new(&m);
        assert!(amg.n_levels() >= 3, "{:?}", amg.sizes());
        // The same matrix: the same bits as choosing the aggregates again (the same sums in
        // the same order).
        let same = amg.rebuild(&m).unwrap();
        for (l, r) in amg.coarse.iter().zip(&same.coarse) {
            assert_eq!(
                (&l.a.diag, &l.a.val, &l.a.col),
                (&r.a.diag, &r.a.val, &r.a.col)
            );
        }
        // Twice the matrix (exact in floating point): Pᵀ(2A)P = 2 PᵀAP on every level.
        let mut a2 = a.clone();
        for v in a2.diag.iter_mut().chain(&mut a2.upper).chain(&mut a2.lower) {
            *v *= 2.0;
        }
        let m2 = RowMatrix::new(&a2, &g);
        let twice = amg.rebuild(&m2).unwrap();
        for (l, r) in amg.coarse.iter().zip(&twice.coarse) {
            let doubled: Vec<f64> = l.a.val.iter().map(|v| 2.0 * v).collect();
            let ddiag: Vec<f64> = l.a.diag.iter().map(|v| 2.0 * v).collect();
            assert_eq!((&ddiag, &doubled), (&r.a.diag, &r.a.val));
        }
        // The aggregates are chosen again after REAGGREGATE set-ups.
        let mut h = amg;
        for _ in 1..REAGGREGATE {
            h = h.rebuild(&m).unwrap();
        }
        assert!(h.rebuild(&m).is_none());
    }

    #[test]
    fn a_cycle_reduces_the_error() {
        let (g, a) = laplacian(40, 30);
        let m = RowMatrix::new(&a, &g);
        let amg = Amg::new(&m);
        // As a stationary iteration x ← x + M(b − Ax) it converges: the error in the A-norm
        // shrinks by at least ½ per cycle on average (measured: 8 cycles give 6.8e-4).
        let x_true: Vec<f64> = (0..g.n_cells)
            .map(|i| ((i * 7 % 13) as f64).sin())
            .collect();
        let first = error_after(&amg, &m, &x_true, 0);
        let last = error_after(&amg, &m, &x_true, 8);
        assert!(last < 0.5f64.powi(8) * first, "{first} → {last}");
    }

    /// The A-norm of the error after `cycles` stationary multigrid iterations
    /// x ← x + M(b − Ax) from zero towards `x_true` (as in `a_cycle_reduces_the_error`).
    fn error_after(amg: &Amg, m: &RowMatrix<'_>, x_true: &[f64], cycles: usize) -> f64 {
        let n = x_true.len();
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut b = vec![0.0; n];
        m.mul(x_true, &mut b);
        let (mut x, mut r, mut z) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for _ in 0..cycles {
            amg.fine.residual(&b, &x, &mut r);
            amg.apply(&r, &mut z);
            assert!(dot(&r, &z) > 0.0, "the cycle is not positive definite");
            x.iter_mut().zip(&z).for_each(|(x, z)| *x += z);
        }
        let e: Vec<f64> = x.iter().zip(x_true).map(|(a, b)| a - b).collect();
        let mut ae = vec![0.0; n];
        m.mul(&e, &mut ae);
        dot(&e, &ae).sqrt()
    }

    #[test]
    fn blocked_sweeps_give_the_same_bits_on_any_thread_count_and_converge_as_sequential_ones() {
        // 260 × 200 = 52 000 rows ≥ PAR_MIN: the hierarchy's large levels are blocked.
        let (g, a) = laplacian(260, 200);
        let m = RowMatrix::new(&a, &g);
        let amg = Amg::new(&m);
        let n = g.n_cells;
        assert_eq!(amg.fine.blocks, vec![0, n / 4, n / 2, 3 * n / 4, n]);
        assert!(amg.coarse[0].a.is_blocked());
        let r: Vec<f64> = (0..n).map(|i| ((i * 7 % 13) as f64).sin()).collect();
        let cycle_on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut z = vec![0.0; n];
                amg.apply(&r, &mut z);
                z
            })
        };
        let one = cycle_on(1);
        assert_eq!(one, cycle_on(2));
        assert_eq!(one, cycle_on(3));
        // The same hierarchy swept sequentially: the blocks lag at their edges only, so
        // the error falls about as fast (measured: 8 cycles take the error from 140 to 6.9e-3 blocked, 5.1e-3 sequential).
        let mut seq = amg.clone();
        seq.fine.set_blocks(vec![0, n]);
        for l in &mut seq.coarse {
            let n = l.a.n();
            l.a.set_blocks(vec![0, n]);
        }
        let x_true: Vec<f64> = (0..n).map(|i| ((i * 3 % 17) as f64).cos()).collect();
        let blocked = error_after(&amg, &m, &x_true, 8);
        let sequential = error_after(&seq, &m, &x_true, 8);
        let first = error_after(&amg, &m, &x_true, 0);
        assert!(
            blocked < 0.5f64.powi(8) * first && blocked < 1.5 * sequential,
            "{first} → blocked {blocked}, sequential {sequential}"
        );
    }

    #[test]
    fn k_cycle_solves_symmetric_and_non_symmetric_systems_in_few_iterations() {
        use crate::linsolve::{solve, Method, Preconditioner, SolverControls};
        let (g, mut a) = laplacian(60, 50);
        let n = g.n_cells;
        let x_true: Vec<f64> = (0..n).map(|i| 1.0 + ((i * 3 % 17) as f64).cos()).collect();
        let c = SolverControls {
            tolerance: 1e-10,
            ..SolverControls::default()
        };
        let run = |a: &Ldu, method| {
            let mut b = vec![0.0; n];
            a.mul(&g, &x_true, &mut b);
            let mut x = vec![0.0; n];
            let s = solve(method, a, &g, &b, &mut x, &c, "x").unwrap();
            let err = x
                .iter()
                .zip(&x_true)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            (s.iterations, err)
        };
        // The K-cycle as CG's preconditioner (fvSolution's `PCG` with `preconditioner GAMG`;
        // `GAMG` itself on a symmetric matrix is the V-cycle of `vcycle`, tested there).
        let (it_amg, err) = run(&a, Method::Pcg(Preconditioner::Amg));
        let (it_dic, _) = run(&a, Method::Pcg(Preconditioner::Dic));
        assert!(
            err < 1e-7 && it_amg * 4 < it_dic,
            "{it_amg} vs {it_dic}, {err}"
        );
        // Upwind convection along x makes it non-symmetric: BiCGStab with the cycle.
        for f in 0..g.n_internal {
            let flux = 0.5 * g.sf[f][0];
            a.lower[f] -= flux.max(0.0);
            a.upper[f] -= (-flux).max(0.0);
            a.diag[g.owner[f] as usize] += flux.max(0.0);
            a.diag[g.neighbour[f] as usize] += (-flux).max(0.0);
        }
        assert!(!a.is_symmetric());
        let (it, err) = run(&a, Method::Gamg);
        assert!(err < 1e-7 && it < 30, "{it}, {err}");
    }
}
