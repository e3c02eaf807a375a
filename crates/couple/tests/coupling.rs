//! The coupling step on real LIGGGHTS output and on in-memory sides:
//! * one-way replay of `tests/fixtures/liggghts/settle.txt` (200 spheres, two snapshots) on a
//!   mesh around its box in a uniform frozen flow: the exchange fields' volume integrals equal
//!   the summed per-particle forces to round-off, per-particle drag equals Schiller–Naumann by
//!   hand, buoyancy is −ρVg, densities come from the dump's mass column (as in `settle.in`);
//! * a free sphere settling under the coupler with in-memory sides reaches the terminal
//!   velocity solved independently from the force balance.

#![allow(clippy::needless_range_loop)]

use approx::assert_abs_diff_eq;
use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use couple::config::{DragSettings, Forces};
use couple::frozen::FrozenFluid;
use couple::memory::{MemoryFluid, MemoryParticles};
use couple::replay::DumpReplay;
use couple::{Coupler, CouplerSettings, FluidSide, Interpolation, ParticleSide, Physics};
use dem_io::ReadOptions;
use mesh::build::uniform_box;
use mesh::v3::V3;
use std::f64::consts::PI;
use voidage::Method;

const RHO: f64 = 1000.0;
const NU: f64 = 1e-6;
const G: V3 = V3::new(0.0, 0.0, -9.81);

fn physics(law: DragLaw, model: ModelType, implicit_dem: bool, explicit_fluid: bool) -> Physics {
    Physics {
        rho: RHO,
        nu: NU,
        gravity: G,
        model,
        forces: Forces {
            drag: Some(DragSettings {
                closure: DragClosure::from(law),
                interpolation: Interpolation::Smooth,
                implicit_dem,
                explicit_fluid,
                dem_only: false,
            }),
            grad_p: None,
            viscous: None,
            archimedes: true,
            no_drag: None,
            ..Forces::default()
        },
        implicit_couple: true,
    }
}

/// Schiller–Naumann β = 3πμd (1 + 0.15 Re^0.687) for Re < 1000, else (π/8)·0.44·ρd²|u − v|,
/// Re = ρ d |u − v| / μ (Schiller & Naumann 1933, with the Newton-regime C_d = 0.44), written
/// out here independently of `closures`.
fn schiller_naumann(d: f64, slip: f64) -> f64 {
    let mu = RHO * NU;
    let re = RHO * d * slip / mu;
    if re < 1000.0 {
        3.0 * PI * mu * d * (1.0 + 0.15 * re.powf(0.687))
    } else {
        PI / 8.0 * 0.44 * RHO * d * d * slip
    }
}

fn settle_box() -> foam::PolyMesh {
    uniform_box(
        V3::new(-0.012, -0.012, 0.0),
        V3::new(0.012, 0.012, 0.03),
        [8, 8, 10],
    )
}

