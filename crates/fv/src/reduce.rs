//! The vector passes and reductions of the linear solvers ([`crate::linsolve`]): products and
//! sums in index order on small vectors (as OpenFOAM's `gSumProd`, `gSumMag`), else per fixed
//! block of [`BLOCK`] elements in parallel and the block sums in order, so the same bits on any
//! number of threads; the fused passes form each of their results exactly as the single ones.

// Loops index several vectors by the same element.
#![allow(clippy::needless_range_loop)]

use crate::ldu::PAR_MIN;
use crate::team::{self, Blocks};

/// Σ aᵢbᵢ: in index order on small vectors (as OpenFOAM's `gSumProd`), else per fixed block
/// of 8192 in parallel and the block sums in order (the same bits for any thread count).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    if a.len() < PAR_MIN {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    } else {
        dot_blocked(a, b)
    }
}

/// Σ aᵢbᵢ per fixed block of 8192 in parallel and the block sums in order, whatever the
/// length ([`dot`]'s large-vector form: the same bits for any thread count).
pub(crate) fn dot_blocked(a: &[f64], b: &[f64]) -> f64 {
    let parts: Vec<f64> = team::map(a.len().div_ceil(BLOCK), |k| {
        let r = block(k, a.len());
        a[r.clone()].iter().zip(&b[r]).map(|(x, y)| x * y).sum()
    });
    parts.iter().sum()
}

/// Σ|aᵢ|, ordered as [`dot`].
pub(crate) fn sum_abs(a: &[f64]) -> f64 {
    sum_abs_by(a.len(), |i| a[i])
}

/// [`sum_abs`] of the `n` values `at(0)`, …, `at(n − 1)` (the same additions in the same
/// order).
pub(crate) fn sum_abs_by(n: usize, at: impl Fn(usize) -> f64 + Sync) -> f64 {
    sum_abs_lanes::<1>(n, |i| [at(i)])[0]
}

/// [`sum_abs_by`] of `L` sequences at once: `at(i)` gives the i-th value of each (each
/// sequence's additions those of [`sum_abs`] on it alone).
pub(crate) fn sum_abs_lanes<const L: usize>(
    n: usize,
    at: impl Fn(usize) -> [f64; L] + Sync,
) -> [f64; L] {
    let part = |range: std::ops::Range<usize>| {
        let mut s = [0.0; L];
        for i in range {
            for (s, v) in s.iter_mut().zip(at(i)) {
                *s += v.abs();
            }
        }
        s
    };
    if n < PAR_MIN {
        part(0..n)
    } else {
        let parts: Vec<[f64; L]> = team::map(n.div_ceil(BLOCK), |k| part(block(k, n)));
        std::array::from_fn(|l| parts.iter().map(|p| p[l]).sum())
    }
}

/// Block length of the parallel reductions.
pub(crate) const BLOCK: usize = 8192;

/// out_i = row(i).0 for every i, and the sums of the rows' terms row(i).1 (each from −0.0, as
/// f64's `Sum` folds): in index order when not `parallel`, else per fixed block of [`BLOCK`]
/// in parallel and the block sums in order — a matrix–vector product and its dot products in
/// one pass, with the additions of the separate passes.
pub(crate) fn fill_and_sum<const L: usize>(
    out: &mut [f64],
    parallel: bool,
    row: impl Fn(usize) -> (f64, [f64; L]) + Sync,
) -> [f64; L] {
    let part = |r0: usize, out: &mut [f64]| {
        let mut sums = [-0.0; L];
        for (il, o) in out.iter_mut().enumerate() {
            let (v, terms) = row(r0 + il);
            *o = v;
            for (s, t) in sums.iter_mut().zip(terms) {
                *s += t;
            }
        }
        sums
    };
    if !parallel {
        return part(0, out);
    }
    let out = Blocks::new(out, BLOCK);
    // SAFETY: block k by chunk k alone.
    let parts: Vec<[f64; L]> = team::map(out.count(), |k| part(k * BLOCK, unsafe { out.get(k) }));
    std::array::from_fn(|l| parts.iter().map(|p| p[l]).sum())
}

