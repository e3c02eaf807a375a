//! OpenFOAM's GAMG iteration: the V-cycle of `GAMGSolver::Vcycle` (OpenFOAM v1912,
//! `GAMGSolverSolve.C`) with its default controls, on the hierarchy of [`Amg::gamg`].
//! [`crate::linsolve::gamg`] applies it as flexible CG's preconditioner (from x = 0, b = r).
//!
//! With `nPreSweeps 0` the residual of the finest level is restricted down every level
//! unchanged (a coarse level's source is the sum of its aggregates' sources); the coarsest
//! level is solved exactly; going up, each coarse level's correction is the prolonged
//! correction of the level below, scaled (below), then smoothed by
//! min(`nPostSweeps` + l · `postSweepsLevelMultiplier`, `maxPostSweeps`) = min(2 + l, 4)
//! forward Gauss–Seidel sweeps on level l (l = 0 the first coarse level); the finest
//! correction is the prolonged one, scaled, added to x, and x is smoothed by `nFinestSweeps`
//! = 2 sweeps.
//!
//! The scaling (`GAMGSolver::scale`, `scaleCorrection`, on for symmetric matrices) takes the
//! factor s = (b·c)/(c·Ac) that minimises the energy norm of the error along the prolonged
//! correction c and adds a Jacobi step: c ← s c + (b − s A c)/D. It is skipped on the level
//! just above the coarsest, whose correction is the exact coarse solution prolonged (s = 1).
//! Piecewise-constant prolongation under-corrects smooth errors; without the scaling the same
//! cycles reduce a 3-D Poisson residual by 0.42 per cycle instead of 0.14 (`tests` below).
//!
//! The sweeps are those of [`Csr`]: sequential on small levels; on large ones OpenFOAM's
//! sequential sweep run on several threads where the level's numbering allows
//! (`crate::sweep::pipeline`, the sequential bits), else the hybrid blocks of the module doc
//! (the same bits on any thread count either way).

// Row loops index several arrays by the same row, as the equations do.
#![allow(clippy::needless_range_loop)]

use super::{Amg, Csr, Level};
use crate::ldu::RowMatrix;
use crate::sweep::{Pipeline, Schedule};
use std::sync::atomic::Ordering;
use std::sync::Arc;

/// OpenFOAM's `nPostSweeps` (default 2): sweeps on the first coarse level.
const N_POST: usize = 2;
/// OpenFOAM's `maxPostSweeps` (default 4).
const MAX_POST: usize = 4;
/// OpenFOAM's `nFinestSweeps` (default 2).
const N_FINEST: usize = 2;

impl Csr {
    /// Row i of a forward Gauss–Seidel sweep, x_i = ((b_i − Σ_{j>i} a_ij x_j) − Σ_{j<i} a_ij x_j)
    /// / a_ii, with `x(j)` the value of column j: the part above the row (values from before
    /// the sweep) first, the part below (this sweep's values) last, so that what waits for the
    /// row just updated is one product, one sum, one subtraction and one multiplication — a
    /// sweep is a chain of such rows, and its length sets the sweep's time. (The sum of a row
    /// in column order, lower part first, had every upper product on that chain; the two
    /// orders differ by round-off only, and every path below uses this one.)
    #[inline(always)]
    fn forward_row(&self, i: usize, bi: f64, x: impl Fn(usize) -> f64) -> f64 {
        let (s, m, e) = (
            self.start[i] as usize,
            self.mid[i] as usize,
            self.start[i + 1] as usize,
        );
        let mut up = bi;
        for (&j, &v) in self.col[m..e].iter().zip(&self.val[m..e]) {
            up -= v * x(j as usize);
        }
        let mut lo = 0.0;
        for (&j, &v) in self.col[s..m].iter().zip(&self.val[s..m]) {
            lo += v * x(j as usize);
        }
        (up - lo) * self.inv_diag[i]
    }

