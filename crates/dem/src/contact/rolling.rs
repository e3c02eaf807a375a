//! `rolling_friction cdt|epsd2`: rolling resistance torques (Ai, Chen, Rotter & Ooi, Powder
//! Technol. 206 (2011) 269–282: model A "constant directional torque" and the elastic–plastic
//! spring of model C without its dashpot), as LIGGGHTS 3.x parameterises them with the
//! rolling friction coefficient μᵣ and the effective radius R*.
//!
//! Both return the torque T that is *subtracted* from i's torque and *added* to j's.
//! w is the relative angular velocity (ωᵢ − ωⱼ between particles; LIGGGHTS's cᵢωᵢ/r at a wall).
//! The component of T along the normal (torsion) is removed.

use mesh::v3::V3;

use super::HistoryUse;

/// `cdt`: T = μᵣ Fₑ R* ŵ with Fₑ = kₙδ the elastic normal force (N), ŵ = w/|w|, the normal
/// component removed; zero when w = 0. Units: N·m.
#[inline]
pub fn cdt_torque(mu_r: f64, f_elastic: f64, reff: f64, w: V3, n: V3) -> V3 {
    let wmag = w.norm();
    if wmag <= 0.0 {
        return V3::zeros();
    }
    let t = mu_r * f_elastic * reff / wmag * w;
    t - (t.dot(&n) * n)
}

/// `epsd2`: T ← T_old + kᵣ wₜ dt with kᵣ = kₜR*² (kₜ the Hertz–Mindlin tangential stiffness,
/// N/m) and wₜ the tangential part of w, capped at |T| ≤ μᵣ|Fₙ|R*; the history `roll` holds T
/// (N·m) and is updated when `update_history`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn epsd2_torque(
    roll: &mut V3,
    mu_r: f64,
    fn_: f64,
    kt: f64,
    reff: f64,
    w: V3,
    n: V3,
    dt: f64,
    history: HistoryUse,
) -> V3 {
    let wt = w - (w.dot(&n) * n);
    let kr = kt * reff * reff;
    let mut t = match history {
        HistoryUse::Replay => *roll,
        HistoryUse::Advance | HistoryUse::Setup => *roll + (dt * kr * wt),
    };
    let tmag = t.norm();
    let tmax = fn_.abs() * reff * mu_r;
    if tmag > tmax {
        t = tmax / tmag * t;
    }
    if history == HistoryUse::Advance {
        *roll = t;
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdt_is_constant_in_magnitude_and_tangential() {
        let n = V3::new(0.0, 0.0, 1.0);
        let t = cdt_torque(0.1, 2.0, 0.5, V3::new(3.0, 0.0, 4.0), n);
        // μᵣFR* = 0.1; ŵ = (0.6, 0, 0.8); normal part removed → (0.06, 0, 0)
        assert!((t[0] - 0.06).abs() < 1e-15 && t[1] == 0.0 && t[2].abs() < 1e-15);
        assert_eq!(cdt_torque(0.1, 2.0, 0.5, V3::zeros(), n), V3::zeros());
    }

    #[test]
    fn epsd2_spring_then_cap() {
        let n = V3::new(0.0, 0.0, 1.0);
        let mut h = V3::zeros();
        // kr = 100·0.01 = 1 N·m; w = 2 rad/s for dt 1e-3: T = 2e-3 N·m (below cap 0.01)
        let t = epsd2_torque(
            &mut h,
            0.1,
            1.0,
            100.0,
            0.1,
            V3::new(2.0, 0.0, 0.0),
            n,
            1e-3,
            HistoryUse::Advance,
        );
        assert!((t[0] - 2e-3).abs() < 1e-15 && h == t);
        let t = epsd2_torque(
            &mut h,
            0.01,
            1.0,
            100.0,
            0.1,
            V3::new(2.0, 0.0, 0.0),
            n,
            1e-3,
            HistoryUse::Advance,
        );
        assert!((t[0] - 1e-3).abs() < 1e-15);
        // a replay returns the stored (capped) torque of that step; the set-up adds the
        // increment again
        let step = t;
        let args = (0.01, 1.0, 100.0, 0.1, V3::new(2.0, 0.0, 0.0), n, 1e-3);
        let replay = |h: &mut V3, u| {
            epsd2_torque(h, args.0, args.1, args.2, args.3, args.4, args.5, args.6, u)
        };
        let mut h2 = V3::new(0.5e-3, 0.0, 0.0);
        assert_eq!(
            replay(&mut h2, HistoryUse::Replay),
            V3::new(0.5e-3, 0.0, 0.0)
        );
        // 0.5e-3 + kᵣw dt = 2.5e-3, capped at μᵣFₙR* = 1e-3
        assert!((replay(&mut h2, HistoryUse::Setup)[0] - 1e-3).abs() < 1e-15);
        assert_eq!(h2, V3::new(0.5e-3, 0.0, 0.0));
        assert_eq!(replay(&mut h, HistoryUse::Replay), step);
    }
}
