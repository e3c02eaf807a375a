//! Smooth analytic fields with known gradients, used by the tests, the fixture generator
//! (`examples/grad_fixture.rs`) and the benchmarks to check the operators against closed forms.
//! Coordinates are scaled by a length L so the fields are O(1) on any mesh.

use crate::geometry::{FvGeometry, V3};

/// The largest edge of the cell-centre bounding box (m): the scale L of the test fields.
pub fn length_scale(g: &FvGeometry) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for c in g.cf.iter().chain(&g.c) {
        for a in 0..3 {
            lo[a] = lo[a].min(c[a]);
            hi[a] = hi[a].max(c[a]);
        }
    }
    (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max)
}

/// p(x) = 1 + 2x' − 3y' + 0.5z' + x'y' + z'² with x' = x/L (dimensionless).
pub fn smooth_scalar(x: V3, l: f64) -> f64 {
    let [a, b, c] = [x[0] / l, x[1] / l, x[2] / l];
    1.0 + 2.0 * a - 3.0 * b + 0.5 * c + a * b + c * c
}

/// ∇p of [`smooth_scalar`] (1/m).
pub fn smooth_scalar_grad(x: V3, l: f64) -> V3 {
    let [a, b, c] = [x[0] / l, x[1] / l, x[2] / l];
    V3::new((2.0 + b) / l, (-3.0 + a) / l, (0.5 + 2.0 * c) / l)
}

/// U(x) = (y'² + x', x'z' − y', 1 + x'² − z') (dimensionless).
pub fn smooth_vector(x: V3, l: f64) -> V3 {
    let [a, b, c] = [x[0] / l, x[1] / l, x[2] / l];
    V3::new(b * b + a, a * c - b, 1.0 + a * a - c)
}

/// A linear scalar field a + g·x.
pub fn linear_scalar(x: V3, a: f64, g: V3) -> f64 {
    a + g[0] * x[0] + g[1] * x[1] + g[2] * x[2]
}
