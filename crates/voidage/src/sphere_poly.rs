//! Exact volume of a ball ∩ tetrahedron (and any closed polyhedron with triangular faces) by the
//! divergence theorem, reduced to exact integrals over the planar faces.
//!
//! # Derivation
//! Let B be the ball of radius R centred at c and P a polyhedron with outward-oriented planar
//! faces F. For any point c, the indicator of P is the signed sum of the indicators of the
//! pyramids conv(c, F) (sign + when c lies on the inner side of F's plane). Intersect each
//! pyramid with B, which is centred at its apex: along each direction u through F the pyramid
//! ∩ B is the segment from c of length min(R, t_F(u)), t_F the distance to F's plane, so
//!
//! vol(B ∩ conv(c, F)) = (|d|/3)·area(F ∩ D) + (R³/3)·Ω(F \ D),
//!
//! d the signed distance from c to F's plane (positive on the inner side), D the disk cut from
//! that plane by B (radius ρ = √(R² − d²), centred at the foot point p₀ of c), and Ω the solid
//! angle seen from c. Summing with signs,
//!
//! vol(B ∩ P) = Σ_F [ d/3 · area(F ∩ D) + R³/3 · Ω_d(F \ D) ],
//!
//! where Ω_d carries the sign of d. This is the flux form ⅓∮(x − c)·n dS of the volume of
//! B ∩ P: each face's term ([`triangle_flux`]) is odd under reversing the face's orientation, so
//! the terms of a face shared by two cells cancel, the decomposition of a cell into tetrahedra
//! gives the same volume as its boundary triangles, and shares over the cells of a mesh sum to
//! the volume of the ball inside the mesh.
//!
//! Each face integral is split into the signed fan of triangles (p₀, a, b) over the edges (a, b)
//! of F. In polar coordinates about p₀ an edge is the line at distance p from p₀, points at
//! parameter τ along it, angle φ = atan2(τ, |p|); inside the disk (|τ| ≤ τ* = √(ρ² − p²)) the
//! fan triangle is bounded by the edge, outside by the circle. With ψ(τ) = atan2(dτ, |p|·√(d² +
//! p² + τ²)) (the solid-angle primitive of a triangle with a vertex at p₀):
//!
//! * edge part τ₁..τ₂: area ½|p|(τ₂ − τ₁), no solid angle beyond the disk;
//! * arc part τ₁..τ₂: area ½ρ²(φ₂ − φ₁), solid angle (d/R)(φ₂ − φ₁) − (ψ₂ − ψ₁)
//!   (for |d| ≥ R there is no disk and the ratio d/R becomes sign(d));
//!
//! each multiplied by sign(p). All terms are elementary (square roots and `atan2`), so the volume
//! is exact up to rounding — the same quantity as the caps, wedges and vertex terms of Strobl,
//! Formella & Pöschel (J. Comput. Phys. 311 (2016) 158–172), organised by faces instead.
//!
//! Fast paths: a face inside the ball gives the pyramid volume det(a, b, c)/6; a face whose plane
//! misses the ball gives R³/3 times its signed solid angle (Van Oosterom & Strackee, IEEE Trans.
//! Biomed. Eng. 30 (1983) 125–126); a tetrahedron inside the ball gives its volume; one whose
//! bounding box misses the ball gives 0.
//!
//! # Cap form
//! The solid angles of a closed cell's faces sum to 4π·w, w = 1 when the centre lies inside the
//! cell and 0 outside, so
//!
//! vol(B ∩ P) = w·vol(B) + Σ_F g(F),  g(F) = flux(F) − R³Ω(F)/3 = d/3·area(F ∩ D) − R³/3·Ω(F ∩ D),
//!
//! in which a face that misses the ball (F ∩ D = ∅) has no term at all, where the flux form has
//! its solid angle. Over the fan about p₀, F ∩ D is the parts of the fan triangles inside the
//! disk: for each edge the section inside the disk (a flat triangle: area ½|p|Δτ, solid angle
//! sign(d)Δφ − Δψ) and circular sectors (area ½ρ²Δφ, solid angle (sign(d) − d/R)Δφ); the sectors'
//! angles sum to 2π·(winding number of p₀ in F) minus the sections' Δφ, so only edges crossing
//! the disk cost trigonometry. The winding number comes from crossings of a ray, without angles.
//! The form is exact, but w must be known: the caller takes it from point location, which is
//! why a centre within rounding of a face (where w is not certain from the face) uses the flux
//! form instead. Faces shared by two cells keep their term odd under reversal.
//!
//! Accuracy: absolute errors of a few ulps of R³; computed on the unit ball (coordinates
//! relative to c divided by R), so any scale works.

