//! Time-step criteria against independent numbers: the root of the Rayleigh-wave equation,
//! numerical integration of the Hertz contact (elastic and with LIGGGHTS's damping), and hand
//! values for REFERENCE.md's Ergun case (E = 5e6 Pa, ν = 0.45, e = 0.3, d = 1 mm, ρ_p = 2000).

use approx::assert_abs_diff_eq;
use approx::assert_relative_eq;
use closures::timestep::{
    acceleration_number, coupling_interval_steps, drag_relaxation_time, hertz_contact_time,
    rayleigh_time_step, stokes_relaxation_time, HertzContact, DEFAULT_COUPLING_FRACTION,
};
use closures::{DragInput, DragLaw};
use std::f64::consts::PI;

/// Rayleigh wave speed over shear wave speed: the root in (0, 1) of
/// ξ⁶ − 8ξ⁴ + (24 − 16κ)ξ² − 16(1 − κ) = 0, κ = (1 − 2ν)/(2(1 − ν)) (Rayleigh 1885).
fn rayleigh_ratio(nu: f64) -> f64 {
    let k = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
    let f = |x: f64| x.powi(6) - 8.0 * x.powi(4) + (24.0 - 16.0 * k) * x * x - 16.0 * (1.0 - k);
    let (mut lo, mut hi) = (0.5, 1.0 - 1e-12);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if f(lo) * f(m) <= 0.0 {
            hi = m;
        } else {
            lo = m;
        }
    }
    lo
}

#[test]
fn rayleigh_time_step_vs_the_rayleigh_wave_equation() {
    let (r, rho, e) = (5e-4, 2000.0, 5e6_f64);
    for nu in [0.0, 0.1, 0.25, 0.3, 0.45, 0.49] {
        let shear_speed = (e / (2.0 * (1.0 + nu)) / rho).sqrt();
        let exact = PI * r / (rayleigh_ratio(nu) * shear_speed);
        assert!(
            approx::relative_eq!(
                rayleigh_time_step(r, rho, e, nu),
                exact,
                epsilon = 0.0,
                max_relative = 3e-3
            ),
            "ν = {nu}"
        );
    }
    // Ergun case by hand: G = 5e6/2.9 = 1.724138e6 Pa, π·5e-4·√(2000/G) = 5.34994e-5,
    // 0.1631·0.45 + 0.8766 = 0.949995 → 5.63155e-5 s.
    assert_relative_eq!(
        rayleigh_time_step(5e-4, 2000.0, 5e6, 0.45),
        5.63155e-5,
        epsilon = 0.0,
        max_relative = 1e-5
    );
}

/// Integrates m* δ̈ = −F_n(δ, δ̇) from δ = 0, δ̇ = v (RK4, `steps` steps over 1.5 t_H) until
/// the overlap returns to 0; returns (contact duration, rebound speed / v).
fn collide(c: &HertzContact, v: f64, damped: bool, steps: usize) -> (f64, f64) {
    let acc = |x: f64, xd: f64| {
        let f = if damped {
            c.normal_force(x, xd)
        } else {
            c.stiffness(x.max(0.0)) * x.max(0.0)
        };
        -f / c.m_eff
    };
    let dt = 1.5 * c.contact_time(v) / steps as f64;
    let (mut x, mut xd, mut t) = (0.0f64, v, 0.0);
    for _ in 0..steps {
        let (k1x, k1v) = (xd, acc(x, xd));
        let (k2x, k2v) = (
            xd + 0.5 * dt * k1v,
            acc(x + 0.5 * dt * k1x, xd + 0.5 * dt * k1v),
        );
        let (k3x, k3v) = (
            xd + 0.5 * dt * k2v,
            acc(x + 0.5 * dt * k2x, xd + 0.5 * dt * k2v),
        );
        let (k4x, k4v) = (xd + dt * k3v, acc(x + dt * k3x, xd + dt * k3v));
        let xn = x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        let xdn = xd + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if xn <= 0.0 && t > 0.0 {
            return (t + dt * x / (x - xn), -xdn / v);
        }
        (x, xd, t) = (xn, xdn, t + dt);
    }
    panic!("contact did not end");
}

