//! An open system: particles inserted during the steps (`insert/rate/region`, `insert/stream`
//! with its carrying of the new particles to the face), lost through
//! fixed box faces (policy of [`crate::outflow`]) and deleted (`delete_atoms region`). Every
//! removal goes through [`Simulation::remove`], which keeps the per-particle state (wall
//! history, pair history, coupling) with the surviving particles.

use dem_io::Boundary;
use mesh::v3::V3;

use super::Simulation;
use crate::error::DemError;
use crate::insert_rate::{InsertRate, RateInsertion};
use crate::outflow::{LostPolicy, Outflow, Removed};
use crate::region::Region;

/// "x−", "z+" … for axis `k` and face `f` (0 low, 1 high).
fn face_name(k: usize, f: usize) -> String {
    format!("{}{}", ["x", "y", "z"][k], ["−", "+"][f])
}

impl Simulation {
    /// Adds an `insert/rate/region` or `insert/stream` fix defined now (its first insertion is at its `start`, else
    /// at the next step).
    pub fn add_rate_insertion(&mut self, spec: InsertRate) -> Result<(), DemError> {
        if self.rate_inserts.iter().any(|r| r.spec().name == spec.name) {
            return Err(DemError::Setup(format!(
                "insertion fix `{}` is defined twice",
                spec.name
            )));
        }
        let ins = RateInsertion::new(spec, self.step).map_err(DemError::Setup)?;
        self.rate_inserts.push(ins);
        Ok(())
    }

    /// The continuous insertions, with what each inserted so far.
    pub fn rate_insertions(&self) -> &[RateInsertion] {
        &self.rate_inserts
    }

    /// Removes the insertion fix `name` (pending `insert/pack` or `insert/rate/region`);
    /// returns whether it existed.
    pub fn remove_insertion(&mut self, name: &str) -> bool {
        let n = self.rate_inserts.len() + self.pending_inserts.len();
        self.rate_inserts.retain(|r| r.spec().name != name);
        self.pending_inserts.retain(|r| r.name != name);
        n != self.rate_inserts.len() + self.pending_inserts.len()
    }

    /// `thermo_modify lost …`.
    pub fn set_lost_policy(&mut self, policy: LostPolicy) {
        self.lost_policy = policy;
    }

    /// What left the simulation so far.
    pub fn outflow(&self) -> &Outflow {
        &self.outflow
    }

    /// `delete_atoms region R`: removes the particles whose centres lie in `region`
    /// (boundary included, as LIGGGHTS's `region->match`); returns how many.
    pub fn delete_in_region(&mut self, region: &Region) -> u64 {
        let keep: Vec<bool> = self
            .particles
            .x
            .iter()
            .map(|&x| !region.contains(x))
            .collect();
        let mut removed = Removed::default();
        self.remove(&keep, &mut removed);
        self.outflow.deleted.count += removed.count;
        self.outflow.deleted.mass += removed.mass;
        self.outflow.deleted.volume += removed.volume;
        self.outflow.deleted.momentum += removed.momentum;
        self.outflow.deleted.heat += removed.heat;
        self.invalidate_forces();
        removed.count
    }

    /// Renumbers the particles 1…N in the order of their ids (`delete_atoms … compress yes`).
    pub fn compress_ids(&mut self) {
        let mut order: Vec<usize> = (0..self.particles.len()).collect();
        order.sort_unstable_by_key(|&i| self.particles.id[i]);
        for (n, &i) in order.iter().enumerate() {
            self.particles.id[i] = n as u64 + 1;
        }
        self.invalidate_forces();
    }

    /// Fixes each rate insertion's particles per insertion with the current time step and
    /// checks its region against the box (at the start of every run; only the first acts).
    pub(super) fn activate_rate_insertions(&mut self) -> Result<(), DemError> {
        let b = self.sim_box;
        let fixed = b.boundary.iter().flatten().any(|&f| f == Boundary::Fixed);
        let mut warnings = Vec::new();
        for r in &mut self.rate_inserts {
            warnings.extend(
                r.activate(self.dt, fixed, b.lo, b.hi)
                    .map_err(DemError::Setup)?,
            );
        }
        for w in warnings {
            self.warn(w);
        }
        Ok(())
    }

    /// The rate insertions due at the current step.
    pub(super) fn insert_due(&mut self) -> Result<(), DemError> {
        let step = self.step;
        if !self
            .rate_inserts
            .iter()
            .any(|r| r.next_step() == Some(step))
        {
            return Ok(());
        }
        // new particles are appended in insertion order
        self.restore_order();
        let mut inserts = std::mem::take(&mut self.rate_inserts);
        let mut result = Ok(());
        for r in &mut inserts {
            let Some(batch) = r.due(step, &self.particles) else {
                continue;
            };
            if batch.particles.len() < batch.wanted && r.stats().short == 1 {
                self.warn(format!(
                    "{} {}: inserted {} of {} particles at step {step} (no free place found; \
                     later shortfalls are counted, not reported)",
                    r.spec().style(),
                    r.spec().name,
                    batch.particles.len(),
                    batch.wanted
                ));
            }
            let first = self.particles.len();
            result = self.add_particles(&batch.particles);
            if result.is_err() {
                break;
            }
            for (k, h) in batch.held.into_iter().enumerate() {
                self.held.insert(self.particles.id[first + k], h);
            }
        }
        self.rate_inserts = inserts;
        result
    }

