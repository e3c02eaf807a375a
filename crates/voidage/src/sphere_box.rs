//! Exact volume of a ball ∩ axis-aligned box, in closed form.
//!
//! # Formula
//! For a ball of radius R centred at the origin let G(a, b, c) = vol{x > a, y > b, z > c, |x| < R}
//! (the ball beyond a "corner" (a, b, c)). With a, b, c ≥ 0 and a² + b² + c² < R² (else G = 0)
//!
//! G = F(z_t) − F(c),  z_t = √(R² − a² − b²),
//!
//! F(z) = π/4·(R²z − z³/3) + abz + Σ_{s∈{a,b}} [ (z³/6 − R²z/2)·atan2(s, w_s)
//!        + R³/3·atan2(s·z, R·w_s) + s(s² − 3R²)/6·atan2(z, w_s) − s·z·w_s/3 ],
//!
//! w_s = √(R² − s² − z²), and exactly w_a = b, w_b = a at z = z_t. F is the antiderivative in z
//! of the area of the disk of radius √(R² − z²) beyond the corner (a, b) (a circular-segment
//! area), so G is exact up to rounding. Every inverse trigonometric term is an `atan2` with the
//! exact w (an `asin` form loses half the digits near the pole). Special cases: G(0, 0, 0) = V/8,
//! G(a, 0, 0) = π(R − a)²(2R + a)/12 (a quarter cap), and F(0) = 0.
//!
//! Negative arguments follow from the symmetry of the ball: G(−a, b, c) = 2G(0, b, c) − G(a, b, c)
//! (the same for b and c), and arguments are clamped to [−R, R].
//! A box [x₀, x₁] × [y₀, y₁] × [z₀, z₁] (relative to the centre) then has
//! V = Σ_{i,j,k ∈ {0,1}} (−1)^{i+j+k} G(x_i, y_j, z_k).
//!
//! Source: the closed form checked in `REFERENCE.md` ("Exact sphere ∩ axis-aligned box"); it is
//! the exact version of the numerical quadrature of Khawaja et al. (2012), eq. (10)–(12).
//!
//! # Accuracy
//! Every G value is a difference of terms of size ~R³, so the absolute error of a share is a few
//! ulps of the *ball* volume (≈1e-16·V), whatever the box. Boxes far smaller than the ball are
//! therefore taken by fast paths where possible: box inside the ball → box volume, ball inside
//! the box → ball volume, no overlap → 0; results are clamped to [0, min(box, ball) volume].
//! A box much smaller than the ball that straddles its surface keeps the absolute error
//! ≈1e-16·V (its relative error grows like (R/h)³·1e-16).
//!
//! All computations are done on the unit ball (coordinates divided by R, volumes times R³), so
//! radii from 1e-150 m to 1e100 m neither underflow nor overflow.

use mesh::v3::V3;
use std::f64::consts::PI;

/// Volume of the unit ball, 4π/3.
pub(crate) const UNIT_BALL: f64 = 4.0 / 3.0 * PI;

/// Volume of a ball of radius `r`, m³: 4πr³/3.
#[inline]
pub fn ball_volume(r: f64) -> f64 {
    UNIT_BALL * r * r * r
}

/// Volume of the spherical cap of height `h` (0 ≤ h ≤ 2R) of a ball of radius `r`:
/// π h² (3R − h) / 3, m³. `h` is clamped to [0, 2R].
#[inline]
pub fn cap_volume(r: f64, h: f64) -> f64 {
    let h = h.clamp(0.0, 2.0 * r);
    PI * h * h * (3.0 * r - h) / 3.0
}

/// One term of F: the contribution of the cut plane at distance `s` (unit ball).
#[inline(always)]
fn f_term(s: f64, w: f64, z: f64) -> f64 {
    if s == 0.0 {
        return 0.0;
    }
    let z2 = z * z;
    (z2 * z / 6.0 - 0.5 * z) * s.atan2(w)
        + (s * z).atan2(w) / 3.0
        + s * (s * s - 3.0) / 6.0 * z.atan2(w)
        - s * z * w / 3.0
}

