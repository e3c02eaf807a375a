//! Linear solvers for the finite-volume equations, as `fvSolution` names them: preconditioned
//! conjugate gradients (`PCG`) for the symmetric pressure equation, biconjugate gradients
//! (`PBiCG`), BiCGStab (`PBiCGStab`) and
//! Gauss–Seidel smoothing (`smoothSolver` with `GaussSeidel`/`symGaussSeidel`) for the momentum
//! components, with the Jacobi (`diagonal`) or diagonal-incomplete (`DIC`/`DILU`)
//! preconditioner, and `GAMG`: on a symmetric matrix flexible CG preconditioned by OpenFOAM's
//! own V-cycle on the hierarchy its `faceAreaPair` agglomeration builds ([`gamg`],
//! `crate::amg::Amg::v_cycle`), on a non-symmetric one BiCGStab preconditioned by the
//! K-cycle of [`crate::amg`]. All work on the row form of the matrix ([`RowMatrix`]). On large meshes the
//! matrix products and vector operations run in parallel (rayon) with reductions whose bits do
//! not depend on the thread count; the triangular sweeps (DIC/DILU, Gauss–Seidel) are
//! sequential by nature, but for the Gauss–Seidel sweeps of [`Smoother::hybrid`]
//! (`crate::sweep`).
//!
//! Convergence is judged as OpenFOAM judges it (`lduMatrix::solver`): the residual
//! r = Σ|b − Ax| / n_f with the normalisation n_f = Σ(|Ax − A x̄| + |b − A x̄|) + 1e-20, x̄ the
//! mean of x; the solve stops when r < tolerance or r < relTol · r₀, after at least `min_iter`
//! iterations and at most `max_iter`.
//! References: Saad, *Iterative Methods for Sparse Linear Systems*, 2nd ed., Alg. 9.1 (PCG), 9.5
//! (BiCGStab) and §4.1 (Gauss–Seidel); Meijerink & van der Vorst 1977 (incomplete Cholesky, DIC variant).

// Row loops index several arrays by the same row or entry, as the equations do.
#![allow(clippy::needless_range_loop)]

use crate::error::{FvError, Result};
use crate::geometry::FvGeometry;
use crate::ldu::{Ldu, RowAddressing, RowMatrix, PAR_MIN};
use std::sync::Arc;

pub use crate::reduce::dot;
use crate::reduce::{dots_and_keep, par_map2, sum_abs, sum_abs_by, update_and_residual};
pub use crate::sweep::lanes::{smooth_components, Components};

/// Preconditioner of the Krylov solvers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preconditioner {
    /// None (OpenFOAM `none`): the identity.
    None,
    /// Jacobi (OpenFOAM `diagonal`), fully parallel.
    Diagonal,
    /// Diagonal incomplete factorisation: incomplete Cholesky for a symmetric matrix (OpenFOAM
    /// `DIC`), incomplete LU otherwise (`DILU`) — the same no-fill factorisation that keeps
    /// only a modified diagonal.
    Dic,
    /// One K-cycle of the aggregation multigrid of [`crate::amg`] (OpenFOAM's `GAMG` as a
    /// preconditioner; the non-symmetric `GAMG` solver's).
    Amg,
}

/// The linear-solver algorithm of one `fvSolution` `solvers` entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// `PCG` with its preconditioner (symmetric matrices: the pressure equation).
    Pcg(Preconditioner),
    /// `PBiCGStab` with its preconditioner.
    BiCgStab(Preconditioner),
    /// `PBiCG` (biconjugate gradients) with its preconditioner.
    BiCg(Preconditioner),
    /// `smoothSolver` with its smoother.
    Smooth(Smoother),
    /// `GAMG`: on a symmetric matrix flexible CG preconditioned by OpenFOAM's GAMG V-cycle
    /// ([`gamg`]: the `faceAreaPair` hierarchy with its default controls), on others BiCGStab
    /// preconditioned by the K-cycle of [`crate::amg`], to the entry's tolerances. An
    /// iteration is one V-cycle, as in OpenFOAM's count: 189 against pisoFoam's 189 over 30
    /// steps of the 48³ RAS cavity, fewer where CG's acceleration helps (benches/fluid-speed).
    /// The answers agree with OpenFOAM's to the solver tolerance, not bit for bit.
    Gamg,
}

/// Solves `A x = b` from the initial guess `x` with `method` (see [`pcg`], [`bicg`],
/// [`bicgstab`], [`smooth`]).
pub fn solve(
    method: Method,
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    match method {
        Method::Pcg(pre) => pcg(a, g, b, x, pre, c, what),
        Method::BiCgStab(pre) => bicgstab(a, g, b, x, pre, c, what),
        Method::BiCg(pre) => bicg(a, g, b, x, pre, c, what),
        Method::Smooth(s) => smooth(a, g, b, x, s, c, what),
        Method::Gamg if a.is_symmetric() => gamg(a, g, b, x, c, what),
        Method::Gamg => bicgstab(a, g, b, x, Preconditioner::Amg, c, what),
    }
}

/// The smoother of [`smooth`] (OpenFOAM `smoothSolver`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Smoother {
    /// What one sweep does.
    pub kind: SmootherKind,
    /// Sweeps between residual checks (`nSweeps`, default 1).
    pub sweeps: usize,
    /// Gauss–Seidel sweeps in the hybrid block order of `crate::sweep` on ≥ [`PAR_MIN`]
    /// rows (in parallel; the same bits on any number of threads); false: row by row,
    /// OpenFOAM's sweeps bit for bit. fvSolution does not set it (false); the momentum
    /// predictor does.
    pub hybrid: bool,
}