use crate::vec3::{to_unit, V3};

/// The signed solid angle of the triangle (a, b, c) seen from the origin, from the vertex
/// lengths `l` and the triple product `det` = a·(b × c) (Van Oosterom & Strackee):
/// Ω = 2·atan2(det, |a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|).
#[inline]
fn solid_angle(v: &[V3; 3], l: [f64; 3], det: f64) -> f64 {
    let den = l[0] * l[1] * l[2]
        + v[0].dot(&v[1]) * l[2]
        + v[0].dot(&v[2]) * l[1]
        + v[1].dot(&v[2]) * l[0];
    2.0 * det.atan2(den)
}

/// An edge a → b of a face seen from the foot point p₀ of the centre on the face plane (unit
/// ball, module docs): the sign of p (+1 when the fan triangle (p₀, a, b) turns positively about
/// the face normal), |p| the distance from p₀ to the edge's line, and the parameters τ of a and
/// b along the line (τ = 0 at the point nearest p₀).
#[derive(Clone, Copy, Debug)]
struct EdgeFrame {
    s: f64,
    ap: f64,
    ta: f64,
    tb: f64,
}

impl EdgeFrame {
    /// The frame of a → b on the plane of unit normal `nh`; `None` for a zero-length edge. An
    /// edge whose line passes through p₀ has `s` = 0 (its fan triangle is flat).
    #[inline]
    fn new(a: V3, b: V3, nh: V3) -> Option<EdgeFrame> {
        EdgeAxes::new(a, b, nh).frame(a, b)
    }

    /// The frame of a → b from the edge's unit direction `t` and `m` = t × n̂ (both computed
    /// once per mesh edge: [`EdgeAxes`]); the same as [`EdgeFrame::new`] up to the rounding
    /// of t.
    #[inline]
    fn along(a: V3, b: V3, t: V3, m: V3) -> EdgeFrame {
        let p = a.dot(&m);
        EdgeFrame {
            s: if p > 0.0 {
                1.0
            } else if p < 0.0 {
                -1.0
            } else {
                0.0
            },
            ap: p.abs(),
            ta: a.dot(&t),
            tb: b.dot(&t),
        }
    }

    /// Distance from the centre to the point at τ = x, for a plane at signed distance `d`.
    #[inline]
    fn dist(&self, d: f64, x: f64) -> f64 {
        (d * d + self.ap * self.ap + x * x).sqrt()
    }

    /// (Δφ, Δψ) over x1..x2 (x1 < x2), r1, r2 the distances from the centre to the points at
    /// x1, x2: the angle at p₀ and the solid-angle primitive ψ(τ) = atan2(dτ, |p|·r(τ)) (module
    /// docs), each one atan2 of an angle difference.
    #[inline]
    fn angles(&self, d: f64, x1: f64, x2: f64, r1: f64, r2: f64) -> (f64, f64) {
        let ap = self.ap;
        let dphi = (ap * (x2 - x1)).atan2(ap * ap + x1 * x2);
        let (y1, w1) = (d * x1, ap * r1);
        let (y2, w2) = (d * x2, ap * r2);
        let dpsi = (y2 * w1 - y1 * w2).atan2(w1 * w2 + y1 * y2);
        (dphi, dpsi)
    }
}

