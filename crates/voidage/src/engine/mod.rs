//! Depositing particle volumes into the cells of a mesh, and the voidage field.
//!
//! # Accounting
//! Every particle's volume V = 4πr³/3 is either deposited into cells or counted as outside the
//! mesh: per particle, outside = V − Σ deposited shares, so Σ cells + outside = Σ V up to the
//! rounding of the sums. The outside volume of the exact method is the part of the ball beyond
//! the mesh boundary (plus rounding, ≈1e-16·V per particle); that of `centre`, `divided` and
//! `trilinear` the volume of the particles whose centre lies outside the mesh (they keep the rest
//! of a ball beyond the boundary in cells). Voidage ε = 1 − solid/cell volume,
//! unclipped unless `alpha_min` is given; the solid volume removed by clipping is reported.
//!
//! # Methods on axis-aligned grids ([`mesh::AxisGrid`])
//! * `centre`, `divided`: the grid's half-open locate rule;
//! * `trilinear` (only on grids of equal cells, whatever the [`MeshOptions`]): the 8 cells
//!   around the centre by grid index, weights from OpenFOAM's cell centres
//!   ([`crate::trilinear`]); a particle whose centre is in the mesh has all its volume in cells;
//! * `cube`: per-axis overlaps of [c − r, c + r] with the grid intervals, multiplied;
//! * `corrected-cube`: the same per-axis segments, extended by one virtual cell below the first
//!   and above the last plane where the cube leaves the grid, so that the cube is tiled as if the
//!   mesh continued; the polynomial is applied to every piece (virtual ones included),
//!   renormalised over all, and the virtual pieces are counted as outside. Shares of the cells
//!   inside the mesh do not depend on where the mesh ends;
//! * `exact`: [`crate::sphere_grid_volumes`] over the particle's cell range (corner values shared
//!   between the boxes around each grid node).
//!
//! # On every mesh
//! * `bigParticle` (CFDEM's): equal shares to the cells whose centre is within the radius,
//!   found by a walk over face neighbours from the centre's cell (`big`), the same on both
//!   paths.
//!
//! # Methods on general meshes (any polyhedral cells)
//! * `centre`: [`mesh::Locator`];
//! * `divided`: the markers by [`mesh::Locator::locate_near`] from the centre's cell (each
//!   marker tested only against the face planes that pass within the ball, the others located
//!   from the cell across the face they lie beyond); a particle whose markers all fall in one
//!   cell puts its whole volume there. With a [`DividedMemo`](crate::DividedMemo)
//!   ([`VoidageMesh::shares_with_memo_into`]) a particle that has moved less than its markers'
//!   clearance since they were located takes the kept cells instead ([`crate::memo`]);
//! * `trilinear`: not defined ([`crate::VoidageError::UnsupportedMesh`]);
//! * `exact`: Σ ball ∩ tet over [`mesh::TetDecomposition::cell_tets`], computed from the terms
//!   of the cells' faces (each face's polygon, or its fan triangles if warped: the boundary of
//!   the cell's tets). In the cap form of [`crate::sphere_poly`] a face's term is zero unless the
//!   face meets the ball, and the centre's cell adds the whole ball; the cells are found by a
//!   walk from the centre's cell across the faces that meet the ball, which reaches every cell
//!   the ball meets unless the ball crosses a boundary face (then the candidates below). Where a
//!   face passes within 1e-9 (relative) of the centre, the side the centre lies on is not
//!   certain from the face, and the particle takes the flux form over the candidates (the same
//!   volumes, to rounding, with no such condition). A ball inside the kernel of its centre's
//!   cell (on the inner side of every face plane, at distance ≥ r) goes there whole (for a cell
//!   of planar faces the walk finds this by itself: no plane passes within r); a cell inside
//!   the ball gets its (OpenFOAM) volume. A planar face's edge directions (t and t × n̂ per
//!   edge, [`crate::sphere_poly`]'s edge frames) are computed once per mesh;
//! * `cube`: the exact volume of cube ∩ cell from the terms of its faces (each face's polygon, or
//!   its fan triangles if warped) clipped by the cube ([`crate::clip`]), divided by d³;
//! * `corrected-cube`: the polynomial on those fractions plus one piece for the cube's part
//!   outside the mesh (1 − Σφc), renormalised over all of them.
//!
//! A face shared by two cells of one particle has its term computed once (odd under reversing
//! the face, it enters the two cells with opposite signs, so interior faces cancel exactly and
//! Σ shares + outside = particle volume to rounding).
//!
//! Candidate cells for cube (and exact when the walk above cannot be used): a breadth-first walk
//! over face neighbours from the centre's cell through cells whose bounding box meets the ball
//! (cube). For a convex domain the cells meeting the ball are face-connected, so the walk finds
//! them all; when the walk meets a boundary face whose box meets the ball (cube), or the centre
//! lies outside the mesh, the candidates are taken instead from a bin index of cell bounding
//! boxes, which finds every cell whose box meets the ball's box (any domain, convex or not).
//!
//! # Parallelism and determinism
//! Particles are processed in batches of fixed chunks in parallel (rayon); each chunk produces a
//! list of (cell, volume) shares, and the shares are added into the cell array in particle
//! order while the next batch is computed. On general meshes (all methods but `centre`) the
//! chunks of a batch take its particles in the order of their centre's cell, so that
//! consecutive particles read the same mesh data; each particle's shares do not depend on the
//! order. The result does not depend on the number of threads.
//!
//! # Where the code is
//! This module holds [`VoidageMesh`] (the prepared mesh) and the choice of one particle's
//! computation by method and mesh kind; `particles` the input ([`ParticleSet`]), `shares` the
//! results ([`Deposit`], [`CellShares`]), `field` the voidage ([`voidage_field`]); `big` CFDEM's
//! `bigParticle`; `deposit` the
//! public deposits and the pipeline that adds the shares in particle order (and renews the
//! memo), `batch` the parallel work items; `divided` the markers, with and without the memo;
//! `grid` `exact`, `cube` and `corrected-cube` on axis-aligned grids; `general` those on
//! general meshes (`candidates`, `cells`, `faces`, `exact`, `cube`).

