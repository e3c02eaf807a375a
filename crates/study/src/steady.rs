//! When a frozen-bed run has reached its steady state.
//!
//! The monitored quantities (the pressure drop and the total drag on the bed) are recorded
//! after every fluid step. The run is steady at step k when, for each quantity q, the means
//! over the last two windows of `window` steps agree:
//! |q̄_(k−w+1..k) − q̄_(k−2w+1..k−w)| ≤ tolerance · max(|q̄_(k−w+1..k)|, floor),
//! and the run's value is then the mean over the last window ([`SteadyMonitor::mean`]).
//! `floor` (same unit as q) keeps a quantity that is zero at steady state (no flow) from never
//! converging.
//!
//! Why window means and not the change from one step to the next: the PISO solution of a
//! frozen bed settles into a bounded odd–even oscillation of about 1e-4 of Δp (measured on the
//! binary bed: ±0.003 Pa of 68 Pa at Δx = 3 d₃₂, period two steps, not decaying over 4000
//! steps), far below the cell-size effects studied but above any sensible per-step
//! tolerance. Means over a window (even, so that a period-two oscillation cancels) converge
//! like the underlying drift; a window of several steps also keeps a quantity passing through
//! a turning point of a slower oscillation from looking steady. The amplitude that remains is
//! reported ([`SteadyMonitor::fluctuation`]).
//!
//! For an exponential approach q_k = q_∞ + a·e^(−k/τ), the difference of successive window
//! means is a·e^(−(k−w+1)/τ)(e^(w/τ) − 1)·S/w with S = Σ_(j<w) e^(−j/τ) (tested); the mean is
//! then within about tolerance·τ/w·|q| of q_∞.

use serde::Serialize;

/// The criterion's parameters (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SteadyCriterion {
    /// Largest accepted relative difference of successive window means.
    pub tolerance: f64,
    /// Steps per window (≥ 1; even values cancel an odd–even oscillation).
    pub window: usize,
    /// Absolute floor of the denominator, per quantity unit.
    pub floor: f64,
}

impl Default for SteadyCriterion {
    /// 1e-5 over windows of 10 steps: the mean is then within ~1e-4 of its limit for
    /// relaxation times up to 100 steps, far below the cell-size effects studied.
    fn default() -> Self {
        SteadyCriterion {
            tolerance: 1e-5,
            window: 10,
            floor: 1e-12,
        }
    }
}

/// The history of the monitored quantities and the verdict.
#[derive(Clone, Debug, Default)]
pub struct SteadyMonitor {
    history: Vec<Vec<f64>>,
}

impl SteadyMonitor {
    /// An empty history.
    pub fn new() -> SteadyMonitor {
        SteadyMonitor::default()
    }

    /// Records the quantities of one step (the same number every step).
    pub fn push(&mut self, values: &[f64]) {
        self.history.push(values.to_vec());
    }

    /// Steps recorded.
    pub fn len(&self) -> usize {
        self.history.len()
    }

    /// True before the first step.
    pub fn is_empty(&self) -> bool {
        self.history.is_empty()
    }

    /// The mean of each quantity over the `w` steps ending at `end` (exclusive).
    fn window_mean(&self, end: usize, w: usize) -> Vec<f64> {
        let rows = &self.history[end - w..end];
        let n = rows[0].len();
        (0..n)
            .map(|q| rows.iter().map(|r| r[q]).sum::<f64>() / w as f64)
            .collect()
    }

    /// The mean of each quantity over the last window (over all steps if fewer); empty
    /// before the first step.
    pub fn mean(&self, c: &SteadyCriterion) -> Vec<f64> {
        let n = self.history.len();
        if n == 0 {
            return Vec::new();
        }
        self.window_mean(n, c.window.max(1).min(n))
    }

    /// The largest relative difference of the last two window means over the quantities
    /// (infinite before two windows or with a non-finite value).
    pub fn last_change(&self, c: &SteadyCriterion) -> f64 {
        let n = self.history.len();
        let w = c.window.max(1);
        if n < 2 * w {
            return f64::INFINITY;
        }
        let (a, b) = (self.window_mean(n - w, w), self.window_mean(n, w));
        a.iter()
            .zip(&b)
            .map(|(&x, &y)| {
                let r = (y - x).abs() / y.abs().max(c.floor);
                if r.is_finite() {
                    r
                } else {
                    f64::INFINITY
                }
            })
            .fold(0.0, f64::max)
    }

