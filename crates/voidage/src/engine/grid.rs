//! `exact`, `cube` and `corrected-cube` on an axis-aligned grid ([`mesh::AxisGrid`]): the
//! cells by grid index, the volumes in closed form (module docs of [`crate::engine`]).

use super::{Ball, Scratch};
use crate::cube::{cube_axis_fraction, khawaja_correction};
use crate::sphere_box::{cut_ball_unit, sphere_grid_volumes};
use foam::Label;
use mesh::AxisGrid;

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
pub(super) fn grid_exact(
    g: &AxisGrid,
    b: Ball,
    s: &mut Scratch,
    out: &mut Vec<(Label, f64)>,
) -> f64 {
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
pub(super) fn grid_cube(
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
