//! A triangulated surface as `fix mesh/surface` holds it: triangles with their unit normals,
//! the welded topology (which triangles share a vertex or an edge), which edges and corners may
//! carry a contact, and the closest point of a triangle to a sphere centre.
//!
//! # Which features carry contacts
//! A sphere touching a surface made of several triangles must meet it once, not once per
//! triangle. LIGGGHTS 3.8 (`SurfaceMesh::buildNeighbours`, read to learn the rule) does this
//! by marking edges and corners active or inactive, and this module applies the same rule:
//! - an edge shared by two triangles that are coplanar (|n₁·n₂| > cos θ, θ the `curvature`
//!   angle, default arccos(1 − 10⁻⁵) ≈ 0.26°) is inactive in both (the face contact of the
//!   triangle under the sphere covers it); a shared edge of two non-coplanar triangles is
//!   active in the later triangle only (the contact with a convex or concave edge is counted
//!   once); an edge of one triangle only is active;
//! - a corner (welded vertex) is inactive in every triangle when two of the edges meeting
//!   there are colinear (|cos| > cos θ) with different far ends — the vertex lies on a
//!   straight line of the surface, covered by edge contacts — or when none of those edges is
//!   active; otherwise it is active in the last triangle containing it only.
//!
//! A contact whose closest point lies on an inactive edge or corner does not exist. What
//! remains are face contacts of coplanar triangles that share a vertex, when the centre projects
//! onto their common edge or vertex (within the tolerance below): [`TriMesh::coplanar_neighbours`]
//! lists those pairs and the mesh wall keeps one contact of such a group
//! ([`crate::mesh_wall`]).
//!
//! # Closest point
//! With the centre p projected onto the triangle's plane, its barycentric coordinates bₑ are
//! the signed distances to the three edge lines divided by the heights. All bₑ > −ε (ε =
//! precision / (2 r_b), r_b the largest distance of a vertex from the triangle's centroid,
//! precision 10⁻⁸ m by default: LIGGGHTS's tolerance) is a face contact at distance |n·(p − v₀)|
//! with normal ±n; otherwise the closest point is on the boundary (the nearest of the three
//! edge segments, a clamped parameter giving a corner) at distance |p − c|, normal
//! (p − c)/|p − c| (Ericson, *Real-Time Collision Detection*, 2005, §5.1.5).
//!
//! Units: metres throughout; normals are unit vectors.

use std::collections::HashMap;

use mesh::v3::V3;

/// LIGGGHTS's default `curvature`: triangles whose unit normals satisfy |n₁·n₂| > 1 − 10⁻⁵ are
/// coplanar (≈ 0.256°).
pub const DEFAULT_COPLANAR_COS: f64 = 1.0 - 1e-5;

/// LIGGGHTS's default `precision` (m): vertices closer than this in every coordinate are one
/// vertex, and the face tolerance of the closest-point test scales with it.
pub const DEFAULT_PRECISION: f64 = 1e-8;

/// Where on a triangle the closest point lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// The interior (or within the tolerance of it).
    Face,
    /// Edge `e`, from vertex `e` to vertex `(e + 1) % 3`.
    Edge(u8),
    /// Vertex `k`.
    Corner(u8),
}

/// The closest point of a triangle to a sphere centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriContact {
    /// Distance of the centre to the triangle (m).
    pub dist: f64,
    /// Unit normal from the triangle towards the centre.
    pub normal: V3,
    /// The feature the closest point lies on.
    pub feature: Feature,
}

/// A triangulated surface.
#[derive(Debug, Clone)]
pub struct TriMesh {
    name: String,
    nodes: Vec<[V3; 3]>,
    normal: Vec<V3>,
    /// Per triangle: centroid and r_b (largest centroid–vertex distance, m).
    centre: Vec<(V3, f64)>,
    /// Per triangle and edge: the inward unit normal of the edge in the plane and the height
    /// of the opposite vertex over the edge line (m).
    edge_in: Vec<[(V3, f64); 3]>,
    edge_active: Vec<[bool; 3]>,
    corner_active: Vec<[bool; 3]>,
    /// Coplanar triangles sharing a vertex, CSR by triangle.
    coplanar_start: Vec<u32>,
    coplanar: Vec<u32>,
    /// Where each triangle came from (file line or index).
    origin: Vec<usize>,
    precision: f64,
    coplanar_cos: f64,
}

