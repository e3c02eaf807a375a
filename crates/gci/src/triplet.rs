//! One triplet of grids (fine 1, medium 2, coarse 3): refinement ratios, behaviour, apparent
//! order and the estimates of Celik et al. (2008) eqs. (4)–(7).

use crate::error::GciError;
use crate::order::{apparent_order, classify, Behaviour, Method, Undefined};
use serde::Serialize;

/// Celik et al.'s recommended smallest refinement ratio (their step 2: r > 1.3).
pub const MIN_RATIO: f64 = 1.3;

/// Settings of the analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Safety factor Fs of the GCI, eq. (7): 1.25 for three or more grids (Celik et al.).
    pub safety_factor: f64,
    /// Refinement ratios below this are reported with a [`Warning::SmallRatio`].
    pub min_ratio: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            safety_factor: 1.25,
            min_ratio: MIN_RATIO,
        }
    }
}

impl Settings {
    /// Settings with safety factor `fs`, checked finite and > 0.
    pub fn with_safety_factor(fs: f64) -> Result<Settings, GciError> {
        if fs.is_finite() && fs > 0.0 {
            Ok(Settings {
                safety_factor: fs,
                ..Settings::default()
            })
        } else {
            Err(GciError::Setting {
                name: "safety factor",
                value: fs,
                reason: "must be finite and > 0 (Celik et al.: 1.25)",
            })
        }
    }
}

/// Which pair of grids a ratio belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Pair {
    /// Medium over fine, r21 = h2/h1.
    R21,
    /// Coarse over medium, r32 = h3/h2.
    R32,
}

/// Something to report alongside the numbers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Warning {
    /// A refinement ratio below [`Settings::min_ratio`]: the change between the grids may be
    /// dominated by other errors than discretization (Celik et al., step 2).
    SmallRatio {
        /// Which ratio.
        pair: Pair,
        /// Its value.
        r: f64,
    },
}

/// Relative errors and the GCI of the fine grid, as fractions (multiply by 100 for %).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RelativeErrors {
    /// Approximate relative error e_a^21 = |(φ1 − φ2)/φ1|, eq. (5).
    pub e_a21: f64,
    /// Extrapolated relative error e_ext^21 = |(φ_ext^21 − φ1)/φ_ext^21|, eq. (6).
    pub e_ext21: f64,
    /// Fine-grid convergence index GCI_fine^21 = Fs·e_a^21/(r21^p − 1), eq. (7).
    pub gci_fine21: f64,
}

/// The estimates of a converging triplet.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// Apparent order p, eq. (3a).
    pub p: f64,
    /// Iterations (or bisection halvings) taken for p.
    pub iterations: u32,
    /// How p was found.
    pub method: Method,
    /// Extrapolated value φ_ext^21 = (r21^p φ1 − φ2)/(r21^p − 1), eq. (4), in φ's units.
    pub phi_ext21: f64,
    /// φ_ext^32 = (r32^p φ2 − φ3)/(r32^p − 1), the same from grids 2 and 3.
    pub phi_ext32: f64,
    /// Relative errors; `None` when φ1 = 0 or φ_ext^21 = 0 (a relative error has no meaning).
    pub relative: Option<RelativeErrors>,
}

/// An estimate, or why there is none.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// p and the estimates.
    Estimate(Estimate),
    /// Why p is undefined.
    Undefined(Undefined),
}

/// The analysis of three grids, finest first.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Triplet {
    /// Indices of the three grids in the caller's list (fine, medium, coarse); `[0, 1, 2]`
    /// from [`analyse`], positions in the input from [`crate::study::analyse_study`].
    pub grids: [usize; 3],
    /// Representative cell sizes h1 < h2 < h3.
    pub h: [f64; 3],
    /// Values φ1, φ2, φ3 on those grids.
    pub phi: [f64; 3],
    /// r21 = h2/h1.
    pub r21: f64,
    /// r32 = h3/h2.
    pub r32: f64,
    /// ε21 = φ2 − φ1.
    pub eps21: f64,
    /// ε32 = φ3 − φ2.
    pub eps32: f64,
    /// Convergence behaviour.
    pub behaviour: Behaviour,
    /// Estimates or the reason p is undefined.
    pub outcome: Outcome,
    /// Warnings (small refinement ratios).
    pub warnings: Vec<Warning>,
}

impl Triplet {
    /// The estimate, if p is defined.
    pub fn estimate(&self) -> Option<&Estimate> {
        match &self.outcome {
            Outcome::Estimate(e) => Some(e),
            Outcome::Undefined(_) => None,
        }
    }
}

/// Richardson extrapolation from a fine value φf and a coarse value φc with ratio r and order
/// p, eq. (4), written φf + (φf − φc)/(r^p − 1) with r^p − 1 = expm1(p ln r) so that it neither
/// cancels for small p nor overflows for large p.
fn extrapolate(fine: f64, coarse: f64, r: f64, p: f64) -> f64 {
    fine + (fine - coarse) / (p * r.ln()).exp_m1()
}

/// Analyses three grids with sizes `h` (0 < h1 < h2 < h3, any consistent length unit) and
/// values `phi` (finite, any unit), following Celik et al. (2008) steps 3–5.
pub fn analyse(h: [f64; 3], phi: [f64; 3], settings: &Settings) -> Result<Triplet, GciError> {
    let ordered = h[0] > 0.0 && h[0] < h[1] && h[1] < h[2] && h[2].is_finite();
    if !ordered || !phi.iter().all(|v| v.is_finite()) {
        return Err(GciError::Grids { h, phi });
    }
    let r21 = h[1] / h[0];
    let r32 = h[2] / h[1];
    let eps21 = phi[1] - phi[0];
    let eps32 = phi[2] - phi[1];
    let scale = phi.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let behaviour = classify(r21, r32, eps21, eps32, scale);
    let warnings = [(Pair::R21, r21), (Pair::R32, r32)]
        .into_iter()
        .filter(|&(_, r)| r < settings.min_ratio)
        .map(|(pair, r)| Warning::SmallRatio { pair, r })
        .collect();
    let outcome = match apparent_order(r21, r32, eps21, eps32, scale) {
        Err(why) => Outcome::Undefined(why),
        Ok(order) => {
            let p = order.p;
            let phi_ext21 = extrapolate(phi[0], phi[1], r21, p);
            let phi_ext32 = extrapolate(phi[1], phi[2], r32, p);
            let relative = (phi[0] != 0.0 && phi_ext21 != 0.0).then(|| {
                let e_a21 = ((phi[0] - phi[1]) / phi[0]).abs();
                RelativeErrors {
                    e_a21,
                    e_ext21: ((phi_ext21 - phi[0]) / phi_ext21).abs(),
                    gci_fine21: settings.safety_factor * e_a21 / (p * r21.ln()).exp_m1(),
                }
            });
            let finite = phi_ext21.is_finite()
                && phi_ext32.is_finite()
                && relative
                    .iter()
                    .all(|r| r.gci_fine21.is_finite() && r.e_ext21.is_finite());
            if finite {
                Outcome::Estimate(Estimate {
                    p,
                    iterations: order.iterations,
                    method: order.method,
                    phi_ext21,
                    phi_ext32,
                    relative,
                })
            } else {
                Outcome::Undefined(Undefined::NoSolution)
            }
        }
    };
    Ok(Triplet {
        grids: [0, 1, 2],
        h,
        phi,
        r21,
        r32,
        eps21,
        eps32,
        behaviour,
        outcome,
        warnings,
    })
}
