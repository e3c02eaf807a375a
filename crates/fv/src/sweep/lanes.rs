//! The smoothSolver on the components of a vector equation at once
//! ([`smooth_components`]).
//!
//! The momentum equation's components are matrices with the same off-diagonal coefficients
//! and their own diagonals and sources; OpenFOAM's `fvMatrix<vector>::solveSegregated` solves
//! them one after another. Here the Gauss–Seidel sweeps and the residual checks relax every
//! component of a row in one pass over the row ("lanes": the components' values side by side
//! per row). The coefficients and columns are then read once for all components, and the
//! components' recurrences — in a sequential sweep each row waits for the row before it —
//! overlap in the processor instead of following one another.
//!
//! Each component keeps its own arithmetic (the operations of [`crate::linsolve::smooth`] on
//! it alone, in the same order), its own residual checks and its own stop: a component that
//! has converged is carried along unchanged while the others go on. The results, iteration
//! counts included, are therefore those of the solves one after another, bit for bit (tested
//! below), on the sequential, pipelined ([`super::pipeline`]) and hybrid ([`super`]) sweeps
//! alike. The incomplete-factor smoothers keep [`crate::linsolve::smooth`], one component at a
//! time.

use super::Pipeline;
use crate::error::Result;
use crate::geometry::FvGeometry;
use crate::ldu::{Ldu, RowMatrix, PAR_MIN};
use crate::linsolve::{self, Smoother, SmootherKind, SolveStats, SolverControls};
use rayon::prelude::*;
use std::sync::atomic::Ordering;

/// The components of a vector equation for [`smooth_components`]: component i is
/// `A_i x_i = b[i]`, where A_i has the off-diagonal coefficients of the matrix given with them
/// and the diagonal `diags[i]`; `what[i]` names it in errors.
pub struct Components<'a> {
    pub diags: &'a [Vec<f64>],
    pub b: &'a [Vec<f64>],
    pub what: &'a [&'a str],
}

/// The smoothSolver ([`crate::linsolve::smooth`]) on the components `q` of a vector equation
/// whose off-diagonal coefficients are `a`'s (its diagonal is not used), from and into `x`
/// (one vector per component). Returns each component's statistics, in order. The same bits
/// as solving them one after another.
pub fn smooth_components(
    a: &Ldu,
    g: &FvGeometry,
    q: &Components<'_>,
    x: &mut [Vec<f64>],
    smoother: Smoother,
    c: &SolverControls,
) -> Result<Vec<SolveStats>> {
    let Components { diags, b, what } = *q;
    let n_comp = x.len();
    assert!(diags.len() == n_comp && b.len() == n_comp && what.len() == n_comp);
    let lanes = matches!(
        smoother.kind,
        SmootherKind::GaussSeidel | SmootherKind::SymGaussSeidel
    );
    if !lanes {
        // One component at a time (side by side on large meshes: each solve's arithmetic
        // unchanged).
        let one = |(i, x): (usize, &mut Vec<f64>)| {
            let mut m = a.clone();
            m.diag.clone_from(&diags[i]);
            linsolve::smooth(&m, g, &b[i], x, smoother, c, what[i])
        };
        let stats: Vec<Result<SolveStats>> = if g.n_cells >= PAR_MIN {
            x.par_iter_mut().enumerate().map(one).collect()
        } else {
            x.iter_mut().enumerate().map(one).collect()
        };
        return stats.into_iter().collect();
    }
    let m = RowMatrix::new(a, g);
    match n_comp {
        0 => Ok(Vec::new()),
        1 => smooth_lanes::<1>(&m, q, x, smoother, c),
        2 => smooth_lanes::<2>(&m, q, x, smoother, c),
        3 => smooth_lanes::<3>(&m, q, x, smoother, c),
        _ => unreachable!("at most three components"),
    }
}

/// `L` per-component arrays of `n` values side by side: `out[L c + l] = v[l][c]`.
fn interleave<const L: usize>(v: &[Vec<f64>], n: usize) -> Vec<f64> {
    crate::gather::over(0..L * n)
        .map(|i| v[i % L][i / L])
        .collect()
}

