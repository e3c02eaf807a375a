//! The three reference diameters of a polydisperse bed that Volk et al. (2018, seed 001)
//! non-dimensionalise the cell size with, and Δx/d for each.

use serde::Serialize;

/// Reference diameters of a set of spheres, m.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Diameters {
    /// Number mean d₁₀ = Σd / N.
    pub mean: f64,
    /// Sauter mean d₃₂ = Σd³ / Σd² (the surface–volume mean, Ergun's d for mixtures).
    pub sauter: f64,
    /// Largest diameter.
    pub largest: f64,
}

impl Diameters {
    /// The diameters of `d` (m); `None` for an empty or non-positive set.
    pub fn of(d: &[f64]) -> Option<Diameters> {
        if d.is_empty() || d.iter().any(|&x| !(x.is_finite() && x > 0.0)) {
            return None;
        }
        let s1: f64 = d.iter().sum();
        let s2: f64 = d.iter().map(|x| x * x).sum();
        let s3: f64 = d.iter().map(|x| x * x * x).sum();
        Some(Diameters {
            mean: s1 / d.len() as f64,
            sauter: s3 / s2,
            largest: d.iter().copied().fold(0.0, f64::max),
        })
    }

    /// A cell size h (m) made dimensionless with each diameter.
    pub fn ratios(&self, h: f64) -> CellSize {
        CellSize {
            h,
            over_mean: h / self.mean,
            over_sauter: h / self.sauter,
            over_largest: h / self.largest,
        }
    }
}

/// A representative cell size and its three dimensionless forms.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CellSize {
    /// h = (V / N)^(1/3), m (Celik et al. 2008 eq. 1; the cell edge for cubic cells).
    pub h: f64,
    /// h / d₁₀.
    pub over_mean: f64,
    /// h / d₃₂ (the size the study's `dx_over_d` option sets).
    pub over_sauter: f64,
    /// h / d_max.
    pub over_largest: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_binary_mixture_by_hand() {
        // 1 sphere of 0.5 mm and 8 of 0.25 mm (equal volumes): d10 = (0.5 + 2)/9,
        // d32 = (0.125 + 8·0.015625)/(0.25 + 8·0.0625) = 0.25/0.75 = 1/3 mm.
        let mut d = vec![0.5e-3];
        d.extend([0.25e-3; 8]);
        let m = Diameters::of(&d).unwrap();
        assert!((m.mean - 2.5e-3 / 9.0).abs() < 1e-18);
        assert!((m.sauter - 1e-3 / 3.0).abs() < 1e-18);
        assert_eq!(m.largest, 0.5e-3);
        let c = m.ratios(1e-3);
        assert!((c.over_sauter - 3.0).abs() < 1e-12);
        assert!((c.over_largest - 2.0).abs() < 1e-12);
        assert!(Diameters::of(&[]).is_none());
        assert!(Diameters::of(&[1.0, 0.0]).is_none());
    }
}
