//! `cohesion sjkr`: the simplified JKR cohesion of LIGGGHTS — an attractive normal force
//! F = −k·A proportional to the contact area A, k the cohesion energy density (J/m³).
//!
//! A is the area of the circle in which the two sphere surfaces intersect,
//! A = π a² with a² = −(r−Rᵢ−Rⱼ)(r+Rᵢ−Rⱼ)(r−Rᵢ+Rⱼ)(r+Rᵢ+Rⱼ)/(4r²) (the radius of the
//! intersection circle of two spheres at distance r), and A = π(Rᵢ² − r²) against a wall at
//! distance r. Seed 002 (Madden 2020) eq. 9 writes the same force as k·2πδ·(2R)… for equal
//! spheres at small overlap: a² ≈ R δ for two spheres of radius R, so F ≈ −kπRδ.

/// Normal cohesion force (N, negative = attractive) for energy density `k` (J/m³), centre
/// distance `r` (m), radii `radi`, `radj` (m); for a wall `r` is the centre–wall distance.
#[inline]
pub fn sjkr_force(k: f64, r: f64, radi: f64, radj: f64, is_wall: bool) -> f64 {
    let area = if is_wall {
        (radi * radi - r * r) * std::f64::consts::PI
    } else {
        -std::f64::consts::PI / 4.0
            * ((r - radi - radj) * (r + radi - radj) * (r - radi + radj) * (r + radi + radj))
            / (r * r)
    };
    -k * area
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_is_the_intersection_circle() {
        // Two unit spheres at distance r = 1.6: the circle has radius √(1 − 0.8²) = 0.6,
        // A = 0.36π; with k = 2 the force is −0.72π. Wall at distance 0.8: same circle.
        let f = sjkr_force(2.0, 1.6, 1.0, 1.0, false);
        assert!((f + 0.72 * std::f64::consts::PI).abs() < 1e-14);
        let f = sjkr_force(2.0, 0.8, 1.0, 0.0, true);
        assert!((f + 0.72 * std::f64::consts::PI).abs() < 1e-14);
    }
}
