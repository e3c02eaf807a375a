//! Convergence classification and the apparent order p of three grids, Celik et al. (2008)
//! eqs. (3a)–(3c):
//!
//! p = |ln|ε32/ε21| + q(p)| / ln r21,   q(p) = ln((r21^p − s)/(r32^p − s)),   s = sign(ε32/ε21),
//!
//! with ε21 = φ2 − φ1, ε32 = φ3 − φ2 (grid 1 the finest) and r21 = h2/h1, r32 = h3/h2 > 1.
//!
//! The absolute value in eq. (3a) hides divergence: for a sequence that moves *away* from a
//! limit under refinement it still returns a positive "order". So the behaviour is classified
//! first, from the error models behind eq. (3): monotone φ_i = φ0 + C h_i^p (s = +1) and
//! alternating φ_i = φ0 + (−1)^i C h_i^p (s = −1). For p > 0 these give
//! |ε32/ε21| = r21^p (r32^p − s)/(r21^p − s), which grows with p from its p → 0 limit
//! ln r32/ln r21 (s = +1) or 1 (s = −1). A positive p therefore exists exactly when
//! |ε32/ε21| exceeds that limit (convergence); otherwise the sequence diverges and p is
//! reported as undefined.

use serde::Serialize;
use std::fmt;

/// Differences |ε| at or below this fraction of max|φ| count as zero (round-off of the
/// subtraction itself).
pub const ZERO_CHANGE: f64 = 8.0 * f64::EPSILON;

/// Largest number of fixed-point iterations before falling back to bisection.
pub const MAX_ITERATIONS: u32 = 1000;

/// How the solution changes from the coarse to the fine grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Behaviour {
    /// s = +1 and the changes shrink fast enough for a p > 0: monotonic convergence.
    MonotonicConvergence,
    /// s = −1 (ε32/ε21 < 0) and the changes shrink: oscillatory convergence. Celik et al.
    /// still report p and the GCI (their Table 1, third case); they are flagged.
    OscillatoryConvergence,
    /// s = +1 but the changes do not shrink: the solution moves away under refinement.
    MonotonicDivergence,
    /// s = −1 and the oscillation does not shrink.
    OscillatoryDivergence,
    /// ε21 = 0 (φ1 = φ2) but ε32 ≠ 0.
    ZeroChangeFine,
    /// ε32 = 0 (φ2 = φ3) but ε21 ≠ 0.
    ZeroChangeCoarse,
    /// φ1 = φ2 = φ3: no grid dependence at round-off level.
    NoChange,
}

impl Behaviour {
    /// Whether an apparent order exists (the two converging behaviours).
    pub fn converges(self) -> bool {
        matches!(
            self,
            Behaviour::MonotonicConvergence | Behaviour::OscillatoryConvergence
        )
    }

    /// Why p is undefined, for the behaviours without an order.
    pub fn undefined(self) -> Option<Undefined> {
        match self {
            Behaviour::MonotonicConvergence | Behaviour::OscillatoryConvergence => None,
            Behaviour::MonotonicDivergence => Some(Undefined::MonotonicDivergence),
            Behaviour::OscillatoryDivergence => Some(Undefined::OscillatoryDivergence),
            Behaviour::ZeroChangeFine => Some(Undefined::ZeroChangeFine),
            Behaviour::ZeroChangeCoarse => Some(Undefined::ZeroChangeCoarse),
            Behaviour::NoChange => Some(Undefined::NoChange),
        }
    }
}

impl fmt::Display for Behaviour {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Behaviour::MonotonicConvergence => "monotonic convergence",
            Behaviour::OscillatoryConvergence => "oscillatory convergence",
            Behaviour::MonotonicDivergence => "monotonic divergence",
            Behaviour::OscillatoryDivergence => "oscillatory divergence",
            Behaviour::ZeroChangeFine => "no change between the two finest grids",
            Behaviour::ZeroChangeCoarse => "no change between the two coarsest grids",
            Behaviour::NoChange => "no change between any of the grids",
        })
    }
}

