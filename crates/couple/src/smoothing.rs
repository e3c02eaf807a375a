//! CFDEM-PFM's `smoothingModel`s of the voidage ε handed to the fluid (PFM's
//! `cfdemCloud::evolve` smooths `voidFractionNext` right after the voidage model):
//!
//! * `constDiffSmoothing` (used by many PFM tutorials, e.g. `cfdemSolverPiso/settlingTestMPI`):
//!   one implicit diffusion step of length L (`constDiffSmoothingProps/smoothingLength`, m),
//!
//!     ε − D Δt ∇²ε = ε₀,  D = L²/Δt   ⇒   V_c ε_c − Σ_f L² |S_f| δ_f (ε_N − ε_c) = V_c ε₀,c,
//!
//!   (PFM's `constDiffSmoothing::smoothen`: `fvm::ddt(ε) − fvm::laplacian(L²/Δt, ε)` from the
//!   unsmoothed field, so Δt cancels: the smoothing length is √(D Δt), L² = D·Δt, whatever the
//!   time step). The step's response to a point source is the kernel of (1 − L²∇²)⁻¹: in 1-D
//!   e^(−|x|/L)/(2L), in 3-D e^(−r/L)/(4π L² r) (not a Gaussian: one implicit step is the
//!   resolvent of the heat equation; n steps of length L/√n tend to the heat kernel of D t = L²,
//!   the Gaussian e^(−r²/4L²)/(4π L²)^(3/2)). Zero gradient at the boundary (no flux through it:
//!   Σ V(1 − ε), the particle volume, is conserved to the solver's tolerance) and across cyclic
//!   pairs as across internal faces. δ_f is OpenFOAM's non-orthogonal delta coefficient
//!   1/max(n̂·d, 0.05 |d|), the implicit part of `Gauss linear corrected`; the explicit
//!   non-orthogonal correction is left out (zero on the orthogonal meshes of the tutorials).
//! * `temporalSmoothing` (PFM's `temporalSmoothing::smoothen`: `fvm::ddt(s) − γ/Δt (ref −
//!   fvm::Sp(1, s))` with the old value s₀ the field being smoothed and `ref` the field named
//!   by `refField`): one implicit Euler step of ds/dt = (γ/Δt)(ref − s), so
//!
//!     ε = (ε₀ + γ ε_ref) / (1 + γ),
//!
//!   with ε₀ this exchange's unsmoothed ε and ε_ref the fluid's ε (`refField voidfraction`, the
//!   only field the coupler holds), which at an exchange is the last smoothed ε. A step change
//!   of the unsmoothed ε from a to b relaxes as ε_n − b = (a − b) (γ/(1+γ))ⁿ after n
//!   exchanges. PFM's solvers refuse this model at the top level (`checkModelType.H`: "does
//!   not support smoothing of the exchange fields") unless the model check is switched off;
//!   foamgrain acts as PFM's code does with the check off.
//! * `constDiffAndTemporalSmoothing` (PFM's `constDiffAndTemporalSmoothing::smoothen` without
//!   `refField`): the diffusion step above, ε_D = (1 − L²∇²)⁻¹ ε₀, then one implicit Euler step
//!   of the relaxation from the last smoothed ε (the field's old time) towards ε_D, γ =
//!   `smoothingStrength`:
//!
//!     ε = (ε_prev + γ ε_D) / (1 + γ),
//!
//!   so a step change relaxes as (1/(1+γ))ⁿ: PFM's "time scale Δt/γ".
//!
//! * `localPSizeDiffSmoothing`: named by CFDEM-PUBLIC's and PFM's tutorials (ErgunTestMPI,
//!   ErgunTestCG, the multiphase cases) with its Props `lowerLimit`, `upperLimit`,
//!   `dSmoothingLength`, `Csmoothing`, but its source is in neither repository (nor in their
//!   histories). foamgrain makes it what its name and Props say: `constDiffSmoothing`'s implicit
//!   step with a smoothing length that follows the local particle size,
//!
//!     V_c ε_c − Σ_f L_f² |S_f| δ_f (ε_N − ε_c) = V_c ε₀,c,   L_f² = (L_o² + L_n²)/2,
//!
//!   L_c = `Csmoothing` · d̄_c in a cell holding particle volume, d̄_c the particle diameter
//!   averaged over the particle volume in the cell (Σ_p w_pc d_p / Σ_p w_pc with the voidage
//!   shares w_pc), and L_c = `dSmoothingLength` in a cell holding none. The face value is the
//!   mean of the two cells' L², so the operator stays symmetric and conserves Σ V ε exactly as
//!   the constant one does (zero flux through the walls); with one particle size everywhere
//!   (and `dSmoothingLength` = `Csmoothing` · d) it is `constDiffSmoothing` of that length.
//!   Why this reading: "localPSize" is the local particle size, "Diff" the diffusion of
//!   `constDiffSmoothing` (whose Props it shares but for the length), `Csmoothing` a factor on
//!   that size and `dSmoothingLength` (1.5 mm in every tutorial, the `smoothingLength` of the
//!   `constDiffSmoothingProps` next to it) the length where there is no particle to measure.
//!
//! The relaxation's history (the last smoothed ε) starts at ε = 1, the coupler's first ε (and
//! the `voidfraction` of CFDEM's tutorials at t = 0). The relaxation conserves the particle
//! volume only as much as it is stationary: Σ V(1 − ε) after it is the weighted mean of this
//! exchange's and the history's; the difference from this exchange's (the volume the
//! relaxation lags) is reported ([`SmoothingReport::lagged_volume`]), never dropped silently.
//!
//! The spatial step is the fluid's discretisation, which the coupler does not own: it is a
//! [`Diffusion`] (the native one is `fv::diffusion::DiffusionStep`, built by
//! `runner::smoothing`). ε is then bounded to [`lowerLimit`, `upperLimit`], as PFM does; the
//! solid volume that bound adds or removes is returned, so the run reports it.
//!
//! PFM also smooths the cell-averaged particle velocity Us as a "reference field" (cells with
//! particles keep their value, empty cells take their neighbours'). That changes Us only where
//! Ksl = 0, so the fluid's momentum does not see it: it is not done here. PFM's solvers also
//! pass the implicit force field from which PFM's `implicitCouple` forms Ksl through the same
//! model (`smoothen(impParticleForces())`); foamgrain's Ksl is formed from the particles'
//! shares and is not smoothed. The drag uses each particle's unsmoothed ε, as PFM's does
//! without `interpolation`.