/// How a surface is built from triangles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshOptions {
    /// Vertex welding distance per coordinate (m), LIGGGHTS's `precision`.
    pub precision: f64,
    /// cos θ of the `curvature` angle θ.
    pub coplanar_cos: f64,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            precision: DEFAULT_PRECISION,
            coplanar_cos: DEFAULT_COPLANAR_COS,
        }
    }
}

/// Triangles whose vertices coincide (within the precision) or are colinear: the surface
/// leaves them out, as LIGGGHTS does.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dropped {
    /// Their origins (file line or index).
    pub origin: Vec<usize>,
}

impl TriMesh {
    /// Builds the surface from triangles (metres; `origin[k]` says where triangle k came
    /// from). Degenerate triangles (zero area) are left out and returned.
    pub fn new(
        name: &str,
        triangles: &[[V3; 3]],
        origin: &[usize],
        opts: MeshOptions,
    ) -> (TriMesh, Dropped) {
        let mut m = TriMesh {
            name: name.to_string(),
            nodes: Vec::with_capacity(triangles.len()),
            normal: Vec::with_capacity(triangles.len()),
            centre: Vec::new(),
            edge_in: Vec::new(),
            edge_active: Vec::new(),
            corner_active: Vec::new(),
            coplanar_start: Vec::new(),
            coplanar: Vec::new(),
            origin: Vec::new(),
            precision: opts.precision,
            coplanar_cos: opts.coplanar_cos,
        };
        let mut dropped = Vec::new();
        for (k, t) in triangles.iter().enumerate() {
            let o = origin.get(k).copied().unwrap_or(k + 1);
            let cross = (t[1] - t[0]).cross(&(t[2] - t[0]));
            let close = |a: V3, b: V3| (0..3).all(|d| (a[d] - b[d]).abs() <= opts.precision);
            if close(t[0], t[1]) || close(t[1], t[2]) || close(t[0], t[2]) || cross.norm() == 0.0 {
                dropped.push(o);
                continue;
            }
            let n = cross / cross.norm();
            let c = (t[0] + t[1] + t[2]) / 3.0;
            let rb = t.iter().map(|v| (v - c).norm()).fold(0.0, f64::max);
            let mut ein = [(V3::zeros(), 0.0); 3];
            for (e, slot) in ein.iter_mut().enumerate() {
                let (a, b, opp) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                let dir = (b - a) / (b - a).norm();
                let inward = n.cross(&dir);
                *slot = (inward, (opp - a).dot(&inward));
            }
            m.nodes.push(*t);
            m.normal.push(n);
            m.centre.push((c, rb));
            m.edge_in.push(ein);
            m.origin.push(o);
        }
        m.build_topology();
        (m, Dropped { origin: dropped })
    }

    /// The `fix mesh/surface` id (or a name given through the API).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The vertices of triangle `t` (m).
    pub fn nodes(&self, t: usize) -> &[V3; 3] {
        &self.nodes[t]
    }

    /// All triangles' vertices (m).
    pub fn triangles(&self) -> &[[V3; 3]] {
        &self.nodes
    }

    /// The unit normal of triangle `t` ((v₁ − v₀) × (v₂ − v₀) normalised).
    pub fn normal(&self, t: usize) -> V3 {
        self.normal[t]
    }

    /// The area of triangle `t` (m²).
    pub fn area(&self, t: usize) -> f64 {
        let v = &self.nodes[t];
        0.5 * (v[1] - v[0]).cross(&(v[2] - v[0])).norm()
    }

    /// Where triangle `t` came from: its `facet` line in an ASCII file, its 1-based index in
    /// a binary one.
    pub fn origin(&self, t: usize) -> usize {
        self.origin[t]
    }

    /// Whether edge `e` of triangle `t` carries contacts.
    pub fn edge_active(&self, t: usize) -> [bool; 3] {
        self.edge_active[t]
    }

    /// Whether the corners of triangle `t` carry contacts.
    pub fn corner_active(&self, t: usize) -> [bool; 3] {
        self.corner_active[t]
    }

    /// The triangles coplanar with `t` that share a vertex with it, ascending.
    pub fn coplanar_neighbours(&self, t: usize) -> &[u32] {
        let (a, b) = (
            self.coplanar_start[t] as usize,
            self.coplanar_start[t + 1] as usize,
        );
        &self.coplanar[a..b]
    }

    /// Whether `a` and `b` are coplanar and share a vertex.
    pub fn are_coplanar_neighbours(&self, a: usize, b: usize) -> bool {
        self.coplanar_neighbours(a)
            .binary_search(&(b as u32))
            .is_ok()
    }

