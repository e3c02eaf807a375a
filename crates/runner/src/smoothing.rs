//! CFDEM-PFM's `smoothingModel`s ([`couple::smoothing`]) on the native fluid's
//! discretisation: their diffusion step is [`fv::diffusion::DiffusionStep`] (the coupler does
//! not depend on `fv`; this is where the two meet).

use couple::smoothing::{Diffusion, Smoothing, SmoothingModel};
use couple::CoupleError;
use foam::PolyMesh;
use fv::diffusion::DiffusionStep;

/// fv's diffusion step as the smoothing's [`Diffusion`].
#[derive(Debug)]
struct FvDiffusion(DiffusionStep);

impl Diffusion for FvDiffusion {
    fn volumes(&self) -> &[f64] {
        self.0.volumes()
    }

    fn diffuse(&self, eps: &mut [f64]) -> Result<usize, String> {
        self.0
            .solve(eps, "smoothed ε")
            .map(|stats| stats.iterations)
            .map_err(|e| e.to_string())
    }

    fn diffuse_local(&self, eps: &mut [f64], l2: &[f64]) -> Result<usize, String> {
        if l2.len() != eps.len() {
            return Err(format!("{} lengths for {} cells", l2.len(), eps.len()));
        }
        self.0
            .solve_local(eps, l2, "smoothed ε")
            .map(|stats| stats.iterations)
            .map_err(|e| e.to_string())
    }
}

/// The smoothing `model` (or `constDiffSmoothing` with its settings) on `mesh`, diffused by
/// `fv`'s step.
pub fn native(mesh: &PolyMesh, model: impl Into<SmoothingModel>) -> Result<Smoothing, CoupleError> {
    Smoothing::new(model, |length| {
        let step = DiffusionStep::new(mesh, length).map_err(|e| e.to_string())?;
        Ok(Box::new(FvDiffusion(step)) as Box<dyn Diffusion>)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use couple::smoothing::SmoothingSettings;

    /// A row of `n` cubes of side h along x (blockMesh-like numbering), walls all round.
    fn row(n: usize, h: f64) -> PolyMesh {
        mesh::build::uniform_box([0.0; 3], [n as f64 * h, h, h], [n, 1, 1])
    }

    #[test]
    fn smoothing_conserves_particle_volume_and_matches_the_discrete_closed_form() {
        let (n, h, l) = (80, 1e-3, 1.5e-3);
        let s = native(
            &row(n, h),
            SmoothingSettings {
                length: l,
                lower: 0.0,
                upper: 1e99,
            },
        )
        .unwrap();
        // a bed of ε 0.4 in the middle two cells
        let mut eps = vec![1.0; n];
        eps[39] = 0.4;
        eps[40] = 0.4;
        let solid = |e: &[f64]| e.iter().map(|x| (1.0 - x) * h * h * h).sum::<f64>();
        let before = solid(&eps);
        let r = s.smooth(&mut eps).unwrap();
        assert_eq!(r.bounded_cells, 0);
        assert!((solid(&eps) - before).abs() <= 1e-12 * before);
        // the 1-D discrete equation (1 + 2k) x_i − k (x_{i−1} + x_{i+1}) = x0_i, k = (L/h)²,
        // away from the bed and from the ends (whose reflection is r^(2·distance), < 1e-10
        // here): the solid fraction decays by the root r < 1 of k r² − (1 + 2k) r + k = 0
        let k = (l / h).powi(2);
        let root = ((1.0 + 2.0 * k) - ((1.0 + 2.0 * k).powi(2) - 4.0 * k * k).sqrt()) / (2.0 * k);
        for i in 44..50 {
            let ratio = (1.0 - eps[i + 1]) / (1.0 - eps[i]);
            assert!((ratio - root).abs() < 1e-9, "cell {i}: {ratio} vs {root}");
        }
        // symmetric about the bed
        for i in 0..n / 2 {
            assert!((eps[i] - eps[n - 1 - i]).abs() < 1e-12);
        }
    }

    #[test]
    fn the_bounds_report_the_volume_they_change() {
        let h = 1e-3;
        let s = native(
            &row(10, h),
            SmoothingSettings {
                length: 1e-4,
                lower: 0.5,
                upper: 1e10,
            },
        )
        .unwrap();
        let mut eps = vec![1.0; 10];
        eps[5] = 0.2;
        let r = s.smooth(&mut eps).unwrap();
        assert_eq!(r.bounded_cells, 1);
        assert_eq!(eps[5], 0.5);
        // what the bound removed plus what is left is the solid volume put in
        let left: f64 = eps.iter().map(|x| (1.0 - x) * h * h * h).sum();
        assert!((left + r.bounded_volume - 0.8 * h * h * h).abs() < 1e-15);
        assert!(r.bounded_volume > 0.0);
    }

    #[test]
    fn bad_settings_are_errors() {
        let bad = |length, lower, upper| {
            native(
                &row(3, 1.0),
                SmoothingSettings {
                    length,
                    lower,
                    upper,
                },
            )
            .unwrap_err()
            .to_string()
        };
        assert!(bad(0.0, 0.0, 1.0).contains("smoothingLength"));
        assert!(bad(1.0, 2.0, 1.0).contains("lowerLimit"));
    }
}
