//! Per-particle fluid forces of one coupling step, and what each side receives.
//!
//! For every particle inside the mesh the fluid state is interpolated ([`crate::interpolate`])
//! — u_f and ε with the drag's rule, ∇p and ∇·τ with their force models' rules — the drag law
//! gives β (kg/s) at ε floored to the law's floor, and [`closures::model::particle_forces`]
//! splits the force by the model type (A, B, Bfull). Then ([`crate::config::DragSettings`]):
//! * the DEM side gets (β, u_f) when `implForceDEM` is on and applies β (u_f − v) every DEM
//!   step; otherwise it gets β = 0 and the drag frozen into `f_ext`;
//! * the fluid gets β in Ksl/Us (`implicitCouple`), or the drag in `f` when
//!   `treatForceExplicit` is on, or nothing with `treatForceDEM`; the model's explicitly
//!   coupled part (Bfull's pressure and viscous forces) always goes into `f`.
//!
//! With `noDrag` the fluid's share (and with `noDEMForce` the particle's) is zero.
//!
//! Added mass and lift ([`crate::config::Forces`]: `virtualMassForce`, `MeiLift`,
//! `SaffmanLift`) are explicit forces: added to `f_ext` and, unless `treatForceDEM`, to the
//! force whose reaction the fluid gets in `f` (foamgrain's f always reaches the fluid; CFDEM's
//! only with `explicitCouple`). Model B divides the lift by ε, as CFDEM's `MeiLift` does.
//! The added mass C ρ V a_rel ([`closures::forces::virtual_mass`]) takes the particle's
//! acceleration from its velocity change since the previous coupling step ([`Previous`], by
//! tag; a particle new since then gets no added mass): with `splitUrelCalculation` the fluid's
//! part is DU/Dt at the particle ([`FluidState::ddt_u`]) and the particle's part that lagged
//! difference (CFDEM leaves it to LIGGGHTS's integration, which Debian's LIGGGHTS does not
//! do); without it, CFDEM-PFM's form, a_rel is the change of u_f − v over the step. Both lag
//! the particle's acceleration one coupling step, stable for C ρ_f < ρ_p (checked by the
//! coupler).
//!
//! A particle outside the mesh feels no fluid force and gives nothing to the fluid; it is
//! counted. Units: SI, kinematic p (ADR 0004).

use crate::config::{DragSettings, Forces};
use crate::exchange::{Exchange, Sums};
use crate::interpolate::{Interpolation, Lerp, Placement};
use crate::ksl::CfdemSums;
use crate::sides::{FluidState, ParticleState};
use closures::model::{particle_forces, FluidAtParticle, ModelType};
use closures::DragInput;
use mesh::v3::V3;
use rayon::prelude::*;

/// Fluid properties and force models of a coupling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Physics {
    /// Fluid density ρ, kg/m³.
    pub rho: f64,
    /// Kinematic viscosity ν, m²/s.
    pub nu: f64,
    /// Gravity g, m/s² (used by Archimedes).
    pub gravity: V3,
    /// `modelType`.
    pub model: ModelType,
    /// The force models.
    pub forces: Forces,
    /// `implicitCouple`: the drag's reaction is handed to the fluid as Ksl/Us.
    pub implicit_couple: bool,
}

/// The fluid force on one particle and its split between the sides.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ParticleCoupling {
    /// β for the DEM side (kg/s): applied as β (u_f − v) each DEM step; 0 when the drag is
    /// frozen into `f_ext`.
    pub beta_dem: f64,
    /// Fluid velocity at the particle, m/s.
    pub u_f: V3,
    /// Explicit force for the DEM side, N.
    pub f_ext: V3,
    /// The total fluid force at the coupling time, N (drag + explicit).
    pub total: V3,
    /// β summed into Ksl (kg/s).
    pub beta_fluid: f64,
    /// Force whose reaction goes into `f`, N.
    pub f_fluid: V3,
}

/// The couplings of all particles, and how many had no fluid.
#[derive(Clone, Debug, PartialEq)]
pub struct ForceSet {
    /// One per particle.
    pub particles: Vec<ParticleCoupling>,
    /// Particles outside the mesh (no fluid force).
    pub outside: usize,
}

/// A particle's state at the previous coupling step, for the added mass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Before {
    /// u_f − v with the added mass's interpolation, m/s.
    pub u_rel: V3,
    /// The particle's velocity v, m/s.
    pub v: V3,
}