    /// The axis-aligned bounds of all vertices (m); `None` when empty.
    pub fn bounds(&self) -> Option<(V3, V3)> {
        let mut it = self.nodes.iter().flatten();
        let first = *it.next()?;
        Some(it.fold((first, first), |(lo, hi), v| (lo.inf(v), hi.sup(v))))
    }

    /// The closest point of triangle `t` to `p`, or `None` when it lies on an inactive edge
    /// or corner (or p is on the edge or corner itself, where no normal exists).
    #[inline]
    pub fn closest(&self, t: usize, p: V3) -> Option<TriContact> {
        let v = &self.nodes[t];
        let n = self.normal[t];
        let d0 = p - v[0];
        let eps = self.precision / (2.0 * self.centre[t].1);
        let ein = &self.edge_in[t];
        let mut face = true;
        for (e, &(inward, h)) in ein.iter().enumerate() {
            let rel = if e == 0 { d0 } else { p - v[e] };
            if rel.dot(&inward) / h <= -eps {
                face = false;
                break;
            }
        }
        if face {
            let dn = n.dot(&d0);
            let normal = if dn >= 0.0 { n } else { -n };
            return Some(TriContact {
                dist: dn.abs(),
                normal,
                feature: Feature::Face,
            });
        }
        // the nearest point of the boundary
        let mut best = (f64::INFINITY, V3::zeros(), Feature::Face);
        for e in 0..3 {
            let (a, b) = (v[e], v[(e + 1) % 3]);
            let ab = b - a;
            let s = (p - a).dot(&ab) / ab.dot(&ab);
            let (c, f) = if s <= 0.0 {
                (a, Feature::Corner(e as u8))
            } else if s >= 1.0 {
                (b, Feature::Corner(((e + 1) % 3) as u8))
            } else {
                (a + s * ab, Feature::Edge(e as u8))
            };
            let d2 = (p - c).norm_squared();
            if d2 < best.0 {
                best = (d2, c, f);
            }
        }
        let (_, c, feature) = best;
        let active = match feature {
            Feature::Edge(e) => self.edge_active[t][e as usize],
            Feature::Corner(k) => self.corner_active[t][k as usize],
            Feature::Face => true,
        };
        let d = p - c;
        let dist = d.norm();
        if !active || dist == 0.0 {
            return None;
        }
        Some(TriContact {
            dist,
            normal: d / dist,
            feature,
        })
    }

    /// Welds vertices, then marks edges and corners active and lists coplanar neighbours.
    fn build_topology(&mut self) {
        let nt = self.nodes.len();
        let ids = weld(&self.nodes, self.precision);
        self.edge_active = vec![[true; 3]; nt];
        self.corner_active = vec![[true; 3]; nt];
        let coplanar = |a: usize, b: usize| self.normal[a].dot(&self.normal[b]).abs();
        // edges: (low id, high id) → (triangle, edge)
        let mut edges: HashMap<(u32, u32), Vec<(usize, usize)>> = HashMap::new();
        for (t, id) in ids.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (id[e], id[(e + 1) % 3]);
                edges.entry((a.min(b), a.max(b))).or_default().push((t, e));
            }
        }
        let mut shared: Vec<&Vec<(usize, usize)>> =
            edges.values().filter(|v| v.len() > 1).collect();
        shared.sort_unstable();
        for group in shared {
            for (x, &(i, ie)) in group.iter().enumerate() {
                for &(j, je) in &group[x + 1..] {
                    let overlap = {
                        // the third vertices on the same side of the edge: folded over
                        let inward = self.edge_in[i][ie].0;
                        let a = self.nodes[i][ie];
                        let oi = self.nodes[i][(ie + 2) % 3] - a;
                        let oj = self.nodes[j][(je + 2) % 3] - a;
                        oi.dot(&inward) * oj.dot(&inward) > 0.0
                    };
                    if coplanar(i, j) >= self.coplanar_cos && !overlap {
                        self.edge_active[i][ie] = false;
                        self.edge_active[j][je] = false;
                    } else {
                        // i < j: the later triangle keeps the edge
                        self.edge_active[i][ie] = false;
                        self.edge_active[j][je] = true;
                    }
                }
            }
        }
        // corners: vertex id → (triangle, corner)
        let mut at: HashMap<u32, Vec<(usize, usize)>> = HashMap::new();
        for (t, id) in ids.iter().enumerate() {
            for (k, &v) in id.iter().enumerate() {
                at.entry(v).or_default().push((t, k));
            }
        }
        let mut cop: Vec<Vec<u32>> = vec![Vec::new(); nt];
        for (_, tris) in at {
            // the two edges of each triangle at this corner, with their far ends
            let mut spokes: Vec<(V3, u32)> = Vec::with_capacity(2 * tris.len());
            let mut any_active = false;
            for &(t, k) in &tris {
                let v = &self.nodes[t];
                for (far, e) in [((k + 1) % 3, k), ((k + 2) % 3, (k + 2) % 3)] {
                    let d = v[far] - v[k];
                    spokes.push((d / d.norm(), ids[t][far]));
                    any_active |= self.edge_active[t][e];
                }
            }
            let colinear = spokes.iter().enumerate().any(|(x, a)| {
                spokes[x + 1..]
                    .iter()
                    .any(|b| a.1 != b.1 && a.0.dot(&b.0).abs() > self.coplanar_cos)
            });
            let last = tris.iter().map(|&(t, _)| t).max().unwrap_or(0);
            for &(t, k) in &tris {
                self.corner_active[t][k] = !colinear && any_active && t == last;
            }
            for &(a, _) in &tris {
                for &(b, _) in &tris {
                    if a != b && coplanar(a, b) > self.coplanar_cos {
                        cop[a].push(b as u32);
                    }
                }
            }
        }
        self.coplanar_start = Vec::with_capacity(nt + 1);
        self.coplanar_start.push(0);
        self.coplanar.clear();
        for mut c in cop {
            c.sort_unstable();
            c.dedup();
            self.coplanar.extend(c);
            self.coplanar_start.push(self.coplanar.len() as u32);
        }
    }
}

