//! The implicit time derivatives: the coefficients of Euler and of the second-order backward
//! differentiation formula (`ddtSchemes default backward`), and the state of OpenFOAM's
//! `CrankNicolson ψ` ([`CrankNicolsonDdt0`]).
//!
//! With Δt the step, Δt₀ the previous step, OpenFOAM v1912's `backwardDdtScheme` forms
//!
//!   ∂(αU)/∂t ≈ (c αU − c₀ α°U° + c₀₀ α°°U°°)/Δt,
//!   c = 1 + Δt/(Δt + Δt₀), c₀₀ = Δt²/(Δt₀(Δt + Δt₀)), c₀ = c + c₀₀
//!
//! (for Δt₀ = Δt: (3αU − 4α°U° + α°°U°°)/(2Δt), second order; Ferziger & Perić,
//! *Computational Methods for Fluid Dynamics*, 3rd ed., §6.2.2). On the first step of a run
//! there is no second old level: OpenFOAM then takes Δt₀ = GREAT = 10¹⁵ s (`deltaT0_(vf)` while
//! `timeIndex < 2`), which makes c = c₀ = 1 and c₀₀ ≈ Δt²/10³⁰ — Euler to round-off; the same
//! numbers are used here. The same coefficients scale `ddtCorr`'s old fluxes
//! (`fvcDdtPhiCorr`) and ∂ε/∂t of the continuity equation. Euler is c = c₀ = 1, c₀₀ = 0.

use std::ops::{Add, Mul, Sub};

/// OpenFOAM's `GREAT` (`doubleScalarGREAT`), the previous step of a run's first step (s).
const GREAT: f64 = 1.0e15;

/// The three coefficients of one step (dimensionless; the derivative divides by Δt).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DdtCoeffs {
    /// Of the new level, c.
    pub c: f64,
    /// Of the old level, c₀.
    pub c0: f64,
    /// Of the old-old level, c₀₀ (0 for Euler).
    pub c00: f64,
}

impl DdtCoeffs {
    /// Implicit Euler.
    pub const EULER: DdtCoeffs = DdtCoeffs {
        c: 1.0,
        c0: 1.0,
        c00: 0.0,
    };

    /// The backward formula for step `dt` after a step `dt0` (s); `first`: the run's first step
    /// (no old-old level, Δt₀ = GREAT).
    pub fn backward(dt: f64, dt0: f64, first: bool) -> DdtCoeffs {
        let dt0 = if first { GREAT } else { dt0 };
        let c = 1.0 + dt / (dt + dt0);
        let c00 = dt * dt / (dt0 * (dt + dt0));
        DdtCoeffs {
            c,
            c0: c + c00,
            c00,
        }
    }

    /// Whether the old-old level enters (c₀₀ ≠ 0).
    pub fn uses_old_old(&self) -> bool {
        self.c00 != 0.0
    }
}