use crate::CoupleError;
use std::sync::Mutex;

/// How far above 1 a smoothed ε may come out of the solver by round-off alone (the solve's
/// tolerance is 1e-14 of the normalised residual); such a value is set to 1, uncounted.
const ROUND_OFF: f64 = 1e-9;

/// The settings of `constDiffSmoothingProps` (and the spatial part of
/// `constDiffAndTemporalSmoothingProps`).
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
        bounds_problem(self.lower, self.upper)
    }
}

/// The `lowerLimit`/`upperLimit` problem, if any.
fn bounds_problem(lower: f64, upper: f64) -> Option<(&'static str, String)> {
    if lower.is_nan() || upper.is_nan() || lower > upper {
        return Some(("lowerLimit", format!("{lower} is above upperLimit {upper}")));
    }
    None
}

/// One of PFM's smoothing models of ε with its settings (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SmoothingModel {
    /// `constDiffSmoothing`.
    ConstDiff(SmoothingSettings),
    /// `temporalSmoothing` with `gamma` (γ ≥ 0) and the bounds.
    Temporal {
        /// `gamma`: the weight of the fluid's ε against the unsmoothed one.
        gamma: f64,
        /// `lowerLimit`.
        lower: f64,
        /// `upperLimit`.
        upper: f64,
    },
    /// `constDiffAndTemporalSmoothing`: the diffusion `spatial`, then the relaxation of
    /// strength `gamma` (γ > 0, `smoothingStrength`).
    ConstDiffAndTemporal {
        /// `smoothingLength`, `lowerLimit`, `upperLimit`.
        spatial: SmoothingSettings,
        /// `smoothingStrength`.
        gamma: f64,
    },
    /// `localPSizeDiffSmoothing` (foamgrain's reading, module docs): the length `Csmoothing` ·
    /// d̄_c where particles are, `spatial.length` (`dSmoothingLength`) elsewhere.
    LocalPSizeDiff {
        /// `dSmoothingLength`, `lowerLimit`, `upperLimit`.
        spatial: SmoothingSettings,
        /// `Csmoothing` (> 0): the length per particle diameter.
        c: f64,
    },
}

