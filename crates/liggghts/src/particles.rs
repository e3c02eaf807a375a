//! The particles as a LIGGGHTS side hands them to the coupler: owned structure-of-arrays
//! buffers ordered by tag (the `ParticleState` the coupler reads), refilled at each exchange
//! without reallocating.

use couple::ParticleState;
use mesh::v3::V3;

/// Particles ordered by tag (SI units).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Particles {
    /// LIGGGHTS tags, increasing.
    pub ids: Vec<u64>,
    /// Centres, m.
    pub position: Vec<V3>,
    /// Velocities, m/s.
    pub velocity: Vec<V3>,
    /// Radii, m.
    pub radius: Vec<f64>,
    /// Densities, kg/m³.
    pub density: Vec<f64>,
    /// Temperatures, K (LIGGGHTS's per-atom `Temp`), when the side exchanges heat.
    pub temperature: Option<Vec<f64>>,
}

impl Particles {
    /// The view the coupler reads.
    pub fn view(&self) -> ParticleState<'_> {
        ParticleState {
            temperature: self.temperature.as_deref(),
            ids: &self.ids,
            position: &self.position,
            velocity: &self.velocity,
            radius: &self.radius,
            density: &self.density,
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Empties the buffers, keeping their memory.
    pub fn clear(&mut self) {
        self.ids.clear();
        self.position.clear();
        self.velocity.clear();
        self.radius.clear();
        self.density.clear();
        if let Some(t) = self.temperature.as_mut() {
            t.clear();
        }
    }

    /// Appends one particle.
    pub fn push(&mut self, id: u64, x: impl Into<V3>, v: impl Into<V3>, radius: f64, density: f64) {
        self.ids.push(id);
        self.position.push(x.into());
        self.velocity.push(v.into());
        self.radius.push(radius);
        self.density.push(density);
    }
}
