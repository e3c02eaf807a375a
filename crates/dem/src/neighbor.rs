//! Linked-cell neighbour search and the half pair list that carries the contact history
//! (`neighbor SKIN bin`, `neigh_modify delay 0`).
//!
//! The list holds every pair i < j with |xᵢ − xⱼ| < Rᵢ + Rⱼ + skin at build time, grouped by i
//! (CSR) with j ascending. It is rebuilt when a particle has moved more than skin/2 since the
//! last build (then no contact can have been missed). Binning is a counting sort into cubic
//! cells of side ≥ 2R_max + skin, so a build is O(N) for a bounded number of particles per
//! cell; the history of pairs present before and after a rebuild is carried over by a merge of
//! the two sorted lists.

use mesh::v3::V3;
use rayon::prelude::*;

use crate::contact::History;

/// Particles per parallel chunk in builds.
const CHUNK: usize = 512;

/// Half pair list with contact history.
#[derive(Debug, Clone, Default)]
pub struct PairList {
    /// Skin distance (m).
    pub skin: f64,
    /// Positions at the last build.
    x_build: Vec<V3>,
    /// CSR offsets by i (length N + 1).
    pub first: Vec<u32>,
    /// i of each pair.
    pub i: Vec<u32>,
    /// j of each pair (> i, ascending within one i).
    pub j: Vec<u32>,
    /// History of each pair.
    pub hist: Vec<History>,
    valid: bool,
}

impl PairList {
    /// An empty list with the given skin (m).
    pub fn new(skin: f64) -> PairList {
        PairList {
            skin,
            ..Default::default()
        }
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.j.len()
    }

    /// `true` without pairs.
    pub fn is_empty(&self) -> bool {
        self.j.is_empty()
    }

    /// Forces a rebuild at the next [`PairList::ensure`].
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Renumbers the particles after some were removed (`map[old] = Some(new)`); pairs with a
    /// removed particle are dropped, the others keep their history. A rebuild follows.
    pub fn remap(&mut self, map: &[Option<usize>]) {
        let n_new = map.iter().flatten().count();
        let mut first = vec![0u32; n_new + 1];
        let (mut i2, mut j2, mut h2) = (Vec::new(), Vec::new(), Vec::new());
        for p in 0..self.j.len() {
            if let (Some(a), Some(b)) = (map[self.i[p] as usize], map[self.j[p] as usize]) {
                first[a + 1] += 1;
                i2.push(a as u32);
                j2.push(b as u32);
                h2.push(self.hist[p]);
            }
        }
        for k in 0..n_new {
            first[k + 1] += first[k];
        }
        self.first = first;
        self.i = i2;
        self.j = j2;
        self.hist = h2;
        self.x_build.clear();
        self.valid = false;
    }

    /// Rebuilds the list if it is invalid, the particle count changed, or a particle moved more
    /// than skin/2 since the last build. Returns whether it rebuilt.
    pub fn ensure(&mut self, x: &[V3], radius: &[f64]) -> bool {
        let need = !self.valid || self.x_build.len() != x.len() || {
            let lim = 0.25 * self.skin * self.skin;
            x.iter().zip(&self.x_build).any(|(a, b)| {
                let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > lim
            })
        };
        if need {
            self.build(x, radius);
        }
        need
    }

    /// Builds the list now, carrying the history over.
    pub fn build(&mut self, x: &[V3], radius: &[f64]) {
        let n = x.len();
        let cells = CellGrid::new(x, radius, self.skin);
        let skin = self.skin;
        let nchunks = n.div_ceil(CHUNK);
        let old_first = &self.first;
        let old_j = &self.j;
        let old_hist = &self.hist;
        let have_old = old_first.len() >= 2;
        let chunks: Vec<(Vec<u32>, Vec<u32>, Vec<History>)> = (0..nchunks)
            .into_par_iter()
            .map(|c| {
                let lo = c * CHUNK;
                let hi = ((c + 1) * CHUNK).min(n);
                let mut counts = Vec::with_capacity(hi - lo);
                let mut js = Vec::new();
                let mut hs = Vec::new();
                let mut row: Vec<u32> = Vec::with_capacity(32);
                for i in lo..hi {
                    row.clear();
                    let (xi, ri) = (x[i], radius[i]);
                    cells.for_each_candidate(xi, |j, xj, rj| {
                        if j > i {
                            let d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
                            let cut = ri + rj + skin;
                            if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut {
                                row.push(j as u32);
                            }
                        }
                    });
                    row.sort_unstable();
                    counts.push(row.len() as u32);
                    // merge with the old row of i (j ascending in both)
                    let (mut a, a_end) = if have_old && i + 1 < old_first.len() {
                        (old_first[i] as usize, old_first[i + 1] as usize)
                    } else {
                        (0, 0)
                    };
                    for &j in &row {
                        while a < a_end && old_j[a] < j {
                            a += 1;
                        }
                        let h = if a < a_end && old_j[a] == j {
                            old_hist[a]
                        } else {
                            History::default()
                        };
                        hs.push(h);
                    }
                    js.extend_from_slice(&row);
                }
                (counts, js, hs)
            })
            .collect();
        let total: usize = chunks.iter().map(|c| c.1.len()).sum();
        let mut first = Vec::with_capacity(n + 1);
        first.push(0u32);
        let mut pi = Vec::with_capacity(total);
        let mut pj = Vec::with_capacity(total);
        let mut ph = Vec::with_capacity(total);
        let mut i = 0u32;
        for (counts, js, hs) in chunks {
            for c in counts {
                first.push(first.last().unwrap() + c);
                pi.extend(std::iter::repeat_n(i, c as usize));
                i += 1;
            }
            pj.extend(js);
            ph.extend(hs);
        }
        self.first = first;
        self.i = pi;
        self.j = pj;
        self.hist = ph;
        self.x_build = x.to_vec();
        self.valid = true;
    }
}

