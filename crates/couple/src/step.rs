//! The coupling step and its schedule.
//!
//! One coupling step ([`Coupler::step`]), in CFDEMcoupling's order:
//! 1. the particle side advances `couplingInterval` DEM steps;
//! 2. the particles are located and their volumes shared among cells ([`voidage`]), giving
//!    the new ε (clipped at `alphaMin` when set, the clipped volume reported);
//! 3. the fluid state (U, ∇p, ∇·τ, with the new ε) is interpolated to the particles and the
//!    forces computed ([`crate::forces`]);
//! 4. the exchange fields Ksl, Us, f are built with the same shares ([`crate::exchange`](mod@crate::exchange)) and
//!    handed to the fluid with ε old and new (the fluid blends them over the interval,
//!    [`crate::blend`]); the particle side gets (F_ext, β, u_f);
//! 5. the fluid advances one coupling interval, `couplingInterval × dt_DEM`.
//!
//! Step 5 needs the exchange fields of step 4 only, and the next step 1 only the forces of
//! step 4: [`Coupler::step`] is [`Coupler::advance_particles`] (step 1), [`Coupler::hand_over`]
//! (steps 2–4) and the fluid's advance, and a caller whose fluid runs in processes of its own
//! may leave that advance running while the particles advance the next interval (the runner
//! does so with grainPisoFoam), waiting for it before the next hand-over reads the fluid.
//!
//! [`Coupler::exchange`] does steps 2–4 for given states without touching either side (what a
//! one-way replay needs). On several ranks ([`Coupler::set_ranks`], [`crate::ranks`]) each
//! rank runs the same steps on its own particles; steps 2 and 4 then sum the cells' shares on
//! rank 0, which holds the fluid (the other ranks' fluid side is a stand-in that only counts
//! time), or, with [`Coupler::set_owners`], go from every rank straight to the processes that
//! own the fluid's cells ([`crate::ranks::CellOwners`]). [`Coupler::run`] repeats [`Coupler::step`], handing each finished
//! step back ([`Coupler::recycle`]) so its per-particle buffers are reused.

use crate::error::CoupleError;
use crate::exchange::Exchange;
use crate::forces::{
    couplings_and_exchange_with, Before, ForceSet, Input, ParticleCoupling, Physics, Previous,
};
use crate::heat::{
    cell_heat, fluid_temperature, heat_source, particle_heat, particle_temperatures, CellFields,
    HeatAccount, HeatFluid, HeatStep, ParticleHeat,
};
use crate::interpolate::Placement;
use crate::ksl::{CfdemSums, KslForm, CFDEM_SUMS_WIDTH};
use crate::periodic::PeriodicMesh;
use crate::population::{follow_tags, Population, PopulationChange};
use crate::ranks::{
    owner_reply_width, owner_sums_width, pick, touched_cells, CellOwners, Ranks, Serial,
};
use crate::side_checks::{check_particles, fluid_err, particle_err, same_lengths};
use crate::sides::{ExchangeFields, FluidSide, FluidState, ParticleSide, ParticleState};
use foam::{Label, PolyMesh};
use mesh::v3::V3;
use rayon::prelude::*;
use voidage::{
    voidage_field, CellShares, Deposit, DividedMemo, Method, ParticleSet, Voidage, VoidageMesh,
};

mod checks;
mod root;

/// What a coupler needs besides the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CouplerSettings {
    /// The voidage method (also the kernel of the exchange).
    pub method: Method,
    /// ε floor (`alphaMin`), if any.
    pub alpha_min: Option<f64>,
    /// DEM steps per coupling step.
    pub coupling_interval: u64,
    /// Fluid properties and force models.
    pub physics: Physics,
    /// The heat transfer, `None` without heat ([`crate::heat`]).
    pub heat: Option<crate::config::HeatSettings>,
}

/// Everything one exchange produced.
#[derive(Clone, Debug)]
pub struct CouplingStep {
    /// Where the particles are (centre cells and shares).
    pub placement: Placement,
    /// The deposit (volume accounting).
    pub deposit: Deposit,
    /// The new voidage.
    pub voidage: Voidage,
    /// Per-particle forces.
    pub forces: ForceSet,
    /// Ksl, Us, f.
    pub exchange: Exchange,
    /// The particles that entered and left since the last exchange, over all ranks
    /// ([`crate::population`]).
    pub population: PopulationChange,
    /// The heat exchanged ([`crate::heat`]), `None` without heat transfer.
    pub heat: Option<HeatStep>,
}

/// The coupler: the voidage mesh, the settings and the voidage of the last step.
pub struct Coupler {
    pub(crate) vm: VoidageMesh,
    /// The mesh's cyclic directions: centres beyond a cyclic face are placed at their image.
    periodic: PeriodicMesh,
    settings: CouplerSettings,
    pub(crate) voidage: Vec<f64>,
    /// Each particle's centre cell at the last exchange (where the search starts), for the
    /// particles `hint_ids`: followed by tag when the population changes.
    pub(crate) hints: Vec<Option<Label>>,
    pub(crate) hint_ids: Vec<u64>,
    /// `divided`'s marker cells of the last exchange, for the particles `hint_ids`
    /// ([`voidage::memo`]: reused while a particle stays within their clearance).
    pub(crate) memo: DividedMemo,
    pub(crate) population: Population,
    steps: u64,
    pub(crate) spare: Spare,
    ranks: Box<dyn Ranks>,
    /// Cells this rank's particles touched in the last exchange on several ranks.
    touched: usize,
    /// On ranks other than 0: ε and the fluid at the cells this rank's particles touch
    /// (received from rank 0; other cells hold stale values that are never read).
    pub(crate) remote: Remote,
    /// The fluid's cells' owners, when they are not rank 0 ([`Coupler::set_owners`]).
    owners: Option<Box<dyn CellOwners>>,
    /// The smoothing of the ε handed to the fluid ([`Coupler::set_smoothing`]).
    smoothing: Option<crate::smoothing::Smoothing>,
    /// The Ksl form handed to the fluid ([`Coupler::set_ksl_form`]).
    ksl_form: KslForm,
    /// `virtualMassForce`'s record of the last exchange's particles ([`Before`]), by tag.
    pub(crate) before: Vec<Option<Before>>,
    pub(crate) before_ids: Vec<u64>,
    /// The coupling interval Δt, s ([`Coupler::set_coupling_time_step`]).
    coupling_dt: Option<f64>,
    /// PFM's wall heat and inter-grain conduction ([`Coupler::set_bed_heat`]).
    bed_heat: crate::bed_heat::BedHeat,
    /// `KochHillRWDrag`'s eddies by tag ([`crate::random_walk`]).
    random_walk: Option<crate::random_walk::RandomWalk>,
    /// The part of the mesh this rank holds, when it holds one ([`Coupler::set_part`]).
    pub(crate) part: Option<crate::part::Parted>,
    /// On rank 0 holding a part while the fluid is on rank 0: the whole mesh's cell volumes,
    /// ε's denominators ([`Coupler::set_root_volumes`]; `self.voidage` is then whole too).
    pub(crate) root_volumes: Option<Vec<f64>>,
}

