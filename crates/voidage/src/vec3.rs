//! The 3-vector operations the kernels need: mesh's helpers (`mesh::v3`), plus the map of a
//! point into unit-ball coordinates.

pub(crate) use mesh::v3::{cross, dot, mag as norm, sub, V3};

/// `(p − c) / r`: a point in the coordinates of the unit ball centred at `c`.
#[inline(always)]
pub(crate) fn to_unit(p: V3, c: V3, inv_r: f64) -> V3 {
    [
        (p[0] - c[0]) * inv_r,
        (p[1] - c[1]) * inv_r,
        (p[2] - c[2]) * inv_r,
    ]
}