impl From<SmoothingSettings> for SmoothingModel {
    fn from(s: SmoothingSettings) -> SmoothingModel {
        SmoothingModel::ConstDiff(s)
    }
}

impl SmoothingModel {
    /// The `smoothingModel` name.
    pub fn name(&self) -> &'static str {
        match self {
            SmoothingModel::ConstDiff(_) => "constDiffSmoothing",
            SmoothingModel::Temporal { .. } => "temporalSmoothing",
            SmoothingModel::ConstDiffAndTemporal { .. } => "constDiffAndTemporalSmoothing",
            SmoothingModel::LocalPSizeDiff { .. } => "localPSizeDiffSmoothing",
        }
    }

    /// The diffusion length L (m; `localPSizeDiffSmoothing`'s where no particle is); 0 for
    /// `temporalSmoothing` (no spatial step).
    pub fn length(&self) -> f64 {
        match self {
            SmoothingModel::ConstDiff(s)
            | SmoothingModel::ConstDiffAndTemporal { spatial: s, .. }
            | SmoothingModel::LocalPSizeDiff { spatial: s, .. } => s.length,
            SmoothingModel::Temporal { .. } => 0.0,
        }
    }

    /// `lowerLimit`, `upperLimit`.
    pub fn bounds(&self) -> (f64, f64) {
        match *self {
            SmoothingModel::ConstDiff(s)
            | SmoothingModel::ConstDiffAndTemporal { spatial: s, .. }
            | SmoothingModel::LocalPSizeDiff { spatial: s, .. } => (s.lower, s.upper),
            SmoothingModel::Temporal { lower, upper, .. } => (lower, upper),
        }
    }

    /// What makes these settings unusable, if anything: the Props key at fault and why.
    pub fn problem(&self) -> Option<(&'static str, String)> {
        let gamma_problem = |key, gamma: f64| {
            (!(gamma.is_finite() && gamma >= 0.0))
                .then(|| (key, format!("{gamma} is not a non-negative number")))
        };
        match *self {
            SmoothingModel::ConstDiff(s) => s.problem(),
            SmoothingModel::Temporal {
                gamma,
                lower,
                upper,
            } => gamma_problem("gamma", gamma).or_else(|| bounds_problem(lower, upper)),
            SmoothingModel::ConstDiffAndTemporal { spatial, gamma } => {
                gamma_problem("smoothingStrength", gamma).or_else(|| spatial.problem())
            }
            SmoothingModel::LocalPSizeDiff { spatial, c } => match c.is_finite() && c > 0.0 {
                true => spatial.problem(),
                false => Some(("Csmoothing", format!("{c} is not a positive number"))),
            },
        }
    }

    /// `Csmoothing` of `localPSizeDiffSmoothing`: the smoothing length per particle diameter
    /// of the cells holding particles; `None` for the models of one length.
    pub fn size_factor(&self) -> Option<f64> {
        match *self {
            SmoothingModel::LocalPSizeDiff { c, .. } => Some(c),
            _ => None,
        }
    }

    /// The relaxation's weights (of the history, of this exchange's field): `None` without one.
    fn relaxation(&self) -> Option<(f64, f64)> {
        match *self {
            SmoothingModel::ConstDiff(_) | SmoothingModel::LocalPSizeDiff { .. } => None,
            // ε = (ε₀ + γ ε_ref)/(1 + γ)
            SmoothingModel::Temporal { gamma, .. } => {
                Some((gamma / (1.0 + gamma), 1.0 / (1.0 + gamma)))
            }
            // ε = (ε_prev + γ ε_D)/(1 + γ)
            SmoothingModel::ConstDiffAndTemporal { gamma, .. } => {
                Some((1.0 / (1.0 + gamma), gamma / (1.0 + gamma)))
            }
        }
    }
}

