//! OpenFOAM's sequential Gauss–Seidel sweep, bit for bit, on several threads at once.
//!
//! A forward sweep updates row c from the rows before it already done and the rows after it
//! not yet done. Cut the rows into contiguous *chunks*; a chunk may be swept as soon as every
//! earlier chunk it shares a matrix entry with is done: its rows then read the same values as
//! in the sequential sweep (earlier connected rows new, later connected rows old, since a later
//! connected chunk waits for this one in turn). Chunks without a common entry run side by side.
//! The backward sweep mirrors it. Each row computes exactly what the sequential sweep computes,
//! so the result is the same bits on any number of threads and with any chunking (tested);
//! only the speed depends on the mesh's numbering.
//!
//! On a mesh numbered as blockMesh numbers a block (x fastest, then y, then z), a row's lower
//! neighbours lie 1, n_x and n_x n_y rows back. Chunks of half the largest of these distances
//! (half a z-plane in 3-D, half an x-line in 2-D) make chunk i + 1 independent of chunk i:
//! the first half of a plane waits only for the first half of the plane below, the second half
//! for the first half of its own plane and the second half below. Two threads then sweep the
//! two halves as a pipeline one chunk apart, each chunk's rows in memory order — a wavefront
//! at the granularity of half-planes (the level scheduling of sparse triangular solves,
//! applied to chunks of rows instead of single rows). A numbering that connects every chunk to
//! the one before it (bandwidth-reducing renumbering of unstructured meshes) gains nothing:
//! [`Schedule::for_rows`] measures the schedule's longest chain of dependent chunks and
//! declines (the sequential sweep is kept) when two threads could not save a fifth of the
//! sweep, or when a chunk would hold under [`MIN_USEFUL_CHUNK`] rows.
//!
//! Where half the reach is too little work for a chunk (half an x-line of a 2-D block: 160
//! rows of the 320² cavity, a microsecond), the chunks are the whole reach (an x-line) and the
//! waits are per block of [`GATE_BLOCK`] rows ([`Gates`]): a block waits only until each chunk
//! it reads from has done the rows it reads (counted from that chunk's start, or its end in a
//! backward sweep), so the next line follows this one a block behind — the 2-D wavefront at
//! the granularity of blocks. Each row still reads exactly what the sequential sweep reads
//! (tested with several chunk and block sizes). On the 320² cavity it is used for k and ε
//! only (their sweeps were sequential): U keeps the hybrid blocks and GAMG its levels' own
//! choice, which were faster there (30 steps: k and ε gated 0.913 / 0.955 / 0.964 of the time
//! without, everything gated 1.021 / 1.025 / 1.336; 5 pairs each, quiet machine).
//!
//! Threads claim chunks in increasing order from a shared counter and wait (spinning briefly,
//! then yielding) for the chunks theirs depends on; the smallest unfinished chunk therefore
//! always has its dependencies done and its claimer running, so the sweep cannot deadlock, and
//! a thread that finds no other thread to help sweeps all chunks alone, in order. The values
//! are shared as `AtomicU64` bit patterns with relaxed loads and stores (plain moves on
//! x86-64); a chunk's release of its "done" mark and the acquiring wait of a dependent chunk
//! order the writes and reads between threads.

use crate::ldu::{RowAddressing, RowMatrix};
use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize, Ordering};

/// Fewest rows per chunk of [`Schedule::chunked`].
const MIN_CHUNK: usize = 64;

/// Fewest rows per chunk of a schedule worth running: with chunks of half an x-line of the
/// 320² cavity (160 rows, a microsecond of work each) the waits cost more than the second
/// thread saves — 30 steps took 1.30 times as long as the sequential sweeps (3 interleaved
/// pairs, a loaded machine).
const MIN_USEFUL_CHUNK: usize = 1024;

/// Fewest rows per chunk of a gated schedule ([`Gates`]).
const MIN_GATED_CHUNK: usize = 128;

/// Rows per block of a gated schedule.
const GATE_BLOCK: usize = 32;

