//! A uniform grid over one or more surfaces: for any point, the triangles that may lie within
//! `reach` of it, so a sphere of radius ≤ reach finds its contacts by one cell lookup
//! (O(particles) per step instead of O(particles × triangles)).
//!
//! A triangle is listed in every cell whose box, grown by `reach`, meets the triangle's
//! bounding box and whose centre is within (half the cell diagonal + reach) of the triangle's
//! plane. Both tests are necessary conditions for a point of the cell to be within `reach` of
//! the triangle, so no contact is missed; the plane test keeps large tilted triangles out of
//! most of their bounding box. Cells are `2·reach` wide (larger when the grid would exceed
//! [`MAX_CELLS`]); a point outside the grid has no triangle within reach.

use mesh::v3::V3;

use super::surface::TriMesh;

/// The most cells a grid has (the cell size grows to stay below).
pub const MAX_CELLS: usize = 1 << 22;

/// Triangles of a list of surfaces by grid cell. A triangle is named by its global index:
/// its index in its surface plus the triangles of the surfaces before it.
#[derive(Debug, Clone)]
pub struct TriBins {
    lo: V3,
    h: f64,
    dims: [usize; 3],
    /// CSR: the triangles of cell c are `items[start[c]..start[c + 1]]`, ascending.
    start: Vec<u32>,
    items: Vec<u32>,
    reach: f64,
}

impl TriBins {
    /// Bins the triangles of `meshes` for spheres of radius ≤ `reach` (m, > 0).
    pub fn build(meshes: &[&TriMesh], reach: f64) -> TriBins {
        let reach = reach.max(f64::MIN_POSITIVE);
        let bounds = meshes
            .iter()
            .filter_map(|m| m.bounds())
            .reduce(|a, b| (a.0.inf(&b.0), a.1.sup(&b.1)));
        let Some((blo, bhi)) = bounds else {
            return TriBins {
                lo: V3::zeros(),
                h: 1.0,
                dims: [0; 3],
                start: vec![0],
                items: Vec::new(),
                reach,
            };
        };
        let lo = blo - V3::repeat(reach);
        let ext = (bhi + V3::repeat(reach)) - lo;
        let mut h = 2.0 * reach;
        let cells =
            |h: f64| -> [usize; 3] { [0, 1, 2].map(|k| ((ext[k] / h).ceil() as usize).max(1)) };
        while cells(h).iter().map(|&n| n as f64).product::<f64>() > MAX_CELLS as f64 {
            h *= 1.25;
        }
        let dims = cells(h);
        let ncells = dims[0] * dims[1] * dims[2];
        let half_diag = 0.5 * h * 3f64.sqrt();
        // the cells of each triangle, visited twice: count, then fill
        let visit = |f: &mut dyn FnMut(usize, u32)| {
            let mut gid = 0u32;
            for m in meshes {
                for t in 0..m.len() {
                    let v = m.nodes(t);
                    let (tlo, thi) = (v[0].inf(&v[1]).inf(&v[2]), v[0].sup(&v[1]).sup(&v[2]));
                    let n = m.normal(t);
                    let range = |k: usize| {
                        let a = ((tlo[k] - reach - lo[k]) / h).floor().max(0.0) as usize;
                        let b = ((thi[k] + reach - lo[k]) / h).floor() as usize;
                        a..=b.min(dims[k] - 1)
                    };
                    for iz in range(2) {
                        for iy in range(1) {
                            for ix in range(0) {
                                let c = lo
                                    + V3::new(ix as f64 + 0.5, iy as f64 + 0.5, iz as f64 + 0.5)
                                        * h;
                                if n.dot(&(c - v[0])).abs() <= half_diag + reach {
                                    f((iz * dims[1] + iy) * dims[0] + ix, gid);
                                }
                            }
                        }
                    }
                    gid += 1;
                }
            }
        };
        let mut count = vec![0u32; ncells + 1];
        visit(&mut |c, _| count[c + 1] += 1);
        for c in 0..ncells {
            count[c + 1] += count[c];
        }
        let start = count.clone();
        let mut fill = count;
        let mut items = vec![0u32; start[ncells] as usize];
        visit(&mut |c, g| {
            items[fill[c] as usize] = g;
            fill[c] += 1;
        });
        TriBins {
            lo,
            h,
            dims,
            start,
            items,
            reach,
        }
    }