/// The previous coupling step as the added mass sees it: the time since it and each current
/// particle's state then (`None` for a particle new since then).
#[derive(Clone, Copy, Debug)]
pub struct Previous<'a> {
    /// The coupling interval Δt, s.
    pub dt: f64,
    /// One per particle of this step.
    pub before: &'a [Option<Before>],
}

/// The forces on every particle (parallel over particles), with the voidage field `voidage`.
pub fn particle_couplings(
    physics: &Physics,
    placement: &Placement,
    fluid: &FluidState<'_>,
    voidage: &[f64],
    particles: &ParticleState<'_>,
) -> ForceSet {
    let kernel = Kernel::new(physics, fluid, voidage, None);
    let mut out = Vec::new();
    (0..placement.len())
        .into_par_iter()
        .map(|i| kernel.particle(placement, particles, i).unwrap_or_default())
        .collect_into_vec(&mut out);
    let outside = (0..placement.len())
        .into_par_iter()
        .filter(|&i| !placement.inside(i))
        .count();
    ForceSet {
        particles: out,
        outside,
    }
}

/// Particles per stage of [`couplings_and_exchange`]; their (β, F) for the exchange (32 B each,
/// 1 MB) stay in cache between the two stages. The results do not depend on it.
const STAGE: usize = 1 << 15;

/// The couplings of every particle and the exchange fields they give on cells of volumes
/// `cell_volumes` (m³): the same values, bit for bit, as [`particle_couplings`] followed by
/// [`crate::exchange::exchange_with`] on (β_fluid, v, f_fluid), in one pipeline. `reuse` is a
/// vector whose allocation holds the couplings (its contents are discarded; `Vec::new()` for
/// none): the couplings of 10⁶ particles take 112 MB, and writing them into fresh memory costs
/// the kernel about as much time as computing them (page faults). The particles
/// go in stages of 2¹⁵: while the threads compute the couplings of stage k + 1 (parallel
/// over particles; each also copies its β_fluid and f_fluid to a small stage buffer), one of
/// them adds stage k to the exchange sums in particle order from that buffer. The exchange
/// thus overlaps the force loop instead of re-reading 112 B per particle after it, and stays
/// independent of the number of threads. `cfdem`: zero sums of CFDEM's Ksl form to gather
/// too ([`crate::ksl`]; the exchange's `cfdem`), `None` with the conserving form.
#[allow(clippy::too_many_arguments)]
pub fn couplings_and_exchange(
    physics: &Physics,
    placement: &Placement,
    fluid: &FluidState<'_>,
    voidage: &[f64],
    particles: &ParticleState<'_>,
    cell_volumes: &[f64],
    reuse: Vec<ParticleCoupling>,
    cfdem: Option<CfdemSums>,
) -> (ForceSet, Exchange) {
    let input = Input {
        physics,
        placement,
        fluid,
        voidage,
        particles,
        previous: None,
        fluctuation: None,
    };
    couplings_and_exchange_with(&input, cell_volumes, reuse, cfdem)
}

/// What [`couplings_and_exchange_with`] computes from.
#[derive(Clone, Copy)]
pub struct Input<'a> {
    /// Fluid properties and force models.
    pub physics: &'a Physics,
    /// Where the particles are.
    pub placement: &'a Placement,
    /// The fluid per cell.
    pub fluid: &'a FluidState<'a>,
    /// ε per cell.
    pub voidage: &'a [f64],
    /// The particles.
    pub particles: &'a ParticleState<'a>,
    /// The previous coupling step, for `virtualMassForce` (`None`: no added mass acts yet).
    pub previous: Option<Previous<'a>>,
    /// `KochHillRWDrag`'s turbulent fluctuation u′ per particle, m/s ([`crate::random_walk`]):
    /// the drag sees u_f + u′ (`None`: no random walk).
    pub fluctuation: Option<&'a [V3]>,
}

