//! Linked-cell neighbour search, the particles' spatial order, and the half pair list that
//! carries the contact history (`neighbor SKIN bin`, `neigh_modify delay 0`).
//!
//! The list holds every pair i < j (particle indices) with |xᵢ − xⱼ| < Rᵢ + Rⱼ + skin at build
//! time. It is rebuilt when a particle has moved more than skin/2 since the last build (then no
//! contact can have been missed). Binning is a counting sort into cubic cells of side
//! ≥ 2R_max + skin, so a build is O(N) for a bounded number of particles per cell.
//!
//! A build also fixes a *spatial order* of the particles: cell by cell (x fastest, then y, z),
//! as LIGGGHTS/LAMMPS sort atoms by bin for locality. The pairs are stored grouped by the
//! sorted position of their first member, and each refers to its two particles by sorted
//! position, so a pass over the pairs reads per-particle data copied in that order
//! ([`PairList::order`]) from nearby memory. The particle indices themselves never change.
//!
//! Each pair is oriented by the particles' indices (its i is the smaller; with
//! [`PairList::build_keyed`], the smaller key), so its history keeps its sense across builds and
//! renumberings; the pairs of a row are stored in ascending sorted position of the partner,
//! which fixes the order of the per-particle sums (see `pair_loop`). The history of pairs
//! present before and after a rebuild is carried over, keyed by the two particle indices.

use mesh::v3::V3;
use rayon::prelude::*;

use crate::contact::History;
use crate::periodic::Periodic;

/// Particles per parallel chunk in builds.
const CHUNK: usize = 512;

