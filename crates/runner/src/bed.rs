//! Measurements of a particle bed used by the references: bed height and mean voidage.

use mesh::v3::{unit, V3};
use voidage::sphere_box::ball_volume;

/// A packed bed measured from its particles in a vertical column of cross-section `area`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bed {
    /// Height of the bed surface above `floor`, m: the cross-section is divided into square
    /// bins of side 2·d₃₂ (Sauter diameter); in each bin holding particles the highest sphere
    /// top is taken, and the height is the mean over the bins — the mean surface of the bed,
    /// insensitive to single particles sticking out. (Ergun's reference is sensitive to this
    /// definition: for the Ergun case, bins of 1, 2, 3 d and the mean of the highest 1 % of
    /// tops give heights 0.01511, 0.01553, 0.01566, 0.01574 m and Δp references within ±12 %.)
    pub height: f64,
    /// Mean fluid fraction of the bed, 1 − V_particles / (area · height).
    pub voidage: f64,
    /// Total particle volume, m³.
    pub solid_volume: f64,
    /// Total particle mass, kg.
    pub mass: f64,
    /// Number of particles.
    pub particles: usize,
    /// Sauter mean diameter Σd³/Σd², m.
    pub sauter_diameter: f64,
}

impl Bed {
    /// Measures a bed: `positions` of the particle centres, `axis` the unit vector up the
    /// column, `floor` the column's bottom along it (m), `radii` and `densities` per particle,
    /// `area` the column cross-section (m²). Returns `None` for no particles, mismatched
    /// lengths, a non-positive area or a zero axis.
    pub fn measure(
        positions: &[V3],
        axis: V3,
        radii: &[f64],
        densities: &[f64],
        floor: f64,
        area: f64,
    ) -> Option<Bed> {
        Bed::measure_on(
            &couple::Serial::default(),
            positions,
            axis,
            radii,
            densities,
            floor,
            area,
        )
    }

    /// [`Bed::measure`] of the particles of all `ranks`, each giving its own (collective; the
    /// bins' tops are gathered on rank 0, whose result is the bed; other ranks get the sums
    /// and rank 0's height).
    pub fn measure_on(
        ranks: &dyn couple::Ranks,
        positions: &[V3],
        axis: V3,
        radii: &[f64],
        densities: &[f64],
        floor: f64,
        area: f64,
    ) -> Option<Bed> {
        let n = positions.len();
        let consistent = radii.len() == n && densities.len() == n;
        let mut sums = [
            n as f64,
            radii.iter().map(|&r| ball_volume(r)).sum(),
            radii
                .iter()
                .zip(densities)
                .map(|(&r, &d)| d * ball_volume(r))
                .sum(),
            radii.iter().map(|r| (2.0 * r).powi(3)).sum(),
            radii.iter().map(|r| (2.0 * r).powi(2)).sum(),
            f64::from(u8::from(!consistent)),
        ];
        ranks.all_sum(&mut sums);
        let [count, solid_volume, mass, d3, d2, inconsistent] = sums;
        if count == 0.0 || inconsistent > 0.0 || area.is_nan() || area <= 0.0 {
            return None;
        }
        let sauter = d3 / d2;
        let t = if axis[0].abs() < 0.9 {
            V3::x()
        } else {
            V3::y()
        };
        let e1 = unit(axis.cross(&t))?;
        let e2 = axis.cross(&e1);
        let bin = 2.0 * sauter;
        // ordered bins: the sum over them is the same in every process (a HashMap's order,
        // random per process, made the last bit of the height differ between two runs)
        let mut tops: std::collections::BTreeMap<(i64, i64), f64> = Default::default();
        for (x, r) in positions.iter().zip(radii) {
            let key = (
                ((*x).dot(&e1) / bin).floor() as i64,
                ((*x).dot(&e2) / bin).floor() as i64,
            );
            let top = (*x).dot(&axis) + r - floor;
            let e = tops.entry(key).or_insert(f64::NEG_INFINITY);
            *e = e.max(top);
        }
        // (bin i, bin j, top) per bin; bins indices are far below 2⁵³, exact as f64
        let flat: Vec<f64> = tops
            .iter()
            .flat_map(|(&(i, j), &top)| [i as f64, j as f64, top])
            .collect();
        let mut merged: std::collections::BTreeMap<(i64, i64), f64> = Default::default();
        for part in ranks.gather(&flat) {
            for t in part.chunks_exact(3) {
                let e = merged
                    .entry((t[0] as i64, t[1] as i64))
                    .or_insert(f64::NEG_INFINITY);
                *e = e.max(t[2]);
            }
        }
        let mut height = [if merged.is_empty() {
            0.0
        } else {
            merged.values().sum::<f64>() / merged.len() as f64
        }];
        ranks.broadcast(&mut height);
        let height = height[0];
        Some(Bed {
            height,
            voidage: 1.0 - solid_volume / (area * height),
            solid_volume,
            mass,
            particles: count as usize,
            sauter_diameter: sauter,
        })
    }