/// [`couplings_and_exchange`] with the previous step's particle states (added mass).
pub fn couplings_and_exchange_with(
    input: &Input<'_>,
    cell_volumes: &[f64],
    reuse: Vec<ParticleCoupling>,
    cfdem: Option<CfdemSums>,
) -> (ForceSet, Exchange) {
    let Input {
        physics,
        placement,
        fluid,
        voidage,
        particles,
        previous,
        fluctuation,
    } = *input;
    let mut kernel = Kernel::new(physics, fluid, voidage, previous);
    kernel.fluctuation = fluctuation;
    let n = placement.len();
    let stages = n.div_ceil(STAGE);
    let mut out = reuse;
    out.clear();
    out.reserve(n);
    let mut sums = Sums::with_cfdem(cell_volumes.len(), cfdem);
    let mut buffers: [Vec<(f64, V3, V3)>; 2] = [Vec::new(), Vec::new()];
    for k in 0..=stages {
        let [even, odd] = &mut buffers;
        let (next, done) = if k % 2 == 0 {
            (even, &*odd)
        } else {
            (odd, &*even)
        };
        rayon::join(
            || {
                if k < stages {
                    let range = k * STAGE..((k + 1) * STAGE).min(n);
                    next.clear();
                    let mut both = (std::mem::take(&mut out), std::mem::take(next));
                    both.par_extend(range.into_par_iter().map(|i| {
                        let c = kernel.particle(placement, particles, i).unwrap_or_default();
                        (c, (c.beta_fluid, c.f_fluid, c.u_f))
                    }));
                    (out, *next) = both;
                }
            },
            || {
                if k > 0 {
                    let first = (k - 1) * STAGE;
                    for (j, &(beta, f, u)) in done.iter().enumerate() {
                        let i = first + j;
                        sums.add(placement, i, beta, particles.velocity[i], f, u);
                    }
                }
            },
        );
    }
    let exchange = sums.finish(cell_volumes);
    let set = ForceSet {
        particles: out,
        outside: exchange.outside.particles,
    };
    (set, exchange)
}

/// Volume of a sphere of radius r, m³.
#[inline]
pub(crate) fn ball(r: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// What a particle's cells give it: u_f and ε with the drag's rule, ∇p and ∇·τ with theirs.
pub(crate) struct AtParticle {
    pub(crate) u: V3,
    pub(crate) voidage: f64,
    pub(crate) grad_p: V3,
    pub(crate) div_tau: V3,
}

/// The per-particle force computation with the settings resolved once for all particles.
pub(crate) struct Kernel<'a> {
    physics: &'a Physics,
    /// μ = ν ρ, Pa·s.
    mu: f64,
    /// Gravity as Archimedes sees it (zero without Archimedes), m/s².
    gravity: V3,
    fluid: &'a FluidState<'a>,
    voidage: &'a [f64],
    /// Rule for u_f and ε.
    drag_rule: Interpolation,
    /// Rules for ∇p and ∇·τ, `None` when the force is off.
    grad_p_rule: Option<Interpolation>,
    viscous_rule: Option<Interpolation>,
    /// The previous coupling step, for the added mass.
    previous: Option<Previous<'a>>,
    /// The random walk's u′ per particle (`KochHillRWDrag`), m/s.
    fluctuation: Option<&'a [V3]>,
}

impl<'a> Kernel<'a> {
    pub(crate) fn new(
        physics: &'a Physics,
        fluid: &'a FluidState<'a>,
        voidage: &'a [f64],
        previous: Option<Previous<'a>>,
    ) -> Self {
        Kernel {
            previous,
            fluctuation: None,
            physics,
            mu: physics.nu * physics.rho,
            gravity: if physics.forces.archimedes {
                physics.gravity
            } else {
                V3::zeros()
            },
            fluid,
            voidage,
            drag_rule: physics
                .forces
                .drag
                .map_or(Interpolation::Cell, |d| d.interpolation),
            grad_p_rule: physics.forces.grad_p,
            viscous_rule: physics.forces.viscous,
        }
    }

    /// The fluid fields at particle `i`, `None` outside the mesh: the values
    /// [`Placement::value_at`] gives, bit for bit, with one pass over the particle's shares
    /// for all the fields that use the smooth rule.
    #[inline]
    pub(crate) fn fluid_at(&self, placement: &Placement, i: usize) -> Option<AtParticle> {
        if !placement.inside(i) {
            return None;
        }
        let f = self.fluid;
        let centre = placement.centre[i].map(|c| c as usize);
        // The cell value where the rule is `cell` and the centre is inside, else `None`
        // (smooth, summed below).
        let cell = |rule: Interpolation| match (rule, centre) {
            (Interpolation::Cell, Some(c)) => Some(c),
            _ => None,
        };
        let drag_cell = cell(self.drag_rule);
        let grad_p_cell = self.grad_p_rule.map(cell);
        let viscous_cell = self.viscous_rule.map(cell);
        let mut at = AtParticle {
            u: drag_cell.map_or(V3::zeros(), |c| f.u[c]),
            voidage: drag_cell.map_or(0.0, |c| self.voidage[c]),
            grad_p: grad_p_cell.flatten().map_or(V3::zeros(), |c| f.grad_p[c]),
            div_tau: viscous_cell.flatten().map_or(V3::zeros(), |c| f.div_tau[c]),
        };
        let smooth_drag = drag_cell.is_none();
        let smooth_grad_p = grad_p_cell == Some(None);
        let smooth_viscous = viscous_cell == Some(None);
        if smooth_drag || smooth_grad_p || smooth_viscous {
            placement.for_each_weight(i, |c, w| {
                let c = c as usize;
                if smooth_drag {
                    at.u = at.u.add_scaled(w, f.u[c]);
                    at.voidage = at.voidage.add_scaled(w, self.voidage[c]);
                }
                if smooth_grad_p {
                    at.grad_p = at.grad_p.add_scaled(w, f.grad_p[c]);
                }
                if smooth_viscous {
                    at.div_tau = at.div_tau.add_scaled(w, f.div_tau[c]);
                }
            });
        }
        Some(at)
    }

