//! The Gauss–Seidel sweeps of the `smoothSolver` ([`crate::linsolve::smooth`]) on the row form
//! of a matrix: x_c ← (b′_c − Σ_k a_ck x_k) / a_cc over the triangular entries of row c (the
//! interface entries are in b′, updated once per sweep as OpenFOAM v1912 does).
//!
//! On fewer than [`PAR_MIN`] rows, and wherever the caller does not ask for the hybrid sweep,
//! the sweep is sequential, row by row, each row seeing the rows already done: OpenFOAM's
//! `GaussSeidelSmoother` bit for bit (every existing test case, and OpenFOAM's iteration
//! counts). On large meshes whose numbering allows it ([`RowAddressing::pipeline`]) that
//! sequential sweep runs on several threads with the same bits ([`pipeline`]); the momentum
//! predictor then asks for it rather than the hybrid sweep. Elsewhere the momentum predictor
//! asks for the hybrid sweep: on larger matrices it is then the *hybrid* (block-Jacobi /
//! Gauss–Seidel) sweep of Baker, Falgout, Kolev & Yang, *Multigrid smoothers for ultraparallel
//! computing*, SIAM J. Sci. Comput. 33 (2011) 2864–2887, §5, as [`crate::amg`] sweeps its large
//! levels: the rows are cut into the blocks of [`crate::amg::block_bounds`] (from the number of
//! rows alone, never from the thread count), each block is swept as Gauss–Seidel in parallel
//! with the others, and a column in another block is read at its value from the sweep's start.
//! The iterates therefore do not depend on the number of threads; they differ from the
//! sequential sweep's only through the rows next to a block boundary, so the iteration counts
//! and the converged answer (to the solver's tolerance) stay those of the sequential sweep:
//! measured on 20 steps of the 320² RAS cavity (benches/fluid-speed, docs/speed.md, third
//! pass) U moved by 2e-5 of its largest magnitude, the U sweeps 463 against 461. k and ε keep
//! the sequential sweep (pipelined where it can be): with the hybrid one their solves stop at the same normalised
//! residual but leave their error along the block edges, where ε is small, and νt = Cμ k²/ε
//! there moved by 0.5 % (4e-3 of its largest value, against 7e-5 from pisoFoam before).

pub(crate) mod lanes;
mod pipeline;

use crate::ldu::{RowAddressing, RowMatrix, PAR_MIN};
pub(crate) use pipeline::{Pipeline, Schedule};

/// How the rows of one matrix are swept.
pub(crate) struct Sweeper<'a> {
    /// Block boundaries (`[0, n]`: one block, the sequential sweep).
    blocks: Vec<usize>,
    /// The values at the sweep's start (hybrid sweeps only).
    x0: Vec<f64>,
    /// The sequential sweep on several threads ([`pipeline`]), where the mesh allows it.
    pipeline: Option<Pipeline<'a>>,
}