mod batch;
mod big;
mod deposit;
mod divided;
mod field;
mod gauss;
mod general;
mod grid;
mod particles;
mod shares;

pub use field::{voidage_field, Voidage};
pub use particles::ParticleSet;
pub use shares::{CellShares, Deposit};

use crate::clip::ClipScratch;
use crate::divided::{divided_offsets, DIVIDED_MARKERS};
use crate::error::VoidageError;
use crate::label_map::LabelMap;
use crate::method::Method;
use crate::sphere_box::GridScratch;
use crate::sphere_poly::{EdgeAxes, MAX_POLYGON};
use crate::trilinear::{check_grid, grid_trilinear};
use crate::vec3::V3;
use foam::{FaceList, Label, PolyMesh};
use general::{CellBins, CellPlane};
use grid::{grid_cube, grid_exact};
use mesh::{Aabb, AxisGrid, Locator, LocatorOptions, MeshGeometry};
use rayon::prelude::*;

/// Options for [`VoidageMesh::with_options`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshOptions {
    /// Use the axis-aligned-grid paths when the mesh is such a grid (default true). With false
    /// every method takes the general-mesh path.
    pub axis_aligned_fast_path: bool,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            axis_aligned_fast_path: true,
        }
    }
}

/// Per-thread scratch space, reused across the particles of a work item.
#[derive(Default)]
struct Scratch {
    grid: GridScratch,
    vols: Vec<f64>,
    planes: [Vec<f64>; 3],
    segments: [Vec<(Option<usize>, f64)>; 3],
    visited: LabelMap<()>,
    queue: Vec<Label>,
    candidates: Vec<Label>,
    faces: LabelMap<f64>,
    fractions: Vec<f64>,
    clip: ClipScratch,
    polygon: Vec<V3>,
    markers: Vec<(Label, u32)>,
    /// The particles of a work item: centre, radius, centre cell, index.
    gathered: Vec<(V3, f64, Option<Label>, u32)>,
}

impl Scratch {
    /// Starts a walk over face neighbours from `c0`: no cell listed or visited but `c0`, which
    /// is queued.
    fn begin_walk(&mut self, c0: Label) {
        self.candidates.clear();
        self.visited.clear();
        self.queue.clear();
        self.queue.push(c0);
        self.visited.insert(c0, ());
    }
}