/// F(z) of the module docs on the unit ball with explicit w_a, w_b.
#[inline(always)]
fn f_unit(a: f64, b: f64, z: f64, wa: f64, wb: f64) -> f64 {
    PI / 4.0 * (z - z * z * z / 3.0) + a * b * z + f_term(a, wa, z) + f_term(b, wb, z)
}

/// G(a, b, c) of the module docs on the unit ball for a, b, c ≥ 0: the volume of the unit ball
/// beyond the corner (a, b, c). G is symmetric in its arguments.
#[inline]
pub(crate) fn corner_unit(a: f64, b: f64, c: f64) -> f64 {
    // Sort descending so that zeros come last and the special forms apply.
    let (mut a, mut b, mut c) = (a, b, c);
    if a < b {
        std::mem::swap(&mut a, &mut b);
    }
    if b < c {
        std::mem::swap(&mut b, &mut c);
        if a < b {
            std::mem::swap(&mut a, &mut b);
        }
    }
    let ab2 = a * a + b * b;
    if ab2 + c * c >= 1.0 {
        return 0.0;
    }
    if b == 0.0 {
        // Quarter cap beyond x = a (a = 0: one octant).
        return PI * (1.0 - a) * (1.0 - a) * (2.0 + a) / 12.0;
    }
    let zt = (1.0 - ab2).sqrt();
    let top = f_unit(a, b, zt, b, a);
    if c == 0.0 {
        return top.max(0.0);
    }
    let wa = (1.0 - a * a - c * c).sqrt();
    let wb = (1.0 - b * b - c * c).sqrt();
    (top - f_unit(a, b, c, wa, wb)).max(0.0)
}

/// G(a, b, c) for a ball of radius `r` centred at the origin, any signs: the volume of
/// {x > a, y > b, z > c} ∩ ball, m³ (a, b, c in m). Negative arguments by reflection
/// (module docs), arguments clamped to [−R, R].
pub fn corner_volume(r: f64, a: f64, b: f64, c: f64) -> f64 {
    if !(r > 0.0) {
        return 0.0;
    }
    let terms = |t: f64| -> ([(f64, f64); 2], usize) {
        let t = (t / r).clamp(-1.0, 1.0);
        if t >= 0.0 {
            ([(t, 1.0), (0.0, 0.0)], 1)
        } else {
            ([(0.0, 2.0), (-t, -1.0)], 2)
        }
    };
    let (ta, na) = terms(a);
    let (tb, nb) = terms(b);
    let (tc, nc) = terms(c);
    let mut v = 0.0;
    for &(u, cu) in &ta[..na] {
        for &(w, cw) in &tb[..nb] {
            for &(x, cx) in &tc[..nc] {
                v += cu * cw * cx * corner_unit(u, w, x);
            }
        }
    }
    v * r * r * r
}

/// One axis of a box or grid in unit-ball coordinates: the box edge between two planes is the
/// linear combination Σ coef·G(…, u, …) of at most [`MAX_TERMS`] corner arguments u ≥ 0.
pub(crate) const MAX_TERMS: usize = 4;

/// Corner-argument combination of the slab lo < t < hi (unit ball, −1 ≤ lo ≤ hi ≤ 1): `n` pairs
/// (u, coef), u ≥ 0 and u < 1 (arguments u ≥ 1 give G = 0 and are dropped).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slab {
    pub(crate) u: [f64; MAX_TERMS],
    pub(crate) coef: [f64; MAX_TERMS],
    pub(crate) n: usize,
}

impl Slab {
    /// The slab between the planes `lo` and `hi` (unit-ball coordinates, clamped to [−1, 1]).
    #[inline]
    pub(crate) fn new(lo: f64, hi: f64) -> Slab {
        let mut s = Slab {
            u: [0.0; MAX_TERMS],
            coef: [0.0; MAX_TERMS],
            n: 0,
        };
        s.plane(lo, 1.0);
        s.plane(hi, -1.0);
        s
    }

