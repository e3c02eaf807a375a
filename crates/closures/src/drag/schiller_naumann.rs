//! Schiller & Naumann (1933): drag on a single sphere, no voidage correction.

use super::wen_yu::cd_times_slip;
use crate::input::DragInput;

/// Schiller–Naumann drag coefficient per particle, kg/s:
///
/// β = (π/8) C_d ρ d² |u_f − v_p|, C_d = 24/Re (1 + 0.15 Re^0.687) for Re < 1000, 0.44 for
/// Re ≥ 1000, Re = ρ d |u_f − v_p|/μ (no ε: an isolated sphere; CFDEMcoupling's
/// `SchillerNaumannDrag`). That is F = ½ C_d ρ (π d²/4) |u|u. Limits: Re → 0 gives Stokes'
/// 3πμd exactly; the curve is within about 5 % of the standard drag curve up to Re = 1000
/// (Clift, Grace & Weber 1978), with a 0.4 % jump to the 0.44 branch at Re = 1000.
#[inline]
pub fn beta(x: &DragInput) -> f64 {
    let re = x.reynolds_single();
    let cd_slip = cd_times_slip(re, x.slip, x.mu / (x.rho * x.diameter));
    std::f64::consts::PI / 8.0 * cd_slip * x.rho * x.diameter * x.diameter
}
