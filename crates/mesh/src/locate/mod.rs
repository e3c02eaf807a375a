//! Point location: which cell holds a point.
//!
//! The answer is defined by the tet decomposition of [`crate::tets`]: a point belongs to the cell
//! of the tet containing it, with the tie rule documented there (a point on a shared boundary
//! goes to the +x side, then +y, then +z; on an axis-aligned grid this is the half-open rule
//! [xᵢ, xᵢ₊₁) × [yⱼ, yⱼ₊₁) × [z_k, z_k₊₁); points outside the mesh give `None`).
//!
//! Strategy:
//! * **Axis-aligned tensor-product hex meshes** (blockMesh boxes, graded, multi-block as long as
//!   the planes line up) are detected at construction ([`AxisGrid::detect`]) and located by a
//!   per-axis search of the grid planes (arithmetic guess for near-uniform spacing, binary search
//!   otherwise), then the (i, j, k) → cell map.
//! * **General meshes**: a uniform bin grid over the bounding box gives a seed cell near the
//!   point; a tet-to-tet walk (visibility walk over the decomposition, crossing cell faces) moves
//!   to the tet holding the point. [`Locator::locate_from`] starts the walk at a hint cell instead
//!   (particles move little between coupling steps). If the walk leaves the mesh through a
//!   boundary face (non-convex domain, or outside) or does not settle, the cells whose bounding
//!   boxes overlap the point's bin are tested one by one.
//! * **Short cuts** that never change the answer: a point on the inner side of every face plane
//!   of a cell by more than the planes of its fan triangles can tilt away and the rounding is in
//!   that cell ([`Locator::cell_surely_holds`], tried on the start cell before any walk); one
//!   beyond a face plane by more than every vertex of the cell is not
//!   ([`Locator::cell_surely_lacks`], tried before a candidate's tets). Points around a located
//!   centre, such as a particle's marker points, are tested only against the face planes that
//!   pass near the centre ([`Locator::locate_near`]).
//!
//! The code: this module holds the [`Locator`] and its queries; `grid` the axis-aligned grid
//! ([`AxisGrid`]); `planes` the face-plane tests with their margins
//! ([`Locator::cell_surely_holds`], [`Locator::cell_surely_lacks`]); `bins` the bin index of
//! seed cells and candidate cells and the finer seed grid; `walk` the cell and tet walks and
//! the candidate search they fall back on; `near` [`Locator::locate_near`] with its clearance.

mod bins;
mod grid;
mod near;
mod planes;
mod walk;

pub use grid::AxisGrid;

use crate::error::MeshError;
use crate::geometry::{Aabb, MeshGeometry};
use crate::tets::TetDecomposition;
use crate::v3::V3;
use bins::{Bins, SeedGrid};
use foam::{Label, PolyMesh};
use planes::{cell_excess, CellFace, FaceCertainty};
use rayon::prelude::*;

/// Options for [`Locator::with_options`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LocatorOptions {
    /// Detect axis-aligned tensor-product hex meshes and locate on them by plane search
    /// (default true). With false every query takes the general path.
    pub axis_aligned_fast_path: bool,
}

impl Default for LocatorOptions {
    fn default() -> Self {
        Self {
            axis_aligned_fast_path: true,
        }
    }
}

/// Locates points in the cells of a polyMesh (see the module docs for the rule and strategy).
#[derive(Clone, Debug)]
pub struct Locator {
    tets: TetDecomposition,
    grid: Option<AxisGrid>,
    bins: Bins,
    /// Start cells, finer than the bins' seeds.
    seeds: SeedGrid,
    /// Faces whose points lie in one plane ([`Locator::face_is_planar`]).
    face_planar: Vec<bool>,
    /// Every cell's faces as its plane tests see them ([`CellFace`]), in the order of
    /// `tets.cell_faces` (cell i's from `cell_face_start[i]`): one 64-byte record per face
    /// instead of four arrays indexed by face, so a cell's tests read neighbouring memory.
    cell_faces: Vec<CellFace>,
    cell_face_start: Vec<u32>,
    /// Bounding box of every cell's points.
    cell_bounds: Vec<Aabb>,
    /// Per cell, how far beyond one of its face planes a vertex of its tets may lie, plus the
    /// certainty margin of those vertices ([`cell_excess`]); 0 up to rounding for convex cells.
    cell_excess: Vec<f64>,
    /// Per cell, whether every tet is positively oriented: then the tets fill the region the
    /// cell's fan triangles enclose, star-shaped about the cell apex, once.
    cell_star: Vec<bool>,
    /// Mesh bounds, enlarged slightly: points outside are outside the mesh.
    bounds: Aabb,
}

impl Locator {
    /// A locator with the default options (axis-aligned fast path on). The geometry must be
    /// that of `mesh` and every cell volume must be positive.
    pub fn new(mesh: &PolyMesh, geom: &MeshGeometry) -> Result<Self, MeshError> {
        Self::with_options(mesh, geom, LocatorOptions::default())
    }