    /// One forward Gauss–Seidel sweep from `x` ([`Csr::forward_row`]): the sequential sweep,
    /// on several threads where the level has a pipeline; else, on a blocked level, the hybrid
    /// blocks (a column in another block read at its value from the sweep's start, kept in
    /// `x0`).
    fn gs_forward(&self, b: &[f64], x: &mut [f64], x0: &mut [f64]) {
        if let Some(p) = self
            .pipeline
            .as_deref()
            .filter(|_| rayon::current_num_threads() > 1)
        {
            // The sequential sweep's arithmetic (below), rows side by side where independent.
            Pipeline::new(p).run(x, false, |i, xa| {
                self.forward_row(i, b[i], |j| f64::from_bits(xa[j].load(Ordering::Relaxed)))
            });
        } else if self.is_blocked() && self.pipeline.is_none() {
            // Only the rows read across the blocks need their start values.
            for &j in &self.halo {
                x0[j as usize] = x[j as usize];
            }
            let x0 = &*x0;
            crate::team::each(self.split_blocks(x), |(lo, xb)| {
                let hi = lo + xb.len();
                for il in 0..xb.len() {
                    let i = lo + il;
                    let v = self.forward_row(i, b[i], |j| {
                        if (lo..hi).contains(&j) {
                            xb[j - lo]
                        } else {
                            x0[j]
                        }
                    });
                    xb[il] = v;
                }
            });
        } else {
            for i in 0..self.n() {
                x[i] = self.forward_row(i, b[i], |j| x[j]);
            }
        }
    }

    /// ac = A c and (b·c, ac·c) in one pass: the rows' products of [`Csr::mul`] and the sums
    /// of [`Csr::dot`] (on a blocked level per block of `reduce::BLOCK` rows in parallel,
    /// the block sums in order), so the same bits as the three passes.
    fn mul_dots(&self, b: &[f64], c: &[f64], ac: &mut [f64]) -> (f64, f64) {
        let [num, den] = crate::reduce::fill_and_sum(ac, self.is_blocked(), |i| {
            let mut s = self.diag[i] * c[i];
            for k in self.row(i) {
                s += self.val[k] * c[self.col[k] as usize];
            }
            (s, [b[i] * c[i], s * c[i]])
        });
        (num, den)
    }

    /// OpenFOAM's `GAMGSolver::scale` of a correction `c` of `A c = b`: s = (b·c)/(c·Ac)
    /// (its denominator kept off zero as OpenFOAM's `stabilise` with 1e-300), then
    /// c ← s c + (b − s A c)/D. `ac` is scratch of the level's size.
    fn scale(&self, b: &[f64], c: &mut [f64], ac: &mut [f64]) {
        let (num, den) = self.mul_dots(b, c, ac);
        let den = if den >= 0.0 {
            den + 1e-300
        } else {
            den - 1e-300
        };
        let s = num / den;
        crate::reduce::fill(c, self.is_blocked(), |i, ci| {
            s * ci + (b[i] - s * ac[i]) * self.inv_diag[i]
        });
    }
}

impl Level {
    /// x = P xc (OpenFOAM's `prolongField`: each row takes its aggregate's value), in
    /// parallel when `parallel`.
    fn prolong_into(&self, xc: &[f64], x: &mut [f64], parallel: bool) {
        crate::reduce::fill(x, parallel, |i, _| xc[self.from_fine[i] as usize]);
    }
}

/// The work vectors of [`Amg::v_cycle`] for one hierarchy, kept across the cycles of a solve:
/// per level (finest first) its source, its correction, A times the correction, and the
/// sweep's start values.
pub(crate) struct CycleWork {
    src: Vec<Vec<f64>>,
    corr: Vec<Vec<f64>>,
    ac: Vec<Vec<f64>>,
    x0: Vec<Vec<f64>>,
}

impl Amg {
    /// Work vectors for [`Self::v_cycle`] on this hierarchy.
    pub(crate) fn cycle_work(&self) -> CycleWork {
        let zeros = || self.sizes().into_iter().map(|n| vec![0.0; n]).collect();
        CycleWork {
            src: zeros(),
            corr: zeros(),
            ac: zeros(),
            x0: zeros(),
        }
    }

    /// True when `w` has the level sizes of this hierarchy (a [`Self::cycle_work`] of it or of
    /// a hierarchy like it).
    pub(crate) fn fits(&self, w: &CycleWork) -> bool {
        let sizes = self.sizes();
        [&w.src, &w.corr, &w.ac, &w.x0]
            .iter()
            .all(|v| v.len() == sizes.len() && v.iter().zip(&sizes).all(|(x, &n)| x.len() == n))
    }

