//! `tangential history`: Mindlin's tangential spring with a history of the tangential
//! displacement, a dashpot while sticking and a Coulomb cap.
//!
//! Per step, with vₜᵣ the tangential relative velocity of the contact points (m/s):
//! ξ ← ξ + vₜᵣ dt, then ξ ← ξ − (ξ·n)n (the history rotated into the current tangent plane);
//! Fₜ = −kₜξ. If |Fₜ| > μ|Fₙ| (sliding) Fₜ is scaled to μ|Fₙ| and ξ = −Fₜ/kₜ (the spring
//! is kept at the slip limit, no dashpot); otherwise (sticking) Fₜ −= γₜvₜᵣ. This is the
//! Cundall–Strack history model in the form LIGGGHTS 3.x uses (`tangential_model_history`,
//! Fₙ there being the normal contact force with damping but without cohesion).

use mesh::v3::V3;

/// Tangential force on i (N); updates the displacement history `shear` (m) when
/// `update_history`. `kt` (N/m), `gamma_t` (kg/s), `ft_max` = μ|Fₙ| (N), `dt` (s).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn history_force(
    shear: &mut V3,
    n: V3,
    vtr: V3,
    kt: f64,
    gamma_t: f64,
    ft_max: f64,
    dt: f64,
    update_history: bool,
) -> V3 {
    let mut s = *shear;
    if update_history {
        s += dt * vtr;
        let rsht = s.dot(&n);
        s -= rsht * n;
    }
    let shrmag = s.norm();
    let mut ft = -kt * s;
    let ft_shear = kt * shrmag;
    if ft_shear > ft_max {
        if shrmag != 0.0 {
            ft = ft_max / ft_shear * ft;
            if update_history {
                s = -1.0 / kt * ft;
            }
        } else {
            ft = V3::zeros();
        }
    } else {
        ft -= gamma_t * vtr;
    }
    if update_history {
        *shear = s;
    }
    ft
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_sticks_then_caps_at_coulomb() {
        // kt = 100 N/m, vtr = 1 m/s along x for dt = 1 ms: ξ = 1 mm, F = −0.1 N (stick, no
        // damping); with μFn = 0.05 N the force is capped and ξ reset to 0.5 mm.
        let n = V3::new(0.0, 0.0, 1.0);
        let mut s = V3::zeros();
        let f = history_force(
            &mut s,
            n,
            V3::new(1.0, 0.0, 0.0),
            100.0,
            0.0,
            1.0,
            1e-3,
            true,
        );
        assert!((f[0] + 0.1).abs() < 1e-15 && (s[0] - 1e-3).abs() < 1e-18);
        let mut s = V3::zeros();
        let f = history_force(
            &mut s,
            n,
            V3::new(1.0, 0.0, 0.0),
            100.0,
            0.0,
            0.05,
            1e-3,
            true,
        );
        assert!((f[0] + 0.05).abs() < 1e-15 && (s[0] - 5e-4).abs() < 1e-18);
        // a normal component of the history is removed
        let mut s = V3::new(0.0, 0.0, 1.0);
        history_force(&mut s, n, V3::zeros(), 100.0, 0.0, 1.0, 1e-3, true);
        assert_eq!(s, V3::zeros());
    }
}
