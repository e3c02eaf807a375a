//! The cells that may overlap a region ([`Query`]): a walk over face neighbours from the
//! centre's cell, or a bin index of the cells' bounding boxes ([`CellBins`]) where the walk
//! cannot be complete.

use crate::engine::{Scratch, VoidageMesh};
use crate::sphere_box::interval_dist2;
use crate::vec3::V3;
use foam::Label;
use mesh::Aabb;

/// Uniform bins over the mesh bounds holding the cells whose bounding boxes overlap them.
#[derive(Clone, Debug)]
pub(in crate::engine) struct CellBins {
    origin: V3,
    inv: V3,
    dims: [usize; 3],
    offsets: Vec<u32>,
    cells: Vec<Label>,
}

impl CellBins {
    /// Bins of about the mean cell size per axis, at most 4 per cell and 1024 per axis.
    pub(in crate::engine) fn new(bounds: &Aabb, cell_bounds: &[Aabb]) -> CellBins {
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
pub(super) struct Query {
    pub(super) lo: V3,
    pub(super) hi: V3,
    pub(super) ball: Option<(V3, f64)>,
}

impl Query {
    #[inline]
    pub(super) fn hits(&self, b: &Aabb) -> bool {
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

impl VoidageMesh {
    /// The cells that may overlap `q` (module docs), into `s.candidates`.
    pub(super) fn candidates(&self, q: &Query, start: Option<Label>, s: &mut Scratch) {
        s.candidates.clear();
        s.visited.clear();
        let n_internal = self.neighbour.len();
        let tets = self.locator.tets();
        let mut complete = start.is_some();
        if let Some(c0) = start {
            s.begin_walk(c0);
            while let Some(c) = s.queue.pop() {
                s.candidates.push(c);
                for &f in tets.cell_faces(c) {
                    let f = f as usize;
                    if f < n_internal {
                        let n = self.across(f, c);
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
}

impl foam::HeapBytes for CellBins {
    fn heap_bytes(&self) -> usize {
        foam::heap::flat(&self.offsets) + foam::heap::flat(&self.cells)
    }
}
