//! The native DEM against closed-form results: Hertz impact (contact time, restitution), a
//! sphere on an incline (rolling without slip below the friction limit, sliding above), free
//! fall, energy conservation, SJKR equilibrium, rolling friction, coupling forces, and
//! thread-count independence.

mod common;

use approx::assert_abs_diff_eq;
use common::{plane, sim, sim_with, sphere};
use dem::contact::{ContactModel, RollingModel};
use dem::material::{MaterialInput, Materials};
use dem::particles::NewParticle;
use mesh::v3::V3;
use std::f64::consts::PI;

/// ∫₀¹ dx/√(1 − x^{5/2}) by Simpson's rule after x = 1 − s² (which removes the end
/// singularity); Hertz's impact duration is t = 2·I·δ_max/v (Johnson, *Contact Mechanics*,
/// 1985, §11.4, I ≈ 1.4716).
fn hertz_integral() -> f64 {
    let f = |s: f64| {
        if s == 0.0 {
            // limit of 2s/√(1 − (1 − s²)^{5/2}) = 2/√(5/2)
            2.0 / 2.5f64.sqrt()
        } else {
            2.0 * s / (1.0 - (1.0 - s * s).powf(2.5)).sqrt()
        }
    };
    let n = 20_000;
    let h = 1.0 / n as f64;
    let mut sum = f(0.0) + f(1.0);
    for k in 1..n {
        sum += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

fn mass(r: f64, rho: f64) -> f64 {
    4.0 / 3.0 * PI * r.powi(3) * rho
}

#[test]
fn hertz_integral_is_johnsons_constant() {
    assert!(
        approx::abs_diff_eq!(hertz_integral(), 1.4716, epsilon = 1e-4),
        "{}",
        hertz_integral()
    );
}

/// Two equal spheres meet head-on (e = 1): duration of contact and maximum overlap vs Hertz,
/// δ_max = (15 m* v²/(16 Y* √R*))^{2/5}, t = 2.9432 δ_max/v (Johnson 1985, eqs. 11.23–11.24).
#[test]
fn hertz_pair_impact_duration_and_overlap() {
    let (r, rho, e_mod, nu, v) = (1e-3, 2500.0, 1e7, 0.3, 1.0);
    let m = mass(r, rho);
    let (meff, reff, yeff) = (0.5 * m, 0.5 * r, e_mod / (2.0 * (1.0 - nu * nu)));
    let dmax = (15.0 * meff * v * v / (16.0 * yeff * reff.sqrt())).powf(0.4);
    let tc = 2.0 * hertz_integral() * dmax / v;
    // the seed-002 form t_H = 2.87 (m*²/(R* Y*² v))^{1/5} is the same law, rounded
    let t_h = closures::timestep::hertz_contact_time_with(
        closures::timestep::HERTZ_DURATION_CONSTANT_ROUNDED,
        meff,
        reff,
        yeff,
        v,
    );
    assert!(
        approx::abs_diff_eq!(t_h / tc, 1.0, epsilon = 1e-3),
        "{t_h} vs {tc}"
    );

    let dt = tc / 4000.0;
    let mut s = sim(e_mod, nu, 1.0, 0.5, [0.0; 3], dt);
    s.add_particles(&[
        sphere([-r - 1e-6, 0.0, 0.0], [0.5 * v, 0.0, 0.0], r, rho),
        sphere([r + 1e-6, 0.0, 0.0], [-0.5 * v, 0.0, 0.0], r, rho),
    ])
    .unwrap();
    let mut in_contact = 0u64;
    let mut max_overlap: f64 = 0.0;
    for _ in 0..20_000 {
        s.run(1).unwrap();
        let d = s.particles.x[1][0] - s.particles.x[0][0];
        if d < 2.0 * r {
            in_contact += 1;
            max_overlap = max_overlap.max(2.0 * r - d);
        }
    }
    let t = in_contact as f64 * dt;
    eprintln!("contact time {t:.6e} s (Hertz {tc:.6e} s), overlap {max_overlap:.6e} m (Hertz {dmax:.6e} m)");
    assert!(
        approx::abs_diff_eq!(t / tc, 1.0, epsilon = 1e-3),
        "contact {t} s, Hertz {tc} s"
    );
    assert!(
        approx::abs_diff_eq!(max_overlap / dmax, 1.0, epsilon = 1e-3),
        "{max_overlap} vs {dmax}"
    );
    // elastic: the spheres separate with the speed they came with
    assert_abs_diff_eq!(s.particles.v[1][0], 0.5 * v, epsilon = 1e-6 * v);
    assert!((s.particles.v[0][0] + 0.5 * v).abs() < 1e-6 * v);
}

/// Rebound speed over impact speed of a sphere hitting a wall, no gravity.
fn wall_restitution(e: f64, v: f64) -> f64 {
    let (r, rho) = (1e-3, 2500.0);
    let m = mass(r, rho);
    let yeff = 1e7 / (2.0 * (1.0 - 0.09));
    let dmax = (15.0 * m * v * v / (16.0 * yeff * r.sqrt())).powf(0.4);
    let dt = 2.0 * hertz_integral() * dmax / v / 4000.0;
    let mut s = sim(1e7, 0.3, e, 0.5, [0.0; 3], dt);
    s.add_wall(plane(2, 0.0, ContactModel::default())).unwrap();
    s.add_particles(&[sphere([0.0, 0.0, r + 1e-7], [0.0, 0.0, -v], r, rho)])
        .unwrap();
    while s.particles.x[0][2] < r + 2e-7 {
        s.run(1).unwrap();
    }
    s.particles.v[0][2] / v
}

/// LIGGGHTS's damping γₙ = −2√(5/6)β√(Sₙm*) with β = ln e/√(ln²e + π²) gives a Hertz
/// contact a restitution independent of the impact speed (the damped Hertz oscillator scales
/// with δ_max; Tsuji et al., Powder Technol. 71 (1992) 239) and equal to the e set: measured
/// within 2·10⁻⁴ for e = 0.3…0.9 at dt = t_c/4000 (checked to 10⁻³).
#[test]
fn restitution_is_the_e_set_and_speed_independent() {
    for e in [0.9, 0.5, 0.3] {
        let slow = wall_restitution(e, 0.2);
        let fast = wall_restitution(e, 2.0);
        eprintln!("e set {e}: measured {slow:.5} at 0.2 m/s, {fast:.5} at 2 m/s");
        assert!(
            approx::abs_diff_eq!(slow / fast, 1.0, epsilon = 1e-3),
            "e {e}: {slow} vs {fast}"
        );
        assert!(
            approx::abs_diff_eq!(fast / e, 1.0, epsilon = 1e-3),
            "e {e}: measured {fast}"
        );
    }
    assert_abs_diff_eq!(wall_restitution(1.0, 1.0), 1.0, epsilon = 1e-6);
}

/// Constant gravity: velocity Verlet is exact, z = z₀ + v₀t − gt²/2, v = v₀ − gt.
#[test]
fn free_fall_is_exact() {
    let g = 9.81;
    let dt = 1e-4;
    let mut s = sim(1e7, 0.3, 0.5, 0.5, [0.0, 0.0, -g], dt);
    s.add_particles(&[sphere([0.1, 0.2, 0.5], [0.3, 0.0, 1.5], 1e-3, 2500.0)])
        .unwrap();
    s.run(3000).unwrap();
    let t = 3000.0 * dt;
    let p = &s.particles;
    assert_abs_diff_eq!(
        p.x[0][2],
        (0.5 + 1.5 * t - 0.5 * g * t * t),
        epsilon = 1e-12
    );
    assert_abs_diff_eq!(p.v[0][2], (1.5 - g * t), epsilon = 1e-12);
    assert_abs_diff_eq!(p.x[0][0], (0.1 + 0.3 * t), epsilon = 1e-12);
    assert_abs_diff_eq!(s.time(), t, epsilon = 1e-15);
}

/// A sphere released on a plane with gravity tilted by θ. Below tan θ = 7μ/2 it rolls without
/// slipping, a = (5/7) g sin θ, the contact point at rest; above it slides with
/// a = g (sin θ − μ cos θ) and spins up at ω̇ = 5μg cos θ/(2R) (rigid-body mechanics of a
/// solid sphere, I = 2mR²/5).
#[test]
fn sphere_on_incline_rolls_below_and_slides_above_the_friction_limit() {
    let (r, rho, mu, g): (f64, f64, f64, f64) = (1e-3, 2500.0, 0.3, 9.81);
    let critical = (3.5 * mu).atan();
    for theta in [
        0.5 * critical,
        0.8 * critical,
        1.3 * critical,
        1.8 * critical,
    ] {
        let gv = [g * theta.sin(), 0.0, -g * theta.cos()];
        let mut s = sim(1e7, 0.3, 0.5, mu, gv, 2e-6);
        s.add_wall(plane(2, 0.0, ContactModel::default())).unwrap();
        // start at the static overlap: m g cos θ = (4/3) Y* √R δ^{3/2}
        let m = mass(r, rho);
        let yeff = 1e7 / (2.0 * (1.0 - 0.09));
        let d0 = (m * g * theta.cos() / (4.0 / 3.0 * yeff * r.sqrt())).powf(2.0 / 3.0);
        s.add_particles(&[sphere([0.0, 0.0, r - d0], [0.0; 3], r, rho)])
            .unwrap();
        let t = 0.05;
        s.run((t / 2e-6) as u64).unwrap();
        let p = &s.particles;
        let (v, w) = (p.v[0][0], p.omega[0][1]);
        eprintln!(
            "θ/θc {:.2}: v {v:.6} m/s, ωR {:.6} m/s",
            theta / critical,
            w * r
        );
        if theta < critical {
            let a = 5.0 / 7.0 * g * theta.sin();
            assert!(
                approx::abs_diff_eq!(v / (a * t), 1.0, epsilon = 0.01),
                "θ {theta}: v {v}, rolling {}",
                a * t
            );
            // contact point velocity v − ωR (ω about +y rolls towards +x)
            assert!(
                approx::abs_diff_eq!(v, w * r, epsilon = 0.01 * v),
                "θ {theta}: slip {}",
                v - w * r
            );
        } else {
            let a = g * (theta.sin() - mu * theta.cos());
            assert!(
                approx::abs_diff_eq!(v / (a * t), 1.0, epsilon = 0.01),
                "θ {theta}: v {v}, sliding {}",
                a * t
            );
            let wdot = 5.0 * mu * g * theta.cos() / (2.0 * r);
            assert!(
                approx::abs_diff_eq!(w / (wdot * t), 1.0, epsilon = 0.01),
                "θ {theta}: ω {w} vs {}",
                wdot * t
            );
        }
    }
}

/// Elastic energy stored in a Hertz contact, (8/15) Y* √R* δ^{5/2} (the integral of
/// (4/3) Y* √R* δ^{3/2}).
fn hertz_energy(yeff: f64, reff: f64, d: f64) -> f64 {
    8.0 / 15.0 * yeff * reff.sqrt() * d.powf(2.5)
}

/// e = 1 and μ = 0: kinetic + potential + elastic energy of a gas of spheres bouncing in a box
/// under gravity stays constant (velocity Verlet: bounded error of O(dt²)).
#[test]
fn energy_is_conserved_without_damping_and_friction() {
    use rand::{Rng, SeedableRng};
    let (e_mod, nu, g) = (1e7, 0.3, 9.81);
    let yeff = e_mod / (2.0 * (1.0 - nu * nu));
    let mut s = sim(e_mod, nu, 1.0, 0.0, [0.0, 0.0, -g], 2e-6);
    let l = 0.01;
    for axis in 0..3 {
        s.add_wall(plane(axis, 0.0, ContactModel::default()))
            .unwrap();
        s.add_wall(plane(axis, l, ContactModel::default())).unwrap();
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let mut ps = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            for k in 0..4 {
                let x = [
                    0.0015 + 0.0023 * i as f64,
                    0.0015 + 0.0023 * j as f64,
                    0.0015 + 0.0023 * k as f64,
                ];
                let v = [0, 1, 2].map(|_| rng.gen_range(-0.3..0.3));
                ps.push(sphere(x, v, rng.gen_range(5e-4..9e-4), 2500.0));
            }
        }
    }
    s.add_particles(&ps).unwrap();
    let energy = |s: &dem::Simulation| -> (f64, f64) {
        let p = &s.particles;
        let mut e = p.kinetic_energy();
        let mut elastic = 0.0;
        for i in 0..p.len() {
            e += p.mass[i] * g * p.x[i][2];
            for axis in 0..3 {
                for wall in [0.0, l] {
                    let d = p.radius[i] - (p.x[i][axis] - wall).abs();
                    if d > 0.0 {
                        elastic += hertz_energy(yeff, p.radius[i], d);
                    }
                }
            }
            for j in i + 1..p.len() {
                let dist = (0..3)
                    .map(|k| (p.x[i][k] - p.x[j][k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let d = p.radius[i] + p.radius[j] - dist;
                if d > 0.0 {
                    let reff = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
                    elastic += hertz_energy(yeff, reff, d);
                }
            }
        }
        (e + elastic, elastic)
    };
    s.run(0).unwrap();
    let e0 = energy(&s).0;
    let ke0 = s.particles.kinetic_energy();
    let mut max_elastic: f64 = 0.0;
    let mut drift: f64 = 0.0;
    for _ in 0..400 {
        s.run(50).unwrap();
        let (e, elastic) = energy(&s);
        max_elastic = max_elastic.max(elastic);
        drift = drift.max(((e - e0) / ke0).abs());
        // no friction: no torque, ever
        assert!(s.particles.omega.iter().all(|w| *w == V3::zeros()));
    }
    eprintln!(
        "largest energy drift {drift:.3e} of KE₀, largest elastic energy {max_elastic:.3e} J"
    );
    assert!(drift < 1e-4, "energy drift {drift} of KE₀ {ke0}");
    // contacts did happen (stored elastic energy was seen)
    assert!(max_elastic > 1e-3 * ke0);
}

/// SJKR on a wall without gravity: a touching sphere is pulled in until the Hertz force
/// (4/3)Y*√R δ^{3/2} balances the cohesion k·π(R² − (R − δ)²).
#[test]
fn sjkr_equilibrium_overlap() {
    let (r, rho, k) = (1e-3, 2500.0, 2e4);
    let yeff = 1e7 / (2.0 * (1.0 - 0.09));
    let mut inp = MaterialInput::single(1e7, 0.3, 0.3, 0.5);
    inp.cohesion_energy_density = vec![k];
    let model = ContactModel {
        cohesion: true,
        ..Default::default()
    };
    let mut s = sim_with(inp, model, [0.0; 3], 1e-6);
    s.add_wall(plane(2, 0.0, model)).unwrap();
    s.add_particles(&[sphere([0.0, 0.0, r - 1e-9], [0.0; 3], r, rho)])
        .unwrap();
    s.run(100_000).unwrap();
    let d = r - s.particles.x[0][2];
    // bisection of f(δ) = Hertz − cohesion on (0, R/2)
    let f = |d: f64| 4.0 / 3.0 * yeff * (r * d).sqrt() * d - k * PI * (r * r - (r - d) * (r - d));
    let (mut a, mut b) = (1e-12, 0.5 * r);
    for _ in 0..200 {
        let c = 0.5 * (a + b);
        if f(c) < 0.0 {
            a = c
        } else {
            b = c
        }
    }
    assert!(
        approx::abs_diff_eq!(d / a, 1.0, epsilon = 1e-4),
        "δ {d} vs {a}"
    );
    assert!(s.particles.v[0][2].abs() < 1e-8);
}

/// `rolling_friction cdt` on a sphere rolling on a plane: the constant torque μᵣ Fₙ R decelerates
/// rolling without slip at a = −(5/7) μᵣ g (m a = −f, I ω̇ = f R − μᵣ m g R, a = R ω̇).
#[test]
fn cdt_rolling_friction_decelerates_a_rolling_sphere() {
    let (r, rho, g, mur, v0) = (1e-3, 2500.0, 9.81, 0.05, 0.2);
    let mut inp = MaterialInput::single(1e7, 0.3, 0.5, 0.5);
    inp.rolling_friction = vec![mur];
    let model = ContactModel {
        rolling: Some(RollingModel::Cdt),
        ..Default::default()
    };
    let mut s = sim_with(inp, model, [0.0, 0.0, -g], 2e-6);
    s.add_wall(plane(2, 0.0, model)).unwrap();
    let m = mass(r, rho);
    let yeff = 1e7 / (2.0 * (1.0 - 0.09));
    let d0 = (m * g / (4.0 / 3.0 * yeff * r.sqrt())).powf(2.0 / 3.0);
    s.add_particles(&[NewParticle {
        omega: V3::new(0.0, v0 / (r - d0 / 2.0), 0.0),
        ..sphere([0.0, 0.0, r - d0], [v0, 0.0, 0.0], r, rho)
    }])
    .unwrap();
    let t = 0.1;
    s.run((t / 2e-6) as u64).unwrap();
    let v = s.particles.v[0][0];
    let expect = v0 - 5.0 / 7.0 * mur * g * t;
    eprintln!("cdt: v {v:.6} m/s, expected {expect:.6} m/s");
    assert!(
        approx::abs_diff_eq!((v0 - v) / (v0 - expect), 1.0, epsilon = 0.01),
        "v {v} vs {expect}"
    );
}

/// Coupling: a constant F_ext accelerates exactly (a = F/m); the implicit pair relaxes v to
/// u_f as v = u_f (1 − e^{−βt/m}) (to O(β dt/m) for the explicit update).
#[test]
fn coupling_forces_act_as_adr_0004_says() {
    let (r, rho) = (5e-4, 2000.0);
    let m = mass(r, rho);
    let mut s = sim(1e7, 0.3, 0.5, 0.5, [0.0; 3], 1e-5);
    s.add_particles(&[sphere([0.0; 3], [0.0; 3], r, rho)])
        .unwrap();
    s.set_coupling(&[V3::new(1e-5, 0.0, 0.0)], &[0.0], &[V3::zeros()])
        .unwrap();
    s.run(1000).unwrap();
    let t = 1000.0 * 1e-5;
    assert_abs_diff_eq!(s.particles.v[0][0], 1e-5 / m * t, epsilon = 1e-12);
    let beta = 0.02 * m / 1e-5; // β dt/m = 0.02
    s.particles.v[0] = V3::zeros();
    s.invalidate_forces();
    s.set_coupling(&[V3::zeros()], &[beta], &[V3::new(0.0, 0.1, 0.0)])
        .unwrap();
    s.run(100).unwrap();
    let expect = 0.1 * (1.0 - (-beta * 100.0 * 1e-5 / m).exp());
    assert!(
        approx::abs_diff_eq!(s.particles.v[0][1] / expect, 1.0, epsilon = 0.02),
        "{} vs {expect}",
        s.particles.v[0][1]
    );
    let e = s
        .set_coupling(&[V3::zeros()], &[300.0 * m / 1e-5], &[V3::zeros()])
        .unwrap_err();
    assert!(e.to_string().contains("particle 1"), "{e}");
    let e = s.set_coupling(&[], &[], &[]).unwrap_err();
    assert!(e.to_string().contains("1 particles"), "{e}");
}

/// A pour of 400 spheres of two types (cohesion, epsd2 rolling friction, a cylinder wall)
/// settles bit-identically when rerun, and on 1, 2 or 3 threads alike (the pair forces are
/// summed per particle in a fixed order whatever the split between threads).
#[test]
fn results_are_reproducible_and_independent_of_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let inp = MaterialInput {
                youngs_modulus: vec![1e7, 2e7],
                poissons_ratio: vec![0.3, 0.25],
                restitution: vec![0.5, 0.4, 0.4, 0.6],
                friction: vec![0.5, 0.3, 0.3, 0.4],
                rolling_friction: vec![0.1; 4],
                cohesion_energy_density: vec![1e3; 4],
            };
            Materials::new(&inp).unwrap();
            let model = ContactModel {
                cohesion: true,
                rolling: Some(RollingModel::Epsd2),
                ..Default::default()
            };
            let mut s = sim_with(inp, model, [0.0, 0.0, -9.81], 1e-5);
            s.add_wall(plane(2, 0.0, model)).unwrap();
            s.add_wall(dem::walls::Wall {
                name: "cyl".into(),
                shape: dem::walls::WallShape::Cylinder {
                    axis: 2,
                    radius: 0.006,
                    centre: [0.0, 0.0],
                },
                material_type: 2,
                model,
            })
            .unwrap();
            let mut ps = Vec::new();
            for k in 0..400 {
                let (a, h) = (k as f64 * 2.39996, (k / 20) as f64);
                let rad = 0.0045 * ((k % 20) as f64 / 20.0).sqrt();
                ps.push(NewParticle {
                    atom_type: 1 + (k % 2) as u32,
                    ..sphere(
                        [rad * a.cos(), rad * a.sin(), 0.001 + 0.0011 * h],
                        [0.0; 3],
                        5e-4,
                        2500.0,
                    )
                });
            }
            s.add_particles(&ps).unwrap();
            s.run(3000).unwrap();
            (s.particles.x.clone(), s.particles.omega.clone())
        })
    };
    let one = run(1);
    assert!(one == run(1), "two runs on 1 thread differ");
    let two = run(2);
    assert!(two == run(2), "two runs on 2 threads differ");
    assert!(one == two, "1 and 2 threads differ");
    assert!(one == run(3), "1 and 3 threads differ");
    // the bed has settled into the cylinder
    for r in [&one, &two] {
        assert!(r.0.iter().all(|x| x[2] > 0.0 && x[0].hypot(x[1]) < 0.006));
    }
}

