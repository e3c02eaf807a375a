//! Particles for the coupler's tests.
#![allow(dead_code)]

use couple::ParticleState;
use mesh::v3::V3;

/// Particles with tags 1…n, d = 2 mm and ρ_p = 2500 kg/m³ unless changed.
pub struct Particles {
    pub ids: Vec<u64>,
    pub position: Vec<V3>,
    pub velocity: Vec<V3>,
    pub radius: Vec<f64>,
    pub density: Vec<f64>,
}

impl Particles {
    pub fn new(position: Vec<V3>, velocity: Vec<V3>) -> Particles {
        let n = position.len();
        Particles {
            ids: (1..=n as u64).collect(),
            position,
            velocity,
            radius: vec![1e-3; n],
            density: vec![2500.0; n],
        }
    }

    pub fn state(&self) -> ParticleState<'_> {
        ParticleState {
            ids: &self.ids,
            position: &self.position,
            velocity: &self.velocity,
            radius: &self.radius,
            density: &self.density,
            temperature: None,
        }
    }
}
