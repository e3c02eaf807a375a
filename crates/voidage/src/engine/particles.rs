//! The particles of a deposit ([`ParticleSet`]) and their check.

use crate::error::{ParticleProblem, VoidageError};
use crate::sphere_box::ball_volume;
use crate::vec3::V3;
use rayon::prelude::*;

/// Particle data for a deposit: positions (m), radii (m) and optional ids (for error messages).
#[derive(Clone, Copy, Debug)]
pub struct ParticleSet<'a> {
    /// Centre positions, m.
    pub positions: &'a [V3],
    /// Radii, m (≥ 0 with a finite volume; zero-radius particles deposit nothing).
    pub radii: &'a [f64],
    /// Particle ids (LIGGGHTS tags), same length, if known.
    pub ids: Option<&'a [u64]>,
}

impl<'a> ParticleSet<'a> {
    /// Positions and radii without ids.
    pub fn new(positions: &'a [V3], radii: &'a [f64]) -> Self {
        ParticleSet {
            positions,
            radii,
            ids: None,
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Checks lengths and values: the first bad particle (by index) as an error.
    pub fn check(&self) -> Result<(), VoidageError> {
        let n = self.positions.len();
        let mismatch = |what, found| VoidageError::LengthMismatch {
            what,
            expected: n,
            found,
        };
        if self.radii.len() != n {
            return Err(mismatch("radii", self.radii.len()));
        }
        if let Some(ids) = self.ids {
            if ids.len() != n {
                return Err(mismatch("ids", ids.len()));
            }
        }
        let bad = self
            .positions
            .par_iter()
            .zip(self.radii.par_iter())
            .position_first(|(p, &r)| {
                !(p.iter().all(|x| x.is_finite()) && r >= 0.0 && ball_volume(r).is_finite())
            });
        if let Some(index) = bad {
            let p = self.positions[index];
            let problem = if p.iter().all(|x| x.is_finite()) {
                ParticleProblem::BadRadius(self.radii[index])
            } else {
                ParticleProblem::NonFinitePosition(p)
            };
            return Err(VoidageError::InvalidParticle {
                index,
                id: self.ids.map(|ids| ids[index]),
                problem,
            });
        }
        Ok(())
    }
}