impl<'a> Sweeper<'a> {
    /// The sweeps of a matrix on `rows`: hybrid when asked (`hybrid`) on ≥ [`PAR_MIN`] rows,
    /// else sequential — on several threads ([`RowAddressing::pipeline`]) where the pool has
    /// them and the mesh's numbering allows, with the same bits.
    pub(crate) fn new(rows: &'a RowAddressing, hybrid: bool) -> Sweeper<'a> {
        let n = rows.n_rows();
        if hybrid && n >= PAR_MIN {
            Sweeper {
                blocks: crate::amg::block_bounds(n),
                x0: vec![0.0; n],
                pipeline: None,
            }
        } else {
            let pipeline = if rayon::current_num_threads() > 1 {
                rows.pipeline().map(Pipeline::new)
            } else {
                None
            };
            Sweeper {
                blocks: vec![0, n],
                x0: Vec::new(),
                pipeline,
            }
        }
    }

    /// One sweep over the rows, forward or (`backward`) in reverse order, for the right-hand
    /// side `bp` (b′: b less the interface part).
    pub(crate) fn sweep(&mut self, m: &RowMatrix<'_>, bp: &[f64], x: &mut [f64], backward: bool) {
        let rows = m.rows;
        if let Some(p) = &mut self.pipeline {
            p.sweep(m, bp, x, backward);
            return;
        }
        if self.blocks.len() <= 2 {
            let relax = |x: &mut [f64], c: usize| {
                let mut s = bp[c];
                for k in rows.start[c] as usize..rows.end[c] as usize {
                    s -= m.coef[k] * x[rows.col[k] as usize];
                }
                x[c] = s / m.diag[c];
            };
            if backward {
                (0..x.len()).rev().for_each(|c| relax(x, c));
            } else {
                (0..x.len()).for_each(|c| relax(x, c));
            }
            return;
        }
        self.x0.copy_from_slice(x);
        let x0 = &self.x0[..];
        let pieces = crate::amg::split_at_bounds(x, &self.blocks);
        crate::team::each(pieces, |(lo, xb)| {
            let hi = lo + xb.len();
            let relax = |xb: &mut [f64], c: usize| {
                let mut s = bp[c];
                for k in rows.start[c] as usize..rows.end[c] as usize {
                    let j = rows.col[k] as usize;
                    let v = if (lo..hi).contains(&j) {
                        xb[j - lo]
                    } else {
                        x0[j]
                    };
                    s -= m.coef[k] * v;
                }
                xb[c - lo] = s / m.diag[c];
            };
            if backward {
                (lo..hi).rev().for_each(|c| relax(xb, c));
            } else {
                (lo..hi).for_each(|c| relax(xb, c));
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::FvGeometry;
    use crate::ldu::Ldu;

    #[test]
    fn hybrid_sweeps_give_the_same_bits_on_any_thread_count_and_converge_as_sequential_ones() {
        // A diagonally dominant convection–diffusion matrix (upwind along x) on 260 × 200
        // cells ≥ PAR_MIN: four blocks.
        let m = mesh::build::uniform_box([0.0; 3], [1.0, 1.0, 0.1], [260, 200, 1]);
        let g = FvGeometry::new(&m).unwrap();
        let n = g.n_cells;
        let mut a = Ldu::zeros(&g);
        for f in 0..g.n_internal {
            let d = g.mag_sf[f] * g.delta_coeff[f];
            let flux = 0.3 * g.sf[f][0];
            a.upper[f] = -d - (-flux).max(0.0);
            a.lower[f] = -d - flux.max(0.0);
            a.diag[g.owner[f] as usize] += d + flux.max(0.0);
            a.diag[g.neighbour[f] as usize] += d + (-flux).max(0.0);
        }
        for (c, d) in a.diag.iter_mut().enumerate() {
            *d += g.v[c] / 1e-6;
        }
        let rm = RowMatrix::new(&a, &g);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7 % 13) as f64).sin()).collect();
        let run = |threads: usize, sweeps: usize, hybrid: bool| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut s = Sweeper::new(&g.rows, true);
                if !hybrid {
                    s.blocks = vec![0, n];
                }
                let mut x = vec![0.0; n];
                for i in 0..sweeps {
                    s.sweep(&rm, &b, &mut x, i % 2 == 1);
                }
                x
            })
        };
        assert_eq!(Sweeper::new(&g.rows, true).blocks.len(), 5);
        assert_eq!(Sweeper::new(&g.rows, false).blocks, vec![0, n]);
        let one = run(1, 3, true);
        assert_eq!(one, run(2, 3, true));
        assert_eq!(one, run(3, 3, true));
        // Below PAR_MIN rows: the sequential sweep.
        let small = RowAddressing::new(PAR_MIN - 1, &[], &[], 0);
        assert_eq!(Sweeper::new(&small, true).blocks, vec![0, PAR_MIN - 1]);
        // The residual after a few sweeps: the hybrid sweep lags only at the block edges.
        let res = |x: &[f64]| {
            let mut ax = vec![0.0; n];
            rm.mul(x, &mut ax);
            ax.iter().zip(&b).map(|(a, b)| (a - b).abs()).sum::<f64>()
        };
        let r0 = res(&vec![0.0; n]);
        let (rh, rs) = (res(&run(2, 6, true)), res(&run(1, 6, false)));
        assert!(
            rh < 1e-2 * r0 && rh < 1.5 * rs,
            "{r0} → hybrid {rh}, sequential {rs}"
        );
        assert_ne!(run(1, 6, true), run(1, 6, false));
    }
}