/// The least speed-up (rows / rows on the longest chain of dependent chunks) worth the threads.
const MIN_GAIN: f64 = 1.25;

/// A chunking of a matrix's rows and each chunk's dependencies, for both directions: fixed by
/// the mesh, kept with its [`RowAddressing`] ([`RowAddressing::pipeline`]).
#[derive(Debug)]
pub(crate) struct Schedule {
    /// Chunk boundaries: chunk i holds rows `bounds[i]..bounds[i + 1]`.
    bounds: Vec<usize>,
    /// The earlier chunks each chunk shares an entry with (CSR: `before_start`).
    before: Vec<u32>,
    before_start: Vec<u32>,
    /// The later chunks each chunk shares an entry with (CSR: `after_start`).
    after: Vec<u32>,
    after_start: Vec<u32>,
    /// Waits per block of rows instead of per chunk ([`Gates`]), where chunks are long.
    gates: Option<Gates>,
}

/// Row-level waits: a chunk's block of rows waits only until each chunk it depends on has
/// done the rows the block reads (counted from that chunk's start in a forward sweep, from
/// its end in a backward one), so two threads sweep consecutive chunks a block apart.
#[derive(Debug)]
struct Gates {
    /// Rows per block.
    block: usize,
    /// Per chunk (offsets `*_start`), per dependency in [`Schedule::deps`] order, per block:
    /// the rows of the dependency done before the block starts.
    fwd: Vec<u32>,
    fwd_start: Vec<u32>,
    bwd: Vec<u32>,
    bwd_start: Vec<u32>,
}

/// The sweeps of one solve on a [`Schedule`]: which chunks each sweep has finished.
pub(crate) struct Pipeline<'a> {
    schedule: &'a Schedule,
    /// Per chunk, the number of the last sweep that finished it (chunk-level waits only).
    done: Vec<AtomicU32>,
    /// Per chunk of a gated schedule: (sweep number << 32) | rows done in that sweep.
    progress: Vec<AtomicU64>,
    /// The number of the last sweep begun.
    epoch: u32,
}

