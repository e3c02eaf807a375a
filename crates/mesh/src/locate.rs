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

use crate::error::MeshError;
use crate::geometry::{Aabb, MeshGeometry};
use crate::nearest::face_distance;
use crate::tets::{tet_sides, TetDecomposition, TetId};
use crate::v3::V3;
use foam::{Label, PolyMesh};
use rayon::prelude::*;
use std::collections::VecDeque;

/// Walk steps before the walk switches from greedy to randomised exit choice.
const GREEDY_STEPS: usize = 512;
/// Walk steps before giving up and testing candidate cells.
const MAX_STEPS: usize = 8192;
/// A face is planar when its points lie within this fraction of its size (largest distance of a
/// point from the fan apex) of the plane through the apex normal to the area vector.
const PLANAR_WARP: f64 = 1e-12;

/// How far the planes of a face's fan triangles can be from the face plane P (through the fan
/// apex a, unit normal n̂): a fan triangle's plane through its vertex v with unit normal n_t is
/// at signed distance (x − a)·n̂ + (x − a)·(n_t − n̂) + (a − v)·n_t from P's, so by at most
/// `tilt`·|x − a|₁ + `offset`, with `tilt` = max |n_t − n̂|∞ and `offset` = max |(a − v)·n_t|
/// (degenerate triangles, which bound no tet, are skipped); `offset` also holds the rounding of
/// p − a.
#[derive(Clone, Copy, Debug)]
struct FaceCertainty {
    tilt: f64,
    offset: f64,
}

impl FaceCertainty {
    /// The margin at x − a = `x`, for points up to `reach` (L1) farther from the apex; it also
    /// covers the rounding of the distance (1e-12 of |x − a|₁).
    #[inline]
    fn margin(&self, x: V3, reach: f64) -> f64 {
        let l1 = x.abs().sum() + reach;
        self.tilt * l1 + self.offset + 1e-12 * l1
    }

    /// The bounds of face `f` and whether it is planar ([`Locator::face_is_planar`]).
    fn of(tets: &TetDecomposition, f: usize, n: V3) -> (FaceCertainty, bool) {
        let face = tets.faces.face(f);
        let apex = tets.face_apex[f];
        let p = |i: usize| tets.points[face[i] as usize];
        let (mut warp, mut size) = (0.0f64, 0.0f64);
        for i in 0..face.len() {
            let d = p(i) - apex;
            warp = warp.max(d.dot(&n).abs());
            size = size.max(d.norm());
        }
        let planar = n != V3::zeros() && warp <= PLANAR_WARP * size;
        let mut c = FaceCertainty {
            tilt: 0.0,
            offset: 0.0,
        };
        let mut add = |t: [V3; 3]| {
            let nt = (t[1] - t[0]).cross(&(t[2] - t[0]));
            let m = nt.norm();
            if m > 0.0 {
                let nt = nt / m;
                c.tilt = c.tilt.max((nt - n).amax());
                c.offset = c.offset.max((apex - t[0]).dot(&nt).abs());
            }
        };
        if n == V3::zeros() {
            c.tilt = f64::INFINITY;
        } else if face.len() == 3 {
            add([p(0), p(1), p(2)]);
        } else {
            for i in 0..face.len() {
                add([apex, p(i), p((i + 1) % face.len())]);
            }
        }
        // The rounding of p − a relative to the magnitude of a.
        c.offset += 1e-14 * apex.abs().sum();
        (c, planar)
    }
}

/// A face of a cell for the cell's plane tests: the unit normal out of the cell, the fan apex
/// and the face's [`FaceCertainty`].
#[derive(Clone, Copy, Debug)]
struct CellFace {
    n: V3,
    apex: V3,
    certainty: FaceCertainty,
}

impl CellFace {
    /// The signed distance of `p` from the face plane, positive outside the cell, and the
    /// margin by which its fan triangles' planes may differ there (points up to `reach`
    /// farther from the apex, L1).
    #[inline]
    fn outward_distance(&self, p: V3, reach: f64) -> (f64, f64) {
        let x = p - self.apex;
        (x.dot(&self.n), self.certainty.margin(x, reach))
    }
}

/// Most near faces [`Locator::locate_near`] keeps in one call (of the centre's cell and the
/// cells across its faces): a cell with more faces is not tested by near faces.
const NEAR_MAX: usize = 32;

/// No cell.
const NO_LABEL: Label = Label::MAX;

/// A face of a cell whose plane passes near a centre ([`Locator::locate_near`]): outward unit
/// normal, signed distance of the centre (positive outside), certainty margin over the ball
/// around the centre, face label.
#[derive(Clone, Copy, Debug, Default)]
struct NearFace {
    normal: V3,
    d: f64,
    margin: f64,
    face: usize,
}

impl NearFace {
    /// How far the point centre + `scale`·`o` may lie beyond the face's fan triangles
    /// (negative: surely on the inner side).
    #[inline]
    fn excess(&self, scale: f64, o: &V3) -> f64 {
        self.d + scale * o.dot(&self.normal) + self.margin
    }
}