/// One implicit diffusion step of length L on the fluid's mesh (module docs), assembled once.
pub trait Diffusion: std::fmt::Debug + Send + Sync {
    /// The cell volumes V_c, m³ (one per cell).
    fn volumes(&self) -> &[f64];
    /// ε₀ → ε in place: the linear solver's iterations, or what failed.
    fn diffuse(&self, eps: &mut [f64]) -> Result<usize, String>;
    /// ε₀ → ε in place with the length L_c² (m², one per cell) instead of the step's own, the
    /// face's L² the mean of its two cells' (`localPSizeDiffSmoothing`, module docs).
    fn diffuse_local(&self, eps: &mut [f64], l2: &[f64]) -> Result<usize, String>;
}

/// The particle diameter averaged over the particle volume in each cell, Σ_p w_pc d_p /
/// Σ_p w_pc (m; 0 in a cell holding no particle volume), from the voidage shares w_pc and the
/// particle radii (`localPSizeDiffSmoothing`, module docs).
pub fn cell_mean_diameters(
    shares: &voidage::CellShares,
    radius: &[f64],
    n_cells: usize,
) -> Vec<f64> {
    let mut wd = vec![0.0; n_cells];
    let mut w = vec![0.0; n_cells];
    for (i, r) in radius.iter().enumerate().take(shares.particles()) {
        let range = shares.offsets[i]..shares.offsets[i + 1];
        for (&c, &v) in shares.cells[range.clone()]
            .iter()
            .zip(&shares.volumes[range])
        {
            wd[c as usize] += v * 2.0 * r;
            w[c as usize] += v;
        }
    }
    wd.iter()
        .zip(&w)
        .map(|(a, b)| if *b > 0.0 { a / b } else { 0.0 })
        .collect()
}

/// The smoothing operator on one mesh: the model, its diffusion step and the relaxation's
/// history.
#[derive(Debug)]
pub struct Smoothing {
    model: SmoothingModel,
    /// The step of length [`SmoothingModel::length`] (for `temporalSmoothing`, length 0: the
    /// identity, used only for the cell volumes).
    diffusion: Box<dyn Diffusion>,
    /// The last smoothed ε (the relaxation's history); `None` before the first exchange (then
    /// ε = 1, module docs).
    previous: Mutex<Option<Vec<f64>>>,
}

/// The name the smoothing had before the other models: `constDiffSmoothing`'s operator is a
/// [`Smoothing`].
pub type ConstDiffSmoothing = Smoothing;

/// What one smoothing did to the particle volume.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SmoothingReport {
    /// Solid volume removed by the bounds, m³ (Σ (ε_bounded − ε)·V; negative when added).
    pub bounded_volume: f64,
    /// Cells the bounds changed.
    pub bounded_cells: usize,
    /// Solid volume the temporal relaxation holds back, m³ (Σ (ε_relaxed − ε)·V before the
    /// bounds; negative when it keeps more than this exchange's particles): zero while the
    /// particle volume in the mesh is steady, and for `constDiffSmoothing`.
    pub lagged_volume: f64,
    /// Linear-solver iterations.
    pub iterations: usize,
}

impl Smoothing {
    /// The operator for `model` (or the `constDiffSmoothing` settings), with the diffusion step
    /// `diffusion` builds for the smoothing length (m; 0 for `temporalSmoothing`) once the
    /// settings are checked.
    pub fn new(
        model: impl Into<SmoothingModel>,
        diffusion: impl FnOnce(f64) -> Result<Box<dyn Diffusion>, String>,
    ) -> Result<Self, CoupleError> {
        let model = model.into();
        let name = model.name();
        if let Some((key, why)) = model.problem() {
            return Err(CoupleError::Parameter(format!("{name}: {key}: {why}")));
        }
        let diffusion = diffusion(model.length())
            .map_err(|e| CoupleError::Parameter(format!("{name}: {e}")))?;
        Ok(Smoothing {
            model,
            diffusion,
            previous: Mutex::new(None),
        })
    }

    /// The `constDiffSmoothing` settings, or the spatial settings of
    /// `constDiffAndTemporalSmoothing` (for `temporalSmoothing`: length 0 and its bounds).
    pub fn settings(&self) -> SmoothingSettings {
        let (lower, upper) = self.model.bounds();
        SmoothingSettings {
            length: self.model.length(),
            lower,
            upper,
        }
    }

