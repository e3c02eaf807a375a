//! Forces and the model A / B / Bfull formulations: hand values, Archimedes' principle,
//! Saffman's scalar form, and the steady force balances the three models must share.

use approx::assert_abs_diff_eq;
use approx::assert_relative_eq;
use closures::forces::{
    buoyancy, mei_factor, mei_lift, pressure_gradient, saffman_lift, virtual_mass, viscous_stress,
    SPHERE_VIRTUAL_MASS_COEFFICIENT,
};
use closures::{particle_forces, sphere_volume, DragInput, DragLaw, FluidAtParticle, ModelType};
use v3::V3;

/// |aₖ − bₖ| ≤ tol·max|b| for every component.
fn close(a: V3, b: V3, tol: f64) -> bool {
    let scale = b.amax().max(1e-300);
    approx::abs_diff_eq!(a, b, epsilon = tol * scale)
}

const G: V3 = V3::new(0.0, 0.0, -9.81);

#[test]
fn pressure_force_of_a_hydrostatic_fluid_is_archimedes() {
    // hydrostatic kinematic pressure: ∇(p/ρ) = g, so −V ρ ∇(p/ρ) = −ρ V g.
    let (v, rho) = (sphere_volume(2e-3), 998.0);
    assert_eq!(pressure_gradient(v, rho, G), buoyancy(v, rho, G));
    // buoyancy by hand: 998 · 4.18879e-9 · 9.81 N upward
    assert_relative_eq!(
        buoyancy(v, rho, G)[2],
        998.0 * 4.188790205e-9 * 9.81,
        epsilon = 0.0,
        max_relative = 1e-9
    );
    // fully developed channel flow: ∇·τ = ∇p, so a neutral particle feels no net stress force
    let gp = V3::new(-3.0, 0.0, 0.0);
    let sum = pressure_gradient(v, rho, gp) + viscous_stress(v, rho, gp);
    assert_eq!(sum, V3::repeat(0.0));
}

#[test]
fn virtual_mass_of_a_sphere_accelerating_in_still_fluid() {
    // (m + ½ρV) a = F: with F = 1 mN on a 1 mm glass bead in water
    let (v, rho, rho_p, f) = (sphere_volume(1e-3), 1000.0, 2500.0, 1e-3);
    let a = f / ((rho_p + 0.5 * rho) * v);
    let fvm = virtual_mass(
        SPHERE_VIRTUAL_MASS_COEFFICIENT,
        v,
        rho,
        V3::repeat(0.0),
        V3::new(a, 0.0, 0.0),
    );
    // Newton for the particle alone: ρ_p V a = F + F_vm
    assert_relative_eq!(
        rho_p * v * a,
        f + fvm[0],
        epsilon = 0.0,
        max_relative = 1e-12
    );
}

#[test]
fn saffman_and_mei_lift() {
    // Saffman's scalar form 6.46 μ a² U √(κ/ν): a = 5e-5, U = 0.01, κ = 10/s, ν = 1e-6.
    let (d, rho, mu) = (1e-4, 1000.0, 1e-3);
    let f = saffman_lift(d, rho, mu, V3::new(0.01, 0.0, 0.0), V3::new(0.0, 0.0, 10.0));
    let scalar = 6.46 * mu * 2.5e-9 * 0.01 * (10.0f64 / 1e-6).sqrt();
    assert_relative_eq!(f[1].abs(), scalar, epsilon = 0.0, max_relative = 1e-3);
    assert!(f[0] == 0.0 && f[2] == 0.0);
    // direction: (u − v) × ω
    assert!(f[1] < 0.0);
    assert_eq!(
        saffman_lift(d, rho, mu, V3::new(0.01, 0.0, 0.0), V3::repeat(0.0)),
        V3::repeat(0.0)
    );
    // Mei: → 1 at Re_p → 0; hand value at Re_p = 10, Re_ω = 1 (b = 0.05):
    // (1 − 0.3314·√0.05)·e⁻¹ + 0.3314·√0.05 = 0.414722
    assert_abs_diff_eq!(mei_factor(1e-12, 1e-12), 1.0, epsilon = 1e-6);
    assert_abs_diff_eq!(mei_factor(10.0, 1.0), 0.414722, epsilon = 1e-6);
    let b: f64 = 0.5 * 4.0 / 40.0;
    let jump = (1.0 - 0.3314 * b.sqrt()) * (-4.0f64).exp();
    // (0.0524·√40 = 0.331407 rounds to 0.3314: 1.5e-6 of slack)
    assert!((mei_factor(40.0, 4.0) - mei_factor(40.000001, 4.0) - jump).abs() < 5e-6);
    let slip = V3::new(0.2, 0.0, 0.0);
    let w = V3::new(0.0, 0.0, 50.0);
    let re_p = rho * d * 0.2 / mu;
    let re_w = rho * 50.0 * d * d / mu;
    let m = mei_lift(d, rho, mu, slip, w);
    assert!(close(
        m,
        mei_factor(re_p, re_w) * saffman_lift(d, rho, mu, slip, w),
        1e-15
    ));
}

