//! Particle temperatures, as LIGGGHTS 3.8's heat transfer computes them: `fix heat/gran`
//! (conduction between touching particles, [`conduction`]) and `fix couple/cfd/convection`
//! (a per-particle heat flow the CFD side sets), both feeding LIGGGHTS's
//! `transportequation/scalar` `heattransfer` of the quantity `Temp`.
//!
//! Per particle: the temperature T (K), the heat flow of the last step Q (W, LIGGGHTS's
//! `heatFlux`) and, with the convection fix, the convective heat flow Q_c (W,
//! `convectiveHeatFlux`). One step (LIGGGHTS's order): Q is reset to zero when the step begins
//! (`initial_integrate`); after the forces the conduction with walls that have a temperature
//! ([`walls`]), between touching particles and Q_c are added (`post_force`, in the order the
//! fixes were defined); then (`final_integrate`)
//!
//!   T ← T + Q·Δt / (m c)
//!
//! explicit Euler with c the type's `thermalCapacity` (J/(kg K)); a particle whose |c| ≤ 10⁻⁸
//! keeps its temperature (LIGGGHTS's `SMALL` in `fix_scalar_transport_equation.cpp`).
//! Σ m c T (J) is the thermo value of either fix (`compute_scalar` of the transport equation,
//! summed over all particles).
//!
//! A particle inserted gets the default temperature T₀ of the fix that created the equation
//! (the first of `heat/gran` and `couple/cfd/convection`), rounded as LIGGGHTS passes it on:
//! printed `%f` into the equation's arguments, then `%e` into the `property/atom` fix
//! ([`liggghts_default`]).
//!
//! Not modelled: `heatSource` (always zero here), `directionalHeatFlux`, `store_contact_data`,
//! mesh walls with a temperature, `fix_modify … integrate stop|every`. At a run's set-up
//! LIGGGHTS's wall fixes add their wall heat to the flows once more (only what a set-up dump
//! shows; the temperatures never use it): the native set-up leaves the flows as they were.

use rayon::prelude::*;

use crate::neighbor::PairList;
use crate::particles::Particles;
use crate::walls::Wall;

pub mod conduction;
pub mod walls;

pub use conduction::{Conduction, ContactArea};
pub use walls::WallHeat;

/// |c| at or below which a particle's temperature is not integrated (J/(kg K)): LIGGGHTS's
/// `SMALL` of `fix transportequation/scalar`.
pub const SMALL_CAPACITY: f64 = 1e-8;

/// T₀ as LIGGGHTS's `property/atom` fix `Temp` holds it: `heat/gran` (or `couple/cfd/convection`)
/// prints T₀ with `%f` into the arguments of the transport equation, which prints that with
/// `%e` into the property's default (so 7 significant digits, at most 6 decimals).
pub fn liggghts_default(t0: f64) -> f64 {
    let fixed: f64 = format!("{t0:.6}").parse().unwrap_or(t0);
    format!("{fixed:.6e}").parse().unwrap_or(fixed)
}

/// The heat state of a simulation with `heat/gran` and/or `couple/cfd/convection`.
#[derive(Debug, Clone, PartialEq)]
pub struct Heat {
    /// Default temperature of new particles (K), [`liggghts_default`] of the creating fix's T₀.
    pub t0: f64,
    /// `thermalCapacity` per atom type (J/(kg K)).
    pub capacity: Vec<f64>,
    /// `heat/gran`'s conduction, if defined.
    pub conduction: Option<Conduction>,
    /// Walls with a temperature ([`walls`]): they conduct with the particles touching them.
    pub walls: Vec<WallHeat>,
    /// Whether `couple/cfd/convection` is defined (its flows are then in `convective`).
    pub convection: bool,
    /// Whether the convection fix was defined before `heat/gran` (its flow is added first).
    pub convection_first: bool,
    /// Temperature per particle (K), particle index order.
    pub temp: Vec<f64>,
    /// Heat flow of the last step per particle (W): conduction plus convection.
    pub flux: Vec<f64>,
    /// Convective heat flow per particle (W), set by the coupler; zeros without the fix.
    pub convective: Vec<f64>,
    /// Per pair of the list: the conduction flow of the last pass (buffer).
    pair_flux: Vec<f64>,
}

impl Heat {
    /// A heat state for `n` particles at the default temperature of `t0` (K, as the deck
    /// writes it) with capacities per type (J/(kg K)).
    pub fn new(t0: f64, capacity: Vec<f64>, n: usize) -> Heat {
        let t0 = liggghts_default(t0);
        Heat {
            t0,
            capacity,
            conduction: None,
            walls: Vec::new(),
            convection: false,
            convection_first: false,
            temp: vec![t0; n],
            flux: vec![0.0; n],
            convective: vec![0.0; n],
            pair_flux: Vec::new(),
        }
    }