impl<'a> Pipeline<'a> {
    /// The sweeps of one solve (the marks are the solve's own: solves side by side on the
    /// same mesh share the schedule, not the marks).
    pub(crate) fn new(schedule: &'a Schedule) -> Pipeline<'a> {
        Pipeline {
            schedule,
            done: (0..schedule.bounds.len() - 1)
                .map(|_| AtomicU32::new(0))
                .collect(),
            progress: match schedule.gates {
                Some(_) => (0..schedule.bounds.len() - 1)
                    .map(|_| AtomicU64::new(0))
                    .collect(),
                None => Vec::new(),
            },
            epoch: 0,
        }
    }

    /// One Gauss–Seidel sweep (forward, or backward: rows in reverse order) of `m` for the
    /// right-hand side `bp` over the triangular entries (the smoothSolver's sweep, see
    /// [`crate::sweep`]), on the threads of the current pool; the sequential sweep's bits.
    pub(crate) fn sweep(&mut self, m: &RowMatrix<'_>, bp: &[f64], x: &mut [f64], backward: bool) {
        let rows = m.rows;
        self.run(x, backward, |c, xa| {
            let mut s = bp[c];
            for k in rows.start[c] as usize..rows.end[c] as usize {
                s -= m.coef[k] * f64::from_bits(xa[rows.col[k] as usize].load(Ordering::Relaxed));
            }
            s / m.diag[c]
        });
    }

    /// Sets `x[c] = relax(c, x)` for every row c in sweep order (ascending, or descending when
    /// `backward`), the rows of independent chunks side by side on the current pool's threads;
    /// `relax` reads x through the shared view it is given. The bits of the sequential loop,
    /// provided `relax(c, ·)` reads only row c's columns in the schedule's matrix.
    pub(crate) fn run<F>(&mut self, x: &mut [f64], backward: bool, relax: F)
    where
        F: Fn(usize, &[AtomicU64]) -> f64 + Sync,
    {
        self.run_lanes::<1, _>(x, backward, |c, xa| [relax(c, xa)]);
    }

    /// [`Self::run`] for `L` values per row (`x[L c + l]`, lane l of row c): `relax(c, x)`
    /// gives row c's `L` new values.
    pub(crate) fn run_lanes<const L: usize, F>(&mut self, x: &mut [f64], backward: bool, relax: F)
    where
        F: Fn(usize, &[AtomicU64]) -> [f64; L] + Sync,
    {
        const _: () = assert!(
            std::mem::size_of::<AtomicU64>() == std::mem::size_of::<f64>()
                && std::mem::align_of::<AtomicU64>() == std::mem::align_of::<f64>()
        );
        let sched = self.schedule;
        assert_eq!(
            x.len(),
            L * sched.bounds[sched.bounds.len() - 1],
            "L values per row"
        );
        // SAFETY: AtomicU64 has the size and alignment of f64 (asserted above) and the same
        // bit validity as u64, whose every pattern is a valid f64; `x` is borrowed mutably for
        // the whole call, so no other reference reads or writes it meanwhile.
        let xa: &[AtomicU64] =
            unsafe { std::slice::from_raw_parts(x.as_mut_ptr().cast::<AtomicU64>(), x.len()) };
        self.epoch = self.epoch.wrapping_add(1);
        let epoch = self.epoch;
        let done = &self.done;
        let progress = &self.progress;
        let n_chunks = sched.bounds.len() - 1;
        let next = AtomicUsize::new(0);
        let one = |c: usize| {
            let v = relax(c, xa);
            for (l, v) in v.into_iter().enumerate() {
                xa[L * c + l].store(v.to_bits(), Ordering::Relaxed);
            }
        };
        let work = || loop {
            let claimed = next.fetch_add(1, Ordering::Relaxed);
            if claimed >= n_chunks {
                break;
            }
            let i = if backward {
                n_chunks - 1 - claimed
            } else {
                claimed
            };
            let (lo, hi) = (sched.bounds[i], sched.bounds[i + 1]);
            if let Some(gt) = &sched.gates {
                let deps = sched.deps(i, backward);
                let need = gt.table(i, backward);
                let nb = (hi - lo).div_ceil(gt.block);
                for b in 0..nb {
                    for (q, &d) in deps.iter().enumerate() {
                        wait_rows(&progress[d as usize], epoch, need[q * nb + b]);
                    }
                    let done_rows = ((b + 1) * gt.block).min(hi - lo);
                    if backward {
                        (hi - done_rows..hi - b * gt.block).rev().for_each(one);
                    } else {
                        (lo + b * gt.block..lo + done_rows).for_each(one);
                    }
                    progress[i].store(
                        (u64::from(epoch) << 32) | done_rows as u64,
                        Ordering::Release,
                    );
                }
                continue;
            }
            for &j in sched.deps(i, backward) {
                wait_for(&done[j as usize], epoch);
            }
            if backward {
                (lo..hi).rev().for_each(one);
            } else {
                (lo..hi).for_each(one);
            }
            done[i].store(epoch, Ordering::Release);
        };
        // Every thread of the team runs the claim loop; one thread alone finishes the sweep
        // (chunks are claimed in order, each waiting only on earlier ones).
        crate::team::run(rayon::current_num_threads(), &|_| work());
    }
}

impl Schedule {
    /// The schedule of the rows of `rows` (all their entries, interfaces included), or
    /// `None` when it would not pay (see the module doc).
    pub(crate) fn new(rows: &RowAddressing) -> Option<Schedule> {
        Schedule::for_rows(&rows.start, &rows.col)
    }

