//! The two sides of a coupling, as traits, and the data they hand over.
//!
//! * [`ParticleSide`]: a DEM (LIGGGHTS, the native DEM, a dump replay, a test double) that
//!   advances N steps, shows its particles ([`ParticleState`]) and takes per-particle forces:
//!   an explicit force `F_ext` (N) and an implicit pair (β in kg/s, u_f in m/s) to be applied as
//!   `F = F_ext + β (u_f − v)` every DEM step until the next exchange (ADR 0004).
//! * [`FluidSide`]: a CFD solver (OpenFOAM, the native `fv`, a frozen field, a test double)
//!   that takes the exchange fields ([`ExchangeFields`]: ε old/new, Ksl, Us, f) for the next
//!   coupling interval, advances, and shows U, p, ∇p, ∇·τ per cell ([`FluidState`]).
//!
//! Both return [`SideError`]s, which the coupler wraps with the side's name.

use crate::error::SideError;
use crate::exchange::Exchange;
use foam::PolyMesh;
use mesh::v3::V3;

/// The particles as a DEM side shows them (structure of arrays, SI units).
#[derive(Clone, Copy, Debug)]
pub struct ParticleState<'a> {
    /// Particle ids (LIGGGHTS tags).
    pub ids: &'a [u64],
    /// Centres, m.
    pub position: &'a [V3],
    /// Velocities, m/s.
    pub velocity: &'a [V3],
    /// Radii, m.
    pub radius: &'a [f64],
    /// Densities, kg/m³.
    pub density: &'a [f64],
    /// Temperatures T_p, K, when the particle side carries heat (LIGGGHTS's `fix heat/gran`
    /// property `Temp`); `None` otherwise.
    pub temperature: Option<&'a [f64]>,
}

impl ParticleState<'_> {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }
}

/// The fluid per cell as a fluid side shows it (SI units, kinematic pressure).
#[derive(Clone, Copy, Debug)]
pub struct FluidState<'a> {
    /// Interstitial velocity U, m/s.
    pub u: &'a [V3],
    /// Kinematic pressure p/ρ, m²/s².
    pub p: &'a [f64],
    /// ∇(p/ρ), m/s².
    pub grad_p: &'a [V3],
    /// ∇·(τ/ρ), m/s².
    pub div_tau: &'a [V3],
    /// Temperature T, K, when the fluid solves cfdemSolverPisoScalar's temperature equation
    /// (the case has `0/T`); `None` otherwise.
    pub temperature: Option<&'a [f64]>,
    /// The vorticity ∇ × U, 1/s (OpenFOAM's `fvc::curl(U)`), when the coupling's force models
    /// ask for it (`MeiLift`, `SaffmanLift`: [`crate::config::Forces::needs_vorticity`]);
    /// `None` otherwise.
    pub vorticity: Option<&'a [V3]>,
    /// DU/Dt as CFDEM's `virtualMassForce` forms it, `fvc::ddt(U) + fvc::div(phi, U)`, m/s²,
    /// when a force model asks for it ([`crate::config::Forces::needs_ddt_u`]); `None`
    /// otherwise.
    pub ddt_u: Option<&'a [V3]>,
    /// The k–ε model's k and ε per cell, when a force model asks for them (`KochHillRWDrag`:
    /// [`crate::config::Forces::needs_turbulence`]) and the fluid solves k–ε; `None` otherwise.
    pub turbulence: Option<Turbulence<'a>>,
}

/// The k–ε fields of a turbulent fluid, per cell.
#[derive(Clone, Copy, Debug)]
pub struct Turbulence<'a> {
    /// Turbulent kinetic energy k, m²/s².
    pub k: &'a [f64],
    /// Its dissipation rate ε, m²/s³.
    pub epsilon: &'a [f64],
}

/// What the fluid receives for the next coupling interval.
#[derive(Clone, Copy, Debug)]
pub struct ExchangeFields<'a> {
    /// ε at the start of the interval.
    pub voidage_old: &'a [f64],
    /// ε at its end (blend linearly in between, [`crate::blend`]).
    pub voidage_new: &'a [f64],
    /// Ksl, Us and f.
    pub exchange: &'a Exchange,
    /// Length of the coupling interval, s.
    pub interval: f64,
    /// The particles' heat source per cell, CFDEM's `Tsource` (K/s: −Σ q_p share / (ρ c_p V)),
    /// held over the interval, when the coupling carries heat; `None` otherwise.
    pub heat_source: Option<&'a [f64]>,
}

/// A DEM side.
pub trait ParticleSide {
    /// Advances `steps` DEM steps (with the forces last given).
    fn advance(&mut self, steps: u64) -> Result<(), SideError>;
    /// The DEM time step, s.
    fn time_step(&self) -> f64;
    /// The current simulated time, s.
    fn time(&self) -> f64;
    /// The particles now.
    fn state(&self) -> ParticleState<'_>;
    /// Per-particle forces until the next exchange, in the order of [`ParticleSide::state`]:
    /// explicit `f_ext` (N), implicit `beta` (kg/s) and `u_f` (m/s).
    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError>;
    /// The convective heat flux q_p (W, into the particle) per particle until the next
    /// exchange, in the order of [`ParticleSide::state`] (LIGGGHTS's `fix couple/cfd/convection`
    /// property `convectiveHeatFlux`). The default refuses: the side carries no heat.
    fn set_heat_flux(&mut self, q: &[f64]) -> Result<(), SideError> {
        let _ = q;
        Err("this particle side carries no heat (no `fix heat/gran` and `fix couple/cfd/convection`)".into())
    }
    /// Runs one LIGGGHTS command on the particle side (CFDEM's `liggghtsCommands`, e.g.
    /// `write_restart FILE`). The default refuses every command, naming it.
    fn command(&mut self, command: &str) -> Result<(), SideError> {
        Err(format!("this particle side cannot run LIGGGHTS commands (`{command}`)").into())
    }
    /// Bytes this side holds on the heap of the coupler's process for its particles (its
    /// copies of their state and its force buffers, [`foam::HeapBytes`]; not a DEM library's
    /// own arrays); `None` (the default): not counted.
    fn held_bytes(&self) -> Option<usize> {
        None
    }
}

/// A CFD side.
pub trait FluidSide {
    /// The mesh (read once by the coupler to build its voidage mesh).
    fn mesh(&self) -> &PolyMesh;
    /// Takes the exchange fields for the next coupling interval.
    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError>;
    /// Advances the fluid by `dt` seconds (one coupling interval).
    fn advance(&mut self, dt: f64) -> Result<(), SideError>;
    /// The fluid now.
    fn state(&self) -> FluidState<'_>;
    /// Bytes this side holds on the heap of the coupler's process, all of it growing with the
    /// cells ([`foam::HeapBytes`]); `None` (the default): not counted.
    fn held_bytes(&self) -> Option<usize> {
        None
    }
}
