//! Koch & Hill (2001) drag from lattice-Boltzmann simulations of random sphere arrays, as
//! van Buijtenen et al. (2011) and CFDEMcoupling's `KochHillDrag` write it.

use crate::input::DragInput;
use std::f64::consts::PI;

/// The Stokes-flow resistance F₀(φ) of a random array of solid fraction φ = 1 − ε,
/// dimensionless: (1 + 3√(φ/2) + (135/64) φ ln φ + 16.14 φ)/(1 + 0.681 φ − 8.48 φ² + 8.16 φ³)
/// for φ < 0.4, 10 φ/ε³ (Carman–Kozeny) above (Koch & Hill 2001, Annu. Rev. Fluid Mech. 33,
/// 619–647; Hill, Koch & Ladd 2001; van Buijtenen et al. 2011). F₀ → 1 as φ → 0 (Stokes). Note: CFDEMcoupling writes
/// `135/64` in C++ integer arithmetic, which evaluates to 2, not 2.109; we use 135/64.
#[inline]
pub fn f0(phi: f64) -> f64 {
    if phi <= 0.0 {
        1.0
    } else if phi < 0.4 {
        (1.0 + 3.0 * (phi / 2.0).sqrt() + 135.0 / 64.0 * phi * phi.ln() + 16.14 * phi)
            / (1.0 + 0.681 * phi - 8.48 * phi * phi + 8.16 * phi * phi * phi)
    } else {
        let eps = 1.0 - phi;
        10.0 * phi / (eps * eps * eps)
    }
}

/// The inertial coefficient F₃(φ) = 0.0673 + 0.212 φ + 0.0232/ε⁵, dimensionless (Koch & Hill
/// 2001; van Buijtenen et al. 2011).
#[inline]
pub fn f3(phi: f64) -> f64 {
    let eps = 1.0 - phi;
    0.0673 + 0.212 * phi + 0.0232 / eps.powi(5)
}

/// Koch–Hill drag coefficient per particle, kg/s:
///
/// β = 3πμd ε² (F₀(φ) + ½ F₃(φ) Re), φ = 1 − ε, Re = ε ρ d |u_f − v_p|/μ
///
/// (Koch & Hill's Re uses the radius, hence ½ with the diameter). Equivalent to van Buijtenen
/// et al. (2011)'s exchange coefficient K = 18 μ ε² φ (F₀ + ½F₃Re)/d² (kg/(m³·s)) divided among
/// φ/V_p particles per unit volume, which is seed `002` eq. 13 except that the seed prints an
/// extra φ in front of F₃ Re; we follow van Buijtenen and CFDEMcoupling's `KochHillDrag`.
/// Limits: ε → 1, Re → 0 gives Stokes' 3πμd; dense Stokes flow gives the Carman–Kozeny
/// 3πμd·10φ/ε (tested).
#[inline]
pub fn beta(x: &DragInput) -> f64 {
    let eps = x.voidage;
    let phi = 1.0 - eps;
    let re = x.reynolds();
    3.0 * PI * x.mu * x.diameter * eps * eps * (f0(phi) + 0.5 * f3(phi) * re)
}
