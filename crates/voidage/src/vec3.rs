//! The few 3-vector operations the kernels need, on `[f64; 3]` (mesh keeps its own private).

pub(crate) type V3 = [f64; 3];

#[inline(always)]
pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
pub(crate) fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// `(p − c) / r`: a point in the coordinates of the unit ball centred at `c`.
#[inline(always)]
pub(crate) fn to_unit(p: V3, c: V3, inv_r: f64) -> V3 {
    [
        (p[0] - c[0]) * inv_r,
        (p[1] - c[1]) * inv_r,
        (p[2] - c[2]) * inv_r,
    ]
}
