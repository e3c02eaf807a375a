//! The map of a point into unit-ball coordinates (the kernels' one vector helper beyond
//! nalgebra's operators on `mesh::v3::V3`).

pub(crate) use mesh::v3::V3;

/// `(p − c) / r`: a point in the coordinates of the unit ball centred at `c`.
#[inline(always)]
pub(crate) fn to_unit(p: V3, c: V3, inv_r: f64) -> V3 {
    V3::new(
        (p[0] - c[0]) * inv_r,
        (p[1] - c[1]) * inv_r,
        (p[2] - c[2]) * inv_r,
    )
}