/// Half pair list with contact history, in the particles' spatial order.
#[derive(Debug, Clone, Default)]
pub struct PairList {
    /// Skin distance (m).
    pub skin: f64,
    /// Positions at the last build.
    x_build: Vec<V3>,
    /// `order[s]`: the particle at sorted position s.
    order: Vec<u32>,
    /// `rank[i]`: the sorted position of particle i.
    rank: Vec<u32>,
    /// Sorted position of each pair's i (the smaller particle index).
    si: Vec<u32>,
    /// Sorted position of each pair's j.
    sj: Vec<u32>,
    /// History of each pair, as seen from i.
    hist: Vec<History>,
    /// Pairs by row (CSR offsets, length N + 1): the pairs of row a are those whose smaller
    /// sorted position is a.
    row_first: Vec<u32>,
    /// Per sorted position: the smallest row holding one of its pairs (itself if none).
    low_row: Vec<u32>,
    /// Number of builds and renumberings so far (per-particle copies in the sorted order
    /// follow it).
    generation: u64,
    /// Whether `order` is the identity: the particles are stored in the spatial order
    /// ([`PairList::renumber`]), so a pass reads their arrays directly.
    identity: bool,
    valid: bool,
    /// The box's periodic axes: pairs across a periodic face are found and measured through
    /// the nearest image ([`crate::periodic`]).
    periodic: Option<Periodic>,
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
        self.si.len()
    }

    /// `true` without pairs.
    pub fn is_empty(&self) -> bool {
        self.si.is_empty()
    }

    /// Sets the periodic axes the list searches across (forces a rebuild).
    pub fn set_periodic(&mut self, periodic: Option<Periodic>) {
        self.periodic = periodic;
        self.valid = false;
    }

    /// The periodic axes the list searches across.
    pub fn periodic(&self) -> Option<&Periodic> {
        self.periodic.as_ref()
    }

    /// Forces a rebuild at the next [`PairList::ensure`].
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Number of builds so far; changes whenever the order or the pairs change.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The spatial order: `order()[s]` is the particle at sorted position s.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Whether the spatial order is the particles' index order (after [`PairList::renumber`]
    /// with [`PairList::order`]): per-particle data need no copy into that order.
    pub fn is_identity(&self) -> bool {
        self.identity
    }

    /// Follows a renumbering of the particles: the particle now at index `new` was at index
    /// `perm[new]` (a permutation of `0..n`). Pairs, histories and the build positions stay
    /// with their particles; renumbering by [`PairList::order`] right after a build stores the
    /// particles in the spatial order ([`PairList::is_identity`]).
    pub fn renumber(&mut self, perm: &[u32]) {
        let n = perm.len();
        let mut new_of_old = vec![0u32; n];
        for (new, &old) in perm.iter().enumerate() {
            new_of_old[old as usize] = new as u32;
        }
        for o in &mut self.order {
            *o = new_of_old[*o as usize];
        }
        self.rank.resize(self.order.len(), 0);
        for (s, &p) in self.order.iter().enumerate() {
            self.rank[p as usize] = s as u32;
        }
        if self.x_build.len() == n {
            self.x_build = perm.iter().map(|&o| self.x_build[o as usize]).collect();
        }
        self.identity = self.order.iter().enumerate().all(|(s, &p)| p as usize == s);
        self.generation += 1;
    }

    /// The sorted position of particle `i`.
    pub fn rank(&self, i: usize) -> usize {
        self.rank[i] as usize
    }

    /// The sorted positions of all particles, by particle index.
    pub fn ranks(&self) -> &[u32] {
        &self.rank
    }

    /// Particle indices (i, j), i < j, of pair `k`.
    pub fn pair(&self, k: usize) -> (usize, usize) {
        (
            self.order[self.si[k] as usize] as usize,
            self.order[self.sj[k] as usize] as usize,
        )
    }

    /// History of pair `k` as seen from its i.
    pub fn history(&self, k: usize) -> History {
        self.hist[k]
    }

    /// Sets the history of pair `k` as seen from its i.
    pub fn set_history(&mut self, k: usize, h: History) {
        self.hist[k] = h;
    }

    /// The list for a pass over its pairs: everything but the histories, read-only, and the
    /// histories, mutable.
    pub fn split_mut(&mut self) -> (PairView<'_>, &mut [History]) {
        (
            PairView {
                order: &self.order,
                si: &self.si,
                sj: &self.sj,
                row_first: &self.row_first,
                low_row: &self.low_row,
            },
            &mut self.hist,
        )
    }

    /// Renumbers the particles after some were removed (`map[old] = Some(new)`); pairs with a
    /// removed particle are dropped, the others keep their history. A rebuild follows.
    pub fn remap(&mut self, map: &[Option<usize>]) {
        for o in &mut self.order {
            *o = map
                .get(*o as usize)
                .copied()
                .flatten()
                .map_or(u32::MAX, |k| k as u32);
        }
        let order = &self.order;
        let mut k = 0;
        for p in 0..self.si.len() {
            if order[self.si[p] as usize] != u32::MAX && order[self.sj[p] as usize] != u32::MAX {
                self.si[k] = self.si[p];
                self.sj[k] = self.sj[p];
                self.hist[k] = self.hist[p];
                k += 1;
            }
        }
        self.si.truncate(k);
        self.sj.truncate(k);
        self.hist.truncate(k);
        self.row_first.clear();
        self.low_row.clear();
        self.x_build.clear();
        self.identity = false;
        self.valid = false;
    }

    /// Rebuilds the list if it is invalid, the particle count changed, or a particle moved more
    /// than skin/2 since the last build. Returns whether it rebuilt.
    pub fn ensure(&mut self, x: &[V3], radius: &[f64]) -> bool {
        let need = self.needs_build(x);
        if need {
            self.build(x, radius);
        }
        need
    }

    /// Whether [`PairList::ensure`] would rebuild for positions `x` (periodic positions are
    /// wrapped into the box just before such a build, as LIGGGHTS does).
    pub fn needs_build(&self, x: &[V3]) -> bool {
        self.is_stale(x.len())
            || x.par_iter()
                .enumerate()
                .with_min_len(4096)
                .any(|(i, &a)| self.moved_beyond_half_skin(i, a))
    }

    /// Whether the list must be rebuilt whatever the positions of its `n` particles: it was
    /// invalidated, or built for another number of particles.
    pub fn is_stale(&self, n: usize) -> bool {
        !self.valid || self.x_build.len() != n
    }

    /// Whether particle `i`, now at `x`, has moved more than skin/2 since the last build (the
    /// test of [`PairList::needs_build`], for a pass that moves the particles to make as it
    /// goes). The list must not be stale ([`PairList::is_stale`]).
    #[inline]
    pub fn moved_beyond_half_skin(&self, i: usize, x: V3) -> bool {
        let b = self.x_build[i];
        let d = [x[0] - b[0], x[1] - b[1], x[2] - b[2]];
        d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0.25 * self.skin * self.skin
    }

    /// Builds the list now, carrying the history over.
    pub fn build(&mut self, x: &[V3], radius: &[f64]) {
        self.build_keyed(x, radius, None);
    }

    /// [`PairList::build`] for particles stored in another order than their indices:
    /// `key[i]` is the index particle i stands for (its place in the caller's index order), and
    /// pairs are oriented by key instead of by index, so each pair computes its force as in the
    /// index order. `None`: the key is the index. The key must orient every pair as the
    /// previous build's did (the histories are carried over as stored).
    pub fn build_keyed(&mut self, x: &[V3], radius: &[f64], key: Option<&[u32]>) {
        let n = x.len();
        let key_of = |p: u32| key.map_or(p, |k| k[p as usize]);
        let periodic = self.periodic;
        let cells = CellGrid::new(x, radius, self.skin, periodic.as_ref());
        let skin = self.skin;
        // pairs (a, b), a < b in the new sorted order, row by row
        let nchunks = n.div_ceil(CHUNK);
        let chunks: Vec<(Vec<u32>, Vec<u32>)> = (0..nchunks)
            .into_par_iter()
            .map(|c| {
                let (lo, hi) = (c * CHUNK, ((c + 1) * CHUNK).min(n));
                let (mut ra, mut rb) = (Vec::new(), Vec::new());
                let mut row: Vec<u32> = Vec::with_capacity(32);
                for a in lo..hi {
                    row.clear();
                    let (xa, ra_) = (cells.x[a], cells.radius[a]);
                    cells.for_each_candidate(xa, |b, xb, rb_| {
                        if b > a {
                            let d = match &periodic {
                                None => [xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]],
                                Some(per) => per.delta(xa, xb).into(),
                            };
                            let cut = ra_ + rb_ + skin;
                            if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut {
                                row.push(b as u32);
                            }
                        }
                    });
                    row.sort_unstable();
                    ra.extend(std::iter::repeat_n(a as u32, row.len()));
                    rb.extend_from_slice(&row);
                }
                (ra, rb)
            })
            .collect();
        let old = self.old_histories(n, &key_of);
        let order = cells.items;
        let mut rank = vec![0u32; n];
        for (s, &p) in order.iter().enumerate() {
            rank[p as usize] = s as u32;
        }
        let total: usize = chunks.iter().map(|c| c.0.len()).sum();
        let (mut si, mut sj, mut hist) = (
            Vec::with_capacity(total),
            Vec::with_capacity(total),
            Vec::with_capacity(total),
        );
        let mut row_first = vec![0u32; n + 1];
        let mut low_row: Vec<u32> = (0..n as u32).collect();
        for (ra, rb) in chunks {
            for (a, b) in ra.into_iter().zip(rb) {
                row_first[a as usize + 1] += 1;
                low_row[b as usize] = low_row[b as usize].min(a);
                let (pa, pb) = (order[a as usize], order[b as usize]);
                let (s_i, s_j, i, j) = if key_of(pa) < key_of(pb) {
                    (a, b, pa, pb)
                } else {
                    (b, a, pb, pa)
                };
                si.push(s_i);
                sj.push(s_j);
                hist.push(old.find(i as usize, j));
            }
        }
        for a in 0..n {
            row_first[a + 1] += row_first[a];
        }
        self.order = order;
        self.rank = rank;
        self.si = si;
        self.sj = sj;
        self.hist = hist;
        self.row_first = row_first;
        self.low_row = low_row;
        self.x_build = x.to_vec();
        self.identity = self.order.iter().enumerate().all(|(s, &p)| p as usize == s);
        self.generation += 1;
        self.valid = true;
    }

    /// The non-zero histories of the current pairs, by particle index i (for `n` particles),
    /// i the member with the smaller key.
    fn old_histories(&self, n: usize, key_of: &impl Fn(u32) -> u32) -> OldHistories {
        let mut first = vec![0u32; n + 1];
        let mut keep = Vec::new();
        for k in 0..self.si.len() {
            if self.hist[k] == History::default() {
                continue;
            }
            let (a, b) = (
                self.order[self.si[k] as usize] as usize,
                self.order[self.sj[k] as usize] as usize,
            );
            if a.max(b) >= n {
                continue;
            }
            // as seen from the smaller key (a remap may have reversed the pair)
            let (i, j, h) = if key_of(a as u32) < key_of(b as u32) {
                (a, b, self.hist[k])
            } else {
                (
                    b,
                    a,
                    History {
                        shear: -self.hist[k].shear,
                        roll: -self.hist[k].roll,
                    },
                )
            };
            if j < n {
                first[i + 1] += 1;
                keep.push((i, j as u32, h));
            }
        }
        for i in 0..n {
            first[i + 1] += first[i];
        }
        let mut fill = first.clone();
        let mut j = vec![0u32; keep.len()];
        let mut hist = vec![History::default(); keep.len()];
        for (i, jj, h) in keep {
            let at = fill[i] as usize;
            j[at] = jj;
            hist[at] = h;
            fill[i] += 1;
        }
        OldHistories { first, j, hist }
    }
}

