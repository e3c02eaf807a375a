//! What the temperature equation reads of a case's dictionaries when the caller asks for heat
//! ([`crate::settings::Settings::enable_temperature`]): the laminar and turbulent Prandtl
//! numbers of `constant/transportProperties` and the schemes and solver of cfdemSolverPisoScalar's
//! T equation (CFDEMcoupling-PUBLIC `applications/solvers/cfdemSolverPisoScalar`):
//!
//! * `Pr`, `Prt` (dimensionless, > 0): `Pr [0 0 0 0 0 0 0] 0.7;` or `Pr 0.7;`
//!   (CFDEMcoupling-PUBLIC's cfdemSolverPisoScalar: α_eff = ν/Pr + ν_t/Prt); or, without them,
//!   `DT` (m²/s, > 0), CFDEMcoupling-PFM's cfdemSolverPisoScalar, whose T equation has the
//!   same form with the constant α_eff = DT (no turbulent part; its `Laplacian` term is named
//!   `laplacian((DT*voidfraction),T)`). Both solvers carry the same application name, so the
//!   keys decide: Pr and Prt first;
//! * fvSchemes `div(phi,T)` (else `default`): `Gauss linear`, `Gauss upwind`,
//!   `Gauss limitedLinear ψ`, each may be `bounded` ([`crate::convection`]);
//!   `laplacian((alphaEff*voidfraction),T)` — the name OpenFOAM gives the solver's term (the
//!   tutorials' `laplacian((DT*voidfraction),T)` is not looked up by the solver, so it is not
//!   read here either) — else `default`, which must be the momentum Laplacian's scheme (the
//!   delta coefficients and the non-orthogonal correction are the fluid's);
//!   `ddt(voidfraction,T)` and `ddt(voidfraction)` `Euler` (others refused);
//!   `grad(T)` `Gauss linear`;
//! * fvSolution `solvers.T` (an exact key, else a pattern key such as `"(T|C)"`); no
//!   `relaxationFactors` equation factor may apply to T (`T`, a pattern, or `default`):
//!   cfdemSolverPisoScalar calls `TEqn.relax()`, which does nothing without a factor (the
//!   packedBedTemp tutorial) but with one — even 1 — raises every diagonal below the sum of its
//!   row's off-diagonal magnitudes and moves the difference times the old T into the source
//!   (OpenFOAM v1912 `fvMatrix::relax`), which the native solver does not do.

use crate::convection::Convection;
use crate::error::Result;
use crate::settings::{
    convection_of, dimensioned, equation_relaxation, err, linear_solver, scheme_group,
    scheme_words, MOMENTUM_LAPLACIANS,
};
use crate::turbulence::scalar_eqn::ScalarScheme;
use foam::{Case, Dict};
use std::path::Path;

/// The settings of the temperature equation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TemperatureSettings {
    /// The fluid's thermal diffusivity α_eff.
    pub diffusivity: Diffusivity,
    /// `div(phi,T)`, the `T` solver (`crank_nicolson` is always `None`: Euler).
    pub scheme: ScalarScheme,
    /// CFDEM-PFM's bed conductivity model (`thermCondModel`), set by the coupling; `None`
    /// (what [`TemperatureSettings::read`] gives): the fluid's own, ε ν/Pr
    /// ([`crate::temperature::conduction`]).
    pub bed: Option<crate::temperature::conduction::BedConduction>,
}

/// The fluid's thermal diffusivity α_eff (m²/s) in the T equation's `laplacian(α_eff ε, T)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Diffusivity {
    /// CFDEMcoupling-PUBLIC: α_eff = ν/Pr + ν_t/Prt, Pr and Prt dimensionless.
    Prandtl {
        /// Laminar Prandtl number Pr = ν/α: the molecular diffusivity is ν/Pr.
        pr: f64,
        /// Turbulent Prandtl number Prt: α_t = ν_t/Prt.
        prt: f64,
    },
    /// CFDEMcoupling-PFM: α_eff = DT, a constant (m²/s), laminar or not.
    Constant {
        /// DT, m²/s.
        dt: f64,
    },
}

impl Diffusivity {
    /// The molecular part (m²/s) for the laminar kinematic viscosity `nu` (m²/s).
    pub fn laminar(self, nu: f64) -> f64 {
        match self {
            Diffusivity::Prandtl { pr, .. } => nu / pr,
            Diffusivity::Constant { dt } => dt,
        }
    }

    /// Prt, when the turbulent viscosity adds α_t = ν_t/Prt; `None` for a constant DT.
    pub fn turbulent_prandtl(self) -> Option<f64> {
        match self {
            Diffusivity::Prandtl { prt, .. } => Some(prt),
            Diffusivity::Constant { .. } => None,
        }
    }

    /// The name OpenFOAM gives the equation's Laplacian term, the fvSchemes key.
    pub fn laplacian_key(self) -> &'static str {
        match self {
            Diffusivity::Prandtl { .. } => LAPLACIAN_KEY,
            Diffusivity::Constant { .. } => DT_LAPLACIAN_KEY,
        }
    }
}

/// The term OpenFOAM names the T equation's Laplacian by (`fvm::laplacian(alphaEff*voidfraction, T)`).
pub const LAPLACIAN_KEY: &str = "laplacian((alphaEff*voidfraction),T)";

