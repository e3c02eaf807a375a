//! Particle state as a structure of arrays (SI units throughout).

use mesh::v3::V3;

use crate::error::DemError;

/// Moment-of-inertia factor of a solid sphere, I = (2/5) m R².
pub const INERTIA_FACTOR: f64 = 0.4;

/// The spheres of a simulation. All vectors have the same length; index order is insertion
/// order (ids are kept, never renumbered).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Particles {
    /// Particle ids (LIGGGHTS tags, ≥ 1).
    pub id: Vec<u64>,
    /// Atom types (1-based).
    pub atom_type: Vec<u32>,
    /// Centres (m).
    pub x: Vec<V3>,
    /// Velocities (m/s).
    pub v: Vec<V3>,
    /// Angular velocities (rad/s).
    pub omega: Vec<V3>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Densities (kg/m³).
    pub density: Vec<f64>,
    /// Masses (kg), (4/3)πR³ρ.
    pub mass: Vec<f64>,
    /// Total force of the last force evaluation (N).
    pub f: Vec<V3>,
    /// Total torque of the last force evaluation (N·m).
    pub torque: Vec<V3>,
    /// Periodic image counters `ix iy iz`: box lengths the particle was moved back by
    /// ([`crate::periodic`]); zero in a box without periodic axes.
    pub image: Vec<[i32; 3]>,
}

/// One new particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewParticle {
    /// Id (0 = assign the next free one).
    pub id: u64,
    /// Atom type (1-based).
    pub atom_type: u32,
    /// Centre (m).
    pub x: V3,
    /// Velocity (m/s).
    pub v: V3,
    /// Angular velocity (rad/s).
    pub omega: V3,
    /// Radius (m).
    pub radius: f64,
    /// Density (kg/m³).
    pub density: f64,
}

impl Particles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// `true` without particles.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// The largest id in use (0 if none).
    pub fn max_id(&self) -> u64 {
        self.id.iter().copied().max().unwrap_or(0)
    }

    /// Appends a particle after checking it (`ntypes` types exist).
    pub fn push(&mut self, p: NewParticle, ntypes: usize) -> Result<(), DemError> {
        let id = if p.id == 0 { self.max_id() + 1 } else { p.id };
        let bad = |message: String| Err(DemError::Particle { id, message });
        if !(p.radius > 0.0 && p.radius.is_finite()) {
            return bad(format!("radius {} must be > 0", p.radius));
        }
        if !(p.density > 0.0 && p.density.is_finite()) {
            return bad(format!("density {} must be > 0", p.density));
        }
        if p.atom_type == 0 || p.atom_type as usize > ntypes {
            return bad(format!("type {} outside 1..={ntypes}", p.atom_type));
        }
        if !p
            .x
            .iter()
            .chain(&p.v)
            .chain(&p.omega)
            .all(|c| c.is_finite())
        {
            return bad("non-finite position, velocity or angular velocity".into());
        }
        self.id.push(id);
        self.atom_type.push(p.atom_type);
        self.x.push(p.x);
        self.v.push(p.v);
        self.omega.push(p.omega);
        self.radius.push(p.radius);
        self.density.push(p.density);
        self.mass
            .push(4.0 / 3.0 * std::f64::consts::PI * p.radius.powi(3) * p.density);
        self.f.push(V3::zeros());
        self.torque.push(V3::zeros());
        self.image.push([0; 3]);
        Ok(())
    }

    /// Keeps the particles for which `keep[i]` is true; returns the new index of each old one.
    pub fn retain(&mut self, keep: &[bool]) -> Vec<Option<usize>> {
        let mut map = Vec::with_capacity(keep.len());
        let mut k = 0;
        for &kp in keep {
            map.push(kp.then(|| {
                k += 1;
                k - 1
            }));
        }
        fn filter<T: Copy>(v: &mut Vec<T>, keep: &[bool]) {
            let mut it = keep.iter();
            v.retain(|_| *it.next().unwrap());
        }
        filter(&mut self.id, keep);
        filter(&mut self.atom_type, keep);
        filter(&mut self.x, keep);
        filter(&mut self.v, keep);
        filter(&mut self.omega, keep);
        filter(&mut self.radius, keep);
        filter(&mut self.density, keep);
        filter(&mut self.mass, keep);
        filter(&mut self.f, keep);
        filter(&mut self.torque, keep);
        filter(&mut self.image, keep);
        map
    }

    /// Renumbers the particles: the one now at index `new` is the one that was at `perm[new]`
    /// (`perm` a permutation of `0..len()`).
    pub fn permute(&mut self, perm: &[u32]) {
        debug_assert_eq!(perm.len(), self.len());
        permute(&mut self.id, perm);
        permute(&mut self.atom_type, perm);
        permute(&mut self.x, perm);
        permute(&mut self.v, perm);
        permute(&mut self.omega, perm);
        permute(&mut self.radius, perm);
        permute(&mut self.density, perm);
        permute(&mut self.mass, perm);
        permute(&mut self.f, perm);
        permute(&mut self.torque, perm);
        permute(&mut self.image, perm);
    }

    /// Total kinetic energy, translational plus rotational (J).
    pub fn kinetic_energy(&self) -> f64 {
        self.translational_energy() + self.rotational_energy()
    }

    /// Σ ½ m |v|² (J): LIGGGHTS's thermo `ke` (with `thermo_modify norm no`).
    pub fn translational_energy(&self) -> f64 {
        (0..self.len())
            .map(|i| 0.5 * self.mass[i] * self.v[i].dot(&self.v[i]))
            .sum()
    }

    /// Σ ½ I |ω|² with I = ⅖ m r² (J): LIGGGHTS's `compute erotate/sphere`.
    pub fn rotational_energy(&self) -> f64 {
        (0..self.len())
            .map(|i| {
                let inertia = INERTIA_FACTOR * self.mass[i] * self.radius[i] * self.radius[i];
                0.5 * inertia * self.omega[i].dot(&self.omega[i])
            })
            .sum()
    }
}

/// Reorders `v` so that `v[new]` is the former `v[perm[new]]`.
pub(crate) fn permute<T: Copy>(v: &mut Vec<T>, perm: &[u32]) {
    *v = perm.iter().map(|&old| v[old as usize]).collect();
}
