//! Ergun (1952) packed-bed drag, in the per-particle form of Gidaspow (1994).

use crate::input::DragInput;

/// Ergun drag coefficient per particle, kg/s:
///
/// β = V_p · [150 (1−ε) μ / (ε d²) + 1.75 ρ |u_f − v_p| / d],
///
/// i.e. Gidaspow's exchange coefficient K = 150 (1−ε)² μ/(ε d²) + 1.75 (1−ε) ρ |u_f − v_p|/d
/// (kg/(m³·s), for a fluid momentum equation with −ε∇p, model A) divided among the
/// (1−ε)/V_p particles per unit volume: β = K V_p/(1−ε) (seed `001`, eq. 5).
///
/// Consistency: with n = (1−ε)/V_p particles per m³ and interstitial slip u = U_s/ε, n β u
/// equals ε times Ergun's Δp/L = 150 μ (1−ε)² U_s/(ε³ d²) + 1.75 ρ (1−ε) U_s²/(ε³ d) exactly
/// (tested). Seed `001` eq. 6 prints the dense branch as 150(1−ε)²μ/d² + 1.75(1−ε)ρ|u|/(εd):
/// that matches neither Gidaspow's K nor its model-B form K/ε, so we follow Gidaspow (and
/// CFDEMcoupling's `GidaspowDrag`, which uses this K). Valid for dense beds (ε ≲ 0.8);
/// diverges as 1/ε for ε → 0 (use a voidage floor).
#[inline]
pub fn beta(x: &DragInput) -> f64 {
    let d = x.diameter;
    let eps = x.voidage;
    x.particle_volume() * (150.0 * (1.0 - eps) * x.mu / (eps * d * d) + 1.75 * x.rho * x.slip / d)
}