/// An axis-aligned tensor-product grid of hexahedral cells.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisGrid {
    planes: [Vec<f64>; 3],
    /// Cell of grid slot i + nx(j + ny k).
    cells: Vec<Label>,
    /// Grid slot of each cell.
    slots: Vec<u32>,
    /// (origin, 1/spacing) per axis when the planes are nearly uniform.
    uniform: [Option<(f64, f64)>; 3],
}

impl AxisGrid {
    /// Detects whether every cell of `mesh` is an axis-aligned box and the cells form a
    /// tensor-product grid; `None` otherwise. See [`AxisGrid::detect_snapped`].
    pub fn detect(mesh: &PolyMesh) -> Option<AxisGrid> {
        Self::detect_snapped(mesh).map(|(g, _)| g)
    }

    /// Detection, also returning the mesh points moved exactly onto the grid planes.
    ///
    /// blockMesh computes the points of graded and multi-block meshes by interpolation, so points
    /// meant to share a plane differ by a few ulps. Along each axis the point coordinates are
    /// therefore clustered: sorted values closer than 1e-10 × (axis extent) form one plane,
    /// whose coordinate is the median of the cluster. The mesh is a grid when every cell has six
    /// quadrilateral faces, each on one plane, and eight distinct points on the eight corners of
    /// the box between consecutive planes i, i+1 along each axis; when nx·ny·nz equals the number
    /// of cells; and when every (i, j, k) slot holds exactly one cell.
    pub fn detect_snapped(mesh: &PolyMesh) -> Option<(AxisGrid, Vec<V3>)> {
        if mesh.n_cells == 0 || mesh.check().is_err() || mesh.points.is_empty() {
            return None;
        }
        let mut planes: [Vec<f64>; 3] = Default::default();
        let mut ranges: [Vec<(f64, f64)>; 3] = Default::default();
        for a in 0..3 {
            let mut v: Vec<f64> = mesh.points.iter().map(|p| p[a]).collect();
            if v.iter().any(|x| !x.is_finite()) {
                return None;
            }
            v.par_sort_unstable_by(f64::total_cmp);
            let tol = 1e-10 * (v[v.len() - 1] - v[0]);
            let mut start = 0;
            for i in 1..=v.len() {
                if i == v.len() || v[i] - v[i - 1] > tol {
                    if v[i - 1] - v[start] > tol {
                        return None;
                    }
                    ranges[a].push((v[start], v[i - 1]));
                    planes[a].push(v[start + (i - 1 - start) / 2]);
                    start = i;
                }
            }
            if planes[a].len() < 2 {
                return None;
            }
        }
        let plane_of =
            |a: usize, x: f64| -> u32 { (ranges[a].partition_point(|r| r.0 <= x) - 1) as u32 };
        let ijk: Vec<[u32; 3]> = mesh
            .points
            .par_iter()
            .with_min_len(4096)
            .map(|p| std::array::from_fn(|a| plane_of(a, p[a])))
            .collect();
        let cell_faces = mesh.cell_faces();
        let lower: Option<Vec<[u32; 3]>> = (0..mesh.n_cells)
            .into_par_iter()
            .with_min_len(1024)
            .map(|c| cell_box(mesh, cell_faces.face(c), &ijk))
            .collect();
        let lower = lower?;
        let n = [
            planes[0].len() - 1,
            planes[1].len() - 1,
            planes[2].len() - 1,
        ];
        if n[0].checked_mul(n[1])?.checked_mul(n[2])? != mesh.n_cells {
            return None;
        }
        let mut cells = vec![Label::MAX; mesh.n_cells];
        let mut slots = vec![0u32; mesh.n_cells];
        for (c, l) in lower.iter().enumerate() {
            let slot = l[0] as usize + n[0] * (l[1] as usize + n[1] * l[2] as usize);
            if cells[slot] != Label::MAX {
                return None;
            }
            cells[slot] = c as Label;
            slots[c] = slot as u32;
        }
        let snapped = ijk
            .iter()
            .map(|q| V3::from_fn(|a, _| planes[a][q[a] as usize]))
            .collect();
        let uniform = std::array::from_fn(|a| uniform_spacing(&planes[a]));
        Some((
            AxisGrid {
                planes,
                cells,
                slots,
                uniform,
            },
            snapped,
        ))
    }

    /// The sorted plane coordinates along `axis` (0 = x, 1 = y, 2 = z), m; `dims()[axis] + 1`
    /// values.
    pub fn planes(&self, axis: usize) -> &[f64] {
        &self.planes[axis]
    }

    /// Number of cells along each axis (nx, ny, nz).
    pub fn dims(&self) -> [usize; 3] {
        std::array::from_fn(|a| self.planes[a].len() - 1)
    }