    /// The model and its settings.
    pub fn model(&self) -> SmoothingModel {
        self.model
    }

    /// Smooths `eps` (one value per cell) in place and bounds it (module docs); the result is
    /// the history of the next call. `localPSizeDiffSmoothing` needs the cells' particle
    /// sizes: [`Smoothing::smooth_sized`].
    pub fn smooth(&self, eps: &mut [f64]) -> Result<SmoothingReport, CoupleError> {
        self.smooth_sized(eps, None)
    }

    /// [`Smoothing::smooth`] of an exchange's ε with the particles' voidage shares in
    /// `placement` (`localPSizeDiffSmoothing` takes the cells' mean diameters from them; on
    /// `several_ranks` no rank holds them all: an error).
    pub fn smooth_exchange(
        &self,
        eps: &mut [f64],
        placement: &crate::interpolate::Placement,
        particles: &crate::sides::ParticleState<'_>,
        several_ranks: bool,
    ) -> Result<SmoothingReport, CoupleError> {
        let diameters = match self.model.size_factor() {
            Some(_) if several_ranks => {
                return Err(CoupleError::Parameter(
                    "smoothingModel localPSizeDiffSmoothing needs the particle sizes of every \
                     cell on one rank; run one coupler rank"
                        .into(),
                ))
            }
            Some(_) => Some(cell_mean_diameters(
                &placement.shares,
                particles.radius,
                eps.len(),
            )),
            None => None,
        };
        self.smooth_sized(eps, diameters.as_deref())
    }

    /// [`Smoothing::smooth`] with each cell's mean particle diameter (m, 0 where none;
    /// [`cell_mean_diameters`]), which `localPSizeDiffSmoothing` requires and the other models
    /// ignore.
    pub fn smooth_sized(
        &self,
        eps: &mut [f64],
        diameters: Option<&[f64]>,
    ) -> Result<SmoothingReport, CoupleError> {
        let name = self.model.name();
        let volumes = self.diffusion.volumes();
        if eps.len() != volumes.len() {
            return Err(CoupleError::Parameter(format!(
                "{name}: {} voidage values for {} cells",
                eps.len(),
                volumes.len()
            )));
        }
        let mut report = SmoothingReport::default();
        let solved = match (self.model.size_factor(), diameters) {
            (Some(c), Some(d)) if d.len() == eps.len() => {
                let l0 = self.model.length();
                let l2: Vec<f64> = d
                    .iter()
                    .map(|&d| if d > 0.0 { (c * d).powi(2) } else { l0 * l0 })
                    .collect();
                Some(self.diffusion.diffuse_local(eps, &l2))
            }
            (Some(_), _) => {
                return Err(CoupleError::Parameter(format!(
                    "{name}: the cells' particle diameters are missing or of the wrong length"
                )))
            }
            (None, _) => (self.model.length() > 0.0).then(|| self.diffusion.diffuse(eps)),
        };
        if let Some(solved) = solved {
            report.iterations =
                solved.map_err(|e| CoupleError::Parameter(format!("{name}: {e}")))?;
        }
        let mut previous = self
            .previous
            .lock()
            .map_err(|_| CoupleError::Parameter(format!("{name}: history poisoned")))?;
        if let Some((w_prev, w_new)) = self.model.relaxation() {
            let prev = previous.get_or_insert_with(|| vec![1.0; eps.len()]);
            for ((e, p), v) in eps.iter_mut().zip(prev.iter()).zip(volumes) {
                let relaxed = w_prev * p + w_new * *e;
                report.lagged_volume += (relaxed - *e) * v;
                *e = relaxed;
            }
        }
        let (lower, upper) = self.model.bounds();
        for (e, v) in eps.iter_mut().zip(volumes) {
            // diffusion and relaxation keep ε ≤ 1 (a maximum principle, weights summing to 1):
            // above it is round-off
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
        if self.model.relaxation().is_some() {
            match previous.as_mut() {
                Some(p) => p.copy_from_slice(eps),
                None => *previous = Some(eps.to_vec()),
            }
        }
        Ok(report)
    }
}
