//! In-memory sides for tests and examples.
//!
//! * [`MemoryParticles`]: free spheres (no contacts) moved by the forces the coupler gives,
//!   `m dv/dt = F_ext + β (u_f − v) + m g`, integrated with the drag implicit (backward Euler in
//!   v, then x += dt v), so any β·dt/m is stable. With constant F_ext, β, u_f the exact
//!   solution is v(t) = v∞ + (v₀ − v∞) e^(−βt/m), v∞ = u_f + (F_ext + m g)/β, which the
//!   scheme approaches as O(dt).
//! * [`MemoryFluid`]: fixed cell fields (U, p, ∇p, ∇·τ) that records every exchange it is
//!   given and the time it was advanced by.
//!
//! Both carry a temperature when it is set (`temperature: Some(…)`): the particles keep the
//! last heat flux they were given ([`MemoryParticles::heat_flux`]; they do not heat up), the
//! fluid records the heat source with each exchange; without it they have no heat, as before.

use crate::error::SideError;
use crate::exchange::Exchange;
use crate::sides::{ExchangeFields, FluidSide, FluidState, ParticleSide, ParticleState};
use foam::PolyMesh;
use mesh::v3::V3;

/// Free spheres moved by the coupling forces (module docs).
#[derive(Clone, Debug)]
pub struct MemoryParticles {
    /// Ids.
    pub ids: Vec<u64>,
    /// Centres, m.
    pub position: Vec<V3>,
    /// Velocities, m/s.
    pub velocity: Vec<V3>,
    /// Radii, m.
    pub radius: Vec<f64>,
    /// Densities, kg/m³.
    pub density: Vec<f64>,
    /// Gravity, m/s².
    pub gravity: V3,
    /// DEM step, s.
    pub dt: f64,
    /// Simulated time, s.
    pub time: f64,
    /// Temperatures, K, if the particles carry heat (`None`: they refuse a heat flux).
    pub temperature: Option<Vec<f64>>,
    /// The last heat flux per particle given, W.
    pub heat_flux: Vec<f64>,
    f_ext: Vec<V3>,
    beta: Vec<f64>,
    u_f: Vec<V3>,
}

impl MemoryParticles {
    /// Particles at rest at `position` with radius `radius` and density `density`, ids 1…N.
    pub fn new(position: Vec<V3>, radius: Vec<f64>, density: f64, dt: f64) -> Self {
        let n = position.len();
        MemoryParticles {
            ids: (1..=n as u64).collect(),
            velocity: vec![V3::zeros(); n],
            density: vec![density; n],
            position,
            radius,
            gravity: V3::zeros(),
            dt,
            time: 0.0,
            temperature: None,
            heat_flux: Vec::new(),
            f_ext: vec![V3::zeros(); n],
            beta: vec![0.0; n],
            u_f: vec![V3::zeros(); n],
        }
    }

    /// Mass of particle `i`, kg.
    pub fn mass(&self, i: usize) -> f64 {
        self.density[i] * 4.0 / 3.0 * std::f64::consts::PI * self.radius[i].powi(3)
    }
}

impl ParticleSide for MemoryParticles {
    fn advance(&mut self, steps: u64) -> Result<(), SideError> {
        let dt = self.dt;
        for _ in 0..steps {
            for i in 0..self.ids.len() {
                let m = self.mass(i);
                let b = self.beta[i];
                for a in 0..3 {
                    let rhs = m * self.velocity[i][a]
                        + dt * (self.f_ext[i][a] + b * self.u_f[i][a] + m * self.gravity[a]);
                    self.velocity[i][a] = rhs / (m + b * dt);
                    self.position[i][a] += dt * self.velocity[i][a];
                }
            }
            self.time += dt;
        }
        Ok(())
    }

