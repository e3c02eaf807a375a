//! The fluid–particle forces other than drag, per particle, SI units (N). Pressure and the
//! viscous stress are *kinematic* as OpenFOAM's incompressible solvers hold them (ADR 0004):
//! `grad_p` = ∇(p/ρ) in m/s², `div_tau` = ∇·(τ/ρ) in m/s², so every force here multiplies by ρ.
//! Which of these a coupling applies, and where their reactions go, is decided by the model
//! type ([`crate::model`]).

use v3::V3;

/// Pressure-gradient force −V_p ρ ∇p, N, with `grad_p` the gradient of the kinematic
/// pressure p/ρ (m/s²), `volume` V_p (m³), `rho` ρ (kg/m³) (Zhou et al. 2010, f_∇p; seed `002`
/// eq. 6; CFDEMcoupling's `gradPForce` with a kinematic p).
#[inline]
pub fn pressure_gradient(volume: f64, rho: f64, grad_p: V3) -> V3 {
    -volume * rho * grad_p
}

/// Viscous-stress force V_p ρ ∇·τ, N, with `div_tau` = ∇·(ν(∇u + ∇uᵀ)) the divergence of
/// the kinematic viscous *stress* (m/s², the term the fluid momentum equation carries as
/// +∇·τ). Zhou et al. (2010) and CFDEMcoupling's `viscForce` write −V_p ∇·τ because their τ
/// (CFDEM's `divTau` field) has the opposite sign; the force is the same: the particle feels
/// the viscous force density of the fluid it displaces (seed `002` eq. 6, f_∇τ).
#[inline]
pub fn viscous_stress(volume: f64, rho: f64, div_tau: V3) -> V3 {
    volume * rho * div_tau
}

/// Archimedes buoyancy −ρ V_p g, N (opposite to gravity `g`, m/s²; CFDEMcoupling's
/// `Archimedes`). Add it only when the fluid pressure does not contain the hydrostatic part
/// (OpenFOAM's kinematic `p` without a gravity term, as in CFDEM's solvers); with a
/// hydrostatic p the pressure-gradient force already is the buoyancy.
#[inline]
pub fn buoyancy(volume: f64, rho: f64, g: V3) -> V3 {
    -rho * volume * g
}

/// Added-mass coefficient of an isolated sphere in potential flow (Lamb 1932), dimensionless.
pub const SPHERE_VIRTUAL_MASS_COEFFICIENT: f64 = 0.5;

/// Virtual (added) mass force C_vm ρ V_p (Du_f/Dt − dv_p/dt), N: `fluid_accel` the material
/// derivative of the fluid velocity at the particle, `particle_accel` the particle's
/// acceleration (m/s²), C_vm = 0.5 for a sphere ([`SPHERE_VIRTUAL_MASS_COEFFICIENT`];
/// Crowe, Sommerfeld & Tsuji 1998, Multiphase Flows with Droplets and Particles). Explicit in the particle acceleration, it is
/// stable only for ρ_p ≳ C_vm ρ; for light particles integrate it implicitly.
#[inline]
pub fn virtual_mass(c_vm: f64, volume: f64, rho: f64, fluid_accel: V3, particle_accel: V3) -> V3 {
    c_vm * rho * volume * (fluid_accel - particle_accel)
}

/// Saffman (1965) shear lift on a sphere, N:
/// F = 1.615 d² √(ρ μ/|ω|) ((u_f − v_p) × ω), ω = ∇ × u_f the fluid vorticity (1/s),
/// d (m), ρ (kg/m³), μ (Pa·s) (Saffman 1965, J. Fluid Mech. 22, and its 1968 erratum:
/// 6.46 μ a² |u| √(|ω|/ν) with a = d/2). Valid for Re_p ≪ Re_ω^½ ≪ 1; zero without vorticity.
#[inline]
pub fn saffman_lift(d: f64, rho: f64, mu: f64, slip: V3, vorticity: V3) -> V3 {
    let w = vorticity.norm();
    if w == 0.0 {
        return V3::zeros();
    }
    1.615 * d * d * (rho * mu / w).sqrt() * slip.cross(&vorticity)
}

/// Mei's (1992) correction C_L/C_L,Saffman of the Saffman lift to finite Reynolds numbers,
/// dimensionless, with Re_p = ρ d |u_f − v_p|/μ and Re_ω = ρ |ω| d²/μ, b = Re_ω/(2 Re_p):
/// (1 − 0.3314 b^½) e^(−Re_p/10) + 0.3314 b^½ for Re_p ≤ 40, 0.0524 (b Re_p)^½ above
/// (Mei 1992, Int. J. Multiphase Flow 18, 145–147). Tends to
/// 1 as Re_p → 0; the two branches differ by (1 − 0.3314 b^½) e^−4 at Re_p = 40.
#[inline]
pub fn mei_factor(re_p: f64, re_omega: f64) -> f64 {
    if re_p <= 0.0 {
        return 1.0;
    }
    let b = 0.5 * re_omega / re_p;
    if re_p <= 40.0 {
        let s = 0.3314 * b.sqrt();
        (1.0 - s) * (-re_p / 10.0).exp() + s
    } else {
        0.0524 * (b * re_p).sqrt()
    }
}

