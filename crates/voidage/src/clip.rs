//! Exact volume of an axis-aligned box ∩ polyhedron from its faces: the cube methods on general
//! (non-axis-aligned) meshes.
//!
//! # Method
//! Let B = [l, h] be the box and P a closed polyhedron with outward-oriented planar faces. The
//! vector field g(x) = (φ(x₁)·χ(x₂)·χ(x₃), 0, 0), with φ(x₁) = clamp(x₁ − l₁, 0, h₁ − l₁) and χ
//! the indicators of [l₂, h₂] and [l₃, h₃], has divergence 1 inside B and 0 outside, so by the
//! divergence theorem
//!
//! vol(B ∩ P) = Σ_F ∫_F g·n dS = Σ_F ∫_{F ∩ S} φ(x₁) n₁ dS,
//!
//! S the slab l₂ ≤ x₂ ≤ h₂, l₃ ≤ x₃ ≤ h₃. Each face is clipped to S (Sutherland–Hodgman, four
//! planes, only those crossing the face's bounding box), and since φ(x₁) = ψ(x₁ − l₁) −
//! ψ(x₁ − h₁) with ψ(t) = max(t, 0), the face term is M(l₁) − M(h₁) with
//! M(a) = ∫_{F ∩ S ∩ {x₁ ≥ a}} (x₁ − a) n₁ dS, the first moment of the part beyond a: clipped
//! once more and integrated exactly over its fan of triangles (area vector's x₁ component
//! times the mean of x₁ − a at the vertices, exact for the linear integrand). Every step is
//! linear interpolation and products, so the volume is exact up to rounding.
//!
//! The face term ([`box_polygon_flux`]) is odd under reversing the face's orientation, so a
//! face shared by two cells is computed once; a tet's volume is the sum over its four faces
//! ([`box_tet_volume`]).

use crate::sphere_poly::TET_FACES;
use mesh::v3::V3;

/// Scratch space for [`box_polygon_flux`]: two vertex buffers.
#[derive(Clone, Debug, Default)]
pub struct ClipScratch {
    a: Vec<V3>,
    b: Vec<V3>,
}

/// Keeps the part of the polygon `from` where `s·(x_axis − value) ≤ 0`, into `to`.
fn clip_polygon(from: &[V3], to: &mut Vec<V3>, axis: usize, value: f64, s: f64) {
    to.clear();
    let n = from.len();
    for i in 0..n {
        let p = from[i];
        let q = from[if i + 1 == n { 0 } else { i + 1 }];
        let (dp, dq) = (s * (p[axis] - value), s * (q[axis] - value));
        if dp <= 0.0 {
            to.push(p);
        }
        if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
            let t = dp / (dp - dq);
            let mut x = V3::from_fn(|a, _| p[a] + t * (q[a] - p[a]));
            x[axis] = value;
            to.push(x);
        }
    }
}

/// M(a) = ∫ (x₀ − a) n₀ dS over the part of the planar polygon `poly` with x₀ ≥ a (module
/// docs): its fan triangles, clipped on the fly.
fn moment_beyond(poly: &[V3], a: f64) -> f64 {
    let mut first: Option<V3> = None;
    let mut prev: Option<V3> = None;
    let mut sum = 0.0;
    let mut emit = |w: V3| {
        match (first, prev) {
            (Some(w0), Some(wk)) => {
                let ax = (wk[1] - w0[1]) * (w[2] - w0[2]) - (wk[2] - w0[2]) * (w[1] - w0[1]);
                sum += ax * ((w0[0] - a) + (wk[0] - a) + (w[0] - a));
            }
            (None, _) => first = Some(w),
            _ => {}
        }
        prev = Some(w);
    };
    let n = poly.len();
    for i in 0..n {
        let p = poly[i];
        let q = poly[if i + 1 == n { 0 } else { i + 1 }];
        let (dp, dq) = (p[0] - a, q[0] - a);
        if dp >= 0.0 {
            emit(p);
        }
        if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
            let t = dp / (dp - dq);
            emit(V3::new(
                a,
                p[1] + t * (q[1] - p[1]),
                p[2] + t * (q[2] - p[2]),
            ));
        }
    }
    // ½ for the triangle area, ⅓ for the mean.
    sum / 6.0
}

/// The term of the planar polygon `poly` (vertices counter-clockwise about its outward normal)
/// in the volume of the axis-aligned box `lo`..`hi` ∩ a closed polyhedron having it as a face,
/// m³ (module docs). Odd under reversing the vertex order; the terms of a closed polyhedron's
/// faces sum to the volume of box ∩ polyhedron. `s` is scratch space.
pub fn box_polygon_flux(
    lo: impl Into<V3>,
    hi: impl Into<V3>,
    poly: &[V3],
    s: &mut ClipScratch,
) -> f64 {
    let (lo, hi) = (lo.into(), hi.into());
    if poly.len() < 3 {
        return 0.0;
    }
    let mut pmin = poly[0];
    let mut pmax = poly[0];
    for p in &poly[1..] {
        pmin = pmin.inf(p);
        pmax = pmax.sup(p);
    }
    if pmax[0] <= lo[0] || (1..3).any(|a| pmax[a] <= lo[a] || pmin[a] >= hi[a]) {
        return 0.0;
    }
    s.a.clear();
    s.a.extend_from_slice(poly);
    for axis in 1..3 {
        for (value, sign, cuts) in [
            (lo[axis], -1.0, pmin[axis] < lo[axis]),
            (hi[axis], 1.0, pmax[axis] > hi[axis]),
        ] {
            if cuts {
                clip_polygon(&s.a, &mut s.b, axis, value, sign);
                std::mem::swap(&mut s.a, &mut s.b);
                if s.a.len() < 3 {
                    return 0.0;
                }
            }
        }
    }
    let cur = &s.a[..];
    let beyond_hi = if pmax[0] > hi[0] {
        moment_beyond(cur, hi[0])
    } else {
        0.0
    };
    moment_beyond(cur, lo[0]) - beyond_hi
}

/// Volume of the axis-aligned box `lo`..`hi` ∩ the tetrahedron `tet`, m³, signed like
/// [`mesh::tet_volume`] (negative for a negatively oriented tet): the sum of the terms of its
/// four faces ([`box_polygon_flux`]). `s` is scratch space.
pub fn box_tet_volume(
    lo: impl Into<V3>,
    hi: impl Into<V3>,
    tet: &[V3; 4],
    s: &mut ClipScratch,
) -> f64 {
    let (lo, hi) = (lo.into(), hi.into());
    TET_FACES
        .iter()
        .map(|f| box_polygon_flux(lo, hi, &[tet[f[0]], tet[f[1]], tet[f[2]]], s))
        .sum()
}