    fn time_step(&self) -> f64 {
        self.dt
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn state(&self) -> ParticleState<'_> {
        ParticleState {
            temperature: self.temperature.as_deref(),
            ids: &self.ids,
            position: &self.position,
            velocity: &self.velocity,
            radius: &self.radius,
            density: &self.density,
        }
    }

    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError> {
        let n = self.ids.len();
        if f_ext.len() != n || beta.len() != n || u_f.len() != n {
            return Err(format!("forces for {} particles, expected {n}", f_ext.len()).into());
        }
        self.f_ext = f_ext.to_vec();
        self.beta = beta.to_vec();
        self.u_f = u_f.to_vec();
        Ok(())
    }

    fn set_heat_flux(&mut self, q: &[f64]) -> Result<(), SideError> {
        if self.temperature.is_none() {
            return Err("these memory particles carry no temperature".into());
        }
        if q.len() != self.ids.len() {
            return Err(format!(
                "heat flux for {} particles, expected {}",
                q.len(),
                self.ids.len()
            )
            .into());
        }
        self.heat_flux = q.to_vec();
        Ok(())
    }
}

/// One exchange as the fluid received it.
#[derive(Clone, Debug)]
pub struct Received {
    /// ε at the start of the interval.
    pub voidage_old: Vec<f64>,
    /// ε at its end.
    pub voidage_new: Vec<f64>,
    /// Ksl, Us, f.
    pub exchange: Exchange,
    /// The interval, s.
    pub interval: f64,
    /// Tsource per cell, K/s, with heat.
    pub heat_source: Option<Vec<f64>>,
}

/// Fixed fluid fields recording what they receive (module docs).
#[derive(Clone, Debug)]
pub struct MemoryFluid {
    /// The mesh.
    pub mesh: PolyMesh,
    /// U per cell, m/s.
    pub u: Vec<V3>,
    /// Kinematic p per cell, m²/s².
    pub p: Vec<f64>,
    /// ∇p per cell, m/s².
    pub grad_p: Vec<V3>,
    /// ∇·τ per cell, m/s².
    pub div_tau: Vec<V3>,
    /// Every exchange received, in order.
    pub received: Vec<Received>,
    /// Simulated time, s.
    pub time: f64,
    /// T per cell, K, if the fluid carries heat.
    pub temperature: Option<Vec<f64>>,
    /// ∇ × U per cell, 1/s, if given ([`FluidState::vorticity`]).
    pub vorticity: Option<Vec<V3>>,
    /// DU/Dt per cell, m/s², if given ([`FluidState::ddt_u`]).
    pub ddt_u: Option<Vec<V3>>,
    /// k (m²/s²) and ε (m²/s³) per cell, if given ([`FluidState::turbulence`]).
    pub k_epsilon: Option<(Vec<f64>, Vec<f64>)>,
}

impl MemoryFluid {
    /// Uniform U, zero p and gradients, on `mesh`.
    pub fn uniform(mesh: PolyMesh, u: V3) -> Self {
        let n = mesh.n_cells;
        MemoryFluid {
            mesh,
            u: vec![u; n],
            p: vec![0.0; n],
            grad_p: vec![V3::zeros(); n],
            div_tau: vec![V3::zeros(); n],
            received: Vec::new(),
            time: 0.0,
            temperature: None,
            vorticity: None,
            ddt_u: None,
            k_epsilon: None,
        }
    }
}

impl FluidSide for MemoryFluid {
    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError> {
        self.received.push(Received {
            voidage_old: fields.voidage_old.to_vec(),
            voidage_new: fields.voidage_new.to_vec(),
            exchange: fields.exchange.clone(),
            interval: fields.interval,
            heat_source: fields.heat_source.map(<[f64]>::to_vec),
        });
        Ok(())
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.time += dt;
        Ok(())
    }

    fn state(&self) -> FluidState<'_> {
        FluidState {
            vorticity: self.vorticity.as_deref(),
            ddt_u: self.ddt_u.as_deref(),
            turbulence: self
                .k_epsilon
                .as_ref()
                .map(|(k, epsilon)| crate::sides::Turbulence { k, epsilon }),
            temperature: self.temperature.as_deref(),
            u: &self.u,
            p: &self.p,
            grad_p: &self.grad_p,
            div_tau: &self.div_tau,
        }
    }
}