/// Steady, uniform upflow through a bed of resting particles (no viscous term): each model's
/// fluid equation fixes ∇p; every model must then give each particle the same total force, and
/// the particles must carry the whole pressure drop.
#[test]
fn models_agree_at_steady_uniform_flow() {
    let (eps, d, rho, mu) = (0.45, 1e-3, 10.0, 1.5e-3);
    let u = V3::new(0.0, 0.0, 0.02);
    let vol = sphere_volume(d);
    let n = (1.0 - eps) / vol;
    let beta = DragLaw::Ergun.beta(&DragInput::new(eps, d, 0.02, rho, mu));
    let fluid = |grad_p: V3| FluidAtParticle {
        u,
        grad_p,
        div_tau: V3::repeat(0.0),
        voidage: eps,
        rho,
    };
    // A: 0 = −ε∇p − (Ksl/ρ)u with Ksl = nβ.
    let gp_a = -n * beta / (eps * rho) * u;
    // B: 0 = −∇p − (Ksl/ρ)u with Ksl = nβ/ε.
    let gp_b = -n * beta / (eps * rho) * u;
    // Bfull: 0 = −∇p − (Ksl/ρ)u + f/ρ with Ksl = nβ and f = −n·explicit_coupled = nVρ∇p,
    // so ∇p (1 − nV) = −nβu/ρ.
    let gp_bf = -n * beta / ((1.0 - n * vol) * rho) * u;
    let fa = particle_forces(
        ModelType::A,
        beta,
        vol,
        &fluid(gp_a),
        V3::repeat(0.0),
        V3::repeat(0.0),
    );
    let fb = particle_forces(
        ModelType::B,
        beta,
        vol,
        &fluid(gp_b),
        V3::repeat(0.0),
        V3::repeat(0.0),
    );
    let fbf = particle_forces(
        ModelType::BFull,
        beta,
        vol,
        &fluid(gp_bf),
        V3::repeat(0.0),
        V3::repeat(0.0),
    );
    let want = beta / eps * u; // β u/ε
    for f in [fa, fb, fbf] {
        assert!(close(f.total(), want, 1e-12), "{f:?}");
        // particles carry the pressure drop: n·F = −ρ∇p_B (the superficial balance)
        assert!(close(n * f.total(), -rho * gp_b, 1e-12));
    }
    assert_eq!(fa.beta, beta);
    assert_relative_eq!(fb.beta, beta / eps, epsilon = 0.0, max_relative = 1e-15);
    assert_eq!(fbf.beta, beta);
    assert_eq!(fa.explicit_coupled, V3::repeat(0.0));
    assert_eq!(fb.explicit_coupled, V3::repeat(0.0));
    assert!(close(
        fbf.explicit_coupled,
        pressure_gradient(vol, rho, gp_bf),
        1e-15
    ));
}

