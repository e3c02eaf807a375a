//! What the coupler's tests share: particles with tags 1…n ([`Particles`]), and for the bed
//! heat tests a coupler with PFM's heatTransferGunn (explicit, cell values) and no forces, in a
//! gas of ρ 1.2 kg/m³, ν 1e-5 m²/s, λ 0.0256 W/(m K), c_p 1007 J/(kg K); for the tests of
//! parts of the mesh a cluster of spheres and fluid fields varying in space.
#![allow(dead_code)]

use closures::heat::{Nusselt, ReynoldsVelocity};
use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use couple::config::{DragSettings, Forces, HeatModel, HeatSettings};
use couple::memory::MemoryFluid;
use couple::ParticleState;
use couple::{CouplerSettings, Interpolation, Physics};
use foam::PolyMesh;
use mesh::v3::V3;
use voidage::Method;

pub const RHO: f64 = 1.2;
pub const NU: f64 = 1e-5;
pub const LAMBDA: f64 = 0.0256;
pub const CP: f64 = 1007.0;

/// The coupler's settings with the voidage `method`.
pub fn gunn_settings(method: Method) -> CouplerSettings {
    CouplerSettings {
        method,
        alpha_min: None,
        coupling_interval: 1,
        physics: Physics {
            rho: RHO,
            nu: NU,
            gravity: V3::zeros(),
            model: ModelType::A,
            forces: Forces::default(),
            implicit_couple: true,
        },
        heat: Some(HeatSettings {
            model: HeatModel::HeatTransferGunn,
            nusselt: Nusselt::GunnPfm,
            reynolds: ReynoldsVelocity::Superficial,
            voidage_floor: 0.01,
            nusselt_scale: 1.0,
            lambda: LAMBDA,
            cp: CP,
            prandtl: None,
            max_source: None,
            interpolation: Interpolation::Cell,
        }),
    }
}

/// The coupler's settings with the voidage `method`, the drag `law` (φ 0.3 where the law
/// reads it) interpolated by `rule` together with ∇p, ∇·τ at the centre cell, Archimedes, model
/// A, gravity −9.81 z, in a fluid of density `rho` (kg/m³) and viscosity `nu` (m²/s).
pub fn drag_settings(
    method: Method,
    law: DragLaw,
    rule: Interpolation,
    rho: f64,
    nu: f64,
) -> CouplerSettings {
    CouplerSettings {
        method,
        alpha_min: None,
        coupling_interval: 1,
        physics: Physics {
            rho,
            nu,
            gravity: V3::new(0.0, 0.0, -9.81),
            model: ModelType::A,
            forces: Forces {
                drag: Some(DragSettings {
                    closure: DragClosure::new(law, 0.3).unwrap(),
                    interpolation: rule,
                    implicit_dem: true,
                    explicit_fluid: false,
                    dem_only: false,
                }),
                grad_p: Some(rule),
                viscous: Some(Interpolation::Cell),
                archimedes: true,
                no_drag: None,
                ..Forces::default()
            },
            implicit_couple: true,
        },
        heat: None,
    }
}

/// Particles with tags 1…n, d = 2 mm and ρ_p = 2500 kg/m³ unless changed.
pub struct Particles {
    pub ids: Vec<u64>,
    pub position: Vec<V3>,
    pub velocity: Vec<V3>,
    pub radius: Vec<f64>,
    pub density: Vec<f64>,
}

impl Particles {
    pub fn new(position: Vec<V3>, velocity: Vec<V3>) -> Particles {
        let n = position.len();
        Particles {
            ids: (1..=n as u64).collect(),
            position,
            velocity,
            radius: vec![1e-3; n],
            density: vec![2500.0; n],
        }
    }

    pub fn state(&self) -> ParticleState<'_> {
        ParticleState {
            ids: &self.ids,
            position: &self.position,
            velocity: &self.velocity,
            radius: &self.radius,
            density: &self.density,
            temperature: None,
        }
    }
}

/// Fields varying in space over the cells of `mesh` at centres `x`.
pub fn varying_fluid(mesh: &PolyMesh, x: &[V3]) -> MemoryFluid {
    let mut f = MemoryFluid::uniform(mesh.clone(), V3::zeros());
    f.u = x
        .iter()
        .map(|c| V3::new(c[1], -c[0], 0.5 + c[2] * c[2]))
        .collect();
    f.p = x.iter().map(|c| 10.0 * c[2] + c[0]).collect();
    f.grad_p = x
        .iter()
        .map(|c| V3::new(0.1 * c[1], 0.0, 9.0 + c[0]))
        .collect();
    f.div_tau = x.iter().map(|c| V3::new(c[2], c[0] * c[1], -0.2)).collect();
    f
}

/// DiFelice drag with the smooth interpolation in a gas (ρ 1.2, ν 1.5e-5), voidage `method`.
pub fn varying_settings(method: Method) -> CouplerSettings {
    drag_settings(
        method,
        DragLaw::DiFelice,
        Interpolation::Smooth,
        1.2,
        1.5e-5,
    )
}

/// A cluster of 40 spheres (radius 0.012–0.02 m) about `at`, ids 1…40.
pub fn cluster(at: V3) -> Particles {
    let n = 40;
    let pos = (0..n)
        .map(|k| {
            let s = k as f64;
            at + 0.08 * V3::new((s * 1.7).sin(), (s * 0.9).cos(), (s * 2.3).sin())
        })
        .collect();
    let vel = (0..n)
        .map(|k| V3::new(0.1, 0.0, -0.01 * k as f64))
        .collect();
    let mut c = Particles::new(pos, vel);
    c.radius = (0..n).map(|k| 0.012 + 0.0002 * k as f64).collect();
    c
}