/// The edge (a → b) terms of a face's flux on the unit ball (module docs): (area of the fan
/// triangle (p₀, a, b) ∩ disk, solid angle of its part beyond the disk), signed; `nh` the face's
/// unit normal, `d` the signed distance of the plane, `rho2` = 1 − d² > 0.
#[inline]
fn edge_terms(a: V3, b: V3, nh: V3, d: f64, rho2: f64) -> (f64, f64) {
    let Some(e) = EdgeFrame::new(a, b, nh).filter(|e| e.s != 0.0) else {
        return (0.0, 0.0);
    };
    let EdgeFrame { s, ap, ta, tb } = e;
    let mut ae = 0.0;
    let mut oe = 0.0;
    // Arc part over [x1, x2]: (area, solid angle).
    let mut arc = |ae: &mut f64, x1: f64, x2: f64, r1: f64, r2: f64| {
        if x2 > x1 {
            let (dphi, dpsi) = e.angles(d, x1, x2, r1, r2);
            *ae += 0.5 * rho2 * dphi;
            oe += d * dphi - dpsi;
        }
    };
    if ap * ap < rho2 {
        let ts = (rho2 - ap * ap).sqrt();
        let (l1, l2) = (ta.max(-ts), tb.min(ts));
        if l2 > l1 {
            ae += 0.5 * ap * (l2 - l1);
        }
        if ta < -ts {
            let x2 = tb.min(-ts);
            let r2 = if x2 == -ts { 1.0 } else { e.dist(d, x2) };
            arc(&mut ae, ta, x2, e.dist(d, ta), r2);
        }
        if tb > ts {
            let x1 = ta.max(ts);
            let r1 = if x1 == ts { 1.0 } else { e.dist(d, x1) };
            arc(&mut ae, x1, tb, r1, e.dist(d, tb));
        }
    } else {
        arc(&mut ae, ta, tb, e.dist(d, ta), e.dist(d, tb));
    }
    (s * ae, s * oe)
}

/// w = n̂ × e, e the unit axis least aligned with n̂ (the first of equals): a direction in the
/// plane, for the winding number's ray. Written out per axis: building e as a vector on the
/// stack and loading it back cost 11 % of the exact kernel's time (a stalled store forward).
#[inline]
fn ray_direction(nh: V3) -> V3 {
    let a = nh.map(f64::abs);
    if a[0] <= a[1] && a[0] <= a[2] {
        V3::new(0.0, nh[2], -nh[1])
    } else if a[1] <= a[2] {
        V3::new(-nh[2], 0.0, nh[0])
    } else {
        V3::new(nh[1], -nh[0], 0.0)
    }
}

/// The cap form of a planar polygon's term on the unit ball: g = flux − Ω/3 = (d·area(F ∩ D) −
/// Ω(F ∩ D))/3, Ω(F) the polygon's signed solid angle seen from the centre and F ∩ D its part
/// inside the disk the ball cuts from its plane (module docs, "Cap form"). `v` are the vertices
/// (counter-clockwise about the outward unit normal `nh`), `d` the signed distance of the plane
/// (n̂·v for any vertex v). Zero unless the polygon meets the ball, and then only the edges
/// crossing the disk cost trigonometry.
///
/// `None` when the centre is within `tie` of the plane while the polygon meets the ball, or the
/// foot point p₀ is within `tie` of an edge: the caller must then use the flux form.
pub(crate) fn polygon_cap_unit(v: &[V3], nh: V3, d: f64, tie: f64) -> Option<f64> {
    polygon_cap_unit_with(v, nh, d, tie, |_, a, b| EdgeFrame::new(a, b, nh))
}

/// The directions of a planar polygon's edges, for [`polygon_cap_unit_axes`]: for the edge
/// from vertex k to vertex k + 1, its unit direction t (zero for a zero-length edge) and
/// t × n̂. They do not depend on the ball, so a mesh computes them once per face.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct EdgeAxes {
    t: V3,
    m: V3,
}

impl EdgeAxes {
    /// The axes of the edge a → b (any coordinates) of a polygon with unit normal `nh`.
    pub(crate) fn new(a: V3, b: V3, nh: V3) -> EdgeAxes {
        let e = b - a;
        let le = e.norm();
        if !(le > 0.0) {
            return EdgeAxes::default();
        }
        let t = V3::new(e[0] / le, e[1] / le, e[2] / le);
        EdgeAxes { t, m: t.cross(&nh) }
    }
}

impl EdgeAxes {
    /// The frame of the edge a → b (unit-ball coordinates) along these axes; `None` for a
    /// zero-length edge.
    #[inline]
    fn frame(self, a: V3, b: V3) -> Option<EdgeFrame> {
        (self.t != V3::zeros()).then(|| EdgeFrame::along(a, b, self.t, self.m))
    }
}

