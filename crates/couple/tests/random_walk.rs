//! `KochHillRWDrag` ([`couple::random_walk`]) through the coupler: with k = 0 it is
//! `KochHillDrag` bit for bit; with turbulence the fluid loses what the particles gain (the
//! fluctuation's β u′ in f); and the particles' mean drag in homogeneous turbulence is
//! Koch–Hill's at the mean slip, by Monte Carlo (its standard error and the Re-dependence of β
//! bound the difference). The dispersion against Taylor's closed form is the module's test.

mod common;

use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use common::Particles;
use couple::config::{DragSettings, Forces};
use couple::random_walk::RandomWalkSettings;
use couple::{Coupler, CouplerSettings, FluidState, Interpolation, Turbulence};
use couple::{CouplingStep, Physics};
use mesh::build::uniform_box;
use mesh::v3::V3;
use voidage::Method;

/// Water, Koch–Hill drag, centre voidage; `random_walk` as given.
fn settings(random_walk: Option<RandomWalkSettings>) -> CouplerSettings {
    CouplerSettings {
        method: Method::Centre,
        alpha_min: None,
        coupling_interval: 10,
        physics: Physics {
            rho: 1000.0,
            nu: 1e-6,
            gravity: V3::zeros(),
            model: ModelType::A,
            forces: Forces {
                drag: Some(DragSettings {
                    closure: DragClosure::from(DragLaw::KochHill),
                    interpolation: Interpolation::Cell,
                    implicit_dem: false,
                    explicit_fluid: false,
                    dem_only: false,
                }),
                random_walk,
                ..Forces::default()
            },
            implicit_couple: true,
        },
        heat: None,
    }
}

/// `n` particles of d = 0.1 mm, at rest, spread over the one cell of a 10 cm box.
fn particles(n: usize) -> Particles {
    let position = (0..n)
        .map(|i| {
            let f = (i as f64 + 0.5) / n as f64;
            V3::new(0.01 + 0.08 * f, 0.05, 0.05)
        })
        .collect();
    let mut p = Particles::new(position, vec![V3::zeros(); n]);
    p.radius = vec![0.5e-4; n];
    p
}

/// The uniform fluid `u` in one cell with the turbulence `turbulence`.
fn fluid<'a>(u: &'a [V3], zero: &'a [V3], turbulence: Option<Turbulence<'a>>) -> FluidState<'a> {
    FluidState {
        u,
        p: &[0.0],
        grad_p: zero,
        div_tau: zero,
        temperature: None,
        vorticity: None,
        ddt_u: None,
        turbulence,
    }
}

/// One exchange in the uniform fluid `u` with turbulence (k, ε) (`None`: laminar).
fn exchange(
    settings: CouplerSettings,
    p: &Particles,
    u: V3,
    k_eps: Option<(f64, f64)>,
) -> (CouplingStep, f64) {
    let mesh = uniform_box(V3::zeros(), V3::new(0.1, 0.1, 0.1), [1, 1, 1]);
    let mut coupler = Coupler::new(&mesh, settings).unwrap();
    coupler.set_coupling_time_step(1e-3);
    let zero = [V3::zeros()];
    let (k, eps) = k_eps.map_or((vec![], vec![]), |(k, e)| (vec![k], vec![e]));
    let turbulence = k_eps.map(|_| Turbulence {
        k: &k,
        epsilon: &eps,
    });
    let step = coupler
        .exchange(&p.state(), &fluid(&[u], &zero, turbulence))
        .unwrap();
    (step, 1e-3)
}

#[test]
fn without_turbulent_energy_it_is_koch_hill() {
    let p = particles(50);
    let u = V3::new(0.01, 0.002, -0.003);
    let (rw, _) = exchange(
        settings(Some(RandomWalkSettings::default())),
        &p,
        u,
        Some((0.0, 1e-3)),
    );
    let (kh, _) = exchange(settings(None), &p, u, None);
    assert_eq!(rw.forces.particles, kh.forces.particles);
    assert_eq!(rw.exchange.ksl, kh.exchange.ksl);
    assert_eq!(rw.exchange.f, kh.exchange.f);
    // and it needs the fluid's k and ε
    let mesh = uniform_box(V3::zeros(), V3::new(0.1, 0.1, 0.1), [1, 1, 1]);
    let mut c = Coupler::new(&mesh, settings(Some(RandomWalkSettings::default()))).unwrap();
    c.set_coupling_time_step(1e-3);
    let zero = [V3::zeros()];
    let us = [u];
    let laminar = fluid(&us, &zero, None);
    let e = c.exchange(&p.state(), &laminar).unwrap_err().to_string();
    assert!(e.contains("KochHillRWDrag") && e.contains("epsilon"), "{e}");
}

/// N = 40000 particles at rest in U = (s, 0, 0), s = 1 mm/s, turbulence of σ = √(2k/3) =
/// 1 mm/s: each sees w = U + u′. The particles gain Σ F (their drag) and the fluid loses
/// Σ_c V [Ksl (U − Us) − f], equal to round-off. The mean drag is Koch–Hill's β(s)·s within
/// 4 standard errors of the mean (β σ/√N per component) plus the bias of β's Re-dependence:
/// Koch–Hill's F = ε(F₀ + F₃ Re/2), Re = ε d |w|/ν, so β(w) = β₀(1 + a|w|) with
/// a = F₃ ε d/(2F₀ ν) = 0.0905·1e-4/(2·1e-6) = 4.5 s/m (φ = 2e-5: F₀ ≈ 1, F₃ = 0.0905), and
/// |E[β(w) w] − β₀ s| ≤ β₀ a E|w|² (1 + a|s|) ≈ β₀·4.5·(s² + 3σ²) = 1.8 % of β₀ s.
#[test]
fn particles_gain_what_the_fluid_loses_and_the_mean_drag_is_koch_hills() {
    let n = 40_000;
    let p = particles(n);
    let s = 1e-3;
    let u = V3::new(s, 0.0, 0.0);
    let sigma: f64 = 1e-3;
    let k = 1.5 * sigma * sigma;
    let (rw, _) = exchange(
        settings(Some(RandomWalkSettings::default())),
        &p,
        u,
        Some((k, 1e-4)),
    );
    let gained: V3 = rw.forces.particles.iter().map(|c| c.total).sum();
    let volume = 1e-3;
    let e = &rw.exchange;
    let lost = (u - e.us[0]) * (e.ksl[0] * volume) - e.f[0] * volume;
    assert!(
        (gained - lost).norm() <= 1e-12 * gained.norm(),
        "{gained:?} vs {lost:?}"
    );
    // the fluctuations are there: the particles' forces differ
    let spread = rw.forces.particles[0].total - rw.forces.particles[1].total;
    assert!(spread.norm() > 1e-3 * rw.forces.particles[0].total.norm());
    let (kh, _) = exchange(settings(None), &p, u, None);
    let per = kh.forces.particles[0].total;
    let mean = gained / n as f64;
    let beta = per.x / s;
    let se = beta * sigma / (n as f64).sqrt();
    let bias = 0.018 * per.norm();
    for a in 0..3 {
        assert!(
            (mean[a] - per[a]).abs() <= 4.0 * se + bias,
            "component {a}: {} vs {} (SE {se:e})",
            mean[a],
            per[a]
        );
    }
}