/// A rank's copy of ε, U, p, ∇p, ∇·τ (and T with heat) at the cells it touches (dense,
/// `n_cells` long).
#[derive(Default)]
pub(crate) struct Remote {
    pub(crate) eps: Vec<f64>,
    pub(crate) u: Vec<V3>,
    pub(crate) p: Vec<f64>,
    pub(crate) grad_p: Vec<V3>,
    pub(crate) div_tau: Vec<V3>,
    pub(crate) t: Vec<f64>,
}

/// Values per cell rank 0 sends each rank: ε, U (3), p, ∇p (3), ∇·τ (3); with heat T after
/// them.
const FLUID_WIDTH: usize = 11;
/// Values per cell each rank sends rank 0 after the forces: Ksl, Ksl·Us (3), f (3); with heat
/// Σ w q (W) after them.
const EXCHANGE_WIDTH: usize = 7;

/// Per-particle buffers kept from one step to the next ([`Coupler::recycle`]): for 10⁶
/// particles they hold about 200 MB, which fresh allocations would page-fault in again every
/// step.
#[derive(Default)]
pub(crate) struct Spare {
    /// Couplings of a recycled step.
    pub(crate) couplings: Vec<ParticleCoupling>,
    /// Centre cells of a recycled step.
    pub(crate) centre: Vec<Option<Label>>,
    /// Voidage shares of a recycled step.
    pub(crate) shares: Option<CellShares>,
    /// What [`Coupler::step`] hands the particle side: F_ext, β and u_f.
    pub(crate) f_ext: Vec<V3>,
    pub(crate) beta: Vec<f64>,
    pub(crate) u_f: Vec<V3>,
}

impl Coupler {
    /// A coupler on `mesh`; ε starts at 1.
    pub fn new(mesh: &PolyMesh, settings: CouplerSettings) -> Result<Coupler, CoupleError> {
        if settings.coupling_interval == 0 {
            return Err(CoupleError::Parameter(
                "couplingInterval must be at least 1".into(),
            ));
        }
        if let Some(h) = &settings.heat {
            h.check()?;
        }
        let vm = VoidageMesh::new(mesh)?;
        let periodic = PeriodicMesh::new(mesh, vm.geometry())?;
        let settings_random_walk = settings
            .physics
            .forces
            .random_walk
            .map(crate::random_walk::RandomWalk::new);
        let n = vm.n_cells();
        Ok(Coupler {
            vm,
            periodic,
            settings,
            voidage: vec![1.0; n],
            hints: Vec::new(),
            hint_ids: Vec::new(),
            memo: DividedMemo::new(),
            population: Population::default(),
            steps: 0,
            spare: Spare::default(),
            ranks: Box::new(Serial::default()),
            touched: 0,
            remote: Remote::default(),
            owners: None,
            smoothing: None,
            ksl_form: KslForm::Conserving,
            before: Vec::new(),
            before_ids: Vec::new(),
            coupling_dt: None,
            bed_heat: Default::default(),
            random_walk: settings_random_walk,
            part: None,
            root_volumes: None,
        })
    }

    /// Runs this coupler, made on `part`'s mesh, on that part of the mesh ([`crate::part`]:
    /// labels mapped to the whole mesh's, a new part cut when the particles leave this one).
    pub fn set_part(&mut self, part: crate::part::Parted) {
        self.part = Some(part);
    }

    /// The part of the mesh this rank holds (`None`: the whole mesh).
    pub fn part(&self) -> Option<&crate::part::Parted> {
        self.part.as_ref()
    }

    /// The whole mesh's labels of `cells` (the same labels without a part).
    fn global_labels(&self, cells: &[Label]) -> Vec<Label> {
        self.part
            .as_ref()
            .map_or_else(|| cells.to_vec(), |p| p.to_global(cells))
    }

    /// Smooths the voidage handed to the fluid from now on (`smoothingModel`
    /// `constDiffSmoothing`, `temporalSmoothing`, `constDiffAndTemporalSmoothing`,
    /// [`crate::smoothing`]); the bounds' volume change, and the volume a temporal relaxation
    /// lags, are added to the step's clipped volume (the bounds' cells to its clipped cells). Not with [`Coupler::set_owners`] (no rank holds the
    /// whole ε there): the next exchange is then an error.
    pub fn set_smoothing(&mut self, smoothing: crate::smoothing::Smoothing) {
        self.smoothing = Some(smoothing);
    }

    /// Hands the fluid Ksl and Us of `form` from now on ([`crate::ksl`]; the default is
    /// [`KslForm::Conserving`]). CFDEM's form with `dilute` averaging needs one rank: the next
    /// exchange on several ranks is then an error.
    pub fn set_ksl_form(&mut self, form: KslForm) {
        self.ksl_form = form;
    }