/// One particle being deposited: centre (m), radius (m, > 0), volume (m³), centre cell.
#[derive(Clone, Copy, Debug)]
struct Ball {
    c: V3,
    r: f64,
    v: f64,
    cell: Option<Label>,
}

/// A mesh prepared for voidage computations: geometry, locator, face addressing, cell bounding
/// boxes and a bin index.
#[derive(Clone, Debug)]
pub struct VoidageMesh {
    geom: MeshGeometry,
    locator: Locator,
    grid: Option<AxisGrid>,
    faces: FaceList,
    owner: Vec<Label>,
    neighbour: Vec<Label>,
    cell_bounds: Vec<Aabb>,
    /// Bounding box of every boundary face's points (face n_internal + i at i).
    boundary_bounds: Vec<Aabb>,
    /// Unit normal of every face (OpenFOAM's area vector, out of the owner; zero for a
    /// zero-area face) and its plane's offset n̂·(fan apex).
    face_planes: Vec<(V3, f64)>,
    /// The planes of every cell's faces as seen from the cell, in the order of the cell's faces
    /// (cell i's from `cell_plane_start[i]`): kept together so that a cell's plane tests read
    /// neighbouring memory.
    cell_planes: Vec<CellPlane>,
    cell_plane_start: Vec<u32>,
    bins: CellBins,
    markers: [V3; DIVIDED_MARKERS],
    /// Faces whose points lie in one plane ([`Locator::face_is_planar`]) with at most
    /// [`MAX_POLYGON`] points: their flux is taken over the polygon's edges instead of the fan
    /// triangles.
    planar: Vec<bool>,
    /// The edge directions of every planar face (one per point slot of `faces`, the edge from
    /// that point to the next; zero for the slots of other faces), for the cap terms.
    edge_axes: Vec<EdgeAxes>,
}

impl VoidageMesh {
    /// Prepares `mesh` with the default options.
    pub fn new(mesh: &PolyMesh) -> Result<Self, VoidageError> {
        Self::with_options(mesh, MeshOptions::default())
    }

    /// Prepares `mesh`: checks it, computes its geometry (as OpenFOAM does) and builds the
    /// locator and indexes.
    pub fn with_options(mesh: &PolyMesh, options: MeshOptions) -> Result<Self, VoidageError> {
        let geom = MeshGeometry::new(mesh)?;
        let locator = Locator::with_options(
            mesh,
            &geom,
            LocatorOptions {
                axis_aligned_fast_path: options.axis_aligned_fast_path,
            },
        )?;
        let grid = locator.axis_grid().cloned();
        let tets = locator.tets();
        let cell_bounds: Vec<Aabb> = (0..mesh.n_cells as Label)
            .into_par_iter()
            .map(|c| tets.cell_bounds(c))
            .collect();
        let points = tets.points();
        let boundary_bounds = (mesh.n_internal_faces()..mesh.n_faces())
            .into_par_iter()
            .with_min_len(4096)
            .map(|f| Aabb::of_points(mesh.faces.face(f).iter().map(|&p| &points[p as usize])))
            .collect();
        let face_planes: Vec<(V3, f64)> = (0..mesh.n_faces())
            .into_par_iter()
            .with_min_len(4096)
            .map(|f| {
                let a = geom.face_areas[f];
                let m = a.norm();
                let n = if m > 0.0 { a / m } else { V3::zeros() };
                (n, n.dot(&tets.face_apexes()[f]))
            })
            .collect();
        let bins = CellBins::new(&geom.bounds, &cell_bounds);
        let planar: Vec<bool> = (0..mesh.n_faces())
            .map(|f| mesh.faces.face(f).len() <= MAX_POLYGON && locator.face_is_planar(f as Label))
            .collect();
        let (cell_planes, cell_plane_start) =
            CellPlane::table(tets, &mesh.owner, &mesh.neighbour, &face_planes, &planar);
        // one per point slot of the faces (allocated exactly: a flat_map gives no size)
        let mut edge_axes: Vec<EdgeAxes> = Vec::with_capacity(mesh.faces.labels().len());
        edge_axes.extend((0..mesh.n_faces()).flat_map(|f| {
            let face = mesh.faces.face(f);
            let nh = face_planes[f].0;
            let p = |i: usize| points[face[i % face.len()] as usize];
            let planar = planar[f];
            (0..face.len()).map(move |i| {
                if planar {
                    EdgeAxes::new(p(i), p(i + 1), nh)
                } else {
                    EdgeAxes::default()
                }
            })
        }));
        Ok(VoidageMesh {
            geom,
            grid,
            faces: mesh.faces.clone(),
            owner: mesh.owner.clone(),
            neighbour: mesh.neighbour.clone(),
            cell_bounds,
            boundary_bounds,
            cell_planes,
            cell_plane_start,
            face_planes,
            bins,
            locator,
            markers: divided_offsets(),
            planar,
            edge_axes,
        })
    }

