//! Wen & Yu (1966) drag for dilute suspensions, in the per-particle form of Gidaspow (1994).

use crate::input::DragInput;

/// Reynolds number above which the standard drag curve is flat (C_d = 0.44).
pub const RE_NEWTON: f64 = 1000.0;

/// C_d·|u_f − v_p| of the standard drag curve used by Wen–Yu and Schiller–Naumann, m/s:
/// C_d = 24/Re (1 + 0.15 Re^0.687) for Re < 1000, 0.44 above (Schiller & Naumann 1933).
/// Returned multiplied by the slip (`slip_per_re` = slip/Re = μ/(ρ_eff d)) so that it stays
/// finite at zero slip: C_d·slip = 24·slip_per_re·(1 + 0.15 Re^0.687). Re^0.687 is evaluated
/// as exp(0.687 ln Re) (within 1e-15 relative of `powf`, a quarter cheaper; 0 at Re = 0).
#[inline]
pub(crate) fn cd_times_slip(re: f64, slip: f64, slip_per_re: f64) -> f64 {
    if re < RE_NEWTON {
        24.0 * slip_per_re * (1.0 + 0.15 * (0.687 * re.ln()).exp())
    } else {
        0.44 * slip
    }
}

/// Wen–Yu drag coefficient per particle, kg/s:
///
/// β = (3/4) C_d ρ |u_f − v_p| V_p ε^−1.65 / d, C_d = 24/Re (1 + 0.15 Re^0.687) (Re < 1000),
/// 0.44 (Re ≥ 1000), Re = ε ρ d |u_f − v_p|/μ.
///
/// This is Gidaspow's K = (3/4) C_d ε (1−ε) ρ |u_f − v_p| ε^−2.65 / d (kg/(m³·s), model A)
/// divided among (1−ε)/V_p particles per unit volume (β = K V_p/(1−ε)); seed `001` eq. 6
/// prints (1−ε) instead of ε(1−ε), i.e. the model-B form K/ε. As ε → 1 it becomes the
/// single-sphere drag (π/8) C_d ρ d² |u_f − v_p| (Schiller–Naumann) and at Re → 0 Stokes'
/// 3πμd (tested). ε^−1.65 is evaluated as exp(−1.65 ln ε).
#[inline]
pub fn beta(x: &DragInput) -> f64 {
    let re = x.reynolds();
    let cd_slip = cd_times_slip(re, x.slip, x.mu / (x.voidage * x.rho * x.diameter));
    0.75 * cd_slip * x.rho * x.particle_volume() * (-1.65 * x.voidage.ln()).exp() / x.diameter
}