    /// The cell in slot (i, j, k), i.e. the box [xᵢ, xᵢ₊₁] × [yⱼ, yⱼ₊₁] × [z_k, z_k₊₁].
    /// Panics if an index is not below [`AxisGrid::dims`].
    pub fn cell(&self, i: usize, j: usize, k: usize) -> Label {
        let [nx, ny, _] = self.dims();
        self.cells[i + nx * (j + ny * k)]
    }

    /// The cell of every slot, slot i + nx(j + ny k).
    pub fn cells(&self) -> &[Label] {
        &self.cells
    }

    /// The slot (i, j, k) of cell `cell`.
    pub fn ijk(&self, cell: Label) -> [usize; 3] {
        let [nx, ny, _] = self.dims();
        let s = self.slots[cell as usize] as usize;
        [s % nx, (s / nx) % ny, s / (nx * ny)]
    }

    /// The interval index i with `planes[i] ≤ x < planes[i+1]` along `axis`, `None` outside
    /// `[planes[0], planes[n])` or for NaN.
    #[inline]
    pub fn interval(&self, axis: usize, x: f64) -> Option<usize> {
        let pl = &self.planes[axis];
        let n = pl.len() - 1;
        if !(x >= pl[0] && x < pl[n]) {
            return None;
        }
        let mut i = match self.uniform[axis] {
            Some((x0, inv)) => (((x - x0) * inv) as usize).min(n - 1),
            None => pl.partition_point(|&v| v <= x) - 1,
        };
        while pl[i] > x {
            i -= 1;
        }
        while pl[i + 1] <= x {
            i += 1;
        }
        Some(i)
    }

    /// The cell holding `p` by the half-open rule, `None` outside the grid.
    #[inline]
    pub fn locate(&self, p: V3) -> Option<Label> {
        let i = self.interval(0, p[0])?;
        let j = self.interval(1, p[1])?;
        let k = self.interval(2, p[2])?;
        Some(self.cell(i, j, k))
    }

    /// True when the box of cell `cell` holds `p` by the half-open rule.
    #[inline]
    pub fn cell_holds(&self, cell: Label, p: V3) -> bool {
        let ijk = self.ijk(cell);
        (0..3).all(|a| p[a] >= self.planes[a][ijk[a]] && p[a] < self.planes[a][ijk[a] + 1])
    }
}

/// The lower plane indices (i, j, k) of one cell if it is an axis-aligned hexahedron, given the
/// plane indices `ijk` of every point.
fn cell_box(mesh: &PolyMesh, faces: &[Label], ijk: &[[u32; 3]]) -> Option<[u32; 3]> {
    if faces.len() != 6 {
        return None;
    }
    let mut lo = [u32::MAX; 3];
    let mut hi = [0u32; 3];
    let mut labels = [Label::MAX; 24];
    let mut n = 0;
    for &f in faces {
        let face = mesh.faces.face(f as usize);
        if face.len() != 4 {
            return None;
        }
        let q0 = ijk[face[0] as usize];
        if !(0..3).any(|a| face.iter().all(|&q| ijk[q as usize][a] == q0[a])) {
            return None;
        }
        for &q in face {
            for a in 0..3 {
                lo[a] = lo[a].min(ijk[q as usize][a]);
                hi[a] = hi[a].max(ijk[q as usize][a]);
            }
            labels[n] = q;
            n += 1;
        }
    }
    if (0..3).any(|a| hi[a] != lo[a] + 1) {
        return None;
    }
    labels.sort_unstable();
    let mut corners_seen = 0u8;
    let mut distinct = 0;
    for (i, &q) in labels.iter().enumerate() {
        if i > 0 && labels[i - 1] == q {
            continue;
        }
        distinct += 1;
        let corner = (0..3).fold(0u8, |m, a| m | (((ijk[q as usize][a] - lo[a]) as u8) << a));
        if corners_seen & (1 << corner) != 0 {
            return None;
        }
        corners_seen |= 1 << corner;
    }
    (distinct == 8).then_some(lo)
}

/// (origin, 1/spacing) if every plane is within a quarter spacing of the uniform position.
fn uniform_spacing(pl: &[f64]) -> Option<(f64, f64)> {
    let n = pl.len() - 1;
    let h = (pl[n] - pl[0]) / n as f64;
    let ok = pl
        .iter()
        .enumerate()
        .all(|(i, &x)| (x - (pl[0] + h * i as f64)).abs() <= 0.25 * h);
    (ok && h > 0.0).then(|| (pl[0], 1.0 / h))
}

