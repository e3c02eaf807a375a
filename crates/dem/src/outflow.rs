//! Particles leaving the simulation: through a fixed (`f`) box face ("lost atoms") or deleted
//! by `delete_atoms region`, and what is counted of them.
//!
//! LIGGGHTS 3.8.0 drops an atom that has crossed a fixed face when it next re-neighbours and
//! then, at the next thermo output, compares the atom count with the one it expects:
//! `thermo_modify lost error` (the default) stops the run with "Lost atoms: original N current
//! M", `lost warn` warns once and goes on, `lost ignore` goes on silently; the thermo `atoms`
//! column is the count after the removal. The native DEM removes a particle at the step its
//! centre crosses the face and, with `lost error`, stops there with an error naming the step
//! and the particle's id (LIGGGHTS stops at the next thermo row: the run fails either way).
//! Shrink-wrapped faces (`s`, `m`) follow the particles and never lose any.

use mesh::v3::V3;

/// `thermo_modify lost error|warn|ignore`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum LostPolicy {
    /// Stop the run (LIGGGHTS's default).
    #[default]
    Error,
    /// Warn once, then go on removing.
    Warn,
    /// Remove silently.
    Ignore,
}

impl LostPolicy {
    /// The policy named by `thermo_modify lost WORD`.
    pub fn from_word(w: &str) -> Option<LostPolicy> {
        match w {
            "error" => Some(LostPolicy::Error),
            "warn" => Some(LostPolicy::Warn),
            "ignore" => Some(LostPolicy::Ignore),
            _ => None,
        }
    }
}

/// What left the simulation so far, one tally per cause.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Removed {
    /// Particles.
    pub count: u64,
    /// Their mass (kg).
    pub mass: f64,
    /// Their volume (m³).
    pub volume: f64,
    /// Their momentum Σ m v when removed (kg·m/s).
    pub momentum: V3,
    /// Their thermal energy Σ m c T when removed (J; [`crate::heat`]), 0 without heat.
    pub heat: f64,
}

impl Removed {
    /// Adds one particle of mass `m` (kg), radius `r` (m) and velocity `v` (m/s).
    pub fn add(&mut self, m: f64, r: f64, v: V3) {
        self.count += 1;
        self.mass += m;
        self.volume += 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        self.momentum += m * v;
    }
}

/// The outflow tallies of a simulation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Outflow {
    /// Lost through fixed box faces.
    pub lost: Removed,
    /// Removed by `delete_atoms`.
    pub deleted: Removed,
}
