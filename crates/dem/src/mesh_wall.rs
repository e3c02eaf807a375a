//! Mesh walls: `fix ID all wall/gran model … mesh n_meshes N meshes m₁ … m_N`, spheres meeting
//! the triangles of `fix mesh/surface` surfaces ([`crate::trimesh`]) with the contact model of
//! the primitive walls ([`crate::walls::wall_contact`], the same code).
//!
//! # Contacts
//! Each step a particle's candidate triangles come from one grid lookup
//! ([`TriBins`]); a triangle is in contact when its closest point (on an active feature,
//! [`TriMesh::closest`]) is nearer than the radius. One contact per (wall, surface, triangle)
//! carries a tangential (and `epsd2` rolling) history, as LIGGGHTS's
//! `fix contact/history/mesh` does. Contacts of coplanar triangles that share a vertex are one
//! contact — the rule LIGGGHTS 3.8 applies (`FixContactHistoryMesh::handleContact`, read to
//! learn it), written here without its dependence on the triangle order:
//! 1. a contact that existed at the previous step continues with its history;
//! 2. a new face contact is dropped when the particle already has a contact (of this step)
//!    with a coplanar neighbour of that triangle (a sphere over the common edge or vertex of a
//!    flat triangulation touches it once);
//! 3. a new face contact takes over the history of a previous-step contact with a coplanar
//!    neighbour (a sphere sliding over a flat triangulation keeps its tangential spring from
//!    triangle to triangle); any other new contact starts with a zero history.
//!
//! LIGGGHTS evaluates triangles in index order and applies (2) only against contacts already
//! handled, so for one step a particle moving onto a lower-numbered coplanar neighbour can be
//! counted twice there; here the order of (1) before (2) prevents it.
//!
//! Contacts across non-coplanar edges are not merged (LIGGGHTS neither): a sphere on a face
//! near a convex edge whose edge belongs to the other triangle may also touch that edge.
//!
//! The force on a surface is minus the sum of its contacts' forces on the particles
//! ([`mesh_force`]; `fix mesh/surface/stress`'s total force). Surfaces are static (`fix
//! move/mesh` is not supported).

use std::sync::Arc;

use mesh::v3::V3;

use crate::contact::{ContactModel, History, HistoryUse};
use crate::material::Materials;
use crate::trimesh::{Feature, TriBins, TriMesh};
use crate::walls::{wall_contact, SphereState};

/// A surface of `fix ID all mesh/surface[/stress] file F type T …`.
#[derive(Debug, Clone)]
pub struct MeshSurface {
    /// The triangles (the mesh's name is the fix id).
    pub mesh: TriMesh,
    /// The material type (1-based) of `type T`.
    pub material_type: u32,
    /// Whether the fix is `mesh/surface/stress` (its total force is an output).
    pub stress: bool,
}

/// A wall of one or more surfaces with one contact model.
#[derive(Debug, Clone)]
pub struct MeshWall {
    /// Deck fix id of the `wall/gran`.
    pub name: String,
    /// The surfaces, in the order of `meshes …`.
    pub surfaces: Vec<Arc<MeshSurface>>,
    /// The contact model.
    pub model: ContactModel,
    /// Per surface: its first global triangle index in the bins.
    offsets: Vec<u32>,
    bins: Option<TriBins>,
}

/// One contact of a particle with a mesh triangle, kept between steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshContact {
    /// Index of the mesh wall in the simulation.
    pub wall: u16,
    /// Index of the surface in the wall.
    pub surface: u16,
    /// The triangle.
    pub tri: u32,
    /// The contact history.
    pub history: History,
    /// The force of the last evaluation on the particle (N).
    pub force: V3,
}

impl MeshWall {
    /// A wall of `surfaces` with `model`.
    pub fn new(name: &str, surfaces: Vec<Arc<MeshSurface>>, model: ContactModel) -> MeshWall {
        let mut offsets = Vec::with_capacity(surfaces.len());
        let mut n = 0u32;
        for s in &surfaces {
            offsets.push(n);
            n += s.mesh.len() as u32;
        }
        MeshWall {
            name: name.to_string(),
            surfaces,
            model,
            offsets,
            bins: None,
        }
    }

    /// Makes sure the grid finds the contacts of spheres of radius ≤ `rmax` (m): rebuilds it
    /// when it was built for smaller ones.
    pub fn prepare(&mut self, rmax: f64) {
        if self.bins.as_ref().is_some_and(|b| b.reach() >= rmax) {
            return;
        }
        let meshes: Vec<&TriMesh> = self.surfaces.iter().map(|s| &s.mesh).collect();
        self.bins = Some(TriBins::build(&meshes, rmax));
    }

    /// The grid, once [`MeshWall::prepare`]d.
    pub fn bins(&self) -> Option<&TriBins> {
        self.bins.as_ref()
    }

    /// The surface and triangle of a global triangle index.
    #[inline]
    fn locate(&self, g: u32) -> (usize, usize) {
        let k = self.offsets.partition_point(|&o| o <= g) - 1;
        (k, (g - self.offsets[k]) as usize)
    }
}