#[test]
fn hertz_contact_time_vs_integrated_collision() {
    let (d, rho_p) = (1e-3_f64, 2000.0);
    let m = rho_p * PI * d.powi(3) / 6.0;
    let c = HertzContact::new(5e6, 0.45, 0.3, [d / 2.0; 2], [m; 2]).unwrap();
    assert_relative_eq!(
        c.y_eff,
        5e6 / (2.0 * (1.0 - 0.45 * 0.45)),
        epsilon = 0.0,
        max_relative = 1e-15
    );
    assert_relative_eq!(c.r_eff, 2.5e-4, epsilon = 0.0, max_relative = 1e-15);
    for v in [0.01, 0.1, 1.0] {
        let (t, cor) = collide(&c, v, false, 20_000);
        assert!(
            approx::relative_eq!(c.contact_time(v), t, epsilon = 0.0, max_relative = 1e-4),
            "v = {v}: {} vs {t}",
            c.contact_time(v)
        );
        assert_abs_diff_eq!(cor, 1.0, epsilon = 1e-6);
        // seed 002 eq. 11's rounded 2.87 is within 0.1 %
        let seed = 2.87 * (c.m_eff.powi(2) / (c.r_eff * c.y_eff.powi(2) * v)).powf(0.2);
        assert_relative_eq!(seed, t, epsilon = 0.0, max_relative = 1e-3);
    }
    // hand value at v = 0.1 m/s: m* = 5.23599e-7 kg, R* = 2.5e-4 m, Y* = 3.134796e6 Pa
    assert_relative_eq!(
        hertz_contact_time(5.23599e-7, 2.5e-4, 3.134796e6, 0.1),
        1.84989e-4,
        epsilon = 0.0,
        max_relative = 1e-4
    );
}

#[test]
fn liggghts_damping_gives_the_requested_restitution() {
    let (d, rho_p) = (1e-3_f64, 2000.0);
    let m = rho_p * PI * d.powi(3) / 6.0;
    for e in [0.3, 0.6, 0.9] {
        let c = HertzContact::new(5e6, 0.45, e, [d / 2.0; 2], [m; 2]).unwrap();
        for v in [0.05, 0.5] {
            let (_, cor) = collide(&c, v, true, 20_000);
            assert!(
                approx::abs_diff_eq!(cor, e, epsilon = 1e-4),
                "e = {e}, v = {v}: {cor}"
            );
        }
    }
    assert!(HertzContact::new(5e6, 0.6, 0.3, [1e-3; 2], [1.0; 2]).is_err());
    assert!(HertzContact::new(5e6, 0.3, 0.0, [1e-3; 2], [1.0; 2]).is_err());
    let err = HertzContact::new(-1.0, 0.3, 0.5, [1e-3; 2], [1.0; 2]).unwrap_err();
    assert!(err.to_string().contains("youngsModulus"), "{err}");
}

#[test]
fn relaxation_times_and_coupling_interval() {
    // Ergun case: τ = 2000·1e-6/(18·1.5e-3) = 0.0740741 s.
    let tau = stokes_relaxation_time(2000.0, 1e-3, 1.5e-3);
    assert_relative_eq!(tau, 0.0740741, epsilon = 0.0, max_relative = 1e-6);
    // the drag-law time with Stokes' β is the same; with Schiller–Naumann at Re = 10 shorter
    let m = 2000.0 * PI * 1e-9 / 6.0;
    assert_relative_eq!(
        drag_relaxation_time(m, 3.0 * PI * 1.5e-3 * 1e-3),
        tau,
        epsilon = 0.0,
        max_relative = 1e-14
    );
    let x = DragInput::new(1.0, 1e-3, 1.5, 10.0, 1.5e-3);
    let sn = drag_relaxation_time(m, DragLaw::SchillerNaumann.beta(&x));
    assert_relative_eq!(
        sn,
        tau / (1.0 + 0.15 * 10f64.powf(0.687)),
        epsilon = 0.0,
        max_relative = 1e-12
    );
    // 10 % of τ at a DEM step of 1e-5 s: ⌊740.7⌋ steps
    assert_eq!(coupling_interval_steps(1e-5, tau, 0.1).unwrap(), 740);
    assert_eq!(coupling_interval_steps(1e-3, 1e-4, 0.1).unwrap(), 1);
    assert!(coupling_interval_steps(0.0, tau, 0.1).is_err());
    // REFERENCE.md's Ergun case couples every 50 steps of 1e-5 s: 5e-4/0.0740741 = 0.00675
    assert_relative_eq!(
        acceleration_number(50.0 * 1e-5, tau),
        0.00675,
        epsilon = 0.0,
        max_relative = 1e-3
    );
    let steps = coupling_interval_steps(1e-5, tau, DEFAULT_COUPLING_FRACTION).unwrap();
    assert!(acceleration_number(steps as f64 * 1e-5, tau) <= DEFAULT_COUPLING_FRACTION);
    assert!(acceleration_number((steps + 1) as f64 * 1e-5, tau) > DEFAULT_COUPLING_FRACTION);
}