/// Why the apparent order (and with it φ_ext, e_ext and the GCI) is undefined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Undefined {
    /// The solution moves monotonically away from a limit under refinement.
    MonotonicDivergence,
    /// The oscillation grows under refinement.
    OscillatoryDivergence,
    /// ε21 = 0: eq. (3a) takes ln of ∞. Celik et al.: the exact solution may have been reached,
    /// or the convergence is oscillatory.
    ZeroChangeFine,
    /// ε32 = 0: eq. (3a) takes ln 0.
    ZeroChangeCoarse,
    /// ε21 = ε32 = 0: grid-independent at round-off level, nothing to extrapolate.
    NoChange,
    /// Neither the fixed-point iteration nor the bisection fallback found a finite p > 0
    /// (only for extreme ratios, e.g. |ε32/ε21| near the limits of f64).
    NoSolution,
}

impl fmt::Display for Undefined {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Undefined::MonotonicDivergence => {
                "p undefined: monotonic divergence (the change grows under refinement)"
            }
            Undefined::OscillatoryDivergence => {
                "p undefined: oscillatory divergence (the oscillation grows under refinement)"
            }
            Undefined::ZeroChangeFine => {
                "p undefined: ε21 = 0 (φ1 = φ2); exact solution reached or oscillatory convergence"
            }
            Undefined::ZeroChangeCoarse => "p undefined: ε32 = 0 (φ2 = φ3)",
            Undefined::NoChange => "p undefined: φ1 = φ2 = φ3 (no grid dependence)",
            Undefined::NoSolution => "p undefined: no finite p > 0 solves eq. (3a)",
        })
    }
}

/// How p was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Celik's fixed-point iteration of eq. (3a).
    FixedPoint,
    /// Bisection on the signed eq. (3a), used when the iteration does not contract.
    Bisection,
}

/// The apparent order and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Order {
    /// Apparent order p (dimensionless), > 0.
    pub p: f64,
    /// Iterations (fixed point) or halvings (bisection) taken.
    pub iterations: u32,
    /// How p was found.
    pub method: Method,
}

/// The behaviour of a triplet from its ratios r21, r32 (> 1) and changes ε21, ε32; `scale` is
/// max|φ_i|, against which |ε| ≤ [`ZERO_CHANGE`]·scale counts as zero. See the module
/// documentation for the thresholds ln r32/ln r21 (s = +1) and 1 (s = −1).
pub fn classify(r21: f64, r32: f64, eps21: f64, eps32: f64, scale: f64) -> Behaviour {
    let tiny = ZERO_CHANGE * scale;
    let zero21 = eps21.abs() <= tiny;
    let zero32 = eps32.abs() <= tiny;
    match (zero21, zero32) {
        (true, true) => return Behaviour::NoChange,
        (true, false) => return Behaviour::ZeroChangeFine,
        (false, true) => return Behaviour::ZeroChangeCoarse,
        (false, false) => {}
    }
    let ratio = (eps32 / eps21).abs();
    if eps32 / eps21 > 0.0 {
        if ratio > r32.ln() / r21.ln() {
            Behaviour::MonotonicConvergence
        } else {
            Behaviour::MonotonicDivergence
        }
    } else if ratio > 1.0 {
        Behaviour::OscillatoryConvergence
    } else {
        Behaviour::OscillatoryDivergence
    }
}

/// ln(r^p − s) for p > 0, r > 1, s = ±1, without overflow for large p or cancellation for
/// small p (expm1/ln_1p forms).
fn ln_power_minus_sign(p: f64, ln_r: f64, s: f64) -> f64 {
    let x = p * ln_r;
    if s > 0.0 {
        if x <= 1.0 {
            x.exp_m1().ln()
        } else {
            x + (-(-x).exp()).ln_1p()
        }
    } else {
        x + (-x).exp().ln_1p()
    }
}