/// OpenFOAM v1912's `CrankNicolson ψ` time derivative of one field x (cell or face values):
/// the spatial terms stay implicit, and the derivative is
///
///   ddt(x) ≈ r (x − x⁰) − ψ d₀,   r = c/Δt,
///
/// with d₀ the stored estimate of the previous step's derivative (OpenFOAM's `ddt0(x)` field),
/// updated before it is used by the same recursion one level back:
///
///   d₀ ← r₀ (x⁰ − x⁰⁰) − ψ d₀,   r₀ = c₀/Δt₀.
///
/// Counting the steps of a run from 1: step 1 is Euler (c = 1, d₀ = 0 and not updated);
/// step 2 has c = 1 + ψ and r₀ = 1/Δt₀ (c₀ = 1), so d₀ = (x⁰ − x⁰⁰)/Δt₀, step 1's Euler
/// derivative; from step 3 on c = c₀ = 1 + ψ. For a linear problem ẋ = −λx this is the
/// θ-scheme with θ = 1/(1 + ψ) after one Euler step (d₀ is then exactly −λx⁰): ψ = 1 is the
/// trapezoidal rule, second order; ψ = 0 is Euler.
///
/// When the update happens: v1912's `evaluate` compares the ddt0 field's time index with the
/// run's, but `GeometricField` moves that index on only for fields that keep old times, which
/// ddt0 fields do not; so from step 2 on v1912 updates d₀ on every call of the scheme, not once
/// per step (later OpenFOAM versions set the index in `evaluate`). pisoFoam calls `fvm::ddt(U)`,
/// `fvm::ddt(k)`, `fvm::ddt(epsilon)` once per step ([`Self::begin_step`] alone) but
/// `fvc::ddtCorr(U, phi)` once per PISO corrector ([`Self::evaluate_again`] for the second
/// and later correctors).
///
/// Reference: OpenFOAM v1912 `src/finiteVolume/finiteVolume/ddtSchemes/CrankNicolsonDdtScheme`
/// (`rDtCoef_`, `rDtCoef0_`, `coef_`, `coef0_`, `offCentre_`, `evaluate`, the ddt0 field created
/// at the first call with that time index as its start) and
/// `src/OpenFOAM/fields/GeometricFields/GeometricField/GeometricField.C` (`storeOldTimes`).
/// A field whose old-old level OpenFOAM creates only when the scheme first asks for it
/// ([`Self::with_late_old_old`]: the flux φ of `ddtCorr`, whose `phi.oldTime().oldTime()` is
/// first called by the step-2 update and is then a copy of φ⁰) has x⁰⁰ = x⁰ in that update,
/// so d₀ = 0 on step 2; U, k and ε have their old-old level from step 1 on (`fvmDdt` asks for
/// it on every call).
///
/// Restarts: OpenFOAM writes d₀ at every write time as the field `ddt0(…)` and the old level
/// x⁰ as `<field>_0`; a run started from that time reads both and continues the recursion
/// with c = c₀ = 1 + ψ from its first step ([`Self::restarted`]: v1912's `DDt0Field` read
/// from a file has start index −2), which reproduces the uninterrupted run. A field whose
/// `ddt0(…)` file is missing starts as at a run's first step ([`Self::new`]: Euler first).
#[derive(Clone, Debug)]
pub struct CrankNicolsonDdt0<T> {
    /// The off-centring coefficient ψ ∈ [0, 1] (OpenFOAM's `ocCoeff`).
    psi: f64,
    /// Steps begun so far.
    steps: usize,
    /// d₀ (units of x per second); empty until the second step (d₀ = 0).
    ddt0: Vec<T>,
    /// The current step's old level x⁰.
    old0: Vec<T>,
    /// The level before, x⁰⁰.
    old00: Vec<T>,
    /// The current step (Δt, s).
    dt: f64,
    /// The step before (Δt₀, s).
    dt0: f64,
    /// x⁰⁰ = x⁰ on step 2 ([`Self::with_late_old_old`]).
    late_old_old: bool,
}

