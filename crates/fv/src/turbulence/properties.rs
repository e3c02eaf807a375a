//! `constant/turbulenceProperties` as OpenFOAM v1912 reads it, and the schemes and solvers the
//! selected model's equations take from `system/fvSchemes` and `system/fvSolution`.
//!
//! * no file: icoFoam's momentum equation (the Laplacian alone);
//! * `simulationType laminar` (`laminar { laminarModel Stokes; }` optional): pisoFoam's
//!   laminar stress, −∇·(ν∇U) − ∇·(ν dev2(∇Uᵀ));
//! * `simulationType RAS; RAS { RASModel kEpsilon; turbulence on|off; printCoeffs …;
//!   kEpsilonCoeffs { Cmu C1 C2 C3 sigmak sigmaEps } kMin epsilonMin }`: the standard k–ε model
//!   ([`super::k_epsilon`]); coefficients not given keep Launder & Sharma's / OpenFOAM's
//!   defaults. Other RAS models (kOmegaSST, realizableKE, …) and `LES` are refused naming the
//!   file and key: they are later work.
//!
//! For k–ε, fvSchemes' `div(phi,k)` and `div(phi,epsilon)` may be `Gauss linear`,
//! `Gauss upwind` or `Gauss limitedLinear ψ`, each optionally `bounded`;
//! `laplacian(DkEff,k)`, `laplacian(DepsilonEff,epsilon)` must use the momentum Laplacian's
//! scheme, `ddt(k)`/`ddt(epsilon)` must be `Euler`, `grad(k)`, `grad(epsilon)` `Gauss linear`;
//! fvSolution must have solvers for `k` and `epsilon` (exact or pattern keys), and their
//! equations must not be under-relaxed (factor 1).

use super::k_epsilon::KEpsilonCoeffs;
use super::scalar_eqn::ScalarScheme;
use crate::convection::Convection;
use crate::error::Result;
use crate::settings::{convection_of, err, linear_solver, scheme_words};
use foam::{Case, Dict, Item};
use std::path::Path;

/// The turbulence treatment a case selects.
#[derive(Clone, Debug, PartialEq)]
pub enum TurbulenceSettings {
    /// No `turbulenceProperties`: icoFoam's momentum equation.
    None,
    /// `simulationType laminar` (Stokes): pisoFoam's laminar stress.
    Laminar,
    /// `simulationType RAS`, `RASModel kEpsilon`.
    KEpsilon(Box<KEpsilonSettings>),
}

/// What the k–ε model reads.
#[derive(Clone, Debug, PartialEq)]
pub struct KEpsilonSettings {
    /// `turbulence on|off` (off: νt stays as computed from the start fields).
    pub active: bool,
    /// The model coefficients.
    pub coeffs: KEpsilonCoeffs,
    /// Schemes and solver of the k equation.
    pub k: ScalarScheme,
    /// Schemes and solver of the ε equation.
    pub epsilon: ScalarScheme,
}

impl TurbulenceSettings {
    /// True when the momentum equation has pisoFoam's full stress (laminar or RAS).
    pub fn full_stress(&self) -> bool {
        !matches!(self, TurbulenceSettings::None)
    }
}

/// A dimensioned or bare number `key` of `d` (the last number of its stream), `default` when
/// absent; `dotted` names it in errors.
fn coefficient(d: &Dict, file: &Path, key: &str, dotted: &str, default: f64) -> Result<f64> {
    match d.stream(key) {
        Err(_) => Ok(default),
        Ok(s) => s
            .iter()
            .rev()
            .find_map(Item::as_f64)
            .filter(|v| v.is_finite())
            .ok_or_else(|| err(file, dotted, "expected a number")),
    }
}

