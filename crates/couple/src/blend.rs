//! Time blending of the exchange fields within a coupling interval.
//!
//! The particle data (hence ε and Us) are new only every coupling interval Δt_c = N Δt_DEM,
//! while the fluid may take several steps per interval. As CFDEMcoupling does (its
//! `voidFractionModel` and `averagingModel` keep a previous and a next field and blend them
//! with the fraction of the interval elapsed), the fluid sees, at time t within the interval
//! that started at t₀,
//! `φ(t) = (1 − α) φ_old + α φ_new`, α = clamp((t − t₀) / Δt_c, 0, 1),
//! applied cell by cell. α = 1 at the end of the interval gives the new field exactly.

use mesh::v3::V3;

/// The blending fraction α for time `t` in the interval starting at `t0` of length
/// `interval` (s); 1 for a zero-length interval.
pub fn fraction(t: f64, t0: f64, interval: f64) -> f64 {
    if interval > 0.0 {
        ((t - t0) / interval).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// `(1 − α) old + α new` for scalar fields, into `out`.
pub fn blend_scalar(old: &[f64], new: &[f64], alpha: f64, out: &mut Vec<f64>) {
    assert_eq!(old.len(), new.len(), "blended fields of equal length");
    out.clear();
    out.extend(
        old.iter()
            .zip(new)
            .map(|(&o, &n)| (1.0 - alpha) * o + alpha * n),
    );
}

/// `(1 − α) old + α new` for vector fields, into `out`.
pub fn blend_vector(old: &[V3], new: &[V3], alpha: f64, out: &mut Vec<V3>) {
    assert_eq!(old.len(), new.len(), "blended fields of equal length");
    out.clear();
    out.extend(
        old.iter()
            .zip(new)
            .map(|(o, n)| V3::from_fn(|a, _| (1.0 - alpha) * o[a] + alpha * n[a])),
    );
}
