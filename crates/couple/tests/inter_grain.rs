//! CFDEM-PFM's `heatTransferInterGrain` (`couple::inter_grain`) against closed forms: a bed of
//! uniform solid fraction in a column of 5 cells, particles on a lattice wholly inside their
//! cells. The conduction is the exchange's q with the model minus q without it.
//! * k_eff = ½(3α − 1) k_s by hand (Qian et al.'s form as PFM computes it);
//! * a linear particle temperature T = T0 + G x is steady 1-D conduction: Fourier's heat
//!   k_eff A G leaves the hot end cell and enters the cold one, nothing in between;
//! * a quadratic T = T0 + a x² gives ∇·(k_eff ∇T) = 2 a k_eff in the inner cells;
//! * the particles' conduction sums to zero (the bed's boundary is insulated), counted in the
//!   account; a bed below α = 0.334 conducts nothing.

mod common;
use couple::bed_heat::BedHeat;
use couple::inter_grain::{effective_conductivity, InterGrain};
use couple::{Coupler, CouplerSettings, FluidState, ParticleState};
use mesh::build::uniform_box;
use mesh::v3::V3;
use voidage::Method;

const KS: f64 = 2.0;
const H: f64 = 0.01;

fn settings() -> CouplerSettings {
    common::gunn_settings(Method::Exact)
}

/// 5 × 5 × 5 spheres of diameter `d` per 1 cm cell (centres 1, 3, …, 9 mm into the cell),
/// five cells along x; the particles' x.
fn lattice(d: f64) -> (Vec<V3>, Vec<f64>) {
    let mut pos = Vec::new();
    for c in 0..5 {
        for i in 0..5 {
            for j in 0..5 {
                for k in 0..5 {
                    let at = |n: usize| 1e-3 * (1.0 + 2.0 * n as f64);
                    pos.push(V3::new(c as f64 * H + at(i), at(j), at(k)));
                }
            }
        }
    }
    let rad = vec![0.5 * d; pos.len()];
    (pos, rad)
}

/// The conduction each particle receives (W) for temperatures `temp(x)` and the account's sum.
fn conduction(d: f64, temp: impl Fn(f64) -> f64) -> (Vec<f64>, f64) {
    let mesh = uniform_box(V3::zeros(), V3::new(5.0 * H, H, H), [5, 1, 1]);
    let (pos, rad) = lattice(d);
    let n = pos.len();
    let temperature: Vec<f64> = pos.iter().map(|p| temp(p[0])).collect();
    let (vel, ids, den) = (
        vec![V3::zeros(); n],
        (1..=n as u64).collect::<Vec<_>>(),
        vec![2500.0; n],
    );
    let particles = ParticleState {
        ids: &ids,
        position: &pos,
        velocity: &vel,
        radius: &rad,
        density: &den,
        temperature: Some(&temperature),
    };
    let (u, zero, p, t) = (
        vec![V3::zeros(); 5],
        vec![V3::zeros(); 5],
        vec![0.0; 5],
        vec![300.0; 5],
    );
    let fluid = FluidState {
        vorticity: None,
        ddt_u: None,
        turbulence: None,
        u: &u,
        p: &p,
        grad_p: &zero,
        div_tau: &zero,
        temperature: Some(&t),
    };
    let plain = Coupler::new(&mesh, settings())
        .unwrap()
        .exchange(&particles, &fluid)
        .unwrap();
    let mut c = Coupler::new(&mesh, settings()).unwrap();
    c.set_bed_heat(BedHeat {
        wall: None,
        inter_grain: Some(InterGrain::new(&mesh, KS, None).unwrap()),
    });
    let with = c.exchange(&particles, &fluid).unwrap();
    let (h0, h) = (plain.heat.unwrap(), with.heat.unwrap());
    assert_eq!(h.account.to_particles, h0.account.to_particles);
    assert_eq!(
        h.tsource, h0.tsource,
        "the conduction stays among the particles"
    );
    let q = h.q.iter().zip(&h0.q).map(|(a, b)| a - b).collect();
    (q, h.account.between_particles)
}

/// α = 125 (π/6) d³ / 1 cm³ for d = 1.9 mm: 0.4489205…; k_eff = ½(3α − 1)·2 W/(m K) =
/// 0.3467615… W/(m K) (by hand, python: 125 π 1.9³/6/1000).
fn k_eff() -> f64 {
    let alpha = 0.448_920_500_228_591_4;
    assert!((effective_conductivity(alpha, KS) - 0.346_761_500_685_774_27).abs() < 1e-15);
    0.5 * (3.0 * alpha - 1.0) * KS
}

#[test]
fn a_linear_profile_conducts_fouriers_heat_end_to_end() {
    let g = 1000.0; // K/m
    let (q, total) = conduction(1.9e-3, |x| 300.0 + g * x);
    let fourier = k_eff() * H * H * g; // W through the 1 cm² cross-section
    for (i, &qi) in q.iter().enumerate() {
        let want = match i / 125 {
            0 => fourier / 125.0,
            4 => -fourier / 125.0,
            _ => 0.0,
        };
        assert!(
            (qi - want).abs() <= 1e-9 * fourier / 125.0,
            "particle {i}: {qi} vs {want}"
        );
    }
    assert!(total.abs() <= 1e-12 * fourier, "{total}");
}

#[test]
fn a_quadratic_profile_gives_the_laplacian() {
    let a = 1e4; // K/m²
    let (q, total) = conduction(1.9e-3, |x| 300.0 + a * x * x);
    let inner = 2.0 * a * k_eff() * H * H * H / 125.0; // 2 a k_eff V_c per particle
    for (i, &qi) in q
        .iter()
        .enumerate()
        .filter(|(i, _)| (1..4).contains(&(i / 125)))
    {
        assert!(
            (qi - inner).abs() <= 1e-9 * inner,
            "particle {i}: {qi} vs {inner}"
        );
    }
    let scale: f64 = q.iter().map(|x| x.abs()).sum();
    assert!(total.abs() <= 1e-12 * scale, "{total}");
    assert!((q.iter().sum::<f64>() - total).abs() <= 1e-12 * scale);
}

#[test]
fn a_loose_bed_conducts_nothing() {
    // d = 1.5 mm: α = 0.2209 < 0.334
    let (q, total) = conduction(1.5e-3, |x| 300.0 + 1000.0 * x);
    assert!(q.iter().all(|&x| x == 0.0));
    assert_eq!(total, 0.0);
}