    /// Adds `sign` × (the combination for G at the plane t).
    #[inline]
    fn plane(&mut self, t: f64, sign: f64) {
        let t = t.clamp(-1.0, 1.0);
        if t >= 0.0 {
            self.push(t, sign);
        } else {
            self.push(0.0, 2.0 * sign);
            self.push(-t, -sign);
        }
    }

    #[inline]
    fn push(&mut self, u: f64, coef: f64) {
        if u >= 1.0 {
            return;
        }
        for k in 0..self.n {
            if self.u[k] == u {
                self.coef[k] += coef;
                return;
            }
        }
        self.u[self.n] = u;
        self.coef[self.n] = coef;
        self.n += 1;
    }
}

/// Squared distances from 0 to the nearest and farthest points of [lo, hi].
#[inline]
pub(crate) fn interval_dist2(lo: f64, hi: f64) -> (f64, f64) {
    let near = if lo > 0.0 {
        lo * lo
    } else if hi < 0.0 {
        hi * hi
    } else {
        0.0
    };
    (near, (lo * lo).max(hi * hi))
}

/// How a box lies relative to the unit ball.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum BoxCase {
    /// No overlap (volume 0).
    Outside,
    /// The box lies in the ball (volume = box volume).
    BoxInside,
    /// The ball lies in the box (volume = ball volume).
    BallInside,
    /// The box straddles the sphere: the corner formula is needed.
    Straddles,
}

/// Classifies the box `lo`..`hi` (unit-ball coordinates relative to the centre, lo ≤ hi) for
/// the fast paths of the module docs.
#[inline]
fn box_case(lo: V3, hi: V3) -> BoxCase {
    let mut near = 0.0;
    let mut far = 0.0;
    let mut contains_ball = true;
    for a in 0..3 {
        let (n, f) = interval_dist2(lo[a], hi[a]);
        near += n;
        far += f;
        contains_ball &= lo[a] <= -1.0 && hi[a] >= 1.0;
    }
    if near >= 1.0 {
        BoxCase::Outside
    } else if far <= 1.0 {
        BoxCase::BoxInside
    } else if contains_ball {
        BoxCase::BallInside
    } else {
        BoxCase::Straddles
    }
}

/// Volume of the unit ball ∩ box from the three slabs: Σ coef_x coef_y coef_z G(u_x, u_y, u_z).
#[inline]
fn slabs_volume(sx: &Slab, sy: &Slab, sz: &Slab) -> f64 {
    let mut v = 0.0;
    for i in 0..sx.n {
        for j in 0..sy.n {
            let cxy = sx.coef[i] * sy.coef[j];
            if cxy == 0.0 {
                continue;
            }
            for k in 0..sz.n {
                if sz.coef[k] != 0.0 {
                    v += cxy * sz.coef[k] * corner_unit(sx.u[i], sy.u[j], sz.u[k]);
                }
            }
        }
    }
    v
}

/// Exact volume of the ball (centre `centre`, radius `r`) ∩ the axis-aligned box `lo`..`hi`,
/// m³ (all lengths in m).
///
/// Formula, fast paths and accuracy: module docs. Valid for any finite box (empty or inverted
/// boxes give 0) and any r ≥ 0; the result lies in [0, min(box volume, ball volume)].
pub fn sphere_box_volume(
    centre: impl Into<V3>,
    r: f64,
    lo: impl Into<V3>,
    hi: impl Into<V3>,
) -> f64 {
    let (centre, lo, hi) = (centre.into(), lo.into(), hi.into());
    if !(r > 0.0) || (0..3).any(|a| !(hi[a] > lo[a])) {
        return 0.0;
    }
    let inv = 1.0 / r;
    let l = V3::from_fn(|a, _| (lo[a] - centre[a]) * inv);
    let h = V3::from_fn(|a, _| (hi[a] - centre[a]) * inv);
    let r3 = r * r * r;
    match box_case(l, h) {
        BoxCase::Outside => return 0.0,
        // Computed in m³ without rescaling, so tiny boxes keep every digit.
        BoxCase::BoxInside => return (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]),
        BoxCase::BallInside => return UNIT_BALL * r3,
        BoxCase::Straddles => {}
    }
    let s: [Slab; 3] = std::array::from_fn(|a| Slab::new(l[a], h[a]));
    let box_unit: f64 = (0..3)
        .map(|a| h[a].min(1.0) - l[a].max(-1.0))
        .product::<f64>();
    slabs_volume(&s[0], &s[1], &s[2]).clamp(0.0, box_unit.min(UNIT_BALL)) * r3
}