/// [`polygon_cap_unit`] with the edges' directions given (`axes[k]` for the edge from `v[k]`):
/// per edge three dot products instead of a square root, three divisions and a cross product.
/// The result differs from [`polygon_cap_unit`]'s by rounding only.
pub(crate) fn polygon_cap_unit_axes(
    v: &[V3],
    axes: &[EdgeAxes],
    nh: V3,
    d: f64,
    tie: f64,
) -> Option<f64> {
    debug_assert_eq!(v.len(), axes.len());
    polygon_cap_unit_with(v, nh, d, tie, |k, a, b| axes[k].frame(a, b))
}

/// [`polygon_cap_unit`] with `frame(k, a, b)` the frame of the edge a → b from vertex k.
#[inline(always)]
fn polygon_cap_unit_with(
    v: &[V3],
    nh: V3,
    d: f64,
    tie: f64,
    frame: impl Fn(usize, V3, V3) -> Option<EdgeFrame>,
) -> Option<f64> {
    let n = v.len();
    if n < 3 {
        return Some(0.0);
    }
    if !(d.abs() < 1.0) {
        return Some(0.0);
    }
    let rho2 = 1.0 - d * d;
    let p0 = nh * d;
    // The winding number of p₀ counts the crossings of the in-plane ray from p₀ along w × n̂,
    // w = n̂ × (the axis least aligned with n̂).
    let w = ray_direction(nh);
    let (mut area_in, mut phi_in, mut psi_in) = (0.0, 0.0, 0.0);
    let mut winding = 0i32;
    let mut crossed = false;
    let mut yb = (v[0] - p0).dot(&w);
    for k in 0..n {
        let a = v[k];
        let b = v[if k + 1 == n { 0 } else { k + 1 }];
        // Winding number of p₀ (crossings of the ray from p₀ along u).
        let ya = yb;
        yb = (b - p0).dot(&w);
        if (ya <= 0.0) != (yb <= 0.0) {
            let left = (a - p0).cross(&(b - p0)).dot(&nh);
            if ya <= 0.0 && left > 0.0 {
                winding += 1;
            } else if yb <= 0.0 && left < 0.0 {
                winding -= 1;
            }
        }
        // An edge beyond a face of the ball's box (with the tie margin) misses the disk.
        let reach = 1.0 + 2.0 * tie;
        if (0..3).any(|i| (a[i] > reach && b[i] > reach) || (a[i] < -reach && b[i] < -reach)) {
            continue;
        }
        let Some(e) = frame(k, a, b) else {
            continue;
        };
        if e.ap < tie && e.ta < tie && e.tb > -tie {
            // p₀ on or next to the edge: its winding number is not certain.
            return None;
        }
        if e.ap * e.ap >= rho2 {
            continue;
        }
        let ts = (rho2 - e.ap * e.ap).sqrt();
        let (l1, l2) = (e.ta.max(-ts), e.tb.min(ts));
        if l2 > l1 {
            let r1 = if l1 == -ts { 1.0 } else { e.dist(d, l1) };
            let r2 = if l2 == ts { 1.0 } else { e.dist(d, l2) };
            let (dphi, dpsi) = e.angles(d, l1, l2, r1, r2);
            area_in += e.s * 0.5 * e.ap * (l2 - l1);
            phi_in += e.s * dphi;
            psi_in += e.s * dpsi;
            crossed = true;
        }
    }
    if winding == 0 && !crossed {
        // No edge crosses the disk and p₀ is outside: the polygon misses the ball.
        return Some(0.0);
    }
    if d.abs() < tie && winding != 0 {
        // The centre next to the polygon: which side it is on is not certain.
        return None;
    }
    let sd = d.signum();
    let phi_arc = 2.0 * std::f64::consts::PI * winding as f64 - phi_in;
    let area = area_in + 0.5 * rho2 * phi_arc;
    let omega = sd * phi_in - psi_in + (sd - d) * phi_arc;
    Some((d * area - omega) / 3.0)
}