/// Reads `constant/turbulenceProperties` of `case` and, for k–ε, the schemes and solvers of
/// its equations (`sch`, `sol`: the parsed fvSchemes and fvSolution); `sn_grad_words` are the
/// momentum Laplacian's scheme words, which the k and ε Laplacians must repeat.
pub fn read(
    case: &Case,
    sch: &Dict,
    sol: &Dict,
    sn_grad_words: &[String],
) -> Result<TurbulenceSettings> {
    let root = case.root();
    let file = root.join("constant/turbulenceProperties");
    if !file.is_file() {
        return Ok(TurbulenceSettings::None);
    }
    let d = case.read_dict("constant/turbulenceProperties")?;
    let kind = d
        .word("simulationType")
        .map_err(|e| err(&file, "simulationType", e.0))?;
    match kind {
        "laminar" => {
            if let Ok(m) = d
                .dict("laminar")
                .and_then(|l| l.word("laminarModel").or_else(|_| l.word("model")))
            {
                if m != "Stokes" {
                    return Err(err(
                        &file,
                        "laminar.laminarModel",
                        format!("`{m}` is not supported (Stokes)"),
                    ));
                }
            }
            Ok(TurbulenceSettings::Laminar)
        }
        "RAS" => {
            let ras = d.dict("RAS").map_err(|e| err(&file, "RAS", e.0))?;
            let model = ras
                .word("RASModel")
                .or_else(|_| ras.word("model"))
                .map_err(|e| err(&file, "RAS.RASModel", e.0))?;
            if model != "kEpsilon" {
                return Err(err(
                    &file,
                    "RAS.RASModel",
                    format!(
                        "`{model}` is not supported (kEpsilon; kOmegaSST and other RAS models \
                         are later work)"
                    ),
                ));
            }
            let active = match ras.get("turbulence") {
                None => true,
                Some(_) => ras
                    .switch("turbulence")
                    .map_err(|e| err(&file, "RAS.turbulence", e.0))?,
            };
            let cd = ras.opt_dict("kEpsilonCoeffs");
            let empty = Dict::new();
            let c = cd.unwrap_or(&empty);
            let cf = |key: &str, default: f64| {
                coefficient(c, &file, key, &format!("RAS.kEpsilonCoeffs.{key}"), default)
            };
            let coeffs = KEpsilonCoeffs {
                cmu: cf("Cmu", 0.09)?,
                c1: cf("C1", 1.44)?,
                c2: cf("C2", 1.92)?,
                c3: cf("C3", 0.0)?,
                sigma_k: cf("sigmak", 1.0)?,
                sigma_eps: cf("sigmaEps", 1.3)?,
                k_min: coefficient(ras, &file, "kMin", "RAS.kMin", 1e-15)?,
                epsilon_min: coefficient(ras, &file, "epsilonMin", "RAS.epsilonMin", 1e-15)?,
            };
            if coeffs.cmu <= 0.0 || coeffs.sigma_k <= 0.0 || coeffs.sigma_eps <= 0.0 {
                return Err(err(
                    &file,
                    "RAS.kEpsilonCoeffs",
                    "Cmu, sigmak and sigmaEps must be positive",
                ));
            }
            let sch_file = root.join("system/fvSchemes");
            let sol_file = root.join("system/fvSolution");
            let k = equation(sch, sol, &sch_file, &sol_file, "k", "DkEff", sn_grad_words)?;
            let epsilon = equation(
                sch,
                sol,
                &sch_file,
                &sol_file,
                "epsilon",
                "DepsilonEff",
                sn_grad_words,
            )?;
            Ok(TurbulenceSettings::KEpsilon(Box::new(KEpsilonSettings {
                active,
                coeffs,
                k,
                epsilon,
            })))
        }
        other => Err(err(
            &file,
            "simulationType",
            format!("`{other}` is not supported (laminar, RAS with kEpsilon; LES is later work)"),
        )),
    }
}

/// The schemes and solver of the transport equation of `field` with diffusivity `gamma`.
fn equation(
    sch: &Dict,
    sol: &Dict,
    sch_file: &Path,
    sol_file: &Path,
    field: &str,
    gamma: &str,
    sn_grad_words: &[String],
) -> Result<ScalarScheme> {
    let (convection, bounded) = convection_of(sch, sch_file, &format!("div(phi,{field})"))?;
    if !matches!(
        convection,
        Convection::Linear | Convection::Upwind | Convection::LimitedLinear(_)
    ) {
        let (w, key) = scheme_words(sch, sch_file, "divSchemes", &format!("div(phi,{field})"))?;
        return Err(err(
            sch_file,
            &key,
            format!(
                "`{}` is not supported for {field} (Gauss linear, Gauss upwind, Gauss \
                 limitedLinear ψ, each may be `bounded`)",
                w.join(" ")
            ),
        ));
    }
    let (lap, key) = scheme_words(
        sch,
        sch_file,
        "laplacianSchemes",
        &format!("laplacian({gamma},{field})"),
    )?;
    if lap != sn_grad_words {
        return Err(err(
            sch_file,
            &key,
            format!(
                "`{}`: the {field} Laplacian must use the momentum Laplacian's scheme `{}`",
                lap.join(" "),
                sn_grad_words.join(" ")
            ),
        ));
    }
    // Euler or OpenFOAM's `CrankNicolson ψ`, each field its own (`backward` with k–ε is
    // refused with the momentum's settings).
    let (ddt, key) = scheme_words(sch, sch_file, "ddtSchemes", &format!("ddt({field})"))?;
    let crank_nicolson = match ddt.as_slice() {
        [w] if w == "Euler" => None,
        [w, psi] if w == "CrankNicolson" => match psi.parse::<f64>() {
            Ok(p) if (0.0..=1.0).contains(&p) => Some(p),
            _ => {
                return Err(err(sch_file, &key, "CrankNicolson needs ψ in [0, 1]"));
            }
        },
        _ => {
            return Err(err(
                sch_file,
                &key,
                format!(
                    "`{}` is not supported for {field} (Euler, CrankNicolson ψ)",
                    ddt.join(" ")
                ),
            ));
        }
    };
    let (grad, key) = scheme_words(sch, sch_file, "gradSchemes", &format!("grad({field})"))?;
    if grad != ["Gauss", "linear"] {
        return Err(err(
            sch_file,
            &key,
            format!("`{}` is not supported (Gauss linear)", grad.join(" ")),
        ));
    }
    if let Some(rf) = sol.opt_dict("relaxationFactors") {
        let eq = rf.opt_dict("equations").unwrap_or(rf);
        if let Some(foam::Value::Stream(s)) = eq.lookup_path(field) {
            let f = s.iter().rev().find_map(Item::as_f64);
            if f != Some(1.0) {
                return Err(err(
                    sol_file,
                    &format!("relaxationFactors.equations.{field}"),
                    "under-relaxing the turbulence equations is not supported (only 1)",
                ));
            }
        }
    }
    let solver = linear_solver(sol, sol_file, field)?;
    Ok(ScalarScheme {
        convection,
        bounded,
        solver,
        crank_nicolson,
    })
}
