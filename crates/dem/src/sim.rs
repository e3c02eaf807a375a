//! The simulation: particle state, contact model, walls, neighbour list, coupling forces, and
//! the velocity-Verlet step of `fix nve/sphere`.
//!
//! One step (LIGGGHTS's order): half kick v += (dt/2) F/m, ω += (dt/2) T/I (I = 0.4mR²);
//! drift x += dt·v; particles outside a fixed (`f`) box face are removed; the neighbour list is
//! rebuilt if needed; forces are evaluated (gravity mg, coupling, pair and wall contacts, the
//! contact history advanced); second half kick; due dumps are written. With constant force this
//! integrates exactly (x = x₀ + v₀t + ½at²).
//!
//! The pair forces ([`crate::pair_loop`]) are evaluated over the half pair list in the
//! particles' spatial order and summed per particle in a fixed order (by the partner's place in
//! the spatial order of the last list build), so results are bit-identical from run to run and
//! for any number of rayon threads. Walls,
//! gravity, coupling and the kicks are per particle, in index order.

use dem_io::{Boundary, BoxBounds};
use mesh::v3::V3;
use rayon::prelude::*;

use crate::contact::{ContactModel, History, HistoryUse};
use crate::coupling::Coupling;
use crate::dump::DumpOutput;
use crate::error::DemError;
use crate::heat::Heat;
use crate::insert::InsertPack;
use crate::insert_rate::RateInsertion;
use crate::material::Materials;
use crate::mesh_wall::{self, MeshContact, MeshWall};
use crate::neighbor::PairList;
use crate::outflow::{LostPolicy, Outflow};
use crate::pair_loop::PairForces;
use crate::particles::{NewParticle, Particles, INERTIA_FACTOR};
use crate::periodic::Periodic;
use crate::walls::{wall_contact, SphereState, Wall};

mod heat;
mod open;

/// The simulation box of `create_box` with its `boundary` settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimBox {
    /// Lower corner (m).
    pub lo: V3,
    /// Upper corner (m).
    pub hi: V3,
    /// Boundary per axis and face (`p`: [`crate::periodic`]).
    pub boundary: [[Boundary; 2]; 3],
}

impl SimBox {
    /// A box with fixed (`f f f`) boundaries.
    pub fn fixed(lo: V3, hi: V3) -> SimBox {
        SimBox {
            lo,
            hi,
            boundary: [[Boundary::Fixed; 2]; 3],
        }
    }

    /// The fixed face a particle at `x` has left through, as (axis, 0 low | 1 high).
    pub fn exit_face(&self, x: V3) -> Option<(usize, usize)> {
        (0..3).find_map(|k| {
            if self.boundary[k][0] == Boundary::Fixed && x[k] < self.lo[k] {
                Some((k, 0))
            } else if self.boundary[k][1] == Boundary::Fixed && x[k] > self.hi[k] {
                Some((k, 1))
            } else {
                None
            }
        })
    }

    /// Bounds as a dump states them: shrink-wrapped faces (`s`, `m`) follow the particles
    /// (`m` never inside its initial value).
    pub fn dump_bounds(&self, x: &[V3]) -> BoxBounds {
        let mut lo = self.lo;
        let mut hi = self.hi;
        for k in 0..3 {
            let (mn, mx) = x
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p[k]), b.max(p[k]))
                });
            if x.is_empty() {
                continue;
            }
            match self.boundary[k][0] {
                Boundary::Shrink => lo[k] = mn,
                Boundary::ShrinkMin => lo[k] = lo[k].min(mn),
                _ => {}
            }
            match self.boundary[k][1] {
                Boundary::Shrink => hi[k] = mx,
                Boundary::ShrinkMin => hi[k] = hi[k].max(mx),
                _ => {}
            }
        }
        BoxBounds {
            lo: lo.into(),
            hi: hi.into(),
            tilt: None,
            boundary: self.boundary,
        }
    }
}

/// Everything fixed at construction.
#[derive(Debug, Clone)]
pub struct SimConfig {
    /// Materials per type.
    pub materials: Materials,
    /// The particle–particle contact model (`pair_style gran …`).
    pub pair_model: ContactModel,
    /// Time step (s).
    pub dt: f64,
    /// Gravitational acceleration (m/s²).
    pub gravity: V3,
    /// Neighbour skin (m).
    pub skin: f64,
    /// Simulation box.
    pub sim_box: SimBox,
}