/// Exact volumes of the ball ∩ every box of a tensor-product grid, sharing the corner values G
/// among neighbouring boxes (each G is evaluated once per grid node, and the boxes around a
/// node are differences of those values).
///
/// `planes[a]` are the grid planes along axis a **relative to the centre and divided by the
/// radius** (strictly increasing, at least two values); planes beyond ±1 may be passed and are
/// clamped. `out` receives (in m³ after multiplying by `r3` = R³) the volume of box
/// (i, j, k), index i + nx(j + ny·k), for nx = `planes[0].len() − 1` etc. Boxes inside the ball
/// or outside it take the fast paths; only boxes straddling the sphere use the corner values.
///
/// `scratch` is reused between calls to avoid allocations.
pub fn sphere_grid_volumes(
    r3: f64,
    planes: [&[f64]; 3],
    out: &mut Vec<f64>,
    scratch: &mut GridScratch,
) {
    let n: [usize; 3] = std::array::from_fn(|a| planes[a].len().saturating_sub(1));
    out.clear();
    out.resize(n[0] * n[1] * n[2], 0.0);
    if out.is_empty() {
        return;
    }
    // Per axis: the distinct corner arguments u (≥ 0, < 1), and each box edge's combination as
    // (index into them, coefficient) pairs.
    for (a, &pl) in planes.iter().enumerate() {
        let u = &mut scratch.u[a];
        u.clear();
        let terms = &mut scratch.terms[a];
        terms.clear();
        for w in pl.windows(2) {
            let slab = Slab::new(w[0], w[1]);
            let mut t = SlabTerms {
                idx: [0; MAX_TERMS],
                coef: slab.coef,
                n: slab.n,
            };
            for k in 0..slab.n {
                t.idx[k] = match u.iter().position(|&x| x == slab.u[k]) {
                    Some(i) => i,
                    None => {
                        u.push(slab.u[k]);
                        u.len() - 1
                    }
                };
            }
            terms.push(t);
        }
    }
    // Corner table, filled lazily (NaN = not yet computed).
    let m = [scratch.u[0].len(), scratch.u[1].len(), scratch.u[2].len()];
    scratch.g.clear();
    scratch.g.resize(m[0] * m[1] * m[2], f64::NAN);
    for k in 0..n[2] {
        let (zl, zh) = (planes[2][k], planes[2][k + 1]);
        for j in 0..n[1] {
            let (yl, yh) = (planes[1][j], planes[1][j + 1]);
            for i in 0..n[0] {
                let (xl, xh) = (planes[0][i], planes[0][i + 1]);
                let lo = V3::new(xl, yl, zl);
                let hi = V3::new(xh, yh, zh);
                let cell = i + n[0] * (j + n[1] * k);
                match box_case(lo, hi) {
                    BoxCase::Outside => continue,
                    BoxCase::BoxInside => {
                        out[cell] = (xh - xl) * (yh - yl) * (zh - zl) * r3;
                        continue;
                    }
                    BoxCase::BallInside => {
                        out[cell] = UNIT_BALL * r3;
                        continue;
                    }
                    BoxCase::Straddles => {}
                }
                let (sx, sy, sz) = (
                    &scratch.terms[0][i],
                    &scratch.terms[1][j],
                    &scratch.terms[2][k],
                );
                let us = &scratch.u;
                let mut v = 0.0;
                for p in 0..sx.n {
                    let ip = sx.idx[p];
                    for q in 0..sy.n {
                        let cxy = sx.coef[p] * sy.coef[q];
                        if cxy == 0.0 {
                            continue;
                        }
                        let iq = sy.idx[q];
                        for s in 0..sz.n {
                            if sz.coef[s] == 0.0 {
                                continue;
                            }
                            let is = sz.idx[s];
                            let g = &mut scratch.g[ip + m[0] * (iq + m[1] * is)];
                            if g.is_nan() {
                                *g = corner_unit(us[0][ip], us[1][iq], us[2][is]);
                            }
                            v += cxy * sz.coef[s] * *g;
                        }
                    }
                }
                let box_unit: f64 = (0..3)
                    .map(|a| hi[a].min(1.0) - lo[a].max(-1.0))
                    .product::<f64>();
                out[cell] = v.clamp(0.0, box_unit.min(UNIT_BALL)) * r3;
            }
        }
    }
}

