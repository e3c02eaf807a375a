//! The 3-vector every computing crate uses: nalgebra's `Vector3<f64>` (positions, velocities,
//! forces, area vectors), so that vector algebra reads as algebra (`a + b`, `s * v`,
//! `a.dot(&b)`, `a.cross(&b)`, `a.norm()`).
//!
//! OpenFOAM-exact geometry depends on the order of floating-point operations. nalgebra's
//! operators evaluate in OpenFOAM's order (`VectorI.H`, `VectorSpaceI.H`): `+`, `−`, `s * v`
//! and `v / s` component by component (a division, not a reciprocal); `dot` as
//! `(x·x' + y·y') + z·z'`; `cross` with OpenFOAM's `^` formula; `norm` as
//! `sqrt(x² + y² + z²)`; the geometry tests compare with OpenFOAM's own output to the last bit.
//!
//! The I/O crates (`foam`, `dem-io`, `vtk`) keep plain `[f64; 3]` records, as the files store
//! them; [`V3::from`] and [`Into<[f64; 3]>`] convert at their boundary.

/// A point or vector, m (or whatever the caller's unit).
pub type V3 = nalgebra::Vector3<f64>;

/// `a / |a|`, or `None` for a zero or non-finite vector.
#[inline]
pub fn unit(a: V3) -> Option<V3> {
    let n = a.norm();
    (n > 0.0 && n.is_finite()).then(|| a / n)
}

/// `[f64; 3]` records (as the I/O crates hold them) seen as vectors, without a copy (a
/// `Vector3<f64>` is three contiguous `f64`, as an array is).
pub fn as_vectors(a: &[[f64; 3]]) -> &[V3] {
    bytemuck::cast_slice(a)
}

/// Vectors seen as `[f64; 3]` records (for the I/O crates), without a copy.
pub fn as_arrays(v: &[V3]) -> &[[f64; 3]] {
    bytemuck::cast_slice(v)
}

/// `[f64; 3]` records (as the I/O crates hold them) as vectors.
pub fn from_arrays(a: &[[f64; 3]]) -> Vec<V3> {
    a.iter().map(|&p| V3::from(p)).collect()
}

/// Vectors as `[f64; 3]` records (for the I/O crates).
pub fn to_arrays(v: &[V3]) -> Vec<[f64; 3]> {
    v.iter().map(|&p| p.into()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// nalgebra's operators give the bits of OpenFOAM's operator order on values chosen so
    /// that another order would round differently.
    #[test]
    fn operators_follow_openfoams_order() {
        let a = V3::new(0.1, 1e16, -0.3);
        let b = V3::new(0.7, 1.0, 1e-17);
        let dot = (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
        assert_eq!(a.dot(&b).to_bits(), dot.to_bits());
        let n = ((a[0] * a[0] + a[1] * a[1]) + a[2] * a[2]).sqrt();
        assert_eq!(a.norm().to_bits(), n.to_bits());
        let c = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        assert_eq!(a.cross(&b), V3::from(c));
        let d = a / 3.0;
        assert_eq!(d, V3::new(a[0] / 3.0, a[1] / 3.0, a[2] / 3.0));
        assert_eq!(unit(V3::zeros()), None);
        let records = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]];
        assert_eq!(
            as_vectors(&records),
            [V3::new(1.0, 2.0, 3.0), V3::new(4.0, 5.0, 6.0)]
        );
        assert_eq!(as_arrays(as_vectors(&records)), records);
        assert_eq!(unit(V3::new(0.0, 3.0, 4.0)), Some(V3::new(0.0, 0.6, 0.8)));
    }
}
