//! CFDEM's Ksl form ([`couple::ksl`]) through the coupler, against hand calculation:
//! * one cell, three particles with different velocities: Ksl = |Σ β (U − v)| / (V |U − Us|)
//!   with Us the mean particle velocity (CFDEM's dense averaging, equal shares), and the
//!   conserving form Σ β / V with the β-weighted Us, from each particle's β and v;
//! * many cells whose particles share one velocity per cell, centre interpolation (u_p = U of
//!   the cell): the two forms give the same Ksl (to round-off) and the same Us.

mod common;

use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use common::Particles;
use couple::config::{DragSettings, Forces};
use couple::ksl::{CfdemKsl, KslForm};
use couple::{Coupler, CouplerSettings, FluidState, Interpolation, Physics};
use mesh::build::uniform_box;
use mesh::v3::V3;
use voidage::Method;

fn settings() -> CouplerSettings {
    CouplerSettings {
        method: Method::Centre,
        alpha_min: None,
        coupling_interval: 10,
        physics: Physics {
            rho: 1.2,
            nu: 1.5e-5,
            gravity: V3::zeros(),
            model: ModelType::B,
            forces: Forces {
                drag: Some(DragSettings {
                    closure: DragClosure::from(DragLaw::SchillerNaumann),
                    interpolation: Interpolation::Cell,
                    implicit_dem: true,
                    explicit_fluid: false,
                    dem_only: false,
                }),
                grad_p: None,
                viscous: None,
                archimedes: false,
                no_drag: None,
                virtual_mass: None,
                mei_lift: None,
                saffman_lift: None,
                random_walk: None,
            },
            implicit_couple: true,
        },
        heat: None,
    }
}

/// The exchange of `particles` in the fluid `u` (per cell) on `mesh` with `form`.
fn exchange(
    mesh: &foam::PolyMesh,
    u: &[V3],
    particles: &Particles,
    form: KslForm,
) -> couple::CouplingStep {
    let mut coupler = Coupler::new(mesh, settings()).unwrap();
    coupler.set_ksl_form(form);
    let n = mesh.n_cells;
    let zero = vec![V3::zeros(); n];
    let fluid = FluidState {
        u,
        p: &vec![0.0; n],
        grad_p: &zero,
        div_tau: &zero,
        temperature: None,
        vorticity: None,
        ddt_u: None,
        turbulence: None,
    };
    coupler.exchange(&particles.state(), &fluid).unwrap()
}

const CFDEM: KslForm = KslForm::Cfdem(CfdemKsl {
    limit: 1e10,
    max_voidage: 1.0 - 1e-15,
    averaging: couple::ksl::UsAveraging::Dense,
});

#[test]
fn one_cell_by_hand() {
    let mesh = uniform_box(V3::zeros(), V3::new(0.1, 0.1, 0.1), [1, 1, 1]);
    let volume = 1e-3;
    let u = [V3::new(0.5, 0.0, 0.2)];
    let p = Particles::new(
        vec![
            V3::new(0.02, 0.05, 0.05),
            V3::new(0.05, 0.05, 0.05),
            V3::new(0.08, 0.03, 0.07),
        ],
        vec![
            V3::new(0.1, 0.0, 0.0),
            V3::new(0.0, 0.3, -0.1),
            V3::new(-0.2, 0.1, 0.4),
        ],
    );
    let cfdem = exchange(&mesh, &u, &p, CFDEM);
    let cons = exchange(&mesh, &u, &p, KslForm::Conserving);
    let beta: Vec<f64> = cfdem
        .forces
        .particles
        .iter()
        .map(|c| c.beta_fluid)
        .collect();
    assert!(beta.iter().all(|&b| b > 0.0));
    // by hand: F = Σ β (U − v), Us = mean v, Ksl = |F| / (V |U − Us|)
    let mut f = V3::zeros();
    let mut mean = V3::zeros();
    let (mut sb, mut sbv) = (0.0, V3::zeros());
    for (b, v) in beta.iter().zip(&p.velocity) {
        f += (u[0] - *v) * *b;
        mean += *v / 3.0;
        sb += b;
        sbv += *v * *b;
    }
    let ksl = f.norm() / (volume * (u[0] - mean).norm());
    let got = &cfdem.exchange;
    assert!(
        (got.ksl[0] - ksl).abs() <= 1e-12 * ksl,
        "{} {ksl}",
        got.ksl[0]
    );
    assert!(
        (got.us[0] - mean).norm() <= 1e-15,
        "{:?} {mean:?}",
        got.us[0]
    );
    let got = &cons.exchange;
    assert!((got.ksl[0] - sb / volume).abs() <= 1e-12 * ksl);
    assert!((got.us[0] - sbv / sb).norm() <= 1e-15);
    // the forms differ here (different velocities): by more than round-off
    assert!((cfdem.exchange.ksl[0] - cons.exchange.ksl[0]).abs() > 1e-3 * ksl);
    // β and f are the same in both
    assert_eq!(cfdem.exchange.f, cons.exchange.f);
}