    /// Buoyant weight of the bed per unit cross-section, Pa:
    /// (m − ρ_f V_p) g / A — the pressure drop at which the bed fluidises.
    pub fn weight_per_area(&self, rho_fluid: f64, g: f64, area: f64) -> f64 {
        (self.mass - rho_fluid * self.solid_volume) * g / area
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_cubic_layers_give_the_textbook_voidage() {
        // Spheres d = 1 on a simple cubic lattice, 10 × 10 × 5 in a 10 × 10 column: the bed top is
        // at 5 and the voidage is 1 − π/6.
        let mut h = vec![];
        for k in 0..5 {
            for i in 0..10 {
                for j in 0..10 {
                    h.push(V3::new(0.5 + i as f64, 0.5 + j as f64, 0.5 + k as f64));
                }
            }
        }
        let r = vec![0.5; h.len()];
        let rho = vec![2.0; h.len()];
        let bed = Bed::measure(&h, V3::z(), &r, &rho, 0.0, 100.0).unwrap();
        assert!((bed.height - 5.0).abs() < 1e-12);
        assert!((bed.voidage - (1.0 - std::f64::consts::PI / 6.0)).abs() < 1e-12);
        assert!((bed.sauter_diameter - 1.0).abs() < 1e-12);
        // weight per area: (ρp − ρf) Vp g / A
        let w = bed.weight_per_area(1.0, 10.0, 100.0);
        let vp = 500.0 * std::f64::consts::PI / 6.0;
        assert!((w - (2.0 - 1.0) * vp * 10.0 / 100.0).abs() < 1e-12);
    }

    #[test]
    fn the_surface_is_the_mean_of_the_bin_tops_not_the_outliers() {
        // A flat layer of spheres (tops at 1) on a 20 × 20 grid, d = 1, plus one sphere sticking
        // out to a top of 3: bins are 2 × 2 wide, so 1 of 100 bins reads 3.
        let mut x = vec![];
        for i in 0..20 {
            for j in 0..20 {
                x.push(V3::new(0.5 + i as f64, 0.5 + j as f64, 0.5));
            }
        }
        x.push(V3::new(0.5, 0.5, 2.5));
        let n = x.len();
        let bed = Bed::measure(&x, V3::z(), &vec![0.5; n], &vec![1.0; n], 0.0, 400.0).unwrap();
        assert!(
            (bed.height - (99.0 * 1.0 + 3.0) / 100.0).abs() < 1e-12,
            "{}",
            bed.height
        );
        // The same bed along −x: axis and floor follow.
        let xr: Vec<V3> = x.iter().map(|p| V3::new(-p[2], p[1], p[0])).collect();
        let b2 = Bed::measure(&xr, -V3::x(), &vec![0.5; n], &vec![1.0; n], 0.0, 400.0).unwrap();
        assert!((b2.height - bed.height).abs() < 1e-12);
    }

    #[test]
    fn sauter_diameter_of_a_binary_mixture() {
        let r = [0.5, 1.0];
        let bed = Bed::measure(&[V3::z(); 2], V3::z(), &r, &[1.0, 1.0], 0.0, 1.0).unwrap();
        assert!((bed.sauter_diameter - (1.0 + 8.0) / (1.0 + 4.0)).abs() < 1e-12);
    }

    #[test]
    fn empty_or_degenerate_input_is_none() {
        let z = V3::z();
        assert!(Bed::measure(&[], z, &[], &[], 0.0, 1.0).is_none());
        assert!(Bed::measure(&[V3::zeros()], z, &[0.5], &[1.0], 0.0, 0.0).is_none());
        assert!(Bed::measure(&[V3::zeros()], z, &[0.5, 0.5], &[1.0], 0.0, 1.0).is_none());
    }
}