/// A contact found this step, before the de-duplication.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    wall: u16,
    surface: u16,
    tri: u32,
    face: bool,
    dist: f64,
    normal: V3,
    history: Option<History>,
}

/// The mesh-wall forces on one particle (force N, torque N·m) at centre `x` (m): finds its
/// contacts, applies the de-duplication of the module doc, evaluates each contact with the
/// walls' contact model (history advanced by `dt` s with [`HistoryUse::Advance`]) and
/// replaces `contacts` with this step's contacts. Every wall must be
/// [`MeshWall::prepare`]d for a radius ≥ the particle's.
#[allow(clippy::too_many_arguments)]
pub fn particle_forces(
    walls: &[MeshWall],
    mats: &Materials,
    atom_type: u32,
    s: &SphereState,
    x: V3,
    contacts: &mut Vec<MeshContact>,
    dt: f64,
    history: HistoryUse,
) -> (V3, V3) {
    SCRATCH.with(|scratch| {
        let (cand, now) = &mut *scratch.borrow_mut();
        cand.clear();
        now.clear();
        evaluate(
            walls, mats, atom_type, s, x, contacts, dt, history, cand, now,
        )
    })
}

thread_local! {
    /// Per thread: the candidates and the new contacts of the particle being evaluated (kept
    /// between particles so that the hot loop does not allocate).
    static SCRATCH: std::cell::RefCell<(Vec<Candidate>, Vec<MeshContact>)> =
        const { std::cell::RefCell::new((Vec::new(), Vec::new())) };
}

/// [`particle_forces`] with the scratch buffers (empty on entry).
#[allow(clippy::too_many_arguments)]
fn evaluate(
    walls: &[MeshWall],
    mats: &Materials,
    atom_type: u32,
    s: &SphereState,
    x: V3,
    contacts: &mut Vec<MeshContact>,
    dt: f64,
    history: HistoryUse,
    cand: &mut Vec<Candidate>,
    now: &mut Vec<MeshContact>,
) -> (V3, V3) {
    for (wi, wall) in walls.iter().enumerate() {
        let Some(bins) = wall.bins.as_ref() else {
            continue;
        };
        for &g in bins.candidates(x) {
            let (k, t) = wall.locate(g);
            let Some(c) = wall.surfaces[k].mesh.closest(t, x) else {
                continue;
            };
            if c.dist < s.radius {
                cand.push(Candidate {
                    wall: wi as u16,
                    surface: k as u16,
                    tri: t as u32,
                    face: c.feature == Feature::Face,
                    dist: c.dist,
                    normal: c.normal,
                    history: None,
                });
            }
        }
    }
    if cand.is_empty() {
        contacts.clear();
        return (V3::zeros(), V3::zeros());
    }
    let old = &*contacts;
    let same_surface = |a: &Candidate, w: u16, k: u16| a.wall == w && a.surface == k;
    // 1. contacts that continue
    for c in cand.iter_mut() {
        if let Some(o) = old
            .iter()
            .find(|o| o.wall == c.wall && o.surface == c.surface && o.tri == c.tri)
        {
            c.history = Some(o.history);
        }
    }
    // 2.–3. new ones, in triangle order
    for i in 0..cand.len() {
        if cand[i].history.is_some() {
            continue;
        }
        let c = cand[i];
        let mesh = &walls[c.wall as usize].surfaces[c.surface as usize].mesh;
        let mut h = History::default();
        if c.face {
            let covered = cand.iter().any(|o| {
                o.history.is_some()
                    && same_surface(o, c.wall, c.surface)
                    && mesh.are_coplanar_neighbours(o.tri as usize, c.tri as usize)
            });
            if covered {
                continue;
            }
            if let Some(o) = old.iter().find(|o| {
                o.wall == c.wall
                    && o.surface == c.surface
                    && mesh.are_coplanar_neighbours(o.tri as usize, c.tri as usize)
            }) {
                h = o.history;
            }
        }
        cand[i].history = Some(h);
    }
    let (mut f, mut t) = (V3::zeros(), V3::zeros());
    for c in cand.iter() {
        let Some(mut h) = c.history else { continue };
        let wall = &walls[c.wall as usize];
        let surf = &wall.surfaces[c.surface as usize];
        let coeffs = mats.pair(atom_type, surf.material_type);
        let o = wall_contact(
            &wall.model,
            coeffs,
            s,
            c.dist,
            c.normal,
            &mut h,
            dt,
            history,
        );
        f += o.force;
        t += o.torque_i;
        now.push(MeshContact {
            wall: c.wall,
            surface: c.surface,
            tri: c.tri,
            history: h,
            force: o.force,
        });
    }
    // this step's contacts, in the allocation of the previous step's
    contacts.clear();
    contacts.extend_from_slice(now);
    (f, t)
}

/// The force the particles exert on surface `surface` of wall `wall` (N): minus the sum of the
/// forces of its contacts, summed particle by particle in index order.
pub fn mesh_force(contacts: &[Vec<MeshContact>], wall: usize, surface: usize) -> V3 {
    contacts
        .iter()
        .flatten()
        .filter(|c| c.wall as usize == wall && c.surface as usize == surface)
        .fold(V3::zeros(), |sum, c| sum - c.force)
}
