//! Coarse-grained parcels (LIGGGHTS-PFM's `coarsegraining CG`) in the coupler, as
//! CFDEMcoupling-PFM treats them.
//!
//! PFM's `cfdemCloud` takes CG from LIGGGHTS (`dataExchangeModel::getCG`, LIGGGHTS's
//! `force->cg()`); a drag model uses its Props' `scale` when that is > 1 and CG otherwise
//! ([`closures::Parcel`]: the law at the real diameter d/CG, times CG³ and `scaleDrag`). The
//! voidage models deposit each parcel's own volume (no factor: a parcel's volume is that of its
//! CG³ particles), and the forces proportional to the particle volume (`gradPForce`,
//! `viscForce`, `Archimedes`) act on the parcel's volume as they are. foamgrain reads CG from
//! the coupled deck (`liggghts_deck::Deck::coarse_graining`) and hands it here.
//!
//! Where PFM would silently prefer one of two factors, foamgrain refuses: a Props `scale` > 1
//! that differs from the deck's CG > 1 is an error. The heat transfer, whose Nusselt number
//! PFM's `heatTransferGunn` also evaluates at d/CG, is refused with CG > 1 (foamgrain's heat
//! models do not scale it).

use crate::error::CoupleError;
use crate::step::CouplerSettings;
use std::path::Path;

impl CouplerSettings {
    /// These settings for particles that are parcels of factor `cg` (the deck's
    /// `coarsegraining`, 1 without; `deck` names it in errors, `config` is
    /// `couplingProperties`). With `cg` = 1 and no Props `scale` the settings are unchanged.
    pub fn with_coarse_graining(
        mut self,
        cg: f64,
        deck: &str,
        config: &Path,
    ) -> Result<CouplerSettings, CoupleError> {
        let err = |key: String, message: String| CoupleError::Config {
            file: config.to_path_buf(),
            key,
            message,
        };
        if let Some(drag) = self.physics.forces.drag.as_mut() {
            let parcel = &mut drag.closure.parcel;
            let name = drag.closure.law.cfdem_name();
            if parcel.cg > 1.0 && cg > 1.0 && parcel.cg != cg {
                return Err(err(
                    format!("{name}Props/scale"),
                    format!(
                        "{} disagrees with the deck's coarsegraining {cg} ({deck}); give one \
                         factor (PFM would use the Props' scale for the drag only)",
                        parcel.cg
                    ),
                ));
            }
            if parcel.cg == 1.0 {
                parcel.cg = cg;
            }
        }
        let effective = self
            .physics
            .forces
            .drag
            .map_or(cg, |d| d.closure.parcel.cg.max(cg));
        if effective > 1.0 && self.heat.is_some() {
            return Err(err(
                "heat transfer".into(),
                format!(
                    "coarse graining (factor {effective}, {deck}) with heat transfer is not \
                     supported: foamgrain's Nusselt laws would see the parcels' diameter"
                ),
            ));
        }
        Ok(self)
    }

    /// The parcels' factor CG the drag uses (1 for real particles or without drag).
    pub fn coarse_graining(&self) -> f64 {
        self.physics
            .forces
            .drag
            .map_or(1.0, |d| d.closure.parcel.cg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{DragSettings, Forces};
    use crate::{Interpolation, Physics};
    use closures::model::ModelType;
    use closures::{DragClosure, DragLaw, Parcel};
    use mesh::v3::V3;
    use voidage::Method;

    fn settings(props_scale: f64) -> CouplerSettings {
        let closure = DragClosure::from(DragLaw::GIDASPOW)
            .with_parcel(Parcel::new(props_scale, 1.0).unwrap());
        CouplerSettings {
            method: Method::Divided,
            alpha_min: None,
            coupling_interval: 100,
            physics: Physics {
                rho: 10.0,
                nu: 1.5e-4,
                gravity: V3::zeros(),
                model: ModelType::A,
                forces: Forces {
                    drag: Some(DragSettings {
                        closure,
                        interpolation: Interpolation::Cell,
                        implicit_dem: false,
                        explicit_fluid: false,
                        dem_only: false,
                    }),
                    ..Forces::default()
                },
                implicit_couple: true,
            },
            heat: None,
        }
    }

    #[test]
    fn the_decks_factor_reaches_the_drag_unless_props_give_one() {
        let file = Path::new("constant/couplingProperties");
        let real = settings(1.0).with_coarse_graining(1.0, "", file).unwrap();
        assert_eq!(real, settings(1.0));
        let s = settings(1.0)
            .with_coarse_graining(2.0, "in:3", file)
            .unwrap();
        assert_eq!(s.coarse_graining(), 2.0);
        // PFM's `scale` > 1 wins over a deck without coarse graining; an equal one agrees
        let s = settings(3.0).with_coarse_graining(1.0, "", file).unwrap();
        assert_eq!(s.coarse_graining(), 3.0);
        let s = settings(3.0)
            .with_coarse_graining(3.0, "in:3", file)
            .unwrap();
        assert_eq!(s.coarse_graining(), 3.0);
        let e = settings(3.0)
            .with_coarse_graining(2.0, "DEM/in.run:7", file)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("GidaspowDragProps/scale") && e.contains("DEM/in.run:7"),
            "{e}"
        );
    }

    #[test]
    fn heat_with_parcels_is_refused() {
        let file = Path::new("constant/couplingProperties");
        let mut s = settings(1.0);
        s.heat = Some(crate::config::HeatSettings {
            model: crate::config::HeatModel::LaEuScalarTemp,
            nusselt: closures::Nusselt::Deen,
            reynolds: closures::heat::ReynoldsVelocity::Interstitial,
            voidage_floor: 0.0,
            nusselt_scale: 1.0,
            lambda: 0.0256,
            cp: 1007.0,
            prandtl: None,
            max_source: None,
            interpolation: Interpolation::Cell,
        });
        let e = s
            .with_coarse_graining(2.0, "in:3", file)
            .unwrap_err()
            .to_string();
        assert!(e.contains("heat transfer is not supported"), "{e}");
    }
}