/// One sweep of a [`Smoother`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmootherKind {
    /// `GaussSeidel` (and `nonBlockingGaussSeidel`, the same in serial): a forward sweep.
    GaussSeidel,
    /// `symGaussSeidel`: a forward then a backward sweep.
    SymGaussSeidel,
    /// `DIC`, `DILU`, `FDIC`: x ← x + M⁻¹(b − A x) with the diagonal incomplete factorisation
    /// M of the `DIC`/`DILU` preconditioner (OpenFOAM's `DICSmoother`, `DILUSmoother`; `FDIC`
    /// is the same arithmetic with stored coefficients).
    Factor,
    /// `DICGaussSeidel`, `DILUGaussSeidel`: a [`SmootherKind::Factor`] sweep then a
    /// [`SmootherKind::GaussSeidel`] sweep.
    FactorGaussSeidel,
}

impl SmootherKind {
    /// The smoother fvSolution names `name`, if supported.
    pub fn from_name(name: &str) -> Option<SmootherKind> {
        Some(match name {
            "GaussSeidel" | "nonBlockingGaussSeidel" => SmootherKind::GaussSeidel,
            "symGaussSeidel" => SmootherKind::SymGaussSeidel,
            "DIC" | "DILU" | "FDIC" => SmootherKind::Factor,
            "DICGaussSeidel" | "DILUGaussSeidel" => SmootherKind::FactorGaussSeidel,
            _ => return None,
        })
    }

    /// The names [`SmootherKind::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &[
        "GaussSeidel",
        "symGaussSeidel",
        "nonBlockingGaussSeidel",
        "DIC",
        "DILU",
        "FDIC",
        "DICGaussSeidel",
        "DILUGaussSeidel",
    ];
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

/// OpenFOAM's normalisation factor for the residual of `A x = b` (see the module doc), with
/// the residual r = b − A x: per row, computed in one pass over the row's entries, the
/// residual and the factor's term |A x − A x̄| + |b − A x̄| (x̄ the mean of x); the terms
/// summed in row order (the same bits on any number of threads).
fn residual_and_norm_factor(a: &RowMatrix<'_>, x: &[f64], b: &[f64]) -> (Vec<f64>, f64) {
    let n = x.len().max(1) as f64;
    let xbar = x.iter().sum::<f64>() / n;
    let row = |c: usize| {
        // Row c of A x and of A times the uniform field x̄ in one pass over the row's entries,
        // each sum's terms in row order (RowMatrix::row_times's for A x).
        let (mut ax, mut axr) = (a.diag[c] * x[c], a.diag[c] * xbar);
        for k in a.rows.row(c) {
            let v = a.coef[k];
            ax += v * x[a.rows.col[k] as usize];
            axr += v * xbar;
        }
        (b[c] - ax, (ax - axr).abs() + (b[c] - axr).abs())
    };
    let (r, terms): (Vec<f64>, Vec<f64>) = if x.len() < PAR_MIN {
        (0..x.len()).map(row).unzip()
    } else {
        crate::gather::over(0..x.len()).map(row).unzip()
    };
    let mut s = 0.0;
    for t in terms {
        s += t;
    }
    (r, s + 1e-20)
}

/// The residual `r` meets the tolerances (initial residual `r0`).
fn meets(c: &SolverControls, r: f64, r0: f64) -> bool {
    r < c.tolerance || (c.rel_tol > 0.0 && r < c.rel_tol * r0)
}

pub(crate) fn converged(c: &SolverControls, r: f64, r0: f64, it: usize) -> bool {
    it >= c.min_iter && meets(c, r, r0)
}

pub(crate) fn check_finite(what: &str, r: f64) -> Result<()> {
    if r.is_finite() {
        Ok(())
    } else {
        Err(FvError::Diverged(format!(
            "{what}: the linear solver produced a non-finite residual"
        )))
    }
}

/// The diagonal incomplete factorisation (DIC for a symmetric matrix, DILU in general; the
/// no-fill ILU(0) of Meijerink & van der Vorst 1977 that keeps only a modified diagonal):
/// `M = (D* + L) D*⁻¹ (D* + U)` with the reciprocal diagonal
/// `r_c = 1 / (a_cc − Σ_{j<c} a_cj a_jc r_j)`. Interface entries (cyclic pairs) are left
/// out, as OpenFOAM's `DICPreconditioner`/`DILUPreconditioner` loop over internal faces only.
struct Dilu {
    /// r_c (the reciprocal of D*).
    rd: Vec<f64>,
    /// r_c a_ck for every entry k of row c: the coefficients of both triangular sweeps.
    rdc: Vec<f64>,
}

impl Dilu {
    fn new(a: &Ldu, m: &RowMatrix<'_>) -> Self {
        let rows = m.rows;
        let n = rows.n_rows();
        let mut rd = a.diag.clone();
        for c in 0..n {
            let mut d = rd[c];
            for k in rows.start[c] as usize..rows.mid[c] as usize {
                let f = rows.face[k] as usize;
                d -= a.upper[f] * a.lower[f] / rd[rows.col[k] as usize];
            }
            rd[c] = d;
        }
        for d in &mut rd {
            *d = 1.0 / *d;
        }
        let mut rdc = vec![0.0; m.coef.len()];
        for c in 0..n {
            for k in rows.row(c) {
                rdc[k] = rd[c] * m.coef[k];
            }
        }
        Dilu { rd, rdc }
    }