/// During a run the particles are stored in the neighbour list's spatial order; outside it
/// (and in dumps written mid-run) they are in insertion order, each with its own state. Spheres
/// inserted top layer first (so the spatial order, z fastest-varying last, is not the insertion
/// order), too far apart to touch, fall freely for 2000 steps (many list rebuilds): every
/// sphere, by index and in the mid-run dump, is where x₀ + v₀t − ½gt² puts it (velocity
/// Verlet is exact for a constant force; 1e-12 m tolerance for round-off).
#[test]
fn free_fall_keeps_insertion_order_through_the_spatial_storage() {
    let (g, dt) = (9.81, 1e-5);
    let mut s = sim(1e7, 0.3, 0.5, 0.5, [0.0, 0.0, -g], dt);
    let mut start = Vec::new();
    for k in (0..4).rev() {
        for j in 0..5 {
            for i in (0..5).rev() {
                let x = V3::new(i as f64 * 4e-3, j as f64 * 4e-3, k as f64 * 4e-3);
                // distinct drifts (≤ 0.1 mm over the run) tell the spheres apart
                let v = V3::new(1e-4 * (start.len() % 7) as f64, 0.0, -0.5);
                start.push((x, v));
            }
        }
    }
    let new: Vec<NewParticle> = start
        .iter()
        .map(|&(x, v)| sphere(x, v, 5e-4, 2500.0))
        .collect();
    s.add_particles(&new).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let columns = ["id", "x", "y", "z"].map(String::from).to_vec();
    let dump = dem::dump::DumpOutput::new("d", 700, dir.path().join("d_*.txt"), columns).unwrap();
    s.add_dump(dump);
    let at = |k: usize, steps: u64| {
        let t = steps as f64 * dt;
        let (x, v) = start[k];
        x + t * v + V3::new(0.0, 0.0, -0.5 * g * t * t)
    };
    s.run(2000).unwrap();
    let p = &s.particles;
    for k in 0..start.len() {
        assert_eq!(p.id[k], k as u64 + 1);
        assert_abs_diff_eq!((p.x[k] - at(k, 2000)).norm(), 0.0, epsilon = 1e-12);
    }
    let snap = common::last_snapshot(dir.path().join("d_1400.txt"));
    let col = |name: &str| snap.column(name).unwrap().to_vec();
    let (id, x, y, z) = (col("id"), col("x"), col("y"), col("z"));
    for k in 0..start.len() {
        assert_eq!(id[k], (k + 1) as f64);
        let got = V3::new(x[k], y[k], z[k]);
        assert_abs_diff_eq!((got - at(k, 1400)).norm(), 0.0, epsilon = 1e-12);
    }
}
