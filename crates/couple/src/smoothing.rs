//! CFDEM's `smoothingModel constDiffSmoothing` (CFDEMcoupling-PFM, used by many of its
//! tutorials, e.g. `cfdemSolverPiso/settlingTestMPI`): the voidage handed to the fluid is spread
//! by one implicit diffusion step of length L (`constDiffSmoothingProps/smoothingLength`, m),
//!
//!   ε − D Δt ∇²ε = ε₀,  D = L²/Δt   ⇒   V_c ε_c − Σ_f L² |S_f| δ_f (ε_N − ε_c) = V_c ε₀,c,
//!
//! (PFM's `constDiffSmoothing::smoothen`: `fvm::ddt(ε) − fvm::laplacian(L²/Δt, ε)` from the
//! unsmoothed field, so Δt cancels), with zero gradient at the boundary (no flux through it:
//! Σ V(1 − ε), the particle volume, is conserved to the solver's tolerance) and across cyclic
//! pairs as across internal faces. δ_f is OpenFOAM's non-orthogonal delta coefficient
//! 1/max(n̂·d, 0.05 |d|) ([`fv::FvGeometry::delta_coeff`]), the implicit part of `Gauss linear
//! corrected`; the explicit non-orthogonal correction is left out (zero on the orthogonal
//! meshes of the tutorials). ε is then bounded to [`lowerLimit`, `upperLimit`], as PFM does;
//! the solid volume that bound adds or removes is returned, so the run reports it.
//!
//! PFM also smooths the cell-averaged particle velocity Us as a "reference field" (cells with
//! particles keep their value, empty cells take their neighbours'). That changes Us only where
//! Ksl = 0 (PFM does not smooth Ksl), so the fluid's momentum does not see it: it is not done
//! here. The drag uses each particle's unsmoothed ε, as PFM's does without `interpolation`.
//! (With `interpolation true`, PFM interpolates the smoothed field to the particle.)

use crate::CoupleError;
use foam::PolyMesh;
use fv::ldu::Ldu;
use fv::linsolve::{pcg, Preconditioner, SolverControls};
use fv::FvGeometry;

/// How far above 1 a smoothed ε may come out of the solver by round-off alone (the solve's
/// tolerance is 1e-14 of the normalised residual); such a value is set to 1, uncounted.
const ROUND_OFF: f64 = 1e-9;

/// The settings of `constDiffSmoothingProps`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothingSettings {
    /// `smoothingLength` L, m (> 0).
    pub length: f64,
    /// `lowerLimit`: ε is raised to at least this.
    pub lower: f64,
    /// `upperLimit`: ε is lowered to at most this.
    pub upper: f64,
}

impl SmoothingSettings {
    /// What makes these settings unusable, if anything: the `constDiffSmoothingProps` key at
    /// fault and why (a length that is not positive and finite, limits that are not ordered).
    pub fn problem(&self) -> Option<(&'static str, String)> {
        if !(self.length.is_finite() && self.length > 0.0) {
            return Some((
                "smoothingLength",
                format!("{} is not a positive length (m)", self.length),
            ));
        }
        if self.lower.is_nan() || self.upper.is_nan() || self.lower > self.upper {
            return Some((
                "lowerLimit",
                format!("{} is above upperLimit {}", self.lower, self.upper),
            ));
        }
        None
    }
}

/// The smoothing operator on one mesh: the matrix V + L²·(−∇²) assembled once.
#[derive(Debug)]
pub struct ConstDiffSmoothing {
    settings: SmoothingSettings,
    g: FvGeometry,
    a: Ldu,
}

/// What one smoothing did to the particle volume.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SmoothingReport {
    /// Solid volume removed by the bounds, m³ (Σ (ε_bounded − ε)·V; negative when added).
    pub bounded_volume: f64,
    /// Cells the bounds changed.
    pub bounded_cells: usize,
    /// Linear-solver iterations.
    pub iterations: usize,
}

impl ConstDiffSmoothing {
    /// The operator on `mesh` for `settings`.
    pub fn new(mesh: &PolyMesh, settings: SmoothingSettings) -> Result<Self, CoupleError> {
        if let Some((key, why)) = settings.problem() {
            return Err(CoupleError::Parameter(format!(
                "constDiffSmoothing: {key}: {why}"
            )));
        }
        let g = FvGeometry::new(mesh)
            .map_err(|e| CoupleError::Parameter(format!("constDiffSmoothing: {e}")))?;
        let mut a = Ldu::zeros(&g);
        a.diag.clone_from(&g.v);
        let l2 = settings.length * settings.length;
        for f in 0..g.n_internal {
            let c = l2 * g.mag_sf[f] * g.delta_coeff[f];
            a.upper[f] = -c;
            a.lower[f] = -c;
            a.diag[g.owner[f] as usize] += c;
            a.diag[g.neighbour[f] as usize] += c;
        }
        Ok(ConstDiffSmoothing { settings, g, a })
    }

    /// The settings.
    pub fn settings(&self) -> SmoothingSettings {
        self.settings
    }

    /// Smooths `eps` (one value per cell) in place and bounds it (module docs).
    pub fn smooth(&self, eps: &mut [f64]) -> Result<SmoothingReport, CoupleError> {
        let g = &self.g;
        if eps.len() != g.n_cells {
            return Err(CoupleError::Parameter(format!(
                "constDiffSmoothing: {} voidage values for {} cells",
                eps.len(),
                g.n_cells
            )));
        }
        let b: Vec<f64> = eps.iter().zip(&g.v).map(|(e, v)| e * v).collect();
        let controls = SolverControls {
            tolerance: 1e-14,
            rel_tol: 0.0,
            max_iter: 1000,
            min_iter: 0,
        };
        let stats = pcg(
            &self.a,
            g,
            &b,
            eps,
            Preconditioner::Dic,
            &controls,
            "smoothed ε",
        )
        .map_err(|e| CoupleError::Parameter(format!("constDiffSmoothing: {e}")))?;
        let mut report = SmoothingReport {
            iterations: stats.iterations,
            ..SmoothingReport::default()
        };
        let SmoothingSettings { lower, upper, .. } = self.settings;
        for (e, v) in eps.iter_mut().zip(&g.v) {
            // diffusion keeps ε ≤ 1 (a maximum principle): above it is the solver's round-off
            if *e > 1.0 && *e <= 1.0 + ROUND_OFF {
                *e = 1.0;
            }
            let bounded = e.clamp(lower, upper);
            if bounded != *e {
                report.bounded_volume += (bounded - *e) * v;
                report.bounded_cells += 1;
                *e = bounded;
            }
        }
        Ok(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row of `n` cubes of side h along x (blockMesh-like numbering), walls all round.
    fn row(n: usize, h: f64) -> PolyMesh {
        mesh::build::uniform_box([0.0; 3], [n as f64 * h, h, h], [n, 1, 1])
    }

    #[test]
    fn smoothing_conserves_particle_volume_and_matches_the_discrete_closed_form() {
        let (n, h, l) = (80, 1e-3, 1.5e-3);
        let s = ConstDiffSmoothing::new(
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
        let s = ConstDiffSmoothing::new(
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
            ConstDiffSmoothing::new(
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
