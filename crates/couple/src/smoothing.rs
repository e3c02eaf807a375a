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
//! 1/max(n̂·d, 0.05 |d|), the implicit part of `Gauss linear corrected`; the explicit
//! non-orthogonal correction is left out (zero on the orthogonal meshes of the tutorials).
//! That step is the fluid's discretisation, which the coupler does not own: it is a
//! [`Diffusion`] (the native one is `fv::diffusion::DiffusionStep`, built by
//! `runner::native::smoothing`). ε is then bounded to [`lowerLimit`, `upperLimit`], as PFM
//! does; the solid volume that bound adds or removes is returned, so the run reports it.
//!
//! PFM also smooths the cell-averaged particle velocity Us as a "reference field" (cells with
//! particles keep their value, empty cells take their neighbours'). That changes Us only where
//! Ksl = 0 (PFM does not smooth Ksl), so the fluid's momentum does not see it: it is not done
//! here. The drag uses each particle's unsmoothed ε, as PFM's does without `interpolation`.
//! (With `interpolation true`, PFM interpolates the smoothed field to the particle.)

use crate::CoupleError;

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

/// One implicit diffusion step of length L on the fluid's mesh (module docs), assembled once.
pub trait Diffusion: std::fmt::Debug + Send + Sync {
    /// The cell volumes V_c, m³ (one per cell).
    fn volumes(&self) -> &[f64];
    /// ε₀ → ε in place: the linear solver's iterations, or what failed.
    fn diffuse(&self, eps: &mut [f64]) -> Result<usize, String>;
}

/// The smoothing operator on one mesh: the settings and their diffusion step.
#[derive(Debug)]
pub struct ConstDiffSmoothing {
    settings: SmoothingSettings,
    diffusion: Box<dyn Diffusion>,
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
    /// The operator for `settings`, with the diffusion step `diffusion` builds for the
    /// smoothing length (m) once the settings are checked.
    pub fn new(
        settings: SmoothingSettings,
        diffusion: impl FnOnce(f64) -> Result<Box<dyn Diffusion>, String>,
    ) -> Result<Self, CoupleError> {
        if let Some((key, why)) = settings.problem() {
            return Err(CoupleError::Parameter(format!(
                "constDiffSmoothing: {key}: {why}"
            )));
        }
        let diffusion = diffusion(settings.length)
            .map_err(|e| CoupleError::Parameter(format!("constDiffSmoothing: {e}")))?;
        Ok(ConstDiffSmoothing {
            settings,
            diffusion,
        })
    }

    /// The settings.
    pub fn settings(&self) -> SmoothingSettings {
        self.settings
    }

    /// Smooths `eps` (one value per cell) in place and bounds it (module docs).
    pub fn smooth(&self, eps: &mut [f64]) -> Result<SmoothingReport, CoupleError> {
        let volumes = self.diffusion.volumes();
        if eps.len() != volumes.len() {
            return Err(CoupleError::Parameter(format!(
                "constDiffSmoothing: {} voidage values for {} cells",
                eps.len(),
                volumes.len()
            )));
        }
        let iterations = self
            .diffusion
            .diffuse(eps)
            .map_err(|e| CoupleError::Parameter(format!("constDiffSmoothing: {e}")))?;
        let mut report = SmoothingReport {
            iterations,
            ..SmoothingReport::default()
        };
        let SmoothingSettings { lower, upper, .. } = self.settings;
        for (e, v) in eps.iter_mut().zip(volumes) {
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