/// A read-only view of a [`PairList`] without its histories ([`PairList::split_mut`]).
#[derive(Debug, Clone, Copy)]
pub struct PairView<'a> {
    /// `order[s]`: the particle at sorted position s.
    pub order: &'a [u32],
    /// Sorted position of each pair's i (the smaller particle index).
    pub si: &'a [u32],
    /// Sorted position of each pair's j.
    pub sj: &'a [u32],
    /// Pairs by row (length N + 1): row a holds the pairs whose smaller sorted position is a,
    /// `row_first[a]..row_first[a + 1]`; pairs are stored row by row, each row in ascending
    /// sorted position of the partner.
    pub row_first: &'a [u32],
    /// Per sorted position s: the smallest row holding a pair of s (`s` itself if none lies
    /// below): once rows `low_row[s]..=s` are evaluated, all of `s`'s pairs are.
    pub low_row: &'a [u32],
}

/// Non-zero histories of a list about to be rebuilt, by particle index i (CSR).
struct OldHistories {
    first: Vec<u32>,
    j: Vec<u32>,
    hist: Vec<History>,
}

impl OldHistories {
    /// The history of pair (i, j), zero if it had none.
    fn find(&self, i: usize, j: u32) -> History {
        let row = self.first[i] as usize..self.first[i + 1] as usize;
        self.j[row.clone()]
            .iter()
            .position(|&x| x == j)
            .map_or(History::default(), |k| self.hist[row.start + k])
    }
}