/// One id per vertex position: vertices within `precision` in every coordinate share an id.
fn weld(nodes: &[[V3; 3]], precision: f64) -> Vec<[u32; 3]> {
    let h = precision.max(f64::MIN_POSITIVE);
    let key = |v: V3| {
        [
            (v[0] / h).floor() as i64,
            (v[1] / h).floor() as i64,
            (v[2] / h).floor() as i64,
        ]
    };
    let mut cells: HashMap<[i64; 3], Vec<(V3, u32)>> = HashMap::new();
    let mut next = 0u32;
    let mut out = Vec::with_capacity(nodes.len());
    for t in nodes {
        let mut ids = [0u32; 3];
        for (k, &v) in t.iter().enumerate() {
            let c = key(v);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(list) = cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                            if let Some(&(_, id)) = list
                                .iter()
                                .find(|(w, _)| (0..3).all(|d| (v[d] - w[d]).abs() <= precision))
                            {
                                found = Some(id);
                                break 'search;
                            }
                        }
                    }
                }
            }
            ids[k] = found.unwrap_or_else(|| {
                cells.entry(c).or_default().push((v, next));
                next += 1;
                next - 1
            });
        }
        out.push(ids);
    }
    out
}

/// Transformations of `fix mesh/surface`, applied in the order the deck gives them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transform {
    /// `scale s`: every coordinate times s.
    Scale(f64),
    /// `move dx dy dz` (m).
    Move(V3),
    /// `rotate axis ax ay az angle θ`: a right-handed rotation by θ (degrees) about the axis
    /// through the origin.
    Rotate {
        /// The axis (any length > 0).
        axis: V3,
        /// The angle (degrees).
        degrees: f64,
    },
}

/// π as LIGGGHTS 3.8 converts `rotate … angle` degrees to radians (`fix_mesh.cpp` multiplies
/// by 3.14159265/180); using the same constant puts the rotated vertices where LIGGGHTS has
/// them (the true π differs by 1.2·10⁻⁹ relative).
#[allow(clippy::approx_constant)]
pub const LIGGGHTS_PI: f64 = 3.14159265;

