//! `model hertz`: the Hertz normal force with the viscous damping LIGGGHTS derives from the
//! coefficient of restitution, plus the stiffnesses the tangential and rolling models reuse.
//!
//! With Y*, G* and β from [`PairCoeffs`](crate::material::PairCoeffs), effective radius R*
//! (R for a wall) and effective mass m* (m for a wall), overlap δ:
//! - Sₙ = 2Y*√(R*δ), Sₜ = 8G*√(R*δ) (N/m);
//! - kₙ = (4/3)Y*√(R*δ) (N/m), so the elastic force kₙδ = (4/3)Y*√R* δ^{3/2} is Hertz's
//!   (Johnson, *Contact Mechanics*, 1985, eq. 4.23);
//! - γₙ = −2√(5/6) β √(Sₙ m*), γₜ = −2√(5/6) β √(Sₜ m*) (kg/s, ≥ 0 since β ≤ 0);
//! - Fₙ = kₙδ − γₙ vₙ with vₙ = (vᵢ − vⱼ)·n (negative while approaching).
//!
//! These are the Tsuji/Antypov–Elliott forms used by LIGGGHTS 3.x (`normal_model_hertz`), here
//! written from its documentation (`pair gran model hertz`) and checked against Hertz's contact
//! time and the restitution in `tests/analytic.rs`.

/// √(5/6), the damping prefactor of the Hertz–Mindlin dashpot.
pub const SQRT_FIVE_SIXTHS: f64 = 0.912_870_929_175_276_9;

/// Stiffnesses and damping of one Hertz contact at overlap δ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzCoeffs {
    /// Normal stiffness kₙ (N/m).
    pub kn: f64,
    /// Tangential stiffness kₜ = Sₜ (N/m).
    pub kt: f64,
    /// Normal damping γₙ (kg/s, ≥ 0).
    pub gamma_n: f64,
    /// Tangential damping γₜ (kg/s, ≥ 0; 0 with `tangential_damping off`).
    pub gamma_t: f64,
}

/// The coefficients at overlap `deltan` (m) for effective radius `reff` (m), mass `meff` (kg),
/// moduli `y_eff`, `g_eff` (Pa) and damping ratio `beta` (≤ 0).
#[inline]
pub fn hertz_coeffs(
    deltan: f64,
    reff: f64,
    meff: f64,
    y_eff: f64,
    g_eff: f64,
    beta: f64,
    tangential_damping: bool,
) -> HertzCoeffs {
    let sqrtval = (reff * deltan).sqrt();
    let sn = 2.0 * y_eff * sqrtval;
    let st = 8.0 * g_eff * sqrtval;
    let gamma_n = -2.0 * SQRT_FIVE_SIXTHS * beta * (sn * meff).sqrt();
    let gamma_t = if tangential_damping {
        -2.0 * SQRT_FIVE_SIXTHS * beta * (st * meff).sqrt()
    } else {
        0.0
    };
    HertzCoeffs {
        kn: 4.0 / 3.0 * y_eff * sqrtval,
        kt: st,
        gamma_n,
        gamma_t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elastic_force_is_hertz() {
        // F = 4/3 Y* √R δ^1.5 (Johnson 1985, eq. 4.23); R = 1 mm, δ = 10 µm, Y* = 1e7 Pa:
        // 4/3 · 1e7 · √1e-3 · 1e-7.5 = 4/3 · 1e7 · 1e-9 = 1.3333e-2 N.
        let c = hertz_coeffs(1e-5, 1e-3, 1e-3, 1e7, 4e6, 0.0, true);
        assert!((c.kn * 1e-5 - 4.0 / 3.0 * 1e-2).abs() < 1e-15);
        assert_eq!(c.gamma_n, 0.0);
        assert!((c.kt - 8.0 * 4e6 * 1e-4).abs() < 1e-9);
    }
}
