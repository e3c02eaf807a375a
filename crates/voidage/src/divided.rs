//! CFDEM's "divided" marker points.
//!
//! The ball is split into a central ball and two concentric shells of equal volume per marker:
//! radii r₁ = (1/29)^⅓ R and r₂ = (15/29)^⅓ R enclose 1, 15 and 29 twenty-ninths of the volume, so
//! the central ball holds 1/29 and each shell 14/29. Each shell carries 14 markers (8 in the
//! directions (±½, ±½, ±1/√2) and 6 on the axes) at the radius of the shell's volume centroid,
//!
//! r_inner / R = ¾ (r₂⁴ − r₁⁴)/(r₂³ − r₁³) ≈ 0.627607,  r_outer / R = ¾ (1 − r₂⁴)/(1 − r₂³) ≈ 0.908528
//!
//! (radial centroid ∫r·r²dr / ∫r²dr of the shell), plus the centre: 29 markers, each carrying
//! 1/29 of the particle volume. Each marker's volume goes to the cell holding it; markers outside
//! the mesh go to the cell of the centre.
//!
//! Source: CFDEMcoupling's `dividedVoidFraction` model as described in `REFERENCE.md`; the radii
//! are computed here from r₁ and r₂ (not the rounded constants).

use mesh::v3::V3;

/// Number of marker points.
pub const DIVIDED_MARKERS: usize = 29;

/// Radii (r₁, r₂)/R of the shell boundaries: (1/29)^⅓ and (15/29)^⅓.
pub fn divided_shell_bounds() -> (f64, f64) {
    ((1.0f64 / 29.0).cbrt(), (15.0f64 / 29.0).cbrt())
}

/// Marker radii (inner, outer)/R: the volume-centroid radii of the two shells (module docs).
pub fn divided_radii() -> (f64, f64) {
    let (r1, r2) = divided_shell_bounds();
    let inner = 0.75 * (r2.powi(4) - r1.powi(4)) / (r2.powi(3) - r1.powi(3));
    let outer = 0.75 * (1.0 - r2.powi(4)) / (1.0 - r2.powi(3));
    (inner, outer)
}

/// The 14 unit marker directions of one shell: 8 at (±½, ±½, ±1/√2), then ±x, ±y, ±z.
pub fn divided_directions() -> [V3; 14] {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let mut d = [V3::zeros(); 14];
    let mut n = 0;
    for sx in [-0.5, 0.5] {
        for sy in [-0.5, 0.5] {
            for sz in [-h, h] {
                d[n] = V3::new(sx, sy, sz);
                n += 1;
            }
        }
    }
    for axis in [V3::x(), V3::y(), V3::z()] {
        for s in [-1.0, 1.0] {
            d[n] = s * axis;
            n += 1;
        }
    }
    d
}

/// The 29 marker offsets of a unit ball (multiply by R and add the centre): the centre, then the
/// inner shell, then the outer shell.
pub fn divided_offsets() -> [V3; DIVIDED_MARKERS] {
    let (ri, ro) = divided_radii();
    let dirs = divided_directions();
    let mut p = [V3::zeros(); DIVIDED_MARKERS];
    for (k, d) in dirs.iter().enumerate() {
        p[1 + k] = ri * d;
        p[15 + k] = ro * d;
    }
    p
}