/// Minimum fluidisation: drag (model B) balances weight minus buoyancy, and model A's fluid
/// pressure gradient is then the classical Δp/L = (1 − ε)(ρ_p − ρ) g (Kunii & Levenspiel).
#[test]
fn fluidised_bed_pressure_drop() {
    let (eps, d, rho, mu, rho_p) = (0.45, 1e-3, 10.0, 1.5e-3, 2000.0);
    let vol = sphere_volume(d);
    let net_weight = (rho_p - rho) * vol * 9.81;
    // find the interstitial speed where β(u)·u/ε = (ρ_p − ρ) V g (bisection on Ergun)
    let beta_at = |s: f64| DragLaw::Ergun.beta(&DragInput::new(eps, d, s, rho, mu));
    let (mut lo, mut hi) = (0.0, 10.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if beta_at(mid) * mid / eps < net_weight {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let s = lo;
    let beta = beta_at(s);
    let fluid = FluidAtParticle {
        u: V3::new(0.0, 0.0, s),
        grad_p: V3::repeat(0.0),
        div_tau: V3::repeat(0.0),
        voidage: eps,
        rho,
    };
    let fb = particle_forces(ModelType::B, beta, vol, &fluid, V3::repeat(0.0), G);
    let m = rho_p * vol;
    // particle at rest: fluid force + weight = 0
    let residual = (fb.total() + (m * G)).norm();
    assert!(residual < 1e-9 * m * 9.81, "{residual}");
    // model A fluid: ε ∇(p/ρ) = −(nβ/ρ) u  →  −ρ dp/dz = (1 − ε)(ρ_p − ρ) g
    let n = (1.0 - eps) / vol;
    let dpdz = -n * beta * s / eps; // ρ·∂(p/ρ)/∂z, Pa/m
    assert_relative_eq!(
        -dpdz,
        (1.0 - eps) * (rho_p - rho) * 9.81,
        epsilon = 0.0,
        max_relative = 1e-9
    );
    // superficial velocity ~ 0.0135 m/s: REFERENCE.md's minimum fluidisation "≈ 0.0145 m/s"
    // at ε = 0.4513 and a 167 Pa plateau over L = 0.0156 m
    assert!(
        approx::abs_diff_eq!(s * eps, 0.0145, epsilon = 0.002),
        "{}",
        s * eps
    );
    assert_relative_eq!(
        (1.0 - 0.4513) * (rho_p - rho) * 9.81 * 0.0156,
        167.0,
        epsilon = 0.0,
        max_relative = 0.005
    );
}

#[test]
fn model_names() {
    for (name, m) in [
        ("A", ModelType::A),
        ("B", ModelType::B),
        ("Bfull", ModelType::BFull),
    ] {
        assert_eq!(ModelType::from_name(name).unwrap(), m);
        assert_eq!(m.name(), name);
    }
    let err = ModelType::from_name("C").unwrap_err().to_string();
    assert!(err.contains("`C`") && err.contains("Bfull"), "{err}");
}

/// CFDEM's MeiLift: McLaughlin's asymptotes at both ends of J*, and Saffman's lift in the
/// strong-shear limit ε ≫ 1 (Saffman 1965 with the 1968 erratum's 6.46).
#[test]
fn cfdem_mei_lift_tends_to_saffman_and_mclaughlin() {
    use closures::forces::{cfdem_mei_lift, mclaughlin_j_star};
    // McLaughlin (1991) eq. 3.26, J = 2.255 − 0.6463/ε², and 3.27, J = −32π² ε⁵ ln(1/ε²)
    for eps in [25.0, 50.0, 400.0] {
        let j = 2.255 - 0.6463 / (eps * eps);
        assert_relative_eq!(mclaughlin_j_star(eps) * 2.255, j, max_relative = 2e-4);
    }
    for eps in [0.02f64, 0.05, 0.09] {
        let pi2 = std::f64::consts::PI.powi(2);
        let j = -32.0 * pi2 * eps.powi(5) * (1.0 / (eps * eps)).ln();
        assert_relative_eq!(mclaughlin_j_star(eps) * 2.255, j, max_relative = 2e-3);
    }
    // Mei's fit meets the asymptotes: within 0.02 of J* at ε = 20 and 0.006 at ε = 0.1
    assert!((mclaughlin_j_star(19.999) - mclaughlin_j_star(20.001)).abs() < 0.02);
    assert!((mclaughlin_j_star(0.0999) - mclaughlin_j_star(0.1001)).abs() < 0.006);
    // Saffman's limit: d = 100 µm, ν = 1e-6, ω = 1e4/s, |u_r| = 1e-3 m/s: ε = 100
    let (d, rho, nu) = (1e-4, 1000.0, 1e-6);
    let slip = V3::new(1e-3, 0.0, 0.0);
    let w = V3::new(0.0, 0.0, -1e4);
    let mei = cfdem_mei_lift(d, rho, nu, slip, w, false);
    let saffman = saffman_lift(d, rho, rho * nu, slip, w);
    assert!(mei[1] > 0.0 && mei[0] == 0.0 && mei[2] == 0.0);
    assert_relative_eq!(mei[1], saffman[1], max_relative = 0.287e-4 + 1e-3);
    assert_eq!(
        cfdem_mei_lift(d, rho, nu, V3::zeros(), w, true),
        V3::zeros()
    );
}