    /// The mesh geometry (cell volumes as OpenFOAM computes them).
    pub fn geometry(&self) -> &MeshGeometry {
        &self.geom
    }

    /// The locator.
    pub fn locator(&self) -> &Locator {
        &self.locator
    }

    /// The axis-aligned grid, when the mesh is one and the fast path is on.
    pub fn axis_grid(&self) -> Option<&AxisGrid> {
        self.grid.as_ref()
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.geom.n_cells()
    }

    /// Cell volumes, m³.
    pub fn cell_volumes(&self) -> &[f64] {
        &self.geom.cell_volumes
    }

    /// Whether `method` is defined on this mesh: every method is, except `trilinear` on a
    /// mesh that is not a structured grid of equal axis-aligned cells
    /// ([`crate::trilinear::check_grid`]; independent of [`MeshOptions`]). Deposits check it
    /// first.
    pub fn check_method(&self, method: Method) -> Result<(), VoidageError> {
        match method {
            Method::Trilinear => check_grid(self.locator.tets().axis_grid()).map(|_| ()),
            _ => Ok(()),
        }
    }

    /// The cell across internal face `f` from cell `c`.
    #[inline]
    fn across(&self, f: usize, c: Label) -> Label {
        if self.owner[f] == c {
            self.neighbour[f]
        } else {
            self.owner[f]
        }
    }

    /// Pushes the shares of one particle and returns its volume outside the mesh.
    fn particle(
        &self,
        method: Method,
        b: Ball,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> f64 {
        let corrected = method == Method::CorrectedCube;
        match (method, &self.grid) {
            (Method::Centre, _) => match b.cell {
                Some(c0) => {
                    out.push((c0, b.v));
                    0.0
                }
                None => b.v,
            },
            (Method::Divided, _) => self.divided(b, s, out),
            (Method::BigParticle, _) => self.big_particle(b, s, out),
            (Method::Gauss, _) => self.gauss(b, s, out),
            (Method::Trilinear, _) => {
                let g = self.locator.tets().axis_grid();
                let g = g.expect("trilinear: the grid is checked before depositing");
                grid_trilinear(g, &self.geom.cell_centres, b.c, b.cell, b.v, out)
            }
            (Method::Exact, Some(g)) => grid_exact(g, b, s, out),
            (Method::Cube | Method::CorrectedCube, Some(g)) => grid_cube(g, b, corrected, s, out),
            (Method::Exact, None) => self.general_exact(b, s, out),
            (Method::Cube | Method::CorrectedCube, None) => self.general_cube(b, corrected, s, out),
        }
    }
}

impl foam::HeapBytes for VoidageMesh {
    /// Its geometry, locator, grid, its own copy of the faces and addressing, and the per-face
    /// and per-cell records of the general kernels (planes, bins, edge directions).
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        self.geom.heap_bytes()
            + self.locator.heap_bytes()
            + self.grid.heap_bytes()
            + self.faces.heap_bytes()
            + flat(&self.owner)
            + flat(&self.neighbour)
            + flat(&self.cell_bounds)
            + flat(&self.boundary_bounds)
            + flat(&self.face_planes)
            + flat(&self.cell_planes)
            + flat(&self.cell_plane_start)
            + self.bins.heap_bytes()
            + flat(&self.planar)
            + flat(&self.edge_axes)
    }
}
