//! Di Felice (1994) drag with a Reynolds-dependent voidage exponent.

use crate::input::DragInput;
use std::f64::consts::PI;

/// Di Felice's voidage exponent χ = 3.7 − 0.65 exp(−(1.5 − log₁₀ Re)²/2), dimensionless
/// (Di Felice 1994, Int. J. Multiphase Flow 20, 153–159). χ → 3.7 for Re → 0 and Re → ∞,
/// minimum 3.05 at Re = 10^1.5.
#[inline]
pub fn exponent(re: f64) -> f64 {
    let l = 1.5 - re.log10();
    3.7 - 0.65 * (-0.5 * l * l).exp()
}

/// Di Felice drag coefficient per particle, kg/s:
///
/// β = (π/8) C_d ρ d² ε^(2−χ) |u_f − v_p|, C_d = (0.63 + 4.8/√Re)² (Dallavalle),
/// Re = ε ρ d |u_f − v_p|/μ, χ from [`exponent`]
/// (Di Felice 1994, written on the interstitial slip as CFDEMcoupling's
/// `DiFeliceDrag`: ε²|u|u is the superficial |U|U). Limits: ε = 1 gives the single-sphere
/// Dallavalle drag; at Re → 0 that is (0.96) 3πμd — Dallavalle's 4.8² = 23.04 instead of 24.
/// C_d·|u| is evaluated as (0.63√|u| + 4.8√(μ/(ερd)))², finite at zero slip.
#[inline]
pub fn beta(x: &DragInput) -> f64 {
    let re = x.reynolds();
    let a = 0.63 * x.slip.sqrt() + 4.8 * (x.mu / (x.voidage * x.rho * x.diameter)).sqrt();
    let cd_slip = a * a;
    PI / 8.0 * cd_slip * x.rho * x.diameter * x.diameter * x.voidage.powf(2.0 - exponent(re))
}