    /// w = M⁻¹ r: forward substitution with (D* + L) D*⁻¹ in increasing row order, then backward
    /// with (D* + U) in decreasing order. Each row's last term is usually the row just done
    /// (c − 1 forward, c + 1 backward); that value is taken from a register instead of being
    /// read back from memory, which shortens the chain of dependent operations the sweep is
    /// bound by (the same operations in the same order, so the same bits).
    fn apply(&self, rows: &RowAddressing, r: &[f64], w: &mut [f64]) {
        let n = w.len();
        let mut prev = 0.0;
        for c in 0..n {
            let (s0, m) = (rows.start[c] as usize, rows.mid[c] as usize);
            let mut s = self.rd[c] * r[c];
            if m > s0 {
                for (&j, &v) in rows.col[s0..m - 1].iter().zip(&self.rdc[s0..m - 1]) {
                    s -= v * w[j as usize];
                }
                let j = rows.col[m - 1] as usize;
                s -= self.rdc[m - 1] * if j + 1 == c { prev } else { w[j] };
            }
            w[c] = s;
            prev = s;
        }
        for c in (0..n).rev() {
            let (m, e) = (rows.mid[c] as usize, rows.end[c] as usize);
            let mut s = w[c];
            if e > m {
                for (&j, &v) in rows.col[m + 1..e].iter().zip(&self.rdc[m + 1..e]).rev() {
                    s -= v * w[j as usize];
                }
                let j = rows.col[m] as usize;
                s -= self.rdc[m] * if j == c + 1 { prev } else { w[j] };
            }
            w[c] = s;
            prev = s;
        }
    }
}

/// A preconditioner ready to apply.
enum Precond {
    Identity,
    /// 1/a_cc.
    Jacobi(Vec<f64>),
    Dilu(Dilu),
    /// A K-cycle of [`crate::amg`].
    Amg(std::rc::Rc<crate::amg::Amg>),
    /// A V-cycle of OpenFOAM's GAMG ([`gamg`]), its work vectors this thread's `GAMG_WORK`.
    VCycle(std::rc::Rc<crate::amg::Amg>),
}

/// A multigrid hierarchy, the matrix and the pairing weights it was built for (none for the
/// K-cycle's, whose pairing follows the matrix).
type Cached = (Ldu, Arc<Vec<f64>>, std::rc::Rc<crate::amg::Amg>);

thread_local! {
    /// The last K-cycle hierarchy ([`amg_for`]) on this thread.
    static AMG_CACHE: std::cell::RefCell<Option<Cached>> = const { std::cell::RefCell::new(None) };
    /// The last hierarchy [`gamg`] used ([`gamg_for`]) on this thread.
    static GAMG_CACHE: std::cell::RefCell<Option<Cached>> = const { std::cell::RefCell::new(None) };
    /// The V-cycle's work vectors of the last [`gamg`] solve on this thread, for the next
    /// solve on a hierarchy of the same level sizes (every entry is written before it is read
    /// in a cycle, so what they hold does not matter; allocating and zeroing them took about a
    /// millisecond per solve on the 48³ cavity).
    static GAMG_WORK: std::cell::RefCell<Option<crate::amg::CycleWork>> =
        const { std::cell::RefCell::new(None) };
}

/// The hierarchy in `cache` when it was built for `a` (bit for bit) and `weights`; else, for
/// the same `weights` and when `keep`, the cached hierarchy's aggregates with `a`'s Galerkin
/// products ([`crate::amg::Amg::refresh`] in place when no solve holds the hierarchy, else
/// [`crate::amg::Amg::rebuild`]; either may refuse); else `build(weights)`. The result is
/// cached. Redoing the values in place, without the copies and allocations of a new
/// hierarchy, took the set-up from 0.29 to 0.13 s of the main thread's 5.3 s on 30 steps of
/// the 48³ k-ε cavity at 2 threads (perf samples; docs/speed.md, sixth pass).
fn cached_hierarchy(
    cache: &'static std::thread::LocalKey<std::cell::RefCell<Option<Cached>>>,
    a: &Ldu,
    m: &RowMatrix<'_>,
    weights: Arc<Vec<f64>>,
    keep: bool,
    build: impl FnOnce(Vec<f64>) -> crate::amg::Amg,
) -> std::rc::Rc<crate::amg::Amg> {
    cache.with(|cache| {
        let mut cache = cache.borrow_mut();
        let mut rebuilt = None;
        if let Some((cached, cached_w, amg)) = cache.as_mut() {
            if Arc::ptr_eq(cached_w, &weights) || *cached_w == weights {
                if same_matrix(cached, a) {
                    return amg.clone();
                }
                if keep {
                    // In place when no solve holds the hierarchy (the same bits as rebuild).
                    if std::rc::Rc::get_mut(amg).is_some_and(|h| h.refresh(m)) {
                        copy_matrix(a, cached);
                        return amg.clone();
                    }
                    rebuilt = amg.rebuild(m);
                }
            }
        }
        let amg = std::rc::Rc::new(rebuilt.unwrap_or_else(|| build(weights.to_vec())));
        *cache = Some((a.clone(), weights, amg.clone()));
        amg
    })
}

/// `a == b` (each entry compared with `==`), on large matrices in parallel blocks.
fn same_matrix(a: &Ldu, b: &Ldu) -> bool {
    let same = |x: &[f64], y: &[f64]| {
        x.len() == y.len()
            && crate::reduce::all_blocks(x.len(), x.len() >= PAR_MIN, |r| x[r.clone()] == y[r])
    };
    same(&a.diag, &b.diag) && same(&a.upper, &b.upper) && same(&a.lower, &b.lower)
}

/// `to` becomes a copy of `from` (on large matrices in parallel blocks).
fn copy_matrix(from: &Ldu, to: &mut Ldu) {
    let copy = |x: &[f64], y: &mut Vec<f64>| {
        y.resize(x.len(), 0.0);
        crate::reduce::copy_values(x, y, x.len() >= PAR_MIN);
    };
    copy(&from.diag, &mut to.diag);
    copy(&from.upper, &mut to.upper);
    copy(&from.lower, &mut to.lower);
}