    /// The schedule of a matrix whose row i has its off-diagonal columns at
    /// `col[start[i]..start[i + 1]]`, or `None` when it would not pay (see the module doc).
    pub(crate) fn for_rows(start: &[u32], col: &[u32]) -> Option<Schedule> {
        let n = start.len() - 1;
        let row = |c: usize| col[start[c] as usize..start[c + 1] as usize].iter();
        // The typical distance back to a row's farthest lower neighbour.
        let mut reach: Vec<usize> = (0..n)
            .filter_map(|c| {
                row(c)
                    .map(|&j| j as usize)
                    .min()
                    .filter(|&lo| lo < c)
                    .map(|lo| c - lo)
            })
            .collect();
        if reach.is_empty() {
            return None;
        }
        let mid = reach.len() / 2;
        let typical = *reach.select_nth_unstable(mid).1;
        let size = (typical / 2).max(MIN_CHUNK);
        if size < MIN_USEFUL_CHUNK {
            // Chunks of the whole reach (an x-line of a 2-D blockMesh block) with waits per
            // block of rows: the next chunk follows this one a block behind.
            if typical < MIN_GATED_CHUNK {
                return None;
            }
            let mut p = Schedule::chunked(start, col, typical);
            p.gates = Some(Gates::new(&p, start, col, GATE_BLOCK));
            return (p.bounds.len() > 3).then_some(p);
        }
        let p = Schedule::chunked(start, col, size);
        (p.bounds.len() > 3 && p.gain() >= MIN_GAIN).then_some(p)
    }

    /// The schedule of chunks of `size` rows (the last one shorter).
    fn chunked(start: &[u32], col: &[u32], size: usize) -> Schedule {
        let n = start.len() - 1;
        let mut bounds: Vec<usize> = (0..n).step_by(size).collect();
        bounds.push(n);
        let n_chunks = bounds.len() - 1;
        let mut before = Vec::new();
        let mut before_start = vec![0u32];
        let mut after = Vec::new();
        let mut after_start = vec![0u32];
        let (mut lower, mut upper) = (Vec::new(), Vec::new());
        for i in 0..n_chunks {
            lower.clear();
            upper.clear();
            for &j in &col[start[bounds[i]] as usize..start[bounds[i + 1]] as usize] {
                let j = j as usize / size;
                if j < i {
                    lower.push(j as u32);
                } else if j > i {
                    upper.push(j as u32);
                }
            }
            for (list, starts, seen) in [
                (&mut before, &mut before_start, &mut lower),
                (&mut after, &mut after_start, &mut upper),
            ] {
                seen.sort_unstable();
                seen.dedup();
                list.extend_from_slice(seen);
                starts.push(list.len() as u32);
            }
        }
        Schedule {
            bounds,
            before,
            before_start,
            after,
            after_start,
            gates: None,
        }
    }

    /// Rows / rows on the longest chain of dependent chunks of a forward sweep: the speed-up
    /// unlimited threads could reach (the backward sweep's is the same: its chains are the
    /// forward ones reversed).
    fn gain(&self) -> f64 {
        let n_chunks = self.bounds.len() - 1;
        let mut chain = vec![0usize; n_chunks];
        for i in 0..n_chunks {
            let deps = self.deps(i, false);
            let longest = deps.iter().map(|&j| chain[j as usize]).max().unwrap_or(0);
            chain[i] = longest + self.bounds[i + 1] - self.bounds[i];
        }
        let n = self.bounds[n_chunks];
        n as f64 / chain.into_iter().max().unwrap_or(n) as f64
    }

    /// True for row-level waits.
    pub(crate) fn is_gated(&self) -> bool {
        self.gates.is_some()
    }