/// What a continued run needs beyond positions, end-of-step velocities and contact history
/// to carry on exactly as the uninterrupted run: the velocities half a step earlier, with
/// which the last forces were evaluated (velocity Verlet evaluates them between its two half
/// kicks), and those forces. Particle-index vectors of equal length.
#[derive(Debug, Clone, PartialEq)]
pub struct HalfStep {
    /// Velocities half a step before the current one, v − (dt/2)F/m (m/s).
    pub v: Vec<V3>,
    /// Angular velocities half a step before, ω − (dt/2)T/I (rad/s).
    pub omega: Vec<V3>,
    /// The forces of the current step (N).
    pub force: Vec<V3>,
    /// The torques of the current step (N·m).
    pub torque: Vec<V3>,
    /// The part of `force` the CFD coupling contributed, F_ext + β(u_f − v) with the coupling
    /// the forces were evaluated with (N); empty when unknown (files without it). The coupler
    /// sets the next interval's coupling before the state is written, so the set-up must
    /// take the recorded coupling force apart from the forces it evaluates again.
    pub coupling: Vec<V3>,
}

/// Largest difference, relative to the largest force (torque), between forces evaluated again
/// at the half-step velocities and the recorded ones for which the set-up is taken to be the
/// one that recorded them (the recorded forces are then used as they are).
const SAME_FORCES: f64 = 1e-9;

/// Particles per parallel block of the passes with a few flops per particle.
pub(crate) const STREAM_BLOCK: usize = 4096;

/// x_i − x_j, to the nearest image of x_j in a periodic box (m).
fn separation(periodic: Option<&Periodic>, xi: V3, xj: V3) -> V3 {
    match periodic {
        None => xi - xj,
        Some(per) => per.delta(xi, xj),
    }
}

/// A running DEM simulation.
#[derive(Debug)]
pub struct Simulation {
    /// The particles.
    pub particles: Particles,
    materials: Materials,
    pair_model: ContactModel,
    walls: Vec<Wall>,
    wall_hist: Vec<History>,
    /// Per particle: whether one of its wall histories may be non-zero (false only where the
    /// last force evaluation found them all zero; emptied by every other change of
    /// `wall_hist`, which makes it all true again).
    wall_maybe: Vec<bool>,
    /// Mesh walls ([`crate::mesh_wall`]) and, per particle, its contacts with them.
    mesh_walls: Vec<MeshWall>,
    mesh_contacts: Vec<Vec<MeshContact>>,
    dt: f64,
    gravity: V3,
    step: u64,
    sim_box: SimBox,
    pairs: PairList,
    /// The pair loop's buffers.
    pair_forces: PairForces,
    /// While a run stores the particles in the list's spatial order ([`Simulation::run`]):
    /// `home[i]` is the index particle i has outside the run (insertion order); empty while
    /// they are in that order.
    home: Vec<u32>,
    coupling: Coupling,
    /// The coupling the current forces were evaluated with, when it was replaced since
    /// ([`Simulation::set_coupling`] between two steps); `None`: the current one.
    forces_coupling: Option<Coupling>,
    forces_valid: bool,
    /// The state the next set-up evaluates the forces from ([`Simulation::set_half_step`]).
    replay: Option<HalfStep>,
    pending_inserts: Vec<InsertPack>,
    /// Continuous insertions (`insert/rate/region`), performed in [`Simulation::advance`].
    rate_inserts: Vec<RateInsertion>,
    /// `insert/stream` particles still carried to their face, by id ([`crate::insert_stream`]).
    held: std::collections::HashMap<u64, crate::insert_stream::Held>,
    dumps: Vec<DumpOutput>,
    /// What left through fixed faces or was deleted ([`crate::outflow`]).
    outflow: Outflow,
    lost_policy: LostPolicy,
    warnings: Vec<String>,
    /// Particle temperatures (`heat/gran`, `couple/cfd/convection`; [`crate::heat`]).
    heat: Option<Heat>,
}

impl Simulation {
    /// An empty simulation. Errors: dt ≤ 0, negative skin, non-finite gravity.
    pub fn new(cfg: SimConfig) -> Result<Simulation, DemError> {
        if !(cfg.dt > 0.0 && cfg.dt.is_finite()) {
            return Err(DemError::Setup(format!("time step {} must be > 0", cfg.dt)));
        }
        if !(cfg.skin >= 0.0 && cfg.skin.is_finite()) {
            return Err(DemError::Setup(format!(
                "neighbour skin {} must be ≥ 0",
                cfg.skin
            )));
        }
        if !cfg.gravity.iter().all(|g| g.is_finite()) {
            return Err(DemError::Setup(format!(
                "gravity {:?} is not finite",
                cfg.gravity
            )));
        }
        let periodic = Periodic::new(cfg.sim_box.lo, cfg.sim_box.hi, &cfg.sim_box.boundary)
            .map_err(|e| DemError::Setup(format!("boundary: {e}")))?;
        let mut pairs = PairList::new(cfg.skin);
        pairs.set_periodic(periodic);
        Ok(Simulation {
            particles: Particles::default(),
            materials: cfg.materials,
            pair_model: cfg.pair_model,
            walls: Vec::new(),
            wall_hist: Vec::new(),
            wall_maybe: Vec::new(),
            mesh_walls: Vec::new(),
            mesh_contacts: Vec::new(),
            dt: cfg.dt,
            gravity: cfg.gravity,
            step: 0,
            sim_box: cfg.sim_box,
            pairs,
            pair_forces: PairForces::default(),
            home: Vec::new(),
            coupling: Coupling::default(),
            forces_coupling: None,
            forces_valid: false,
            replay: None,
            pending_inserts: Vec::new(),
            rate_inserts: Vec::new(),
            held: Default::default(),
            dumps: Vec::new(),
            outflow: Outflow::default(),
            lost_policy: LostPolicy::default(),
            warnings: Vec::new(),
            heat: None,
        })
    }