    /// Appends `n` new particles at T₀ with no heat flow.
    pub fn grow(&mut self, n: usize) {
        let len = self.temp.len() + n;
        self.temp.resize(len, self.t0);
        self.flux.resize(len, 0.0);
        self.convective.resize(len, 0.0);
    }

    /// Keeps the particles with `keep[i]`.
    pub fn retain(&mut self, keep: &[bool]) {
        for v in [&mut self.temp, &mut self.flux, &mut self.convective] {
            let mut k = keep.iter();
            v.retain(|_| *k.next().unwrap_or(&true));
        }
    }

    /// Follows a renumbering of the particles (`perm[new] = old`).
    pub fn permute(&mut self, perm: &[u32]) {
        crate::particles::permute(&mut self.temp, perm);
        crate::particles::permute(&mut self.flux, perm);
        crate::particles::permute(&mut self.convective, perm);
    }

    /// c of particle `i` (J/(kg K)); 0 for a type without a capacity.
    fn capacity_of(&self, p: &Particles, i: usize) -> f64 {
        self.capacity
            .get(p.atom_type[i] as usize - 1)
            .copied()
            .unwrap_or(0.0)
    }

    /// m c T of particle `i` (J).
    pub fn energy_of(&self, p: &Particles, i: usize) -> f64 {
        self.capacity_of(p, i) * p.mass[i] * self.temp[i]
    }

    /// Σ c m T over the particles (J), in index order: LIGGGHTS's `compute_scalar` of the
    /// transport equation (`f_ID` of `heat/gran`).
    pub fn energy(&self, p: &Particles) -> f64 {
        (0..p.len()).map(|i| self.energy_of(p, i)).sum()
    }

    /// One step's heat (after the forces of the step): Q = conduction with the walls, between
    /// particles and convection in the fixes' order, then T ← T + QΔt/(mc). `pairs` is the list
    /// the forces were evaluated with.
    pub fn step(&mut self, pairs: &PairList, p: &Particles, walls: &[Wall], dt: f64) {
        self.flux.clear();
        self.flux.resize(p.len(), 0.0);
        if self.convection && self.convection_first {
            self.add_convection();
        }
        if let (false, Some(c)) = (self.walls.is_empty(), &self.conduction) {
            walls::add_wall_flux(
                &self.walls,
                walls,
                &c.conductivity,
                p,
                &self.temp,
                &mut self.flux,
            );
        }
        if let Some(c) = &self.conduction {
            c.pass(pairs, p, &self.temp, &mut self.pair_flux, &mut self.flux);
        }
        if self.convection && !self.convection_first {
            self.add_convection();
        }
        self.integrate(p, dt);
    }

    /// Q += Q_c (`couple/cfd/convection`'s `post_force`).
    fn add_convection(&mut self) {
        for (q, c) in self.flux.iter_mut().zip(&self.convective) {
            *q += c;
        }
    }

    /// T += Q·Δt/(m c) where |c| > [`SMALL_CAPACITY`] (LIGGGHTS's `advanceQtyExplicit`, in its
    /// operation order).
    fn integrate(&mut self, p: &Particles, dt: f64) {
        let cap = &self.capacity;
        let (flux, m, ty) = (&self.flux, &p.mass, &p.atom_type);
        self.temp
            .par_iter_mut()
            .enumerate()
            .with_min_len(crate::sim::STREAM_BLOCK)
            .for_each(|(i, t)| {
                let c = cap.get(ty[i] as usize - 1).copied().unwrap_or(0.0);
                if c.abs() > SMALL_CAPACITY {
                    *t += flux[i] * dt / (m[i] * c);
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_temperature_is_rounded_as_liggghts_prints_it() {
        // %f then %e: "600.000000" → "6.000000e+02"; "1234.567890" → "1.234568e+03"
        assert_eq!(liggghts_default(600.0), 600.0);
        assert_eq!(liggghts_default(263.0), 263.0);
        assert_eq!(liggghts_default(1234.56789), 1234.568);
        assert_eq!(liggghts_default(0.1234567891), 0.123457);
        // Debian's LIGGGHTS 3.8.0 with `initial_temperature 293.1234567` dumps (%.17g)
        // 293.12349999999998 for every sphere
        assert_eq!(
            liggghts_default(293.1234567),
            "293.12349999999998".parse::<f64>().unwrap()
        );
    }
}