    /// The chunks chunk `i` waits for in a sweep in this direction.
    fn deps(&self, i: usize, backward: bool) -> &[u32] {
        if backward {
            &self.after[self.after_start[i] as usize..self.after_start[i + 1] as usize]
        } else {
            &self.before[self.before_start[i] as usize..self.before_start[i + 1] as usize]
        }
    }
}

impl Gates {
    /// The gates of `s`'s chunks for the matrix rows `start`/`col`, blocks of `block` rows.
    /// For each chunk, direction and chunk it waits for, per block (from the chunk's start in a
    /// forward sweep, from its end in a backward one): how many rows of that chunk, counted in
    /// the sweep's direction, the block and the blocks before it read.
    fn new(s: &Schedule, start: &[u32], col: &[u32], block: usize) -> Gates {
        let n_chunks = s.bounds.len() - 1;
        // [forward, backward]: the tables and where each chunk's part starts.
        let mut tables = [(Vec::new(), vec![0u32]), (Vec::new(), vec![0u32])];
        let cols = |r: usize| col[start[r] as usize..start[r + 1] as usize].iter();
        for i in 0..n_chunks {
            let (lo, hi) = (s.bounds[i], s.bounds[i + 1]);
            let nb = (hi - lo).div_ceil(block);
            for (backward, (table, table_start)) in [false, true].into_iter().zip(&mut tables) {
                for &d in s.deps(i, backward) {
                    let (dlo, dhi) = (s.bounds[d as usize], s.bounds[d as usize + 1]);
                    let mut need = 0usize;
                    for b in 0..nb {
                        let rows = if backward {
                            hi.saturating_sub((b + 1) * block).max(lo)..hi - b * block
                        } else {
                            lo + b * block..(lo + (b + 1) * block).min(hi)
                        };
                        for r in rows {
                            for &j in cols(r) {
                                let j = j as usize;
                                if (dlo..dhi).contains(&j) {
                                    let reach = if backward { dhi - j } else { j - dlo + 1 };
                                    need = need.max(reach);
                                }
                            }
                        }
                        table.push(need as u32);
                    }
                }
                table_start.push(table.len() as u32);
            }
        }
        let [(fwd, fwd_start), (bwd, bwd_start)] = tables;
        Gates {
            block,
            fwd,
            fwd_start,
            bwd,
            bwd_start,
        }
    }

