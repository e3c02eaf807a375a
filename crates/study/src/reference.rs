//! What the total drag on a frozen bed should be, from the measured bed alone.
//!
//! Two references, both for a bed of uniform voidage ε̄ (the measured mean), height L, cross
//! section A and superficial velocity U (interstitial u = U/ε̄), model A:
//!
//! * **Gidaspow on the measured bed** — the drag law the simulation uses (seed 001 eq. 5–6,
//!   [`closures::drag::gidaspow::beta`], each particle with its own diameter d_i). In a uniform
//!   steady bed, model A's momentum balance is ε̄ ∇p = −Ksl u with Ksl = Σβ_i/(A L), so
//!   Δp = Σ_i β_i(ε̄, d_i, u) u / (A ε̄)  (Pa).
//!   The total fluid force on the particles (drag plus the pressure-gradient force
//!   (1 − ε̄) A Δp) is then A Δp. This is what the simulations converge to when the cells are
//!   large enough for the voidage to be uniform across them; it is the reference of the errors
//!   the study reports.
//! * **Ergun with the Sauter diameter** — Ergun (1952)'s Δp/L = 150 μ(1−ε̄)²U/(ε̄³d₃₂²) +
//!   1.75 ρ(1−ε̄)U²/(ε̄³d₃₂) ([`runner::reference::ergun_pressure_gradient`]), the usual
//!   correlation for mixtures. Per particle, Gidaspow's viscous term sums V_i/d_i², Ergun's
//!   uses V/d₃₂²; by Cauchy–Schwarz ΣV_i/d_i² ≥ V/d₃₂² (equal for one size), so for a binary
//!   mixture the model's own drag lies above Ergun–Sauter (for 30 % fines by mass at a size
//!   ratio 2: +12 % in the viscous term); the inertial terms agree (ΣV_i/d_i = V/d₃₂).
//!
//! The minimum fluidisation velocity U_mf is where Δp reaches the bed's buoyant weight per
//! area, (m − ρ V_p) g / A.

use closures::drag::gidaspow;
use closures::input::DragInput;
use runner::reference::{ergun_pressure_gradient, ergun_velocity_for};
use serde::Serialize;

/// Fluid properties, SI.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FluidProps {
    /// Density ρ, kg/m³.
    pub rho: f64,
    /// Dynamic viscosity μ, Pa·s.
    pub mu: f64,
}

/// Gidaspow's Δp over a uniform bed (module docs), Pa: `diameters` of every particle (m),
/// mean voidage `eps`, superficial velocity `u_sup` (m/s), cross-section `area` (m²).
pub fn gidaspow_pressure_drop(
    diameters: &[f64],
    eps: f64,
    u_sup: f64,
    area: f64,
    fluid: FluidProps,
) -> f64 {
    let u = u_sup / eps;
    let beta: f64 = diameters
        .iter()
        .map(|&d| {
            gidaspow::beta(
                &DragInput::new(eps, d, u.abs(), fluid.rho, fluid.mu),
                gidaspow::DEFAULT_SWITCH_VOIDAGE,
            )
        })
        .sum();
    beta * u / (area * eps)
}

/// Ergun's Δp with the Sauter diameter `d32` over a bed of height `height` (module docs), Pa.
pub fn ergun_pressure_drop(u_sup: f64, eps: f64, d32: f64, height: f64, fluid: FluidProps) -> f64 {
    ergun_pressure_gradient(u_sup, eps, d32, fluid.mu, fluid.rho) * height
}

