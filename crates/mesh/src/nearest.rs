//! Nearest points on triangles and mesh faces.
//!
//! * [`triangle_nearest`]: the point of a triangle closest to a query point, by the Voronoi
//!   regions of its vertices, edges and interior (Ericson, *Real-Time Collision Detection*,
//!   2005, §5.1.5, the algorithm OpenFOAM's `triangle::nearestPoint` also follows);
//! * [`face_distance`]: the Euclidean distance from a point to a mesh face, a triangle
//!   directly, a polygon as the fan of triangles (pᵢ, pᵢ₊₁, c) about its centre c, as OpenFOAM
//!   v1912's `face::nearestPoint` decomposes it. For a planar convex face the fan covers the
//!   polygon exactly, so the distance is the exact point–polygon distance; a warped face is
//!   measured on its fan.
//!
//! Units: m. Results agree with the exact distance to round-off (a few ulp of the coordinates).

use crate::v3::V3;
use foam::Label;

/// Below this (OpenFOAM's `ROOTVSMALL`, m²·m²) a triangle's region denominators count as
/// degenerate.
const ROOTVSMALL: f64 = 1.0e-150;

/// The point of triangle (a, b, c) closest to `p` (m). Regions are tested in the order vertex a,
/// vertex b, edge ab, vertex c, edge ac, edge bc, interior, each by the signs of dot products of
/// the edge vectors with the vectors from the vertices to `p` (Ericson 2005, §5.1.5). A
/// degenerate triangle (collinear or coincident vertices) gives a vertex, an edge point or,
/// with no region found, the centroid.
pub fn triangle_nearest(p: V3, a: V3, b: V3, c: V3) -> V3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return edge_point(a, ab, d1, d1 - d3);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return edge_point(a, ac, d2, d2 - d6);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return edge_point(b, c - b, d4 - d3, (d4 - d3) + (d5 - d6));
    }
    let sum = va + vb + vc;
    if sum < ROOTVSMALL {
        return (1.0 / 3.0) * (a + b + c);
    }
    let denom = 1.0 / sum;
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The point `start + (num/den)·edge` on an edge, or `start` when the edge is degenerate
/// (`den` below [`ROOTVSMALL`]).
fn edge_point(start: V3, edge: V3, num: f64, den: f64) -> V3 {
    if den < ROOTVSMALL {
        start
    } else {
        start + (num / den) * edge
    }
}

/// The distance (m) from `p` to the mesh face `face` (point labels into `points`) whose centre
/// is `centre` (the face's area-weighted centre, [`crate::face_centre_and_area`]): for a
/// triangle the distance to it, else the smallest distance to the fan triangles
/// (pᵢ, pᵢ₊₁, centre).
pub fn face_distance(p: V3, points: &[V3], face: &[Label], centre: V3) -> f64 {
    let pt = |i: usize| points[face[i] as usize];
    if face.len() == 3 {
        return (triangle_nearest(p, pt(0), pt(1), pt(2)) - p).norm();
    }
    (0..face.len())
        .map(|i| (triangle_nearest(p, pt(i), pt((i + 1) % face.len()), centre) - p).norm())
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> V3 {
        V3::new(x, y, z)
    }

    /// The right triangle (0,0,0), (2,0,0), (0,2,0): each Voronoi region against the closed
    /// form of its nearest point (the vertex, the foot on the edge line, the projection).
    #[test]
    fn each_region_of_a_triangle_gives_its_closed_form_point() {
        let (a, b, c) = (v(0., 0., 0.), v(2., 0., 0.), v(0., 2., 0.));
        let cases = [
            (v(-1., -1., 3.), a),               // vertex a
            (v(3., -0.5, 1.), b),               // vertex b
            (v(-0.5, 3., -1.), c),              // vertex c
            (v(0.7, -2., 1.), v(0.7, 0., 0.)),  // edge ab
            (v(-3., 1.3, 0.5), v(0., 1.3, 0.)), // edge ac
            // edge bc (x + y = 2): foot of (2, 1, 4) is (1.5, 0.5, 0)
            (v(2., 1., 4.), v(1.5, 0.5, 0.)),
            (v(0.5, 0.25, -7.), v(0.5, 0.25, 0.)), // interior
        ];
        for (p, want) in cases {
            let got = triangle_nearest(p, a, b, c);
            assert!((got - want).norm() < 1e-15, "{p:?}: {got:?} vs {want:?}");
        }
    }

    /// Distance to a planar quad [0,1]×[0,2] in z = 0 (fan about its centre (0.5, 1, 0)):
    /// above the face the height, beside an edge √(h² + d²), beyond a corner the corner
    /// distance; a degenerate triangle gives a finite answer.
    #[test]
    fn distance_to_a_quad_is_the_point_polygon_distance() {
        let pts = [v(0., 0., 0.), v(1., 0., 0.), v(1., 2., 0.), v(0., 2., 0.)];
        let f: [Label; 4] = [0, 1, 2, 3];
        let ctr = v(0.5, 1., 0.);
        let d = |p: V3| face_distance(p, &pts, &f, ctr);
        assert!((d(v(0.3, 1.7, 0.25)) - 0.25).abs() < 1e-15);
        assert!((d(v(1.5, 1.0, -0.5)) - 0.5f64.hypot(0.5)).abs() < 1e-15);
        assert!((d(v(-0.3, -0.4, 1.2)) - (0.09f64 + 0.16 + 1.44).sqrt()).abs() < 1e-15);
        let tri: [Label; 3] = [0, 1, 2];
        assert!((face_distance(v(0.9, 0.1, 2.), &pts, &tri, ctr) - 2.0).abs() < 1e-15);
        let flat = triangle_nearest(v(1., 1., 1.), v(0., 0., 0.), v(0., 0., 0.), v(0., 0., 0.));
        assert_eq!(flat, v(0., 0., 0.));
    }
}