    /// One GAMG V-cycle on `A x = b` (module doc): `r` is b − A x on entry; x is updated.
    /// `w` from [`Self::cycle_work`] of this hierarchy.
    pub(crate) fn v_cycle(&self, b: &[f64], x: &mut [f64], r: &[f64], w: &mut CycleWork) {
        let nl = self.coarse.len();
        let CycleWork { src, corr, ac, x0 } = w;
        if nl == 0 {
            self.direct.solve(r, &mut corr[0]);
            x.iter_mut().zip(&corr[0]).for_each(|(x, c)| *x += c);
            return;
        }
        // Sources: the finest residual restricted down, level by level (src[l] is level l's;
        // src[0] is not used, r is the finest source).
        for l in 1..=nl {
            let (above, below) = src.split_at_mut(l);
            let from = if l == 1 { r } else { &above[l - 1][..] };
            self.coarse[l - 1].restrict(from, &mut below[0], self.matrix(l - 1).is_blocked());
        }
        self.direct.solve(&src[nl], &mut corr[nl]);
        // Up through the coarse levels l = nl − 1 … 1: prolong, scale, post-smooth
        // (OpenFOAM's coarse level l − 1, hence min(2 + l − 1, 4) sweeps).
        for l in (1..nl).rev() {
            let a = self.matrix(l);
            let (upper, lower) = corr.split_at_mut(l + 1);
            self.coarse[l].prolong_into(&lower[0], &mut upper[l], a.is_blocked());
            let c = &mut upper[l];
            if l + 1 < nl {
                a.scale(&src[l], c, &mut ac[l]);
            }
            for _ in 0..(N_POST + l - 1).min(MAX_POST) {
                a.gs_forward(&src[l], c, &mut x0[l]);
            }
        }
        let fine = &self.fine;
        let (c0, rest) = corr.split_at_mut(1);
        self.coarse[0].prolong_into(&rest[0], &mut c0[0], fine.is_blocked());
        fine.scale(r, &mut c0[0], &mut ac[0]);
        let c0 = &c0[0];
        crate::reduce::fill(x, fine.is_blocked(), |i, x| x + c0[i]);
        for _ in 0..N_FINEST {
            fine.gs_forward(b, x, &mut x0[0]);
        }
    }
}

/// OpenFOAM's `nCellsInCoarsestLevel` default: agglomeration stops before a level would have
/// fewer rows.
const COARSEST_GAMG: usize = 10;