impl<T> CrankNicolsonDdt0<T>
where
    T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f64, Output = T>,
{
    /// The state before a run's first step.
    pub fn new(psi: f64) -> Self {
        CrankNicolsonDdt0 {
            psi,
            steps: 0,
            ddt0: Vec::new(),
            old0: Vec::new(),
            old00: Vec::new(),
            dt: 0.0,
            dt0: 0.0,
            late_old_old: false,
        }
    }

    /// The state of a run restarted from a written time (OpenFOAM's `DDt0Field` read from the
    /// start directory): `ddt0` the written d₀ (units of x per second), `old` the written old
    /// level x⁰ of the last step before the write (OpenFOAM's `<field>_0`), `dt0` that step
    /// (s; `None`: the same as the first step after the restart). The first step continues the
    /// recursion with c = c₀ = 1 + ψ.
    pub fn restarted(psi: f64, ddt0: Vec<T>, old: Vec<T>, dt0: Option<f64>) -> Self {
        CrankNicolsonDdt0 {
            // a restarted field is past its first two steps (OpenFOAM: start index −2)
            steps: 2,
            ddt0,
            old0: old,
            // NaN: take the first step's Δt (begin_step)
            dt: dt0.unwrap_or(f64::NAN),
            ..Self::new(psi)
        }
    }

    /// The stored derivative d₀ to write (units of x per second), `None` before the run's
    /// first step (OpenFOAM creates its `ddt0(…)` field at the first step); zero on the first
    /// step, as OpenFOAM's is.
    pub fn ddt0(&self) -> Option<Vec<T>>
    where
        T: Default,
    {
        match (self.steps, self.ddt0.is_empty()) {
            (0, _) => None,
            (_, true) => Some(vec![T::default(); self.old0.len()]),
            (_, false) => Some(self.ddt0.clone()),
        }
    }

    /// The off-centring coefficient ψ.
    pub fn psi(&self) -> f64 {
        self.psi
    }

    /// The same for a field whose old-old level appears only on step 2, as a copy of the old
    /// level (see the type's documentation).
    pub fn with_late_old_old(psi: f64) -> Self {
        CrankNicolsonDdt0 {
            late_old_old: true,
            ..Self::new(psi)
        }
    }

    /// Begins a step of `dt` seconds from the old level `old` (x⁰): updates d₀ once (from the
    /// second step on) and returns r = c/Δt (1/s). Call once per step and field.
    pub fn begin_step(&mut self, old: &[T], dt: f64) -> f64 {
        self.steps += 1;
        self.old00 = std::mem::replace(&mut self.old0, old.to_vec());
        if self.late_old_old && self.steps == 2 {
            self.old00.clone_from(&self.old0);
        }
        self.dt0 = if self.dt.is_nan() { dt } else { self.dt };
        self.dt = dt;
        self.evaluate_again();
        let c = if self.steps >= 2 { 1.0 + self.psi } else { 1.0 };
        c / dt
    }

    /// Applies the update of d₀ once more within the step (v1912's behaviour on a further call
    /// of the scheme in the same step; nothing on the first step).
    pub fn evaluate_again(&mut self) {
        if self.steps < 2 {
            return;
        }
        let c0 = if self.steps >= 3 { 1.0 + self.psi } else { 1.0 };
        let r0 = c0 / self.dt0;
        let psi = self.psi;
        if self.ddt0.is_empty() {
            self.ddt0 = (self.old0.iter().zip(&self.old00))
                .map(|(&x0, &x00)| (x0 - x00) * r0)
                .collect();
        } else {
            for ((d, &x0), &x00) in self.ddt0.iter_mut().zip(&self.old0).zip(&self.old00) {
                *d = (x0 - x00) * r0 - *d * psi;
            }
        }
    }

    /// The old-time part of the derivative's source, r x⁰ + ψ d₀, of element `i` (units of x
    /// per second; OpenFOAM's `rDtCoef*vf.oldTime() + offCentre_(ddt0)`), for the step begun
    /// last with rate `r` and old value `old` (x⁰ᵢ).
    pub fn old_part(&self, i: usize, r: f64, old: T) -> T {
        match self.ddt0.get(i) {
            Some(&d) => old * r + d * self.psi,
            None => old * r,
        }
    }

    /// The explicit derivative r (x − x⁰) − ψ d₀ of element `i` (units of x per second).
    pub fn explicit(&self, i: usize, r: f64, new: T, old: T) -> T {
        match self.ddt0.get(i) {
            Some(&d) => (new - old) * r - d * self.psi,
            None => (new - old) * r,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backward_is_bdf2_at_constant_step_and_euler_first() {
        let k = DdtCoeffs::backward(0.1, 0.1, false);
        assert!((k.c - 1.5).abs() < 1e-15 && (k.c0 - 2.0).abs() < 1e-15);
        assert!((k.c00 - 0.5).abs() < 1e-15);
        let first = DdtCoeffs::backward(1e-3, 1e-3, true);
        assert_eq!((first.c, first.c0), (1.0, 1.0));
        assert!(first.c00 < 1e-35);
        // exact for a quadratic in time: u = t², steps 0.1 then 0.2
        let (t00, t0, t) = (0.0f64, 0.2, 0.3);
        let k = DdtCoeffs::backward(t - t0, t0 - t00, false);
        let d = (k.c * t * t - k.c0 * t0 * t0 + k.c00 * t00 * t00) / (t - t0);
        assert!((d - 2.0 * t).abs() < 1e-12, "{d}");
    }

    /// ẋ = −λx with `CrankNicolson ψ`: one Euler step, then the θ-scheme with θ = 1/(1 + ψ)
    /// (closed form of the recursion, see [`CrankNicolsonDdt0`]); ψ = 1 is second order.
    #[test]
    fn crank_nicolson_is_the_theta_scheme_after_an_euler_step() {
        let run = |psi: f64, lambda: f64, dt: f64, steps: usize| {
            let mut s = CrankNicolsonDdt0::<f64>::new(psi);
            let mut x = 1.0f64;
            for _ in 0..steps {
                let r = s.begin_step(&[x], dt);
                // r x − (r x⁰ + ψ d₀) = −λ x
                x = s.old_part(0, r, x) / (r + lambda);
            }
            x
        };
        for psi in [0.0, 0.5, 0.9, 1.0] {
            let (lambda, dt, n) = (3.0f64, 0.01f64, 50i32);
            let theta = 1.0 / (1.0 + psi);
            let z = lambda * dt;
            let g = (1.0 - (1.0 - theta) * z) / (1.0 + theta * z);
            let closed = 1.0 / (1.0 + z) * g.powi(n - 1);
            let x = run(psi, lambda, dt, n as usize);
            assert!((x / closed - 1.0).abs() < 1e-13, "ψ {psi}: {x} vs {closed}");
        }
        // ψ = 1: the error against e^(−λT) falls 4× per halving of Δt
        let err = |n: usize| (run(1.0, 3.0, 1.0 / n as f64, n) - (-3.0f64).exp()).abs();
        let order = (err(40) / err(80)).log2();
        assert!((order - 2.0).abs() < 0.1, "order {order}");
    }
}