    /// The drag law's β (kg/s) for a particle of radius `r` and velocity `v` in the fluid at
    /// it, and that fluid with ε floored to the law's floor, as `particle_forces` takes it.
    #[inline]
    pub(crate) fn drag_at(
        &self,
        u_f: V3,
        eps: f64,
        grad_p: V3,
        div_tau: V3,
        r: f64,
        v: V3,
    ) -> (f64, FluidAtParticle) {
        let ph = self.physics;
        let (beta, floored) = match ph.forces.drag {
            Some(DragSettings { closure, .. }) => {
                let x = DragInput::new(eps, 2.0 * r, (u_f - v).norm(), ph.rho, self.mu);
                let floored = eps.clamp(closure.voidage_floor, 1.0);
                (closure.beta(&x), floored)
            }
            None => (0.0, eps.clamp(f64::MIN_POSITIVE, 1.0)),
        };
        let at = FluidAtParticle {
            u: u_f,
            grad_p,
            div_tau,
            voidage: floored,
            rho: ph.rho,
        };
        (beta, at)
    }

    /// Gravity as Archimedes sees it (zero without Archimedes), m/s².
    pub(crate) fn gravity(&self) -> V3 {
        self.gravity
    }

    /// The coupling of particle `i`, `None` outside the mesh.
    #[inline]
    fn particle(
        &self,
        placement: &Placement,
        p: &ParticleState<'_>,
        i: usize,
    ) -> Option<ParticleCoupling> {
        let ph = self.physics;
        let AtParticle {
            u: u_f,
            voidage: eps,
            grad_p,
            div_tau,
        } = self.fluid_at(placement, i)?;
        let r = p.radius[i];
        let v = p.velocity[i];
        // KochHillRWDrag: the drag sees the fluctuation too (crate::random_walk)
        let u_turb = self.fluctuation.map_or(V3::zeros(), |u| u[i]);
        let (beta, at) = match self.fluctuation {
            Some(_) => self.drag_at(u_f + u_turb, eps, grad_p, div_tau, r, v),
            None => self.drag_at(u_f, eps, grad_p, div_tau, r, v),
        };
        let f = particle_forces(ph.model, beta, ball(r), &at, v, self.gravity);
        let settings = ph.forces.drag;
        let implicit_dem = settings.is_some_and(|d| d.implicit_dem);
        let explicit_fluid = settings.is_some_and(|d| d.explicit_fluid);
        let dem_only = settings.is_some_and(|d| d.dem_only);
        let (beta_dem, f_ext) = if implicit_dem {
            match self.fluctuation {
                // β (u_f − v) each DEM step on the mean u_f, and β u′ held
                Some(_) => (f.beta, f.explicit + u_turb * f.beta),
                None => (f.beta, f.explicit),
            }
        } else {
            (0.0, (f.explicit + f.drag))
        };
        let (beta_fluid, drag_to_f) = if dem_only {
            (0.0, V3::zeros())
        } else if explicit_fluid {
            (0.0, f.drag)
        } else if ph.implicit_couple {
            (f.beta, V3::zeros())
        } else {
            (0.0, V3::zeros())
        };
        let mut c = ParticleCoupling {
            beta_dem,
            u_f,
            f_ext,
            total: f.total(),
            beta_fluid,
            f_fluid: (f.explicit_coupled + drag_to_f),
        };
        if self.fluctuation.is_some() && beta_fluid != 0.0 {
            // the fluid's implicit part is β (U − Us) on its mean velocity: the fluctuation's
            // β u′ reaches it explicitly, so it loses what the particle gains
            c.f_fluid += u_turb * beta_fluid;
        }
        let (to_particle, to_fluid) = self.added_mass_and_lift(placement, p, i, at.voidage);
        c.f_ext += to_particle;
        c.total += to_particle;
        c.f_fluid += to_fluid;
        if let Some(no_drag) = ph.forces.no_drag {
            // CFDEM's noDrag: the fluid loses the particles' reaction unless keepCFDForce, the
            // particles their fluid force with noDEMForce.
            if !no_drag.keep_cfd_force {
                c.beta_fluid = 0.0;
                c.f_fluid = V3::zeros();
            }
            if no_drag.no_dem_force {
                c.beta_dem = 0.0;
                c.f_ext = V3::zeros();
                c.total = V3::zeros();
            }
        }
        Some(c)
    }
}