/// The right-hand side of eq. (3a) before the absolute value: ln|ε32/ε21| + q(p).
fn inner(p: f64, ln_r21: f64, ln_r32: f64, ln_ratio: f64, s: f64) -> f64 {
    ln_ratio + ln_power_minus_sign(p, ln_r21, s) - ln_power_minus_sign(p, ln_r32, s)
}

/// The apparent order p of eqs. (3a)–(3c) for ratios r21, r32 > 1 and changes ε21, ε32.
///
/// Classifies first ([`classify`], `scale` = max|φ_i|) and returns the [`Undefined`] reason
/// for the non-converging behaviours. Then iterates eq. (3a) from p0 = |ln|ε32/ε21||/ln r21
/// (exact when r21 = r32) until two iterates differ by ≤ 4 ulp of max(p, 1). The iteration
/// contracts for most studies (|dp_{k+1}/dp_k| → |1 − ln r32/ln r21| for large p, so it may not
/// when r32 > r21²); when it fails, or lands on a root of the absolute value's mirror branch,
/// the signed equation p·ln r21 = ln|ε32/ε21| + q(p) is solved by bisection on (0, p_max],
/// whose bracket the classification guarantees. Accuracy: p to ≈1e-15 relative.
pub fn apparent_order(
    r21: f64,
    r32: f64,
    eps21: f64,
    eps32: f64,
    scale: f64,
) -> Result<Order, Undefined> {
    if let Some(why) = classify(r21, r32, eps21, eps32, scale).undefined() {
        return Err(why);
    }
    let (ln_r21, ln_r32) = (r21.ln(), r32.ln());
    let ln_ratio = (eps32 / eps21).abs().ln();
    let s = if eps32 / eps21 > 0.0 { 1.0 } else { -1.0 };
    let g = |p: f64| inner(p, ln_r21, ln_r32, ln_ratio, s).abs() / ln_r21;

    let mut p = ln_ratio.abs() / ln_r21;
    if !(p > 0.0 && p.is_finite()) {
        p = 1.0;
    }
    for k in 1..=MAX_ITERATIONS {
        let next = g(p);
        if !(next > 0.0 && next.is_finite()) {
            break;
        }
        if (next - p).abs() <= 4.0 * f64::EPSILON * next.max(1.0) {
            if inner(next, ln_r21, ln_r32, ln_ratio, s) >= 0.0 {
                return Ok(Order {
                    p: next,
                    iterations: k,
                    method: Method::FixedPoint,
                });
            }
            break;
        }
        p = next;
    }
    bisect(|p| p * ln_r21 - inner(p, ln_r21, ln_r32, ln_ratio, s))
}