    /// Current step number.
    pub fn step(&self) -> u64 {
        self.step
    }

    /// Simulated time since step 0 (s), step × dt.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }

    /// Time step (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Changes the time step (`timestep` between runs).
    pub fn set_dt(&mut self, dt: f64) -> Result<(), DemError> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(DemError::Setup(format!("time step {dt} must be > 0")));
        }
        self.dt = dt;
        Ok(())
    }

    /// Changes gravity (m/s²).
    pub fn set_gravity(&mut self, g: V3) {
        self.gravity = g;
        self.forces_valid = false;
    }

    /// The materials.
    pub fn materials(&self) -> &Materials {
        &self.materials
    }

    /// The box.
    pub fn sim_box(&self) -> &SimBox {
        &self.sim_box
    }

    /// Walls.
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// Particles removed so far because they left the box through a fixed face.
    pub fn lost(&self) -> u64 {
        self.outflow.lost.count
    }

    /// Warnings collected (incomplete insertions, time-step checks).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    pub(crate) fn warn(&mut self, w: String) {
        self.warnings.push(w);
    }

    /// Adds a wall; its material type must exist.
    pub fn add_wall(&mut self, wall: Wall) -> Result<(), DemError> {
        if wall.material_type == 0 || wall.material_type as usize > self.materials.ntypes() {
            return Err(DemError::Setup(format!(
                "wall {}: material type {} outside 1..={}",
                wall.name,
                wall.material_type,
                self.materials.ntypes()
            )));
        }
        let nw = self.walls.len();
        let mut h = Vec::with_capacity(self.particles.len() * (nw + 1));
        for i in 0..self.particles.len() {
            h.extend_from_slice(&self.wall_hist[i * nw..(i + 1) * nw]);
            h.push(History::default());
        }
        self.wall_hist = h;
        self.wall_maybe.clear();
        self.walls.push(wall);
        self.forces_valid = false;
        Ok(())
    }

    /// Adds a mesh wall; the material types of its surfaces must exist.
    pub fn add_mesh_wall(&mut self, mut wall: MeshWall) -> Result<(), DemError> {
        for s in &wall.surfaces {
            if s.material_type == 0 || s.material_type as usize > self.materials.ntypes() {
                return Err(DemError::Setup(format!(
                    "mesh/surface {} of wall {}: material type {} outside 1..={}",
                    s.mesh.name(),
                    wall.name,
                    s.material_type,
                    self.materials.ntypes()
                )));
            }
        }
        if self.mesh_walls.len() >= u16::MAX as usize {
            return Err(DemError::Setup("too many mesh walls".into()));
        }
        wall.prepare(self.particles.radius.iter().copied().fold(0.0, f64::max));
        self.mesh_walls.push(wall);
        self.mesh_contacts.resize(self.particles.len(), Vec::new());
        self.forces_valid = false;
        Ok(())
    }

    /// Mesh walls.
    pub fn mesh_walls(&self) -> &[MeshWall] {
        &self.mesh_walls
    }

    /// Per particle, its contacts with the mesh walls (empty without mesh walls).
    pub fn mesh_contacts(&self) -> &[Vec<MeshContact>] {
        &self.mesh_contacts
    }

    /// The force of the particles on the surface named `surface` (a `fix mesh/surface` id),
    /// summed over the mesh walls that use it (N); `None` when no mesh wall uses it.
    pub fn mesh_surface_force(&self, surface: &str) -> Option<V3> {
        let mut found = None;
        for (w, wall) in self.mesh_walls.iter().enumerate() {
            for (k, s) in wall.surfaces.iter().enumerate() {
                if s.mesh.name() == surface {
                    let f = mesh_wall::mesh_force(&self.mesh_contacts, w, k);
                    found = Some(found.unwrap_or(V3::zeros()) + f);
                }
            }
        }
        found
    }

    /// Makes the mesh walls' grids find the contacts of the largest particle.
    fn prepare_mesh_walls(&mut self) {
        if self.mesh_walls.is_empty() {
            return;
        }
        let rmax = self.particles.radius.iter().copied().fold(0.0, f64::max);
        for w in &mut self.mesh_walls {
            w.prepare(rmax);
        }
        self.mesh_contacts.resize(self.particles.len(), Vec::new());
    }

    /// Adds particles (ids 0 are assigned the next free ids; duplicate ids are refused).
    pub fn add_particles(&mut self, new: &[NewParticle]) -> Result<(), DemError> {
        let mut ids: std::collections::HashSet<u64> = self.particles.id.iter().copied().collect();
        let before = self.particles.len();
        // the largest id so far, kept here (Particles::max_id is a pass over all particles)
        let mut max_id = self.particles.max_id();
        for p in new {
            if p.id != 0 && !ids.insert(p.id) {
                return Err(DemError::Particle {
                    id: p.id,
                    message: "id already in use".into(),
                });
            }
            let id = if p.id == 0 { max_id + 1 } else { p.id };
            if let Err(e) = self
                .particles
                .push(NewParticle { id, ..*p }, self.materials.ntypes())
            {
                self.particles.retain(
                    &(0..self.particles.len())
                        .map(|i| i < before)
                        .collect::<Vec<_>>(),
                );
                return Err(e);
            }
            ids.insert(id);
            max_id = max_id.max(id);
        }
        let added = self.particles.len() - before;
        self.wall_hist
            .resize(self.particles.len() * self.walls.len(), History::default());
        self.wall_maybe.clear();
        self.prepare_mesh_walls();
        self.coupling.grow(added);
        if let Some(h) = &mut self.heat {
            h.grow(added);
        }
        self.pairs.invalidate();
        self.forces_valid = false;
        Ok(())
    }

    /// Queues an insertion performed at the start of the next run.
    pub fn add_insertion(&mut self, ins: InsertPack) {
        self.pending_inserts.push(ins);
    }

    /// Adds a periodic dump.
    pub fn add_dump(&mut self, d: DumpOutput) {
        self.dumps.push(d);
    }

    /// The dump with id `name`.
    pub fn dump_mut(&mut self, name: &str) -> Option<&mut DumpOutput> {
        self.dumps.iter_mut().find(|d| d.name == name)
    }

    /// Removes the dump with id `name` (`undump`); returns whether it existed.
    pub fn remove_dump(&mut self, name: &str) -> bool {
        let n = self.dumps.len();
        self.dumps.retain(|d| d.name != name);
        n != self.dumps.len()
    }

    /// Sets the coupling forces, in particle index order (see [`Coupling::set`]). They act from
    /// the next force evaluation on; the current forces keep the coupling they were evaluated
    /// with (recorded for [`Simulation::half_step`]).
    pub fn set_coupling(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), DemError> {
        if self.forces_valid && self.forces_coupling.is_none() {
            self.forces_coupling = Some(self.coupling.clone());
        }
        self.coupling.set(
            f_ext,
            beta,
            u_f,
            &self.particles.id,
            &self.particles.mass,
            self.dt,
        )
    }

    /// The coupling forces (empty without coupling).
    pub fn coupling(&self) -> &Coupling {
        &self.coupling
    }

    /// Σ over the particles of the coupling force of the last step, F_ext + β(u_f − v) with v
    /// the half-step velocity it was evaluated at (N): LIGGGHTS's global vector of `fix
    /// couple/cfd/force[/implicit]` (`f_ID[1..3]`). Zero without coupling.
    pub fn coupling_force_total(&self) -> V3 {
        let coupling = self.forces_coupling();
        if !coupling.is_active() {
            return V3::zeros();
        }
        let p = &self.particles;
        let half = if self.forces_valid {
            0.5 * self.dt
        } else {
            0.0
        };
        (0..p.len()).fold(V3::zeros(), |sum, i| {
            let v = p.v[i] - (half / p.mass[i]) * p.f[i];
            sum + coupling.force(i, v)
        })
    }

    /// The coupling the current forces were evaluated with.
    fn forces_coupling(&self) -> &Coupling {
        self.forces_coupling.as_ref().unwrap_or(&self.coupling)
    }

    /// Removes the coupling forces (from the next force evaluation on).
    pub fn clear_coupling(&mut self) {
        if self.forces_valid && self.forces_coupling.is_none() {
            self.forces_coupling = Some(std::mem::take(&mut self.coupling));
        }
        self.coupling = Coupling::default();
    }

    /// The neighbour skin (m): `neighbor SKIN`, with `coarsegraining CG` CG × SKIN.
    pub fn skin(&self) -> f64 {
        self.pairs.skin
    }

    /// Marks the stored forces stale (after editing positions or velocities directly).
    pub fn invalidate_forces(&mut self) {
        self.forces_valid = false;
        self.replay = None;
        self.pairs.invalidate();
        self.prepare_mesh_walls();
    }

    /// Sets the step counter (a run continued from a restart file starts at the file's step).
    pub fn set_step(&mut self, step: u64) {
        self.step = step;
    }

    /// The particle–particle contact model.
    pub fn pair_model(&self) -> &ContactModel {
        &self.pair_model
    }

    /// The pairs of particles in contact now (centre distance below the sum of the radii),
    /// as particle indices `i < j` with their history as seen from `i`, ordered by `i` then
    /// `j`. This is the history the next step continues from.
    pub fn pair_contacts(&self) -> Vec<(usize, usize, History)> {
        let (x, r) = (&self.particles.x, &self.particles.radius);
        let n = x.len();
        let pl = &self.pairs;
        let mut v: Vec<(usize, usize, History)> = (0..pl.len())
            .filter_map(|k| {
                let (i, j) = pl.pair(k);
                if i >= n || j >= n {
                    return None;
                }
                let d = separation(pl.periodic(), x[i], x[j]);
                let radsum = r[i] + r[j];
                (d.dot(&d) < radsum * radsum).then_some((i, j, pl.history(k)))
            })
            .collect();
        v.sort_unstable_by_key(|c| (c.0, c.1));
        v
    }

    /// Sets the history of the pairs in contact, as `(i, j, history seen from i)` with
    /// particle indices (either order). Builds the pair list at the current positions first;
    /// pairs not in contact now are skipped (their history would be reset at the next step,
    /// as LIGGGHTS does) and their number is returned.
    pub fn set_pair_contacts(&mut self, contacts: &[(usize, usize, History)]) -> usize {
        let p = &self.particles;
        self.pairs.build(&p.x, &p.radius);
        let n = p.len();
        let mut index: Vec<((usize, usize), usize)> = (0..self.pairs.len())
            .map(|k| (self.pairs.pair(k), k))
            .collect();
        index.sort_unstable();
        let mut skipped = 0;
        for &(a, b, h) in contacts {
            let (i, j, h) = if a < b {
                (a, b, h)
            } else {
                (
                    b,
                    a,
                    History {
                        shear: -h.shear,
                        roll: -h.roll,
                    },
                )
            };
            let in_contact = i != j && j < n && {
                let d = separation(self.pairs.periodic(), p.x[i], p.x[j]);
                let radsum = p.radius[i] + p.radius[j];
                d.dot(&d) < radsum * radsum
            };
            match index.binary_search_by_key(&(i, j), |e| e.0) {
                Ok(at) if in_contact => self.pairs.set_history(index[at].1, h),
                _ => skipped += 1,
            }
        }
        self.forces_valid = false;
        skipped
    }

    /// The contact history of every particle with every wall: `walls().len()` entries per
    /// particle, particle by particle (zero when not in contact).
    pub fn wall_history(&self) -> &[History] {
        &self.wall_hist
    }

    /// Sets the contact history of particle `i` with wall `w`.
    pub fn set_wall_history(&mut self, i: usize, w: usize, h: History) {
        let nw = self.walls.len();
        self.wall_hist[i * nw + w] = h;
        self.wall_maybe.clear();
        self.forces_valid = false;
    }

    /// Runs `n` steps (performing queued insertions and the set-up force evaluation first).
    ///
    /// Within the run the particles are stored in the neighbour list's spatial order from its
    /// first rebuild on (each rebuild renumbers them with all their per-particle state), so the
    /// passes over particles and pairs read memory in order; before anything sees indices
    /// (insertions, removals, dumps, the end of the run) they are put back in insertion order.
    /// Pairs are oriented by that order and summed in the list's spatial order, which the
    /// renumbering does not change, so the results are those of a run without the renumbering,
    /// bit for bit.
    pub fn run(&mut self, n: u64) -> Result<(), DemError> {
        let mut result = self.setup();
        if result.is_ok() {
            for _ in 0..n {
                result = self.advance();
                if result.is_err() {
                    break;
                }
            }
        }
        self.restore_order();
        result
    }

    /// Stores the particles in the order of the list just built (`pairs.order()`), with their
    /// per-particle state, and records their insertion-order indices in `home`.
    fn adopt_spatial_order(&mut self) {
        if self.pairs.is_identity() {
            return;
        }
        let perm = self.pairs.order().to_vec();
        self.home = match self.home.is_empty() {
            true => perm.clone(),
            false => perm.iter().map(|&o| self.home[o as usize]).collect(),
        };
        self.permute_all(&perm);
    }

    /// Puts the particles back in insertion order (undoes [`Simulation::adopt_spatial_order`]).
    pub(crate) fn restore_order(&mut self) {
        if self.home.is_empty() {
            return;
        }
        let mut perm = vec![0u32; self.home.len()];
        for (now, &home) in self.home.iter().enumerate() {
            perm[home as usize] = now as u32;
        }
        self.home.clear();
        self.permute_all(&perm);
    }

    /// Renumbers the particles and everything kept per particle (`perm[new] = old`).
    fn permute_all(&mut self, perm: &[u32]) {
        self.particles.permute(perm);
        let nw = self.walls.len();
        if nw > 0 && self.wall_hist.len() == perm.len() * nw {
            let old = std::mem::take(&mut self.wall_hist);
            self.wall_hist = perm
                .iter()
                .flat_map(|&o| &old[o as usize * nw..(o as usize + 1) * nw])
                .copied()
                .collect();
        }
        if self.wall_maybe.len() == perm.len() {
            crate::particles::permute(&mut self.wall_maybe, perm);
        }
        if self.mesh_contacts.len() == perm.len() {
            let mut old = std::mem::take(&mut self.mesh_contacts);
            self.mesh_contacts = perm
                .iter()
                .map(|&o| std::mem::take(&mut old[o as usize]))
                .collect();
        }
        self.coupling.permute(perm);
        if let Some(h) = &mut self.heat {
            h.permute(perm);
        }
        // the coupling the current forces were evaluated with is kept until the next force
        // evaluation; particles inserted since have no entry in it (nor current forces), and a
        // renumbering with them is always followed by that evaluation
        match &mut self.forces_coupling {
            Some(c) if c.f_ext.len() == perm.len() => c.permute(perm),
            Some(_) => self.forces_coupling = None,
            None => {}
        }
        self.pairs.renumber(perm);
    }

    /// Insertions, a force evaluation if forces are stale, due dumps.
    fn setup(&mut self) -> Result<(), DemError> {
        self.activate_rate_insertions()?;
        for ins in std::mem::take(&mut self.pending_inserts) {
            let got = ins.insert(&self.particles);
            if got.particles.len() < got.wanted {
                self.warn(format!(
                    "insert/pack {}: inserted {} of {} particles (no free place found)",
                    ins.name,
                    got.particles.len(),
                    got.wanted
                ));
            }
            self.add_particles(&got.particles)?;
        }
        self.prepare_mesh_walls();
        if let Some(per) = self.pairs.periodic().copied() {
            let rmax = self.particles.radius.iter().copied().fold(0.0, f64::max);
            per.check_cutoff(2.0 * rmax + self.pairs.skin)
                .map_err(DemError::Setup)?;
            // a set-up wraps, as LIGGGHTS's does (the list then rebuilds: the wrapped particles
            // moved by a box length); a chunk boundary of a run, with valid forces, does not
            if !self.forces_valid {
                self.wrap_periodic(&per);
            }
        }
        if !self.forces_valid {
            self.pairs.ensure(&self.particles.x, &self.particles.radius);
            match self.replay.take() {
                Some(h) => self.replay_forces(&h),
                None => self.compute_forces(HistoryUse::Setup, None),
            }
        }
        self.write_dumps()
    }

    /// The half-step velocities and the forces of the current step ([`HalfStep`]); `None`
    /// while the forces are not those of the last step (before the first run, or after the
    /// state was edited). Between `read_restart` and the first run, the state read.
    pub fn half_step(&self) -> Option<HalfStep> {
        if !self.forces_valid {
            return self.replay.clone();
        }
        let p = &self.particles;
        let half = 0.5 * self.dt;
        let mut v = Vec::with_capacity(p.len());
        let mut w = Vec::with_capacity(p.len());
        for i in 0..p.len() {
            let a = half / p.mass[i];
            let ai = half / (INERTIA_FACTOR * p.mass[i] * p.radius[i] * p.radius[i]);
            v.push(p.v[i] - a * p.f[i]);
            w.push(p.omega[i] - ai * p.torque[i]);
        }
        let c = self.forces_coupling();
        let coupling = match c.is_active() {
            true => (0..p.len()).map(|i| c.force(i, v[i])).collect(),
            false => Vec::new(),
        };
        Some(HalfStep {
            v,
            omega: w,
            force: p.f.clone(),
            torque: p.torque.clone(),
            coupling,
        })
    }

    /// Hands the next run's set-up the [`HalfStep`] state of the first `h.v.len()` particles
    /// (a native restart file records it). The set-up evaluates the forces at the half-step
    /// velocities without advancing the contact history ([`HistoryUse::Replay`]); if they are
    /// the recorded ones to a relative 10⁻⁹ (the same set-up), the recorded forces are used as
    /// they are, so the run continues bit for bit; otherwise (the deck changed gravity, walls or
    /// materials) the new ones are. When `h.coupling` records the coupling part of the forces
    /// (a coupled run writes its state after an exchange, when the coupling already holds the
    /// next interval's values), the other forces are evaluated again and that part added.
    /// Without it the set-up is LIGGGHTS's, at the end-of-step velocities. Editing velocities
    /// or radii ([`Simulation::invalidate_forces`]) cancels it.
    pub fn set_half_step(&mut self, h: HalfStep) {
        self.replay = Some(h);
        self.forces_valid = false;
    }

    /// The set-up's force evaluation from a [`HalfStep`].
    fn replay_forces(&mut self, h: &HalfStep) {
        let n =
            h.v.len()
                .min(h.omega.len())
                .min(h.force.len())
                .min(h.torque.len())
                .min(self.particles.len());
        let p = &mut self.particles;
        let full_v: Vec<V3> = p.v[..n].to_vec();
        let full_w: Vec<V3> = p.omega[..n].to_vec();
        p.v[..n].copy_from_slice(&h.v[..n]);
        p.omega[..n].copy_from_slice(&h.omega[..n]);
        // With the recorded coupling force, the other forces are evaluated again and the
        // recorded coupling force added: the coupling now set is the next interval's.
        let recorded_coupling = h.coupling.len() >= n && self.coupling.is_active();
        if recorded_coupling {
            let next = std::mem::take(&mut self.coupling);
            self.compute_forces(HistoryUse::Replay, None);
            self.coupling = next;
            for (f, c) in self.particles.f[..n].iter_mut().zip(&h.coupling) {
                *f += c;
            }
        } else {
            self.compute_forces(HistoryUse::Replay, None);
        }
        let same = |now: &[V3], recorded: &[V3]| {
            let scale = recorded.iter().map(|f| f.norm()).fold(0.0, f64::max);
            now.iter()
                .zip(recorded)
                .all(|(a, b)| (a - b).norm() <= SAME_FORCES * scale)
        };
        let p = &self.particles;
        let matches = same(&p.f[..n], &h.force[..n]) && same(&p.torque[..n], &h.torque[..n]);
        if !matches && recorded_coupling {
            // another set-up: the forces at the half-step velocities with the coupling now set
            self.compute_forces(HistoryUse::Replay, None);
        }
        let p = &mut self.particles;
        p.v[..n].copy_from_slice(&full_v);
        p.omega[..n].copy_from_slice(&full_w);
        if matches {
            p.f[..n].copy_from_slice(&h.force[..n]);
            p.torque[..n].copy_from_slice(&h.torque[..n]);
        }
    }

    fn write_dumps(&mut self) -> Result<(), DemError> {
        // the bounds are a pass over all particles: only when a dump writes
        if !self.dumps.iter().any(|d| d.is_due(self.step)) {
            return Ok(());
        }
        // dumps list the particles in insertion order
        self.restore_order();
        let bounds = self.sim_box.dump_bounds(&self.particles.x);
        for d in &mut self.dumps {
            let heat = self.heat.as_ref();
            d.maybe_write(self.step, &self.particles, &self.coupling, heat, bounds)?;
        }
        Ok(())
    }

    /// One velocity-Verlet step.
    fn advance(&mut self) -> Result<(), DemError> {
        let dt = self.dt;
        let half = 0.5 * dt;
        // the half kick and drift, with the neighbour list's skin test in the same pass
        let moved = {
            // a few flops per particle: parallel only in large blocks
            let p = &mut self.particles;
            let (m, r, f, t) = (&p.mass, &p.radius, &p.f, &p.torque);
            let pairs = &self.pairs;
            let test = !pairs.is_stale(p.x.len());
            p.x.par_iter_mut()
                .zip(&mut p.v)
                .zip(&mut p.omega)
                .enumerate()
                .with_min_len(STREAM_BLOCK)
                .map(|(i, ((x, v), w))| {
                    let a = half / m[i];
                    let ai = half / (INERTIA_FACTOR * m[i] * r[i] * r[i]);
                    for k in 0..3 {
                        v[k] += a * f[i][k];
                        x[k] += dt * v[k];
                        w[k] += ai * t[i][k];
                    }
                    test && pairs.moved_beyond_half_skin(i, *x)
                })
                .reduce(|| false, |a, b| a || b)
        };
        self.step += 1;
        self.remove_lost()?;
        self.insert_due()?;
        // removals and insertions make the list stale
        if moved || self.pairs.is_stale(self.particles.len()) {
            if let Some(per) = self.pairs.periodic().copied() {
                self.wrap_periodic(&per);
            }
            let key = (!self.home.is_empty()).then_some(&self.home[..]);
            self.pairs
                .build_keyed(&self.particles.x, &self.particles.radius, key);
            self.adopt_spatial_order();
        }
        // forces, then the second half kick in the same pass
        self.compute_forces(HistoryUse::Advance, Some(half));
        if let Some(h) = &mut self.heat {
            h.step(&self.pairs, &self.particles, &self.walls, dt);
        }
        self.carry_held();
        self.write_dumps()
    }

    /// Moves the particles back into the box on its periodic axes, counting their images.
    fn wrap_periodic(&mut self, per: &Periodic) {
        let p = &mut self.particles;
        for (x, im) in p.x.iter_mut().zip(&mut p.image) {
            per.wrap(x, im);
        }
    }

    /// Evaluates all forces and torques into `particles.f`, `particles.torque`; with
    /// `kick = Some(dt/2)` also applies the second half kick of velocity Verlet.
    fn compute_forces(&mut self, history: HistoryUse, kick: Option<f64>) {
        let dt = self.dt;
        let model = self.pair_model;
        let mats = &self.materials;
        self.pair_forces
            .evaluate(&mut self.pairs, &self.particles, mats, &model, dt, history);
        let pair_forces = &self.pair_forces;
        let walls = &self.walls;
        let nw = walls.len();
        let coupling = &self.coupling;
        let g = self.gravity;
        let p = &mut self.particles;
        let (x, r, m, ty) = (&p.x, &p.radius, &p.mass, &p.atom_type);
        let wall_hist = &mut self.wall_hist;
        if self.wall_maybe.len() != p.len() {
            self.wall_maybe.clear();
            self.wall_maybe.resize(p.len(), true);
        }
        let wall_maybe = &mut self.wall_maybe;
        let mesh_walls = &self.mesh_walls;
        if self.mesh_contacts.len() != p.len() {
            self.mesh_contacts.resize(p.len(), Vec::new());
        }
        let mesh_contacts = &mut self.mesh_contacts;
        let gather =
            |i: usize,
             (f, t): (&mut V3, &mut V3),
             (v, w): (&mut V3, &mut V3),
             (wh, maybe, mc): (&mut [History], &mut bool, &mut Vec<MeshContact>)| {
                let mut ff = (m[i] * g) + coupling.force(i, *v);
                let mut tt = V3::zeros();
                let (fp, tp) = pair_forces.sum(i);
                ff += fp;
                tt += tp;
                let sphere = SphereState {
                    radius: r[i],
                    mass: m[i],
                    v: *v,
                    omega: *w,
                };
                // most particles touch no wall and have no wall history to reset: their
                // histories are neither read nor written
                let (check, mut touched) = (*maybe, false);
                for (wall, h) in walls.iter().zip(wh.iter_mut()) {
                    // the gap first: the normal only for contacts
                    let contact = (wall.shape.gap(x[i]) < r[i])
                        .then(|| wall.shape.distance(x[i]))
                        .flatten();
                    let Some((dist, n)) = contact else {
                        if check && *h != History::default() {
                            *h = History::default();
                        }
                        continue;
                    };
                    touched = true;
                    let c = mats.pair(ty[i], wall.material_type);
                    let o = wall_contact(&wall.model, c, &sphere, dist, n, h, dt, history);
                    ff += o.force;
                    tt += o.torque_i;
                }
                *maybe = touched;
                if !mesh_walls.is_empty() {
                    let (fm, tm) = mesh_wall::particle_forces(
                        mesh_walls, mats, ty[i], &sphere, x[i], mc, dt, history,
                    );
                    ff += fm;
                    tt += tm;
                }
                *f = ff;
                *t = tt;
                if let Some(half) = kick {
                    let a = half / m[i];
                    let ai = half / (INERTIA_FACTOR * m[i] * r[i] * r[i]);
                    for k in 0..3 {
                        v[k] += a * ff[k];
                        w[k] += ai * tt[k];
                    }
                }
            };
        let ft = p.f.par_iter_mut().zip(p.torque.par_iter_mut());
        let vw = p.v.par_iter_mut().zip(p.omega.par_iter_mut());
        if nw == 0 {
            ft.zip(vw)
                .zip(wall_maybe.par_iter_mut())
                .zip(mesh_contacts.par_iter_mut())
                .enumerate()
                .with_min_len(256)
                .for_each(|(i, (((a, b), maybe), mc))| gather(i, a, b, (&mut [], maybe, mc)));
        } else {
            ft.zip(vw)
                .zip(wall_hist.par_chunks_mut(nw))
                .zip(wall_maybe.par_iter_mut())
                .zip(mesh_contacts.par_iter_mut())
                .enumerate()
                .with_min_len(256)
                .for_each(|(i, ((((a, b), wh), maybe), mc))| gather(i, a, b, (wh, maybe, mc)));
        }
        self.forces_valid = true;
        self.forces_coupling = None;
    }
}
