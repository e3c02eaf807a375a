//! What the bed heat tests share: a coupler with PFM's heatTransferGunn (explicit, cell
//! values) and no forces, in a gas of ρ 1.2 kg/m³, ν 1e-5 m²/s, λ 0.0256 W/(m K), c_p 1007
//! J/(kg K).

use closures::heat::{Nusselt, ReynoldsVelocity};
use closures::model::ModelType;
use couple::config::{Forces, HeatModel, HeatSettings};
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