/// [`smooth_components`] with `L` Gauss–Seidel lanes.
fn smooth_lanes<const L: usize>(
    m: &RowMatrix<'_>,
    q: &Components<'_>,
    x: &mut [Vec<f64>],
    smoother: Smoother,
    c: &SolverControls,
) -> Result<Vec<SolveStats>> {
    let Components { diags, b, what } = *q;
    let n = m.diag.len();
    let rows = m.rows;
    // Each component's start: residual, normalisation factor, and whether it is done already.
    let mut stats = Vec::with_capacity(L);
    let mut norm = [0.0; L];
    let mut active = [false; L];
    for l in 0..L {
        let (_, nf, s) = linsolve::start(&m.with_diag(&diags[l]), &b[l], &x[l], what[l])?;
        active[l] = !linsolve::converged(c, s.initial, s.initial, 0);
        norm[l] = nf;
        stats.push(s);
    }
    if !active.contains(&true) {
        return Ok(stats);
    }
    let sweeps = smoother.sweeps.max(1);
    let d = interleave::<L>(diags, n);
    let bl = interleave::<L>(b, n);
    let mut xl = interleave::<L>(x, n);
    let mut bp = bl.clone();
    let has_iface = (0..n).any(|i| rows.end[i] < rows.start[i + 1]);
    let mut sweeper = LaneSweeper::<L>::new(m, smoother.hybrid);
    loop {
        for _ in 0..sweeps {
            if has_iface {
                interfaces::<L>(m, &bl, &xl, &mut bp);
            }
            sweeper.sweep(&bp, &d, &mut xl, active, false);
            if smoother.kind == SmootherKind::SymGaussSeidel {
                sweeper.sweep(&bp, &d, &mut xl, active, true);
            }
        }
        let sums = crate::reduce::sum_abs_lanes::<L>(n, |i| residual_row::<L>(m, &d, &bl, &xl, i));
        for l in 0..L {
            if !active[l] {
                continue;
            }
            let s = &mut stats[l];
            s.last = sums[l] / norm[l];
            linsolve::check_finite(what[l], s.last)?;
            s.iterations += sweeps;
            if s.iterations >= c.max_iter || linsolve::converged(c, s.last, s.initial, s.iterations)
            {
                active[l] = false;
            }
        }
        if !active.contains(&true) {
            break;
        }
    }
    for (l, x) in x.iter_mut().enumerate() {
        crate::gather::each_mut(x, |i, v| *v = xl[L * i + l]);
    }
    Ok(stats)
}

/// b′ = b − (interface part of A) x for every lane (the smoothSolver's once-per-sweep update
/// of the coupled interfaces, [`crate::linsolve::smooth`]).
fn interfaces<const L: usize>(m: &RowMatrix<'_>, b: &[f64], x: &[f64], bp: &mut [f64]) {
    let rows = m.rows;
    for i in 0..m.diag.len() {
        let mut s: [f64; L] = std::array::from_fn(|l| b[L * i + l]);
        for k in rows.end[i] as usize..rows.start[i + 1] as usize {
            let j = rows.col[k] as usize;
            for l in 0..L {
                s[l] -= m.coef[k] * x[L * j + l];
            }
        }
        bp[L * i..L * i + L].copy_from_slice(&s);
    }
}

/// Row i of b − A x for every lane: d x then the row's entries in order, as
/// [`RowMatrix::mul`] and [`crate::linsolve::smooth`] form it.
#[inline(always)]
fn residual_row<const L: usize>(
    m: &RowMatrix<'_>,
    d: &[f64],
    b: &[f64],
    x: &[f64],
    i: usize,
) -> [f64; L] {
    let rows = m.rows;
    let mut s: [f64; L] = std::array::from_fn(|l| d[L * i + l] * x[L * i + l]);
    for k in rows.row(i) {
        let j = rows.col[k] as usize;
        for (l, s) in s.iter_mut().enumerate() {
            *s += m.coef[k] * x[L * j + l];
        }
    }
    std::array::from_fn(|l| b[L * i + l] - s[l])
}

/// Row `i`'s new values: (b′ − Σ_k a_ik x_k) / d for the active lanes, over the row's
/// triangular entries (the arithmetic of `super::Sweeper`), the old value for the others;
/// `at(j)` reads lane l of row j.
#[inline(always)]
fn relax<const L: usize>(
    m: &RowMatrix<'_>,
    bp: &[f64],
    d: &[f64],
    active: [bool; L],
    i: usize,
    at: impl Fn(usize, usize) -> f64,
) -> [f64; L] {
    let rows = m.rows;
    let mut s: [f64; L] = std::array::from_fn(|l| bp[L * i + l]);
    for k in rows.start[i] as usize..rows.end[i] as usize {
        let j = rows.col[k] as usize;
        for (l, s) in s.iter_mut().enumerate() {
            *s -= m.coef[k] * at(j, l);
        }
    }
    std::array::from_fn(|l| {
        if active[l] {
            s[l] / d[L * i + l]
        } else {
            at(i, l)
        }
    })
}