/// PFM's name of that term (`fvm::laplacian(DT*voidfraction, T)`).
pub const DT_LAPLACIAN_KEY: &str = "laplacian((DT*voidfraction),T)";

impl TemperatureSettings {
    /// Reads the temperature settings of `case` (see the module documentation); every
    /// refusal names the file and key.
    pub fn read(case: &Case) -> Result<TemperatureSettings> {
        let root = case.root();
        let tp_file = root.join("constant/transportProperties");
        let tp = case.read_dict("constant/transportProperties")?;
        let diffusivity = diffusivity(&tp, &tp_file)?;

        let sch_file = root.join("system/fvSchemes");
        let sch = case.read_dict("system/fvSchemes")?;
        let (convection, bounded) = convection_of(&sch, &sch_file, "div(phi,T)")?;
        if !matches!(
            convection,
            Convection::Linear | Convection::Upwind | Convection::LimitedLinear(_)
        ) {
            let (w, key) = scheme_words(&sch, &sch_file, "divSchemes", "div(phi,T)")?;
            return Err(err(
                &sch_file,
                &key,
                format!(
                    "`{}` is not supported for T (Gauss linear, Gauss upwind, Gauss \
                     limitedLinear ψ, each may be `bounded`)",
                    w.join(" ")
                ),
            ));
        }
        laplacian(&sch, &sch_file, diffusivity.laplacian_key())?;
        for entry in ["ddt(voidfraction,T)", "ddt(voidfraction)"] {
            let (w, key) = scheme_words(&sch, &sch_file, "ddtSchemes", entry)?;
            if w != ["Euler"] {
                return Err(err(
                    &sch_file,
                    &key,
                    format!(
                        "`{}` is not supported for the temperature equation (Euler)",
                        w.join(" ")
                    ),
                ));
            }
        }
        let (grad, key) = scheme_words(&sch, &sch_file, "gradSchemes", "grad(T)")?;
        if grad != ["Gauss", "linear"] {
            return Err(err(
                &sch_file,
                &key,
                format!("`{}` is not supported (Gauss linear)", grad.join(" ")),
            ));
        }

        let sol_file = root.join("system/fvSolution");
        let sol = case.read_dict("system/fvSolution")?;
        relaxation(&sol, &sol_file)?;
        let solver = linear_solver(&sol, &sol_file, "T")?;
        Ok(TemperatureSettings {
            diffusivity,
            scheme: ScalarScheme {
                convection,
                bounded,
                solver,
                crank_nicolson: None,
            },
            bed: None,
        })
    }
}

/// `Pr` and `Prt` of transportProperties (PUBLIC's form) or, when neither is given, `DT`
/// (PFM's); each a positive number, with or without a dimension set.
fn diffusivity(tp: &Dict, file: &Path) -> Result<Diffusivity> {
    let positive = |key: &str| -> Result<Option<f64>> {
        match dimensioned(tp, file, key)? {
            Some(v) if v > 0.0 => Ok(Some(v)),
            Some(v) => Err(err(file, key, format!("{v} is not a positive number"))),
            None => Ok(None),
        }
    };
    match (positive("Pr")?, positive("Prt")?, positive("DT")?) {
        (Some(pr), Some(prt), _) => Ok(Diffusivity::Prandtl { pr, prt }),
        (None, None, Some(dt)) => Ok(Diffusivity::Constant { dt }),
        (pr, _, _) => Err(err(
            file,
            if pr.is_some() { "Prt" } else { "Pr" },
            "missing: the temperature equation needs the laminar and turbulent Prandtl \
             numbers `Pr` and `Prt` (CFDEMcoupling-PUBLIC's cfdemSolverPisoScalar), or the \
             thermal diffusivity `DT` in m²/s without them (CFDEMcoupling-PFM's)",
        )),
    }
}

/// The T Laplacian's scheme (fvSchemes key `name`) must be the momentum Laplacian's (the
/// fluid's delta coefficients and non-orthogonal correction).
fn laplacian(sch: &Dict, sch_file: &Path, name: &str) -> Result<()> {
    let mom = scheme_group(sch, sch_file, "laplacianSchemes", MOMENTUM_LAPLACIANS)?
        .into_iter()
        .next()
        .map(|(w, _)| w)
        .unwrap_or_default();
    let (lap, key) = scheme_words(sch, sch_file, "laplacianSchemes", name)?;
    if lap != mom {
        return Err(err(
            sch_file,
            &key,
            format!(
                "`{}`: the T Laplacian must use the momentum Laplacian's scheme `{}`",
                lap.join(" "),
                mom.join(" ")
            ),
        ));
    }
    Ok(())
}

/// No `relaxationFactors` equation factor may apply to T (see the module documentation).
fn relaxation(sol: &Dict, sol_file: &Path) -> Result<()> {
    let Some((factor, dotted)) = equation_relaxation(sol, "T") else {
        return Ok(());
    };
    Err(err(
        sol_file,
        &dotted,
        format!(
            "a relaxation factor ({}) applies to the temperature equation: not supported \
             (OpenFOAM's relax changes a matrix that is not diagonally dominant even with \
             factor 1); remove it for T",
            factor.map_or("not a number".to_string(), |f| f.to_string())
        ),
    ))
}
