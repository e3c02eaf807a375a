//! The simulation's heat state ([`crate::heat`]): created by the deck's `heat/gran` or
//! `couple/cfd/convection`, read and set by the coupler. Per-particle values are in the
//! particle order of [`Simulation::particles`] (insertion order between runs); renumberings,
//! insertions and removals keep them with their particles, as the coupling forces are kept.

use mesh::v3::V3;

use super::Simulation;
use crate::error::DemError;
use crate::heat::{Conduction, Heat};

impl Simulation {
    /// The heat state, if the deck has `heat/gran` or `couple/cfd/convection`.
    pub fn heat(&self) -> Option<&Heat> {
        self.heat.as_ref()
    }

    /// Creates the heat state if there is none: every particle at the default temperature of
    /// `t0` (K; [`crate::heat::liggghts_default`]), capacities per type (J/(kg K)). An existing
    /// state keeps its temperatures and T₀ (LIGGGHTS's equation is created by the first fix);
    /// its capacities are replaced.
    pub fn enable_heat(&mut self, t0: f64, capacity: Vec<f64>) -> Result<&mut Heat, DemError> {
        let ntypes = self.materials.ntypes();
        if capacity.len() != ntypes {
            return Err(DemError::Setup(format!(
                "thermalCapacity has {} values, {ntypes} needed for {ntypes} atom types",
                capacity.len()
            )));
        }
        if !(t0.is_finite() && t0 >= 0.0) {
            return Err(DemError::Setup(format!(
                "initial temperature {t0} K must be ≥ 0"
            )));
        }
        let n = self.particles.len();
        let h = self
            .heat
            .get_or_insert_with(|| Heat::new(t0, Vec::new(), n));
        h.capacity = capacity;
        Ok(h)
    }

    /// Sets `heat/gran`'s conduction (the heat state must exist: [`Simulation::enable_heat`]).
    pub fn set_conduction(&mut self, c: Conduction) -> Result<(), DemError> {
        let ntypes = self.materials.ntypes();
        if c.conductivity.len() != ntypes {
            return Err(DemError::Setup(format!(
                "thermalConductivity has {} values, {ntypes} needed for {ntypes} atom types",
                c.conductivity.len()
            )));
        }
        if let Some(t) = c.conductivity.iter().position(|&k| k < 0.0) {
            return Err(DemError::Setup(format!(
                "thermalConductivity of type {} is {} < 0",
                t + 1,
                c.conductivity[t]
            )));
        }
        let h = self.heat.as_mut().ok_or_else(|| {
            DemError::Setup("conduction needs the heat state (fix heat/gran)".into())
        })?;
        h.conduction = Some(c);
        Ok(())
    }

    /// Gives a primitive wall a temperature (replacing its earlier settings); nothing without
    /// the heat state (the deck executor hands the walls over when it is created).
    pub fn set_wall_heat(&mut self, w: crate::heat::WallHeat) {
        if let Some(h) = &mut self.heat {
            h.walls.retain(|x| x.wall != w.wall);
            h.walls.push(w);
        }
    }

    /// Particle temperatures (K), in the order of [`Simulation::particles`]; `None` without
    /// `heat/gran` or `couple/cfd/convection`.
    pub fn temperature(&self) -> Option<&[f64]> {
        self.heat.as_ref().map(|h| &h.temp[..])
    }

    /// Sets the convective heat flow into each particle (W, in the order of
    /// [`Simulation::particles`]), added to the particle's heat flow at every step from the
    /// next one until changed (`fix couple/cfd/convection`'s `convectiveHeatFlux`). Errors: no
    /// `couple/cfd/convection` fix, a wrong length, a non-finite value (naming the particle).
    pub fn set_convective_heat_flux(&mut self, q: &[f64]) -> Result<(), DemError> {
        let Some(h) = self.heat.as_mut().filter(|h| h.convection) else {
            return Err(DemError::Coupling(
                "convective heat flux: the deck has no `fix ID all couple/cfd/convection T0 …` \
                 (it needs that fix, with `fix … property/global thermalCapacity peratomtype …`)"
                    .into(),
            ));
        };
        let n = self.particles.len();
        if q.len() != n {
            return Err(DemError::Coupling(format!(
                "{n} particles but {} convective heat flows",
                q.len()
            )));
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite()) {
            return Err(DemError::Coupling(format!(
                "particle {}: convective heat flow {} W is not finite",
                self.particles.id[i], q[i]
            )));
        }
        h.convective.clear();
        h.convective.extend_from_slice(q);
        Ok(())
    }

    /// Sets the per-atom heat property `name` — `Temp` (K), `heatFlux` (W) or
    /// `convectiveHeatFlux` (W) — of the particles whose centre satisfies `select` to `value`
    /// (`set … property/atom NAME VALUE`); returns how many. Errors: another name, no heat
    /// state (or no convection fix for `convectiveHeatFlux`), as LIGGGHTS's "Could not identify
    /// the per-atom property".
    pub fn set_per_atom_where(
        &mut self,
        name: &str,
        select: impl Fn(V3) -> bool,
        value: f64,
    ) -> Result<usize, DemError> {
        let missing = || {
            DemError::Setup(format!(
                "no per-atom property `{name}` (the native DEM has Temp and heatFlux with \
                 `fix heat/gran` or `couple/cfd/convection`, convectiveHeatFlux with the latter)"
            ))
        };
        let h = self.heat.as_mut().ok_or_else(missing)?;
        let values = match name {
            "Temp" => &mut h.temp,
            "heatFlux" => &mut h.flux,
            "convectiveHeatFlux" if h.convection => &mut h.convective,
            _ => return Err(missing()),
        };
        let mut n = 0;
        for (x, v) in self.particles.x.iter().zip(values.iter_mut()) {
            if select(*x) {
                *v = value;
                n += 1;
            }
        }
        Ok(n)
    }

    /// Σ m c T over the particles (J): the thermo value of `heat/gran`; `None` without heat.
    pub fn heat_energy(&self) -> Option<f64> {
        self.heat.as_ref().map(|h| h.energy(&self.particles))
    }

    /// Sets temperatures and heat flows by particle id (a restart file's `Temp`, `heatFlux`);
    /// particles not named keep theirs. Errors without the heat state.
    pub fn set_heat_by_id(
        &mut self,
        values: &std::collections::HashMap<u64, (f64, Option<f64>)>,
    ) -> Result<(), DemError> {
        let h = self.heat.as_mut().ok_or_else(|| {
            DemError::Setup("temperatures given but there is no heat state".into())
        })?;
        for (i, id) in self.particles.id.iter().enumerate() {
            if let Some(&(t, q)) = values.get(id) {
                h.temp[i] = t;
                if let Some(q) = q {
                    h.flux[i] = q;
                }
            }
        }
        Ok(())
    }
}
