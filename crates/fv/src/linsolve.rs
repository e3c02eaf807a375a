//! Linear solvers for the finite-volume equations: preconditioned conjugate gradients for the
//! symmetric pressure equation (diagonal/Jacobi or DIC preconditioner) and Jacobi-preconditioned
//! BiCGStab for the momentum components. Vector operations and matrix products are parallel
//! (rayon); the DIC sweeps are sequential by nature.
//!
//! Convergence is judged as OpenFOAM judges it (`lduMatrix::solver`): the residual
//! r = Σ|b − Ax| / n_f with the normalisation n_f = Σ(|Ax − A x̄| + |b − A x̄|) + 1e-20, x̄ the
//! mean of x; the solve stops when r < tolerance or r < relTol · r₀, after at least `min_iter`
//! iterations and at most `max_iter`.
//! References: Saad, *Iterative Methods for Sparse Linear Systems*, 2nd ed., Alg. 9.1 (PCG) and
//! 7.7 (BiCGStab); Meijerink & van der Vorst 1977 (incomplete Cholesky, DIC variant).

use crate::error::{FvError, Result};
use crate::geometry::FvGeometry;
use crate::ldu::Ldu;
use rayon::prelude::*;

/// Vectors shorter than this are processed on the calling thread: below it, handing work to
/// rayon's pool (a wake-up and a context switch per operation) costs more than it saves.
pub const PAR_MIN: usize = 50_000;

/// Preconditioner of the conjugate-gradient solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preconditioner {
    /// Jacobi (OpenFOAM `diagonal`), fully parallel.
    Diagonal,
    /// Diagonal incomplete Cholesky (OpenFOAM `DIC`): the no-fill incomplete factorisation that
    /// keeps only a modified diagonal.
    Dic,
}

/// Settings of one linear solve (OpenFOAM `fvSolution` `solvers` entry).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverControls {
    /// Absolute tolerance on the normalised residual.
    pub tolerance: f64,
    /// Relative tolerance (0 = only the absolute one).
    pub rel_tol: f64,
    /// At most this many iterations.
    pub max_iter: usize,
    /// At least this many iterations.
    pub min_iter: usize,
}

impl Default for SolverControls {
    fn default() -> Self {
        SolverControls {
            tolerance: 1e-6,
            rel_tol: 0.0,
            max_iter: 1000,
            min_iter: 0,
        }
    }
}

/// What a solve did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveStats {
    /// Normalised residual before the solve.
    pub initial: f64,
    /// Normalised residual after it.
    pub last: f64,
    /// Iterations done.
    pub iterations: usize,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    if a.len() < PAR_MIN {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    } else {
        a.par_iter().zip(b).map(|(x, y)| x * y).sum()
    }
}

fn sum_abs(a: &[f64]) -> f64 {
    if a.len() < PAR_MIN {
        a.iter().map(|x| x.abs()).sum()
    } else {
        a.par_iter().map(|x| x.abs()).sum()
    }
}

/// OpenFOAM's normalisation factor for the residual of `A x = b` (see the module doc).
fn norm_factor(a: &Ldu, g: &FvGeometry, x: &[f64], b: &[f64], ax: &[f64]) -> f64 {
    let n = x.len().max(1) as f64;
    let xbar = x.iter().sum::<f64>() / n;
    let xr = vec![xbar; x.len()];
    let mut axr = vec![0.0; x.len()];
    a.mul(g, &xr, &mut axr);
    ax.iter()
        .zip(b)
        .zip(&axr)
        .map(|((ax, b), axr)| (ax - axr).abs() + (b - axr).abs())
        .sum::<f64>()
        + 1e-20
}

fn converged(c: &SolverControls, r: f64, r0: f64, it: usize) -> bool {
    it >= c.min_iter && (r < c.tolerance || (c.rel_tol > 0.0 && r < c.rel_tol * r0))
}

fn check_finite(what: &str, r: f64) -> Result<()> {
    if r.is_finite() {
        Ok(())
    } else {
        Err(FvError::Diverged(format!(
            "{what}: the linear solver produced a non-finite residual"
        )))
    }
}

/// The DIC factor's reciprocal diagonal: r_c = 1 / (a_cc − Σ_{faces with c as neighbour}
/// a_cf² r_owner), faces in increasing order (lower-triangular sweep).
fn dic_factor(a: &Ldu, g: &FvGeometry) -> Vec<f64> {
    let mut rd = a.diag.clone();
    for f in 0..g.n_internal {
        let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
        rd[n] -= a.upper[f] * a.upper[f] / rd[p];
    }
    for d in &mut rd {
        *d = 1.0 / *d;
    }
    rd
}

/// w = M⁻¹ r for the DIC preconditioner with reciprocal factor diagonal `rd`.
fn dic_apply(a: &Ldu, g: &FvGeometry, rd: &[f64], r: &[f64], w: &mut [f64]) {
    for c in 0..w.len() {
        w[c] = rd[c] * r[c];
    }
    for f in 0..g.n_internal {
        let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
        w[n] -= rd[n] * a.upper[f] * w[p];
    }
    for f in (0..g.n_internal).rev() {
        let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
        w[p] -= rd[p] * a.upper[f] * w[n];
    }
}

