//! Primitive walls of `fix wall/gran … primitive type T xplane|yplane|zplane X` and
//! `… zcylinder R Cx Cy` (likewise `xcylinder`, `ycylinder`): infinite planes normal to an
//! axis and infinite circular cylinders along an axis. As in LIGGGHTS both sides of a wall
//! repel (a particle inside a cylinder meets its inner surface, one outside the outer).

use mesh::v3::V3;

use crate::contact::{
    contact_force, ContactInput, ContactModel, ContactOutput, History, HistoryUse,
};
use crate::material::PairCoeffs;

/// Wall geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WallShape {
    /// The plane `x[axis] = position` (m).
    Plane {
        /// 0, 1, 2 for x, y, z.
        axis: usize,
        /// Plane coordinate (m).
        position: f64,
    },
    /// The cylinder of `radius` (m) around the line through `centre` (the two other
    /// coordinates, in cyclic order after `axis`: y,z for x; z,x for y; x,y for z) along `axis`.
    Cylinder {
        /// 0, 1, 2 for x, y, z.
        axis: usize,
        /// Radius (m).
        radius: f64,
        /// Coordinates of the axis in the other two directions (m).
        centre: [f64; 2],
    },
}

/// A wall: shape, the atom type whose material it has, and its contact model.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    /// Deck fix id (or a name given through the API).
    pub name: String,
    /// Geometry.
    pub shape: WallShape,
    /// Material type (1-based), as `primitive type T`.
    pub material_type: u32,
    /// Contact model options of the wall's `model … ` settings.
    pub model: ContactModel,
}

/// A sphere's state as a static wall contact sees it.
#[derive(Debug, Clone, Copy)]
pub struct SphereState {
    /// Radius (m).
    pub radius: f64,
    /// Mass (kg).
    pub mass: f64,
    /// Velocity (m/s).
    pub v: V3,
    /// Angular velocity (rad/s).
    pub omega: V3,
}

/// The contact of a sphere with a static wall surface (a primitive wall or a mesh triangle)
/// whose closest point is at distance `dist` < R (m) along the unit normal `n` (from the wall
/// to the centre): overlap δ = R − dist, R* = R, m* = m, the wall at rest, through
/// [`contact_force`] (LIGGGHTS's wall contact: `fix wall/gran` treats primitive and mesh walls
/// alike). Advances the history `h` by `dt` (s) with [`HistoryUse::Advance`].
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn wall_contact(
    model: &ContactModel,
    c: &PairCoeffs,
    s: &SphereState,
    dist: f64,
    n: V3,
    h: &mut History,
    dt: f64,
    history: HistoryUse,
) -> ContactOutput {
    let inp = ContactInput {
        n,
        r: dist,
        deltan: s.radius - dist,
        radi: s.radius,
        radj: 0.0,
        reff: s.radius,
        meff: s.mass,
        vrel: s.v,
        omega_i: s.omega,
        omega_j: V3::zeros(),
        is_wall: true,
    };
    contact_force(model, c, &inp, h, dt, history)
}

/// The two axes after `axis` in cyclic order (LIGGGHTS's `Dim<dim>`: y,z for x; z,x for y;
/// x,y for z).
pub fn other_axes(axis: usize) -> (usize, usize) {
    ((axis + 1) % 3, (axis + 2) % 3)
}

/// A point's offset from a cylinder's axis: the two other axes (a, b), the offsets along
/// them (m) and the distance from the axis ρ (m).
#[inline]
fn axis_offset(axis: usize, centre: [f64; 2], x: V3) -> (usize, usize, f64, f64, f64) {
    let (a, b) = other_axes(axis);
    let (da, db) = (x[a] - centre[0], x[b] - centre[1]);
    (a, b, da, db, (da * da + db * db).sqrt())
}

impl WallShape {
    /// Distance (m) of point `x` to the wall surface, as [`WallShape::distance`] gives it
    /// (bit for bit), without the normal; infinite where that has none.
    #[inline]
    pub fn gap(&self, x: V3) -> f64 {
        match *self {
            WallShape::Plane { axis, position } => (x[axis] - position).abs(),
            WallShape::Cylinder {
                axis,
                radius,
                centre,
            } => match axis_offset(axis, centre, x) {
                (.., 0.0) => f64::INFINITY,
                (.., rho) => (rho - radius).abs(),
            },
        }
    }

    /// Distance (m) of point `x` to the wall surface and the unit normal from the wall towards
    /// `x`; `None` when the normal is undefined (a point on a cylinder's axis).
    #[inline]
    pub fn distance(&self, x: V3) -> Option<(f64, V3)> {
        match *self {
            WallShape::Plane { axis, position } => {
                let d = x[axis] - position;
                let mut n = V3::zeros();
                n[axis] = if d >= 0.0 { 1.0 } else { -1.0 };
                Some((d.abs(), n))
            }
            WallShape::Cylinder {
                axis,
                radius,
                centre,
            } => {
                let (a, b, da, db, rho) = axis_offset(axis, centre, x);
                if rho == 0.0 {
                    return None;
                }
                // outward radial unit vector; inside the cylinder the normal points inwards
                let sign = if rho > radius { 1.0 } else { -1.0 };
                let mut n = V3::zeros();
                n[a] = sign * da / rho;
                n[b] = sign * db / rho;
                Some(((rho - radius).abs(), n))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_and_normals() {
        let p = WallShape::Plane {
            axis: 2,
            position: 1.0,
        };
        assert_eq!(
            p.distance(V3::new(0.0, 0.0, 0.25)),
            Some((0.75, V3::new(0.0, 0.0, -1.0)))
        );
        let c = WallShape::Cylinder {
            axis: 2,
            radius: 2.0,
            centre: [1.0, 0.0],
        };
        // inside at distance 1.5 from the axis along +x: 0.5 from the wall, normal −x
        assert_eq!(
            c.distance(V3::new(2.5, 0.0, 7.0)),
            Some((0.5, V3::new(-1.0, 0.0, 0.0)))
        );
        assert_eq!(
            c.distance(V3::new(1.0, 3.0, 0.0)),
            Some((1.0, V3::new(0.0, 1.0, 0.0)))
        );
        assert_eq!(c.distance(V3::new(1.0, 0.0, 0.0)), None);
        assert_eq!(c.gap(V3::new(1.0, 0.0, 0.0)), f64::INFINITY);
        for x in [V3::new(2.5, 0.1, 7.0), V3::new(1.0, 3.0, 0.0)] {
            assert_eq!(c.gap(x), c.distance(x).unwrap().0);
            assert_eq!(p.gap(x), p.distance(x).unwrap().0);
        }
        // y-cylinder: the centre is (z, x)
        let y = WallShape::Cylinder {
            axis: 1,
            radius: 1.0,
            centre: [0.5, 0.0],
        };
        assert_eq!(
            y.distance(V3::new(0.0, 9.0, 0.0)),
            Some((0.5, V3::new(0.0, 0.0, 1.0)))
        );
    }
}