/// How far a vertex of the tets of cell `c` (mesh points, fan apexes, the cell apex) lies
/// beyond the plane of one of the cell's faces, at most, plus the margin by which a fan
/// triangle's plane may differ from the face plane at that vertex ([`FaceCertainty`]). A point
/// beyond a face plane by more than this and its own margin is beyond a fan triangle's plane
/// farther than every vertex, so outside the convex hull of the tets, so outside the cell
/// ([`Locator::cell_surely_lacks`]).
fn cell_excess(
    tets: &TetDecomposition,
    c: Label,
    normals: &[V3],
    certainty: &[FaceCertainty],
) -> f64 {
    let faces = tets.cell_faces(c);
    let mut excess = 0.0f64;
    for &f in faces {
        let f = f as usize;
        let apex = tets.face_apex[f];
        let n = if tets.owner[f] == c {
            normals[f]
        } else {
            -normals[f]
        };
        let fc = certainty[f];
        if !fc.tilt.is_finite() {
            return f64::INFINITY;
        }
        let mut beyond = |v: V3| {
            let x = v - apex;
            excess = excess.max(x.dot(&n) + fc.margin(x, 0.0));
        };
        beyond(tets.cell_apex[c as usize]);
        for &g in faces {
            beyond(tets.face_apex[g as usize]);
            for &q in tets.faces.face(g as usize) {
                beyond(tets.points[q as usize]);
            }
        }
    }
    excess
}

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

/// Uniform bin grid over the mesh bounding box: a seed cell per bin and, per bin, the cells whose
/// bounding boxes overlap it.
#[derive(Clone, Debug)]
struct Bins {
    origin: V3,
    inv: V3,
    dims: [usize; 3],
    seeds: Vec<Label>,
    offsets: Vec<u32>,
    cells: Vec<Label>,
}

impl Bins {
    fn new(tets: &TetDecomposition, bounds: &Aabb, cell_bounds: &[Aabb]) -> Bins {
        let n_cells = tets.n_cells();
        let ext = bounds.extent();
        let vol: f64 = ext.iter().map(|e| e.max(1e-300)).product();
        let mut h = (vol / n_cells as f64).cbrt();
        let mut dims = [1usize; 3];
        for _ in 0..64 {
            dims = std::array::from_fn(|a| ((ext[a] / h).ceil() as usize).clamp(1, 4096));
            if dims.iter().product::<usize>() <= 2 * n_cells + 64 {
                break;
            }
            h *= 1.26;
        }
        let inv = V3::from_fn(|a, _| {
            if ext[a] > 0.0 {
                dims[a] as f64 / ext[a]
            } else {
                0.0
            }
        });
        let mut bins = Bins {
            origin: bounds.min,
            inv,
            dims,
            seeds: Vec::new(),
            offsets: Vec::new(),
            cells: Vec::new(),
        };
        let n_bins: usize = dims.iter().product();
        // Candidate lists from cell bounding boxes (slightly enlarged against rounding).
        let ranges: Vec<([usize; 3], [usize; 3])> = cell_bounds
            .par_iter()
            .with_min_len(1024)
            .map(|b| {
                let pad: V3 = V3::from_fn(|a, _| 1e-9 * (b.max[a] - b.min[a]) + 1e-300);
                (
                    bins.bin_of(b.min - pad),
                    bins.bin_of(V3::from_fn(|a, _| b.max[a] + pad[a])),
                )
            })
            .collect();
        let mut counts = vec![0u32; n_bins + 1];
        let for_each_bin = |(lo, hi): &([usize; 3], [usize; 3]), f: &mut dyn FnMut(usize)| {
            for k in lo[2]..=hi[2] {
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        f(i + dims[0] * (j + dims[1] * k));
                    }
                }
            }
        };
        for r in &ranges {
            for_each_bin(r, &mut |b| counts[b + 1] += 1);
        }
        for b in 0..n_bins {
            counts[b + 1] += counts[b];
        }
        let mut fill = counts.clone();
        let mut cells = vec![0 as Label; counts[n_bins] as usize];
        for (c, r) in ranges.iter().enumerate() {
            for_each_bin(r, &mut |b| {
                cells[fill[b] as usize] = c as Label;
                fill[b] += 1;
            });
        }
        // Seeds: a cell whose apex lies in the bin, spread to empty bins breadth-first.
        let mut seeds = vec![Label::MAX; n_bins];
        let mut queue = VecDeque::new();
        for (c, apex) in tets.cell_apexes().iter().enumerate() {
            let b = bins.index(bins.bin_of(*apex));
            if seeds[b] == Label::MAX {
                seeds[b] = c as Label;
                queue.push_back(b);
            }
        }
        while let Some(b) = queue.pop_front() {
            let (i, j, k) = (
                b % dims[0],
                (b / dims[0]) % dims[1],
                b / (dims[0] * dims[1]),
            );
            let mut visit = |i: usize, j: usize, k: usize| {
                let nb = i + dims[0] * (j + dims[1] * k);
                if seeds[nb] == Label::MAX {
                    seeds[nb] = seeds[b];
                    queue.push_back(nb);
                }
            };
            if i > 0 {
                visit(i - 1, j, k);
            }
            if i + 1 < dims[0] {
                visit(i + 1, j, k);
            }
            if j > 0 {
                visit(i, j - 1, k);
            }
            if j + 1 < dims[1] {
                visit(i, j + 1, k);
            }
            if k > 0 {
                visit(i, j, k - 1);
            }
            if k + 1 < dims[2] {
                visit(i, j, k + 1);
            }
        }
        bins.seeds = seeds;
        bins.offsets = counts;
        bins.cells = cells;
        bins
    }

    #[inline]
    fn bin_of(&self, p: V3) -> [usize; 3] {
        std::array::from_fn(|a| {
            let t = (p[a] - self.origin[a]) * self.inv[a];
            if t >= 0.0 {
                (t as usize).min(self.dims[a] - 1)
            } else {
                0
            }
        })
    }

    #[inline]
    fn index(&self, b: [usize; 3]) -> usize {
        b[0] + self.dims[0] * (b[1] + self.dims[1] * b[2])
    }

    #[inline]
    fn seed(&self, p: V3) -> Label {
        self.seeds[self.index(self.bin_of(p))]
    }

    #[inline]
    fn candidates(&self, p: V3) -> &[Label] {
        let b = self.index(self.bin_of(p));
        &self.cells[self.offsets[b] as usize..self.offsets[b + 1] as usize]
    }
}