/// Particles binned into cubic cells (counting sort), with their positions and radii copied
/// in cell order so that a search reads neighbouring cells from contiguous memory.
struct CellGrid {
    lo: V3,
    inv: f64,
    dims: [usize; 3],
    /// Per axis: whether the cells wrap around (a periodic axis).
    wraps: [bool; 3],
    start: Vec<u32>,
    items: Vec<u32>,
    /// Positions in `items` order (m).
    x: Vec<V3>,
    /// Radii in `items` order (m).
    radius: Vec<f64>,
}

impl CellGrid {
    /// On a periodic axis the cells span the box (the particles are wrapped into it at each
    /// build) and the neighbours of the first cell include the last.
    fn new(x: &[V3], radius: &[f64], skin: f64, periodic: Option<&Periodic>) -> CellGrid {
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
        let mut wraps = [false; 3];
        if let Some(per) = periodic {
            for k in (0..3).filter(|&k| per.is_periodic(k)) {
                wraps[k] = true;
                lo[k] = lo[k].min(per.lo()[k]);
                hi[k] = hi[k].max(per.lo()[k] + per.len()[k]);
            }
        }
        // keep the number of cells O(N) for sparse clouds
        let count = |side: f64| -> [usize; 3] {
            let mut d = [1usize; 3];
            for k in 0..3 {
                d[k] = if wraps[k] {
                    // whole cells of at least `side` tile the period
                    (((hi[k] - lo[k]) / side).floor() as usize).max(1)
                } else {
                    (((hi[k] - lo[k]) / side).floor() as usize).saturating_add(1)
                };
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
            wraps,
            start,
            x: items.iter().map(|&p| x[p as usize]).collect(),
            radius: items.iter().map(|&p| radius[p as usize]).collect(),
            items,
        }
    }

    /// Calls `f(k, xₖ, Rₖ)` for every particle in the 27 cells around `p`, k its position in
    /// cell order (`items`).
    #[inline]
    fn for_each_candidate(&self, p: V3, mut f: impl FnMut(usize, V3, f64)) {
        let mut c = [0isize; 3];
        for k in 0..3 {
            c[k] = (((p[k] - self.lo[k]) * self.inv) as isize).min(self.dims[k] as isize - 1);
        }
        let d = self.dims;
        if self.wraps.iter().any(|&w| w) {
            return self.for_each_candidate_wrapped(c, f);
        }
        for cz in (c[2] - 1).max(0)..=(c[2] + 1).min(d[2] as isize - 1) {
            for cy in (c[1] - 1).max(0)..=(c[1] + 1).min(d[1] as isize - 1) {
                let row = (cz as usize * d[1] + cy as usize) * d[0];
                let x0 = (c[0] - 1).max(0) as usize;
                let x1 = (c[0] + 1).min(d[0] as isize - 1) as usize;
                let s = self.start[row + x0] as usize;
                let e = self.start[row + x1 + 1] as usize;
                for k in s..e {
                    f(k, self.x[k], self.radius[k]);
                }
            }
        }
    }

    /// [`CellGrid::for_each_candidate`] with wrapping axes: the neighbouring cells modulo the
    /// cell count, each once (a period of one or two cells has fewer than three neighbours).
    fn for_each_candidate_wrapped(&self, c: [isize; 3], mut f: impl FnMut(usize, V3, f64)) {
        let d = self.dims;
        let around = |k: usize| -> Vec<usize> {
            let n = d[k] as isize;
            let mut v: Vec<usize> = if self.wraps[k] {
                (c[k] - 1..=c[k] + 1)
                    .map(|q| q.rem_euclid(n) as usize)
                    .collect()
            } else {
                ((c[k] - 1).max(0)..=(c[k] + 1).min(n - 1))
                    .map(|q| q as usize)
                    .collect()
            };
            v.sort_unstable();
            v.dedup();
            v
        };
        let (xs, ys, zs) = (around(0), around(1), around(2));
        for &cz in &zs {
            for &cy in &ys {
                let row = (cz * d[1] + cy) * d[0];
                for &cx in &xs {
                    let s = self.start[row + cx] as usize;
                    let e = self.start[row + cx + 1] as usize;
                    for k in s..e {
                        f(k, self.x[k], self.radius[k]);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Row a holds the pairs whose smaller sorted position is a, partners ascending, and
    /// `low_row` is each position's lowest row.
    fn assert_rows(list: &mut PairList) {
        let n = list.order().len();
        let (view, _) = list.split_mut();
        let mut low: Vec<u32> = (0..n as u32).collect();
        for a in 0..n {
            let row = view.row_first[a] as usize..view.row_first[a + 1] as usize;
            let partners: Vec<u32> = row
                .clone()
                .map(|k| {
                    let (s_i, s_j) = (view.si[k], view.sj[k]);
                    let b = if s_i as usize == a { s_j } else { s_i };
                    assert_eq!(s_i.min(s_j) as usize, a);
                    low[b as usize] = low[b as usize].min(a as u32);
                    b
                })
                .collect();
            assert!(partners.windows(2).all(|w| w[0] < w[1]), "{partners:?}");
        }
        assert_eq!(view.low_row, &low[..]);
    }

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
        let pairs = |l: &PairList| {
            let mut v: Vec<(u32, u32, usize)> = (0..l.len())
                .map(|k| {
                    let (i, j) = l.pair(k);
                    (i as u32, j as u32, k)
                })
                .collect();
            v.sort_unstable();
            v
        };
        let got: Vec<(u32, u32)> = pairs(&list).iter().map(|p| (p.0, p.1)).collect();
        assert_eq!(got, brute);
        // rows in order, each row's partners ascending, and every particle's lowest row
        assert_rows(&mut list.clone());
        // history survives a rebuild, keyed by the pair
        for k in 0..list.len() {
            let (i, j) = list.pair(k);
            list.set_history(
                k,
                History {
                    shear: V3::new(k as f64 + 1.0, i as f64, j as f64),
                    roll: V3::zeros(),
                },
            );
        }
        let keyed = |l: &PairList| -> Vec<(u32, u32, History)> {
            pairs(l)
                .iter()
                .map(|p| (p.0, p.1, l.history(p.2)))
                .collect()
        };
        let old = keyed(&list);
        list.build(&x, &r);
        assert_eq!(keyed(&list), old);
        // storing the particles in the spatial order keeps every pair and its history, and a
        // build keyed by the former indices orients and orders them as before
        let perm = list.order().to_vec();
        let mut moved = list.clone();
        moved.renumber(&perm);
        assert!(moved.is_identity());
        let (xp, rp): (Vec<V3>, Vec<f64>) =
            perm.iter().map(|&o| (x[o as usize], r[o as usize])).unzip();
        moved.build_keyed(&xp, &rp, Some(&perm));
        let back = |l: &PairList| -> Vec<(u32, u32, History)> {
            let mut v: Vec<(u32, u32, History)> = (0..l.len())
                .map(|k| {
                    let (i, j) = l.pair(k);
                    (perm[i], perm[j], l.history(k))
                })
                .collect();
            v.sort_unstable_by_key(|p| (p.0, p.1));
            v
        };
        assert_eq!(back(&moved), old);
        assert_rows(&mut moved.clone());
        // and back in index order, the list is the one built there
        let mut inverse = vec![0u32; n];
        for (now, &home) in perm.iter().enumerate() {
            inverse[home as usize] = now as u32;
        }
        moved.renumber(&inverse);
        assert_eq!(keyed(&moved), old);
        // removing particle 0 drops its pairs and renumbers the others
        let map: Vec<Option<usize>> = (0..n).map(|k| (k > 0).then(|| k - 1)).collect();
        list.remap(&map);
        list.build(&x[1..], &r[1..]);
        assert_eq!(list.len(), old.iter().filter(|p| p.0 > 0).count());
        for k in 0..list.len() {
            let (i, j) = list.pair(k);
            assert_eq!(list.history(k).shear[1], (i + 1) as f64);
            assert_eq!(list.history(k).shear[2], (j + 1) as f64);
        }
    }
}
