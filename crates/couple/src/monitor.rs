//! The values of CFDEM's observing models ([`crate::config::monitors`]), as pure functions of
//! cell fields. The runner calls them after each coupling step and writes what CFDEM writes.
//!
//! Thresholds are strict, as in CFDEM: a cell counts when `lower < φ < upper` (`|φ|` for
//! vectors). Volumes in m³ (the case's units), fields in their own units.

use mesh::v3::V3;

/// `particleCellVolume`: over the cells with `lower < ε < upper`, the particle volume
/// Σ (1 − ε) V, the cells' volume Σ V, and ε's range there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellVolumeSummary {
    /// Σ (1 − ε_c) V_c over the counted cells, m³.
    pub particle_volume: f64,
    /// Σ V_c over the counted cells, m³.
    pub cell_volume: f64,
    /// Smallest ε of a counted cell (`None` when no cell counts).
    pub min: Option<f64>,
    /// Largest ε of a counted cell.
    pub max: Option<f64>,
}

impl CellVolumeSummary {
    /// The counted cells' mean solid fraction, particle volume / cell volume (`None` when no
    /// cell counts).
    pub fn average_fraction(&self) -> Option<f64> {
        (self.cell_volume > 0.0).then(|| self.particle_volume / self.cell_volume)
    }
}

/// [`CellVolumeSummary`] of the voidage field `eps` on cells of volumes `volumes`.
pub fn particle_cell_volume(
    eps: &[f64],
    volumes: &[f64],
    lower: f64,
    upper: f64,
) -> CellVolumeSummary {
    let mut s = CellVolumeSummary {
        particle_volume: 0.0,
        cell_volume: 0.0,
        min: None,
        max: None,
    };
    for (&e, &v) in eps.iter().zip(volumes) {
        if lower < e && e < upper {
            s.particle_volume += (1.0 - e) * v;
            s.cell_volume += v;
            s.min = Some(s.min.map_or(e, |m: f64| m.min(e)));
            s.max = Some(s.max.map_or(e, |m: f64| m.max(e)));
        }
    }
    s
}

/// A volume-weighted average: Σ φ V w / Σ V over the counted cells (w = ε with
/// `useVolumeFraction`, else 1), with the integral Σ φ V w and the counted volume Σ V.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolAverage<T> {
    /// Σ φ V w / Σ V (`None` when no cell counts).
    pub average: Option<T>,
    /// Σ φ V w.
    pub integral: T,
    /// Σ V of the counted cells, m³.
    pub volume: f64,
}

/// `volWeightedAverage` of a scalar field `phi`; `weights` is ε with `useVolumeFraction`.
pub fn vol_weighted_scalar(
    phi: &[f64],
    volumes: &[f64],
    weights: Option<&[f64]>,
    lower: f64,
    upper: f64,
) -> VolAverage<f64> {
    let (mut integral, mut volume) = (0.0, 0.0);
    for (c, (&x, &v)) in phi.iter().zip(volumes).enumerate() {
        if lower < x && x < upper {
            integral += x * v * weights.map_or(1.0, |w| w[c]);
            volume += v;
        }
    }
    VolAverage {
        average: (volume > 0.0).then(|| integral / volume),
        integral,
        volume,
    }
}

/// `volWeightedAverage` of a vector field `phi`; a cell counts when `lower < |φ| < upper`.
pub fn vol_weighted_vector(
    phi: &[V3],
    volumes: &[f64],
    weights: Option<&[f64]>,
    lower: f64,
    upper: f64,
) -> VolAverage<V3> {
    let (mut integral, mut volume) = (V3::zeros(), 0.0);
    for (c, (x, &v)) in phi.iter().zip(volumes).enumerate() {
        let m = x.norm();
        if lower < m && m < upper {
            integral += x * (v * weights.map_or(1.0, |w| w[c]));
            volume += v;
        }
    }
    VolAverage {
        average: (volume > 0.0).then(|| integral / volume),
        integral,
        volume,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn particle_cell_volume_counts_cells_strictly_inside_the_thresholds() {
        let eps = [1.0, 0.4, 0.6, 0.999];
        let vol = [2.0, 1.0, 3.0, 1.0];
        let s = particle_cell_volume(&eps, &vol, 0.0, 0.999);
        // cells 1 and 2: (0.6·1 + 0.4·3) = 1.8 of 4
        assert_relative_eq!(s.particle_volume, 1.8, max_relative = 1e-15);
        assert_eq!(s.cell_volume, 4.0);
        assert_relative_eq!(s.average_fraction().unwrap(), 0.45, max_relative = 1e-15);
        assert_eq!((s.min, s.max), (Some(0.4), Some(0.6)));
        let none = particle_cell_volume(&eps, &vol, 0.0, 0.3);
        assert_eq!((none.min, none.average_fraction()), (None, None));
    }

    #[test]
    fn volume_weighted_averages() {
        let phi = [1.0, 2.0, 10.0];
        let vol = [1.0, 3.0, 1.0];
        let a = vol_weighted_scalar(&phi, &vol, None, 0.0, 5.0);
        assert_relative_eq!(a.average.unwrap(), 7.0 / 4.0, max_relative = 1e-15);
        let eps = [0.5, 0.5, 1.0];
        let w = vol_weighted_scalar(&phi, &vol, Some(&eps), 0.0, 5.0);
        assert_relative_eq!(w.integral, 3.5, max_relative = 1e-15);
        assert_eq!(w.volume, 4.0);
        let u = [V3::new(3.0, 4.0, 0.0), V3::new(0.0, 0.0, 20.0)];
        let v = vol_weighted_vector(&u, &[2.0, 1.0], None, 0.0, 10.0);
        assert_relative_eq!(
            v.average.unwrap(),
            V3::new(3.0, 4.0, 0.0),
            max_relative = 1e-15
        );
    }
}
