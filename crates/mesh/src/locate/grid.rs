//! Axis-aligned tensor-product hex meshes ([`AxisGrid`]): their detection, with the points
//! snapped onto the grid planes, and location by a per-axis search of the planes.

use crate::v3::V3;
use foam::{Label, PolyMesh};
use rayon::prelude::*;

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

impl foam::HeapBytes for AxisGrid {
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        self.planes.iter().map(flat).sum::<usize>() + flat(&self.cells) + flat(&self.slots)
    }
}