    /// The length of a coupling interval, s: what `virtualMassForce` divides the velocity change
    /// since the last exchange by. [`Coupler::hand_over`] sets it from the particle side's time
    /// step; a caller of [`Coupler::exchange`] alone sets it here.
    pub fn set_coupling_time_step(&mut self, dt: f64) {
        self.coupling_dt = Some(dt);
    }

    /// PFM's bed heat models from now on ([`crate::bed_heat`]): each exchange with heat adds
    /// them to its heat step. One coupler rank only: an exchange on several is an error.
    pub fn set_bed_heat(&mut self, models: crate::bed_heat::BedHeat) {
        self.bed_heat = models;
    }

    /// Runs this coupler as one of several ranks ([`crate::ranks`]): from now on every
    /// exchange is collective over `ranks`.
    pub fn set_ranks(&mut self, ranks: Box<dyn Ranks>) {
        self.ranks = ranks;
    }

    /// Exchanges the touched cells' values straight with the processes owning the fluid's
    /// cells, on every rank ([`crate::ranks`], [`CellOwners`]); the fluid side's
    /// `set_exchange` then gets empty ε and exchange fields (the owners hold them), and no
    /// rank's [`CouplingStep`] holds a whole ε or exchange field.
    pub fn set_owners(&mut self, owners: Box<dyn CellOwners>) {
        self.owners = Some(owners);
    }

    /// Bytes sent to and received from the cells' owners so far ((0, 0) without them).
    pub fn owner_traffic(&self) -> (u64, u64) {
        self.owners.as_ref().map_or((0, 0), |o| o.traffic())
    }

    /// Cells this rank's particles touched in the last exchange (on several ranks; 0 alone).
    pub fn touched_cells(&self) -> usize {
        self.touched
    }

    /// The coupler's ranks ([`Serial`] unless [`Coupler::set_ranks`] gave others).
    pub fn ranks(&self) -> &dyn Ranks {
        self.ranks.as_ref()
    }

    /// The voidage mesh (geometry, cell volumes).
    pub fn voidage_mesh(&self) -> &VoidageMesh {
        &self.vm
    }

    /// The settings.
    pub fn settings(&self) -> &CouplerSettings {
        &self.settings
    }

    /// ε after the last exchange (1 before the first).
    pub fn voidage(&self) -> &[f64] {
        &self.voidage
    }

    /// What entered and left since the first exchange, over all ranks.
    pub fn population_total(&self) -> PopulationChange {
        self.population.total()
    }

