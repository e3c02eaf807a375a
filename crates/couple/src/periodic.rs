//! Particles of a periodic DEM box on a fluid mesh with translational `cyclic` patch pairs.
//!
//! A DEM with periodic axes (LIGGGHTS's `boundary p …`, the native DEM's
//! `dem::periodic`) moves a particle that crossed a periodic face back into the box only when
//! it rebuilds its neighbour list, so between two rebuilds a centre may lie up to half the
//! neighbour skin beyond the face, outside the fluid mesh. Such a centre is located, and its
//! volume deposited, at its image inside the mesh: the centre moved by whole separations of
//! the cyclic pairs ([`mesh::cyclic`]) until it lies within the periodic span, which is the
//! mesh's extent along each separation's direction (m). The particle side's own positions are
//! not changed.
//!
//! The part of a ball beyond a cyclic face is deposited as the voidage model does at any other
//! boundary (CFDEM's `divided` gives the markers beyond it to the centre's cell, `engine`
//! locates nothing across a cyclic face either): the volume stays next to the face on the
//! centre's side.

use foam::PolyMesh;
use mesh::v3::V3;
use mesh::MeshGeometry;

use crate::error::CoupleError;

/// One periodic direction of the mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Span {
    /// Unit vector along the separation.
    dir: V3,
    /// The mesh's smallest coordinate along `dir` (m).
    lo: f64,
    /// The separation's length (m): the period.
    period: f64,
}

/// The periodic directions of a mesh (none without cyclic patches).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PeriodicMesh {
    spans: Vec<Span>,
}

impl PeriodicMesh {
    /// The translational cyclic pairs of `mesh` (geometry `g`) as periodic directions; errors
    /// are [`mesh::cyclic::pairs`]'s (they name the boundary file and patch).
    pub fn new(mesh: &PolyMesh, g: &MeshGeometry) -> Result<PeriodicMesh, CoupleError> {
        let pairs =
            mesh::cyclic::pairs(mesh, g).map_err(|e| CoupleError::Parameter(e.to_string()))?;
        let spans = pairs
            .iter()
            .filter(|p| p.separation.norm() > 0.0)
            .map(|p| {
                let period = p.separation.norm();
                let dir = p.separation / period;
                let lo = mesh
                    .points
                    .iter()
                    .map(|x| V3::from(*x).dot(&dir))
                    .fold(f64::INFINITY, f64::min);
                Span { dir, lo, period }
            })
            .collect();
        Ok(PeriodicMesh { spans })
    }

    /// Whether the mesh has no periodic direction.
    pub fn is_empty(&self) -> bool {
        self.spans.is_empty()
    }

    /// `x` moved by whole periods into the periodic span of every direction (m).
    pub fn wrap(&self, mut x: V3) -> V3 {
        for s in &self.spans {
            let t = x.dot(&s.dir) - s.lo;
            if !(0.0..s.period).contains(&t) && t.is_finite() {
                x -= (t / s.period).floor() * s.period * s.dir;
            }
        }
        x
    }

    /// The positions with those outside a periodic span wrapped ([`PeriodicMesh::wrap`]);
    /// `None` when every position already lies within (no copy).
    pub fn wrap_all(&self, positions: &[V3]) -> Option<Vec<V3>> {
        let outside = |x: &V3| {
            self.spans.iter().any(|s| {
                let t = x.dot(&s.dir) - s.lo;
                !(0.0..s.period).contains(&t)
            })
        };
        if self.spans.is_empty() || !positions.iter().any(outside) {
            return None;
        }
        Some(positions.iter().map(|&x| self.wrap(x)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A channel of 4 × 1 × 1 cells, 0.4 m long in x, cyclic in x.
    fn channel() -> (PolyMesh, MeshGeometry) {
        let mut m = mesh::build::uniform_box([0.0; 3], [0.4, 0.1, 0.1], [4, 1, 1]);
        let names: Vec<String> = m.boundary.iter().map(|p| p.name.clone()).collect();
        for p in &mut m.boundary {
            if p.name == "xMin" || p.name == "xMax" {
                let other = if p.name == "xMin" { "xMax" } else { "xMin" };
                p.patch_type = "cyclic".into();
                p.extra = vec![("neighbourPatch".into(), other.into())];
            }
        }
        assert!(names.contains(&"xMin".to_string()), "{names:?}");
        let g = MeshGeometry::new(&m).unwrap();
        (m, g)
    }

    #[test]
    fn centres_beyond_a_cyclic_face_come_back_by_one_period() {
        let (m, g) = channel();
        let per = PeriodicMesh::new(&m, &g).unwrap();
        assert!(!per.is_empty());
        let x = per.wrap(V3::new(0.40025, 0.05, 0.05));
        assert!((x[0] - 0.00025).abs() < 1e-15, "{x:?}");
        let x = per.wrap(V3::new(-0.0002, 0.05, 0.05));
        assert!((x[0] - 0.3998).abs() < 1e-15, "{x:?}");
        let inside = [V3::new(0.2, 0.05, 0.05)];
        assert!(per.wrap_all(&inside).is_none());
        // y and z are walls: never moved
        assert_eq!(per.wrap(V3::new(0.1, 0.2, -1.0))[1], 0.2);
    }
}
