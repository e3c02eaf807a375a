//! Reference values the cases are checked against, computed from each case's own parameters.

use closures::drag::{di_felice, schiller_naumann};
use closures::input::{sphere_volume, DragInput};

/// Ergun's (1952) pressure gradient through a packed bed, Pa/m:
/// Δp/L = 150 μ (1−ε)² U / (ε³ d²) + 1.75 ρ (1−ε) U² / (ε³ d),
/// with U the superficial velocity (m/s), ε the bed voidage, d the (Sauter-mean) particle
/// diameter (m), μ (Pa·s) and ρ (kg/m³) of the fluid. Ergun, Chem. Eng. Prog. 48 (1952) 89–94.
pub fn ergun_pressure_gradient(u: f64, eps: f64, d: f64, mu: f64, rho: f64) -> f64 {
    let e3 = eps * eps * eps;
    150.0 * mu * (1.0 - eps) * (1.0 - eps) * u / (e3 * d * d)
        + 1.75 * rho * (1.0 - eps) * u * u / (e3 * d)
}

/// The superficial velocity at which Ergun's Δp over a bed of height `l` reaches `dp` (Pa): the
/// minimum fluidisation velocity when `dp` is the bed's buoyant weight per area. Solves the
/// quadratic in U exactly. Returns 0 for `dp <= 0`.
pub fn ergun_velocity_for(dp: f64, l: f64, eps: f64, d: f64, mu: f64, rho: f64) -> f64 {
    if dp <= 0.0 {
        return 0.0;
    }
    let e3 = eps * eps * eps;
    let a = 1.75 * rho * (1.0 - eps) / (e3 * d);
    let b = 150.0 * mu * (1.0 - eps) * (1.0 - eps) / (e3 * d * d);
    let c = dp / l;
    // a U² + b U − c = 0, positive root in the cancellation-free form.
    2.0 * c / (b + (b * b + 4.0 * a * c).sqrt())
}

/// One sphere settling from rest in a quiescent fluid under gravity, integrated as CFDEM's
/// settlingTestMPI reference does, with the drag law `beta` (kg/s, from a [`DragInput`] at
/// ε = 1): each step solves v⁺ = (v + Δt (1 − ρ/ρ_p) g) / (1 + Δt β/m), i.e. drag implicit in
/// v with β frozen at the old velocity. Returns the speeds at t = 0, Δt, 2Δt, …, `t_end`
/// (m/s, positive downwards).
#[allow(clippy::too_many_arguments)]
pub fn settling_speed_history_with(
    beta: &dyn Fn(&DragInput) -> f64,
    d: f64,
    rho_p: f64,
    rho: f64,
    nu: f64,
    g: f64,
    dt: f64,
    t_end: f64,
) -> Vec<(f64, f64)> {
    let m = rho_p * sphere_volume(d);
    let n = (t_end / dt).round() as usize;
    let mut v = 0.0f64;
    let mut out = Vec::with_capacity(n + 1);
    out.push((0.0, 0.0));
    for k in 1..=n {
        let b = beta(&DragInput::new(1.0, d, v.abs(), rho, nu * rho));
        v = (v + dt * (1.0 - rho / rho_p) * g) / (1.0 + dt * b / m);
        out.push((k as f64 * dt, v));
    }
    out
}

/// [`settling_speed_history_with`] with Schiller–Naumann's drag
/// ([`closures::drag::schiller_naumann::beta`]): CFDEM's reference curve.
pub fn settling_speed_history(
    d: f64,
    rho_p: f64,
    rho: f64,
    nu: f64,
    g: f64,
    dt: f64,
    t_end: f64,
) -> Vec<(f64, f64)> {
    settling_speed_history_with(&schiller_naumann::beta, d, rho_p, rho, nu, g, dt, t_end)
}