    /// Removes the particles outside a fixed face, as `thermo_modify lost` says.
    pub(super) fn remove_lost(&mut self) -> Result<(), DemError> {
        let b = self.sim_box;
        let out_face = |x: V3| b.exit_face(x).map(|(k, f)| face_name(k, f));
        if !self.particles.x.iter().any(|&x| out_face(x).is_some()) {
            return Ok(());
        }
        // the first one in insertion order is reported, and removals renumber by that order
        self.restore_order();
        let Some(first) = self.particles.x.iter().position(|&x| out_face(x).is_some()) else {
            return Ok(());
        };
        let p = &self.particles;
        let what = format!(
            "left the box through its fixed face {} at step {} (x = [{}, {}, {}] m)",
            out_face(p.x[first]).unwrap_or_default(),
            self.step,
            p.x[first][0],
            p.x[first][1],
            p.x[first][2]
        );
        match self.lost_policy {
            LostPolicy::Error => {
                return Err(DemError::Particle {
                    id: p.id[first],
                    message: format!(
                        "{what}: lost atoms (LIGGGHTS stops too; `thermo_modify lost ignore` \
                         removes such particles)"
                    ),
                })
            }
            LostPolicy::Warn if self.outflow.lost.count == 0 => {
                let w = format!("particle {} {what}: lost atoms are removed", p.id[first]);
                self.warn(w);
            }
            _ => {}
        }
        let p = &self.particles;
        let keep: Vec<bool> = p.x.iter().map(|&x| out_face(x).is_none()).collect();
        let mut lost = self.outflow.lost;
        self.remove(&keep, &mut lost);
        self.outflow.lost = lost;
        Ok(())
    }

    /// Keeps the particles with `keep[i]`, with their wall and pair histories and coupling;
    /// the removed ones are added to `tally`.
    fn remove(&mut self, keep: &[bool], tally: &mut Removed) {
        if keep.iter().all(|&k| k) {
            return;
        }
        debug_assert!(self.home.is_empty(), "removal while renumbered");
        let p = &self.particles;
        for (i, _) in keep.iter().enumerate().filter(|(_, &k)| !k) {
            tally.add(p.mass[i], p.radius[i], p.v[i]);
            if let Some(h) = &self.heat {
                tally.heat += h.energy_of(p, i);
            }
        }
        if let Some(h) = &mut self.heat {
            h.retain(keep);
        }
        let nw = self.walls.len();
        let mut it = (0..p.len()).flat_map(|i| std::iter::repeat_n(keep[i], nw));
        self.wall_hist.retain(|_| it.next().unwrap_or(true));
        self.wall_maybe.clear();
        if !self.mesh_contacts.is_empty() {
            let mut k = keep.iter();
            self.mesh_contacts.retain(|_| *k.next().unwrap_or(&true));
        }
        if !self.held.is_empty() {
            for (i, _) in keep.iter().enumerate().filter(|(_, &k)| !k) {
                self.held.remove(&self.particles.id[i]);
            }
        }
        let map = self.particles.retain(keep);
        self.pairs.remap(&map);
        self.coupling.remap(&map);
        if let Some(c) = &mut self.forces_coupling {
            c.remap(&map);
        }
    }

    /// `insert/stream`'s carrying at the end of a step: a held particle is put where v_n has
    /// taken it since its insertion, with velocity v_n, no spin, no force or torque; at its
    /// release step it gets the fix's `vel` and `omega` and is free from then on
    /// ([`crate::insert_stream`]).
    pub(super) fn carry_held(&mut self) {
        if self.held.is_empty() {
            return;
        }
        let (step, dt) = (self.step, self.dt);
        let p = &mut self.particles;
        for i in 0..p.len() {
            let Some(h) = self.held.get(&p.id[i]) else {
                continue;
            };
            p.x[i] = h.position(step, dt);
            p.f[i] = V3::zeros();
            p.torque[i] = V3::zeros();
            if step >= h.release {
                p.v[i] = h.v_release;
                p.omega[i] = h.omega_release;
                self.held.remove(&p.id[i]);
            } else {
                p.v[i] = h.v_carry;
                p.omega[i] = V3::zeros();
            }
        }
    }

    /// How many `insert/stream` particles are still carried to their face.
    pub fn held_count(&self) -> usize {
        self.held.len()
    }
}
