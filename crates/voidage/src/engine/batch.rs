//! The parallel work items of a deposit: a batch of particles cut into chunks of [`CHUNK`],
//! in index order or in the order of their centre's cell, each chunk computed on one thread
//! with its own scratch space into a list of (cell, volume) shares.

use super::{Ball, ParticleSet, Scratch, VoidageMesh};
use crate::memo::MemoEntry;
use crate::method::Method;
use crate::sphere_box::ball_volume;
use foam::Label;
use rayon::prelude::*;

/// Particles per parallel work item.
pub(super) const CHUNK: usize = 1024;

/// Work items per batch (bounds the memory of the share lists).
pub(super) const BATCH: usize = 64;

/// What one work item produced.
pub(super) struct ChunkOut {
    pub(super) shares: Vec<(Label, f64)>,
    /// Number of entries of `shares` per particle of the work item, in order.
    pub(super) counts: Vec<u32>,
    pub(super) outside: f64,
    pub(super) volume: f64,
    pub(super) fully_outside: usize,
    pub(super) partly_outside: usize,
    /// With a memo: each particle's new entry, in order.
    pub(super) memo: Vec<MemoEntry>,
    /// With a memo: particles whose kept entry was used.
    pub(super) reused: usize,
}

/// What one batch of work items produced.
pub(super) struct BatchOut {
    /// Index of the batch's first particle.
    pub(super) start: usize,
    /// The particles in the order computed, when not in index order.
    pub(super) order: Option<Vec<u32>>,
    /// The work items: `CHUNK` particles each, in that order.
    pub(super) chunks: Vec<ChunkOut>,
}

impl VoidageMesh {
    /// The work items of the particles `range`, in parallel: in index order, or with `sort` in
    /// the order of their centre's cell (then `order` holds that order).
    pub(super) fn batch(
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
}