/// The sweeps of `super::Sweeper` on lanes: sequential, pipelined or hybrid as it chooses.
struct LaneSweeper<'m, 'a, const L: usize> {
    m: &'m RowMatrix<'a>,
    /// Hybrid block boundaries (`[0, n]`: not hybrid).
    blocks: Vec<usize>,
    /// The lanes at the sweep's start (hybrid sweeps only).
    x0: Vec<f64>,
    pipeline: Option<Pipeline<'m>>,
}

impl<'m, 'a, const L: usize> LaneSweeper<'m, 'a, L> {
    fn new(m: &'m RowMatrix<'a>, hybrid: bool) -> Self {
        let n = m.diag.len();
        let (blocks, x0, pipeline) = if hybrid && n >= PAR_MIN {
            (crate::amg::block_bounds(n), vec![0.0; L * n], None)
        } else {
            let p = if rayon::current_num_threads() > 1 {
                m.rows.pipeline().map(Pipeline::new)
            } else {
                None
            };
            (vec![0, n], Vec::new(), p)
        };
        LaneSweeper {
            m,
            blocks,
            x0,
            pipeline,
        }
    }

    /// One sweep (forward, or backward: rows in reverse order) of the active lanes.
    fn sweep(&mut self, bp: &[f64], d: &[f64], x: &mut [f64], active: [bool; L], backward: bool) {
        let m = self.m;
        if let Some(p) = &mut self.pipeline {
            p.run_lanes::<L, _>(x, backward, |i, xa| {
                relax(m, bp, d, active, i, |j, l| {
                    f64::from_bits(xa[L * j + l].load(Ordering::Relaxed))
                })
            });
            return;
        }
        if self.blocks.len() <= 2 {
            let mut one = |i: usize| {
                let v = relax(m, bp, d, active, i, |j, l| x[L * j + l]);
                x[L * i..L * i + L].copy_from_slice(&v);
            };
            if backward {
                (0..m.diag.len()).rev().for_each(&mut one);
            } else {
                (0..m.diag.len()).for_each(&mut one);
            }
            return;
        }
        self.x0.copy_from_slice(x);
        let x0 = &self.x0[..];
        let bounds: Vec<usize> = self.blocks.iter().map(|b| L * b).collect();
        let pieces = crate::amg::split_at_bounds(x, &bounds);
        crate::team::each(pieces, |(lo, xb)| {
            let (lo, hi) = (lo / L, (lo + xb.len()) / L);
            let mut one = |i: usize| {
                let v = relax(m, bp, d, active, i, |j, l| {
                    if (lo..hi).contains(&j) {
                        xb[L * (j - lo) + l]
                    } else {
                        x0[L * j + l]
                    }
                });
                xb[L * (i - lo)..L * (i - lo) + L].copy_from_slice(&v);
            };
            if backward {
                (lo..hi).rev().for_each(&mut one);
            } else {
                (lo..hi).for_each(&mut one);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linsolve::smooth;

    /// A convection–diffusion matrix (upwind along `u`) on `n` cells of a box, with three
    /// diagonals and three sources.
    /// With `iface`, the last 40 internal faces are interface entries (as a cyclic pair's
    /// are: updated once per sweep).
    fn problem(n: [usize; 3], iface: bool) -> (FvGeometry, Ldu, Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let mesh = mesh::build::uniform_box([0.0; 3], [1.0, 0.8, 0.6], n);
        let mut g = FvGeometry::new(&mesh).unwrap();
        if iface {
            let ni = g.n_internal;
            let (o, nb) = (&g.owner[..ni], &g.neighbour[..ni]);
            g.rows = crate::ldu::RowAddressing::new(g.n_cells, o, nb, ni - 40);
        }
        let mut a = Ldu::zeros(&g);
        let u = [0.3, -0.2, 0.1];
        for f in 0..g.n_internal {
            let dc = g.mag_sf[f] * g.delta_coeff[f];
            let flux: f64 = (0..3).map(|i| u[i] * g.sf[f][i]).sum();
            a.upper[f] = -dc - (-flux).max(0.0);
            a.lower[f] = -dc - flux.max(0.0);
        }
        let mut base = vec![0.0; g.n_cells];
        for f in 0..g.n_internal {
            base[g.owner[f] as usize] -= a.upper[f];
            base[g.neighbour[f] as usize] -= a.lower[f];
        }
        // A time term of three sizes relative to the off-diagonal sum: the components
        // converge at different rates.
        let diags = (0..3)
            .map(|k| base.iter().map(|d| d * [1.05, 1.5, 4.0][k]).collect())
            .collect();
        let b = (0..3)
            .map(|k| {
                (0..g.n_cells)
                    .map(|c| ((c * (k + 3) % 17) as f64).sin() * g.v[c])
                    .collect()
            })
            .collect();
        (g, a, diags, b)
    }

    /// The components solved one after another with `linsolve::smooth`.
    fn one_by_one(
        g: &FvGeometry,
        a: &Ldu,
        diags: &[Vec<f64>],
        b: &[Vec<f64>],
        x: &mut [Vec<f64>],
        s: Smoother,
        c: &SolverControls,
    ) -> Vec<SolveStats> {
        (0..x.len())
            .map(|i| {
                let mut m = a.clone();
                m.diag.clone_from(&diags[i]);
                smooth(&m, g, &b[i], &mut x[i], s, c, "x").unwrap()
            })
            .collect()
    }

    fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    }

    #[test]
    fn lanes_give_the_bits_and_counts_of_the_components_solved_one_after_another() {
        let c = SolverControls {
            tolerance: 1e-8,
            max_iter: 60,
            ..SolverControls::default()
        };
        // (cells, interface entries, hybrid, kinds, components): sequential (small),
        // pipelined (numbered as blockMesh: half a 64 × 40 plane is a chunk the pipeline takes)
        // and hybrid (≥ PAR_MIN rows).
        use SmootherKind::{GaussSeidel as Gs, SymGaussSeidel as Sym};
        type Case = (
            [usize; 3],
            bool,
            bool,
            &'static [SmootherKind],
            &'static [usize],
        );
        let cases: [Case; 4] = [
            ([12, 10, 8], false, false, &[Gs, Sym], &[2, 3]),
            ([12, 10, 8], true, false, &[Gs, Sym], &[3]),
            ([64, 40, 20], false, false, &[Gs], &[3]),
            ([250, 200, 1], false, true, &[Gs], &[3]),
        ];
        for (n, iface, hybrid, kinds, comps) in cases {
            let (g, a, diags, b) = problem(n, iface);
            let pipelined = g.rows.pipeline().is_some_and(|p| !p.is_gated());
            assert_eq!(pipelined, n[0] == 64, "{n:?}");
            for &kind in kinds {
                for &comps in comps {
                    let s = Smoother {
                        kind,
                        sweeps: 2,
                        hybrid,
                    };
                    let (d, b) = (&diags[..comps], &b[..comps]);
                    let x0: Vec<Vec<f64>> = (0..comps)
                        .map(|k| {
                            (0..g.n_cells)
                                .map(|i| 0.01 * ((i + k) % 5) as f64)
                                .collect()
                        })
                        .collect();
                    let mut want = x0.clone();
                    let want_stats = on_threads(1, || one_by_one(&g, &a, d, b, &mut want, s, &c));
                    // The components stop at different counts (their diagonals differ; some
                    // at max_iter).
                    let its: Vec<usize> = want_stats.iter().map(|s| s.iterations).collect();
                    assert!(its.windows(2).any(|w| w[0] != w[1]), "{n:?} {its:?}");
                    for threads in [1, 2] {
                        let mut got = x0.clone();
                        let what = ["x", "y", "z"];
                        let stats = on_threads(threads, || {
                            let q = Components {
                                diags: d,
                                b,
                                what: &what[..comps],
                            };
                            smooth_components(&a, &g, &q, &mut got, s, &c).unwrap()
                        });
                        assert_eq!(stats, want_stats, "{n:?} {kind:?} {comps} {threads}");
                        assert!(
                            got == want,
                            "{n:?} {kind:?} {comps} lanes, {threads} threads"
                        );
                    }
                }
            }
        }
    }
}