impl Transform {
    /// The transformed point (Rodrigues' rotation formula for `Rotate`).
    pub fn apply(&self, p: V3) -> V3 {
        match *self {
            Transform::Scale(s) => s * p,
            Transform::Move(d) => p + d,
            Transform::Rotate { axis, degrees } => {
                let k = axis / axis.norm();
                let th = degrees * LIGGGHTS_PI / 180.0;
                let (s, c) = th.sin_cos();
                (c * p) + (s * k.cross(&p)) + ((1.0 - c) * k.dot(&p) * k)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> V3 {
        V3::new(x, y, z)
    }

    /// A unit square at z = 0 of two triangles sharing the diagonal (0,0)–(1,1).
    fn square() -> TriMesh {
        let t = [
            [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.)],
            [v(0., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)],
        ];
        TriMesh::new("sq", &t, &[1, 2], MeshOptions::default()).0
    }

    #[test]
    fn square_topology() {
        let m = square();
        // the diagonal is inactive in both; the outer edges are active
        assert_eq!(m.edge_active(0), [true, true, false]);
        assert_eq!(m.edge_active(1), [false, true, true]);
        // no two spokes of a corner are colinear: each corner is active in the last
        // triangle that has it
        assert_eq!(m.corner_active(0), [false, true, false]);
        assert_eq!(m.corner_active(1), [true, true, true]);
        assert_eq!(m.coplanar_neighbours(0), &[1]);
        assert!(m.are_coplanar_neighbours(1, 0));
    }

    #[test]
    fn closest_point_regions() {
        let m = square();
        // above the interior of triangle 0: face, distance 0.3, normal +z
        let c = m.closest(0, v(0.7, 0.2, 0.3)).unwrap();
        assert_eq!(
            (c.feature, c.dist, c.normal),
            (Feature::Face, 0.3, v(0., 0., 1.))
        );
        // below: normal −z
        let c = m.closest(0, v(0.7, 0.2, -0.3)).unwrap();
        assert_eq!(c.normal, v(0., 0., -1.));
        // beyond the outer edge x = 1 of triangle 0: edge contact at distance 0.5
        let c = m.closest(0, v(1.3, 0.5, 0.4)).unwrap();
        assert_eq!(c.feature, Feature::Edge(1));
        assert!((c.dist - 0.5).abs() < 1e-15 && (c.normal - v(0.6, 0., 0.8)).norm() < 1e-15);
        // over triangle 1 seen from triangle 0: the inactive diagonal → no contact
        assert!(m.closest(0, v(0.2, 0.7, 0.1)).is_none());
        // exactly over the diagonal: a face contact of both
        for t in 0..2 {
            assert_eq!(
                m.closest(t, v(0.5, 0.5, 0.2)).unwrap().feature,
                Feature::Face
            );
        }
        // beyond the corner (0,0): active in triangle 1 only
        let p = v(-0.3, -0.4, 0.0);
        assert!(m.closest(0, p).is_none());
        let c = m.closest(1, p).unwrap();
        assert_eq!((c.feature, c.dist), (Feature::Corner(0), 0.5));
    }

    #[test]
    fn box_edge_once() {
        // two faces of a cube meeting at the edge x = 1, z ∈ [0, 1] (y = 0 face and x = 1 face)
        let t = [
            [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 1.)],
            [v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.)],
            [v(1., 0., 0.), v(1., 1., 1.), v(1., 0., 1.)],
        ];
        let (m, dropped) = TriMesh::new("b", &t, &[1, 2, 3], MeshOptions::default());
        assert!(dropped.origin.is_empty());
        // a centre outside both faces near the shared edge: edge contact from one triangle only
        let p = v(1.2, -0.2, 0.5);
        let hits: Vec<_> = (0..3)
            .filter_map(|k| m.closest(k, p).map(|c| (k, c)))
            .collect();
        assert_eq!(hits.len(), 1, "{hits:?}");
        assert!((hits[0].1.dist - 0.08f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn degenerate_triangles_are_dropped() {
        let t = [
            [v(0., 0., 0.), v(1., 0., 0.), v(2., 0., 0.)],
            [v(0., 0., 0.), v(1., 0., 0.), v(0., 1., 0.)],
        ];
        let (m, d) = TriMesh::new("d", &t, &[7, 9], MeshOptions::default());
        assert_eq!((m.len(), d.origin), (1, vec![7]));
    }

    #[test]
    fn transforms() {
        let r = Transform::Rotate {
            axis: v(0., 0., 2.),
            degrees: 90.0,
        };
        assert!((r.apply(v(1., 0., 0.)) - v(0., 1., 0.)).norm() < 1e-8);
        assert_eq!(Transform::Scale(0.5).apply(v(2., 4., 6.)), v(1., 2., 3.));
        assert_eq!(
            Transform::Move(v(1., 1., 1.)).apply(v(0., 0., 0.)),
            v(1., 1., 1.)
        );
    }
}