/// The K-cycle's hierarchy of `a`: reused when `a` equals (bit for bit) the matrix of the
/// previous call on this thread — the pressure matrix of every PISO corrector and
/// non-orthogonal correction of a time step is the same — else built. On fewer than
/// [`PAR_MIN`] rows the result depends on the matrix only, never on what was solved before;
/// on larger matrices a new matrix of the same rows keeps the previous hierarchy's aggregates
/// for up to [`crate::amg::REAGGREGATE`] set-ups ([`crate::amg::Amg::rebuild`]), so the
/// hierarchy depends on the matrices of the last few time steps (the same on any number of
/// threads).
fn amg_for(a: &Ldu, m: &RowMatrix<'_>) -> std::rc::Rc<crate::amg::Amg> {
    let keep = a.diag.len() >= PAR_MIN;
    cached_hierarchy(&AMG_CACHE, a, m, Arc::default(), keep, |_| {
        crate::amg::Amg::new(m)
    })
}

/// OpenFOAM's `faceAreaPair` weight of each entry of the rows of `g`: |S ∘ (1, 1.01, 1.02)| /
/// √|S| of its face (`faceAreaPairGAMGAgglomeration`; the factors break the ties of a
/// Cartesian mesh's faces).
pub(crate) fn face_area_pair_weights(g: &FvGeometry) -> Vec<f64> {
    g.rows
        .face
        .iter()
        .map(|&f| {
            let s = g.sf[f as usize];
            let m = g.mag_sf[f as usize];
            (s[0] * s[0] + (1.01 * s[1]).powi(2) + (1.02 * s[2]).powi(2)).sqrt() / m.sqrt()
        })
        .collect()
}

/// [`gamg`]'s hierarchy of `a` on the mesh of `g`: reused when `a` equals the matrix of the
/// previous call on this thread; else, for the same pairing weights (the same mesh), the
/// previous hierarchy's aggregates with `a`'s Galerkin products ([`crate::amg::Amg::rebuild`]:
/// the aggregates follow the mesh alone, so this is the hierarchy [`crate::amg::Amg::gamg`]
/// would build, bit for bit, as OpenFOAM's `cacheAgglomeration` keeps it); else built.
fn gamg_for(a: &Ldu, g: &FvGeometry, m: &RowMatrix<'_>) -> std::rc::Rc<crate::amg::Amg> {
    let w = g.pair_weights(face_area_pair_weights);
    cached_hierarchy(&GAMG_CACHE, a, m, w, true, |w| crate::amg::Amg::gamg(m, w))
}

impl Precond {
    fn new(kind: Preconditioner, a: &Ldu, m: &RowMatrix<'_>) -> Self {
        match kind {
            Preconditioner::None => Precond::Identity,
            Preconditioner::Diagonal => Precond::Jacobi(a.diag.iter().map(|d| 1.0 / d).collect()),
            Preconditioner::Dic => Precond::Dilu(Dilu::new(a, m)),
            Preconditioner::Amg => Precond::Amg(amg_for(a, m)),
        }
    }

    fn apply(&self, rows: &RowAddressing, r: &[f64], w: &mut [f64]) {
        match self {
            Precond::Identity => w.copy_from_slice(r),
            Precond::Jacobi(dinv) => w
                .iter_mut()
                .zip(r)
                .zip(dinv)
                .for_each(|((w, r), d)| *w = r * d),
            Precond::Dilu(f) => f.apply(rows, r, w),
            Precond::Amg(amg) => amg.apply(r, w),
            Precond::VCycle(amg) => {
                w.iter_mut().for_each(|v| *v = 0.0);
                GAMG_WORK.with_borrow_mut(|work| {
                    let work = match work {
                        Some(kept) if amg.fits(kept) => kept,
                        _ => work.insert(amg.cycle_work()),
                    };
                    amg.v_cycle(r, w, r, work);
                });
            }
        }
    }
}