/// The initial residual `b − A x`, OpenFOAM's normalisation factor and the normalised initial
/// residual (an error if it is not finite).
fn start(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &[f64],
    what: &str,
) -> Result<(Vec<f64>, f64, SolveStats)> {
    let mut ax = vec![0.0; x.len()];
    a.mul(g, x, &mut ax);
    let r: Vec<f64> = b.iter().zip(&ax).map(|(b, ax)| b - ax).collect();
    let nf = norm_factor(a, g, x, b, &ax);
    let r0 = sum_abs(&r) / nf;
    check_finite(what, r0)?;
    let stats = SolveStats {
        initial: r0,
        last: r0,
        iterations: 0,
    };
    Ok((r, nf, stats))
}

/// Solves the symmetric positive (semi-)definite system `A x = b` by preconditioned conjugate
/// gradients, starting from `x`. `what` names the field in errors.
pub fn pcg(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    pre: Preconditioner,
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    let n = x.len();
    let (mut r, nf, mut stats) = start(a, g, b, x, what)?;
    let r0 = stats.initial;
    if converged(c, r0, r0, 0) {
        return Ok(stats);
    }
    let mut ax = vec![0.0; n];
    let rd = match pre {
        Preconditioner::Dic => dic_factor(a, g),
        Preconditioner::Diagonal => a.diag.iter().map(|d| 1.0 / d).collect(),
    };
    let mut w = vec![0.0; n];
    let mut p = vec![0.0; n];
    let mut rho_old = 1.0;
    while stats.iterations < c.max_iter {
        match pre {
            Preconditioner::Dic => dic_apply(a, g, &rd, &r, &mut w),
            Preconditioner::Diagonal => w
                .iter_mut()
                .zip(&r)
                .zip(&rd)
                .for_each(|((w, r), d)| *w = r * d),
        }
        let rho = dot(&w, &r);
        let beta = if stats.iterations == 0 {
            0.0
        } else {
            rho / rho_old
        };
        p.iter_mut().zip(&w).for_each(|(p, w)| *p = w + beta * *p);
        a.mul(g, &p, &mut ax);
        let pap = dot(&p, &ax);
        if pap == 0.0 {
            break;
        }
        let alpha = rho / pap;
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&ax).for_each(|(r, ap)| *r -= alpha * ap);
        rho_old = rho;
        stats.iterations += 1;
        stats.last = sum_abs(&r) / nf;
        check_finite(what, stats.last)?;
        if converged(c, stats.last, r0, stats.iterations) {
            break;
        }
    }
    Ok(stats)
}

/// Solves `A x = b` (any non-singular A) by Jacobi-preconditioned BiCGStab, starting from `x`.
pub fn bicgstab(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    let n = x.len();
    let (mut r, nf, mut stats) = start(a, g, b, x, what)?;
    let r0 = stats.initial;
    if converged(c, r0, r0, 0) {
        return Ok(stats);
    }
    let mut t = vec![0.0; n];
    let dinv: Vec<f64> = a.diag.iter().map(|d| 1.0 / d).collect();
    let rhat = r.clone();
    let (mut rho, mut alpha, mut omega) = (1.0, 1.0, 1.0);
    let mut v = vec![0.0; n];
    let mut p = vec![0.0; n];
    let mut y = vec![0.0; n];
    let mut s = vec![0.0; n];
    let mut z = vec![0.0; n];
    while stats.iterations < c.max_iter {
        let rho_new = dot(&rhat, &r);
        if rho_new == 0.0 {
            break;
        }
        let beta = (rho_new / rho) * (alpha / omega);
        rho = rho_new;
        p.iter_mut()
            .zip(&r)
            .zip(&v)
            .for_each(|((p, r), v)| *p = r + beta * (*p - omega * v));
        y.iter_mut()
            .zip(&p)
            .zip(&dinv)
            .for_each(|((y, p), d)| *y = p * d);
        a.mul(g, &y, &mut v);
        let rv = dot(&rhat, &v);
        if rv == 0.0 || !rv.is_finite() {
            break;
        }
        alpha = rho / rv;
        s.iter_mut()
            .zip(&r)
            .zip(&v)
            .for_each(|((s, r), v)| *s = r - alpha * v);
        z.iter_mut()
            .zip(&s)
            .zip(&dinv)
            .for_each(|((z, s), d)| *z = s * d);
        a.mul(g, &z, &mut t);
        let tt = dot(&t, &t);
        omega = if tt > 0.0 { dot(&t, &s) / tt } else { 0.0 };
        x.iter_mut()
            .zip(&y)
            .zip(&z)
            .for_each(|((x, y), z)| *x += alpha * y + omega * z);
        r.iter_mut()
            .zip(&s)
            .zip(&t)
            .for_each(|((r, s), t)| *r = s - omega * t);
        stats.iterations += 1;
        stats.last = sum_abs(&r) / nf;
        check_finite(what, stats.last)?;
        if converged(c, stats.last, r0, stats.iterations) || omega == 0.0 {
            break;
        }
    }
    Ok(stats)
}
