//! Measures of a settled bed in a square box of half width `w` centred on the z axis, used to
//! compare the native DEM with LIGGGHTS (shared by the tests and the `pour_compare` example).

#![allow(dead_code)]

/// Bed height and solid fraction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bed {
    /// Mean top (z + R) of the highest 10 % of the spheres (m).
    pub top: f64,
    /// Solid fraction in the core of the bed: |x|, |y| < w − 2d_max, 2d_max < z < top − 3d_max,
    /// from exact sphere ∩ box volumes (voidage's closed form).
    pub core_solid_fraction: f64,
    /// Solid fraction of the slab d_max/2 < z < top − d_max over the whole box section (wall
    /// layers included; the measure for narrow beds).
    pub slab_solid_fraction: f64,
    /// Σ sphere volumes / (box area × core solid fraction) (m): the height the bed would have
    /// at the core packing everywhere.
    pub packed_height: f64,
    /// Number of spheres.
    pub n: usize,
}

/// Measures the bed of spheres at `x` (m) with radii `r` (m) in a box of half width `w` (m).
pub fn measure(x: &[[f64; 3]], r: &[f64], w: f64) -> Bed {
    let n = x.len();
    let mut tops: Vec<f64> = x.iter().zip(r).map(|(p, r)| p[2] + r).collect();
    tops.sort_by(|a, b| b.total_cmp(a));
    let k = (n / 10).max(1);
    let top = tops[..k].iter().sum::<f64>() / k as f64;
    let d = 2.0 * r.iter().copied().fold(0.0, f64::max);
    let lo = [-w + 2.0 * d, -w + 2.0 * d, 2.0 * d];
    let hi = [w - 2.0 * d, w - 2.0 * d, top - 3.0 * d];
    let solid: f64 = x
        .iter()
        .zip(r)
        .map(|(p, &r)| voidage::sphere_box_volume(*p, r, lo, hi))
        .sum();
    let core = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    let phi = solid / core;
    let (slo, shi) = ([-w, -w, 0.5 * d], [w, w, top - d]);
    let slab: f64 = x
        .iter()
        .zip(r)
        .map(|(p, &r)| voidage::sphere_box_volume(*p, r, slo, shi))
        .sum();
    let slab_phi = slab / (4.0 * w * w * (shi[2] - slo[2]));
    let total: f64 = r
        .iter()
        .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
        .sum();
    Bed {
        top,
        core_solid_fraction: phi,
        slab_solid_fraction: slab_phi,
        packed_height: total / (4.0 * w * w * phi),
        n,
    }
}

/// Relative differences (native / reference − 1) of top, core and slab solid fractions and
/// packed height.
pub fn relative(native: &Bed, reference: &Bed) -> [f64; 4] {
    [
        native.top / reference.top - 1.0,
        native.core_solid_fraction / reference.core_solid_fraction - 1.0,
        native.slab_solid_fraction / reference.slab_solid_fraction - 1.0,
        native.packed_height / reference.packed_height - 1.0,
    ]
}