/// Mei (1992) lift: the [`saffman_lift`] times [`mei_factor`], N.
#[inline]
pub fn mei_lift(d: f64, rho: f64, mu: f64, slip: V3, vorticity: V3) -> V3 {
    let re_p = rho * d * slip.norm() / mu;
    let re_omega = rho * vorticity.norm() * d * d / mu;
    mei_factor(re_p, re_omega) * saffman_lift(d, rho, mu, slip, vorticity)
}

/// McLaughlin's (1991) weak-shear correction of the Saffman lift, normalised by its
/// strong-shear limit: J*(ε) = J(ε)/2.255, dimensionless, with ε = √(ν|ω|)/|u_f − v_p| =
/// (Re_ω/Re_p²)^½ the ratio of the Saffman length to the Oseen length. Three ranges, as CFDEM's
/// `MeiLift` evaluates them:
/// * ε < 0.1: J* = −140 ε⁵ ln(1/ε²) (McLaughlin 1991, J. Fluid Mech. 224, 261–274, eq. 3.27:
///   J = −32π² ε⁵ ln(1/ε²); 32π²/2.255 = 140.05);
/// * ε > 20: J* = 1 − 0.287/ε² (McLaughlin's eq. 3.26: J = 2.255 − 0.6463/ε²);
/// * between: Mei's (1992) fit of McLaughlin's numbers, J* = 0.3 {1 + tanh[2.5 (log₁₀ ε +
///   0.191)]} {0.667 + tanh[6 (ε − 0.32)]} (Mei 1992, Int. J. Multiphase Flow 18, 145–147,
///   eq. 10 with J = 2.255 J*; Loth & Dorgan 2009, Environ. Fluid Mech. 9, 187–206, eq. 32).
///
/// The fit meets the asymptotes to about 2 % at ε = 20 and to 0.005 (absolute) at ε = 0.1.
/// CFDEM-PFM writes the fit as here; CFDEM-PUBLIC moves the bracket (`log10(ε + 0.191)` before
/// 2016-09, `2.5·log10(ε) + 0.191` after): foamgrain follows Mei's paper.
#[inline]
pub fn mclaughlin_j_star(eps: f64) -> f64 {
    if eps < 0.1 {
        let e2 = eps * eps;
        -140.0 * e2 * e2 * eps * (1.0 / e2).ln()
    } else if eps > 20.0 {
        1.0 - 0.287 / (eps * eps)
    } else {
        0.3 * (1.0 + (2.5 * (eps.log10() + 0.191)).tanh()) * (0.667 + (6.0 * (eps - 0.32)).tanh())
    }
}

/// The shear lift of CFDEM's `MeiLift`, N: F = (π/8) ρ d² C_L |u_r| (u_r × ω)/|ω| with
/// u_r = u_f − v_p (m/s), ω = ∇ × u_f (1/s), d (m), ρ (kg/m³), ν (m²/s), and
/// C_L = 4.11 ε J*(ε) ([`mclaughlin_j_star`]; ε = √(ν|ω|)/|u_r|) — Loth & Dorgan (2009) eq. 27
/// and 31, which is Saffman's (1965) lift times J* (4.11 = 8·1.615/π to 0.06 %). With
/// `second_order` (CFDEM-PUBLIC's `useSecondOrderTerms`) C_L gains Loth & Dorgan's spin term at
/// the equilibrium spin Ω*_eq = (ω*/2)(1 − 0.0075 Re_ω)(1 − 0.062 Re_p^½ − 0.001 Re_p) times
/// C*_L,Ω = 1 − {0.675 + 0.15 [1 + tanh(0.28 (ω*/2 − 2))]} tanh(0.18 Re_p^½) (their eq. 34, 38,
/// 39; ω* = |ω| d/|u_r|, Re_p = d|u_r|/ν, Re_ω = |ω| d²/ν), as CFDEM-PUBLIC adds it. Zero when
/// u_r or ω vanishes. In Saffman's range (ε ≫ 1) it is [`saffman_lift`] to 0.287/ε² + 0.06 %.
#[inline]
pub fn cfdem_mei_lift(
    d: f64,
    rho: f64,
    nu: f64,
    slip: V3,
    vorticity: V3,
    second_order: bool,
) -> V3 {
    let (ur, w) = (slip.norm(), vorticity.norm());
    if ur == 0.0 || w == 0.0 {
        return V3::zeros();
    }
    let eps = (nu * w).sqrt() / ur;
    let mut cl = mclaughlin_j_star(eps) * 4.11 * eps;
    if second_order {
        let re_p = d * ur / nu;
        let re_w = w * d * d / nu;
        let half_omega = 0.5 * w * d / ur;
        let omega_eq =
            half_omega * (1.0 - 0.0075 * re_w) * (1.0 - 0.062 * re_p.sqrt() - 0.001 * re_p);
        let cl_spin = 1.0
            - (0.675 + 0.15 * (1.0 + (0.28 * (half_omega - 2.0)).tanh()))
                * (0.18 * re_p.sqrt()).tanh();
        cl += omega_eq * cl_spin;
    }
    (0.125 * std::f64::consts::PI * rho * cl * ur * d * d / w) * slip.cross(&vorticity)
}
