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

/// `fieldTimeAverage`: adds sample number `count` (from 0) of a field to the running mean
/// `mean` of the samples before it, as CFDEM-PUBLIC's `fieldTimeAverage::averaging` does:
/// the first sample is copied, then mean ← (mean·n + x)/(n + 1). After N samples `mean` is
/// their arithmetic mean (to round-off, a few ulp per sample).
pub fn accumulate_mean<T>(mean: &mut Vec<T>, count: u64, x: &[T])
where
    T: Copy
        + std::ops::Mul<f64, Output = T>
        + std::ops::Add<Output = T>
        + std::ops::Div<f64, Output = T>,
{
    if count == 0 || mean.len() != x.len() {
        mean.clear();
        mean.extend_from_slice(x);
        return;
    }
    let n = count as f64;
    for (m, &v) in mean.iter_mut().zip(x) {
        *m = (*m * n + v) / (n + 1.0);
    }
}

/// `particleVolume`: Σ 4πr³/3 (m³) over the particles of radii `radius` (m) for which
/// `located(i)` holds (CFDEM-PUBLIC's `particleVolume.C`: the particles whose centre cell is
/// found, `cellIDs()[i][0] >= 0`).
pub fn located_particle_volume(radius: &[f64], located: impl Fn(usize) -> bool) -> f64 {
    let c = 4.0 / 3.0 * std::f64::consts::PI;
    radius
        .iter()
        .enumerate()
        .filter(|&(i, _)| located(i))
        .map(|(_, &r)| c * r * r * r)
        .sum()
}

/// The momentum exchanged between the fluid and the particles in one coupling step, as the
/// force on the particles (N), from the exchange fields (ADR 0004).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MomentumExchange {
    /// Σ_c V_c Ksl_c (U_c − Us_c): the implicitly coupled part (drag), N.
    pub implicit: V3,
    /// −Σ_c V_c f_c: the explicitly coupled part, N (zero when not summed).
    pub explicit: V3,
}

impl MomentumExchange {
    /// implicit + explicit, N.
    pub fn total(&self) -> V3 {
        self.implicit + self.explicit
    }
}

/// `totalMomentumExchange` over the cells of volumes `volumes` (m³): Ksl (kg/(m³·s)), the
/// fluid's U and the particles' Us (m/s), and f (N/m³, the particles' force density on the
/// fluid; summed only with `explicit`). With Ksl_c = Σ_p w_pc β_p / V_c and Us_c the
/// β-weighted particle velocity (ADR 0004) the implicit part equals Σ_p β_p (U_c(p) − v_p),
/// the particles' drag at the cell's U, and the explicit part Σ_p F_p, to round-off.
pub fn total_momentum_exchange(
    ksl: &[f64],
    u: &[V3],
    us: &[V3],
    f: &[V3],
    volumes: &[f64],
    explicit: bool,
) -> MomentumExchange {
    let mut m = MomentumExchange {
        implicit: V3::zeros(),
        explicit: V3::zeros(),
    };
    for (c, &v) in volumes.iter().enumerate() {
        m.implicit += (u[c] - us[c]) * (ksl[c] * v);
        if explicit {
            m.explicit -= f[c] * v;
        }
    }
    m
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

#[cfg(test)]
mod exchange_tests {
    use super::*;
    use crate::interpolate::Placement;
    use approx::assert_relative_eq;
    use voidage::{CellShares, Method};

    /// fieldTimeAverage of fields with a closed-form history: x_k = a + b k + c k² per cell
    /// (k = 0 … N−1) has the mean a + b (N−1)/2 + c (N−1)(2N−1)/6 (Σ k and Σ k² in closed
    /// form); the running mean agrees to 1e-13 relative after N = 1000 samples.
    #[test]
    fn time_average_of_a_polynomial_history() {
        let (a, b, c) = ([1.0, -2.0], [0.5, 3.0], [1e-3, -2e-4]);
        let n = 1000u64;
        let mut mean = Vec::new();
        let mut vmean: Vec<V3> = Vec::new();
        for k in 0..n {
            let kf = k as f64;
            let x: Vec<f64> = (0..2).map(|i| a[i] + b[i] * kf + c[i] * kf * kf).collect();
            accumulate_mean(&mut mean, k, &x);
            let v = [V3::new(x[0], x[1], kf.sin())];
            accumulate_mean(&mut vmean, k, &v);
        }
        let nf = n as f64;
        for i in 0..2 {
            let exact = a[i] + b[i] * (nf - 1.0) / 2.0 + c[i] * (nf - 1.0) * (2.0 * nf - 1.0) / 6.0;
            assert_relative_eq!(mean[i], exact, max_relative = 1e-13);
        }
        // Σ_{k<N} sin k = sin(N/2) sin((N−1)/2) / sin(1/2)
        let sines = (nf / 2.0).sin() * ((nf - 1.0) / 2.0).sin() / 0.5f64.sin();
        assert_relative_eq!(vmean[0].z, sines / nf, epsilon = 1e-14);
        assert_relative_eq!(vmean[0].x, mean[0], max_relative = 1e-15);
    }

    #[test]
    fn particle_volume_counts_located_particles() {
        let r = [1.0, 2.0, 3.0];
        // the third is outside: 4π/3 (1 + 8) = 12π
        let v = located_particle_volume(&r, |i| i < 2);
        assert_relative_eq!(v, 12.0 * std::f64::consts::PI, max_relative = 1e-15);
    }

    /// The total momentum exchange from the cell fields equals the particles' summed force:
    /// three particles over two cells (one split between both), drag β_p (U_c − v_p) at its
    /// cells' fluid velocity and an explicit force F_p each; the reference is the sum over
    /// particles, Σ_p Σ_c w_pc β_p (U_c − v_p) and Σ_p F_p.
    #[test]
    fn total_exchange_is_the_particles_summed_force() {
        let placement = Placement {
            centre: vec![Some(0), Some(1), Some(1)],
            shares: CellShares {
                method: Method::Divided,
                offsets: vec![0, 1, 3, 4],
                cells: vec![0, 0, 1, 1],
                volumes: vec![1e-9, 0.25e-9, 0.75e-9, 2e-9],
            },
        };
        let volumes = [2e-6, 3e-6];
        let beta = [1e-3, 2e-3, 4e-3];
        let v = [
            V3::new(0.1, 0.0, 0.0),
            V3::new(0.0, -0.2, 0.05),
            V3::new(0.3, 0.1, 0.0),
        ];
        let force = [
            V3::new(0.0, 0.0, -1e-4),
            V3::new(2e-5, 0.0, 0.0),
            V3::new(0.0, 3e-5, 1e-5),
        ];
        let ex = crate::exchange::exchange(&placement, &volumes, &beta, &v, &force);
        let u = [V3::new(1.0, 0.5, -0.1), V3::new(-0.4, 0.2, 0.7)];
        let m = total_momentum_exchange(&ex.ksl, &u, &ex.us, &ex.f, &volumes, true);
        let mut drag = V3::zeros();
        let mut explicit = V3::zeros();
        for p in 0..3 {
            placement.for_each_weight(p, |c, w| drag += (u[c as usize] - v[p]) * (w * beta[p]));
            explicit += force[p];
        }
        for k in 0..3 {
            assert_relative_eq!(m.implicit[k], drag[k], max_relative = 1e-13);
            assert_relative_eq!(m.explicit[k], explicit[k], max_relative = 1e-13);
        }
        let none = total_momentum_exchange(&ex.ksl, &u, &ex.us, &ex.f, &volumes, false);
        assert_eq!(none.explicit, V3::zeros());
        assert_eq!(none.total(), none.implicit);
    }
}
