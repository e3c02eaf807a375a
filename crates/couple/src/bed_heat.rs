//! CFDEM-PFM's bed heat models beside a heat transfer model ([`BedHeat`]): the walls' heat into
//! the fluid ([`crate::wall_heat`], `wallHeatTransferYagi`) and the particles' continuum
//! conduction ([`crate::inter_grain`], `heatTransferInterGrain`), added to each exchange's
//! heat step on one coupler rank ([`crate::Coupler::set_bed_heat`]).

use crate::error::CoupleError;
use crate::heat::{particle_temperatures, CellFields};
use crate::inter_grain::InterGrain;
use crate::interpolate::Placement;
use crate::sides::ParticleState;
use crate::wall_heat::{At, WallHeat, WallProperties};
use crate::{CouplerSettings, HeatStep};

/// The bed heat models of a run (none by default).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BedHeat {
    /// `wallHeatTransferYagi`'s walls.
    pub wall: Option<WallHeat>,
    /// `heatTransferInterGrain`.
    pub inter_grain: Option<InterGrain>,
}

impl BedHeat {
    /// An error when a model is on and `several` coupler ranks (or the cells' owners) share
    /// the particles: the models' cell averages need every particle on one rank.
    pub fn check_ranks(&self, several: bool) -> Result<(), CoupleError> {
        match several && (self.wall.is_some() || self.inter_grain.is_some()) {
            true => Err(CoupleError::Parameter(
                "wallHeatTransferYagi and heatTransferInterGrain run on one coupler rank \
                 (their cell averages of the particles are summed there); run one coupler rank"
                    .into(),
            )),
            false => Ok(()),
        }
    }

    /// Adds the models to the heat step `h` of the particles `at` in the fluid `cells` of
    /// volumes `volumes` (m³), with the fluid and heat properties of `settings`.
    pub fn add_to(
        &self,
        h: &mut HeatStep,
        at: (&Placement, &ParticleState<'_>),
        cells: CellFields<'_>,
        volumes: &[f64],
        settings: &CouplerSettings,
    ) -> Result<(), CoupleError> {
        let (placement, particles) = at;
        if let (Some(wall), Some(heat)) = (&self.wall, &settings.heat) {
            let props = WallProperties {
                rho: settings.physics.rho,
                nu: settings.physics.nu,
                lambda: heat.lambda,
                cp: heat.cp,
            };
            let at = At {
                placement,
                radius: particles.radius,
            };
            wall.add_to(h, at, cells, volumes, props)?;
        }
        if let Some(g) = &self.inter_grain {
            let t = particle_temperatures(particles)?;
            g.add_to(h, placement, t, cells.eps)?;
        }
        Ok(())
    }
}
