//! The particle side of the CFD–DEM exchange (ADR 0004): per particle an explicit force
//! F_ext (N) and an implicit pair (β in kg/s, u_f in m/s), applied at every DEM step until the
//! next exchange as F = F_ext + β(u_f − v), like LIGGGHTS's `couple/cfd/force/implicit`.
//! v is the particle velocity when forces are evaluated (after the drift, i.e. the half-step
//! velocity of velocity Verlet, as in LIGGGHTS's `post_force`); the explicit drag is stable
//! for β·dt/m < 2, which [`Coupling::set`] checks against the particle masses.

use mesh::v3::V3;

use crate::error::DemError;

/// Coupling forces per particle (all empty = no coupling).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Coupling {
    /// Explicit force F_ext (N).
    pub f_ext: Vec<V3>,
    /// Drag coefficient β (kg/s).
    pub beta: Vec<f64>,
    /// Fluid velocity at the particle u_f (m/s).
    pub u_f: Vec<V3>,
}

impl Coupling {
    /// Whether coupling data is present.
    pub fn is_active(&self) -> bool {
        !self.f_ext.is_empty()
    }

    /// Replaces the data after checking lengths (= `ids.len()`), finiteness, β ≥ 0 and the
    /// explicit-drag stability limit β·dt/m < 2 (naming the particle by id).
    pub fn set(
        &mut self,
        f_ext: &[V3],
        beta: &[f64],
        u_f: &[V3],
        ids: &[u64],
        mass: &[f64],
        dt: f64,
    ) -> Result<(), DemError> {
        let n = ids.len();
        if f_ext.len() != n || beta.len() != n || u_f.len() != n {
            return Err(DemError::Coupling(format!(
                "{} particles but {} forces, {} drag coefficients, {} fluid velocities",
                n,
                f_ext.len(),
                beta.len(),
                u_f.len()
            )));
        }
        for i in 0..n {
            let finite = f_ext[i].iter().chain(&u_f[i]).all(|c| c.is_finite());
            if !(finite && beta[i] >= 0.0 && beta[i].is_finite()) {
                return Err(DemError::Coupling(format!(
                    "particle {}: F_ext {:?}, β {}, u_f {:?} (finite values and β ≥ 0 needed)",
                    ids[i], f_ext[i], beta[i], u_f[i]
                )));
            }
            if beta[i] * dt >= 2.0 * mass[i] {
                return Err(DemError::Coupling(format!(
                    "particle {}: β·dt/m = {} ≥ 2, the explicit drag would be unstable \
                     (reduce the DEM time step)",
                    ids[i],
                    beta[i] * dt / mass[i]
                )));
            }
        }
        self.f_ext = f_ext.to_vec();
        self.beta = beta.to_vec();
        self.u_f = u_f.to_vec();
        Ok(())
    }

    /// The coupling force on particle `i` moving at `v` (N).
    #[inline]
    pub fn force(&self, i: usize, v: V3) -> V3 {
        if self.f_ext.is_empty() {
            return V3::zeros();
        }
        let (f, b, u) = (self.f_ext[i], self.beta[i], self.u_f[i]);
        V3::new(
            f[0] + b * (u[0] - v[0]),
            f[1] + b * (u[1] - v[1]),
            f[2] + b * (u[2] - v[2]),
        )
    }

    /// Keeps the entries of surviving particles (`map[old] = Some(new)`).
    pub fn remap(&mut self, map: &[Option<usize>]) {
        if !self.is_active() {
            return;
        }
        let keep: Vec<bool> = map.iter().map(Option::is_some).collect();
        let mut k = keep.iter();
        self.f_ext.retain(|_| *k.next().unwrap());
        let mut k = keep.iter();
        self.beta.retain(|_| *k.next().unwrap());
        let mut k = keep.iter();
        self.u_f.retain(|_| *k.next().unwrap());
    }

    /// Follows a renumbering of the particles (`perm[new] = old`, see [`Particles::permute`]).
    ///
    /// [`Particles::permute`]: crate::particles::Particles::permute
    pub fn permute(&mut self, perm: &[u32]) {
        if self.is_active() {
            crate::particles::permute(&mut self.f_ext, perm);
            crate::particles::permute(&mut self.beta, perm);
            crate::particles::permute(&mut self.u_f, perm);
        }
    }

    /// Extends with zero coupling for `n` new particles.
    pub fn grow(&mut self, n: usize) {
        if self.is_active() {
            self.f_ext.resize(self.f_ext.len() + n, V3::zeros());
            self.beta.resize(self.beta.len() + n, 0.0);
            self.u_f.resize(self.u_f.len() + n, V3::zeros());
        }
    }
}
