//! CFDEM-PFM's bed heat models as the run hands them to its sides: the `thermCondModel`
//! ([`couple::config::BedConductivity`]) to the native fluid's temperature equation.

use couple::config::BedConductivity;
use fv::temperature::BedConduction;

/// The native fluid's bed conduction for the `thermCondModel` `bed`, with the fluid's
/// conductivity `lambda` (W/(m·K), the heat model's λ: PFM's `kf`) giving
/// Zehner & Schlünder's ratio A = k_s/λ.
pub fn fluid_bed(bed: BedConductivity, lambda: f64) -> BedConduction {
    match bed {
        BedConductivity::Syamlal => BedConduction::Syamlal,
        BedConductivity::ZehnerSchluender { ks } => BedConduction::ZehnerSchluender {
            ks_over_kf: ks / lambda,
        },
    }
}

/// The coupler's bed heat models for the run of `plan` on `mesh`
/// ([`couple::bed_heat::BedHeat`]): `wallHeatTransferYagi`'s walls, read from the start
/// time's wall temperature and T fields ([`couple::wall_heat::WallHeat::read`]), and
/// `heatTransferInterGrain` on the mesh's faces.
pub fn bed_heat(
    plan: &crate::plan::RunPlan,
    mesh: &foam::PolyMesh,
) -> Result<couple::bed_heat::BedHeat, crate::error::RunError> {
    let config = &plan.layout.coupling;
    let inter_grain = match config.inter_grain {
        Some(g) => Some(couple::inter_grain::InterGrain::new(mesh, g.ks, g.k_max)?),
        None => None,
    };
    let Some(w) = &config.wall_heat else {
        return Ok(couple::bed_heat::BedHeat {
            wall: None,
            inter_grain,
        });
    };
    let case = foam::Case::open(&plan.layout.cfd)?;
    let start = plan.fluid.start_time;
    let dir = case
        .times()?
        .into_iter()
        .find(|t| (t.value - start).abs() <= 1e-12 * start.abs().max(1.0))
        .map(|t| t.path)
        .ok_or_else(|| crate::error::RunError::Setup {
            file: plan.layout.cfd.join("system/controlDict"),
            message: format!("there is no time directory for the start time {start}"),
        })?;
    let wall =
        couple::wall_heat::WallHeat::read(&dir, &w.wall_temp_name, mesh, w.eps_max, w.max_source)?;
    Ok(couple::bed_heat::BedHeat {
        wall: Some(wall),
        inter_grain,
    })
}