/// Flux term of one oriented triangle on the unit ball centred at the origin (module docs):
/// its contribution to vol(unit ball ∩ P) for a polyhedron P having it as a face with the normal
/// (v₁ − v₀) × (v₂ − v₀) pointing out of P.
pub(crate) fn triangle_flux_unit(v: &[V3; 3]) -> f64 {
    let n = (v[1] - v[0]).cross(&(v[2] - v[0]));
    let nn = n.norm();
    if !(nn > 0.0) {
        return 0.0;
    }
    let det = v[0].dot(&v[1].cross(&v[2]));
    let l = [v[0].norm(), v[1].norm(), v[2].norm()];
    if l[0] <= 1.0 && l[1] <= 1.0 && l[2] <= 1.0 {
        return det / 6.0;
    }
    let inv = 1.0 / nn;
    let nh = V3::new(n[0] * inv, n[1] * inv, n[2] * inv);
    let d = v[0].dot(&nh);
    if d.abs() >= 1.0 {
        return solid_angle(v, l, det) / 3.0;
    }
    let rho2 = 1.0 - d * d;
    let (mut area, mut omega) = (0.0, 0.0);
    for k in 0..3 {
        let (a, o) = edge_terms(v[k], v[(k + 1) % 3], nh, d, rho2);
        area += a;
        omega += o;
    }
    (d * area + omega) / 3.0
}

/// Most vertices of a planar polygon handled by [`polygon_flux_unit`].
pub(crate) const MAX_POLYGON: usize = 64;

/// Flux term of a *planar* polygon (at most [`MAX_POLYGON`] vertices `v`, unit-ball
/// coordinates, ordered counter-clockwise about the outward normal) with area vector
/// `area_vec` (outward, magnitude = area in unit-ball units): the same as the sum over any fan of its triangles,
/// since the fan's inner edges cancel, with one edge term per polygon edge.
pub(crate) fn polygon_flux_unit(v: &[V3], area_vec: V3) -> f64 {
    let n = v.len();
    let area = area_vec.norm();
    if !(area > 0.0) || !(3..=MAX_POLYGON).contains(&n) {
        return 0.0;
    }
    let nh = area_vec.map(|x| x / area);
    let d = v.iter().map(|p| (*p).dot(&nh)).sum::<f64>() / n as f64;
    let mut l = [0.0; MAX_POLYGON];
    let mut inside = true;
    for (li, p) in l.iter_mut().zip(v) {
        *li = (*p).norm();
        inside &= *li <= 1.0;
    }
    if inside {
        return d * area / 3.0;
    }
    if d.abs() >= 1.0 {
        let mut omega = 0.0;
        for i in 1..n - 1 {
            let t = [v[0], v[i], v[i + 1]];
            let det = t[0].dot(&t[1].cross(&t[2]));
            omega += solid_angle(&t, [l[0], l[i], l[i + 1]], det);
        }
        return omega / 3.0;
    }
    let rho2 = 1.0 - d * d;
    let (mut a_sum, mut omega) = (0.0, 0.0);
    for k in 0..n {
        let (a, o) = edge_terms(v[k], v[if k + 1 == n { 0 } else { k + 1 }], nh, d, rho2);
        a_sum += a;
        omega += o;
    }
    (d * a_sum + omega) / 3.0
}

/// The flux term of the oriented triangle `tri` (m) for the ball (centre `centre`, radius
/// `r` > 0), m³: its contribution to the volume of ball ∩ P for any closed polyhedron P having
/// `tri` as a face with normal (v₁ − v₀) × (v₂ − v₀) pointing out of P (module docs). Odd under
/// reversing the orientation.
pub fn triangle_flux(centre: impl Into<V3>, r: f64, tri: &[V3; 3]) -> f64 {
    let centre = centre.into();
    if !(r > 0.0) {
        return 0.0;
    }
    let inv = 1.0 / r;
    let v = tri.map(|p| to_unit(p, centre, inv));
    triangle_flux_unit(&v) * r * r * r
}

/// The faces of the tet (a, b, c, d), outward for a positively oriented tet
/// ((b − a)·((c − a) × (d − a)) > 0), as vertex indices.
pub const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// Exact volume of the ball (centre `centre`, radius `r`) ∩ the tetrahedron `tet`, m³, signed
/// like [`mesh::tet_volume`]: positive for a positively oriented tet
/// ((b − a)·((c − a) × (d − a)) > 0), negative otherwise. Module docs for the method.
pub fn sphere_tet_volume(centre: impl Into<V3>, r: f64, tet: &[V3; 4]) -> f64 {
    let centre = centre.into();
    if !(r > 0.0) {
        return 0.0;
    }
    let inv = 1.0 / r;
    let v = tet.map(|p| to_unit(p, centre, inv));
    let r3 = r * r * r;
    // Bounding box misses the ball: nothing.
    let mut near = 0.0;
    let mut inside = true;
    for a in 0..3 {
        let lo = v.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min);
        let hi = v.iter().map(|p| p[a]).fold(f64::NEG_INFINITY, f64::max);
        near += crate::sphere_box::interval_dist2(lo, hi).0;
    }
    if near >= 1.0 {
        return 0.0;
    }
    for p in &v {
        inside &= (*p).dot(p) <= 1.0;
    }
    if inside {
        return mesh::tet_volume(tet);
    }
    TET_FACES
        .iter()
        .map(|f| triangle_flux_unit(&[v[f[0]], v[f[1]], v[f[2]]]))
        .sum::<f64>()
        * r3
}

