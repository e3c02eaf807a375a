//! What a deposit produces: the solid volume per cell with its accounting ([`Deposit`]) and,
//! when asked for, every particle's (cell, volume) shares ([`CellShares`]).

use crate::method::Method;
use foam::Label;

/// The solid volume of a set of particles per cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Deposit {
    /// The method used.
    pub method: Method,
    /// Solid volume per cell, m³.
    pub solid: Vec<f64>,
    /// Number of particles.
    pub particles: usize,
    /// Σ 4πr³/3 over the particles, m³.
    pub particle_volume: f64,
    /// Σ `solid`, m³.
    pub deposited_volume: f64,
    /// Volume counted outside the mesh, m³ (Σ per particle of V − deposited shares).
    pub outside_volume: f64,
    /// Particles with nothing deposited (centre outside the mesh, or ball beyond it).
    pub particles_outside: usize,
    /// Particles with part of their volume (more than 1e-12·V) outside the mesh.
    pub particles_partly_outside: usize,
}

impl Deposit {
    /// |particle − deposited − outside| / particle volume (0 for no volume): the accounting
    /// residual, rounding only.
    pub fn conservation_error(&self) -> f64 {
        let d = self.particle_volume - self.deposited_volume - self.outside_volume;
        if self.particle_volume > 0.0 {
            d.abs() / self.particle_volume
        } else {
            d.abs()
        }
    }
}

/// The (cell, volume) shares of every particle, in compressed-row layout: particle i put
/// `volumes[k]` m³ into cell `cells[k]` for k in `offsets[i]..offsets[i + 1]` (a cell may
/// appear at most once per particle).
/// A particle with no entries lies outside the mesh (or has radius 0).
#[derive(Clone, Debug, PartialEq)]
pub struct CellShares {
    /// The method that produced the shares.
    pub method: Method,
    /// Start of each particle's entries; `particles + 1` values, the last is `cells.len()`.
    pub offsets: Vec<usize>,
    /// Cell of each entry.
    pub cells: Vec<Label>,
    /// Volume of each entry, m³ (> 0 except for exact zeros some methods may keep).
    pub volumes: Vec<f64>,
}

impl CellShares {
    /// Empties the lists for a deposit of `n` particles with `method`, keeping their
    /// allocations.
    pub(super) fn restart(&mut self, method: Method, n: usize) {
        self.method = method;
        self.offsets.clear();
        self.offsets.reserve(n + 1);
        self.offsets.push(0);
        self.cells.clear();
        self.volumes.clear();
    }

    /// Number of particles.
    pub fn particles(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The cells and volumes of particle `i`.
    pub fn of(&self, i: usize) -> (&[Label], &[f64]) {
        let r = self.offsets[i]..self.offsets[i + 1];
        (&self.cells[r.clone()], &self.volumes[r])
    }

    /// Σ of the volumes of particle `i` inside the mesh, m³.
    pub fn inside_volume(&self, i: usize) -> f64 {
        self.of(i).1.iter().sum()
    }

    pub(super) fn append(&mut self, shares: &[(Label, f64)], counts: &[u32]) {
        let mut end = *self.offsets.last().expect("offsets start with 0");
        for &n in counts {
            end += n as usize;
            self.offsets.push(end);
        }
        self.cells.extend(shares.iter().map(|s| s.0));
        self.volumes.extend(shares.iter().map(|s| s.1));
    }
}

impl foam::HeapBytes for CellShares {
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        flat(&self.offsets) + flat(&self.cells) + flat(&self.volumes)
    }
}
