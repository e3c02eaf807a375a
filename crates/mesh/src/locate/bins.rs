//! Start cells and candidate cells of a general mesh: a uniform bin grid over the mesh's box
//! with a seed cell and the overlapping cells per bin ([`Bins`]), and a finer grid of start
//! cells ([`SeedGrid`]), both seeded when the [`Locator`] is built.

use super::Locator;
use crate::geometry::Aabb;
use crate::tets::TetDecomposition;
use crate::v3::V3;
use foam::Label;
use rayon::prelude::*;
use std::collections::VecDeque;

/// Uniform bin grid over the mesh bounding box: a seed cell per bin and, per bin, the cells whose
/// bounding boxes overlap it.
#[derive(Clone, Debug)]
pub(super) struct Bins {
    pub(super) origin: V3,
    pub(super) inv: V3,
    pub(super) dims: [usize; 3],
    pub(super) seeds: Vec<Label>,
    pub(super) offsets: Vec<u32>,
    pub(super) cells: Vec<Label>,
}

impl Bins {
    pub(super) fn new(tets: &TetDecomposition, bounds: &Aabb, cell_bounds: &[Aabb]) -> Bins {
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
    pub(super) fn seed(&self, p: V3) -> Label {
        self.seeds[self.index(self.bin_of(p))]
    }

    #[inline]
    pub(super) fn candidates(&self, p: V3) -> &[Label] {
        let b = self.index(self.bin_of(p));
        &self.cells[self.offsets[b] as usize..self.offsets[b + 1] as usize]
    }
}

/// A uniform grid of start cells for point location, twice as fine per axis as [`Bins`]: the
/// cell holding each bin's centre (where there is one), so that most points lie in their bin's
/// seed and are located by one [`Locator::cell_surely_holds`] (measured on the Ergun O-grid:
/// locating from the coarse bins' seeds cost 12 % of the exact voidage benchmark).
#[derive(Clone, Debug)]
pub(super) struct SeedGrid {
    origin: V3,
    inv: V3,
    dims: [usize; 3],
    seeds: Vec<Label>,
}

impl SeedGrid {
    /// An empty grid (axis-aligned meshes locate by their planes).
    pub(super) fn empty() -> SeedGrid {
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
    pub(super) fn seed(&self, p: V3) -> Label {
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

impl Locator {
    /// The start cells of a general mesh: each bin's seed moved to the cell holding the bin's
    /// centre, where there is one, then the finer [`SeedGrid`] from those.
    pub(super) fn place_seeds(&mut self) {
        // Seeds that hold their bin's centre, where there is one: a walk from there is short.
        let b = &self.bins;
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
                self.walk_or_search(centre, b.seeds[i])
                    .unwrap_or(b.seeds[i])
            })
            .collect();
        self.bins.seeds = seeds;
        let fine = SeedGrid::new(&self.bins, |centre| {
            let coarse = self.bins.seed(centre);
            self.walk_or_search(centre, coarse).unwrap_or(coarse)
        });
        self.seeds = fine;
    }
}

impl foam::HeapBytes for Bins {
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        flat(&self.seeds) + flat(&self.offsets) + flat(&self.cells)
    }
}

impl foam::HeapBytes for SeedGrid {
    fn heap_bytes(&self) -> usize {
        foam::heap::flat(&self.seeds)
    }
}
