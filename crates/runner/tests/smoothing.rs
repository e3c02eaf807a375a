//! `smoothingModel constDiffSmoothing` on the coupler with the native diffusion step
//! (`runner::smoothing`), on in-memory sides.

use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use couple::config::{DragSettings, Forces};
use couple::memory::{MemoryFluid, MemoryParticles};
use couple::{Coupler, CouplerSettings, FluidSide, Interpolation, Physics};
use mesh::build::uniform_box;
use mesh::v3::V3;
use std::f64::consts::PI;
use voidage::Method;

/// Water, model A, Di Felice's drag and buoyancy.
fn physics() -> Physics {
    Physics {
        rho: 1000.0,
        nu: 1e-6,
        gravity: V3::new(0.0, 0.0, -9.81),
        model: ModelType::A,
        forces: Forces {
            drag: Some(DragSettings {
                closure: DragClosure::from(DragLaw::DiFelice),
                interpolation: Interpolation::Smooth,
                implicit_dem: false,
                explicit_fluid: false,
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

/// `smoothingModel constDiffSmoothing` on the coupler: the fluid receives the smoothed ε
/// (spread over more cells, the particle volume Σ V(1 − ε) unchanged to round-off), while the
/// particle's drag is computed from its unsmoothed ε (the forces equal those without smoothing).
#[test]
fn smoothing_spreads_the_voidage_the_fluid_gets_and_keeps_the_drag() {
    let d = 1e-3;
    let run = |smooth: bool| {
        let mesh = uniform_box(
            V3::new(0.0, 0.0, 0.0),
            V3::new(0.01, 0.01, 0.01),
            [10, 10, 10],
        );
        let mut fluid = MemoryFluid::uniform(mesh, V3::new(0.0, 0.0, 0.1));
        let mut particles = MemoryParticles::new(
            vec![V3::new(0.0052, 0.0047, 0.005)],
            vec![d / 2.0],
            2500.0,
            1e-5,
        );
        let settings = CouplerSettings {
            method: Method::Exact,
            alpha_min: None,
            coupling_interval: 1,
            physics: physics(),
            heat: None,
        };
        let mut coupler = Coupler::new(fluid.mesh(), settings).unwrap();
        if smooth {
            let s = couple::smoothing::SmoothingSettings {
                length: 1e-3,
                lower: 0.0,
                upper: 1e99,
            };
            coupler.set_smoothing(runner::smoothing::native(fluid.mesh(), s).unwrap());
        }
        let mut drag = V3::zeros();
        coupler
            .run(&mut particles, &mut fluid, 1, |s| {
                drag = s.forces.particles[0].f_ext
            })
            .unwrap();
        let vols = coupler.voidage_mesh().cell_volumes().to_vec();
        (fluid.received[0].voidage_new.clone(), vols, drag)
    };
    let (plain, vols, drag_plain) = run(false);
    let (smooth, _, drag_smooth) = run(true);
    let solid = |e: &[f64]| e.iter().zip(&vols).map(|(x, v)| (1.0 - x) * v).sum::<f64>();
    let particle = PI * d * d * d / 6.0;
    assert!((solid(&plain) - particle).abs() < 1e-12 * particle);
    assert!(
        (solid(&smooth) - particle).abs() < 1e-9 * particle,
        "{}",
        solid(&smooth)
    );
    let touched = |e: &[f64]| e.iter().filter(|&&x| x < 1.0 - 1e-12).count();
    assert!(
        touched(&smooth) > 3 * touched(&plain),
        "{} vs {}",
        touched(&smooth),
        touched(&plain)
    );
    let min = |e: &[f64]| e.iter().copied().fold(1.0, f64::min);
    assert!(min(&smooth) > min(&plain));
    assert!(smooth.iter().all(|&x| x <= 1.0));
    assert_eq!(drag_plain, drag_smooth);
    assert!(drag_plain.norm() > 0.0);
}