impl Amg {
    /// The hierarchy OpenFOAM's GAMG builds (`pairGAMGAgglomeration`, `mergeLevels 1`): one
    /// pairing pass per level on the pairing weights `w` (one per entry of `m`'s rows), rows
    /// taken forward on the first level and in reverse on the next, alternately; the coarse
    /// weights are the sums of the fine ones between two aggregates (`restrictFaceField`), the
    /// coarse matrices the Galerkin products. Stops when a pass would leave fewer than
    /// `COARSEST_GAMG` (10) rows or would not shrink the level.
    pub fn gamg(m: &RowMatrix<'_>, w: Vec<f64>) -> Amg {
        let fine = Csr::from_rows(m);
        let mut weights = Csr::new(
            m.rows.start.clone(),
            m.rows.col.clone(),
            w,
            vec![0.0; fine.n()],
        );
        let mut coarse: Vec<Level> = Vec::new();
        let mut forward = true;
        loop {
            let a = coarse.last().map_or(&fine, |l| &l.a);
            let n = a.n();
            let (agg, nc) = weights.pairwise(forward);
            forward = !forward;
            if nc < COARSEST_GAMG || nc >= n {
                break;
            }
            weights = weights.galerkin(&agg, nc);
            let ac = a.galerkin(&agg, nc);
            let level = Level::new(a, ac, agg);
            coarse.push(level);
        }
        let mut amg = Amg {
            geometric: true,
            ..Amg::finish(fine, coarse)
        };
        // The blocked levels sweep as OpenFOAM does, in sequence, on several threads where
        // their numbering allows (crate::sweep::pipeline; the hybrid blocks elsewhere).
        let mut levels: Vec<&mut Csr> = vec![&mut amg.fine];
        levels.extend(amg.coarse.iter_mut().map(|l| &mut l.a));
        for a in levels.into_iter().filter(|a| a.is_blocked()) {
            // (Not the row-level waits of a 2-D numbering: the hybrid blocks were faster
            // there, crate::sweep::pipeline.)
            a.pipeline = Schedule::for_rows(&a.start, &a.col)
                .filter(|s| !s.is_gated())
                .map(Arc::new);
        }
        amg
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::FvGeometry;
    use crate::ldu::Ldu;
    use crate::linsolve::{solve, Method, SolverControls};

    fn laplacian(n: [usize; 3]) -> (FvGeometry, Ldu) {
        crate::amg::tests::laplacian_box([1.0, 0.8, 0.6], n)
    }

    fn controls(tolerance: f64) -> SolverControls {
        SolverControls {
            tolerance,
            max_iter: 200,
            ..SolverControls::default()
        }
    }

    /// A smooth-and-rough exact solution and its right-hand side.
    fn problem(g: &FvGeometry, a: &Ldu) -> (Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = (0..g.n_cells)
            .map(|i| 1.0 + g.c[i][0] * g.c[i][1] + 0.1 * ((i * 3 % 17) as f64).cos())
            .collect();
        let mut b = vec![0.0; g.n_cells];
        a.mul(g, &x, &mut b);
        (x, b)
    }

    #[test]
    fn v_cycles_reduce_a_3d_poisson_residual_by_four_per_cycle_and_cg_reaches_the_solution() {
        let (g, a) = laplacian([24, 20, 16]);
        let (x_true, b) = problem(&g, &a);
        // The V-cycle alone, as OpenFOAM's GAMG iterates it, 10 cycles from zero.
        let m = crate::ldu::RowMatrix::new(&a, &g);
        let amg = super::Amg::gamg(&m, crate::linsolve::face_area_pair_weights(&g));
        let mut work = amg.cycle_work();
        let mut x = vec![0.0; g.n_cells];
        let mut r = b.clone();
        let sum_abs = |r: &[f64]| r.iter().map(|v| v.abs()).sum::<f64>();
        let r0 = sum_abs(&r);
        let cycles = 10;
        for _ in 0..cycles {
            amg.v_cycle(&b, &mut x, &r.clone(), &mut work);
            m.mul(&x, &mut r);
            r.iter_mut().zip(&b).for_each(|(r, b)| *r = b - *r);
        }
        // Per cycle: the mean reduction of Σ|b − Ax|. OpenFOAM's GAMG with these defaults took
        // pisoFoam's 48³ cavity's final pressure residual from 7.2e-2 to 3.2e-7 in 8 cycles
        // (0.21 per cycle; benches/fluid-speed). Here: 0.14; the same cycles without the
        // scaling (s = 1): 0.42.
        let per_cycle = (sum_abs(&r) / r0).powf(1.0 / cycles as f64);
        assert!(per_cycle < 0.25, "{per_cycle} per cycle");
        // GAMG's solve (CG with the cycle) to 1e-13 reaches the exact solution.
        let mut x = vec![0.0; g.n_cells];
        let s = solve(Method::Gamg, &a, &g, &b, &mut x, &controls(1e-13), "p").unwrap();
        let err = x
            .iter()
            .zip(&x_true)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(s.last < 1e-13 && err < 1e-9, "{s:?}, max error {err}");
    }

    #[test]
    fn the_hierarchy_kept_for_a_new_matrix_on_the_same_mesh_gives_a_fresh_ones_bits() {
        // 52 × 40 × 25 = 52 000 rows ≥ PAR_MIN: blocked sweeps on the large levels.
        let (g, a) = laplacian([52, 40, 25]);
        let mut a2 = a.clone();
        for (f, u) in a2.upper.iter_mut().enumerate() {
            let k = 1.0 + 0.5 * ((f % 7) as f64 / 7.0);
            let o = g.owner[f] as usize;
            let nb = g.neighbour[f] as usize;
            a2.diag[o] += (k - 1.0) * -*u;
            a2.diag[nb] += (k - 1.0) * -*u;
            *u *= k;
            a2.lower[f] = *u;
        }
        let (_, b) = problem(&g, &a2);
        let c = controls(1e-8);
        let solve_on = |first: Option<&Ldu>, threads: usize| {
            let (g, a2, b, c) = (&g, &a2, &b, &c);
            let first = first.cloned();
            std::thread::scope(|s| {
                s.spawn(move || {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    pool.install(|| {
                        if let Some(a) = first {
                            let mut x = vec![0.0; g.n_cells];
                            solve(Method::Gamg, &a, g, b, &mut x, c, "p").unwrap();
                        }
                        let mut x = vec![0.0; g.n_cells];
                        let s = solve(Method::Gamg, a2, g, b, &mut x, c, "p").unwrap();
                        (s.iterations, x)
                    })
                })
                .join()
                .unwrap()
            })
        };
        let fresh = solve_on(None, 1);
        assert!(fresh.0 > 1);
        assert_eq!(fresh, solve_on(Some(&a), 1), "kept hierarchy");
        assert_eq!(fresh, solve_on(None, 2), "two threads");
        assert_eq!(
            fresh,
            solve_on(Some(&a), 3),
            "kept hierarchy, three threads"
        );
    }
}
