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
//! # Methods on general meshes (any polyhedral cells)
//! * `centre`: [`mesh::Locator`];
//! * `divided`: the markers by [`mesh::Locator::locate_near`] from the centre's cell (each
//!   marker tested only against the face planes that pass within the ball, the others located
//!   from the cell across the face they lie beyond); a particle whose markers all fall in one
//!   cell puts its whole volume there. With a [`DividedMemo`]
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

use crate::clip::{box_polygon_flux, ClipScratch};
use crate::cube::{cube_axis_fraction, khawaja_correction};
use crate::divided::{divided_offsets, DIVIDED_MARKERS};
use crate::error::{ParticleProblem, VoidageError};
use crate::label_map::LabelMap;
use crate::memo::{DividedMemo, MemoEntry};
use crate::method::Method;
use crate::sphere_box::{
    ball_volume, cut_ball_unit, interval_dist2, sphere_grid_volumes, GridScratch,
};
use crate::sphere_poly::{
    polygon_cap_unit, polygon_cap_unit_axes, polygon_flux_unit, triangle_flux_unit, EdgeAxes,
    MAX_POLYGON,
};
use crate::trilinear::{check_grid, grid_trilinear};
use crate::vec3::{to_unit, V3};
use foam::{FaceList, Label, PolyMesh};
use mesh::{Aabb, AxisGrid, Locator, LocatorOptions, MeshGeometry};
use rayon::prelude::*;

/// Particles per parallel work item.
const CHUNK: usize = 1024;
/// Work items per batch (bounds the memory of the share lists).
const BATCH: usize = 64;

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
    fn restart(&mut self, method: Method, n: usize) {
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

    fn append(&mut self, shares: &[(Label, f64)], counts: &[u32]) {
        let mut end = *self.offsets.last().expect("offsets start with 0");
        for &n in counts {
            end += n as usize;
            self.offsets.push(end);
        }
        self.cells.extend(shares.iter().map(|s| s.0));
        self.volumes.extend(shares.iter().map(|s| s.1));
    }
}

/// A voidage field ε = 1 − solid / cell volume, optionally clipped from below.
#[derive(Clone, Debug, PartialEq)]
pub struct Voidage {
    /// ε per cell (dimensionless).
    pub epsilon: Vec<f64>,
    /// The floor applied, if any.
    pub alpha_min: Option<f64>,
    /// Solid volume removed by clipping, m³: Σ (alpha_min − ε)·V over clipped cells.
    pub clipped_volume: f64,
    /// Number of clipped cells.
    pub clipped_cells: usize,
    /// Smallest ε before clipping (1 for no cells).
    pub min_epsilon: f64,
    /// Cells with ε < 0 before clipping (more solid than cell volume).
    pub negative_cells: usize,
}

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

/// Uniform bins over the mesh bounds holding the cells whose bounding boxes overlap them.
#[derive(Clone, Debug)]
struct CellBins {
    origin: V3,
    inv: V3,
    dims: [usize; 3],
    offsets: Vec<u32>,
    cells: Vec<Label>,
}

