//! Standard wall functions of the k–ε model, as OpenFOAM v1912's `nutkWallFunction`,
//! `kqRWallFunction` and `epsilonWallFunction` define them (Launder & Spalding 1974, Comput.
//! Methods Appl. Mech. Eng. 3, 269–289: the log law u⁺ = ln(E y⁺)/κ with the friction velocity
//! from the wall cell's k, u_τ = Cμ^¼ √k, valid for 30 ≲ y⁺ ≲ 300; below y⁺_lam the viscous
//! sublayer).
//!
//! Per wall face with owner cell P at wall distance y (m; OpenFOAM's `nearWallDist`, the
//! distance to the nearest face of the patch around it, [`super::near_wall`]), ν (m²/s):
//!
//! * y⁺ = Cμ^¼ y √k_P / ν;
//! * y⁺_lam: the intersection of u⁺ = y⁺ and the log law, y⁺ = ln(E y⁺)/κ, found by OpenFOAM's
//!   ten fixed-point steps from 11 (11.53 for κ 0.41, E 9.8);
//! * νt_w = ν (y⁺ κ / ln(E y⁺) − 1) for y⁺ > y⁺_lam, else 0 (`nutkWallFunction`): the face
//!   viscosity that makes the wall shear stress (ν + νt_w) |∂U/∂n| equal the log law's;
//! * k: zero gradient (`kqRWallFunction`);
//! * in the wall cell (`epsilonWallFunction`): ε_P = Cμ^¾ k_P^{3/2} / (κ y) and the production
//!   G_P = (νt_w + ν) |∂U/∂n|_w Cμ^¼ √k_P / (κ y), each averaged over the cell's wall faces
//!   (weight 1/number of its wall faces); with `lowReCorrection` and y⁺ < y⁺_lam,
//!   ε_P = 2 k_P ν / y² and G_P = 0. The ε equation keeps ε_P in those cells (its rows are
//!   replaced by ε = ε_P, OpenFOAM's `fvMatrix::setValues`) and the k equation takes G_P.

use super::scalar_bc::LogLaw;

/// y⁺ at which the viscous sublayer u⁺ = y⁺ meets the log law (dimensionless), computed as
/// OpenFOAM's `nutWallFunction::yPlusLam` does: y ← ln(max(E y, 1))/κ ten times from y = 11.
pub fn y_plus_lam(kappa: f64, e: f64) -> f64 {
    let mut y = 11.0;
    for _ in 0..10 {
        y = (e * y).max(1.0).ln() / kappa;
    }
    y
}

/// y⁺ = Cμ^¼ y √k / ν of a wall cell: wall distance `y` (m), its `k` (m²/s²), `nu` (m²/s).
pub fn y_plus(law: &LogLaw, y: f64, k: f64, nu: f64) -> f64 {
    law.cmu25() * y * k.sqrt() / nu
}

/// The wall value of νt (m²/s) of `nutkWallFunction` for a wall cell with `y`, `k`, `nu`.
pub fn nut_wall(law: &LogLaw, y: f64, k: f64, nu: f64) -> f64 {
    let yp = y_plus(law, y, k, nu);
    if law.y_plus_lam() < yp {
        nu * (yp * law.kappa() / (law.e() * yp).ln() - 1.0)
    } else {
        0.0
    }
}

/// One wall face's contribution (weight `w` = 1/number of wall faces of the cell) to the
/// wall cell's ε (m²/s³) and G (m²/s³): `nut_w` the face's νt, `mag_grad_u` = |∂U/∂n| at the
/// face (1/s).
#[allow(clippy::too_many_arguments)]
pub fn epsilon_and_g(
    law: &LogLaw,
    low_re: bool,
    w: f64,
    y: f64,
    k: f64,
    nu: f64,
    nut_w: f64,
    mag_grad_u: f64,
) -> (f64, f64) {
    let (cmu25, kappa) = (law.cmu25(), law.kappa());
    let yp = y_plus(law, y, k, nu);
    if low_re && yp < law.y_plus_lam() {
        return (w * 2.0 * k * nu / (y * y), 0.0);
    }
    let eps = w * law.cmu75() * k.powf(1.5) / (kappa * y);
    let g = w * (nut_w + nu) * mag_grad_u * cmu25 * k.sqrt() / (kappa * y);
    (eps, g)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_plus_lam_solves_the_sublayer_log_law_intersection() {
        let law = LogLaw::default();
        let y = y_plus_lam(law.kappa(), law.e());
        assert_eq!(y, law.y_plus_lam());
        // Ten fixed-point steps converge to ~1e-6 (contraction 1/(κ y) ≈ 0.2 per step).
        assert!((y - (law.e() * y).ln() / law.kappa()).abs() < 1e-5, "{y}");
        assert!((y - 11.53).abs() < 0.01, "{y}");
    }

    /// In the log layer the wall function reproduces the log law's wall shear stress:
    /// with k = u_τ²/√Cμ (equilibrium) and the cell velocity of the log law,
    /// U_P = u_τ ln(E y⁺)/κ, the stress (ν + νt_w) U_P/y equals u_τ².
    #[test]
    fn nut_wall_gives_the_log_law_shear_stress() {
        let law = LogLaw::default();
        let (nu, u_tau) = (1e-5, 0.05);
        for y in [0.005, 0.02, 0.05] {
            let k = u_tau * u_tau / law.cmu().sqrt();
            let yp = y * u_tau / nu;
            assert!((y_plus(&law, y, k, nu) - yp).abs() < 1e-9 * yp);
            let u_p = u_tau * (law.e() * yp).ln() / law.kappa();
            let tau = (nu + nut_wall(&law, y, k, nu)) * u_p / y;
            assert!(
                (tau / (u_tau * u_tau) - 1.0).abs() < 1e-12,
                "y+ {yp}: {tau}"
            );
            // ε of the log layer in equilibrium: u_τ³/(κ y); G = u_τ² · du/dy = ε too.
            let (eps, g) = epsilon_and_g(&law, false, 1.0, y, k, nu, tau * y / u_p - nu, u_p / y);
            let eps_exact = u_tau.powi(3) / (law.kappa() * y);
            assert!((eps / eps_exact - 1.0).abs() < 1e-12, "{eps} {eps_exact}");
            assert!((g / eps_exact - 1.0).abs() < 1e-12, "{g} {eps_exact}");
        }
        // Below y⁺_lam: no eddy viscosity.
        assert_eq!(nut_wall(&law, 1e-4, 1e-4, 1e-5), 0.0);
    }
}
