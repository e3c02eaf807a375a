//! A particle side that never moves: a packed bed frozen in place, so that every coupling step
//! is one fluid step with the same voidage (and Ksl changing only through the fluid velocity).
//!
//! [`ParticleSide::advance`] only counts time; positions stay bit for bit what they were and
//! velocities are zero. The forces the coupler hands over are checked for length and kept for
//! the caller ([`FrozenParticles::forces`]): they would move a free bed, but move nothing here.

use crate::pack::PackedBed;
use couple::{ParticleSide, ParticleState, SideError};
use mesh::v3::V3;

/// A frozen bed (module docs).
#[derive(Clone, Debug)]
pub struct FrozenParticles {
    bed: PackedBed,
    velocity: Vec<V3>,
    dt: f64,
    steps: u64,
    f_ext: Vec<V3>,
    beta: Vec<f64>,
    u_f: Vec<V3>,
}

impl FrozenParticles {
    /// Freezes `bed`; `dt` (s) is the DEM step the coupler multiplies by its coupling
    /// interval to get the fluid's interval. `dt` must be positive and finite.
    pub fn new(bed: PackedBed, dt: f64) -> Result<FrozenParticles, SideError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(format!("DEM time step {dt} is not a positive number").into());
        }
        let n = bed.len();
        Ok(FrozenParticles {
            bed,
            velocity: vec![V3::zeros(); n],
            dt,
            steps: 0,
            f_ext: vec![V3::zeros(); n],
            beta: vec![0.0; n],
            u_f: vec![V3::zeros(); n],
        })
    }

    /// The bed.
    pub fn bed(&self) -> &PackedBed {
        &self.bed
    }

    /// DEM steps counted so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The forces last set: F_ext (N), β (kg/s), u_f (m/s), one per particle.
    pub fn forces(&self) -> (&[V3], &[f64], &[V3]) {
        (&self.f_ext, &self.beta, &self.u_f)
    }
}

impl ParticleSide for FrozenParticles {
    fn advance(&mut self, steps: u64) -> Result<(), SideError> {
        self.steps += steps;
        Ok(())
    }

    fn time_step(&self) -> f64 {
        self.dt
    }

    fn time(&self) -> f64 {
        self.steps as f64 * self.dt
    }

    fn state(&self) -> ParticleState<'_> {
        ParticleState {
            temperature: None,
            ids: &self.bed.ids,
            position: &self.bed.position,
            velocity: &self.velocity,
            radius: &self.bed.radius,
            density: &self.bed.density,
        }
    }

    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError> {
        let n = self.bed.len();
        if f_ext.len() != n || beta.len() != n || u_f.len() != n {
            return Err(format!(
                "forces for {} / {} / {} particles, the frozen bed has {n}",
                f_ext.len(),
                beta.len(),
                u_f.len()
            )
            .into());
        }
        self.f_ext.clone_from_slice(f_ext);
        self.beta.clone_from_slice(beta);
        self.u_f.clone_from_slice(u_f);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bed() -> PackedBed {
        PackedBed {
            ids: vec![1, 2],
            position: vec![V3::new(0.1, 0.2, 0.3), V3::new(0.4, 0.5, 0.6)],
            radius: vec![0.01, 0.02],
            density: vec![2500.0, 2500.0],
        }
    }

    #[test]
    fn advancing_moves_nothing_and_counts_time() {
        let mut f = FrozenParticles::new(bed(), 1e-3).unwrap();
        f.set_forces(
            &[V3::new(1.0, 2.0, 3.0); 2],
            &[5.0, 6.0],
            &[V3::new(0.0, 0.0, 9.0); 2],
        )
        .unwrap();
        f.advance(250).unwrap();
        let s = f.state();
        assert_eq!(s.position, bed().position.as_slice());
        assert_eq!(s.velocity, [V3::zeros(); 2].as_slice());
        assert!((f.time() - 0.25).abs() < 1e-15);
        assert_eq!(f.forces().1, [5.0, 6.0].as_slice());
    }

    #[test]
    fn wrong_lengths_and_time_steps_are_refused() {
        let mut f = FrozenParticles::new(bed(), 1e-3).unwrap();
        let e = f
            .set_forces(&[V3::zeros(); 3], &[0.0; 3], &[V3::zeros(); 3])
            .unwrap_err();
        assert!(e.to_string().contains("frozen bed has 2"), "{e}");
        assert!(FrozenParticles::new(bed(), 0.0).is_err());
        assert!(FrozenParticles::new(bed(), f64::NAN).is_err());
    }
}
