//! Rank 0 on a part of the mesh while the fluid is on rank 0 (the native fluid on several
//! coupler ranks, [`Coupler::set_root_volumes`]).
//!
//! Rank 0 then plays two roles that [`Coupler::exchange`] on a whole mesh plays in the same
//! arrays. As a placing rank it is like every other rank: its particles are placed on its part
//! of the mesh ([`crate::part`]), its touched cells are mapped to the whole mesh's labels, and
//! its particles' forces come from ε and the fluid at its touched cells
//! ([`Coupler::forces_at`]). As the root it sums every rank's touched cells (its own first, in
//! rank order, as before) into whole-length arrays: the solid volume, ε from the whole mesh's
//! cell volumes, the records each rank is sent, and Ksl, Us, f (and the heat per cell) handed
//! to the fluid; smoothing, when configured, diffuses ε on the mesh it was built on (the
//! fluid's). Per cell of the whole mesh the root holds its volume, the summed solid volume and
//! ε, the voidage handed over last, and the exchange fields while a step is summed: no voidage
//! mesh, locator or tetrahedra. Every touched cell is an inner cell of the part, whose geometry
//! is the whole mesh's bit for bit, and the sums run in the same order: the results are those
//! of a whole-mesh rank 0.

use super::{fluid_record, Coupler, CouplingStep};
use crate::error::CoupleError;
use crate::exchange::Exchange;
use crate::ksl::{form_cfdem, CfdemSums};
use crate::population::PopulationChange;
use crate::ranks::{pick, touched_cells};
use crate::sides::{FluidState, ParticleState};
use foam::Label;
use mesh::v3::V3;
use voidage::voidage_field;

impl Coupler {
    /// Makes this coupler, on rank 0's part of the mesh ([`Coupler::set_part`]), the root of
    /// a fluid on rank 0 whose mesh is the whole mesh of cell volumes `volumes` (m³, as the
    /// coupler's geometry computes them): from now on each exchange sums the ranks' cells into
    /// whole-length ε and exchange fields (module docs), and [`Coupler::voidage`] is whole
    /// (ε = 1 until the next exchange).
    pub fn set_root_volumes(&mut self, volumes: Vec<f64>) {
        self.voidage = vec![1.0; volumes.len()];
        self.root_volumes = Some(volumes);
    }

    /// The cell volumes of the fields rank 0 hands the fluid: the whole mesh's on a part with
    /// [`Coupler::set_root_volumes`], else the coupler's own.
    pub(crate) fn root_cells(&self) -> &[f64] {
        self.root_volumes
            .as_deref()
            .unwrap_or(self.vm.cell_volumes())
    }

    /// With CFDEM's Ksl form, Ksl and Us of the summed `exchange` formed from its per-cell
    /// sums ([`crate::ksl::form_cfdem`]) with the fluid velocity `u` and voidage `eps`, over
    /// the cell volumes of the fields handed to the fluid ([`Coupler::root_cells`]).
    pub(super) fn form_cfdem_ksl(&self, exchange: &mut Exchange, u: &[V3], eps: &[f64]) {
        if let (Some(k), Some(sums)) = (self.ksl_form.cfdem(), &exchange.cfdem) {
            let (ksl, us) = (&mut exchange.ksl, &mut exchange.us);
            form_cfdem(&k, sums, u, eps, self.root_cells(), ksl, us);
        }
    }

    /// [`Coupler::exchange`] on rank 0 holding a part with the fluid on rank 0 (module docs):
    /// the same collective steps as [`Coupler::exchange_remote`], with the root's sums.
    pub(super) fn exchange_root(
        &mut self,
        particles: &ParticleState<'_>,
        fluid: &FluidState<'_>,
        population: PopulationChange,
    ) -> Result<CouplingStep, CoupleError> {
        let n = self.root_cells().len();
        let t_fluid = self.whole_fluid(fluid, n)?;
        // PFM's bed heat averages the particles over whole cells: one coupler rank only
        self.bed_heat.check_ranks(true)?;
        let (shares, mut deposit) = self.place(particles)?;
        let touched = touched_cells(&shares, &self.hints);
        self.touched = touched.len();
        let global = self.global_labels(&touched);
        let mut own = Vec::with_capacity(touched.len());
        pick(&touched, &deposit.solid, 1, &mut own);
        // the whole deposit: this rank's cells, then the other ranks', as on a whole mesh
        deposit.solid = vec![0.0; n];
        self.ranks.sum_to_root(&global, &own, 1, &mut deposit.solid);
        self.sum_totals(&mut deposit);
        let mut voidage =
            voidage_field(&deposit.solid, self.root_cells(), self.settings.alpha_min)?;
        self.broadcast_voidage_stats(&mut voidage);
        let width = self.fluid_width();
        let mut got = Vec::with_capacity(touched.len() * width);
        {
            let (eps, fluid) = (&voidage.epsilon, *fluid);
            let record = |c: Label, out: &mut Vec<f64>| {
                fluid_record(eps, &fluid, c as usize, out);
                out.extend(t_fluid.map(|t| t[c as usize]));
            };
            self.ranks
                .scatter_from_root(width, &record, &mut Vec::new());
            for &c in &global {
                record(c, &mut got);
            }
        }
        let (placement, forces, mut exchange) = self.forces_at(&touched, &got, shares, particles);
        let mut heat = match self.settings.heat {
            Some(_) => Some(self.heat_of_touched(&placement, particles)?),
            None => None,
        };
        self.sum_exchange(&touched, &mut exchange, heat.as_mut().map(|h| &mut h.1));
        self.form_cfdem_ksl(&mut exchange, fluid.u, &voidage.epsilon);
        let heat = heat.map(|(p, w)| self.heat_finish(p, &w));
        self.smooth_and_keep(&mut voidage, &placement, particles)?;
        Ok(CouplingStep {
            placement,
            deposit,
            voidage,
            forces,
            exchange,
            population,
            heat,
        })
    }
}

/// `exchange` made `n` cells long and zero, for rank 0's whole sums of a part's fields (its
/// outside-the-mesh accounting kept).
pub(super) fn widen(exchange: &mut Exchange, n: usize) {
    exchange.ksl = vec![0.0; n];
    exchange.us = vec![V3::zeros(); n];
    exchange.f = vec![V3::zeros(); n];
    if let Some(k) = exchange.cfdem.as_mut() {
        *k = CfdemSums::new(n, k.averaging);
    }
}
