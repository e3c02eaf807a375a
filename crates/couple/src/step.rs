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
//! [`Coupler::exchange`] does steps 2–4 for given states without touching either side (what a
//! one-way replay needs). [`Coupler::run`] repeats [`Coupler::step`], handing each finished
//! step back ([`Coupler::recycle`]) so its per-particle buffers are reused.

use crate::error::CoupleError;
use crate::exchange::Exchange;
use crate::forces::{couplings_and_exchange, ForceSet, ParticleCoupling, Physics};
use crate::interpolate::Placement;
use crate::sides::{ExchangeFields, FluidSide, FluidState, ParticleSide, ParticleState};
use foam::{Label, PolyMesh};
use mesh::v3::V3;
use rayon::prelude::*;
use voidage::{CellShares, Deposit, Method, ParticleSet, Voidage, VoidageMesh};

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
}

/// The coupler: the voidage mesh, the settings and the voidage of the last step.
pub struct Coupler {
    vm: VoidageMesh,
    settings: CouplerSettings,
    voidage: Vec<f64>,
    hints: Vec<Option<Label>>,
    steps: u64,
    spare: Spare,
}

/// Per-particle buffers kept from one step to the next ([`Coupler::recycle`]): for 10⁶
/// particles they hold about 200 MB, which fresh allocations would page-fault in again every
/// step.
#[derive(Default)]
struct Spare {
    /// Couplings of a recycled step.
    couplings: Vec<ParticleCoupling>,
    /// Centre cells of a recycled step.
    centre: Vec<Option<Label>>,
    /// Voidage shares of a recycled step.
    shares: Option<CellShares>,
    /// What [`Coupler::step`] hands the particle side: F_ext, β and u_f.
    f_ext: Vec<V3>,
    beta: Vec<f64>,
    u_f: Vec<V3>,
}

impl Coupler {
    /// A coupler on `mesh`; ε starts at 1.
    pub fn new(mesh: &PolyMesh, settings: CouplerSettings) -> Result<Coupler, CoupleError> {
        if settings.coupling_interval == 0 {
            return Err(CoupleError::Parameter(
                "couplingInterval must be at least 1".into(),
            ));
        }
        let vm = VoidageMesh::new(mesh)?;
        let n = vm.n_cells();
        Ok(Coupler {
            vm,
            settings,
            voidage: vec![1.0; n],
            hints: Vec::new(),
            steps: 0,
            spare: Spare::default(),
        })
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

    /// Coupling steps done.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Steps 2–4 of the module docs for `particles` in `fluid`: placement, ε, forces and
    /// exchange fields. Updates the coupler's ε; touches neither side.
    pub fn exchange(
        &mut self,
        particles: &ParticleState<'_>,
        fluid: &FluidState<'_>,
    ) -> Result<CouplingStep, CoupleError> {
        check_particles(particles)?;
        let n_cells = self.vm.n_cells();
        for (what, len) in [
            ("fluid U", fluid.u.len()),
            ("fluid p", fluid.p.len()),
            ("fluid grad(p)", fluid.grad_p.len()),
            ("fluid div(tau)", fluid.div_tau.len()),
        ] {
            if len != n_cells {
                return Err(CoupleError::Length {
                    what,
                    expected: n_cells,
                    found: len,
                });
            }
        }
        if self.hints.len() != particles.len() {
            self.hints = vec![None; particles.len()];
        }
        let set = ParticleSet {
            positions: particles.position,
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
        let deposit = self
            .vm
            .shares_with_cells_into(method, &set, &mut self.hints, &mut shares)?;
        let voidage = self.vm.voidage(&deposit, self.settings.alpha_min)?;
        let mut centre = std::mem::take(&mut self.spare.centre);
        centre.clone_from(&self.hints);
        let placement = Placement { centre, shares };
        let (forces, exchange) = couplings_and_exchange(
            &self.settings.physics,
            &placement,
            fluid,
            &voidage.epsilon,
            particles,
            self.vm.cell_volumes(),
            std::mem::take(&mut self.spare.couplings),
        );
        self.voidage.clone_from(&voidage.epsilon);
        Ok(CouplingStep {
            placement,
            deposit,
            voidage,
            forces,
            exchange,
        })
    }

    /// One coupling step (module docs).
    pub fn step<P: ParticleSide, F: FluidSide>(
        &mut self,
        particles: &mut P,
        fluid: &mut F,
    ) -> Result<CouplingStep, CoupleError> {
        let interval = self.settings.coupling_interval;
        particles.advance(interval).map_err(particle_err)?;
        let old = self.voidage.clone();
        let step = self.exchange(&particles.state(), &fluid.state())?;
        let dt = interval as f64 * particles.time_step();
        fluid
            .set_exchange(&ExchangeFields {
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
        fluid.advance(dt).map_err(fluid_err)?;
        self.steps += 1;
        Ok(step)
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

fn particle_err(source: crate::error::SideError) -> CoupleError {
    CoupleError::Side {
        side: "particle",
        source,
    }
}

fn fluid_err(source: crate::error::SideError) -> CoupleError {
    CoupleError::Side {
        side: "fluid",
        source,
    }
}

/// Equal lengths, finite velocities and positive finite densities; the first bad particle as
/// an error naming its index and id. (Positions and radii are checked by the voidage.)
fn check_particles(p: &ParticleState<'_>) -> Result<(), CoupleError> {
    let n = p.ids.len();
    for (what, len) in [
        ("particle positions", p.position.len()),
        ("particle velocities", p.velocity.len()),
        ("particle radii", p.radius.len()),
        ("particle densities", p.density.len()),
    ] {
        if len != n {
            return Err(CoupleError::Length {
                what,
                expected: n,
                found: len,
            });
        }
    }
    let valid = |i: usize| {
        p.velocity[i].iter().all(|x| x.is_finite())
            && p.density[i].is_finite()
            && p.density[i] > 0.0
    };
    if let Some(i) = (0..n).into_par_iter().find_first(|&i| !valid(i)) {
        let message = if !p.velocity[i].iter().all(|x| x.is_finite()) {
            format!("non-finite velocity {:?}", p.velocity[i])
        } else {
            format!("density {} is not a positive number", p.density[i])
        };
        return Err(CoupleError::Particle {
            index: i,
            id: Some(p.ids[i]),
            message,
        });
    }
    Ok(())
}
