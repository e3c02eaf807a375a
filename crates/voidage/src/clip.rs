//! Exact volume of an axis-aligned box ∩ tetrahedron by clipping: the cube methods on general
//! (non-axis-aligned) meshes.
//!
//! The tet is clipped successively by the six half-spaces of the box. Against one plane a tet
//! keeps 0 to 4 vertices; the kept part is empty, the tet itself, a tet (1 vertex kept) or a
//! triangular prism (2 or 3 kept), and a prism is split into 3 tets. The plane intersection
//! points are linear interpolations along the cut edges, so the volume is exact up to rounding.
//! Only planes that cut the current piece's bounding box are applied.

use mesh::tet_volume;
use mesh::v3::V3;

type Tet = [V3; 4];

/// Volume of the axis-aligned box `lo`..`hi` ∩ the tetrahedron `tet`, m³, signed like
/// [`mesh::tet_volume`] (negative for a negatively oriented tet). `stack` is scratch space.
pub fn box_tet_volume(
    lo: impl Into<V3>,
    hi: impl Into<V3>,
    tet: &Tet,
    stack: &mut Vec<Tet>,
) -> f64 {
    let (lo, hi) = (lo.into(), hi.into());
    let full = tet_volume(tet);
    let sign = if full < 0.0 { -1.0 } else { 1.0 };
    let (tlo, thi) = bounds(tet);
    if (0..3).any(|a| thi[a] <= lo[a] || tlo[a] >= hi[a]) {
        return 0.0;
    }
    if (0..3).all(|a| tlo[a] >= lo[a] && thi[a] <= hi[a]) {
        return full;
    }
    stack.clear();
    stack.push(*tet);
    for a in 0..3 {
        // Keep x_a ≥ lo_a: distance f = lo_a − x_a ≤ 0; keep x_a ≤ hi_a: f = x_a − hi_a ≤ 0.
        for (value, s) in [(lo[a], -1.0), (hi[a], 1.0)] {
            let cuts = (s < 0.0 && tlo[a] < value) || (s > 0.0 && thi[a] > value);
            if cuts {
                clip(stack, |p: &V3| s * (p[a] - value));
            }
        }
    }
    sign * stack.iter().map(|t| tet_volume(t).abs()).sum::<f64>()
}

fn bounds(t: &Tet) -> (V3, V3) {
    let mut lo = t[0];
    let mut hi = t[0];
    for p in &t[1..] {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

/// Replaces every tet of `stack` by its part where `f ≤ 0`.
fn clip(stack: &mut Vec<Tet>, f: impl Fn(&V3) -> f64) {
    let n = stack.len();
    for idx in 0..n {
        let t = stack[idx];
        let d = t.map(|p| f(&p));
        let (mut keep, mut drop) = ([0usize; 4], [0usize; 4]);
        let (mut nk, mut nd) = (0, 0);
        for (i, &di) in d.iter().enumerate() {
            if di <= 0.0 {
                keep[nk] = i;
                nk += 1;
            } else {
                drop[nd] = i;
                nd += 1;
            }
        }
        // Point on edge i–j where f = 0.
        let cut = |i: usize, j: usize| -> V3 {
            let s = d[i] / (d[i] - d[j]);
            V3::from_fn(|a, _| t[i][a] + s * (t[j][a] - t[i][a]))
        };
        match nk {
            4 => continue,
            0 => stack[idx] = [V3::zeros(); 4],
            1 => {
                let i = keep[0];
                stack[idx] = [t[i], cut(i, drop[0]), cut(i, drop[1]), cut(i, drop[2])];
            }
            3 => {
                let l = drop[0];
                let [i, j, k] = [keep[0], keep[1], keep[2]];
                let prism = [t[i], t[j], t[k], cut(i, l), cut(j, l), cut(k, l)];
                stack[idx] = prism_tet(&prism, 0);
                stack.push(prism_tet(&prism, 1));
                stack.push(prism_tet(&prism, 2));
            }
            _ => {
                let [i, j] = [keep[0], keep[1]];
                let [k, l] = [drop[0], drop[1]];
                let prism = [t[i], cut(i, k), cut(i, l), t[j], cut(j, k), cut(j, l)];
                stack[idx] = prism_tet(&prism, 0);
                stack.push(prism_tet(&prism, 1));
                stack.push(prism_tet(&prism, 2));
            }
        }
    }
}

/// Tet `k` (0..3) of the prism with triangles (p0, p1, p2) and (p3, p4, p5), pᵢ and pᵢ₊₃ joined
/// by the side edges.
fn prism_tet(p: &[V3; 6], k: usize) -> Tet {
    match k {
        0 => [p[0], p[1], p[2], p[3]],
        1 => [p[1], p[2], p[3], p[4]],
        _ => [p[2], p[3], p[4], p[5]],
    }
}