/// The initial residual `b − A x`, OpenFOAM's normalisation factor and the normalised initial
/// residual (an error if it is not finite).
pub(crate) fn start(
    m: &RowMatrix<'_>,
    b: &[f64],
    x: &[f64],
    what: &str,
) -> Result<(Vec<f64>, f64, SolveStats)> {
    let (r, nf) = residual_and_norm_factor(m, x, b);
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
/// gradients, starting from `x`. `what` names the field in errors. With the multigrid
/// preconditioner (not a fixed linear operator) β is the flexible one,
/// β = w_k·(r_k − r_{k−1}) / (w_{k−1}·r_{k−1}) (Notay, *Flexible conjugate gradients*, SIAM
/// J. Sci. Comput. 22 (2000) 1444–1460), which equals the classical w_k·r_k / (w_{k−1}·r_{k−1})
/// for a fixed preconditioner; the others keep the classical form and OpenFOAM's bits.
pub fn pcg(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    pre: Preconditioner,
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    pcg_with(a, g, b, x, |m| Precond::new(pre, a, m), c, what)
}

/// `GAMG` on a symmetric matrix: flexible conjugate gradients ([`pcg`]'s) preconditioned by
/// one V-cycle of OpenFOAM's GAMG (`crate::amg::Amg::v_cycle` on the `faceAreaPair`
/// hierarchy of [`crate::amg::Amg::gamg`], kept across calls by `gamg_for`), to the
/// entry's tolerances. OpenFOAM iterates the V-cycles alone; CG's acceleration takes fewer of
/// them where the pressure field has long smooth modes (the 320² RAS cavity: 479 against 759
/// V-cycles alone over 30 steps, pisoFoam's GAMG ≈ 25 per step) and the same number elsewhere
/// (the 48³ cavity: 189 against 188 alone and pisoFoam's 189).
pub fn gamg(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    let cycle = |m: &RowMatrix<'_>| Precond::VCycle(gamg_for(a, g, m));
    pcg_with(a, g, b, x, cycle, c, what)
}

/// [`pcg`] with the preconditioner `make` builds (only when the initial guess has not met the
/// tolerances already).
fn pcg_with<'a>(
    a: &'a Ldu,
    g: &'a FvGeometry,
    b: &[f64],
    x: &mut [f64],
    make: impl FnOnce(&RowMatrix<'a>) -> Precond,
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    let n = x.len();
    let m = RowMatrix::new(a, g);
    let (mut r, nf, mut stats) = start(&m, b, x, what)?;
    let r0 = stats.initial;
    if converged(c, r0, r0, 0) {
        return Ok(stats);
    }
    let mut ap = vec![0.0; n];
    let pre = make(&m);
    let mut w = vec![0.0; n];
    let mut p = vec![0.0; n];
    let mut rho_old = 1.0;
    let flexible = matches!(pre, Precond::Amg(_) | Precond::VCycle(_));
    let mut r_prev = if flexible { r.clone() } else { Vec::new() };
    while stats.iterations < c.max_iter {
        pre.apply(m.rows, &r, &mut w);
        // The flexible β's two products and r kept for the next one, in one pass.
        let (rho, w_r_prev) = if flexible {
            dots_and_keep(&w, &r, &mut r_prev)
        } else {
            (dot(&w, &r), 0.0)
        };
        let beta = if stats.iterations == 0 {
            0.0
        } else if flexible {
            (rho - w_r_prev) / rho_old
        } else {
            rho / rho_old
        };
        par_map2(&mut p, &w, &[], |w, p| w + beta * p);
        let pap = m.mul_dot(&p, &mut ap);
        if pap == 0.0 {
            break;
        }
        let alpha = rho / pap;
        let res = update_and_residual(x, &mut r, &p, &ap, alpha);
        rho_old = rho;
        stats.iterations += 1;
        stats.last = res / nf;
        check_finite(what, stats.last)?;
        if converged(c, stats.last, r0, stats.iterations) {
            break;
        }
    }
    Ok(stats)
}

/// Solves `A x = b` (any non-singular A) by preconditioned biconjugate gradients, starting
/// from `x` (Saad Alg. 7.3 with a preconditioner; OpenFOAM's `PBiCG`): the recurrences of CG
/// run on A with the residual r and on Aᵀ with a shadow residual r̃ = b − Aᵀx, each
/// preconditioned (Aᵀ by the transposed factorisation: the DILU of Aᵀ, whose reciprocal
/// diagonal is that of A), α = (w·r̃)/(Ap·p̃), β = (w·r̃)/(w·r̃)_old. The operations follow
/// OpenFOAM v1912's `PBiCG::solve`, so the results are its to round-off. The multigrid
/// preconditioner has no transposed form here: with it the solve is [`bicgstab`].
pub fn bicg(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    pre: Preconditioner,
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    if pre == Preconditioner::Amg {
        return bicgstab(a, g, b, x, pre, c, what);
    }
    let n = x.len();
    let m = RowMatrix::new(a, g);
    let (mut ra, nf, mut stats) = start(&m, b, x, what)?;
    let r0 = stats.initial;
    if converged(c, r0, r0, 0) {
        return Ok(stats);
    }
    let at = Ldu {
        diag: a.diag.clone(),
        upper: a.lower.clone(),
        lower: a.upper.clone(),
    };
    let mt = RowMatrix::new(&at, g);
    let mut wt = vec![0.0; n];
    mt.mul(x, &mut wt);
    let mut rt: Vec<f64> = b.iter().zip(&wt).map(|(b, w)| b - w).collect();
    let pre_a = Precond::new(pre, a, &m);
    let pre_t = Precond::new(pre, &at, &mt);
    let mut wa = vec![0.0; n];
    let mut pa = vec![0.0; n];
    let mut pt = vec![0.0; n];
    let mut wart = 0.0;
    loop {
        let wart_old = wart;
        pre_a.apply(m.rows, &ra, &mut wa);
        pre_t.apply(mt.rows, &rt, &mut wt);
        wart = dot(&wa, &rt);
        if stats.iterations == 0 {
            pa.copy_from_slice(&wa);
            pt.copy_from_slice(&wt);
        } else {
            let beta = wart / wart_old;
            pa.iter_mut().zip(&wa).for_each(|(p, w)| *p = w + beta * *p);
            pt.iter_mut().zip(&wt).for_each(|(p, w)| *p = w + beta * *p);
        }
        m.mul(&pa, &mut wa);
        mt.mul(&pt, &mut wt);
        let wapt = dot(&wa, &pt);
        // OpenFOAM's singularity test (|w·p̃|/n_f below VSMALL).
        if wapt.abs() / nf < 1e-300 {
            break;
        }
        let alpha = wart / wapt;
        for i in 0..n {
            x[i] += alpha * pa[i];
            ra[i] -= alpha * wa[i];
            rt[i] -= alpha * wt[i];
        }
        stats.last = sum_abs(&ra) / nf;
        check_finite(what, stats.last)?;
        stats.iterations += 1;
        if (stats.iterations >= c.max_iter || meets(c, stats.last, r0))
            && stats.iterations >= c.min_iter
        {
            break;
        }
    }
    Ok(stats)
}

/// Solves `A x = b` (any non-singular A) by right-preconditioned BiCGStab (Saad Alg. 9.5 with
/// the Jacobi or DILU preconditioner), starting from `x`. As OpenFOAM's `PBiCGStab`, the
/// residual of the half step s = r − αAy is checked too and the solve ends there when it
/// meets the tolerances.
pub fn bicgstab(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    pre: Preconditioner,
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    let n = x.len();
    let m = RowMatrix::new(a, g);
    let (mut r, nf, mut stats) = start(&m, b, x, what)?;
    let r0 = stats.initial;
    if converged(c, r0, r0, 0) {
        return Ok(stats);
    }
    let pre = Precond::new(pre, a, &m);
    let mut t = vec![0.0; n];
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
        pre.apply(m.rows, &p, &mut y);
        m.mul(&y, &mut v);
        let rv = dot(&rhat, &v);
        if rv == 0.0 || !rv.is_finite() {
            break;
        }
        alpha = rho / rv;
        s.iter_mut()
            .zip(&r)
            .zip(&v)
            .for_each(|((s, r), v)| *s = r - alpha * v);
        // The half step may already meet the tolerances (OpenFOAM's PBiCGStab checks, too).
        let half = sum_abs(&s) / nf;
        check_finite(what, half)?;
        if meets(c, half, r0) {
            x.iter_mut().zip(&y).for_each(|(x, y)| *x += alpha * y);
            stats.iterations += 1;
            stats.last = half;
            break;
        }
        pre.apply(m.rows, &s, &mut z);
        m.mul(&z, &mut t);
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

/// Smoothing as OpenFOAM's `smoothSolver` runs it: `sweeps` sweeps of the smoother between
/// residual checks, the iteration count advancing by `sweeps`, until the residual meets the
/// tolerances or `max_iter` is reached. A Gauss–Seidel sweep updates the rows in place,
/// x_c ← (b_c − Σ_k a_ck x_k) / a_cc, so a row sees the values of the rows already done in
/// this sweep (Saad §4.1; `symGaussSeidel` adds the backward sweep); an incomplete-factor
/// sweep adds M⁻¹(b − A x) ([`SmootherKind::Factor`]). Converges for diagonally dominant
/// matrices (the momentum equation's).
pub fn smooth(
    a: &Ldu,
    g: &FvGeometry,
    b: &[f64],
    x: &mut [f64],
    smoother: Smoother,
    c: &SolverControls,
    what: &str,
) -> Result<SolveStats> {
    let m = RowMatrix::new(a, g);
    let (mut r, nf, mut stats) = start(&m, b, x, what)?;
    let r0 = stats.initial;
    if converged(c, r0, r0, 0) {
        return Ok(stats);
    }
    let sweeps = smoother.sweeps.max(1);
    // b′ = b − (interface part of A) x with x at the start of the sweep: OpenFOAM's
    // Gauss–Seidel smoothers update the coupled (cyclic) interfaces once per sweep.
    let rows = m.rows;
    let has_iface = (0..x.len()).any(|c| rows.end[c] < rows.start[c + 1]);
    let mut b_prime = b.to_vec();
    let interfaces = |x: &[f64], bp: &mut [f64]| {
        if has_iface {
            for c in 0..x.len() {
                let mut s = b[c];
                for k in rows.end[c] as usize..rows.start[c + 1] as usize {
                    s -= m.coef[k] * x[rows.col[k] as usize];
                }
                bp[c] = s;
            }
        }
    };
    let mut sweeper = crate::sweep::Sweeper::new(m.rows, smoother.hybrid);
    let factor = match smoother.kind {
        SmootherKind::Factor | SmootherKind::FactorGaussSeidel => Some(Dilu::new(a, &m)),
        _ => None,
    };
    let mut w = vec![0.0; if factor.is_some() { x.len() } else { 0 }];
    let factor_sweep = |x: &mut [f64], r: &mut [f64], w: &mut [f64], f: &Dilu| {
        // r = b − A x (OpenFOAM's lduMatrix::residual order: b − d x, then the faces).
        for c in 0..x.len() {
            let mut s = b[c] - m.diag[c] * x[c];
            for k in m.rows.row(c) {
                s -= m.coef[k] * x[m.rows.col[k] as usize];
            }
            r[c] = s;
        }
        f.apply(m.rows, r, w);
        x.iter_mut().zip(w.iter()).for_each(|(x, w)| *x += w);
    };
    loop {
        match (smoother.kind, &factor) {
            (SmootherKind::GaussSeidel | SmootherKind::SymGaussSeidel, _) => {
                for _ in 0..sweeps {
                    interfaces(x, &mut b_prime);
                    sweeper.sweep(&m, &b_prime, x, false);
                    if smoother.kind == SmootherKind::SymGaussSeidel {
                        sweeper.sweep(&m, &b_prime, x, true);
                    }
                }
            }
            (_, Some(f)) => {
                for _ in 0..sweeps {
                    factor_sweep(x, &mut r, &mut w, f);
                }
                if smoother.kind == SmootherKind::FactorGaussSeidel {
                    for _ in 0..sweeps {
                        interfaces(x, &mut b_prime);
                        sweeper.sweep(&m, &b_prime, x, false);
                    }
                }
            }
            (_, None) => unreachable!("factor smoothers build their factorisation"),
        }
        // Σ|b − A x| in one pass (the additions of sum_abs over m.mul's residual).
        stats.last = sum_abs_by(x.len(), |c| b[c] - m.row_times(c, x)) / nf;
        check_finite(what, stats.last)?;
        stats.iterations += sweeps;
        if stats.iterations >= c.max_iter || converged(c, stats.last, r0, stats.iterations) {
            break;
        }
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The largest |a − b| over two equally long vectors.
    fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    fn geometry(n: [usize; 3]) -> FvGeometry {
        let m = mesh::build::uniform_box([0.0; 3], [1.0, 0.7, 0.4], n);
        FvGeometry::new(&m).unwrap()
    }

    /// A diagonally dominant matrix on the mesh of `g`, symmetric or not.
    fn matrix(g: &FvGeometry, symmetric: bool, seed: u64) -> Ldu {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut a = Ldu::zeros(g);
        for f in 0..g.n_internal {
            a.upper[f] = -rng.gen_range(0.1..1.0);
            a.lower[f] = if symmetric {
                a.upper[f]
            } else {
                -rng.gen_range(0.1..1.0)
            };
            let (o, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
            a.diag[o] -= a.lower[f];
            a.diag[n] -= a.upper[f];
        }
        for d in &mut a.diag {
            *d += rng.gen_range(0.01..0.5);
        }
        a
    }

    /// OpenFOAM's face-ordered DIC/DILU (`DICPreconditioner`, `DILUPreconditioner` on a mesh in
    /// upper-triangular face order): the reference the row form must reproduce bit for bit.
    fn face_ordered_dilu(a: &Ldu, g: &FvGeometry, r: &[f64]) -> Vec<f64> {
        let mut rd = a.diag.clone();
        for f in 0..g.n_internal {
            let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
            rd[n] -= a.upper[f] * a.lower[f] / rd[p];
        }
        rd.iter_mut().for_each(|d| *d = 1.0 / *d);
        let mut w: Vec<f64> = rd.iter().zip(r).map(|(d, r)| d * r).collect();
        for f in 0..g.n_internal {
            let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
            w[n] -= rd[n] * a.lower[f] * w[p];
        }
        for f in (0..g.n_internal).rev() {
            let (p, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
            w[p] -= rd[p] * a.upper[f] * w[n];
        }
        w
    }

    fn face_ordered_mul(a: &Ldu, g: &FvGeometry, x: &[f64]) -> Vec<f64> {
        let mut y: Vec<f64> = a.diag.iter().zip(x).map(|(d, x)| d * x).collect();
        for f in 0..g.n_internal {
            let (o, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
            y[o] += a.upper[f] * x[n];
            y[n] += a.lower[f] * x[o];
        }
        y
    }

    #[test]
    fn row_form_reproduces_openfoams_face_loops_bit_for_bit() {
        let g = geometry([7, 5, 3]);
        for (seed, symmetric) in [(1, true), (2, false)] {
            let a = matrix(&g, symmetric, seed);
            let m = RowMatrix::new(&a, &g);
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed + 10);
            let r: Vec<f64> = (0..g.n_cells).map(|_| rng.gen_range(-1.0..1.0)).collect();
            let mut w = vec![0.0; g.n_cells];
            Dilu::new(&a, &m).apply(m.rows, &r, &mut w);
            assert_eq!(w, face_ordered_dilu(&a, &g, &r), "symmetric {symmetric}");
            let mut y = vec![0.0; g.n_cells];
            let d = m.mul_dot(&r, &mut y);
            assert_eq!(y, face_ordered_mul(&a, &g, &r));
            assert_eq!(d, dot(&r, &y));
        }
    }

    #[test]
    fn dic_is_the_exact_factorisation_of_a_tridiagonal_matrix() {
        // On a 1-D chain of cells ILU(0) has no dropped fill: M = A, so PCG converges in one
        // iteration and BiCGStab in one, to round-off.
        let g = geometry([40, 1, 1]);
        let x_true: Vec<f64> = (0..g.n_cells).map(|i| (i as f64 * 0.3).sin()).collect();
        for symmetric in [true, false] {
            let a = matrix(&g, symmetric, 3);
            let mut b = vec![0.0; g.n_cells];
            a.mul(&g, &x_true, &mut b);
            let c = SolverControls {
                tolerance: 1e-13,
                ..SolverControls::default()
            };
            let mut x = vec![0.0; g.n_cells];
            let s = if symmetric {
                pcg(&a, &g, &b, &mut x, Preconditioner::Dic, &c, "x").unwrap()
            } else {
                bicgstab(&a, &g, &b, &mut x, Preconditioner::Dic, &c, "x").unwrap()
            };
            assert_eq!(s.iterations, 1, "symmetric {symmetric}: {s:?}");
            let err = max_abs_diff(&x, &x_true);
            assert!(err < 1e-12, "{err}");
        }
    }

    #[test]
    fn every_method_solves_a_diagonally_dominant_system() {
        let g = geometry([9, 8, 4]);
        let x_true: Vec<f64> = (0..g.n_cells).map(|i| 1.0 + (i as f64).cos()).collect();
        let c = SolverControls {
            tolerance: 1e-12,
            ..SolverControls::default()
        };
        let sm = |kind| {
            Method::Smooth(Smoother {
                kind,
                sweeps: 1,
                hybrid: false,
            })
        };
        let gs = |symmetric| {
            sm(if symmetric {
                SmootherKind::SymGaussSeidel
            } else {
                SmootherKind::GaussSeidel
            })
        };
        let mut iters = Vec::new();
        for symmetric in [true, false] {
            let a = matrix(&g, symmetric, 4);
            let mut b = vec![0.0; g.n_cells];
            a.mul(&g, &x_true, &mut b);
            let mut methods = vec![
                Method::BiCgStab(Preconditioner::Dic),
                Method::BiCgStab(Preconditioner::Diagonal),
                Method::BiCgStab(Preconditioner::None),
                Method::BiCg(Preconditioner::Dic),
                Method::BiCg(Preconditioner::Diagonal),
                Method::BiCg(Preconditioner::None),
                gs(true),
                gs(false),
                sm(SmootherKind::Factor),
                sm(SmootherKind::FactorGaussSeidel),
                Method::Gamg,
            ];
            if symmetric {
                methods.push(Method::Pcg(Preconditioner::Dic));
                methods.push(Method::Pcg(Preconditioner::Diagonal));
                methods.push(Method::Pcg(Preconditioner::None));
            }
            for method in methods {
                let mut x = vec![0.0; g.n_cells];
                let s = solve(method, &a, &g, &b, &mut x, &c, "x").unwrap();
                let err = max_abs_diff(&x, &x_true);
                assert!(
                    s.last < 1e-12 && err < 1e-9,
                    "{method:?}: {s:?}, error {err}"
                );
                iters.push((symmetric, method, s.iterations));
            }
        }
        // A symmetric sweep does the work of two forward ones and converges in fewer sweeps;
        // DIC beats Jacobi in CG iterations; an incomplete-factor sweep followed by a
        // Gauss–Seidel one beats either alone.
        let it = |sym: bool, m: Method| iters.iter().find(|i| i.0 == sym && i.1 == m).unwrap().2;
        assert!(it(true, gs(true)) < it(true, gs(false)));
        for sym in [true, false] {
            let both = it(sym, sm(SmootherKind::FactorGaussSeidel));
            assert!(both < it(sym, sm(SmootherKind::Factor)) && both < it(sym, gs(false)));
        }
        assert!(
            it(true, Method::Pcg(Preconditioner::Dic))
                < it(true, Method::Pcg(Preconditioner::Diagonal))
        );
    }

    /// A box periodic in x (the xMin/xMax patches a cyclic pair).
    fn periodic_geometry(n: [usize; 3]) -> FvGeometry {
        let mut m = mesh::build::uniform_box([0.0; 3], [1.0, 0.7, 0.4], n);
        for p in &mut m.boundary {
            let nbr = match p.name.as_str() {
                "xMin" => "xMax",
                "xMax" => "xMin",
                _ => continue,
            };
            p.patch_type = "cyclic".into();
            p.extra.push(("neighbourPatch".into(), nbr.into()));
        }
        FvGeometry::new(&m).unwrap()
    }

    #[test]
    fn every_method_solves_a_system_with_cyclic_interfaces() {
        // The interfaces (cyclic pair faces) enter the products, not the factorisations: all
        // methods still converge to the solution of the whole matrix.
        let g = periodic_geometry([6, 5, 3]);
        assert!(g.n_internal > g.n_mesh_internal);
        let x_true: Vec<f64> = (0..g.n_cells).map(|i| 1.0 + (i as f64).sin()).collect();
        let c = SolverControls {
            tolerance: 1e-12,
            ..SolverControls::default()
        };
        for symmetric in [true, false] {
            let a = matrix(&g, symmetric, 6);
            let mut b = vec![0.0; g.n_cells];
            a.mul(&g, &x_true, &mut b);
            let mut methods = vec![
                Method::BiCgStab(Preconditioner::Dic),
                Method::BiCg(Preconditioner::Dic),
                Method::Smooth(Smoother {
                    kind: SmootherKind::SymGaussSeidel,
                    sweeps: 1,
                    hybrid: false,
                }),
                Method::Smooth(Smoother {
                    kind: SmootherKind::FactorGaussSeidel,
                    sweeps: 2,
                    hybrid: false,
                }),
                Method::Gamg,
            ];
            if symmetric {
                methods.push(Method::Pcg(Preconditioner::Dic));
            }
            for method in methods {
                let mut x = vec![0.0; g.n_cells];
                let s = solve(method, &a, &g, &b, &mut x, &c, "x").unwrap();
                let err = max_abs_diff(&x, &x_true);
                assert!(err < 1e-9, "{method:?}: {s:?}, error {err}");
            }
        }
    }

    #[test]
    fn dic_leaves_the_interfaces_out_as_openfoam() {
        // OpenFOAM's DIC/DILU loop over internal faces only: the factorisation of the matrix
        // with its interface coefficients is the one of the matrix without them.
        let g = periodic_geometry([5, 4, 2]);
        let a = matrix(&g, false, 7);
        let mut cut = a.clone();
        for f in g.n_mesh_internal..g.n_internal {
            cut.upper[f] = 0.0;
            cut.lower[f] = 0.0;
        }
        let (m, mc) = (RowMatrix::new(&a, &g), RowMatrix::new(&cut, &g));
        let r: Vec<f64> = (0..g.n_cells).map(|i| (i as f64 * 0.7).cos()).collect();
        let (mut w, mut wc) = (vec![0.0; g.n_cells], vec![0.0; g.n_cells]);
        Dilu::new(&a, &m).apply(m.rows, &r, &mut w);
        Dilu::new(&cut, &mc).apply(mc.rows, &r, &mut wc);
        assert_eq!(w, wc);
    }

    #[test]
    fn smooth_counts_sweeps_and_honours_max_iter() {
        let g = geometry([6, 6, 1]);
        let a = matrix(&g, false, 5);
        let b = vec![1.0; g.n_cells];
        let c = SolverControls {
            tolerance: 1e-30,
            max_iter: 7,
            ..SolverControls::default()
        };
        for kind in [
            SmootherKind::SymGaussSeidel,
            SmootherKind::FactorGaussSeidel,
        ] {
            let sm = Smoother {
                kind,
                sweeps: 3,
                hybrid: false,
            };
            let mut x = vec![0.0; g.n_cells];
            let s = smooth(&a, &g, &b, &mut x, sm, &c, "x").unwrap();
            // Checks after 3, 6 and 9 sweeps; 9 ≥ 7 stops (OpenFOAM's smoothSolver count).
            assert_eq!(s.iterations, 9);
            assert!(s.last < s.initial);
        }
    }
}
