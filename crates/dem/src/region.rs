//! Regions of `region ID block xlo xhi ylo yhi zlo zhi` and `region ID cylinder dim c1 c2
//! radius lo hi` (`units box`), used by `create_box` and `fix insert/pack`.

use mesh::v3::V3;
use rand::Rng;

/// A region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Region {
    /// Axis-aligned box (m).
    Block {
        /// Lower corner.
        lo: V3,
        /// Upper corner.
        hi: V3,
    },
    /// Finite circular cylinder (m).
    Cylinder {
        /// Axis direction, 0, 1, 2 for x, y, z.
        axis: usize,
        /// Axis position in the other two coordinates, in LAMMPS order (y z for x; x z for y;
        /// x y for z).
        centre: [f64; 2],
        /// Radius.
        radius: f64,
        /// Extent along the axis.
        lo: f64,
        /// Extent along the axis.
        hi: f64,
    },
}

/// The two coordinates across a cylinder region's axis, in LAMMPS's `c1 c2` order.
pub fn cross_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

impl Region {
    /// Bounding box `(lo, hi)`.
    pub fn bounds(&self) -> (V3, V3) {
        match *self {
            Region::Block { lo, hi } => (lo, hi),
            Region::Cylinder {
                axis,
                centre,
                radius,
                lo,
                hi,
            } => {
                let (a, b) = cross_axes(axis);
                let mut l = V3::zeros();
                let mut h = V3::zeros();
                l[axis] = lo;
                h[axis] = hi;
                l[a] = centre[0] - radius;
                h[a] = centre[0] + radius;
                l[b] = centre[1] - radius;
                h[b] = centre[1] + radius;
                (l, h)
            }
        }
    }

    /// Volume (m³).
    pub fn volume(&self) -> f64 {
        match *self {
            Region::Block { lo, hi } => (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]),
            Region::Cylinder { radius, lo, hi, .. } => {
                std::f64::consts::PI * radius * radius * (hi - lo)
            }
        }
    }

    /// A uniformly random point of the region shrunk by `shrink` (m) on every side, or `None`
    /// if nothing is left.
    pub fn random_point(&self, rng: &mut impl Rng, shrink: f64) -> Option<V3> {
        let (lo, hi) = self.bounds();
        let (l, h) = (lo.map(|v| v + shrink), hi.map(|v| v - shrink));
        if (0..3).any(|k| l[k] > h[k]) {
            return None;
        }
        let mut draw = || V3::from_fn(|k, _| l[k] + (h[k] - l[k]) * rng.gen::<f64>());
        match *self {
            Region::Block { .. } => Some(draw()),
            // rejection in the bounding box: accepts π/4 of the draws
            Region::Cylinder { .. } => loop {
                let p = draw();
                if self.contains_sphere(p, shrink) {
                    return Some(p);
                }
            },
        }
    }

    /// Whether the point `p` is inside (boundary included).
    pub fn contains(&self, p: V3) -> bool {
        self.contains_sphere(p, 0.0)
    }

    /// Whether the sphere of radius `r` at `p` lies entirely inside (`all_in yes`).
    pub fn contains_sphere(&self, p: V3, r: f64) -> bool {
        let (lo, hi) = self.bounds();
        let in_box = (0..3).all(|k| p[k] - r >= lo[k] && p[k] + r <= hi[k]);
        match *self {
            Region::Block { .. } => in_box,
            Region::Cylinder {
                axis,
                centre,
                radius,
                ..
            } => {
                let (a, b) = cross_axes(axis);
                let (da, db) = (p[a] - centre[0], p[b] - centre[1]);
                in_box && da * da + db * db <= (radius - r) * (radius - r)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cylinder_membership() {
        let c = Region::Cylinder {
            axis: 2,
            centre: [0.0, 0.0],
            radius: 1.0,
            lo: 0.0,
            hi: 2.0,
        };
        assert!(c.contains(V3::new(0.7, 0.7, 1.0)));
        assert!(!c.contains(V3::new(0.8, 0.7, 1.0)));
        assert!(c.contains_sphere(V3::new(0.5, 0.0, 1.0), 0.5));
        assert!(!c.contains_sphere(V3::new(0.5, 0.0, 1.0), 0.51));
        assert!(!c.contains_sphere(V3::new(0.0, 0.0, 0.4), 0.5));
        assert!((c.volume() - 2.0 * std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(
            c.bounds(),
            (V3::new(-1.0, -1.0, 0.0), V3::new(1.0, 1.0, 2.0))
        );
    }
}