/// Exact volume of the ball (centre `centre`, radius `r`) ∩ the closed polyhedron bounded by the
/// triangles `faces` (m), each oriented with its normal (v₁ − v₀) × (v₂ − v₀) pointing outwards,
/// m³. The polyhedron may be non-convex; the faces must close (every edge shared by two faces
/// with opposite directions), otherwise the result is meaningless.
pub fn sphere_polyhedron_volume(centre: impl Into<V3>, r: f64, faces: &[[V3; 3]]) -> f64 {
    let centre = centre.into();
    faces.iter().map(|t| triangle_flux(centre, r, t)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The signed solid angle of a planar polygon from the origin, by its fan.
    fn polygon_solid_angle(v: &[V3]) -> f64 {
        (1..v.len() - 1)
            .map(|i| {
                let t = [v[0], v[i], v[i + 1]];
                let l = t.map(|p| p.norm());
                solid_angle(&t, l, t[0].dot(&t[1].cross(&t[2])))
            })
            .sum()
    }

    /// SplitMix64 in [−1, 1).
    fn uniform(rng: &mut testkit::SplitMix) -> f64 {
        rng.range(-1.0, 1.0)
    }

    /// The cap form plus a third of the solid angle is the flux form, for convex polygons of 3
    /// to 7 vertices in random planes at every distance from the unit ball (crossing it,
    /// inside it, beyond it, holding the disk, holding the foot point or not), both
    /// orientations.
    #[test]
    fn cap_form_plus_solid_angle_is_the_flux_form() {
        let mut rng = testkit::SplitMix(5);
        let mut checked = [0usize; 3];
        for k in 0..20_000 {
            let nh = V3::from_fn(|_, _| uniform(&mut rng)).normalize();
            let d = 1.2 * uniform(&mut rng);
            let u = nh.cross(&V3::new(0.3, -0.7, 0.2)).normalize();
            let w = nh.cross(&u);
            let centre = nh * d + (u * uniform(&mut rng) + w * uniform(&mut rng)) * 1.5;
            let size = 0.05 + 2.0 * (0.5 + 0.5 * uniform(&mut rng));
            let n = 3 + k % 5;
            let turn = std::f64::consts::TAU / n as f64;
            let mut v: Vec<V3> = (0..n)
                .map(|i| {
                    let a = turn * (i as f64 + 0.4 * uniform(&mut rng));
                    centre + (u * a.cos() + w * a.sin()) * size
                })
                .collect();
            let mut nrm = nh;
            if k % 2 == 1 {
                v.reverse();
                nrm = -nh;
            }
            let area: V3 = (1..n - 1)
                .map(|i| 0.5 * (v[i] - v[0]).cross(&(v[i + 1] - v[0])))
                .sum();
            let flux = polygon_flux_unit(&v, area);
            let d_plane = v.iter().map(|p| p.dot(&nrm)).sum::<f64>() / n as f64;
            let Some(cap) = polygon_cap_unit(&v, nrm, d_plane, 1e-9) else {
                continue;
            };
            let via_cap = cap + polygon_solid_angle(&v) / 3.0;
            assert!(
                (via_cap - flux).abs() < 1e-12,
                "case {k}: {via_cap} vs {flux} (cap {cap}, d {d}) {v:?} {nrm:?}"
            );
            checked[if cap == 0.0 {
                0
            } else if d.abs() < 1.0 {
                1
            } else {
                2
            }] += 1;
        }
        assert!(checked[0] > 1000 && checked[1] > 1000, "{checked:?}");
    }
}
