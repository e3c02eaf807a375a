//! The convective heat exchanged between fluid and particles in one coupling step, CFDEM's
//! `LaEuScalarTemp` / `heatTransferGunn` ([`crate::config::HeatSettings`]).
//!
//! Per particle p inside the mesh, with d = 2r, the fluid's U, T and ε at the particle (the
//! centre cell's value or the share-weighted average, as the `interpolation` switch says,
//! [`crate::interpolate`]) and the particle's v and T_p:
//! * Re = d |U − v| / ν (× ε for the superficial convention of PFM's `heatTransferGunn` and
//!   `scalarGeneralExchange`), Pr = c_p ν ρ / λ (or the model's given Pr), Nu from the law
//!   ([`closures::heat`]), h = λ Nu / d (W/(m²·K));
//! * q_p = h π d² (T_f − T_p), W, into the particle (what the DEM side gets,
//!   [`crate::ParticleSide::set_heat_flux`]).
//!
//! Per cell c of volume V_c, with w_pc the renormalised voidage share of particle p in c — the
//! same shares as the momentum exchange ([`crate::exchange`](mod@crate::exchange)):
//! Tsource_c = −Σ_p w_pc q_p / (ρ c_p V_c), K/s, the source of the fluid's temperature
//! equation (CFDEM's `Tsource`); |Tsource| above `maxSource` is cut to it and the heat cut
//! counted ([`HeatAccount::clipped`]).
//!
//! A particle with no share in any cell gets q = 0 and is counted. Σ_p q_p = −Σ_c Tsource_c ρ
//! c_p V_c + clipped to round-off ([`HeatAccount::imbalance`]). The per-particle loop is
//! parallel; the sums run in particle order, so results do not depend on the thread count.

use crate::config::HeatSettings;
use crate::error::CoupleError;
use crate::interpolate::Placement;
use crate::sides::ParticleState;
use closures::heat::{heat_flow, heat_transfer_coefficient, nusselt, prandtl, reynolds};
use mesh::v3::V3;
use rayon::prelude::*;

/// The heat balance of one coupling step, over all ranks (W unless stated).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HeatAccount {
    /// Σ_p q_p: the heat the particles receive, W.
    pub to_particles: f64,
    /// −Σ_c Tsource_c ρ c_p V_c: the heat the fluid gives (with the clipped source), W.
    pub from_fluid: f64,
    /// Heat the particles receive that the fluid does not give because `maxSource` cut its
    /// source (the cut's −Σ ΔTsource ρ c_p V), W.
    pub clipped: f64,
    /// Cells whose source `maxSource` cut.
    pub clipped_cells: usize,
    /// to_particles − from_fluid − clipped: round-off, W.
    pub imbalance: f64,
    /// Particles outside the mesh (q = 0).
    pub particles_outside: usize,
    /// Heat the walls give the fluid (`wallHeatTransferYagi`, [`crate::wall_heat`]), in
    /// Tsource besides the particles' part, W; 0 without it.
    pub from_wall: f64,
    /// Wall heat `maxSource` kept out of the fluid, W.
    pub wall_clipped: f64,
    /// Σ_p of the conduction between particles (`heatTransferInterGrain`,
    /// [`crate::inter_grain`]), included in `q` but not in `to_particles`: 0 to round-off, W.
    pub between_particles: f64,
}

/// The heat of one coupling step.
#[derive(Clone, Debug, PartialEq)]
pub struct HeatStep {
    /// q_p per particle (this rank's), W into the particle.
    pub q: Vec<f64>,
    /// Tsource per cell, K/s (on rank 0 of several ranks; empty on the others, and on every
    /// rank when the cells' owners are elsewhere, [`crate::ranks::CellOwners`]).
    pub tsource: Vec<f64>,
    /// The balance.
    pub account: HeatAccount,
}

/// The fluid properties the heat needs besides [`HeatSettings`].
#[derive(Clone, Copy, Debug)]
pub struct HeatFluid {
    /// Density ρ, kg/m³.
    pub rho: f64,
    /// Kinematic viscosity ν, m²/s.
    pub nu: f64,
}

/// The fluid per cell as the heat reads it.
#[derive(Clone, Copy, Debug)]
pub struct CellFields<'a> {
    /// ε.
    pub eps: &'a [f64],
    /// U, m/s.
    pub u: &'a [V3],
    /// T, K.
    pub t: &'a [f64],
}

/// The particles' side of a step: q per particle, its sums and what lay outside.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleHeat {
    /// q_p per particle, W (0 outside the mesh).
    pub q: Vec<f64>,
    /// Σ_p q_p in particle order, W.
    pub to_particles: f64,
    /// Particles outside the mesh.
    pub outside: usize,
}