    /// A locator with explicit options.
    pub fn with_options(
        mesh: &PolyMesh,
        geom: &MeshGeometry,
        options: LocatorOptions,
    ) -> Result<Self, MeshError> {
        geom.check_matches(mesh)?;
        geom.check_volumes()?;
        let tets = TetDecomposition::new(mesh, geom)?;
        let grid = if options.axis_aligned_fast_path {
            tets.axis_grid().cloned()
        } else {
            None
        };
        let b = geom.bounds;
        let pad: V3 = V3::from_fn(|a, _| 1e-9 * (b.max[a] - b.min[a]) + 1e-300);
        let bounds = Aabb {
            min: (b.min - pad),
            max: V3::from_fn(|a, _| b.max[a] + pad[a]),
        };
        let cell_bounds: Vec<Aabb> = (0..tets.n_cells() as Label)
            .into_par_iter()
            .with_min_len(1024)
            .map(|c| tets.cell_bounds(c))
            .collect();
        let bins = Bins::new(&tets, &bounds, &cell_bounds);
        let face_normals: Vec<V3> = geom
            .face_areas
            .par_iter()
            .with_min_len(4096)
            .map(|a| {
                let m = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                if m > 0.0 {
                    V3::new(a[0] / m, a[1] / m, a[2] / m)
                } else {
                    V3::zeros()
                }
            })
            .collect();
        let (face_certainty, face_planar): (Vec<FaceCertainty>, Vec<bool>) = (0..mesh.n_faces())
            .into_par_iter()
            .with_min_len(4096)
            .map(|f| FaceCertainty::of(&tets, f, face_normals[f]))
            .unzip();
        let cell_excess = (0..tets.n_cells() as Label)
            .into_par_iter()
            .with_min_len(1024)
            .map(|c| cell_excess(&tets, c, &face_normals, &face_certainty))
            .collect();
        let cell_star = (0..tets.n_cells() as Label)
            .into_par_iter()
            .with_min_len(1024)
            .map(|c| tets.cell_tets(c).all(|t| t.volume() > 0.0))
            .collect();
        let (cell_faces, cell_face_start) = CellFace::table(&tets, &face_normals, &face_certainty);
        let mut locator = Self {
            tets,
            grid,
            bins,
            seeds: SeedGrid::empty(),
            face_planar,
            cell_faces,
            cell_face_start,
            cell_bounds,
            cell_excess,
            cell_star,
            bounds,
        };
        if locator.grid.is_none() {
            locator.place_seeds();
        }
        Ok(locator)
    }

    /// The axis-aligned grid, when the mesh is one and the fast path is enabled.
    pub fn axis_grid(&self) -> Option<&AxisGrid> {
        self.grid.as_ref()
    }

    /// The tet decomposition the locator works on.
    pub fn tets(&self) -> &TetDecomposition {
        &self.tets
    }

    /// True when the points of face `face` lie in one plane, within 1e-12 of the face size (the
    /// largest distance of a point from the fan apex) of the plane through the fan apex normal
    /// to OpenFOAM's area vector. Such a face's fan triangles and its polygon are the same
    /// region up to rounding.
    #[inline]
    pub fn face_is_planar(&self, face: Label) -> bool {
        self.face_planar[face as usize]
    }

    /// Bounding box of every cell's points (the tet decomposition's points), m.
    pub fn cell_bounds(&self) -> &[Aabb] {
        &self.cell_bounds
    }

    /// The cell holding `p`, `None` outside the mesh.
    #[inline]
    pub fn locate(&self, p: V3) -> Option<Label> {
        if let Some(g) = &self.grid {
            return g.locate(p);
        }
        if !self.bounds.contains(p) {
            return None;
        }
        self.walk_or_search(p, self.seeds.seed(p))
    }

    /// The cell holding `p`, searching from cell `hint` first (e.g. the particle's cell at the
    /// previous step). Same answer as [`Locator::locate`]; faster when `hint` is at or near the
    /// answer. A `hint` that is not a cell index is ignored.
    #[inline]
    pub fn locate_from(&self, p: V3, hint: Label) -> Option<Label> {
        if hint as usize >= self.tets.n_cells() {
            return self.locate(p);
        }
        if let Some(g) = &self.grid {
            if g.cell_holds(hint, p) {
                return Some(hint);
            }
            return g.locate(p);
        }
        if !self.bounds.contains(p) {
            return None;
        }
        self.walk_or_search(p, hint)
    }

    /// [`Locator::locate`] for every point, in parallel.
    pub fn locate_all(&self, points: &[V3]) -> Vec<Option<Label>> {
        points
            .par_iter()
            .with_min_len(512)
            .map(|&p| self.locate(p))
            .collect()
    }

    /// [`Locator::locate_from`] for every point, in parallel: `cells[i]` is the hint for
    /// `points[i]` on entry (`None`: no hint) and the answer on return.
    pub fn locate_all_from(&self, points: &[V3], cells: &mut [Option<Label>]) {
        assert_eq!(points.len(), cells.len(), "one cell slot per point");
        cells
            .par_iter_mut()
            .zip(points.par_iter())
            .with_min_len(512)
            .for_each(|(c, &p)| {
                *c = match *c {
                    Some(h) => self.locate_from(p, h),
                    None => self.locate(p),
                }
            });
    }

    /// The cell holding `p` by the general path only (tet walk from the bin seed, then candidate
    /// search), ignoring the axis-aligned grid.
    pub fn locate_general(&self, p: V3) -> Option<Label> {
        if !self.bounds.contains(p) {
            return None;
        }
        self.walk_or_search(p, self.seeds.seed(p))
    }
}

impl foam::HeapBytes for Locator {
    /// Its tetrahedra (an own copy of the mesh's points, faces and addressing), grid, bins and
    /// per-cell plane records.
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        self.tets.heap_bytes()
            + self.grid.heap_bytes()
            + self.bins.heap_bytes()
            + self.seeds.heap_bytes()
            + flat(&self.face_planar)
            + flat(&self.cell_faces)
            + flat(&self.cell_face_start)
            + flat(&self.cell_bounds)
            + flat(&self.cell_excess)
            + flat(&self.cell_star)
    }
}
