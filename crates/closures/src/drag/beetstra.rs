//! Beetstra, van der Hoef & Kuipers (2007) drag from lattice-Boltzmann simulations, mono- and
//! polydisperse.

use crate::input::DragInput;
use std::f64::consts::PI;

/// Beetstra's normalised drag F(ε, Re) = F_d/(3πμ d U_s), dimensionless, U_s = ε|u_f − v_p|:
///
/// F = 10φ/ε² + ε²(1 + 1.5√φ) + 0.413 Re/(24ε²) · (1/ε + 3εφ + 8.4 Re^−0.343)
///     / (1 + 10^(3φ) Re^(−(1+4φ)/2)),   φ = 1 − ε, Re = ε ρ d |u_f − v_p|/μ
///
/// (Beetstra et al. 2007, AIChE J. 53, eq. 16; as CFDEMcoupling-PFM's `BeetstraDrag`). The
/// inertial term vanishes at Re = 0 (evaluated as 0 there, its limit).
#[inline]
pub fn normalised_drag(eps: f64, re: f64) -> f64 {
    let phi = 1.0 - eps;
    let stokes = 10.0 * phi / (eps * eps) + eps * eps * (1.0 + 1.5 * phi.sqrt());
    if re <= 0.0 {
        return stokes;
    }
    // one logarithm for both powers of Re; 10^(3φ) Re^(−(1+4φ)/2) as a single exponential
    let ln_re = re.ln();
    let num = 1.0 / eps + 3.0 * eps * phi + 8.4 * (-0.343 * ln_re).exp();
    let den = 1.0 + (3.0 * phi * std::f64::consts::LN_10 - 0.5 * (1.0 + 4.0 * phi) * ln_re).exp();
    stokes + 0.413 * re / (24.0 * eps * eps) * num / den
}

/// Monodisperse Beetstra drag coefficient per particle, kg/s: β = 3πμ d ε F(ε, Re), with F
/// from [`normalised_drag`] — the exchange coefficient K = 18 μ ε φ F/d² (kg/(m³·s), model A)
/// divided among φ/V_p particles per unit volume.
///
/// Seed `000` (Khawaja et al.) eq. 4–5 writes the same law as
/// β_p = V_p/(1−ε) · [A μ (1−ε)²/(ε d²) + B μ (1−ε) Re/d²]: its Stokes part (A) is identical to
/// ours; its inertial part (B) lacks the 1/ε of Beetstra's 0.413 Re/(24ε²) (and prints
/// 10^(3φ) as 10³(1−ε)); both differences are checked in the tests. We follow the paper.
/// Limits: ε → 1, Re → 0 gives Stokes' 3πμd; dense Stokes flow gives 3πμd·10φ/ε, the
/// Carman–Kozeny form (as Koch–Hill).
#[inline]
pub fn beta(x: &DragInput) -> f64 {
    3.0 * PI * x.mu * x.diameter * x.voidage * normalised_drag(x.voidage, x.reynolds())
}

/// The polydisperse correction f(y) = ε y + φ y² + 0.064 ε y³ of particle i with diameter
/// ratio y = d_i/⟨d⟩ (⟨d⟩ the local Sauter mean), dimensionless (Beetstra et al. 2007,
/// bidisperse arrays; the ε y + φ y² part is van der Hoef et al. 2005's Stokes result).
/// f(1) = 1 + 0.064ε: the fit does not reduce exactly to the monodisperse law at y = 1.
#[inline]
pub fn polydisperse_factor(eps: f64, y: f64) -> f64 {
    let phi = 1.0 - eps;
    eps * y + phi * y * y + 0.064 * eps * y * y * y
}

/// Polydisperse Beetstra drag coefficient per particle, kg/s:
/// β_i = 3πμ d_i ε F(ε, ⟨Re⟩) f(y_i), ⟨Re⟩ = ε ρ ⟨d⟩ |u_f − v_p|/μ on the local Sauter-mean
/// diameter ⟨d⟩ (`DragInput::sauter_diameter`), f from [`polydisperse_factor`].
/// (CFDEMcoupling-PFM's `BeetstraDragPoly` uses the simpler f = y + 0.064 y³.)
#[inline]
pub fn beta_polydisperse(x: &DragInput) -> f64 {
    let eps = x.voidage;
    let re_mean = eps * x.rho * x.sauter_diameter * x.slip / x.mu;
    let y = x.diameter / x.sauter_diameter;
    3.0 * PI * x.mu * x.diameter * eps * normalised_drag(eps, re_mean) * polydisperse_factor(eps, y)
}