/// `to` = `from` (of the same length), in parallel pieces when `parallel`.
pub(crate) fn copy_values(from: &[f64], to: &mut [f64], parallel: bool) {
    if parallel {
        let to = Blocks::new(to, BLOCK);
        team::run(to.count(), &|k| {
            // SAFETY: block k by chunk k alone.
            let t = unsafe { to.get(k) };
            t.copy_from_slice(&from[k * BLOCK..k * BLOCK + t.len()]);
        });
    } else {
        to.copy_from_slice(from);
    }
}

/// x += α p, r −= α q, and returns Σ|r| (one pass on small vectors).
pub(crate) fn update_and_residual(
    x: &mut [f64],
    r: &mut [f64],
    p: &[f64],
    q: &[f64],
    alpha: f64,
) -> f64 {
    if x.len() < PAR_MIN {
        let mut s = 0.0;
        for i in 0..x.len() {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            s += r[i].abs();
        }
        s
    } else {
        // One pass, the sum per block as sum_abs forms it.
        let (x, r) = (Blocks::new(x, BLOCK), Blocks::new(r, BLOCK));
        let parts: Vec<f64> = team::map(x.count(), |k| {
            // SAFETY: block k by chunk k alone.
            let (x, r) = unsafe { (x.get(k), r.get(k)) };
            let (p, q) = (&p[k * BLOCK..], &q[k * BLOCK..]);
            let mut s = 0.0;
            for i in 0..x.len() {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
                s += r[i].abs();
            }
            s
        });
        parts.iter().sum()
    }
}

/// (w·r, w·r_prev), each as [`dot`] forms it, and then r_prev = r, in one pass.
pub(crate) fn dots_and_keep(w: &[f64], r: &[f64], r_prev: &mut [f64]) -> (f64, f64) {
    let part = |w: &[f64], r: &[f64], rp: &mut [f64]| {
        // From −0.0, as f64's Sum folds ([`dot`]'s small-vector form).
        let (mut a, mut b) = (-0.0, -0.0);
        for i in 0..w.len() {
            a += w[i] * r[i];
            b += w[i] * rp[i];
            rp[i] = r[i];
        }
        (a, b)
    };
    if w.len() < PAR_MIN {
        part(w, r, r_prev)
    } else {
        let rp = Blocks::new(r_prev, BLOCK);
        let parts: Vec<(f64, f64)> = team::map(rp.count(), |k| {
            // SAFETY: block k by chunk k alone.
            let rp = unsafe { rp.get(k) };
            let lo = k * BLOCK;
            part(&w[lo..lo + rp.len()], &r[lo..lo + rp.len()], rp)
        });
        (
            parts.iter().map(|p| p.0).sum(),
            parts.iter().map(|p| p.1).sum(),
        )
    }
}

/// out_i = f(i, out_i) for every i: in order when not `parallel`, else per block of
/// [`BLOCK`] on the team (each element on its own: the same bits either way).
pub(crate) fn fill(out: &mut [f64], parallel: bool, f: impl Fn(usize, f64) -> f64 + Sync) {
    if !parallel {
        out.iter_mut().enumerate().for_each(|(i, o)| *o = f(i, *o));
        return;
    }
    team::each_mut(out, BLOCK, |i, o| *o = f(i, *o));
}

/// Block `k` of the fixed blocks of [`BLOCK`] elements of a vector of length `n`.
pub(crate) fn block(k: usize, n: usize) -> std::ops::Range<usize> {
    k * BLOCK..((k + 1) * BLOCK).min(n)
}

/// `pred(block)` holds for every fixed block of [`BLOCK`] of `0..n` (on the team when
/// `parallel`, else in order, stopping at the first that fails).
pub(crate) fn all_blocks(
    n: usize,
    parallel: bool,
    pred: impl Fn(std::ops::Range<usize>) -> bool + Sync,
) -> bool {
    let count = n.div_ceil(BLOCK);
    if parallel {
        team::map(count, |k| pred(block(k, n)))
            .into_iter()
            .all(|ok| ok)
    } else {
        (0..count).all(|k| pred(block(k, n)))
    }
}

/// out_i = f(a_i, b_i) (b empty: f(a_i, out_i)), in parallel on ≥ [`PAR_MIN`] elements (each
/// element on its own: the same bits either way).
pub(crate) fn par_map2(out: &mut [f64], a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64 + Sync) {
    let parallel = out.len() >= PAR_MIN;
    fill(out, parallel, |i, o| {
        f(a[i], if b.is_empty() { o } else { b[i] })
    });
}