/// Terminal settling speed of one sphere (m/s) with the drag law `beta` at ε = 1: the speed u
/// where β(u)·u equals the buoyant weight (ρ_p − ρ) V_p g, found by bisection to 1e-12
/// relative. The drag must grow at least like Stokes' (true of every law in `closures`).
pub fn terminal_speed_with(
    beta: &dyn Fn(&DragInput) -> f64,
    d: f64,
    rho_p: f64,
    rho: f64,
    nu: f64,
    g: f64,
) -> f64 {
    let weight = (rho_p - rho) * sphere_volume(d) * g;
    let drag = |u: f64| beta(&DragInput::new(1.0, d, u, rho, nu * rho)) * u;
    let (mut lo, mut hi) = (0.0, weight / (3.0 * std::f64::consts::PI * nu * rho * d));
    let mut grow = 0;
    while drag(hi) < weight && grow < 200 {
        hi *= 2.0;
        grow += 1;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if drag(mid) < weight {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// Terminal settling speed of one sphere (m/s) with Di Felice's drag at ε = 1
/// ([`closures::drag::di_felice::beta`]).
pub fn di_felice_terminal_speed(d: f64, rho_p: f64, rho: f64, nu: f64, g: f64) -> f64 {
    terminal_speed_with(&di_felice::beta, d, rho_p, rho, nu, g)
}

/// Pressure gradient through a uniform packed bed (particles at rest) under the drag law
/// `beta` (kg/s per particle, from a [`DragInput`]) in model A, Pa/m: the fluid's momentum
/// balance ε ∇p = K u_i with K = n β the exchange coefficient of n = (1 − ε)/V_p particles per
/// unit volume and u_i = u_s/ε the interstitial velocity, so
/// Δp/L = (1 − ε)/V_p · β(ε, d, u_s/ε) · u_s/ε². `u_s` superficial velocity (m/s), `d` the
/// particle diameter (m), `rho` (kg/m³) and `mu` (Pa·s) of the fluid. With Gidaspow's drag
/// (Ergun below ε 0.8) this is Ergun's equation ([`ergun_pressure_gradient`]).
pub fn packed_bed_pressure_gradient_with(
    beta: &dyn Fn(&DragInput) -> f64,
    u_s: f64,
    eps: f64,
    d: f64,
    rho: f64,
    mu: f64,
) -> f64 {
    let u_i = u_s / eps;
    (1.0 - eps) / sphere_volume(d) * beta(&DragInput::new(eps, d, u_i, rho, mu)) * u_i / eps
}

/// The superficial velocity at which [`packed_bed_pressure_gradient_with`] over a bed of height
/// `l` reaches `dp` (Pa) — the minimum fluidisation velocity of that drag law when `dp` is the
/// bed's weight per area — by bisection to 1e-12 relative (the gradient grows monotonically
/// with u for the drag laws of `closures`). Returns 0 for `dp <= 0`, NaN if not reached below
/// 1000 m/s.
pub fn packed_bed_velocity_for(
    beta: &dyn Fn(&DragInput) -> f64,
    dp: f64,
    l: f64,
    eps: f64,
    d: f64,
    rho: f64,
    mu: f64,
) -> f64 {
    if dp <= 0.0 {
        return 0.0;
    }
    let f = |u: f64| packed_bed_pressure_gradient_with(beta, u, eps, d, rho, mu) * l - dp;
    let (mut lo, mut hi) = (0.0, 1000.0);
    let top = f(hi);
    if top.is_nan() || top < 0.0 {
        // not reached below 1000 m/s (or a NaN input): no root to bracket
        return f64::NAN;
    }
    while hi - lo > 1e-12 * hi {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ergun_reproduces_cfdems_numbers() {
        // REFERENCE.md: L = 0.0156 m, ε = 0.4513, d = 1 mm, ν = 1.5e-4, ρ = 10:
        // 23.0 Pa at 0.002 m/s and 115.1 Pa at 0.01 m/s.
        let (l, e, d, mu, rho) = (0.0156, 0.4513, 1e-3, 1.5e-3, 10.0);
        let dp1 = ergun_pressure_gradient(0.002, e, d, mu, rho) * l;
        let dp2 = ergun_pressure_gradient(0.01, e, d, mu, rho) * l;
        assert!((dp1 - 23.0).abs() < 0.05, "{dp1}");
        assert!((dp2 - 115.1).abs() < 0.05, "{dp2}");
    }

    #[test]
    fn packed_bed_gradient_with_gidaspow_is_ergun_and_inverts() {
        // Gidaspow's drag is Ergun's below ε 0.8 (Gidaspow 1994): the packed-bed gradient of the
        // drag law equals Ergun's closed form, and the bisection inverts it.
        let law = closures::DragClosure::new(
            closures::DragLaw::from_name("GidaspowDrag").unwrap(),
            closures::DEFAULT_VOIDAGE_FLOOR,
        )
        .unwrap();
        let beta = |x: &DragInput| law.beta(x);
        let (eps, d, rho, mu) = (0.404, 1.2e-3, 1.13, 1.68e-5);
        for u in [0.01, 0.1, 0.36, 0.66] {
            let a = packed_bed_pressure_gradient_with(&beta, u, eps, d, rho, mu);
            let b = ergun_pressure_gradient(u, eps, d, mu, rho);
            assert!((a / b - 1.0).abs() < 1e-12, "u {u}: {a} vs Ergun {b}");
        }
        let u = packed_bed_velocity_for(&beta, 189.6, 0.0325, eps, d, rho, mu);
        let u_ergun = ergun_velocity_for(189.6, 0.0325, eps, d, mu, rho);
        assert!((u / u_ergun - 1.0).abs() < 1e-9, "{u} vs {u_ergun}");
        assert_eq!(
            packed_bed_velocity_for(&beta, 0.0, 0.03, eps, d, rho, mu),
            0.0
        );
    }

    #[test]
    fn fluidisation_velocity_inverts_ergun() {
        let (l, e, d, mu, rho) = (0.0156, 0.4513, 1e-3, 1.5e-3, 10.0);
        let u = ergun_velocity_for(167.0, l, e, d, mu, rho);
        let dp = ergun_pressure_gradient(u, e, d, mu, rho) * l;
        assert!((dp - 167.0).abs() < 1e-9, "{dp}");
        // REFERENCE.md: minimum fluidisation ≈ 0.0145 m/s for ≈ 167 Pa.
        assert!((u - 0.0145).abs() < 0.0003, "{u}");
        assert_eq!(ergun_velocity_for(0.0, l, e, d, mu, rho), 0.0);
    }

    #[test]
    fn settling_history_matches_cfdems_reference() {
        // REFERENCE.md: the Schiller–Naumann ODE of settlingTestMPI gives u(0.2 s) = 0.1373 m/s.
        let h = settling_speed_history(1e-4, 3000.0, 10.0, 1e-5, 9.81, 1e-3, 0.2);
        assert_eq!(h.len(), 201);
        let (t, v) = *h.last().unwrap();
        assert!((t - 0.2).abs() < 1e-12);
        assert!((v - 0.1373).abs() < 5e-5, "{v}");
        // First step from rest: β is Stokes' 3πμd, so v₁ = Δt g' / (1 + Δt / τ) with
        // τ = ρp d² / (18 μ) the Stokes relaxation time.
        let (t1, v1) = h[1];
        let tau = 3000.0 * 1e-8 / (18.0 * 1e-4);
        let expect = t1 * (1.0 - 10.0 / 3000.0) * 9.81 / (1.0 + t1 / tau);
        assert!((v1 - expect).abs() < 1e-12 * expect, "{v1} vs {expect}");
    }

    #[test]
    fn di_felice_terminal_speed_matches_reference() {
        // REFERENCE.md: 0.1286 m/s.
        let u = di_felice_terminal_speed(1e-4, 3000.0, 10.0, 1e-5, 9.81);
        assert!((u - 0.1286).abs() < 5e-5, "{u}");
        // The Di Felice ODE converges to it.
        let h = settling_speed_history_with(
            &di_felice::beta,
            1e-4,
            3000.0,
            10.0,
            1e-5,
            9.81,
            1e-3,
            0.5,
        );
        assert!((h.last().unwrap().1 - u).abs() < 1e-9, "{:?}", h.last());
        // Stokes' law: terminal speed (ρp − ρ) g d² / (18 μ) for the Stokes drag 3πμd.
        let stokes = |x: &DragInput| 3.0 * std::f64::consts::PI * x.mu * x.diameter;
        let us = terminal_speed_with(&stokes, 1e-4, 3000.0, 10.0, 1e-5, 9.81);
        let exact = (3000.0 - 10.0) * 9.81 * 1e-8 / (18.0 * 1e-4);
        assert!((us - exact).abs() < 1e-11 * exact, "{us} vs {exact}");
    }
}
