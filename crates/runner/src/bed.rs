//! Measurements of a particle bed used by the references: bed height and mean voidage.

/// A packed bed measured from its particles in a vertical column of cross-section `area`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bed {
    /// Height of the bed top above `floor`, m: the mean of the highest 1 % of sphere tops
    /// (at least one sphere), which is insensitive to single particles sticking out.
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
    /// Measures a bed: `heights[i]` is particle i's centre coordinate along the column axis
    /// (measured from `floor` upwards), `radii` and `densities` per particle, `area` the column
    /// cross-section (m²). Returns `None` for no particles or a non-positive area.
    pub fn measure(
        heights: &[f64],
        radii: &[f64],
        densities: &[f64],
        floor: f64,
        area: f64,
    ) -> Option<Bed> {
        let n = heights.len();
        if n == 0 || radii.len() != n || densities.len() != n || area.is_nan() || area <= 0.0 {
            return None;
        }
        let mut tops: Vec<f64> = heights
            .iter()
            .zip(radii)
            .map(|(h, r)| h + r - floor)
            .collect();
        tops.sort_by(|a, b| b.total_cmp(a));
        let k = (n / 100).max(1);
        let height = tops[..k].iter().sum::<f64>() / k as f64;
        let vol = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        let solid_volume: f64 = radii.iter().map(|&r| vol(r)).sum();
        let mass: f64 = radii.iter().zip(densities).map(|(&r, &d)| d * vol(r)).sum();
        let d3: f64 = radii.iter().map(|r| (2.0 * r).powi(3)).sum();
        let d2: f64 = radii.iter().map(|r| (2.0 * r).powi(2)).sum();
        Some(Bed {
            height,
            voidage: 1.0 - solid_volume / (area * height),
            solid_volume,
            mass,
            particles: n,
            sauter_diameter: d3 / d2,
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
            for _ in 0..100 {
                h.push(0.5 + k as f64);
            }
        }
        let r = vec![0.5; h.len()];
        let rho = vec![2.0; h.len()];
        let bed = Bed::measure(&h, &r, &rho, 0.0, 100.0).unwrap();
        assert!((bed.height - 5.0).abs() < 1e-12);
        assert!((bed.voidage - (1.0 - std::f64::consts::PI / 6.0)).abs() < 1e-12);
        assert!((bed.sauter_diameter - 1.0).abs() < 1e-12);
        // weight per area: (ρp − ρf) Vp g / A
        let w = bed.weight_per_area(1.0, 10.0, 100.0);
        let vp = 500.0 * std::f64::consts::PI / 6.0;
        assert!((w - (2.0 - 1.0) * vp * 10.0 / 100.0).abs() < 1e-12);
    }

    #[test]
    fn sauter_diameter_of_a_binary_mixture() {
        let r = [0.5, 1.0];
        let bed = Bed::measure(&[1.0, 1.0], &r, &[1.0, 1.0], 0.0, 1.0).unwrap();
        assert!((bed.sauter_diameter - (1.0 + 8.0) / (1.0 + 4.0)).abs() < 1e-12);
    }

    #[test]
    fn empty_or_degenerate_input_is_none() {
        assert!(Bed::measure(&[], &[], &[], 0.0, 1.0).is_none());
        assert!(Bed::measure(&[1.0], &[0.5], &[1.0], 0.0, 0.0).is_none());
        assert!(Bed::measure(&[1.0], &[0.5, 0.5], &[1.0], 0.0, 1.0).is_none());
    }
}