/// A uniform grid of start cells for point location, twice as fine per axis as [`Bins`]: the
/// cell holding each bin's centre (where there is one), so that most points lie in their bin's
/// seed and are located by one [`Locator::cell_surely_holds`] (measured on the Ergun O-grid:
/// locating from the coarse bins' seeds cost 12 % of the exact voidage benchmark).
#[derive(Clone, Debug)]
struct SeedGrid {
    origin: V3,
    inv: V3,
    dims: [usize; 3],
    seeds: Vec<Label>,
}

impl SeedGrid {
    /// An empty grid (axis-aligned meshes locate by their planes).
    fn empty() -> SeedGrid {
        SeedGrid {
            origin: V3::zeros(),
            inv: V3::zeros(),
            dims: [1; 3],
            seeds: Vec::new(),
        }
    }

    /// The grid over the bins' box, `seed(centre)` the start cell of a bin with centre
    /// `centre`.
    fn new(bins: &Bins, seed: impl Fn(V3) -> Label + Sync) -> SeedGrid {
        let dims = std::array::from_fn(|a| {
            if bins.inv[a] > 0.0 {
                2 * bins.dims[a]
            } else {
                1
            }
        });
        let inv = 2.0 * bins.inv;
        let mut g = SeedGrid {
            origin: bins.origin,
            inv,
            dims,
            seeds: Vec::new(),
        };
        g.seeds = (0..dims.iter().product::<usize>())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let ijk = [
                    i % dims[0],
                    (i / dims[0]) % dims[1],
                    i / (dims[0] * dims[1]),
                ];
                seed(V3::from_fn(|a, _| {
                    if inv[a] > 0.0 {
                        g.origin[a] + (ijk[a] as f64 + 0.5) / inv[a]
                    } else {
                        g.origin[a]
                    }
                }))
            })
            .collect();
        g
    }

    #[inline]
    fn seed(&self, p: V3) -> Label {
        let b: [usize; 3] = std::array::from_fn(|a| {
            let t = (p[a] - self.origin[a]) * self.inv[a];
            if t >= 0.0 {
                (t as usize).min(self.dims[a] - 1)
            } else {
                0
            }
        });
        self.seeds[b[0] + self.dims[0] * (b[1] + self.dims[1] * b[2])]
    }
}

/// Result of a tet walk.
enum Walk {
    Found(TetId),
    /// Left the mesh through a boundary face, did not settle, or met a non-manifold edge.
    Lost,
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
        let mut cell_faces = Vec::new();
        let mut cell_face_start = Vec::with_capacity(tets.n_cells() + 1);
        for c in 0..tets.n_cells() as Label {
            cell_face_start.push(cell_faces.len() as u32);
            for &f in tets.cell_faces(c) {
                let f = f as usize;
                // −(x·n) = x·(−n) exactly: the same distances as from the owner's normal.
                let n = if tets.owner[f] == c {
                    face_normals[f]
                } else {
                    -face_normals[f]
                };
                cell_faces.push(CellFace {
                    n,
                    apex: tets.face_apex[f],
                    certainty: face_certainty[f],
                });
            }
        }
        cell_face_start.push(cell_faces.len() as u32);
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
            // Seeds that hold their bin's centre, where there is one: a walk from there is short.
            let b = &locator.bins;
            let seeds = (0..b.seeds.len())
                .into_par_iter()
                .with_min_len(256)
                .map(|i| {
                    let ijk = [
                        i % b.dims[0],
                        (i / b.dims[0]) % b.dims[1],
                        i / (b.dims[0] * b.dims[1]),
                    ];
                    let centre = V3::from_fn(|a, _| {
                        let inv = b.inv[a];
                        if inv > 0.0 {
                            b.origin[a] + (ijk[a] as f64 + 0.5) / inv
                        } else {
                            b.origin[a]
                        }
                    });
                    locator
                        .walk_or_search(centre, b.seeds[i])
                        .unwrap_or(b.seeds[i])
                })
                .collect();
            locator.bins.seeds = seeds;
            let fine = SeedGrid::new(&locator.bins, |centre| {
                let coarse = locator.bins.seed(centre);
                locator.walk_or_search(centre, coarse).unwrap_or(coarse)
            });
            locator.seeds = fine;
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