/// Root of the signed residual f on (0, p_max]: f(0+) < 0 by the classification and f grows
/// like p·ln r32 for large p.
fn bisect(f: impl Fn(f64) -> f64) -> Result<Order, Undefined> {
    let mut lo = 0.0_f64;
    let mut hi = 1.0_f64;
    while f(hi).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        lo = hi;
        hi *= 2.0;
        if hi > 1e6 {
            return Err(Undefined::NoSolution);
        }
    }
    let mut iterations = 0;
    while hi - lo > 2.0 * f64::EPSILON * hi && iterations < 200 {
        let mid = 0.5 * (lo + hi);
        let fm = f(mid);
        if !fm.is_finite() {
            return Err(Undefined::NoSolution);
        }
        if fm > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
        iterations += 1;
    }
    let p = 0.5 * (lo + hi);
    if p > 0.0 && p.is_finite() {
        Ok(Order {
            p,
            iterations,
            method: Method::Bisection,
        })
    } else {
        Err(Undefined::NoSolution)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The changes ε21, ε32 of φ(h) = φ0 + C h^p0 (C = 0.3), formed without φ0 so that no
    /// cancellation blurs the reference.
    fn monotone(h: [f64; 3], p0: f64) -> (f64, f64) {
        let c = h.map(|h| 0.3 * h.powf(p0));
        (c[1] - c[0], c[2] - c[1])
    }

    #[test]
    fn constant_ratio_needs_no_iteration() {
        // r21 = r32 = 2, ε halves... quarters: p = ln 4 / ln 2 = 2 exactly (q = 0).
        let o = apparent_order(2.0, 2.0, 0.25, 1.0, 1.0).unwrap();
        assert!((o.p - 2.0).abs() < 1e-15, "{o:?}");
        assert_eq!(o.method, Method::FixedPoint);
        assert!(o.iterations <= 2);
    }

    #[test]
    fn fixed_point_recovers_known_orders_with_unequal_ratios() {
        for &p0 in &[0.5, 1.0, 1.7, 2.0, 3.0] {
            let h = [0.1, 0.15, 0.2]; // r21 = 1.5, r32 = 4/3
            let (e21, e32) = monotone(h, p0);
            let o = apparent_order(h[1] / h[0], h[2] / h[1], e21, e32, 2.5).unwrap();
            assert!((o.p - p0).abs() < 1e-12, "p0 {p0}: {o:?}");
        }
    }

    #[test]
    fn bisection_takes_over_when_the_iteration_does_not_contract() {
        // r32 = r21^3: |g'| → |1 − 3| = 2 for large p, the fixed point repels.
        let (r21, r32) = (1.3_f64, 1.3_f64.powi(3));
        let h = [1.0, r21, r21 * r32];
        let p0 = 2.5;
        let (e21, e32) = monotone(h, p0);
        let o = apparent_order(r21, r32, e21, e32, 10.0).unwrap();
        assert_eq!(o.method, Method::Bisection);
        assert!((o.p - p0).abs() < 1e-12, "{o:?}");
    }

    #[test]
    fn divergence_and_zero_changes_are_classified() {
        // Change grows on refinement with r = 2: monotonic divergence, never a positive p.
        assert_eq!(
            apparent_order(2.0, 2.0, 0.2, 0.1, 1.0),
            Err(Undefined::MonotonicDivergence)
        );
        assert_eq!(
            apparent_order(2.0, 2.0, 0.2, -0.1, 1.0),
            Err(Undefined::OscillatoryDivergence)
        );
        assert_eq!(
            apparent_order(2.0, 2.0, 0.0, 0.1, 1.0),
            Err(Undefined::ZeroChangeFine)
        );
        assert_eq!(
            apparent_order(2.0, 2.0, 0.1, 0.0, 1.0),
            Err(Undefined::ZeroChangeCoarse)
        );
        assert_eq!(
            apparent_order(2.0, 2.0, 0.0, 0.0, 1.0),
            Err(Undefined::NoChange)
        );
    }

    #[test]
    fn divergence_threshold_follows_the_ratio_of_logs() {
        // r21 = 2, r32 = 4: a monotone sequence with p → 0 has |ε32/ε21| → ln 4/ln 2 = 2.
        assert_eq!(
            classify(2.0, 4.0, 1.0, 1.9, 1.0),
            Behaviour::MonotonicDivergence
        );
        assert_eq!(
            classify(2.0, 4.0, 1.0, 2.1, 1.0),
            Behaviour::MonotonicConvergence
        );
        let o = apparent_order(2.0, 4.0, 1.0, 2.1, 1.0).unwrap();
        // Check the root of the signed eq. (3a) by hand: p ln 2 = ln 2.1 + ln((2^p−1)/(4^p−1)).
        let lhs = o.p * 2f64.ln();
        let rhs = 2.1f64.ln() + ((2f64.powf(o.p) - 1.0) / (4f64.powf(o.p) - 1.0)).ln();
        assert!((lhs - rhs).abs() < 1e-13, "{o:?}");
        assert!(o.p > 0.0 && o.p < 0.2);
    }

    #[test]
    fn large_orders_do_not_overflow() {
        // |ε32/ε21| = 2^600 with r = 2 ⇒ p = 600; r^p itself is 4e180, r^p·φ would be finite,
        // but the log-space q(p) never forms it.
        let o = apparent_order(2.0, 2.1, 1.0, 2f64.powi(600), 1.0).unwrap();
        assert!(o.p.is_finite() && o.p > 500.0, "{o:?}");
    }
}