    /// The sphere radius the grid was built for (m).
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// The cell width (m).
    pub fn cell_size(&self) -> f64 {
        self.h
    }

    /// The global indices of the triangles that may lie within `reach` of `p`, ascending.
    #[inline]
    pub fn candidates(&self, p: V3) -> &[u32] {
        let mut c = 0usize;
        for k in (0..3).rev() {
            let x = (p[k] - self.lo[k]) / self.h;
            // also false for NaN
            if !(x >= 0.0 && x < self.dims[k] as f64) {
                return &[];
            }
            c = c * self.dims[k] + x as usize;
        }
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trimesh::surface::MeshOptions;

    /// Every triangle within reach of a point is among its candidates (brute force over a
    /// tilted, finely triangulated plane and random points).
    #[test]
    fn no_contact_is_missed() {
        use rand::{Rng, SeedableRng};
        let mut tris = Vec::new();
        let n = 12;
        let z = |x: f64, y: f64| 0.3 * x - 0.2 * y + 0.05;
        for i in 0..n {
            for j in 0..n {
                let (x0, y0, x1, y1) = (
                    i as f64 / n as f64,
                    j as f64 / n as f64,
                    (i + 1) as f64 / n as f64,
                    (j + 1) as f64 / n as f64,
                );
                let p = |x, y| V3::new(x, y, z(x, y));
                tris.push([p(x0, y0), p(x1, y0), p(x1, y1)]);
                tris.push([p(x0, y0), p(x1, y1), p(x0, y1)]);
            }
        }
        let (m, _) = TriMesh::new("p", &tris, &[], MeshOptions::default());
        let reach = 0.03;
        let bins = TriBins::build(&[&m], reach);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut listed = 0;
        for _ in 0..3000 {
            let p = V3::new(
                rng.gen_range(-0.1..1.1),
                rng.gen_range(-0.1..1.1),
                rng.gen_range(-0.4..0.5),
            );
            let cand = bins.candidates(p);
            listed += cand.len();
            for t in 0..m.len() {
                let v = m.nodes(t);
                // distance to the triangle, brute force by its closest point
                let d = closest_distance(p, v);
                if d <= reach {
                    assert!(cand.contains(&(t as u32)), "{p:?} misses {t} at {d}");
                }
            }
        }
        // and the lists are short compared with the 288 triangles
        assert!(listed < 3000 * 20, "{listed}");
    }

    fn closest_distance(p: V3, v: &[V3; 3]) -> f64 {
        let n = (v[1] - v[0]).cross(&(v[2] - v[0]));
        let n = n / n.norm();
        let q = p - n.dot(&(p - v[0])) * n;
        let inside = (0..3).all(|e| {
            let (a, b) = (v[e], v[(e + 1) % 3]);
            n.dot(&(b - a).cross(&(q - a))) >= 0.0
        });
        if inside {
            return (p - q).norm();
        }
        (0..3)
            .map(|e| {
                let (a, b) = (v[e], v[(e + 1) % 3]);
                let s = ((p - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0);
                (p - (a + s * (b - a))).norm()
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn outside_the_grid_has_no_candidates() {
        let t = [[V3::zeros(), V3::new(1., 0., 0.), V3::new(0., 1., 0.)]];
        let (m, _) = TriMesh::new("t", &t, &[], MeshOptions::default());
        let b = TriBins::build(&[&m], 0.1);
        assert!(b.candidates(V3::new(0.2, 0.2, 0.5)).is_empty());
        assert!(b.candidates(V3::new(f64::NAN, 0.2, 0.0)).is_empty());
        assert_eq!(b.candidates(V3::new(0.2, 0.2, 0.05)), &[0]);
    }
}