    /// True when `p` lies in cell `cell` beyond doubt: on the inner side of the plane of every
    /// fan triangle of its faces, tested on the face planes (six dot products for a hexahedron)
    /// with a margin for how far the fan triangles' planes tilt from them and for rounding;
    /// hence in the kernel of the cell, hence in the cell under any tie rule. False says
    /// nothing.
    #[inline]
    pub fn cell_surely_holds(&self, cell: Label, p: V3) -> bool {
        self.faces_of(cell).iter().all(|cf| {
            let (d, margin) = cf.outward_distance(p, 0.0);
            d + margin < 0.0
        })
    }

    /// The faces of `cell` ([`CellFace`]), in the order of its faces in the tets.
    #[inline]
    fn faces_of(&self, cell: Label) -> &[CellFace] {
        let i = cell as usize;
        &self.cell_faces[self.cell_face_start[i] as usize..self.cell_face_start[i + 1] as usize]
    }

    /// True when `p` lies outside cell `cell` beyond doubt: outside its bounding box, or beyond
    /// one of its face planes by more than any vertex of its tets, the tilt of its fan
    /// triangles' planes and the rounding. False says nothing.
    #[inline]
    pub fn cell_surely_lacks(&self, cell: Label, p: V3) -> bool {
        if !self.cell_bounds[cell as usize].contains(p) {
            return true;
        }
        let excess = self.cell_excess[cell as usize];
        self.faces_of(cell).iter().any(|cf| {
            let (d, margin) = cf.outward_distance(p, 0.0);
            d - margin > excess
        })
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

    /// The cells holding the points `offsets` × `scale` + `centre`, each point within
    /// `radius` of `centre`, which lies in cell `cell` (e.g. the marker points of a particle):
    /// `f(i, cell)` for the i-th point, with the answers of [`Locator::locate`]. The distances of
    /// `centre` from the cell's face planes are computed once; a point is then tested only
    /// against the faces whose planes come within `radius` of `centre`, and is given `cell`
    /// when it lies on their inner side by more than the rounding ([`Locator::cell_surely_holds`]).
    /// A point beyond one of them is tested the same way against the cell across that face
    /// (whose near faces are computed once per call too), and given that cell when surely
    /// inside it; the others are located from there by [`Locator::locate_from`].
    ///
    /// [`Locator::locate_near_clearance`] also returns how far the cluster may move with every
    /// answer unchanged.
    pub fn locate_near(
        &self,
        cell: Label,
        centre: V3,
        scale: f64,
        offsets: &[V3],
        f: impl FnMut(usize, Option<Label>),
    ) {
        self.near::<false>(cell, centre, scale, offsets, f);
    }

    /// [`Locator::locate_near`], returning a **clearance** (m): every point lies on the inner
    /// side of every fan-triangle
    /// plane of the cell it was given by more than this distance, so moving all of them by the
    /// same vector of length below it leaves every answer unchanged (a point surely inside a
    /// cell's kernel is in that cell under any tie rule). For a point given by the face tests it
    /// is the least of −(d + s·o·n̂ + margin) over the near faces of its cell (the computed bound
    /// on its fan-triangle distances, the face's certainty margin, which already covers the rounding) and
    /// −(d + radius + margin) over the other faces; for a point located by a walk, how far it
    /// lies from its cell's boundary (`clearance_at`); 0 when a point lies outside the mesh or
    /// no bound applies.
    pub fn locate_near_clearance(
        &self,
        cell: Label,
        centre: V3,
        scale: f64,
        offsets: &[V3],
        f: impl FnMut(usize, Option<Label>),
    ) -> f64 {
        self.near::<true>(cell, centre, scale, offsets, f)
    }

    /// [`Locator::locate_near`] and, with `CLEAR`, the clearance of
    /// [`Locator::locate_near_clearance`] (without, 0 where a point needed a walk: the bound
    /// from its cell's fan triangles is what costs).
    // `!(x < 0.0)` is used on purpose: it is also true for NaN (a face that cannot certify).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn near<const CLEAR: bool>(
        &self,
        cell: Label,
        centre: V3,
        scale: f64,
        offsets: &[V3],
        mut f: impl FnMut(usize, Option<Label>),
    ) -> f64 {
        /// Neighbour cells whose near faces one call keeps.
        const CELLS: usize = 8;
        if cell as usize >= self.tets.n_cells() {
            for (i, o) in offsets.iter().enumerate() {
                f(i, self.locate(V3::from_fn(|a, _| centre[a] + scale * o[a])));
            }
            return 0.0;
        }
        let radius = scale
            * offsets
                .iter()
                .map(|o| o.norm_squared())
                .fold(0.0, f64::max)
                .sqrt();
        // The near faces of `cell` first, then those of the neighbours met (`nb`: cell, range
        // and the far faces' clearance), as long as they fit.
        let mut near = [NearFace::default(); NEAR_MAX];
        let own = self.near_faces(cell, centre, radius, true, &mut near);
        let mut nb = [(NO_LABEL, 0usize, 0usize, 0.0f64); CELLS];
        let mut nb_len = 0;
        let mut used = own.map_or(0, |(n, _)| n);
        let mut clearance = f64::INFINITY;
        for (i, o) in offsets.iter().enumerate() {
            let p = V3::from_fn(|a, _| centre[a] + scale * o[a]);
            let Some((n, far)) = own else {
                f(i, self.walked::<CLEAR>(p, cell, &mut clearance));
                continue;
            };
            // The face the point lies farthest beyond (or not surely inside), and the largest
            // excess over all near faces.
            let mut worst: Option<(f64, usize)> = None;
            let mut top = f64::NEG_INFINITY;
            for nf in &near[..n] {
                let e = nf.excess(scale, o);
                if CLEAR {
                    top = top.max(e);
                }
                if !(e < 0.0) && worst.is_none_or(|w| e > w.0) {
                    worst = Some((e, nf.face));
                }
            }
            let Some((_, face)) = worst else {
                clearance = clearance.min(-top).min(far);
                f(i, Some(cell));
                continue;
            };
            let Some(next) = self.tets.across(face, cell) else {
                f(i, self.walked::<CLEAR>(p, cell, &mut clearance));
                continue;
            };
            let range = match nb[..nb_len].iter().find(|e| e.0 == next) {
                Some(&(_, a, b, far)) => Some((a, b, far)),
                None if nb_len < CELLS => {
                    let got = self.near_faces(next, centre, radius, false, &mut near[used..]);
                    got.map(|(k, far)| {
                        nb[nb_len] = (next, used, used + k, far);
                        nb_len += 1;
                        used += k;
                        (used - k, used, far)
                    })
                }
                None => None,
            };
            // Surely in `next`: inside all its near faces; then the largest excess among them.
            let next_top = range.and_then(|(a, b, far)| {
                let mut top = f64::NEG_INFINITY;
                for nf in &near[a..b] {
                    let e = nf.excess(scale, o);
                    if !(e < 0.0) {
                        return None;
                    }
                    top = top.max(e);
                }
                Some((top, far))
            });
            match next_top {
                Some((top, far)) => {
                    clearance = clearance.min(-top).min(far);
                    f(i, Some(next));
                }
                None => f(i, self.walked::<CLEAR>(p, next, &mut clearance)),
            }
        }
        clearance
    }