/// Particles binned into cubic cells (counting sort), with their positions and radii copied
/// in cell order so that a search reads neighbouring cells from contiguous memory.
struct CellGrid {
    lo: V3,
    inv: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
    /// Positions in `items` order (m).
    x: Vec<V3>,
    /// Radii in `items` order (m).
    radius: Vec<f64>,
}

impl CellGrid {
    fn new(x: &[V3], radius: &[f64], skin: f64) -> CellGrid {
        let n = x.len();
        let mut lo = V3::repeat(f64::INFINITY);
        let mut hi = V3::repeat(f64::NEG_INFINITY);
        for p in x {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let rmax = radius.iter().copied().fold(0.0, f64::max);
        let mut side = (2.0 * rmax + skin).max(f64::MIN_POSITIVE);
        if n == 0 {
            lo = V3::zeros();
            hi = V3::zeros();
        }
        // keep the number of cells O(N) for sparse clouds
        let count = |side: f64| -> [usize; 3] {
            let mut d = [1usize; 3];
            for k in 0..3 {
                d[k] = (((hi[k] - lo[k]) / side).floor() as usize).saturating_add(1);
            }
            d
        };
        let mut dims = count(side);
        while (dims[0] as f64) * (dims[1] as f64) * (dims[2] as f64) > 8.0 * (n.max(1) as f64) {
            side *= 1.5;
            dims = count(side);
        }
        let inv = 1.0 / side;
        let ncell = dims[0] * dims[1] * dims[2];
        let cell_of = |p: &V3| -> usize {
            let mut c = [0usize; 3];
            for k in 0..3 {
                c[k] = (((p[k] - lo[k]) * inv) as usize).min(dims[k] - 1);
            }
            (c[2] * dims[1] + c[1]) * dims[0] + c[0]
        };
        let ids: Vec<u32> = x.par_iter().map(|p| cell_of(p) as u32).collect();
        let mut start = vec![0u32; ncell + 1];
        for &c in &ids {
            start[c as usize + 1] += 1;
        }
        for k in 0..ncell {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; n];
        for (p, &c) in ids.iter().enumerate() {
            items[fill[c as usize] as usize] = p as u32;
            fill[c as usize] += 1;
        }
        CellGrid {
            lo,
            inv,
            dims,
            start,
            x: items.iter().map(|&p| x[p as usize]).collect(),
            radius: items.iter().map(|&p| radius[p as usize]).collect(),
            items,
        }
    }

    /// Calls `f(j, xⱼ, Rⱼ)` for every particle j in the 27 cells around `p`.
    #[inline]
    fn for_each_candidate(&self, p: V3, mut f: impl FnMut(usize, V3, f64)) {
        let mut c = [0isize; 3];
        for k in 0..3 {
            c[k] = (((p[k] - self.lo[k]) * self.inv) as isize).min(self.dims[k] as isize - 1);
        }
        let d = self.dims;
        for cz in (c[2] - 1).max(0)..=(c[2] + 1).min(d[2] as isize - 1) {
            for cy in (c[1] - 1).max(0)..=(c[1] + 1).min(d[1] as isize - 1) {
                let row = (cz as usize * d[1] + cy as usize) * d[0];
                let x0 = (c[0] - 1).max(0) as usize;
                let x1 = (c[0] + 1).min(d[0] as isize - 1) as usize;
                let s = self.start[row + x0] as usize;
                let e = self.start[row + x1 + 1] as usize;
                for k in s..e {
                    f(self.items[k] as usize, self.x[k], self.radius[k]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn same_pairs_as_brute_force_and_history_kept() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let n = 900;
        let x: Vec<V3> = (0..n)
            .map(|_| {
                V3::new(
                    rng.gen::<f64>(),
                    rng.gen::<f64>() * 0.3,
                    rng.gen::<f64>() * 2.0,
                )
            })
            .collect();
        let r: Vec<f64> = (0..n).map(|_| 0.01 + 0.03 * rng.gen::<f64>()).collect();
        let mut list = PairList::new(0.005);
        list.build(&x, &r);
        let mut brute = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                let d2: f64 = (0..3).map(|k| (x[i][k] - x[j][k]).powi(2)).sum();
                if d2 < (r[i] + r[j] + 0.005f64).powi(2) {
                    brute.push((i as u32, j as u32));
                }
            }
        }
        let got: Vec<(u32, u32)> = list.i.iter().copied().zip(list.j.iter().copied()).collect();
        assert_eq!(got, brute);
        // history survives a rebuild, keyed by the pair
        for (p, h) in list.hist.iter_mut().enumerate() {
            h.shear = V3::new(p as f64, list.i[p] as f64, list.j[p] as f64);
        }
        let old = list.clone();
        list.build(&x, &r);
        assert_eq!(list.hist, old.hist);
        // removing particle 0 drops its pairs and renumbers the others
        let map: Vec<Option<usize>> = (0..n).map(|k| (k > 0).then(|| k - 1)).collect();
        list.remap(&map);
        list.build(&x[1..], &r[1..]);
        for p in 0..list.len() {
            assert_eq!(list.hist[p].shear[1], (list.i[p] + 1) as f64);
            assert_eq!(list.hist[p].shear[2], (list.j[p] + 1) as f64);
        }
    }
}