/// A [`Slab`] with its arguments as indices into the axis's distinct arguments.
#[derive(Clone, Copy, Debug)]
struct SlabTerms {
    idx: [usize; MAX_TERMS],
    coef: [f64; MAX_TERMS],
    n: usize,
}

/// Volumes of the pieces of the unit ball cut by at most one plane per axis: `t[a]` is the
/// plane along axis a (|t| < 1, unit-ball coordinates relative to the centre) or `None`.
/// Piece `bits` (bit a set: the side above the plane along axis a; always clear for an uncut
/// axis) gets `out[bits]`; the others are 0. The same corner-value combination as
/// [`sphere_grid_volumes`] with at most 8 corner values, without its bookkeeping — the common
/// case of cells a few times larger than the particle.
pub(crate) fn cut_ball_unit(t: [Option<f64>; 3]) -> [f64; 8] {
    // Per axis and side: up to two (argument index, coefficient) terms; argument 0 is u = 0 and
    // argument 1 is u = |t|.
    type Terms = ([(usize, f64); 2], usize);
    let side_terms = |t: Option<f64>| -> [Terms; 2] {
        match t {
            None => [([(0, 2.0), (0, 0.0)], 1), ([(0, 0.0), (0, 0.0)], 0)],
            Some(t) if t >= 0.0 => [([(0, 2.0), (1, -1.0)], 2), ([(1, 1.0), (0, 0.0)], 1)],
            Some(_) => [([(1, 1.0), (0, 0.0)], 1), ([(0, 2.0), (1, -1.0)], 2)],
        }
    };
    let terms = [side_terms(t[0]), side_terms(t[1]), side_terms(t[2])];
    let u = t.map(|t| [0.0, t.map_or(0.0, f64::abs)]);
    let mut g = [f64::NAN; 8];
    let mut out = [0.0; 8];
    for (bits, o) in out.iter_mut().enumerate() {
        let side = [bits & 1, (bits >> 1) & 1, (bits >> 2) & 1];
        if (0..3).any(|a| side[a] == 1 && t[a].is_none()) {
            continue;
        }
        let [(tx, nx), (ty, ny), (tz, nz)] = [0, 1, 2].map(|a| terms[a][side[a]]);
        let mut v = 0.0;
        for &(i, cx) in &tx[..nx] {
            for &(j, cy) in &ty[..ny] {
                for &(k, cz) in &tz[..nz] {
                    let gi = &mut g[i | (j << 1) | (k << 2)];
                    if gi.is_nan() {
                        *gi = corner_unit(u[0][i], u[1][j], u[2][k]);
                    }
                    v += cx * cy * cz * *gi;
                }
            }
        }
        *o = v.clamp(0.0, UNIT_BALL);
    }
    out
}

/// Reusable buffers of [`sphere_grid_volumes`].
#[derive(Clone, Debug, Default)]
pub struct GridScratch {
    u: [Vec<f64>; 3],
    terms: [Vec<SlabTerms>; 3],
    g: Vec<f64>,
}