impl CellBins {
    /// Bins of about the mean cell size per axis, at most 4 per cell and 1024 per axis.
    fn new(bounds: &Aabb, cell_bounds: &[Aabb]) -> CellBins {
        let n = cell_bounds.len().max(1) as f64;
        let ext = bounds.extent();
        let mut dims = [1usize; 3];
        let mut inv = V3::zeros();
        for a in 0..3 {
            let mean = cell_bounds.iter().map(|b| b.max[a] - b.min[a]).sum::<f64>() / n;
            if ext[a] > 0.0 && mean > 0.0 {
                dims[a] = ((ext[a] / mean).round() as usize).clamp(1, 1024);
            }
        }
        while dims.iter().product::<usize>() as f64 > 4.0 * n {
            dims = dims.map(|d| d.div_ceil(2));
        }
        for a in 0..3 {
            if ext[a] > 0.0 {
                inv[a] = dims[a] as f64 / ext[a];
            }
        }
        let mut bins = CellBins {
            origin: bounds.min,
            inv,
            dims,
            offsets: vec![],
            cells: vec![],
        };
        let n_bins = dims.iter().product::<usize>();
        let mut counts = vec![0u32; n_bins + 1];
        for b in cell_bounds {
            bins.for_each_bin(b.min, b.max, |i| counts[i + 1] += 1);
        }
        for i in 0..n_bins {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut cells = vec![0; counts[n_bins] as usize];
        for (c, b) in cell_bounds.iter().enumerate() {
            bins.for_each_bin(b.min, b.max, |i| {
                cells[fill[i] as usize] = c as Label;
                fill[i] += 1;
            });
        }
        bins.offsets = counts;
        bins.cells = cells;
        bins
    }

    #[inline]
    fn bin(&self, a: usize, x: f64) -> usize {
        let t = (x - self.origin[a]) * self.inv[a];
        if t > 0.0 {
            (t as usize).min(self.dims[a] - 1)
        } else {
            0
        }
    }

    fn for_each_bin(&self, lo: V3, hi: V3, mut f: impl FnMut(usize)) {
        let l: [usize; 3] = std::array::from_fn(|a| self.bin(a, lo[a]));
        let h: [usize; 3] = std::array::from_fn(|a| self.bin(a, hi[a]));
        for k in l[2]..=h[2] {
            for j in l[1]..=h[1] {
                for i in l[0]..=h[0] {
                    f(i + self.dims[0] * (j + self.dims[1] * k));
                }
            }
        }
    }

    fn for_each_cell(&self, lo: V3, hi: V3, mut f: impl FnMut(Label)) {
        self.for_each_bin(lo, hi, |b| {
            let r = self.offsets[b] as usize..self.offsets[b + 1] as usize;
            for &c in &self.cells[r] {
                f(c);
            }
        });
    }
}

/// A region whose overlapping cells are wanted: an axis-aligned box, optionally narrowed to a
/// ball.
#[derive(Clone, Copy, Debug)]
struct Query {
    lo: V3,
    hi: V3,
    ball: Option<(V3, f64)>,
}

impl Query {
    #[inline]
    fn hits(&self, b: &Aabb) -> bool {
        if (0..3).any(|a| b.max[a] <= self.lo[a] || b.min[a] >= self.hi[a]) {
            return false;
        }
        match self.ball {
            None => true,
            Some((c, r)) => {
                let d2: f64 = (0..3)
                    .map(|a| interval_dist2(b.min[a] - c[a], b.max[a] - c[a]).0)
                    .sum();
                d2 < r * r
            }
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

/// The plane of one face of a cell, as seen from the cell.
#[derive(Clone, Copy, Debug)]
struct CellPlane {
    /// Unit normal out of the cell (zero for a warped face).
    n: V3,
    /// n · (fan apex); NaN for a warped face, whose fan triangles have planes of their own.
    k: f64,
    /// The face.
    face: Label,
    /// The cell across the face ([`NO_CELL`] for a boundary face): kept here so that a walk
    /// does not look up the face's owner and neighbour.
    across: Label,
    /// True when the cell owns the face (its terms, computed in the owner's orientation,
    /// enter with a + sign).
    own: bool,
}

/// [`CellPlane::across`] of a boundary face.
const NO_CELL: Label = Label::MAX;

impl CellPlane {
    /// The table of every cell's face planes and each cell's first entry (one more for the
    /// end).
    fn table(
        tets: &mesh::TetDecomposition,
        owner: &[Label],
        neighbour: &[Label],
        face_planes: &[(V3, f64)],
        planar: &[bool],
    ) -> (Vec<CellPlane>, Vec<u32>) {
        let mut planes = Vec::new();
        let mut start = Vec::with_capacity(tets.n_cells() + 1);
        for cell in 0..tets.n_cells() as Label {
            start.push(planes.len() as u32);
            for &f in tets.cell_faces(cell) {
                let (n, k) = face_planes[f as usize];
                let own = owner[f as usize] == cell;
                let across = match neighbour.get(f as usize) {
                    None => NO_CELL,
                    Some(&nb) if own => nb,
                    Some(_) => owner[f as usize],
                };
                let (n, k) = if !planar[f as usize] {
                    (V3::zeros(), f64::NAN)
                } else if own {
                    (n, k)
                } else {
                    (-n, -k)
                };
                planes.push(CellPlane {
                    n,
                    k,
                    face: f,
                    across,
                    own,
                });
            }
        }
        start.push(planes.len() as u32);
        (planes, start)
    }

    /// Signed distance of `p` from the plane, positive outside the cell (NaN for a warped face).
    #[inline]
    fn outside(&self, p: V3) -> f64 {
        self.n.dot(&p) - self.k
    }
}

/// How a walk over the cells a ball meets ended ([`VoidageMesh::exact_walk`]).
enum CapWalk {
    /// Every cell found; the volume outside the mesh.
    Done(f64),
    /// The ball crosses a boundary face: the candidates must come from the bins.
    Incomplete,
    /// A face cannot tell the side of the centre: the flux form must be used.
    Tie,
}

/// One particle being deposited: centre (m), radius (m, > 0), volume (m³), centre cell.
#[derive(Clone, Copy, Debug)]
struct Ball {
    c: V3,
    r: f64,
    v: f64,
    cell: Option<Label>,
}

/// What one work item produced.
struct ChunkOut {
    shares: Vec<(Label, f64)>,
    /// Number of entries of `shares` per particle of the work item, in order.
    counts: Vec<u32>,
    outside: f64,
    volume: f64,
    fully_outside: usize,
    partly_outside: usize,
    /// With a memo: each particle's new entry, in order.
    memo: Vec<MemoEntry>,
    /// With a memo: particles whose kept entry was used.
    reused: usize,
}

/// What one batch of work items produced.
struct BatchOut {
    /// Index of the batch's first particle.
    start: usize,
    /// The particles in the order computed, when not in index order.
    order: Option<Vec<u32>>,
    /// The work items: `CHUNK` particles each, in that order.
    chunks: Vec<ChunkOut>,
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
        let edge_axes: Vec<EdgeAxes> = (0..mesh.n_faces())
            .flat_map(|f| {
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
            })
            .collect();
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

    /// Deposits the particles' volumes with `method` (module docs), locating the centres
    /// without hints.
    pub fn deposit(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
    ) -> Result<Deposit, VoidageError> {
        let mut cells = vec![None; particles.len()];
        self.deposit_with_cells(method, particles, &mut cells)
    }

    /// Deposits the particles' volumes with `method`. `cells[i]` is a hint for the cell of
    /// particle i on entry (e.g. from the previous coupling step; `None`: no hint) and the cell
    /// holding its centre on return (`None` outside the mesh).
    pub fn deposit_with_cells(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
    ) -> Result<Deposit, VoidageError> {
        self.run(method, particles, cells, None, None)
    }

    /// The (cell, volume) shares each particle deposits with `method`, together with the
    /// deposit they add up to: the same code path as [`VoidageMesh::deposit_with_cells`], so
    /// `deposit.solid[c]` is the sum of the shares of cell c (in the same order, hence
    /// bit-identical to a plain deposit). `cells` is a hint and the result as there.
    pub fn shares_with_cells(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
    ) -> Result<(CellShares, Deposit), VoidageError> {
        let mut shares = CellShares {
            method,
            offsets: Vec::new(),
            cells: Vec::new(),
            volumes: Vec::new(),
        };
        let dep = self.shares_with_cells_into(method, particles, cells, &mut shares)?;
        Ok((shares, dep))
    }

    /// [`VoidageMesh::shares_with_cells`] into `shares`, whose previous contents are replaced
    /// and whose allocations are reused: a coupling loop that hands back the shares of the
    /// last step writes 20 bytes per share into memory already mapped instead of fresh pages.
    /// On error `shares` is left empty or partly filled.
    pub fn shares_with_cells_into(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
        shares: &mut CellShares,
    ) -> Result<Deposit, VoidageError> {
        shares.restart(method, particles.len());
        self.run(method, particles, cells, Some(shares), None)
    }

    /// [`VoidageMesh::shares_with_cells_into`] that reuses the `divided` markers' cells kept
    /// in `memo` where the particle has not moved past their clearance, and keeps this
    /// deposit's for the next ([`crate::memo`]). The result is bit for bit the one without a
    /// memo, whatever the memo holds; `memo` is only read and written by `divided` on a general
    /// mesh. Entry i belongs to particle i ([`DividedMemo::reorder`] follows a changed order).
    pub fn shares_with_memo_into(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
        memo: &mut DividedMemo,
        shares: &mut CellShares,
    ) -> Result<Deposit, VoidageError> {
        shares.restart(method, particles.len());
        self.run(method, particles, cells, Some(shares), Some(memo))
    }

    /// [`VoidageMesh::shares_with_cells`] without a cell hint.
    pub fn shares(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
    ) -> Result<(CellShares, Deposit), VoidageError> {
        let mut cells = vec![None; particles.len()];
        self.shares_with_cells(method, particles, &mut cells)
    }

    /// Locates, deposits and reduces; keeps the per-particle shares when `keep` is given, and
    /// uses and renews the `divided` memo when `memo` is.
    fn run(
        &self,
        method: Method,
        particles: &ParticleSet<'_>,
        cells: &mut [Option<Label>],
        mut keep: Option<&mut CellShares>,
        memo: Option<&mut DividedMemo>,
    ) -> Result<Deposit, VoidageError> {
        self.check_method(method)?;
        particles.check()?;
        if cells.len() != particles.len() {
            return Err(VoidageError::LengthMismatch {
                what: "cells",
                expected: particles.len(),
                found: cells.len(),
            });
        }
        self.locator
            .locate_all_from(particles.positions, &mut cells[..]);
        let mut solid = vec![0.0; self.n_cells()];
        let mut dep = Deposit {
            method,
            solid: vec![],
            particles: particles.len(),
            particle_volume: 0.0,
            deposited_volume: 0.0,
            outside_volume: 0.0,
            particles_outside: 0,
            particles_partly_outside: 0,
        };
        let n = particles.len();
        let batches: Vec<std::ops::Range<usize>> = (0..n)
            .step_by(CHUNK * BATCH)
            .map(|s| s..(s + CHUNK * BATCH).min(n))
            .collect();
        let cells: &[Option<Label>] = cells;
        // The memo's entries of the last deposit (read by the work items) and this one's
        // (written in particle order with the shares).
        let mut memo = memo.filter(|_| method == Method::Divided && self.grid.is_none());
        let (mut kept, mut renewed) = (Vec::new(), Vec::new());
        if let Some(m) = memo.as_deref_mut() {
            kept = std::mem::take(&mut m.entries);
            if kept.len() != n {
                kept.clear();
                kept.resize(n, MemoEntry::EMPTY);
            }
            renewed = std::mem::take(&mut m.spare);
            renewed.clear();
            renewed.resize(n, MemoEntry::EMPTY);
        }
        let mut reused = 0;
        let kept_all = kept;
        let kept = memo.is_some().then_some(&kept_all[..]);
        // On a general mesh the particles of a batch are computed in the order of their
        // centre's cell, so that consecutive particles read the same mesh data (random particle
        // orders otherwise wait on memory); the shares are still added in particle order.
        let sort = self.grid.is_none() && method != Method::Centre && n <= u32::MAX as usize;
        // A two-stage pipeline: while the threads compute batch b + 1, one of them adds batch
        // b to the solid volumes and the shares, in particle order.
        let mut done: Option<BatchOut> = None;
        for batch in batches.iter().map(Some).chain([None]) {
            let (next, ()) = rayon::join(
                || batch.map(|b| self.batch(method, particles, cells, kept, b.clone(), sort)),
                || {
                    let Some(out) = done.take() else { return };
                    let mut add = |shares: &[(Label, f64)], counts: &[u32]| {
                        for &(c, v) in shares {
                            solid[c as usize] += v;
                        }
                        if let Some(k) = keep.as_deref_mut() {
                            k.append(shares, counts);
                        }
                    };
                    if kept.is_some() {
                        for (k, o) in out.chunks.iter().enumerate() {
                            reused += o.reused;
                            for (j, &e) in o.memo.iter().enumerate() {
                                let i = match &out.order {
                                    None => out.start + k * CHUNK + j,
                                    Some(order) => order[k * CHUNK + j] as usize,
                                };
                                renewed[i] = e;
                            }
                        }
                    }
                    match &out.order {
                        None => {
                            for o in &out.chunks {
                                add(&o.shares, &o.counts);
                            }
                        }
                        Some(order) => {
                            // Where each particle's shares are: (work item, first, count).
                            let mut at = vec![(0u32, 0u32, 0u32); order.len()];
                            for (k, o) in out.chunks.iter().enumerate() {
                                let mut first = 0u32;
                                for (j, &count) in o.counts.iter().enumerate() {
                                    let i = order[k * CHUNK + j] as usize - out.start;
                                    at[i] = (k as u32, first, count);
                                    first += count;
                                }
                            }
                            for &(k, first, count) in &at {
                                let shares = &out.chunks[k as usize].shares;
                                add(&shares[first as usize..(first + count) as usize], &[count]);
                            }
                        }
                    }
                    for o in &out.chunks {
                        dep.outside_volume += o.outside;
                        dep.particle_volume += o.volume;
                        dep.particles_outside += o.fully_outside;
                        dep.particles_partly_outside += o.partly_outside;
                    }
                },
            );
            done = next;
        }
        if let Some(m) = memo {
            m.entries = renewed;
            m.spare = kept_all;
            m.reused = reused;
        }
        dep.deposited_volume = solid.iter().sum();
        dep.solid = solid;
        Ok(dep)
    }

    /// The voidage ε = 1 − solid / cell volume of a deposit, clipped to `alpha_min` when given
    /// (which must lie in [0, 1)).
    pub fn voidage(
        &self,
        deposit: &Deposit,
        alpha_min: Option<f64>,
    ) -> Result<Voidage, VoidageError> {
        voidage_field(&deposit.solid, self.cell_volumes(), alpha_min)
    }

    /// The work items of the particles `range`, in parallel: in index order, or with `sort` in
    /// the order of their centre's cell (then `order` holds that order).
    fn batch(
        &self,
        method: Method,
        p: &ParticleSet<'_>,
        cells: &[Option<Label>],
        kept: Option<&[MemoEntry]>,
        range: std::ops::Range<usize>,
        sort: bool,
    ) -> BatchOut {
        let start = range.start;
        if !sort {
            let items: Vec<std::ops::Range<usize>> = range
                .clone()
                .step_by(CHUNK)
                .map(|s| s..(s + CHUNK).min(range.end))
                .collect();
            let chunks = items
                .par_iter()
                .map_init(Scratch::default, |s, r| {
                    self.chunk(method, p, cells, kept, r.clone(), s)
                })
                .collect();
            return BatchOut {
                start,
                order: None,
                chunks,
            };
        }
        let mut keys: Vec<u64> = range
            .map(|i| (u64::from(cells[i].unwrap_or(Label::MAX)) << 32) | i as u64)
            .collect();
        keys.par_sort_unstable();
        let order: Vec<u32> = keys.iter().map(|&k| k as u32).collect();
        let chunks = order
            .par_chunks(CHUNK)
            .map_init(Scratch::default, |s, idx| {
                self.chunk(method, p, cells, kept, idx.iter().map(|&i| i as usize), s)
            })
            .collect();
        BatchOut {
            start,
            order: Some(order),
            chunks,
        }
    }

    /// The shares of the particles `indices`, in that order. Their centres, radii and cells
    /// are gathered first into `s.gathered`: in a loop of independent loads the misses of a
    /// scattered order overlap, where the per-particle work between them would serialise them
    /// (measured 8 % of the general-mesh exact benchmark's time on those loads).
    fn chunk(
        &self,
        method: Method,
        p: &ParticleSet<'_>,
        cells: &[Option<Label>],
        kept: Option<&[MemoEntry]>,
        indices: impl Iterator<Item = usize>,
        s: &mut Scratch,
    ) -> ChunkOut {
        let mut gathered = std::mem::take(&mut s.gathered);
        gathered.clear();
        gathered.extend(indices.map(|i| (p.positions[i], p.radii[i], cells[i], i as u32)));
        let len = gathered.len();
        let mut out = ChunkOut {
            shares: Vec::with_capacity(len * 2),
            counts: Vec::with_capacity(len),
            outside: 0.0,
            volume: 0.0,
            fully_outside: 0,
            partly_outside: 0,
            memo: Vec::with_capacity(if kept.is_some() { len } else { 0 }),
            reused: 0,
        };
        for &(c, r, cell, i) in &gathered {
            let start = out.shares.len();
            if r == 0.0 {
                out.counts.push(0);
                if kept.is_some() {
                    out.memo.push(MemoEntry::EMPTY);
                }
                continue;
            }
            let v = ball_volume(r);
            let ball = Ball { c, r, v, cell };
            let outside = if let Some(kept) = kept {
                let (outside, renewed, reused) =
                    self.divided_kept(ball, &kept[i as usize], s, &mut out.shares);
                out.reused += usize::from(reused);
                out.memo.push(renewed);
                outside
            } else {
                self.particle(method, ball, s, &mut out.shares)
            };
            out.counts.push((out.shares.len() - start) as u32);
            out.volume += v;
            out.outside += outside;
            if out.shares.len() == start {
                out.fully_outside += 1;
            } else if outside > 1e-12 * v {
                out.partly_outside += 1;
            }
        }
        s.gathered = gathered;
        out
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

    /// `divided`'s shares of one particle (module docs).
    fn divided(&self, b: Ball, s: &mut Scratch, out: &mut Vec<(Label, f64)>) -> f64 {
        let Ball { c, r, v, cell } = b;
        let Some(c0) = cell else {
            return v;
        };
        s.markers.clear();
        s.markers.push((c0, 1));
        let mut add = |m: Option<Label>| count_marker(&mut s.markers, m.unwrap_or(c0));
        match &self.grid {
            Some(g) => {
                for off in &self.markers[1..] {
                    add(g.locate(V3::from_fn(|a, _| c[a] + r * off[a])));
                }
            }
            None => self
                .locator
                .locate_near(c0, c, r, &self.markers[1..], |_, m| add(m)),
        }
        push_markers(&s.markers, v, out);
        0.0
    }

    /// [`VoidageMesh::divided`] on a general mesh with a memo ([`crate::memo`]): the kept
    /// entry's cells when it holds for the ball, else the markers located afresh with their
    /// clearance; returns the outside volume, the entry for the next deposit and whether the
    /// kept one was used.
    fn divided_kept(
        &self,
        b: Ball,
        kept: &MemoEntry,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> (f64, MemoEntry, bool) {
        let Ball { c, r, v, cell } = b;
        let Some(c0) = cell else {
            return (v, MemoEntry::EMPTY, false);
        };
        s.markers.clear();
        if kept.holds(c, r, c0) {
            s.markers.extend(kept.found());
            push_markers(&s.markers, v, out);
            return (0.0, *kept, true);
        }
        s.markers.push((c0, 1));
        let mut add = |m: Option<Label>| count_marker(&mut s.markers, m.unwrap_or(c0));
        let clearance = self
            .locator
            .locate_near_clearance(c0, c, r, &self.markers[1..], |_, m| add(m));
        push_markers(&s.markers, v, out);
        (0.0, MemoEntry::new(c, r, clearance, &s.markers), false)
    }

    /// The cells that may overlap `q` (module docs), into `s.candidates`.
    fn candidates(&self, q: &Query, start: Option<Label>, s: &mut Scratch) {
        s.candidates.clear();
        s.visited.clear();
        let n_internal = self.neighbour.len();
        let tets = self.locator.tets();
        let mut complete = start.is_some();
        if let Some(c0) = start {
            s.queue.clear();
            s.queue.push(c0);
            s.visited.insert(c0, ());
            while let Some(c) = s.queue.pop() {
                s.candidates.push(c);
                for &f in tets.cell_faces(c) {
                    let f = f as usize;
                    if f < n_internal {
                        let n = if self.owner[f] == c {
                            self.neighbour[f]
                        } else {
                            self.owner[f]
                        };
                        if s.visited.insert(n, ()) && q.hits(&self.cell_bounds[n as usize]) {
                            s.queue.push(n);
                        }
                    } else if q.hits(&self.boundary_bounds[f - n_internal]) {
                        complete = false;
                    }
                }
            }
        }
        if !complete {
            s.candidates.clear();
            s.visited.clear();
            self.bins.for_each_cell(q.lo, q.hi, |c| {
                if s.visited.insert(c, ()) && q.hits(&self.cell_bounds[c as usize]) {
                    s.candidates.push(c);
                }
            });
        }
    }

    /// The flux term of face `f` (owner orientation) for the unit ball: Σ over its fan
    /// triangles, in coordinates relative to the centre divided by the radius.
    fn face_flux_unit(&self, f: usize, c: V3, inv_r: f64) -> f64 {
        let tets = self.locator.tets();
        let points = tets.points();
        let face = self.faces.face(f);
        let q = |i: usize| to_unit(points[face[i] as usize], c, inv_r);
        if self.planar[f] {
            // A zeroed array of records is a memset; an array of `V3::zeros()` was measured
            // 8 % slower on the general-mesh exact benchmark.
            let mut v = [[0.0; 3]; MAX_POLYGON];
            for (u, &p) in v.iter_mut().zip(face) {
                *u = to_unit(points[p as usize], c, inv_r).into();
            }
            let a = self.geom.face_areas[f].map(|x| x * inv_r * inv_r);
            return polygon_flux_unit(mesh::v3::as_vectors(&v[..face.len()]), a);
        }
        if face.len() == 3 {
            return triangle_flux_unit(&[q(0), q(1), q(2)]);
        }
        let apex = to_unit(tets.face_apexes()[f], c, inv_r);
        let n = face.len();
        let mut sum = 0.0;
        let first = q(0);
        let mut prev = first;
        for i in 0..n {
            let next = if i + 1 == n { first } else { q(i + 1) };
            sum += triangle_flux_unit(&[apex, prev, next]);
            prev = next;
        }
        sum
    }

    /// The cap-form term g = flux − Ω/3 of face `f` (owner orientation) for the unit ball
    /// ([`crate::sphere_poly`], "Cap form"): over the polygon for planar faces, over the fan
    /// triangles otherwise; zero without trigonometry unless the face meets the ball. `None`
    /// when the centre or its foot point is within 1e-9 of the face (relative to the face's
    /// extent in unit-ball coordinates): then which side of the face the centre lies on, by the
    /// locator's tie rule, is not certain from the face alone.
    fn face_cap_unit(&self, f: usize, c: V3, r: f64, poly: &mut Vec<V3>) -> Option<f64> {
        const TIE: f64 = 1e-9;
        let inv_r = 1.0 / r;
        let tets = self.locator.tets();
        let points = tets.points();
        let face = self.faces.face(f);
        if self.planar[f] {
            let (nh, k) = self.face_planes[f];
            let d = (k - nh.dot(&c)) * inv_r;
            if !(d.abs() < 1.0) {
                return Some(0.0);
            }
            poly.clear();
            let mut extent = 0.0f64;
            for &p in face {
                let q = to_unit(points[p as usize], c, inv_r);
                extent = extent.max(q.amax());
                poly.push(q);
            }
            let slots = self.faces.offsets()[f] as usize..self.faces.offsets()[f + 1] as usize;
            let axes = &self.edge_axes[slots];
            return polygon_cap_unit_axes(poly, axes, nh, d, TIE * (1.0 + extent));
        }
        let tri = |t: [V3; 3]| -> Option<f64> {
            let nrm = (t[1] - t[0]).cross(&(t[2] - t[0]));
            let m = nrm.norm();
            if !(m > 0.0) {
                return Some(0.0);
            }
            let nh = nrm / m;
            let u = t.map(|p| to_unit(p, c, inv_r));
            let d = u[0].dot(&nh);
            if !(d.abs() < 1.0) {
                return Some(0.0);
            }
            let extent = u.iter().map(|p| p.amax()).fold(0.0, f64::max);
            polygon_cap_unit(&u, nh, d, TIE * (1.0 + extent))
        };
        let p = |i: usize| points[face[i] as usize];
        if face.len() == 3 {
            return tri([p(0), p(1), p(2)]);
        }
        let apex = tets.face_apexes()[f];
        let n = face.len();
        let mut sum = 0.0;
        for i in 0..n {
            sum += tri([apex, p(i), p(if i + 1 == n { 0 } else { i + 1 })])?;
        }
        Some(sum)
    }

    /// The term of face `f` (owner orientation) in the volume of the cube of half-side `r`
    /// centred at `c` ∩ a cell ([`crate::clip`]), m³: over the polygon for planar faces, over
    /// its fan triangles (the boundary of the cells' tets) otherwise; coordinates relative to
    /// `c`.
    fn face_cube_flux(
        &self,
        f: usize,
        c: V3,
        r: f64,
        polygon: &mut Vec<V3>,
        clip: &mut ClipScratch,
    ) -> f64 {
        let tets = self.locator.tets();
        let points = tets.points();
        let face = self.faces.face(f);
        let (lo, hi) = (V3::from_element(-r), V3::from_element(r));
        polygon.clear();
        polygon.extend(face.iter().map(|&p| points[p as usize] - c));
        if self.planar[f] || face.len() == 3 {
            return box_polygon_flux(lo, hi, polygon, clip);
        }
        let apex = tets.face_apexes()[f] - c;
        let n = face.len();
        (0..n)
            .map(|i| {
                let tri = [
                    apex,
                    polygon[i],
                    polygon[if i + 1 == n { 0 } else { i + 1 }],
                ];
                box_polygon_flux(lo, hi, &tri, clip)
            })
            .sum()
    }

    /// True when a body centred at `c` lies in the kernel of `cell`: on the inner side of the
    /// plane of every fan triangle of its faces (of the whole face for planar faces) by at
    /// least its support `support(n)` along the plane's normal `n` (not normalised): r·|n| for
    /// a ball, r·(|n_x| + |n_y| + |n_z|) for the cube of half-side r. The kernel lies in the
    /// cell, so the body does too.
    fn body_in_cell(&self, cell: Label, c: V3, support: impl Fn(V3) -> f64) -> bool {
        let tets = self.locator.tets();
        let points = tets.points();
        let apexes = tets.face_apexes();
        for plane in self.planes_of(cell) {
            if plane.k.is_finite() {
                if !(-plane.outside(c) >= support(plane.n)) {
                    return false;
                }
                continue;
            }
            let f = plane.face as usize;
            let face = self.faces.face(f);
            let sign = if self.owner[f] == cell { 1.0 } else { -1.0 };
            let inside = |a: V3, nrm: V3| sign * (a - c).dot(&nrm) >= support(nrm);
            let p = |i: usize| points[face[i] as usize];
            let tri = |a: V3, b: V3, d: V3| (b - a).cross(&(d - a));
            let n = face.len();
            if n == 3 {
                if !inside(p(0), tri(p(0), p(1), p(2))) {
                    return false;
                }
                continue;
            }
            for i in 0..n {
                let q = p(if i + 1 == n { 0 } else { i + 1 });
                if !inside(apexes[f], tri(apexes[f], p(i), q)) {
                    return false;
                }
            }
        }
        true
    }

    /// The face planes of `cell` ([`CellPlane`]).
    #[inline]
    fn planes_of(&self, cell: Label) -> &[CellPlane] {
        let i = cell as usize;
        &self.cell_planes[self.cell_plane_start[i] as usize..self.cell_plane_start[i + 1] as usize]
    }

    /// True when every point of `cell` lies in the ball (centre `c`, radius `r`), hence the
    /// whole cell (its tets' other vertices, face and cell centres, are averages of its points).
    fn cell_in_ball(&self, cell: Label, c: V3, r: f64) -> bool {
        let points = self.locator.tets().points();
        self.locator.tets().cell_faces(cell).iter().all(|&f| {
            self.faces
                .face(f as usize)
                .iter()
                .all(|&p| (points[p as usize] - c).norm_squared() <= r * r)
        })
    }

    /// [`VoidageMesh::body_in_cell`] for the ball of radius `r`.
    fn ball_in_cell(&self, cell: Label, c: V3, r: f64) -> bool {
        self.body_in_cell(cell, c, |n| r * n.norm())
    }

    fn general_exact(&self, b: Ball, s: &mut Scratch, out: &mut Vec<(Label, f64)>) -> f64 {
        let Ball { c, r, v, cell } = b;
        if let Some(c0) = cell {
            // A cell of planar faces needs no kernel test: its face planes all miss a ball in
            // its kernel, so the walk below visits it alone and adds no term.
            let planar = self.planes_of(c0).iter().all(|p| p.k.is_finite());
            if !planar && self.ball_in_cell(c0, c, r) {
                out.push((c0, v));
                return 0.0;
            }
        }
        let q = Query {
            lo: c.map(|x| x - r),
            hi: c.map(|x| x + r),
            ball: Some((c, r)),
        };
        let start = out.len();
        s.faces.clear();
        let caps = match cell {
            Some(c0) => match self.exact_walk(b, c0, s, out) {
                CapWalk::Done(outside) => return outside,
                CapWalk::Incomplete => true,
                CapWalk::Tie => false,
            },
            None => true,
        };
        out.truncate(start);
        self.candidates(&q, cell, s);
        if caps {
            if let Some(outside) = self.exact_shares(b, true, s, out) {
                return outside;
            }
            out.truncate(start);
        }
        s.faces.clear();
        self.exact_shares(b, false, s, out)
            .expect("the flux form has a value for every face")
    }

    /// The exact shares in the cap form by a walk from the centre's cell `c0` across the faces
    /// that meet the ball (nonzero cap term): for a ball that crosses no boundary face every
    /// cell it meets is reached this way (the segment from the centre to any point of the ball
    /// in the mesh crosses only faces meeting the ball), and only those cells are visited.
    fn exact_walk(
        &self,
        b: Ball,
        c0: Label,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> CapWalk {
        let Ball { c, r, v, .. } = b;
        let r3 = r * r * r;
        s.visited.clear();
        s.queue.clear();
        s.queue.push(c0);
        s.visited.insert(c0, ());
        let mut sum = 0.0;
        while let Some(cell) = s.queue.pop() {
            let mut unit = 0.0;
            for plane in self.planes_of(cell) {
                if plane.outside(c).abs() >= r {
                    // The plane misses the ball: no term.
                    continue;
                }
                let f = plane.face;
                let term = match s.faces.get(f) {
                    Some(x) => x,
                    None => match self.face_cap_unit(f as usize, c, r, &mut s.polygon) {
                        Some(x) => {
                            s.faces.insert(f, x);
                            x
                        }
                        None => return CapWalk::Tie,
                    },
                };
                unit += if plane.own { term } else { -term };
                if term != 0.0 {
                    let next = plane.across;
                    if next == NO_CELL {
                        return CapWalk::Incomplete;
                    }
                    if s.visited.insert(next, ()) {
                        s.queue.push(next);
                    }
                }
            }
            let vol = self.cap_cell_volume(cell, c0 == cell, unit * r3, b);
            if vol > 0.0 {
                out.push((cell, vol));
                sum += vol;
            }
        }
        CapWalk::Done(v - sum)
    }

    /// The share of `cell` from its cap-form sum `caps` (m³; plus the ball if `centre_cell`),
    /// clamped to [0, min(cell volume, ball volume)], and exactly the cell volume for a cell
    /// inside the ball: the cap form adds the ball and takes the caps off, a rounding of order
    /// ulp(v) that the flux form's clamp at the cell volume removes.
    fn cap_cell_volume(&self, cell: Label, centre_cell: bool, caps: f64, b: Ball) -> f64 {
        let cv = self.geom.cell_volumes[cell as usize];
        let vol = if centre_cell { b.v + caps } else { caps };
        if vol >= cv - 1e-9 * b.v && self.cell_in_ball(cell, b.c, b.r) {
            cv
        } else {
            vol.clamp(0.0, cv.min(b.v))
        }
    }

    /// The exact shares of the candidate cells (module docs), in the cap form (`caps`: face
    /// terms [`VoidageMesh::face_cap_unit`] plus the whole ball for the centre's cell; `None`
    /// when a face cannot tell the side of the centre) or in the flux form
    /// ([`VoidageMesh::face_flux_unit`]), the face terms cached in `s.faces` (which must hold
    /// terms of the same form). Returns the volume outside the mesh.
    fn exact_shares(
        &self,
        b: Ball,
        caps: bool,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> Option<f64> {
        let Ball { c, r, v, cell: c0 } = b;
        let inv_r = 1.0 / r;
        let r3 = r * r * r;
        let tets = self.locator.tets();
        let mut sum = 0.0;
        for &cell in &s.candidates {
            let bb = &self.cell_bounds[cell as usize];
            let far: f64 = (0..3)
                .map(|a| interval_dist2(bb.min[a] - c[a], bb.max[a] - c[a]).1)
                .sum();
            let cv = self.geom.cell_volumes[cell as usize];
            let vol = if far <= r * r {
                cv
            } else {
                let mut unit = 0.0;
                for &f in tets.cell_faces(cell) {
                    let term = match s.faces.get(f) {
                        Some(x) => x,
                        None => {
                            let x = if caps {
                                self.face_cap_unit(f as usize, c, r, &mut s.polygon)?
                            } else {
                                self.face_flux_unit(f as usize, c, inv_r)
                            };
                            s.faces.insert(f, x);
                            x
                        }
                    };
                    unit += if self.owner[f as usize] == cell {
                        term
                    } else {
                        -term
                    };
                }
                if caps {
                    self.cap_cell_volume(cell, c0 == Some(cell), unit * r3, b)
                } else {
                    (unit * r3).clamp(0.0, cv.min(v))
                }
            };
            if vol > 0.0 {
                out.push((cell, vol));
                sum += vol;
            }
        }
        Some(v - sum)
    }

    fn general_cube(
        &self,
        b: Ball,
        corrected: bool,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> f64 {
        let Ball { c, r, v, cell } = b;
        if let Some(c0) = cell {
            let cube_support = |n: V3| r * (n[0].abs() + n[1].abs() + n[2].abs());
            if self.body_in_cell(c0, c, cube_support) {
                out.push((c0, v));
                return 0.0;
            }
        }
        let lo = c.map(|x| x - r);
        let hi = c.map(|x| x + r);
        let q = Query { lo, hi, ball: None };
        self.candidates(&q, cell, s);
        let cube = 8.0 * r * r * r;
        s.fractions.clear();
        s.faces.clear();
        let mut total = 0.0;
        for &cell in &s.candidates {
            let b = &self.cell_bounds[cell as usize];
            let cv = self.geom.cell_volumes[cell as usize];
            let vol = if (0..3).all(|a| b.min[a] >= lo[a] && b.max[a] <= hi[a]) {
                cv
            } else {
                let mut sum = 0.0;
                for &f in self.locator.tets().cell_faces(cell) {
                    let flux = match s.faces.get(f) {
                        Some(x) => x,
                        None => {
                            let x =
                                self.face_cube_flux(f as usize, c, r, &mut s.polygon, &mut s.clip);
                            s.faces.insert(f, x);
                            x
                        }
                    };
                    sum += if self.owner[f as usize] == cell {
                        flux
                    } else {
                        -flux
                    };
                }
                sum.clamp(0.0, cv)
            };
            let phi = (vol / cube).min(1.0);
            s.fractions.push(phi);
            total += phi;
        }
        let mut sum = 0.0;
        if corrected {
            let outside_piece = khawaja_correction((1.0 - total).clamp(0.0, 1.0));
            let mut wsum = outside_piece;
            for f in &mut s.fractions {
                *f = khawaja_correction(*f);
                wsum += *f;
            }
            let scale = if wsum > 0.0 { v / wsum } else { 0.0 };
            for (&cell, &w) in s.candidates.iter().zip(&s.fractions) {
                if w > 0.0 {
                    out.push((cell, w * scale));
                    sum += w * scale;
                }
            }
        } else {
            for (&cell, &phi) in s.candidates.iter().zip(&s.fractions) {
                if phi > 0.0 {
                    out.push((cell, phi * v));
                    sum += phi * v;
                }
            }
        }
        v - sum
    }
}

/// The index range [i0, i1] of the grid cells along `axis` overlapping [lo, hi] (lo < hi), or
/// `None` when the interval misses the grid.
fn axis_range(g: &AxisGrid, axis: usize, lo: f64, hi: f64) -> Option<(usize, usize)> {
    let pl = g.planes(axis);
    let n = pl.len() - 1;
    if hi <= pl[0] || lo >= pl[n] {
        return None;
    }
    let i0 = g.interval(axis, lo).unwrap_or(0);
    let i1 = match g.interval(axis, hi) {
        // A cell starting exactly at hi has no overlap.
        Some(i) if pl[i] == hi => i.saturating_sub(1).max(i0),
        Some(i) => i,
        None => n - 1,
    };
    Some((i0, i1))
}

/// Exact shares on an axis-aligned grid.
/// Counts one `divided` marker in cell `m` ((cell, count) in the order first met).
fn count_marker(markers: &mut Vec<(Label, u32)>, m: Label) {
    match markers.iter_mut().find(|(cell, _)| *cell == m) {
        Some(e) => e.1 += 1,
        None => markers.push((m, 1)),
    }
}

/// The shares of `divided`'s markers (cell, count), the centre's cell first: the whole volume
/// `v` when every marker is in one cell, else v/29 per marker.
fn push_markers(markers: &[(Label, u32)], v: f64, out: &mut Vec<(Label, f64)>) {
    if let [(m, _)] = markers[..] {
        // Every marker in one cell (no kernel test first: the centre's face distances, which
        // locate_near computes anyway, show most such particles at once).
        out.push((m, v));
        return;
    }
    let each = v / DIVIDED_MARKERS as f64;
    for &(m, k) in markers {
        out.push((m, k as f64 * each));
    }
}

fn grid_exact(g: &AxisGrid, b: Ball, s: &mut Scratch, out: &mut Vec<(Label, f64)>) -> f64 {
    let Ball { c, r, v, .. } = b;
    let mut first = [0usize; 3];
    let mut last = [0usize; 3];
    let mut whole = true;
    for a in 0..3 {
        let Some((i0, i1)) = axis_range(g, a, c[a] - r, c[a] + r) else {
            return v;
        };
        let pl = g.planes(a);
        whole &= i0 == i1 && pl[i0] <= c[a] - r && pl[i1 + 1] >= c[a] + r;
        first[a] = i0;
        last[a] = i1;
    }
    if whole {
        // The ball lies in one cell.
        out.push((g.cell(first[0], first[1], first[2]), v));
        return 0.0;
    }
    let inv = 1.0 / r;
    let r3 = r * r * r;
    // At most one plane inside the ball per axis and the ball inside the grid: the 8-piece form.
    let inside_grid = (0..3).all(|a| {
        let pl = g.planes(a);
        last[a] <= first[a] + 1 && pl[first[a]] <= c[a] - r && pl[last[a] + 1] >= c[a] + r
    });
    if inside_grid {
        let t: [Option<f64>; 3] = std::array::from_fn(|a| {
            (last[a] > first[a]).then(|| (g.planes(a)[last[a]] - c[a]) * inv)
        });
        let pieces = cut_ball_unit(t);
        let mut sum = 0.0;
        for (bits, &p) in pieces.iter().enumerate() {
            if p > 0.0 {
                let vol = p * r3;
                let (i, j, k) = (bits & 1, (bits >> 1) & 1, (bits >> 2) & 1);
                out.push((g.cell(first[0] + i, first[1] + j, first[2] + k), vol));
                sum += vol;
            }
        }
        return v - sum;
    }
    for a in 0..3 {
        s.planes[a].clear();
        let pl = &g.planes(a)[first[a]..=last[a] + 1];
        s.planes[a].extend(pl.iter().map(|&x| (x - c[a]) * inv));
    }
    sphere_grid_volumes(
        r3,
        [&s.planes[0], &s.planes[1], &s.planes[2]],
        &mut s.vols,
        &mut s.grid,
    );
    let n = [s.planes[0].len() - 1, s.planes[1].len() - 1];
    let mut sum = 0.0;
    for (idx, &vol) in s.vols.iter().enumerate() {
        if vol > 0.0 {
            let (i, j, k) = (idx % n[0], (idx / n[0]) % n[1], idx / (n[0] * n[1]));
            out.push((g.cell(first[0] + i, first[1] + j, first[2] + k), vol));
            sum += vol;
        }
    }
    v - sum
}

/// Cube and corrected-cube shares on an axis-aligned grid (module docs).
fn grid_cube(
    g: &AxisGrid,
    b: Ball,
    corrected: bool,
    s: &mut Scratch,
    out: &mut Vec<(Label, f64)>,
) -> f64 {
    let Ball { c, r, v, .. } = b;
    for (a, seg) in s.segments.iter_mut().enumerate() {
        seg.clear();
        let pl = g.planes(a);
        let n = pl.len() - 1;
        let (lo, hi) = (c[a] - r, c[a] + r);
        // The virtual cells beyond the grid (index None).
        let below = cube_axis_fraction(c[a], r, f64::NEG_INFINITY, pl[0]);
        let above = cube_axis_fraction(c[a], r, pl[n], f64::INFINITY);
        if below > 0.0 {
            seg.push((None, below));
        }
        if let Some((i0, i1)) = axis_range(g, a, lo, hi) {
            for i in i0..=i1 {
                let f = cube_axis_fraction(c[a], r, pl[i], pl[i + 1]);
                if f > 0.0 {
                    seg.push((Some(i), f));
                }
            }
        }
        if above > 0.0 {
            seg.push((None, above));
        }
    }
    let [sx, sy, sz] = &s.segments;
    let mut wsum = 0.0;
    if corrected {
        for &(_, fz) in sz {
            for &(_, fy) in sy {
                for &(_, fx) in sx {
                    wsum += khawaja_correction(fx * fy * fz);
                }
            }
        }
    }
    let scale = if corrected {
        if wsum > 0.0 {
            v / wsum
        } else {
            0.0
        }
    } else {
        v
    };
    let mut sum = 0.0;
    for &(k, fz) in sz {
        let Some(k) = k else { continue };
        for &(j, fy) in sy {
            let Some(j) = j else { continue };
            for &(i, fx) in sx {
                let Some(i) = i else { continue };
                let phi = fx * fy * fz;
                let w = if corrected {
                    khawaja_correction(phi)
                } else {
                    phi
                };
                let vol = w * scale;
                out.push((g.cell(i, j, k), vol));
                sum += vol;
            }
        }
    }
    v - sum
}

/// ε = 1 − solid / V per cell, clipped to `alpha_min` when given (module docs).
pub fn voidage_field(
    solid: &[f64],
    cell_volumes: &[f64],
    alpha_min: Option<f64>,
) -> Result<Voidage, VoidageError> {
    if let Some(a) = alpha_min {
        if !(a.is_finite() && (0.0..1.0).contains(&a)) {
            return Err(VoidageError::BadAlphaMin(a));
        }
    }
    if solid.len() != cell_volumes.len() {
        return Err(VoidageError::LengthMismatch {
            what: "solid volumes",
            expected: cell_volumes.len(),
            found: solid.len(),
        });
    }
    let mut res = Voidage {
        epsilon: Vec::with_capacity(solid.len()),
        alpha_min,
        clipped_volume: 0.0,
        clipped_cells: 0,
        min_epsilon: 1.0,
        negative_cells: 0,
    };
    for (&s, &vc) in solid.iter().zip(cell_volumes) {
        let mut e = 1.0 - s / vc;
        res.min_epsilon = res.min_epsilon.min(e);
        if e < 0.0 {
            res.negative_cells += 1;
        }
        if let Some(a) = alpha_min {
            if e < a {
                res.clipped_volume += (a - e) * vc;
                res.clipped_cells += 1;
                e = a;
            }
        }
        res.epsilon.push(e);
    }
    Ok(res)
}