/// q_p of every particle (module docs) in the fluid `cells`; parallel over particles. The
/// particles must carry temperatures (else an error saying so); the first particle whose q is
/// not finite (a non-finite temperature, or ε, U or T at it) is an error naming it.
pub fn particle_heat(
    heat: &HeatSettings,
    fluid: HeatFluid,
    placement: &Placement,
    cells: CellFields<'_>,
    particles: &ParticleState<'_>,
) -> Result<ParticleHeat, CoupleError> {
    let t_particles = particle_temperatures(particles)?;
    let CellFields { eps, u, t } = cells;
    let pr = heat
        .prandtl
        .unwrap_or_else(|| prandtl(heat.cp, fluid.nu, fluid.rho, heat.lambda));
    let rule = heat.interpolation;
    let one = |i: usize| -> Option<f64> {
        let u_f = placement.value_at(u, i, rule)?;
        let e = placement.value_at(eps, i, rule)?;
        let t_f = placement.value_at(t, i, rule)?;
        // ε outside [0, 1] is a voidage artefact (counted by the voidage); the laws need it
        // in range, and PFM's floor applies
        let e = e.clamp(heat.voidage_floor.max(0.0), 1.0);
        let d = 2.0 * particles.radius[i];
        let slip = (u_f - particles.velocity[i]).norm();
        let re = reynolds(heat.reynolds, d, slip, fluid.nu, e);
        let nu_number = heat.nusselt_scale * nusselt(heat.nusselt, re, pr, e);
        let h = heat_transfer_coefficient(heat.lambda, nu_number, d);
        Some(heat_flow(h, d, t_f, t_particles[i]))
    };
    let n = placement.len();
    let mut q = Vec::with_capacity(n);
    (0..n)
        .into_par_iter()
        .map(|i| one(i).unwrap_or(f64::NAN))
        .collect_into_vec(&mut q);
    let mut to_particles = 0.0;
    let mut outside = 0;
    for (i, x) in q.iter_mut().enumerate() {
        if !placement.inside(i) {
            *x = 0.0;
            outside += 1;
        } else if !x.is_finite() {
            return Err(CoupleError::Particle {
                index: i,
                id: particles.ids.get(i).copied(),
                message: format!(
                    "heat flux {x}: its temperature {} K or the fluid's ε, U or T at it is not \
                     finite",
                    t_particles[i]
                ),
            });
        } else {
            to_particles += *x;
        }
    }
    Ok(ParticleHeat {
        q,
        to_particles,
        outside,
    })
}

/// Σ_p w_pc q_p per cell of `n_cells` (W), added in particle order.
pub fn cell_heat(placement: &Placement, q: &[f64], n_cells: usize) -> Vec<f64> {
    let mut w = vec![0.0; n_cells];
    for (i, &x) in q.iter().enumerate() {
        placement.for_each_weight(i, |c, s| w[c as usize] += s * x);
    }
    w
}

/// The fluid's side: Tsource per cell from the heat the particles take per cell `cell_w` (W),
/// and the account's fluid part (`from_fluid`, `clipped`, `clipped_cells`).
pub fn heat_source(
    heat: &HeatSettings,
    rho: f64,
    cell_w: &[f64],
    cell_volumes: &[f64],
) -> (Vec<f64>, HeatAccount) {
    let rho_cp = rho * heat.cp;
    let limit = heat.max_source.map(|m| m.kelvin_per_second(rho_cp));
    let mut account = HeatAccount::default();
    let tsource = cell_w
        .iter()
        .zip(cell_volumes)
        .map(|(&w, &v)| {
            let s = -w / (rho_cp * v);
            match limit {
                Some(max) if s.abs() > max => {
                    let cut = max.copysign(s);
                    account.clipped -= (s - cut) * rho_cp * v;
                    account.clipped_cells += 1;
                    account.from_fluid -= cut * rho_cp * v;
                    cut
                }
                _ => {
                    account.from_fluid -= s * rho_cp * v;
                    s
                }
            }
        })
        .collect();
    (tsource, account)
}

impl HeatAccount {
    /// The account of `particles` (over all ranks) and the fluid part `fluid` of
    /// [`heat_source`], with the imbalance.
    pub fn close(particles: &ParticleHeat, fluid: HeatAccount) -> HeatAccount {
        HeatAccount {
            to_particles: particles.to_particles,
            particles_outside: particles.outside,
            imbalance: particles.to_particles - fluid.from_fluid - fluid.clipped,
            ..fluid
        }
    }
}

/// One rank's heat step (module docs) on cells of volumes `cell_volumes`.
pub fn heat_step(
    heat: &HeatSettings,
    fluid: HeatFluid,
    placement: &Placement,
    cells: CellFields<'_>,
    particles: &ParticleState<'_>,
    cell_volumes: &[f64],
) -> Result<HeatStep, CoupleError> {
    let p = particle_heat(heat, fluid, placement, cells, particles)?;
    let w = cell_heat(placement, &p.q, cell_volumes.len());
    let (tsource, f) = heat_source(heat, fluid.rho, &w, cell_volumes);
    let account = HeatAccount::close(&p, f);
    Ok(HeatStep {
        q: p.q,
        tsource,
        account,
    })
}

/// The particles' temperatures, or the error that they carry none (what the case needs).
pub fn particle_temperatures<'a>(particles: &ParticleState<'a>) -> Result<&'a [f64], CoupleError> {
    let t = particles.temperature.ok_or_else(|| {
        CoupleError::Parameter(
            "the heat transfer is on, but the particle side has no temperatures: the LIGGGHTS \
             deck needs `fix heat/gran` (with `fix property/global thermalConductivity` and \
             `thermalCapacity`) and `fix couple/cfd/convection`"
                .into(),
        )
    })?;
    if t.len() != particles.len() {
        return Err(CoupleError::Length {
            what: "particle temperatures",
            expected: particles.len(),
            found: t.len(),
        });
    }
    Ok(t)
}

/// The fluid's temperature per cell, or the error that it has none (what the case needs).
pub fn fluid_temperature(t: Option<&[f64]>, n_cells: usize) -> Result<&[f64], CoupleError> {
    let t = t.ok_or_else(|| {
        CoupleError::Parameter(
            "the heat transfer is on, but the fluid side has no temperature: the case needs \
             the field `0/T` and a fluid that solves the temperature equation \
             (cfdemSolverPisoScalar's)"
                .into(),
        )
    })?;
    if t.len() != n_cells {
        return Err(CoupleError::Length {
            what: "fluid T",
            expected: n_cells,
            found: t.len(),
        });
    }
    Ok(t)
}