#[test]
fn replay_of_a_liggghts_dump_conserves_momentum() {
    let dump = testkit::fixture("liggghts/settle.txt");
    let u = V3::new(0.01, -0.02, 0.05);
    for method in [Method::Centre, Method::Divided, Method::Exact] {
        for explicit_fluid in [false, true] {
            let mut replay =
                DumpReplay::open(vec![dump.clone()], ReadOptions::default(), 1e-5, None).unwrap();
            let mut fluid = FrozenFluid::uniform(settle_box(), u);
            let settings = CouplerSettings {
                method,
                alpha_min: None,
                coupling_interval: 3000,
                physics: physics(DragLaw::SchillerNaumann, ModelType::A, true, explicit_fluid),
                heat: None,
            };
            let mut coupler = Coupler::new(fluid.mesh(), settings).unwrap();
            let vols = coupler.voidage_mesh().cell_volumes().to_vec();
            let mut steps = vec![coupler.exchange(&replay.state(), &fluid.state()).unwrap()];
            assert_eq!(replay.timestep(), 3000);
            let mut velocities = vec![replay.state().velocity.to_vec()];
            steps.push(coupler.step(&mut replay, &mut fluid).unwrap());
            velocities.push(replay.state().velocity.to_vec());
            assert_eq!(replay.timestep(), 6000);
            let (f_ext, beta_dem, _) = replay.forces();
            assert_eq!(f_ext.len(), 200);
            let (eps_new, received) = fluid.last_exchange().unwrap();
            assert_eq!(eps_new, &steps[1].voidage.epsilon);
            assert_eq!(received, &steps[1].exchange);
            for (s, vel) in steps.iter().zip(&velocities) {
                let n = s.placement.len();
                assert_eq!(n, 200);
                assert_eq!(s.forces.outside, 0);
                assert!(s.deposit.conservation_error() < 1e-12);
                let mut loss = V3::repeat(0.0);
                let mut scale = 0.0;
                for (c, v) in s.forces.particles.iter().zip(vel) {
                    for a in 0..3 {
                        loss[a] += c.beta_fluid * (c.u_f[a] - v[a]);
                        scale += c.total[a].abs();
                    }
                }
                let ex = &s.exchange;
                let mut cells = V3::repeat(0.0);
                for c in 0..vols.len() {
                    for a in 0..3 {
                        cells[a] += vols[c] * ex.ksl[c] * (u[a] - ex.us[c][a]);
                    }
                }
                let f = ex.total_f(&vols);
                let fluid_parts: Vec<V3> = s.forces.particles.iter().map(|c| c.f_fluid).collect();
                for a in 0..3 {
                    let sum_f: f64 = fluid_parts.iter().map(|x| x[a]).sum();
                    assert!((f[a] + sum_f).abs() <= 1e-12 * scale, "{method}: Σ f");
                    assert!(
                        approx::abs_diff_eq!(cells[a], loss[a], epsilon = 1e-12 * scale),
                        "{method}: Σ Ksl"
                    );
                }
                if explicit_fluid {
                    assert!(ex.ksl.iter().all(|&k| k == 0.0));
                } else {
                    assert!(f.iter().all(|&x| x == 0.0));
                    assert!(ex.total_ksl(&vols) > 0.0);
                }
            }
            // Per particle, snapshot 6000: drag by hand, buoyancy −ρVg, the DEM split.
            let s = &steps[1];
            let st = replay.state();
            for i in 0..200 {
                let c = &s.forces.particles[i];
                let r = st.radius[i];
                let v = st.velocity[i];
                let slip = [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
                let mag = (slip[0] * slip[0] + slip[1] * slip[1] + slip[2] * slip[2]).sqrt();
                let beta = schiller_naumann(2.0 * r, mag);
                assert!(
                    approx::abs_diff_eq!(c.beta_dem, beta, epsilon = 1e-12 * beta),
                    "{method} particle {i}: {} vs {beta}, slip {mag}",
                    c.beta_dem
                );
                assert_eq!(beta_dem[i], c.beta_dem);
                let vol = 4.0 / 3.0 * PI * r * r * r;
                let buoy = V3::new(0.0, 0.0, RHO * vol * 9.81);
                for a in 0..3 {
                    assert!(
                        approx::abs_diff_eq!(c.f_ext[a], buoy[a], epsilon = 1e-15),
                        "{:?}",
                        c.f_ext
                    );
                    let total = beta * slip[a] + buoy[a];
                    assert_abs_diff_eq!(c.total[a], total, epsilon = 1e-12 * total.abs().max(1e-9));
                }
                // settle.in: templates of radius 0.0005 m at 2500 kg/m³ and 0.0007 m at 2000.
                let density = if r < 6e-4 { 2500.0 } else { 2000.0 };
                assert!(
                    approx::abs_diff_eq!(st.density[i], density, epsilon = 1e-9),
                    "{}",
                    st.density[i]
                );
            }
        }
    }
}

#[test]
fn a_settling_sphere_reaches_terminal_velocity() {
    let d = 2e-4;
    let rho_p = 2500.0;
    let mesh = uniform_box(
        V3::new(-0.02, -0.02, -0.3),
        V3::new(0.02, 0.02, 0.02),
        [4, 4, 32],
    );
    let mut fluid = MemoryFluid::uniform(mesh, V3::repeat(0.0));
    let mut particles =
        MemoryParticles::new(vec![V3::new(0.001, 0.0, 0.0)], vec![d / 2.0], rho_p, 1e-4);
    particles.gravity = G;
    let settings = CouplerSettings {
        method: Method::Exact,
        alpha_min: None,
        coupling_interval: 10,
        physics: physics(DragLaw::SchillerNaumann, ModelType::A, true, false),
        heat: None,
    };
    let mut coupler = Coupler::new(fluid.mesh(), settings).unwrap();
    coupler
        .run(&mut particles, &mut fluid, 300, |_| {})
        .unwrap();
    // Terminal speed: β(w) w = (ρ_p − ρ) V g, solved by bisection.
    let vol = PI * d * d * d / 6.0;
    let weight = (rho_p - RHO) * vol * 9.81;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let w = 0.5 * (lo + hi);
        if schiller_naumann(d, w) * w < weight {
            lo = w;
        } else {
            hi = w;
        }
    }
    let w = 0.5 * (lo + hi);
    let v = particles.velocity[0];
    assert!((v[2] + w).abs() < 1e-6 * w, "{} vs {}", v[2], -w);
    assert!(v[0].abs() < 1e-12 && v[1].abs() < 1e-12);
    // The fluid received, at every step, Ksl integrating to β and Us = v at the exchange.
    assert_eq!(fluid.received.len(), 300);
    let vols = coupler.voidage_mesh().cell_volumes().to_vec();
    let last = &fluid.received[299];
    let beta = schiller_naumann(d, w);
    assert_abs_diff_eq!(last.exchange.total_ksl(&vols), beta, epsilon = 1e-5 * beta);
    assert_abs_diff_eq!(fluid.time, 300.0 * 10.0 * 1e-4, epsilon = 1e-12);
    assert_eq!(last.interval, 1e-3);
}