impl Kernel<'_> {
    /// The added mass and lift on particle `i` (inside the mesh; ε `eps` the drag's, floored)
    /// and the part of them whose reaction the fluid gets, N (module docs).
    #[inline]
    fn added_mass_and_lift(
        &self,
        placement: &Placement,
        p: &ParticleState<'_>,
        i: usize,
        eps: f64,
    ) -> (V3, V3) {
        let forces = &self.physics.forces;
        let (mut particle, mut fluid) = (V3::zeros(), V3::zeros());
        let mut add = |f: V3, dem_only: bool| {
            particle += f;
            if !dem_only {
                fluid += f;
            }
        };
        let (rho, nu) = (self.physics.rho, self.physics.nu);
        let (r, v) = (p.radius[i], p.velocity[i]);
        let at = |field: &[V3], rule| placement.value_at(field, i, rule).unwrap_or_default();
        if let (Some(vm), Some(prev)) = (forces.virtual_mass, self.previous) {
            if let Some(before) = prev.before[i] {
                let a_particle = (v - before.v) / prev.dt;
                let a_rel = match (vm.split, self.fluid.ddt_u) {
                    (true, Some(ddt_u)) => at(ddt_u, vm.interpolation) - a_particle,
                    (true, None) => V3::zeros(),
                    (false, _) => {
                        let u_rel = at(self.fluid.u, vm.interpolation) - v;
                        (u_rel - before.u_rel) / prev.dt
                    }
                };
                let f = closures::forces::virtual_mass(vm.c_add, ball(r), rho, a_rel, V3::zeros());
                add(f, vm.dem_only);
            }
        }
        let model_b = |f: V3| match self.physics.model {
            closures::ModelType::B => f / eps,
            _ => f,
        };
        let lifts = [(forces.mei_lift, true), (forces.saffman_lift, false)];
        for (settings, mei) in lifts {
            let (Some(l), Some(w)) = (settings, self.fluid.vorticity) else {
                continue;
            };
            let slip = at(self.fluid.u, l.interpolation) - v;
            let omega = at(w, l.interpolation);
            let f = match mei {
                true => {
                    closures::forces::cfdem_mei_lift(2.0 * r, rho, nu, slip, omega, l.second_order)
                }
                false => closures::forces::saffman_lift(2.0 * r, rho, rho * nu, slip, omega),
            };
            add(model_b(f), l.dem_only);
        }
        (particle, fluid)
    }
}

/// The added mass's record of particle `i` for the next step: u_f − v with its interpolation
/// and v ([`Before`]); `None` outside the mesh or without `virtualMassForce`.
pub fn before(
    physics: &Physics,
    placement: &Placement,
    fluid: &FluidState<'_>,
    particles: &ParticleState<'_>,
    i: usize,
) -> Option<Before> {
    let vm = physics.forces.virtual_mass?;
    let v = particles.velocity[i];
    let u = placement.value_at(fluid.u, i, vm.interpolation)?;
    Some(Before { u_rel: u - v, v })
}

/// Σ of the total fluid forces on the particles, N.
pub fn total_force(set: &ForceSet) -> V3 {
    set.particles
        .iter()
        .fold(V3::zeros(), |acc, c| acc + c.total)
}

/// Σ_p [β_fluid (u_f − v) + f_fluid]: the momentum per time the fluid gives the particles at
/// the coupling time, N, which Σ_c V_c [Ksl_c (U_c − Us_c) − f_c] equals to round-off when u_f
/// is the smooth interpolation (ADR 0004).
pub fn fluid_momentum_loss(set: &ForceSet, velocity: &[V3]) -> V3 {
    set.particles
        .iter()
        .zip(velocity)
        .fold(V3::zeros(), |acc, (c, &v)| {
            acc + ((c.beta_fluid * (c.u_f - v)) + c.f_fluid)
        })
}