#[test]
fn the_forms_agree_when_a_cell_has_one_particle_velocity() {
    let n = [4, 3, 5];
    let mesh = uniform_box(V3::zeros(), V3::new(0.04, 0.03, 0.05), n);
    let cells = mesh.n_cells;
    let centres = mesh::geometry::MeshGeometry::new(&mesh)
        .unwrap()
        .cell_centres;
    let u: Vec<V3> = centres
        .iter()
        .map(|x| V3::new(1.0 + 10.0 * x[2], -3.0 * x[0], 0.5 + 20.0 * x[1]))
        .collect();
    // four particles around each cell centre, all with the velocity of their cell
    let (mut position, mut velocity) = (Vec::new(), Vec::new());
    for (c, x) in centres.iter().enumerate() {
        let v = V3::new(0.1 * c as f64, -0.05, 0.02 * (c % 7) as f64);
        for k in 0..4 {
            let d = 1e-3 * k as f64;
            position.push(*x + V3::new(d, -d, 0.5 * d));
            velocity.push(v);
        }
    }
    let p = Particles::new(position, velocity);
    let cfdem = exchange(&mesh, &u, &p, CFDEM);
    let cons = exchange(&mesh, &u, &p, KslForm::Conserving);
    for c in 0..cells {
        let (a, b) = (cfdem.exchange.ksl[c], cons.exchange.ksl[c]);
        assert!(b > 0.0);
        assert!((a - b).abs() <= 1e-12 * b, "cell {c}: {a} {b}");
        let (ua, ub) = (cfdem.exchange.us[c], cons.exchange.us[c]);
        assert!((ua - ub).norm() <= 1e-14 * ub.norm().max(1.0), "cell {c}");
    }
}

/// `averagingModel dilute` with CFDEM's form: Us of the cell is the last particle's velocity
/// (CFDEM's `dilute::setVectorAverage`), and Ksl = |Σ β (U − v)| / (V |U − v_last|).
#[test]
fn dilute_us_is_the_last_particles_velocity() {
    let mesh = uniform_box(V3::zeros(), V3::new(0.1, 0.1, 0.1), [1, 1, 1]);
    let u = [V3::new(0.5, 0.0, 0.2)];
    let p = Particles::new(
        vec![V3::new(0.02, 0.05, 0.05), V3::new(0.08, 0.03, 0.07)],
        vec![V3::new(0.1, 0.0, 0.0), V3::new(-0.2, 0.1, 0.4)],
    );
    let dilute = KslForm::Cfdem(CfdemKsl {
        averaging: couple::ksl::UsAveraging::Dilute,
        ..CfdemKsl::default()
    });
    let s = exchange(&mesh, &u, &p, dilute);
    assert_eq!(s.exchange.us[0], p.velocity[1]);
    let mut f = V3::zeros();
    for (c, v) in s.forces.particles.iter().zip(&p.velocity) {
        f += (u[0] - *v) * c.beta_fluid;
    }
    let ksl = f.norm() / (1e-3 * (u[0] - p.velocity[1]).norm());
    assert!((s.exchange.ksl[0] - ksl).abs() <= 1e-12 * ksl);
}