    /// Coupling steps done.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Steps 2–4 of the module docs for `particles` in `fluid`: placement, ε, forces and
    /// exchange fields. Updates the coupler's ε; touches neither side.
    ///
    /// On several ranks, `particles` are this rank's and `fluid` is read on rank 0 only. Rank
    /// 0's result holds the global deposit, ε and exchange fields and its own particles'
    /// placement and forces; another rank's holds its own particles' placement, deposit
    /// (`solid`) and forces, the global accounting totals and ε statistics, and an empty
    /// `voidage.epsilon` and its own (partial) exchange fields.
    pub fn exchange(
        &mut self,
        particles: &ParticleState<'_>,
        fluid: &FluidState<'_>,
    ) -> Result<CouplingStep, CoupleError> {
        check_particles(particles)?;
        if let Some(heat) = &self.settings.heat {
            if self.owners.is_some() && heat.max_source.is_some() {
                return Err(CoupleError::Parameter(
                    "maxSource with grainPisoFoam on several coupler ranks: its cut needs each \
                     cell's Tsource summed over the coupler ranks, which no coupler rank holds; \
                     remove maxSource from the heat model's properties, or run one coupler rank"
                        .into(),
                ));
            }
            particle_temperatures(particles)?;
        }
        self.check_ksl_form()?;
        self.check_added_mass_and_lift(particles, fluid)?;
        let several = self.ranks.size() > 1 || self.owners.is_some();
        self.bed_heat.check_ranks(several)?;
        let population = self.population.update(particles, self.ranks.as_ref());
        let n_cells = self.vm.n_cells();
        if self.owners.is_some() {
            if let Some(s) = &self.smoothing {
                return Err(CoupleError::Parameter(format!(
                    "smoothingModel {} needs the whole voidage field on one \
                     rank; with grainPisoFoam on several coupler ranks no rank holds it (run \
                     one coupler rank, or the native fluid)",
                    s.model().name()
                )));
            }
            return self.exchange_owned(particles, population);
        }
        if self.ranks.size() > 1 && self.ranks.rank() > 0 {
            return self.exchange_remote(particles, population);
        }
        if self.root_volumes.is_some() {
            return self.exchange_root(particles, fluid, population);
        }
        let t_fluid = self.whole_fluid(fluid, n_cells)?;
        let (shares, mut deposit) = self.place(particles)?;
        let parallel = self.ranks.size() > 1;
        let touched = if parallel {
            let touched = touched_cells(&shares, &self.hints);
            self.sum_deposit(&touched, &mut deposit);
            touched
        } else {
            Vec::new()
        };
        let mut voidage = self.vm.voidage(&deposit, self.settings.alpha_min)?;
        if parallel {
            self.broadcast_voidage_stats(&mut voidage);
            let (eps, fluid) = (&voidage.epsilon, *fluid);
            self.ranks.scatter_from_root(
                self.fluid_width(),
                &|c, out| {
                    fluid_record(eps, &fluid, c as usize, out);
                    out.extend(t_fluid.map(|t| t[c as usize]));
                },
                &mut Vec::new(),
            );
        }
        let (placement, forces, mut exchange) =
            self.forces(shares, fluid, &voidage.epsilon, particles);
        let mut heat = match t_fluid {
            Some(t) => {
                let cells = CellFields {
                    eps: &voidage.epsilon,
                    u: fluid.u,
                    t,
                };
                Some(self.heat_particles(&placement, cells, particles)?)
            }
            None => None,
        };
        if parallel {
            self.sum_exchange(&touched, &mut exchange, heat.as_mut().map(|h| &mut h.1));
        }
        self.form_cfdem_ksl(&mut exchange, fluid.u, &voidage.epsilon);
        let mut heat = heat.map(|(p, w)| self.heat_finish(p, &w));
        if let (Some(h), Some(t)) = (heat.as_mut(), t_fluid) {
            let cells = CellFields {
                eps: &voidage.epsilon,
                u: fluid.u,
                t,
            };
            let volumes = self.vm.cell_volumes();
            let at = (&placement, particles);
            self.bed_heat
                .add_to(h, at, cells, volumes, &self.settings)?;
        }
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

    /// The smoothing of the ε handed to the fluid, when configured (after the forces: the drag
    /// uses each particle's unsmoothed ε, module docs of `smoothing`; the fluid gets the
    /// smoothed field), and ε kept for the next hand-over.
    fn smooth_and_keep(
        &mut self,
        voidage: &mut Voidage,
        placement: &Placement,
        particles: &ParticleState<'_>,
    ) -> Result<(), CoupleError> {
        if let Some(s) = &self.smoothing {
            let several = self.ranks.size() > 1;
            let r = s.smooth_exchange(&mut voidage.epsilon, placement, particles, several)?;
            voidage.clipped_volume += r.bounded_volume + r.lagged_volume;
            voidage.clipped_cells += r.bounded_cells;
        }
        self.voidage.clone_from(&voidage.epsilon);
        Ok(())
    }

    /// Checks that `fluid` has `n_cells` values per field; its T with heat.
    fn whole_fluid<'f>(
        &self,
        fluid: &FluidState<'f>,
        n_cells: usize,
    ) -> Result<Option<&'f [f64]>, CoupleError> {
        same_lengths(
            n_cells,
            &[
                ("fluid U", fluid.u.len()),
                ("fluid p", fluid.p.len()),
                ("fluid grad(p)", fluid.grad_p.len()),
                ("fluid div(tau)", fluid.div_tau.len()),
            ],
        )?;
        match self.settings.heat {
            Some(_) => Ok(Some(fluid_temperature(fluid.temperature, n_cells)?)),
            None => Ok(None),
        }
    }

    /// Values per cell rank 0 sends each rank: [`FLUID_WIDTH`], and T with heat.
    fn fluid_width(&self) -> usize {
        FLUID_WIDTH + usize::from(self.settings.heat.is_some())
    }

    /// This rank's particles' heat flows and their heat per cell (W, `n_cells` long, this
    /// rank's shares). On several ranks an error on any rank is an error on every rank (they
    /// would wait for it in the next collective step otherwise).
    fn heat_particles(
        &self,
        placement: &Placement,
        cells: CellFields<'_>,
        particles: &ParticleState<'_>,
    ) -> Result<(ParticleHeat, Vec<f64>), CoupleError> {
        let heat = self.settings.heat.as_ref().expect("heat is on");
        let fluid = HeatFluid {
            rho: self.settings.physics.rho,
            nu: self.settings.physics.nu,
        };
        let result = particle_heat(heat, fluid, placement, cells, particles);
        if self.ranks.size() > 1 {
            let mut failed = [f64::from(u8::from(result.is_err()))];
            self.ranks.all_sum(&mut failed);
            if failed[0] > 0.0 && result.is_ok() {
                return Err(CoupleError::Parameter(
                    "the heat transfer failed on another coupler rank (its error names the \
                     particle)"
                        .into(),
                ));
            }
        }
        let p = result?;
        let w = cell_heat(placement, &p.q, self.vm.n_cells());
        Ok((p, w))
    }

    /// [`Coupler::heat_particles`] with ε, U and T of the rank's touched cells (its dense copy
    /// `self.remote`, [`Coupler::forces_at`]).
    fn heat_of_touched(
        &mut self,
        placement: &Placement,
        particles: &ParticleState<'_>,
    ) -> Result<(ParticleHeat, Vec<f64>), CoupleError> {
        let remote = std::mem::take(&mut self.remote);
        let cells = CellFields {
            eps: &remote.eps,
            u: &remote.u,
            t: &remote.t,
        };
        let got = self.heat_particles(placement, cells, particles);
        self.remote = remote;
        got
    }

    /// The heat step from this rank's particles `p` and the heat per cell summed over ranks
    /// `cell_w` (read on rank 0): Tsource on rank 0, the account summed over ranks on all.
    fn heat_finish(&self, mut p: ParticleHeat, cell_w: &[f64]) -> HeatStep {
        let heat = self.settings.heat.as_ref().expect("heat is on");
        let root = self.ranks.rank() == 0;
        let (tsource, fluid) = match root {
            true => heat_source(heat, self.settings.physics.rho, cell_w, self.root_cells()),
            false => (Vec::new(), HeatAccount::default()),
        };
        let mut sums = [p.to_particles, p.outside as f64];
        self.ranks.all_sum(&mut sums);
        let mut fluid_sums = [fluid.from_fluid, fluid.clipped, fluid.clipped_cells as f64];
        self.ranks.broadcast(&mut fluid_sums);
        let fluid = HeatAccount {
            from_fluid: fluid_sums[0],
            clipped: fluid_sums[1],
            clipped_cells: fluid_sums[2] as usize,
            ..HeatAccount::default()
        };
        closed_heat(std::mem::take(&mut p.q), sums, fluid, tsource)
    }

    /// Step 3: the particles' placement (centre cells from `self.hints`), forces and this
    /// coupler's exchange fields, for `fluid` and ε `eps`.
    fn forces(
        &mut self,
        shares: CellShares,
        fluid: &FluidState<'_>,
        eps: &[f64],
        particles: &ParticleState<'_>,
    ) -> (Placement, ForceSet, Exchange) {
        let mut centre = std::mem::take(&mut self.spare.centre);
        centre.clone_from(&self.hints);
        let placement = Placement { centre, shares };
        let n_cells = self.vm.n_cells();
        let cfdem = (self.ksl_form.cfdem()).map(|k| CfdemSums::new(n_cells, k.averaging));
        let physics = &self.settings.physics;
        let added_mass = physics.forces.virtual_mass.is_some();
        let before: Vec<Option<Before>> = match added_mass {
            true => follow_tags(&self.before_ids, particles.ids)
                .iter()
                .map(|k| k.and_then(|k| self.before[k]))
                .collect(),
            false => Vec::new(),
        };
        let t = self.steps as f64 * self.coupling_dt.unwrap_or(0.0);
        let fluctuation = (self.random_walk.as_mut())
            .map(|w| w.at_exchange(t, physics, &placement, fluid, particles));
        let input = Input {
            physics,
            placement: &placement,
            fluid,
            voidage: eps,
            particles,
            previous: self.coupling_dt.filter(|_| added_mass).map(|dt| Previous {
                dt,
                before: &before,
            }),
            fluctuation: fluctuation.as_deref(),
        };
        let (forces, exchange) = couplings_and_exchange_with(
            &input,
            self.vm.cell_volumes(),
            std::mem::take(&mut self.spare.couplings),
            cfdem,
        );
        if added_mass {
            self.before = (0..particles.len())
                .into_par_iter()
                .map(|i| crate::forces::before(physics, &placement, fluid, particles, i))
                .collect();
            self.before_ids.clear();
            self.before_ids.extend_from_slice(particles.ids);
        }
        (placement, forces, exchange)
    }

    /// Step 2's placement ([`Coupler::place_here`]); on a part of the mesh, a new part first
    /// when a centre has left the safe box, and again (reaching further) when a particle
    /// touched an edge cell ([`crate::part`]).
    fn place(
        &mut self,
        particles: &ParticleState<'_>,
    ) -> Result<(CellShares, Deposit), CoupleError> {
        if self
            .part
            .as_ref()
            .is_some_and(|p| !p.holds(particles.position))
        {
            self.recut(particles, false)?;
        }
        let mut placed = self.place_here(particles)?;
        let mut wider = 0;
        while (self.part.as_ref()).is_some_and(|p| p.touches_edge(&placed.0, &self.hints)) {
            if wider == 2 {
                let m = "a particle reaches beyond this rank's part of the mesh cut 4 × wider";
                return Err(CoupleError::Parameter(m.into()));
            }
            wider += 1;
            self.recut(particles, true)?;
            placed = self.place_here(particles)?;
        }
        Ok(placed)
    }

    /// A new part of the mesh around `particles` (reaching further when `wider`): the voidage
    /// mesh is rebuilt on it, and what was kept by cell (hints, markers, ε) starts again.
    fn recut(&mut self, particles: &ParticleState<'_>, wider: bool) -> Result<(), CoupleError> {
        let p = self.part.as_mut().expect("recut runs on a part");
        let mesh = p.recut(particles, self.coupling_dt, wider)?;
        self.vm = VoidageMesh::new(&mesh)?;
        self.periodic = PeriodicMesh::new(&mesh, self.vm.geometry())?;
        if self.root_volumes.is_none() {
            self.voidage = vec![1.0; self.vm.n_cells()];
        }
        self.hints.clear();
        self.hint_ids.clear();
        self.memo = DividedMemo::new();
        self.remote = Remote::default();
        Ok(())
    }

    /// Step 2's placement on the mesh this coupler holds: each particle's cells and volume
    /// shares (centre cells in `self.hints`) and the deposit.
    fn place_here(
        &mut self,
        particles: &ParticleState<'_>,
    ) -> Result<(CellShares, Deposit), CoupleError> {
        if self.hint_ids != particles.ids {
            let from = follow_tags(&self.hint_ids, particles.ids);
            self.hints = from.iter().map(|k| k.and_then(|k| self.hints[k])).collect();
            self.memo.reorder(&from);
            self.hint_ids.clear();
            self.hint_ids.extend_from_slice(particles.ids);
        }
        let wrapped = self.periodic.wrap_all(particles.position);
        let set = ParticleSet {
            positions: wrapped.as_deref().unwrap_or(particles.position),
            radii: particles.radius,
            ids: Some(particles.ids),
        };
        let method = self.settings.method;
        let mut shares = self.spare.shares.take().unwrap_or(CellShares {
            method,
            offsets: Vec::new(),
            cells: Vec::new(),
            volumes: Vec::new(),
        });
        let deposit = self.vm.shares_with_memo_into(
            method,
            &set,
            &mut self.hints,
            &mut self.memo,
            &mut shares,
        )?;
        Ok((shares, deposit))
    }

    /// [`Coupler::exchange`] on a rank other than 0 (module docs of [`crate::ranks`]).
    fn exchange_remote(
        &mut self,
        particles: &ParticleState<'_>,
        population: PopulationChange,
    ) -> Result<CouplingStep, CoupleError> {
        let (shares, mut deposit) = self.place(particles)?;
        let touched = touched_cells(&shares, &self.hints);
        self.sum_deposit(&touched, &mut deposit);
        let mut voidage = Voidage {
            epsilon: Vec::new(),
            alpha_min: self.settings.alpha_min,
            clipped_volume: 0.0,
            clipped_cells: 0,
            min_epsilon: 1.0,
            negative_cells: 0,
        };
        self.broadcast_voidage_stats(&mut voidage);
        let width = self.fluid_width();
        let mut got = Vec::with_capacity(touched.len() * width);
        self.ranks.scatter_from_root(width, &|_, _| {}, &mut got);
        let (placement, forces, mut exchange) = self.forces_at(&touched, &got, shares, particles);
        let mut heat = match self.settings.heat {
            Some(_) => Some(self.heat_of_touched(&placement, particles)?),
            None => None,
        };
        self.sum_exchange(&touched, &mut exchange, heat.as_mut().map(|h| &mut h.1));
        let heat = heat.map(|(p, w)| self.heat_finish(p, &w));
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

    /// The forces of this rank's particles, with ε and the fluid of the `touched` cells given
    /// as [`Coupler::fluid_width`] values per cell in `got` (written into the rank's dense copy
    /// `self.remote`).
    fn forces_at(
        &mut self,
        touched: &[Label],
        got: &[f64],
        shares: CellShares,
        particles: &ParticleState<'_>,
    ) -> (Placement, ForceSet, Exchange) {
        let n_cells = self.vm.n_cells();
        let mut remote = std::mem::take(&mut self.remote);
        let r = &mut remote;
        if r.eps.len() != n_cells {
            r.eps = vec![1.0; n_cells];
            r.u = vec![V3::zeros(); n_cells];
            r.p = vec![0.0; n_cells];
            r.grad_p = vec![V3::zeros(); n_cells];
            r.div_tau = vec![V3::zeros(); n_cells];
        }
        let width = self.fluid_width();
        if width > FLUID_WIDTH && r.t.len() != n_cells {
            r.t = vec![0.0; n_cells];
        }
        for (&c, g) in touched.iter().zip(got.chunks_exact(width)) {
            let c = c as usize;
            r.eps[c] = g[0];
            r.u[c] = V3::new(g[1], g[2], g[3]);
            r.p[c] = g[4];
            r.grad_p[c] = V3::new(g[5], g[6], g[7]);
            r.div_tau[c] = V3::new(g[8], g[9], g[10]);
            if width > FLUID_WIDTH {
                r.t[c] = g[FLUID_WIDTH];
            }
        }
        let fluid = FluidState {
            vorticity: None,
            ddt_u: None,
            turbulence: None,
            temperature: None,
            u: &r.u,
            p: &r.p,
            grad_p: &r.grad_p,
            div_tau: &r.div_tau,
        };
        let (placement, forces, exchange) = self.forces(shares, &fluid, &r.eps, particles);
        self.remote = remote;
        (placement, forces, exchange)
    }

    /// [`Coupler::exchange`] with the cells' owners elsewhere ([`Coupler::set_owners`],
    /// [`crate::ranks`]): the same on every rank.
    fn exchange_owned(
        &mut self,
        particles: &ParticleState<'_>,
        population: PopulationChange,
    ) -> Result<CouplingStep, CoupleError> {
        let (shares, mut deposit) = self.place(particles)?;
        let touched = touched_cells(&shares, &self.hints);
        self.touched = touched.len();
        let mut solid = Vec::with_capacity(touched.len());
        pick(&touched, &deposit.solid, 1, &mut solid);
        self.sum_totals(&mut deposit);
        let global = self.global_labels(&touched);
        let owners = self
            .owners
            .as_mut()
            .expect("exchange_owned runs with owners");
        let got = owners.deposit(&global, &solid).map_err(fluid_err)?;
        let heat_on = self.settings.heat.is_some();
        let reply_width = owner_reply_width(heat_on);
        same_lengths(touched.len() * reply_width, &[("owners' reply", got.len())])?;
        // ε of the touched cells from the summed volume; statistics on the lowest rank only
        let volumes = self.vm.cell_volumes();
        let mut summed = Vec::with_capacity(touched.len());
        let mut vols = Vec::with_capacity(touched.len());
        let (mut home_summed, mut home_vols) = (Vec::new(), Vec::new());
        for (&c, g) in touched.iter().zip(got.chunks_exact(reply_width)) {
            let v = volumes[c as usize];
            summed.push(g[0]);
            vols.push(v);
            if g[1] > 0.5 {
                home_summed.push(g[0]);
                home_vols.push(v);
            }
        }
        let eps = voidage_field(&summed, &vols, self.settings.alpha_min)?.epsilon;
        let mut voidage = voidage_field(&home_summed, &home_vols, self.settings.alpha_min)?;
        voidage.epsilon = Vec::new();
        let mut stats = [
            voidage.clipped_volume,
            voidage.clipped_cells as f64,
            voidage.negative_cells as f64,
        ];
        self.ranks.all_sum(&mut stats);
        let mut lowest = [-voidage.min_epsilon];
        self.ranks.all_max(&mut lowest);
        voidage.clipped_volume = stats[0];
        voidage.clipped_cells = stats[1] as usize;
        voidage.negative_cells = stats[2] as usize;
        voidage.min_epsilon = -lowest[0];
        // ε, then the reply's U, p, ∇p, ∇·τ (and T): the records of `forces_at`
        let mut records = Vec::with_capacity(touched.len() * self.fluid_width());
        for (e, g) in eps.iter().zip(got.chunks_exact(reply_width)) {
            records.push(*e);
            records.extend_from_slice(&g[2..]);
        }
        let (placement, forces, mut exchange) =
            self.forces_at(&touched, &records, shares, particles);
        let heat = match heat_on {
            true => Some(self.heat_owned(&placement, &touched, particles)?),
            false => None,
        };
        let cfdem_on = exchange.cfdem.is_some();
        let mut sums = Vec::with_capacity(touched.len() * owner_sums_width(heat_on, cfdem_on));
        for (k, (&c, e)) in touched.iter().zip(&eps).enumerate() {
            let c = c as usize;
            let (b, u, f) = (exchange.ksl[c], exchange.us[c], exchange.f[c]);
            sums.extend_from_slice(&[*e, b, b * u[0], b * u[1], b * u[2], f[0], f[1], f[2]]);
            sums.extend(heat.as_ref().map(|h| h.1[k]));
            if let Some(k) = &exchange.cfdem {
                k.record(c, &mut sums);
            }
        }
        let owners = self
            .owners
            .as_mut()
            .expect("exchange_owned runs with owners");
        owners.exchange(&sums).map_err(fluid_err)?;
        self.sum_outside(&mut exchange);
        Ok(CouplingStep {
            placement,
            deposit,
            voidage,
            forces,
            exchange,
            population,
            heat: heat.map(|h| h.0),
        })
    }

    /// The heat of [`Coupler::exchange_owned`] ([`crate::ranks`]): this rank's particles' q
    /// from ε, U and T of its `touched` cells (in `self.remote`), and its share of Tsource per
    /// touched cell, −Σ_p w_pc q_p / (ρ c_p V_c) (K/s, [`heat_source`] on the touched cells;
    /// no `maxSource` here, [`Coupler::exchange`] refuses it). The account's parts (Σ q, the
    /// particles outside, the heat the fluid gives) are summed over the ranks; the step's
    /// `tsource` is empty (the owners sum the shares).
    fn heat_owned(
        &mut self,
        placement: &Placement,
        touched: &[Label],
        particles: &ParticleState<'_>,
    ) -> Result<(HeatStep, Vec<f64>), CoupleError> {
        let (mut p, w) = self.heat_of_touched(placement, particles)?;
        let heat = self.settings.heat.as_ref().expect("heat is on");
        let mut w_touched = Vec::with_capacity(touched.len());
        let mut volumes = Vec::with_capacity(touched.len());
        pick(touched, &w, 1, &mut w_touched);
        pick(touched, self.vm.cell_volumes(), 1, &mut volumes);
        let (share, fluid) = heat_source(heat, self.settings.physics.rho, &w_touched, &volumes);
        let mut sums = [p.to_particles, p.outside as f64, fluid.from_fluid];
        self.ranks.all_sum(&mut sums);
        let fluid = HeatAccount {
            from_fluid: sums[2],
            ..HeatAccount::default()
        };
        let q = std::mem::take(&mut p.q);
        Ok((closed_heat(q, [sums[0], sums[1]], fluid, Vec::new()), share))
    }

    /// Step 1 of [`crate::ranks`]: the touched cells' solid volume summed on rank 0 (which
    /// gets the global `solid`), and the accounting totals summed on every rank.
    fn sum_deposit(&mut self, touched: &[Label], deposit: &mut Deposit) {
        self.touched = touched.len();
        let mut values = Vec::with_capacity(touched.len());
        pick(touched, &deposit.solid, 1, &mut values);
        if self.ranks.rank() == 0 {
            self.ranks
                .sum_to_root(touched, &values, 1, &mut deposit.solid);
        } else {
            let global = self.global_labels(touched);
            self.ranks.sum_to_root(&global, &values, 1, &mut []);
        }
        self.sum_totals(deposit);
    }

    /// The deposit's accounting totals (particles, volumes) summed over ranks, on every rank.
    fn sum_totals(&self, deposit: &mut Deposit) {
        let mut totals = [
            deposit.particles as f64,
            deposit.particle_volume,
            deposit.deposited_volume,
            deposit.outside_volume,
            deposit.particles_outside as f64,
            deposit.particles_partly_outside as f64,
        ];
        self.ranks.all_sum(&mut totals);
        deposit.particles = totals[0] as usize;
        deposit.particle_volume = totals[1];
        deposit.deposited_volume = totals[2];
        deposit.outside_volume = totals[3];
        deposit.particles_outside = totals[4] as usize;
        deposit.particles_partly_outside = totals[5] as usize;
    }

    /// Rank 0's ε statistics (clipping, minimum, negative cells) on every rank.
    fn broadcast_voidage_stats(&self, v: &mut Voidage) {
        let mut stats = [
            v.clipped_volume,
            v.clipped_cells as f64,
            v.min_epsilon,
            v.negative_cells as f64,
        ];
        self.ranks.broadcast(&mut stats);
        v.clipped_volume = stats[0];
        v.clipped_cells = stats[1] as usize;
        v.min_epsilon = stats[2];
        v.negative_cells = stats[3] as usize;
    }

    /// Step 3 of [`crate::ranks`]: the touched cells' Ksl, Ksl·Us and f (and with heat the
    /// heat per cell `heat_w`, W) summed on rank 0 (which gets the global exchange fields and
    /// heat per cell), the outside accounting on every rank.
    fn sum_exchange(
        &mut self,
        touched: &[Label],
        exchange: &mut Exchange,
        mut heat_w: Option<&mut Vec<f64>>,
    ) {
        let heat_width = EXCHANGE_WIDTH + usize::from(heat_w.is_some());
        let width = heat_width + exchange.cfdem.as_ref().map_or(0, |_| CFDEM_SUMS_WIDTH);
        let mut values = Vec::with_capacity(touched.len() * width);
        for &c in touched {
            let c = c as usize;
            let (k, u, f) = (exchange.ksl[c], exchange.us[c], exchange.f[c]);
            values.extend_from_slice(&[k, k * u[0], k * u[1], k * u[2], f[0], f[1], f[2]]);
            values.extend(heat_w.as_ref().map(|w| w[c]));
            if let Some(k) = &exchange.cfdem {
                k.record(c, &mut values);
            }
        }
        let root = self.ranks.rank() == 0;
        if let (true, Some(n)) = (root, self.root_volumes.as_ref().map(Vec::len)) {
            // rank 0 on a part: its own cells' values are in `values`, the sums are whole
            root::widen(exchange, n);
            if let Some(w) = heat_w.as_mut() {
                **w = vec![0.0; n];
            }
        }
        let mut sums = vec![0.0; if root { exchange.ksl.len() * width } else { 0 }];
        let global = self.global_labels(touched);
        self.ranks.sum_to_root(&global, &values, width, &mut sums);
        if root {
            for (c, s) in sums.chunks_exact(width).enumerate() {
                if let Some(w) = heat_w.as_mut() {
                    w[c] = s[EXCHANGE_WIDTH];
                }
                exchange.ksl[c] = s[0];
                exchange.us[c] = if s[0] > 0.0 {
                    V3::new(s[1] / s[0], s[2] / s[0], s[3] / s[0])
                } else {
                    V3::zeros()
                };
                exchange.f[c] = V3::new(s[4], s[5], s[6]);
                if let Some(k) = exchange.cfdem.as_mut() {
                    k.set(c, &s[heat_width..]);
                }
            }
        }
        self.sum_outside(exchange);
    }

    /// The exchange's outside-the-mesh accounting summed over ranks, on every rank.
    fn sum_outside(&self, exchange: &mut Exchange) {
        let o = &mut exchange.outside;
        let mut out = [
            o.particles as f64,
            o.beta,
            o.force[0],
            o.force[1],
            o.force[2],
        ];
        self.ranks.all_sum(&mut out);
        o.particles = out[0] as usize;
        o.beta = out[1];
        o.force = V3::new(out[2], out[3], out[4]);
    }

    /// One coupling step (module docs): [`Coupler::advance_particles`], [`Coupler::hand_over`],
    /// then the fluid advances the interval.
    pub fn step<P: ParticleSide, F: FluidSide>(
        &mut self,
        particles: &mut P,
        fluid: &mut F,
    ) -> Result<CouplingStep, CoupleError> {
        self.advance_particles(particles)?;
        let (step, dt) = self.hand_over(particles, fluid)?;
        fluid.advance(dt).map_err(fluid_err)?;
        Ok(step)
    }

    /// Step 1 of the module docs: the particle side advances `couplingInterval` DEM steps
    /// (with the forces of the last exchange).
    pub fn advance_particles<P: ParticleSide>(
        &mut self,
        particles: &mut P,
    ) -> Result<(), CoupleError> {
        particles
            .advance(self.settings.coupling_interval)
            .map_err(particle_err)
    }

    /// Steps 2–4 of the module docs on the sides themselves: the exchange for the particles
    /// now and the fluid now, the exchange fields handed to the fluid and the forces to the
    /// particles. Returns the step and the coupling interval (s) the fluid must then advance
    /// (step 5, left to the caller, who may run it while the particles advance the next
    /// interval: that interval needs only the forces handed over here).
    pub fn hand_over<P: ParticleSide, F: FluidSide>(
        &mut self,
        particles: &mut P,
        fluid: &mut F,
    ) -> Result<(CouplingStep, f64), CoupleError> {
        let interval = self.settings.coupling_interval;
        self.coupling_dt = Some(interval as f64 * particles.time_step());
        let old = self.voidage.clone();
        let step = self.exchange(&particles.state(), &fluid.state())?;
        let dt = interval as f64 * particles.time_step();
        fluid
            .set_exchange(&ExchangeFields {
                heat_source: step.heat.as_ref().map(|h| h.tsource.as_slice()),
                voidage_old: &old,
                voidage_new: &step.voidage.epsilon,
                exchange: &step.exchange,
                interval: dt,
            })
            .map_err(fluid_err)?;
        // One pass over the couplings into the three per-particle arrays the DEM takes.
        let s = &mut self.spare;
        let [mut f_ext, mut u_f] = [std::mem::take(&mut s.f_ext), std::mem::take(&mut s.u_f)];
        let mut beta = std::mem::take(&mut s.beta);
        f_ext.clear();
        beta.clear();
        u_f.clear();
        let mut arrays = (f_ext, (beta, u_f));
        arrays.par_extend(
            step.forces
                .particles
                .par_iter()
                .map(|c| (c.f_ext, (c.beta_dem, c.u_f))),
        );
        (s.f_ext, (s.beta, s.u_f)) = arrays;
        particles
            .set_forces(&s.f_ext, &s.beta, &s.u_f)
            .map_err(particle_err)?;
        if let Some(h) = &step.heat {
            particles.set_heat_flux(&h.q).map_err(particle_err)?;
        }
        self.steps += 1;
        Ok((step, dt))
    }

    /// `n` coupling steps; `each` sees every step's result (whose buffers are then recycled).
    pub fn run<P: ParticleSide, F: FluidSide>(
        &mut self,
        particles: &mut P,
        fluid: &mut F,
        n: u64,
        mut each: impl FnMut(&CouplingStep),
    ) -> Result<(), CoupleError> {
        for _ in 0..n {
            let s = self.step(particles, fluid)?;
            each(&s);
            self.recycle(s);
        }
        Ok(())
    }

    /// Takes back a step the caller is done with, so that the next [`Coupler::exchange`]
    /// writes its per-particle couplings, voidage shares and centre cells into the same memory
    /// instead of fresh pages (the results are the same either way). Optional; worth it in a loop over
    /// many particles.
    pub fn recycle(&mut self, step: CouplingStep) {
        self.spare.couplings = step.forces.particles;
        self.spare.centre = step.placement.centre;
        self.spare.shares = Some(step.placement.shares);
    }
}

/// A rank's heat step: its particles' `q`, the account closed from the particles' part summed
/// over ranks (`[Σ q (W), particles outside]`) and the fluid's part `fluid` (over all ranks).
fn closed_heat(
    q: Vec<f64>,
    particles: [f64; 2],
    fluid: HeatAccount,
    tsource: Vec<f64>,
) -> HeatStep {
    let all = ParticleHeat {
        q: Vec::new(),
        to_particles: particles[0],
        outside: particles[1] as usize,
    };
    HeatStep {
        q,
        tsource,
        account: HeatAccount::close(&all, fluid),
    }
}

/// ε, U, p, ∇p and ∇·τ of cell `c` ([`FLUID_WIDTH`] values), appended to `out`.
fn fluid_record(eps: &[f64], fluid: &FluidState<'_>, c: usize, out: &mut Vec<f64>) {
    let (u, g, t) = (fluid.u[c], fluid.grad_p[c], fluid.div_tau[c]);
    out.extend_from_slice(&[
        eps[c], u[0], u[1], u[2], fluid.p[c], g[0], g[1], g[2], t[0], t[1], t[2],
    ]);
}
