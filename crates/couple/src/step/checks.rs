//! The checks [`Coupler::exchange`] makes before it places anything: what added mass and lift
//! need, and the Ksl forms several ranks allow.

use super::Coupler;
use crate::error::CoupleError;
use crate::ksl::UsAveraging;
use crate::sides::{FluidState, ParticleState};

impl Coupler {
    /// What added mass and lift need (module docs of [`crate::forces`]): the fluid's vorticity
    /// or DU/Dt when a model asks for them (on one rank: the fields of other ranks' touched
    /// cells do not carry them), the coupling interval, and C_add ρ_f < ρ_p for every particle
    /// (the lagged particle acceleration diverges otherwise).
    pub(super) fn check_added_mass_and_lift(
        &self,
        particles: &ParticleState<'_>,
        fluid: &FluidState<'_>,
    ) -> Result<(), CoupleError> {
        let physics = &self.settings.physics;
        let forces = &physics.forces;
        let several = self.ranks.size() > 1 || self.owners.is_some();
        let fields = [
            (
                forces.needs_vorticity(),
                fluid.vorticity.is_some(),
                "MeiLift/SaffmanLift",
                "vorticity ∇ × U",
            ),
            (
                forces.needs_ddt_u(),
                fluid.ddt_u.is_some(),
                "virtualMassForce with splitUrelCalculation",
                "DU/Dt",
            ),
            (
                forces.needs_turbulence(),
                fluid.turbulence.is_some(),
                "KochHillRWDrag",
                "k and epsilon (a k-epsilon model)",
            ),
        ];
        for (needed, given, model, what) in fields {
            if needed && several {
                return Err(CoupleError::Parameter(format!(
                    "{model} needs the fluid's {what}, which the exchange on several coupler \
                     ranks does not carry: run one coupler rank"
                )));
            }
            if needed && !given {
                return Err(CoupleError::Parameter(format!(
                    "{model} needs the fluid's {what}, which this fluid side does not give"
                )));
            }
        }
        if forces.needs_turbulence() && self.coupling_dt.is_none() {
            return Err(CoupleError::Parameter(
                "KochHillRWDrag needs the coupling interval's length (its eddies' lifetimes; \
                 Coupler::set_coupling_time_step)"
                    .into(),
            ));
        }
        let Some(vm) = forces.virtual_mass else {
            return Ok(());
        };
        if self.coupling_dt.is_none() {
            return Err(CoupleError::Parameter(
                "virtualMassForce needs the coupling interval's length \
                 (Coupler::set_coupling_time_step)"
                    .into(),
            ));
        }
        let limit = vm.c_add * physics.rho;
        if let Some(i) = (0..particles.len()).find(|&i| particles.density[i] <= limit) {
            return Err(CoupleError::Particle {
                index: i,
                id: Some(particles.ids[i]),
                message: format!(
                    "density {} ≤ Cadd·ρ_f = {limit}: the added mass's particle acceleration, \
                     lagged one coupling step, would diverge",
                    particles.density[i]
                ),
            });
        }
        Ok(())
    }

    /// CFDEM's Ksl form with `dilute` averaging on several ranks is an error: "the last
    /// particle in the cell" depends on how the particles are spread over the ranks.
    pub(super) fn check_ksl_form(&self) -> Result<(), CoupleError> {
        let dilute = self
            .ksl_form
            .cfdem()
            .is_some_and(|k| k.averaging == UsAveraging::Dilute);
        if dilute && (self.ranks.size() > 1 || self.owners.is_some()) {
            return Err(CoupleError::Parameter(
                "averagingModel dilute (Us = the last particle's velocity in each cell) on \
                 several coupler ranks: which particle is last depends on the ranks; use \
                 averagingModel dense, or one coupler rank"
                    .into(),
            ));
        }
        Ok(())
    }
}