    /// [`Locator::locate_from`] for a point of [`Locator::near`]'s cluster that the face tests
    /// did not settle, lowering `clearance` to the point's own (`clearance_at`; 0 without
    /// `CLEAR`).
    #[inline]
    fn walked<const CLEAR: bool>(&self, p: V3, from: Label, clearance: &mut f64) -> Option<Label> {
        let got = self.locate_from(p, from);
        *clearance = clearance.min(if CLEAR {
            self.clearance_at(got, p)
        } else {
            0.0
        });
        got
    }

    /// How far `p`, which lies in cell `cell` (`None`: outside the mesh), may move and surely
    /// stay in it: for each face, −(d + margin) when `p` lies inside the planes of all its fan
    /// triangles by that much ([`Locator::cell_surely_holds`]'s bound), else, in a cell whose
    /// tets are all positively oriented (star-shaped: the tets fill the region the fan
    /// triangles enclose), the distance from `p` to the face's fan triangles less 10⁻¹² of
    /// the coordinates' size for rounding; the least over the faces. 0 outside the mesh, or
    /// where neither bound applies.
    // `!(x > 0.0)` is used on purpose: it is also true for NaN (a face that cannot certify).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn clearance_at(&self, cell: Option<Label>, p: V3) -> f64 {
        let Some(cell) = cell else { return 0.0 };
        let mut clearance = f64::INFINITY;
        let faces = self.tets.cell_faces(cell);
        for (&face, cf) in faces.iter().zip(self.faces_of(cell)) {
            let (d, margin) = cf.outward_distance(p, 0.0);
            let inside = -(d + margin);
            let bound = if inside > 0.0 {
                inside
            } else if self.cell_star[cell as usize] {
                let f = face as usize;
                let dist = face_distance(
                    p,
                    self.tets.points(),
                    self.tets.faces.face(f),
                    self.tets.face_apex[f],
                );
                dist - 1e-12 * (p.amax() + dist)
            } else {
                0.0
            };
            if !(bound > 0.0) {
                return 0.0;
            }
            clearance = clearance.min(bound);
        }
        clearance
    }

    /// The faces of `cell` whose planes may pass within `radius` of `centre` ([`NearFace`]),
    /// into `near`, their number and the least −(d + radius + margin) of the other faces (how
    /// far inside those faces' fan-triangle planes every point within `radius` of `centre`
    /// lies; infinite when every face is near); `None` when the cell has more faces than `near`
    /// holds, or, with `centre_inside`, when `centre` is not surely on the inner side of one of
    /// them.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn near_faces(
        &self,
        cell: Label,
        centre: V3,
        radius: f64,
        centre_inside: bool,
        near: &mut [NearFace],
    ) -> Option<(usize, f64)> {
        let faces = self.tets.cell_faces(cell);
        if faces.len() > near.len() {
            return None;
        }
        let reach = 3f64.sqrt() * radius;
        let mut n = 0;
        let mut far = f64::INFINITY;
        for (&face, cf) in faces.iter().zip(self.faces_of(cell)) {
            let (d, margin) = cf.outward_distance(centre, reach);
            let beyond = d + radius + margin;
            if !(beyond < 0.0) {
                if centre_inside && !(d + margin < 0.0) {
                    return None;
                }
                near[n] = NearFace {
                    normal: cf.n,
                    d,
                    margin,
                    face: face as usize,
                };
                n += 1;
            } else {
                far = far.min(-beyond);
            }
        }
        Some((n, far))
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

    fn walk_or_search(&self, p: V3, start: Label) -> Option<Label> {
        if self.cell_surely_holds(start, p) {
            return Some(start);
        }
        let start = self.cell_walk(p, start);
        if self.cell_surely_holds(start, p) {
            return Some(start);
        }
        match self.walk(p, start) {
            Walk::Found(t) => Some(t.cell),
            Walk::Lost => self.bins.candidates(p).iter().copied().find(|&c| {
                !self.cell_surely_lacks(c, p)
                    && (self.cell_surely_holds(c, p) || self.tets.cell_contains(c, p))
            }),
        }
    }

    /// A cheap cell-to-cell walk towards `p` by face planes: step across the face of which `p`
    /// lies farthest outside, until `p` is inside all face planes of the cell, a boundary face is
    /// met, or a step limit is reached. Only a starting point for the exact tet walk.
    fn cell_walk(&self, p: V3, start: Label) -> Label {
        let mut c = start;
        for _ in 0..MAX_STEPS / 8 {
            let mut best = (0.0, None);
            for (&f, cf) in self.tets.cell_faces(c).iter().zip(self.faces_of(c)) {
                let d = (p - cf.apex).dot(&cf.n);
                if d > best.0 {
                    best = (d, Some(f as usize));
                }
            }
            match best.1.and_then(|f| self.tets.across(f, c)) {
                Some(n) => c = n,
                None => break,
            }
        }
        c
    }

    /// The tet of cell `cell` to start a walk towards `p`: fan 0 of the face whose centre lies
    /// most in the direction of `p` seen from the cell apex.
    fn start_tet(&self, cell: Label, p: V3) -> TetId {
        let apex = self.tets.cell_apex[cell as usize];
        let d = p - apex;
        let mut best = (f64::NEG_INFINITY, self.tets.cell_faces(cell)[0]);
        for &f in self.tets.cell_faces(cell) {
            let r = self.tets.face_apex[f as usize] - apex;
            let score = d.dot(&r) / r.dot(&r);
            if score > best.0 {
                best = (score, f);
            }
        }
        TetId {
            cell,
            face: best.1,
            fan: 0,
        }
    }

    /// Visibility walk over the tets from a tet of cell `start` to the tet containing `p`.
    fn walk(&self, p: V3, start: Label) -> Walk {
        let mut t = self.start_tet(start, p);
        let mut tet = self.tets.tet(t);
        let mut known_inside: Option<usize> = None;
        let mut rng: u64 = 0x9E37_79B9_7F4A_7C15 ^ p[0].to_bits() ^ p[1].to_bits().rotate_left(21);
        for step in 0..MAX_STEPS {
            let mut s = tet_sides(&tet.points, &tet.keys, &p);
            if let Some(k) = known_inside {
                s[k] = f64::INFINITY;
            }
            let k = if step < GREEDY_STEPS {
                let mut k = 0;
                for m in 1..4 {
                    if s[m] < s[k] {
                        k = m;
                    }
                }
                if s[k] > 0.0 {
                    return Walk::Found(t);
                }
                k
            } else {
                let neg: Vec<usize> = (0..4).filter(|&m| s[m] < 0.0).collect();
                if neg.is_empty() {
                    return Walk::Found(t);
                }
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                neg[(rng % neg.len() as u64) as usize]
            };
            let next = if k == 0 {
                match self.tets.across(t.face as usize, t.cell) {
                    Some(cell) => TetId { cell, ..t },
                    None => return Walk::Lost,
                }
            } else {
                match self.tets.inner_neighbour(t, k) {
                    Some(n) => n,
                    None => return Walk::Lost,
                }
            };
            let new = self.tets.tet(next);
            known_inside = (0..4).find(|&j| {
                !(0..4)
                    .filter(|&m| m != k)
                    .any(|m| tet.keys[m] == new.keys[j])
            });
            t = next;
            tet = new;
        }
        Walk::Lost
    }
}
