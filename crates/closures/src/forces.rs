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
