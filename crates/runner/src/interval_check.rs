//! CFDEM's `checkCouplingInterval` during a run ([`couple::interval_check`]): from the first
//! coupling step and then every ⌊timeInterval/Δt_c⌋ steps, the check of the exchange's
//! particles and fluid, reduced over the coupler's ranks, goes to the log; a limit exceeded is
//! a warning line, or with `warnOnly false` an error that ends the run (CFDEM's `FatalError`).

use crate::error::RunError;
use couple::interval_check::{IntervalCheck, IntervalCheckInput, IntervalCheckSettings};
use couple::{Coupler, CouplingStep, FluidState, ParticleState};

/// The check of one run.
pub(crate) struct IntervalChecks {
    settings: IntervalCheckSettings,
    every: u64,
    dt_cfd: f64,
}

impl IntervalChecks {
    /// The checks of `settings` for a run of coupling interval `dt_c` and fluid step `dt_cfd`
    /// (s); `None` when the model is not selected.
    pub(crate) fn new(
        settings: Option<IntervalCheckSettings>,
        dt_c: f64,
        dt_cfd: f64,
    ) -> Option<IntervalChecks> {
        settings.map(|settings| IntervalChecks {
            every: settings.every(dt_c),
            settings,
            dt_cfd,
        })
    }

    /// The report of coupling step `k` (from 1) when one is due, collective over the ranks;
    /// an error when a limit is exceeded and `warnOnly` is off. `fluid_volumes`: the volumes
    /// of the cells `fluid` is given on when they are not the coupler's (rank 0 holding a part
    /// of the mesh, [`crate::whole`]); `u_by_size`: max |U|/∛V over the fluid's cells when the
    /// fluid sent it because `fluid` is not current (rank 0 in grainPisoFoam's sparse
    /// exchange, [`crate::fluid::RunFluid::watched`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn check(
        &self,
        k: u64,
        coupler: &Coupler,
        step: &CouplingStep,
        particles: &ParticleState<'_>,
        fluid: &FluidState<'_>,
        fluid_volumes: Option<&[f64]>,
        u_by_size: Option<f64>,
        dt_c: f64,
    ) -> Result<Option<Vec<String>>, RunError> {
        if !(k - 1).is_multiple_of(self.every) {
            return Ok(None);
        }
        let settings = coupler.settings();
        let u_particle: Vec<_> = step.forces.particles.iter().map(|c| c.u_f).collect();
        let drag = settings.physics.forces.drag.map(|d| d.closure.parcel);
        let input = IntervalCheckInput {
            radius: particles.radius,
            density: particles.density,
            velocity: particles.velocity,
            cell: &step.placement.centre,
            u_particle: &u_particle,
            u: fluid.u,
            volumes: coupler.voidage_mesh().cell_volumes(),
            fluid_volumes: fluid_volumes.unwrap_or(coupler.voidage_mesh().cell_volumes()),
            u_by_size,
            rho: settings.physics.rho,
            nu: settings.physics.nu,
            cg: drag.map_or(1.0, |p| p.cg),
            scale_drag: drag.map_or(1.0, |p| p.scale_drag),
            dt_coupling: dt_c,
            dt_cfd: self.dt_cfd,
        };
        let local = IntervalCheck::compute(&input, self.settings.rho_p);
        let mut x = local.extremes();
        coupler.ranks().all_max(&mut x);
        let (mut lines, over) = local.from_extremes(x).report(&self.settings);
        if !over.is_empty() && !self.settings.warn_only {
            return Err(RunError::Check(format!(
                "checkCouplingInterval (warnOnly false): {}",
                over.join("; ")
            )));
        }
        lines.extend(
            over.into_iter()
                .map(|w| format!("warning: {w}; check your settings")),
        );
        Ok(Some(lines))
    }
}