/// U_mf (m/s) of both references for a bed whose buoyant weight per area is `weight` (Pa):
/// `(ergun, gidaspow)`. Ergun's is the closed-form root; Gidaspow's is found by bisection to
/// 1e-12 relative (its Δp grows monotonically with U).
pub fn minimum_fluidisation(
    weight: f64,
    diameters: &[f64],
    eps: f64,
    d32: f64,
    height: f64,
    area: f64,
    fluid: FluidProps,
) -> (f64, f64) {
    let ergun = ergun_velocity_for(weight, height, eps, d32, fluid.mu, fluid.rho);
    let dp = |u: f64| gidaspow_pressure_drop(diameters, eps, u, area, fluid);
    let (mut lo, mut hi) = (0.0, ergun.max(1e-9));
    let mut grow = 0;
    while dp(hi) < weight && grow < 100 {
        hi *= 2.0;
        grow += 1;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if dp(mid) < weight {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    (ergun, 0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const AIR: FluidProps = FluidProps {
        rho: 1.2,
        mu: 1.8e-5,
    };

    /// N spheres of diameter d filling a bed of voidage ε, height L: A = N V / ((1−ε) L).
    fn area(n: usize, d: f64, eps: f64, l: f64) -> f64 {
        n as f64 * PI * d.powi(3) / 6.0 / ((1.0 - eps) * l)
    }

    #[test]
    fn one_size_gidaspow_is_ergun() {
        let (d, eps, l, n) = (0.5e-3, 0.4, 0.01, 1000);
        let a = area(n, d, eps, l);
        for u in [0.01, 0.1, 0.3] {
            let g = gidaspow_pressure_drop(&vec![d; n], eps, u, a, AIR);
            let e = ergun_pressure_drop(u, eps, d, l, AIR);
            assert!((g - e).abs() < 1e-12 * e, "{g} vs {e}");
        }
    }

    #[test]
    fn binary_gidaspow_by_hand() {
        // Equal volumes of d = 2a and d = a at ε = 0.4, Stokes limit (u → 0): the viscous
        // term per solid volume is 150 μ (1−ε)/(ε d²) per particle size, so
        // Δp = 150 μ (1−ε)² u_sup /(ε³) · (½/d₁² + ½/d₂²) · L, against Ergun–Sauter's
        // 1/d₃₂² with d₃₂ = 1/(½/d₁ + ½/d₂).
        let (a, eps, l) = (0.25e-3, 0.4, 0.01);
        let (n1, n2) = (100usize, 800usize); // equal volumes: 100 (2a)³ = 800 a³
        let mut d = vec![2.0 * a; n1];
        d.extend(vec![a; n2]);
        let vs: f64 = d.iter().map(|x| PI * x * x * x / 6.0).sum();
        let area = vs / ((1.0 - eps) * l);
        let u = 1e-6;
        let g = gidaspow_pressure_drop(&d, eps, u, area, AIR);
        let visc =
            |inv_d2: f64| 150.0 * AIR.mu * (1.0 - eps).powi(2) * u / eps.powi(3) * inv_d2 * l;
        let hand = visc(0.5 / (4.0 * a * a) + 0.5 / (a * a));
        assert!((g - hand).abs() < 1e-6 * hand, "{g} vs {hand}");
        let d32 = 1.0 / (0.5 / (2.0 * a) + 0.5 / a);
        let e = ergun_pressure_drop(u, eps, d32, l, AIR);
        // (½/4 + ½) a⁻² = 0.625 a⁻² against (0.75)² a⁻² = 0.5625 a⁻²: ratio 10/9.
        assert!((g / e - 0.625 / 0.5625).abs() < 1e-5, "{}", g / e);
    }

    #[test]
    fn minimum_fluidisation_balances_the_weight() {
        let (d, eps, l, n) = (0.5e-3, 0.4, 0.01, 2000);
        let a = area(n, d, eps, l);
        let w = (2500.0 - 1.2) * (1.0 - eps) * l * 9.81;
        let (ue, ug) = minimum_fluidisation(w, &vec![d; n], eps, d, l, a, AIR);
        assert!((ergun_pressure_drop(ue, eps, d, l, AIR) - w).abs() < 1e-9 * w);
        assert!((ue - ug).abs() < 1e-10 * ue, "{ue} {ug}");
    }
}
