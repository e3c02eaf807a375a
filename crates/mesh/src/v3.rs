//! Small 3-vector helpers on `[f64; 3]` (shared with the voidage crate), each evaluated in exactly the operation order of
//! OpenFOAM's `Vector` operators (`VectorI.H`, `VectorSpaceI.H`), so that results can agree with
//! OpenFOAM to the last bit.

/// A point or vector, m (or whatever the caller's unit).
pub type V3 = [f64; 3];

/// `a + b`.
#[inline(always)]
pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
#[inline(always)]
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `s * v`, component by component.
#[inline(always)]
pub fn scale(s: f64, v: V3) -> V3 {
    [s * v[0], s * v[1], s * v[2]]
}

/// `v / s`, component by component (a division, as OpenFOAM's `divideOp`, not a reciprocal).
#[inline(always)]
pub fn div(v: V3, s: f64) -> V3 {
    [v[0] / s, v[1] / s, v[2] / s]
}

/// OpenFOAM's `&`: `x*x' + y*y' + z*z'`, summed left to right.
#[inline(always)]
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// OpenFOAM's `^`.
#[inline(always)]
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// OpenFOAM's `mag`: `sqrt(x*x + y*y + z*z)`.
#[inline(always)]
pub fn mag(a: V3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// `a / |a|`, or `None` for a zero or non-finite vector.
#[inline]
pub fn unit(a: V3) -> Option<V3> {
    let n = mag(a);
    (n > 0.0 && n.is_finite()).then(|| div(a, n))
}