    /// The largest (max − min)/|mean| of any quantity over the last window: what remains of
    /// the oscillation at the end.
    pub fn fluctuation(&self, c: &SteadyCriterion) -> f64 {
        let n = self.history.len();
        if n == 0 {
            return f64::INFINITY;
        }
        let w = c.window.max(1).min(n);
        let mean = self.window_mean(n, w);
        (0..mean.len())
            .map(|q| {
                let vals = self.history[n - w..].iter().map(|r| r[q]);
                let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                });
                (hi - lo) / mean[q].abs().max(c.floor)
            })
            .fold(0.0, f64::max)
    }

    /// True when the last two window means agree within the tolerance (module docs).
    pub fn is_steady(&self, c: &SteadyCriterion) -> bool {
        self.last_change(c) <= c.tolerance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exponential_approach_is_steady_where_the_closed_form_says() {
        // q_k = 10 + 3 e^(−k/τ): successive window means differ by
        // 3 e^(−(k−w+1)/τ) (e^(w/τ) − 1) S / w with S = Σ_{j<w} e^(−j/τ) (module docs), a
        // decreasing function of k: the criterion first holds at the first k ≥ 2w − 1 where
        // that is ≤ tol · (window mean).
        let (tau, tol, w) = (7.0_f64, 1e-6, 4);
        let c = SteadyCriterion {
            tolerance: tol,
            window: w,
            floor: 1e-12,
        };
        let q = |k: usize| 10.0 + 3.0 * (-(k as f64) / tau).exp();
        let s: f64 = (0..w).map(|j| (-(j as f64) / tau).exp()).sum();
        let diff = |k: usize| {
            3.0 * (-((k + 1 - w) as f64) / tau).exp() * ((w as f64 / tau).exp() - 1.0) * s
                / w as f64
        };
        let mean = |k: usize| (k + 1 - w..=k).map(q).sum::<f64>() / w as f64;
        let expect = (2 * w - 1..400)
            .find(|&k| diff(k) <= tol * mean(k))
            .unwrap();
        let mut m = SteadyMonitor::new();
        let mut fired = None;
        for k in 0..400 {
            m.push(&[q(k), -2.0 * q(k)]);
            if m.is_steady(&c) {
                fired = Some(k);
                break;
            }
        }
        assert_eq!(fired, Some(expect));
        // The reported mean is within tol τ / w of the limit (module docs), and the
        // remaining fluctuation is the last window's spread.
        assert!((m.mean(&c)[0] - 10.0) / 10.0 < tol * tau / w as f64 * 2.0);
        let f = (q(expect + 1 - w) - q(expect)) / mean(expect);
        assert!((m.fluctuation(&c) - f).abs() < 1e-12);
    }

    #[test]
    fn an_odd_even_oscillation_around_a_limit_is_steady() {
        // q_k = 68 + 0.003 (−1)^k + e^(−k/10): per-step changes stay near 1e-4 forever, the
        // means of even windows converge.
        let c = SteadyCriterion {
            tolerance: 1e-6,
            window: 10,
            floor: 1e-12,
        };
        let q = |k: usize| {
            68.0 + 0.003 * if k.is_multiple_of(2) { 1.0 } else { -1.0 } + (-(k as f64) / 10.0).exp()
        };
        let mut m = SteadyMonitor::new();
        let mut fired = None;
        for k in 0..1000 {
            m.push(&[q(k)]);
            if m.is_steady(&c) {
                fired = Some(k);
                break;
            }
        }
        let k = fired.expect("steady");
        assert!(k < 300, "{k}");
        assert!((m.mean(&c)[0] - 68.0).abs() < 1e-4);
        assert!((m.fluctuation(&c) - 0.006 / 68.0).abs() < 1e-6);
    }

    #[test]
    fn a_slow_oscillation_is_not_steady() {
        // q = 1 + 0.5 cos(k/20): successive window means differ by ~1e-2 or more except where
        // they cross, and never both steady for a loose tolerance.
        let c = SteadyCriterion {
            tolerance: 1e-4,
            window: 10,
            floor: 1e-12,
        };
        let mut m = SteadyMonitor::new();
        for k in 0..300 {
            m.push(&[1.0 + 0.5 * (k as f64 / 20.0).cos()]);
            assert!(!m.is_steady(&c), "step {k}");
        }
    }

    #[test]
    fn zero_and_non_finite_values() {
        let c = SteadyCriterion::default();
        let mut m = SteadyMonitor::new();
        assert_eq!(m.last_change(&c), f64::INFINITY);
        assert!(m.mean(&c).is_empty());
        for _ in 0..20 {
            m.push(&[0.0]);
        }
        assert!(
            m.is_steady(&c),
            "a constant zero is steady through the floor"
        );
        m.push(&[f64::NAN]);
        assert!(!m.is_steady(&c));
        assert_eq!(m.last_change(&c), f64::INFINITY);
    }
}
