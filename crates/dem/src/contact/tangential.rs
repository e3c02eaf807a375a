//! `tangential history`: Mindlin's tangential spring with a history of the tangential
//! displacement, a dashpot while sticking and a Coulomb cap.
//!
//! Per step, with vₜᵣ the tangential relative velocity of the contact points (m/s):
//! ξ ← ξ + vₜᵣ dt, then ξ ← ξ − (ξ·n)n (the history rotated into the current tangent plane);
//! Fₜ = −kₜξ. If |Fₜ| > μ|Fₙ| (sliding) Fₜ is scaled to μ|Fₙ| and ξ = −Fₜ/kₜ (the spring
//! is kept at the slip limit, no dashpot); otherwise (sticking) Fₜ −= γₜvₜᵣ. This is the
//! Cundall–Strack history model in the form LIGGGHTS 3.x uses (`tangential_model_history`,
//! Fₙ there being the normal contact force with damping but without cohesion).
//!
//! Evaluated again without advancing the history ([`HistoryUse::Replay`], the first step of a
//! run continued from a native restart file, at the velocities of the step that left the
//! history), the force must be that step's: a slip leaves the spring at the Coulomb limit,
//! kₜ|ξ| = μ|Fₙ|, which round-off puts a few 10⁻¹⁶ above or below it, so a replay counts a
//! spring within a relative [`SLIP_TOLERANCE`] of the limit as slipping. LIGGGHTS's set-up
//! ([`HistoryUse::Setup`]) compares the bare values and so adds the dashpot to some slipping
//! contacts.

use mesh::v3::V3;

use super::HistoryUse;

/// Relative distance to the Coulomb limit within which a replay counts a spring as slipping.
pub const SLIP_TOLERANCE: f64 = 1e-12;

/// Tangential force on i (N); advances the displacement history `shear` (m) with
/// [`HistoryUse::Advance`]. `kt` (N/m), `gamma_t` (kg/s), `ft_max` = μ|Fₙ| (N), `dt` (s).
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
    history: HistoryUse,
) -> V3 {
    let update_history = history == HistoryUse::Advance;
    let mut s = *shear;
    if update_history {
        s += dt * vtr;
        let rsht = s.dot(&n);
        s -= rsht * n;
    }
    let shrmag = s.norm();
    let mut ft = -kt * s;
    let ft_shear = kt * shrmag;
    let limit = if history == HistoryUse::Replay {
        ft_max * (1.0 - SLIP_TOLERANCE)
    } else {
        ft_max
    };
    if ft_shear > limit {
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
            HistoryUse::Advance,
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
            HistoryUse::Advance,
        );
        assert!((f[0] + 0.05).abs() < 1e-15 && (s[0] - 5e-4).abs() < 1e-18);
        // a normal component of the history is removed
        let mut s = V3::new(0.0, 0.0, 1.0);
        history_force(
            &mut s,
            n,
            V3::zeros(),
            100.0,
            0.0,
            1.0,
            1e-3,
            HistoryUse::Advance,
        );
        assert_eq!(s, V3::zeros());
    }

    /// Evaluated again at the same velocities, a slipping and a sticking contact give the
    /// force of the step that left their history (to round-off; the history is unchanged).
    #[test]
    fn replay_gives_the_force_of_the_step() {
        let n = V3::new(0.0, 0.0, 1.0);
        for (vtr, ft_max) in [
            (V3::new(0.3, -0.7, 0.0), 0.05),
            (V3::new(0.3, -0.7, 0.0), 0.5),
            (V3::new(1.0 / 3.0, 0.1, 0.0), 0.03),
        ] {
            let mut s = V3::new(1e-4 / 3.0, 2e-4, 0.0);
            let step = history_force(
                &mut s,
                n,
                vtr,
                97.0,
                0.01,
                ft_max,
                1e-3,
                HistoryUse::Advance,
            );
            let kept = s;
            let again = history_force(&mut s, n, vtr, 97.0, 0.01, ft_max, 1e-3, HistoryUse::Replay);
            assert_eq!(s, kept);
            assert!(
                (again - step).norm() <= 1e-15 * step.norm(),
                "{again:?} vs {step:?}"
            );
        }
    }
}