    /// Chunk `i`'s table for a sweep in this direction (dependency-major, then block).
    fn table(&self, i: usize, backward: bool) -> &[u32] {
        if backward {
            &self.bwd[self.bwd_start[i] as usize..self.bwd_start[i + 1] as usize]
        } else {
            &self.fwd[self.fwd_start[i] as usize..self.fwd_start[i + 1] as usize]
        }
    }
}

/// Waits until `progress` shows at least `rows` rows done in sweep `epoch`.
fn wait_rows(progress: &AtomicU64, epoch: u32, rows: u32) {
    if rows > 0 {
        spin_until(|| {
            let v = progress.load(Ordering::Acquire);
            (v >> 32) as u32 == epoch && v as u32 >= rows
        });
    }
}

/// Waits until `done` reads `epoch`.
fn wait_for(done: &AtomicU32, epoch: u32) {
    spin_until(|| done.load(Ordering::Acquire) == epoch);
}

/// Waits until `ready()`: a short spin, then yielding the core (a machine with more runnable
/// threads than cores may have parked the thread that will make it true).
fn spin_until(ready: impl Fn() -> bool) {
    let mut spins = 0u32;
    while !ready() {
        if spins < 2000 {
            std::hint::spin_loop();
            spins += 1;
        } else {
            std::thread::yield_now();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::FvGeometry;
    use crate::ldu::Ldu;

    /// A non-symmetric, diagonally dominant matrix on the mesh of `g` with values that differ
    /// from row to row, so that any row reading a wrong neighbour value changes the bits.
    fn matrix(g: &FvGeometry) -> Ldu {
        let mut a = Ldu::zeros(g);
        for f in 0..g.n_internal {
            let d = g.mag_sf[f] * g.delta_coeff[f] * (1.0 + 0.3 * ((f % 17) as f64).sin());
            let flux = 0.3 * g.sf[f][0] + 0.1 * g.sf[f][1];
            a.upper[f] = -d - (-flux).max(0.0);
            a.lower[f] = -d - flux.max(0.0);
            a.diag[g.owner[f] as usize] += d + flux.max(0.0);
            a.diag[g.neighbour[f] as usize] += d + (-flux).max(0.0);
        }
        for (c, d) in a.diag.iter_mut().enumerate() {
            *d += g.v[c] * (1e3 + (c % 7) as f64);
        }
        a
    }

    /// Forward and backward sweeps on 1, 2 and 3 threads give the sequential sweep's bits,
    /// with the chosen chunking and with chunkings that leave little or nothing side by side.
    fn check(g: &FvGeometry, sizes: &[usize]) {
        let a = matrix(g);
        let m = RowMatrix::new(&a, g);
        let n = g.n_cells;
        let b: Vec<f64> = (0..n).map(|i| ((i * 7 % 13) as f64).sin() + 0.5).collect();
        // The sequential sweep: a Sweeper on one thread takes no pipeline.
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let expect = one.install(|| {
            let mut s = super::super::Sweeper::new(&g.rows, false);
            let mut x = vec![0.0; n];
            for i in 0..4 {
                s.sweep(&m, &b, &mut x, i % 2 == 1);
            }
            x
        });
        let mut schedules: Vec<(String, Schedule)> = sizes
            .iter()
            .map(|&size| {
                let s = Schedule::chunked(&g.rows.start, &g.rows.col, size);
                (format!("chunks of {size} rows"), s)
            })
            .collect();
        // The same chunkings with row-level waits, in blocks of 32 and of 7 rows.
        for &size in sizes {
            for block in [32, 7] {
                let mut s = Schedule::chunked(&g.rows.start, &g.rows.col, size);
                s.gates = Some(Gates::new(&s, &g.rows.start, &g.rows.col, block));
                schedules.push((format!("chunks of {size} rows, gates of {block}"), s));
            }
        }
        for (what, schedule) in &schedules {
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let x = pool.install(|| {
                    let mut p = Pipeline::new(schedule);
                    let mut x = vec![0.0; n];
                    for i in 0..4 {
                        p.sweep(&m, &b, &mut x, i % 2 == 1);
                    }
                    x
                });
                assert!(x == expect, "{what} on {threads} threads");
            }
        }
    }

    #[test]
    fn pipelined_sweeps_give_the_sequential_bits_in_3d() {
        let m = mesh::build::uniform_box([0.0; 3], [1.0, 0.8, 0.6], [80, 36, 20]);
        let g = FvGeometry::new(&m).unwrap();
        // Half a z-plane per chunk: 1440 rows, about twice as fast on two threads.
        let s = Schedule::new(&g.rows).unwrap();
        assert_eq!(s.bounds[1], 1440);
        assert!(s.gain() > 1.9, "{}", s.gain());
        check(&g, &[1440, MIN_CHUNK, 1000, g.n_cells / 3]);
    }

    #[test]
    fn pipelined_sweeps_give_the_sequential_bits_in_2d() {
        let mut m = mesh::build::uniform_box([0.0; 3], [1.0, 1.0, 0.1], [240, 220, 1]);
        for p in &mut m.boundary {
            if p.name.starts_with('z') {
                p.patch_type = "empty".into();
            }
        }
        let g = FvGeometry::new(&m).unwrap();
        // Half an x-line is too little work per chunk: whole x-lines with row-level waits.
        let s = Schedule::new(&g.rows).unwrap();
        assert!(s.is_gated() && s.bounds[1] == 240, "{:?}", &s.bounds[..2]);
        let half_lines = Schedule::chunked(&g.rows.start, &g.rows.col, 120);
        assert!(half_lines.gain() > 1.9, "{}", half_lines.gain());
        check(&g, &[240, 120, MIN_CHUNK, 1000, g.n_cells / 3]);
    }

    #[test]
    fn a_numbering_without_independent_chunks_keeps_the_sequential_sweep() {
        // One long x-line per plane row: every chunk touches the one before it.
        let m = mesh::build::uniform_box([0.0; 3], [1.0, 0.1, 0.1], [60_000, 1, 1]);
        let g = FvGeometry::new(&m).unwrap();
        assert!(Schedule::new(&g.rows).is_none());
        assert!(Schedule::chunked(&g.rows.start, &g.rows.col, 1000).gain() < 1.01);
    }
}
