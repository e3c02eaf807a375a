//! What the coupler's tests share: particles with tags 1…n ([`Particles`]), and for the bed
//! heat tests a coupler with PFM's heatTransferGunn (explicit, cell values) and no forces, in a
//! gas of ρ 1.2 kg/m³, ν 1e-5 m²/s, λ 0.0256 W/(m K), c_p 1007 J/(kg K).
#![allow(dead_code)]

use closures::heat::{Nusselt, ReynoldsVelocity};
use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use couple::config::{DragSettings, Forces, HeatModel, HeatSettings};
use couple::ParticleState;
use couple::{CouplerSettings, Interpolation, Physics};
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
