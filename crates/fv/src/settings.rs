//! The case settings the solver honours, read from `system/controlDict`, `system/fvSchemes`,
//! `system/fvSolution`, `constant/transportProperties` and (if present)
//! `constant/turbulenceProperties`. Every unsupported choice is refused with an error naming the
//! file and key (and, for a scheme or solver, listing the supported ones); keys the solver has
//! no use for (writePrecision, runTimeModifiable, …) are ignored.
//!
//! fvSchemes: only the entries of the terms the solver forms are read — `ddt(U)`,
//! `div(phi,U)` ([`crate::convection`]), the laminar stress divergence, the momentum and
//! pressure Laplacians under the names icoFoam, pisoFoam and cfdemSolverPiso give them,
//! `grad(p)`, `grad(U)`, the gradient a scheme names (`linearUpwind grad(U)`,
//! `grad(magSqr(U))` for `limitedLinear`) — each its own entry, else `default`. With
//! `simulationType RAS` (k–ε) the k and ε equations' entries too
//! ([`crate::turbulence::properties`]); without it, entries for fields the laminar solver never
//! solves (CFDEM's tutorials carry `div(phi,k)`, `div(phi,epsilon)`, `laplacian(DkEff,k)`, …),
//! `fluxRequired`, `wallDist` and `interpolate(U)` are accepted and not used.
//!
//! fvSolution: the `p`, `pFinal` and `U` solvers (exact keys, else pattern keys such as
//! `"(U|k|epsilon)"`, `$p` inherited) with `tolerance`, `relTol`, `maxIter`, `minIter`; `PISO`
//! (else a `PIMPLE` with one outer corrector) `nCorrectors`, `nNonOrthogonalCorrectors`,
//! `momentumPredictor`, `pRefCell`, `pRefValue`. `GAMG` is solved by the native multigrid
//! ([`crate::amg`]) to the same tolerances; its smoother is checked, its tuning keys
//! (`cacheAgglomeration`, `nCellsInCoarsestLevel`, `agglomerator`, `mergeLevels`, sweeps …)
//! change the path, not the answer, and are accepted. `relaxationFactors` are accepted when
//! they do not change the PISO solution (U's equation factor 1, any field factor).
//! `fvOptions` (`constant/`, else `system/`): the mean-velocity sources of
//! [`crate::fv_options`]; any other active source is refused.
//! With heat ([`Settings::enable_temperature`], called by the caller) also the temperature
//! equation's entries and `Pr`/`Prt` ([`crate::temperature::settings`]); without it none of
//! them is read.

use crate::error::{FvError, Result};
use crate::linsolve::{Method, Preconditioner, Smoother, SmootherKind, SolverControls};
use foam::{Case, Dict, Item};
use std::path::{Path, PathBuf};

/// Time scheme of the momentum equation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeScheme {
    /// Implicit Euler (first order).
    Euler,
    /// OpenFOAM v1912's `CrankNicolson ψ`: spatial terms implicit, the time derivative
    /// (1 + ψ)/Δt (x − x⁰) − ψ ddt0 with ddt0 the recursive estimate of the previous step's
    /// derivative, Euler on a run's first step ([`crate::ddt::CrankNicolsonDdt0`]; ψ = 1:
    /// second order, ψ = 0: Euler), also in `ddtCorr` and ∂ε/∂t.
    CrankNicolson(f64),
    /// Second-order backward differencing over the two previous levels ([`crate::ddt`];
    /// the first step of a run is Euler, as OpenFOAM's).
    Backward,
}

pub use crate::convection::Convection;

/// Surface-normal gradient scheme (laplacian and snGrad).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SnGrad {
    /// `corrected`: non-orthogonal delta coefficient plus explicit correction.
    Corrected,
    /// `uncorrected`: non-orthogonal delta coefficient, no correction.
    Uncorrected,
    /// `orthogonal`: 1/|d|, no correction.
    Orthogonal,
}

/// Linear-solver choice for one field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearSolver {
    /// The algorithm.
    pub method: Method,
    /// Tolerances.
    pub controls: SolverControls,
}

/// When time directories are written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WriteControl {
    /// Every N time steps.
    TimeStep(usize),
    /// Every T seconds of simulated time.
    RunTime(f64),
}

/// Everything the solver reads from the case's dictionaries.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Kinematic viscosity ν (m²/s), `transportProperties` `nu`.
    pub nu: f64,
    /// Fluid density ρ (kg/m³), `transportProperties` `rho` (1 if absent; only the exchange
    /// terms Ksl/ρ and f/ρ use it). A coupled run replaces it with the coupling's ρ, which
    /// CFDEM's cases may keep in the field `0/rho` instead (`runner::native::NativeFluid::open`).
    pub rho: f64,
    /// Start time (s).
    pub start_time: f64,
    /// End time (s).
    pub end_time: f64,
    /// Time step (s).
    pub delta_t: f64,
    /// Write control.
    pub write: WriteControl,
    /// Write ASCII or binary.
    pub write_format: foam::Format,
    /// controlDict's `purgeWrite`: keep only the last N written time directories (0: all).
    pub purge_write: usize,
    /// Momentum time scheme.
    pub time_scheme: TimeScheme,
    /// Convection scheme (`divSchemes` `div(phi,U)`).
    pub convection: Convection,
    /// `bounded Gauss …`: the convection term minus (∇·φ) U
    /// ([`crate::convection`]).
    pub bounded_convection: bool,
    /// Laplacian / snGrad scheme.
    pub sn_grad: SnGrad,
    /// PISO correctors.
    pub n_correctors: usize,
    /// Non-orthogonal correctors.
    pub n_non_orth: usize,
    /// Solve the momentum predictor.
    pub momentum_predictor: bool,
    /// Reference cell and value for a pressure equation without a fixed-value patch.
    pub p_ref: (usize, f64),
    /// Pressure solver (all but the last corrector).
    pub p_solver: LinearSolver,
    /// Pressure solver of the last corrector (`pFinal`, else `p`).
    pub p_final: LinearSolver,
    /// Momentum solver.
    pub u_solver: LinearSolver,
    /// Include the explicit stress part −∇·(ν_eff dev2(∇Uᵀ)) (pisoFoam's laminar model,
    /// selected by `constant/turbulenceProperties` `simulationType laminar`); icoFoam has only
    /// the Laplacian.
    pub full_stress: bool,
    /// What `constant/turbulenceProperties` selects (none, laminar, k–ε) with the k–ε
    /// equations' schemes and solvers ([`crate::turbulence::properties`]).
    pub turbulence: crate::turbulence::TurbulenceSettings,
    /// The active `fvOptions` sources (mean-velocity forces, [`crate::fv_options`]).
    pub fv_options: Vec<crate::fv_options::MeanForceSettings>,
    /// The temperature equation's settings when the caller asked for heat
    /// ([`Settings::enable_temperature`]); `None` (what [`Settings::read`] gives): the fluid
    /// solves no temperature and reads no temperature file.
    pub temperature: Option<crate::temperature::TemperatureSettings>,
}

pub(crate) fn err(file: &Path, key: &str, msg: impl Into<String>) -> FvError {
    FvError::setting(file, key, msg)
}

fn f64_of(d: &Dict, file: &Path, key: &str) -> Result<f64> {
    d.f64(key).map_err(|e| err(file, key, e.0))
}

/// Reads a number that may carry an old-style dimension set (`nu [0 2 -1 0 0 0 0] 0.01;`).
pub(crate) fn dimensioned(d: &Dict, file: &Path, key: &str) -> Result<Option<f64>> {
    let Ok(s) = d.stream(key) else {
        return Ok(None);
    };
    let v = s.iter().rev().find_map(Item::as_f64);
    match v {
        Some(v) if v.is_finite() => Ok(Some(v)),
        _ => Err(err(file, key, "expected a number")),
    }
}

/// The words of the scheme for `key` in the sub-dictionary `sub` of fvSchemes (its own entry,
/// else `default`), numbers written as words (`Gauss limitedLinearV 1` is three words, so an
/// unsupported scheme is named whole), with the dotted key that supplied them (for error
/// messages).
pub(crate) fn scheme_words(
    d: &Dict,
    file: &Path,
    sub: &str,
    key: &str,
) -> Result<(Vec<String>, String)> {
    let s = d.dict(sub).map_err(|e| err(file, sub, e.0))?;
    let (stream, used) = match s.stream(key) {
        Ok(st) => (st, format!("{sub}.{key}")),
        Err(_) => (
            s.stream("default")
                .map_err(|_| err(file, &format!("{sub}.{key}"), "missing (and no `default`)"))?,
            format!("{sub}.default"),
        ),
    };
    let words = stream
        .iter()
        .map(|i| match i {
            Item::Label(l) => Ok(l.to_string()),
            Item::Scalar(x) => Ok(x.to_string()),
            _ => i.as_word().map(str::to_owned).ok_or_else(|| {
                err(
                    file,
                    &used,
                    format!(
                        "expected a scheme (words and numbers, e.g. `Gauss linear`), found a {}",
                        i.kind()
                    ),
                )
            }),
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((words, used))
}

/// The names the momentum Laplacian has in fvSchemes: icoFoam's, pisoFoam's (laminar
/// `nuEff`) and CFDEM's cfdemSolverPiso's.
pub(crate) const MOMENTUM_LAPLACIANS: &[&str] = &[
    "laplacian(nu,U)",
    "laplacian(nuEff,U)",
    "laplacian(viscousTerm,U)",
];

/// The names the pressure Laplacian has: icoFoam's/pisoFoam's and cfdemSolverPiso's.
const PRESSURE_LAPLACIANS: &[&str] =
    &["laplacian((1|A(U)),p)", "laplacian((voidfraction2|A(U)),p)"];

/// The names of the explicit stress divergence of the laminar model: pisoFoam v1912's and the
/// older and CFDEM forms.
const STRESS_DIVERGENCES: &[&str] = &[
    "div((nuEff*dev2(T(grad(U)))))",
    "div((nuEff*dev(T(grad(U)))))",
    "div((nuEff*dev(grad(U).T())))",
    "div((viscousTerm*dev(grad(U).T())))",
];

/// The schemes of one term that has several names (`keys`) in fvSchemes' `sub`: every one of
/// those entries that is there, else the `default` (an error when there is none), each with
/// the dotted key that supplied it. A solver looks up one of the names, so only entries that
/// exist are checked: a `default none` with the term named is fine.
pub(crate) fn scheme_group(
    sch: &Dict,
    file: &Path,
    sub: &str,
    keys: &[&str],
) -> Result<Vec<(Vec<String>, String)>> {
    let s = sch.dict(sub).map_err(|e| err(file, sub, e.0))?;
    let named: Vec<&str> = keys.iter().copied().filter(|k| s.contains(k)).collect();
    if named.is_empty() {
        return Ok(vec![scheme_words(sch, file, sub, keys[0])?]);
    }
    named
        .into_iter()
        .map(|k| scheme_words(sch, file, sub, k))
        .collect()
}

/// Checks that the gradSchemes entry `key` (else `default`) is `Gauss linear`, the only
/// gradient the solver has.
fn gauss_linear_grad(sch: &Dict, file: &Path, key: &str) -> Result<()> {
    let (grad, grad_key) = scheme_words(sch, file, "gradSchemes", key)?;
    if grad != ["Gauss", "linear"] {
        return Err(err(
            file,
            &grad_key,
            format!("`{}` is not supported (Gauss linear)", grad.join(" ")),
        ));
    }
    Ok(())
}

/// The convection scheme of `divSchemes` `div(phi,U)` and whether it is `bounded`; an
/// unsupported entry is refused naming it and listing the supported ones
/// ([`crate::convection::SUPPORTED`]).
fn convection_scheme(sch: &Dict, file: &Path) -> Result<(Convection, bool)> {
    convection_of(sch, file, "div(phi,U)")
}

/// The convection scheme of the `divSchemes` entry `entry` (else `default`) and whether it is
/// `bounded`; see [`convection_scheme`].
pub(crate) fn convection_of(sch: &Dict, file: &Path, entry: &str) -> Result<(Convection, bool)> {
    let (words, key) = scheme_words(sch, file, "divSchemes", entry)?;
    let w: Vec<&str> = words.iter().map(String::as_str).collect();
    let (bounded, rest) = match w.as_slice() {
        ["bounded", rest @ ..] => (true, rest),
        all => (false, all),
    };
    let unsupported = || {
        err(
            file,
            &key,
            format!(
                "`{}` is not supported (supported: {})",
                w.join(" "),
                crate::convection::SUPPORTED
            ),
        )
    };
    let coefficient = |k: &str| -> Result<f64> {
        match k.parse::<f64>() {
            Ok(psi) if (0.0..=1.0).contains(&psi) => Ok(psi),
            _ => Err(err(
                file,
                &key,
                format!(
                    "`{}`: the limiter coefficient must be a number in [0, 1], found `{k}`",
                    w.join(" ")
                ),
            )),
        }
    };
    let convection = match rest {
        ["Gauss", "linear"] => Convection::Linear,
        ["Gauss", "upwind"] => Convection::Upwind,
        ["Gauss", "limitedLinear", k] => Convection::LimitedLinear(coefficient(k)?),
        ["Gauss", "limitedLinearV", k] => Convection::LimitedLinearV(coefficient(k)?),
        ["Gauss", scheme @ ("linearUpwind" | "linearUpwindV"), grad] => {
            // The gradient is the gradSchemes entry the scheme names (`grad(U)` usually).
            gauss_linear_grad(sch, file, grad)?;
            if *scheme == "linearUpwind" {
                Convection::LinearUpwind
            } else {
                Convection::LinearUpwindV
            }
        }
        _ => return Err(unsupported()),
    };
    Ok((convection, bounded))
}

/// Checks `relaxationFactors` of fvSolution: pisoFoam and cfdemSolverPiso relax the momentum
/// equation (`UEqn.relax()`) by the factor of `equations` `U` (an exact key, else a pattern
/// such as `"U.*"`, else `default`; the flat form of older versions counts too), which the
/// native solver does not do, so a factor other than 1 is refused. Factors of fields (p's
/// `fields` entry: the PISO solvers do not call `p.relax()`) and of other equations (k,
/// epsilon, …) change nothing and are accepted.
fn momentum_relaxation(sol: &Dict, file: &Path) -> Result<()> {
    let Some((factor, dotted)) = equation_relaxation(sol, "U") else {
        return Ok(());
    };
    match factor {
        Some(1.0) => Ok(()),
        Some(f) => Err(err(
            file,
            &dotted,
            format!(
                "the momentum equation relaxed by {f} is not supported (the native PISO \
                 solver does not relax U; only 1)"
            ),
        )),
        None => Err(err(file, &dotted, "expected a number")),
    }
}

/// The `relaxationFactors` equation factor that applies to the equation of `field` as OpenFOAM
/// v1912's `solution::relaxEquation` finds it (`equations` `field`, an exact key else a
/// pattern, else `default`; the flat form of older versions counts too), with its dotted key;
/// the factor `None` when the entry is not a number. `None` when no factor applies.
pub(crate) fn equation_relaxation(sol: &Dict, field: &str) -> Option<(Option<f64>, String)> {
    let rf = sol.opt_dict("relaxationFactors")?;
    let (eq, prefix) = match rf.opt_dict("equations") {
        Some(eq) => (eq, "relaxationFactors.equations"),
        None if rf.opt_dict("fields").is_none() => (rf, "relaxationFactors"),
        None => return None,
    };
    let (value, key) = match eq.lookup_path(field) {
        Some(v) => (v, field),
        None => (eq.get("default")?, "default"),
    };
    let factor = match value {
        foam::Value::Stream(s) => s.iter().rev().find_map(Item::as_f64),
        foam::Value::Dict(_) => None,
    };
    Some((factor, format!("{prefix}.{key}")))
}

/// The smoothers OpenFOAM v1912's GAMG accepts.
const GAMG_SMOOTHERS: &[&str] = &[
    "GaussSeidel",
    "symGaussSeidel",
    "nonBlockingGaussSeidel",
    "DIC",
    "DICGaussSeidel",
    "DILU",
    "DILUGaussSeidel",
    "FDIC",
];

/// Checks the `smoother` of a GAMG entry (`dotted` names it in errors). The native solver
/// runs its own multigrid ([`crate::amg`], Gauss–Seidel on every level) to the entry's
/// tolerances, so the smoother, like `cacheAgglomeration`, `nCellsInCoarsestLevel`,
/// `agglomerator`, `mergeLevels`, `nPreSweeps`, `nPostSweeps`, `nFinestSweeps`,
/// `directSolveCoarsest`, `scaleCorrection`, `interpolateCorrection` and `nVcycles`, changes
/// the iterations but not the converged answer; those keys are accepted and not used. A
/// smoother OpenFOAM would refuse is refused here too.
fn gamg_smoother(d: &Dict, file: &Path, dotted: &str) -> Result<()> {
    let smoother = d.word("smoother").map_err(|e| err(file, dotted, e.0))?;
    if !GAMG_SMOOTHERS.contains(&smoother) {
        return Err(err(
            file,
            dotted,
            format!(
                "`{smoother}` is not a GAMG smoother ({})",
                GAMG_SMOOTHERS.join(", ")
            ),
        ));
    }
    Ok(())
}

pub(crate) fn linear_solver(d: &Dict, file: &Path, name: &str) -> Result<LinearSolver> {
    let key = |k: &str| format!("solvers.{name}.{k}");
    let s = match d.lookup_path(&format!("solvers.{name}")) {
        Some(foam::Value::Dict(s)) => s,
        _ => return Err(err(file, &format!("solvers.{name}"), "missing")),
    };
    let solver = s
        .word("solver")
        .map_err(|e| err(file, &key("solver"), e.0))?;
    let preconditioner = || -> Result<Preconditioner> {
        let pre = s
            .word("preconditioner")
            .or_else(|_| {
                s.dict("preconditioner")
                    .and_then(|p| p.word("preconditioner"))
            })
            .unwrap_or("none");
        match pre {
            "DIC" | "DILU" => Ok(Preconditioner::Dic),
            "diagonal" => Ok(Preconditioner::Diagonal),
            "none" => Ok(Preconditioner::None),
            "GAMG" => {
                let d = s
                    .dict("preconditioner")
                    .map_err(|e| err(file, &key("preconditioner"), e.0))?;
                gamg_smoother(d, file, &key("preconditioner.smoother"))?;
                Ok(Preconditioner::Amg)
            }
            other => Err(err(
                file,
                &key("preconditioner"),
                format!("`{other}` is not supported (DIC, DILU, diagonal, none, GAMG)"),
            )),
        }
    };
    let method = match solver {
        "PCG" => Method::Pcg(preconditioner()?),
        "PBiCG" => Method::BiCg(preconditioner()?),
        "PBiCGStab" => Method::BiCgStab(preconditioner()?),
        "smoothSolver" => {
            let smoother = s
                .word("smoother")
                .map_err(|e| err(file, &key("smoother"), e.0))?;
            let kind = SmootherKind::from_name(smoother).ok_or_else(|| {
                err(
                    file,
                    &key("smoother"),
                    format!(
                        "`{smoother}` is not supported ({})",
                        SmootherKind::NAMES.join(", ")
                    ),
                )
            })?;
            let sweeps = s
                .f64_or("nSweeps", 1.0)
                .map_err(|e| err(file, &key("nSweeps"), e.0))?;
            if !(sweeps >= 1.0 && sweeps.fract() == 0.0) {
                return Err(err(file, &key("nSweeps"), "must be a positive integer"));
            }
            Method::Smooth(Smoother {
                kind,
                sweeps: sweeps as usize,
                hybrid: false,
            })
        }
        "GAMG" => {
            gamg_smoother(s, file, &key("smoother"))?;
            Method::Gamg
        }
        other => {
            return Err(err(
                file,
                &key("solver"),
                format!("`{other}` is not supported (PCG, PBiCG, PBiCGStab, smoothSolver, GAMG)"),
            ))
        }
    };
    let num = |k: &str, default: f64| s.f64_or(k, default).map_err(|e| err(file, &key(k), e.0));
    Ok(LinearSolver {
        method,
        controls: SolverControls {
            tolerance: num("tolerance", 1e-6)?,
            rel_tol: num("relTol", 0.0)?,
            max_iter: num("maxIter", 1000.0)? as usize,
            min_iter: num("minIter", 0.0)? as usize,
        },
    })
}

/// `nu` and `rho` (default 1) of `constant/transportProperties` (m²/s, kg/m³), a Newtonian
/// fluid.
fn transport(case: &Case) -> Result<(f64, f64)> {
    let tp_file = case.root().join("constant/transportProperties");
    let tp = case.read_dict("constant/transportProperties")?;
    if let Ok(m) = tp.word("transportModel") {
        if m != "Newtonian" {
            return Err(err(
                &tp_file,
                "transportModel",
                format!("`{m}` is not supported (Newtonian)"),
            ));
        }
    }
    let nu = dimensioned(&tp, &tp_file, "nu")?.ok_or_else(|| err(&tp_file, "nu", "missing"))?;
    if nu <= 0.0 {
        return Err(err(&tp_file, "nu", "must be positive"));
    }
    let rho = dimensioned(&tp, &tp_file, "rho")?.unwrap_or(1.0);
    Ok((nu, rho))
}

/// What `system/controlDict` says of the run's times and writes.
struct Control {
    start_time: f64,
    end_time: f64,
    delta_t: f64,
    write: WriteControl,
    write_format: foam::Format,
    purge_write: usize,
}

impl Control {
    /// Reads the controlDict `cd` of `case`.
    fn read(case: &Case, cd: &Dict) -> Result<Control> {
        let cd_file = case.root().join("system/controlDict");
        let start_time = match cd.word("startFrom").unwrap_or("startTime") {
            "startTime" => f64_of(cd, &cd_file, "startTime")?,
            "firstTime" => case.times()?.first().map_or(0.0, |t| t.value),
            "latestTime" => case.latest_time()?.map_or(0.0, |t| t.value),
            other => {
                return Err(err(
                    &cd_file,
                    "startFrom",
                    format!("`{other}` is not supported"),
                ))
            }
        };
        if cd.word("stopAt").unwrap_or("endTime") != "endTime" {
            return Err(err(&cd_file, "stopAt", "only `endTime` is supported"));
        }
        let end_time = f64_of(cd, &cd_file, "endTime")?;
        let delta_t = f64_of(cd, &cd_file, "deltaT")?;
        if delta_t.is_nan() || delta_t <= 0.0 {
            return Err(err(&cd_file, "deltaT", "must be positive"));
        }
        if cd.switch("adjustTimeStep").unwrap_or(false) {
            return Err(err(
                &cd_file,
                "adjustTimeStep",
                "adjustable time steps are not supported",
            ));
        }
        let (write, write_format) = writes(cd, &cd_file)?;
        let purge_write = match cd.f64_or("purgeWrite", 0.0) {
            Ok(n) if n >= 0.0 && n.fract() == 0.0 => n as usize,
            Ok(n) => {
                return Err(err(
                    &cd_file,
                    "purgeWrite",
                    format!("{n} is not a number of time directories (0, 1, 2, …)"),
                ))
            }
            Err(e) => return Err(err(&cd_file, "purgeWrite", e.0)),
        };
        Ok(Control {
            start_time,
            end_time,
            delta_t,
            write,
            write_format,
            purge_write,
        })
    }
}

/// The controlDict's `writeControl` with `writeInterval`, and `writeFormat`.
fn writes(cd: &Dict, cd_file: &Path) -> Result<(WriteControl, foam::Format)> {
    let interval = f64_of(cd, cd_file, "writeInterval")?;
    let write = match cd.word("writeControl").unwrap_or("timeStep") {
        "timeStep" => WriteControl::TimeStep(interval.max(1.0) as usize),
        "runTime" | "adjustableRunTime" => WriteControl::RunTime(interval),
        other => {
            return Err(err(
                cd_file,
                "writeControl",
                format!("`{other}` is not supported"),
            ))
        }
    };
    let write_format = match cd.word("writeFormat").unwrap_or("ascii") {
        "ascii" => foam::Format::Ascii,
        "binary" => foam::Format::Binary,
        other => {
            return Err(err(
                cd_file,
                "writeFormat",
                format!("`{other}` is not supported"),
            ))
        }
    };
    Ok((write, write_format))
}

/// The momentum equation's time scheme in fvSchemes `sch` (`ddt(U)`, else `default`), with
/// the dotted key that supplied it (for error messages).
fn time_scheme(sch: &Dict, sch_file: &Path) -> Result<(TimeScheme, &'static str)> {
    let ddt = sch
        .dict("ddtSchemes")
        .map_err(|e| err(sch_file, "ddtSchemes", e.0))?;
    let (ddt_s, ddt_key) = match ddt.stream("ddt(U)") {
        Ok(s) => (s, "ddtSchemes.ddt(U)"),
        Err(_) => (
            ddt.stream("default")
                .map_err(|e| err(sch_file, "ddtSchemes.default", e.0))?,
            "ddtSchemes.default",
        ),
    };
    let time_scheme = match ddt_s {
        [w] if w.as_word() == Some("Euler") => TimeScheme::Euler,
        [w] if w.as_word() == Some("backward") => TimeScheme::Backward,
        [w, psi] if w.as_word() == Some("CrankNicolson") => match psi.as_f64() {
            Some(p) if (0.0..=1.0).contains(&p) => TimeScheme::CrankNicolson(p),
            _ => return Err(err(sch_file, ddt_key, "CrankNicolson needs ψ in [0, 1]")),
        },
        _ => {
            return Err(err(
                sch_file,
                ddt_key,
                "supported: `Euler`, `backward`, `CrankNicolson ψ`",
            ))
        }
    };
    Ok((time_scheme, ddt_key))
}

/// The snGrad scheme of the Laplacians in fvSchemes `sch` (default `corrected`).
fn sn_grad(sch: &Dict, sch_file: &Path) -> Result<SnGrad> {
    // One snGrad scheme serves the momentum and the pressure Laplacians, so every
    // Laplacian the solver forms must name the same one.
    let mut sn_grad = None;
    let laplacians = [MOMENTUM_LAPLACIANS, PRESSURE_LAPLACIANS]
        .into_iter()
        .map(|keys| scheme_group(sch, sch_file, "laplacianSchemes", keys))
        .collect::<Result<Vec<_>>>()?;
    for (lap, lap_key) in laplacians.into_iter().flatten() {
        let lap: Vec<&str> = lap.iter().map(String::as_str).collect();
        let this = match lap.as_slice() {
            ["Gauss", "linear", "corrected"] => SnGrad::Corrected,
            ["Gauss", "linear", "uncorrected"] => SnGrad::Uncorrected,
            ["Gauss", "linear", "orthogonal"] => SnGrad::Orthogonal,
            other => {
                return Err(err(
                    sch_file,
                    &lap_key,
                    format!(
                        "`{}` is not supported (Gauss linear corrected|uncorrected|orthogonal)",
                        other.join(" ")
                    ),
                ))
            }
        };
        if sn_grad.is_some_and(|s| s != this) {
            return Err(err(
                sch_file,
                &lap_key,
                "the momentum and pressure Laplacians must use the same scheme",
            ));
        }
        sn_grad = Some(this);
    }
    Ok(sn_grad.unwrap_or(SnGrad::Corrected))
}

/// Checks the gradient and interpolation schemes the solver forms with `convection`.
fn gradients(sch: &Dict, sch_file: &Path, convection: Convection) -> Result<()> {
    // The gradients the solver forms: ∇p, ∇U, and ∇|U|² for limitedLinear's limiter
    // (OpenFOAM names it `grad(magSqr(U))`).
    let mut grads = vec!["grad(p)", "grad(U)"];
    if matches!(convection, Convection::LimitedLinear(_)) {
        grads.push("grad(magSqr(U))");
    }
    for key in grads {
        gauss_linear_grad(sch, sch_file, key)?;
    }
    if let Ok((i, key)) = scheme_words(sch, sch_file, "interpolationSchemes", "default") {
        if i != ["linear"] {
            return Err(err(sch_file, &key, "only `linear` is supported"));
        }
    }
    Ok(())
}

/// What fvSolution's `PISO` (else one-outer-corrector `PIMPLE`) dictionary and `solvers` ask
/// for.
struct Piso {
    n_correctors: usize,
    n_non_orth: usize,
    momentum_predictor: bool,
    p_ref: (usize, f64),
    p_solver: LinearSolver,
    p_final: LinearSolver,
    u_solver: LinearSolver,
}

impl Piso {
    /// Reads fvSolution `sol` (the file `sol_file`).
    fn read(sol: &Dict, sol_file: &Path) -> Result<Piso> {
        let algo = match (sol.dict("PISO"), sol.dict("PIMPLE")) {
            (Ok(d), _) => d,
            (_, Ok(d)) => {
                if d.f64_or("nOuterCorrectors", 1.0).unwrap_or(1.0) != 1.0 {
                    return Err(err(
                        sol_file,
                        "PIMPLE.nOuterCorrectors",
                        "only 1 (PISO) is supported",
                    ));
                }
                d
            }
            _ => return Err(err(sol_file, "PISO", "missing (or PIMPLE)")),
        };
        let count = |k: &str, default: f64| -> Result<usize> {
            let v = algo
                .f64_or(k, default)
                .map_err(|e| err(sol_file, &format!("PISO.{k}"), e.0))?;
            if v < 0.0 || v.fract() != 0.0 {
                return Err(err(
                    sol_file,
                    &format!("PISO.{k}"),
                    "must be a non-negative integer",
                ));
            }
            Ok(v as usize)
        };
        let n_correctors = count("nCorrectors", 1.0)?.max(1);
        let n_non_orth = count("nNonOrthogonalCorrectors", 0.0)?;
        let momentum_predictor = algo.switch("momentumPredictor").unwrap_or(true);
        let p_ref = (
            count("pRefCell", 0.0)?,
            algo.f64_or("pRefValue", 0.0).unwrap_or(0.0),
        );
        let p_solver = linear_solver(sol, sol_file, "p")?;
        let p_final = if sol.lookup_path("solvers.pFinal").is_some() {
            linear_solver(sol, sol_file, "pFinal")?
        } else {
            p_solver
        };
        let u_solver = linear_solver(sol, sol_file, "U")?;
        momentum_relaxation(sol, sol_file)?;
        Ok(Piso {
            n_correctors,
            n_non_orth,
            momentum_predictor,
            p_ref,
            p_solver,
            p_final,
            u_solver,
        })
    }
}

/// The turbulence model of `case` ([`crate::turbulence::properties`]; fvSchemes `sch` in
/// `sch_file`, fvSolution `sol`), checked against the momentum equation's time scheme
/// (`ddt_key` supplied it) and, with the full stress, the stress divergences' schemes.
fn turbulence(
    case: &Case,
    (sch, sch_file): (&Dict, &Path),
    sol: &Dict,
    (time_scheme, ddt_key): (TimeScheme, &str),
) -> Result<crate::turbulence::TurbulenceSettings> {
    let mom_lap = scheme_group(sch, sch_file, "laplacianSchemes", MOMENTUM_LAPLACIANS)?
        .into_iter()
        .next()
        .map(|(w, _)| w)
        .unwrap_or_default();
    let turbulence = crate::turbulence::properties::read(case, sch, sol, &mom_lap)?;
    if time_scheme == TimeScheme::Backward
        && matches!(
            turbulence,
            crate::turbulence::TurbulenceSettings::KEpsilon(_)
        )
    {
        return Err(err(
            sch_file,
            ddt_key,
            "`backward` with the RAS kEpsilon model is not supported (its k and epsilon \
             equations are Euler): use `Euler` or `CrankNicolson ψ`",
        ));
    }
    if turbulence.full_stress() {
        for (w, used) in scheme_group(sch, sch_file, "divSchemes", STRESS_DIVERGENCES)? {
            if w != ["Gauss", "linear"] {
                return Err(err(
                    sch_file,
                    &used,
                    format!("`{}` is not supported (Gauss linear)", w.join(" ")),
                ));
            }
        }
    }
    Ok(turbulence)
}

impl Settings {
    /// Reads the settings of `case`.
    pub fn read(case: &Case) -> Result<Settings> {
        Settings::read_with_control(case, &case.control_dict()?)
    }

    /// Reads the settings of `case` whose `system/controlDict` the caller has parsed already
    /// (`cd`: a run reads each case file once and hands it on).
    pub fn read_with_control(case: &Case, cd: &Dict) -> Result<Settings> {
        let root = case.root();
        let path = |rel: &str| -> PathBuf { root.join(rel) };
        let (nu, rho) = transport(case)?;
        let control = Control::read(case, cd)?;

        let sch_file = path("system/fvSchemes");
        let sch = case.read_dict("system/fvSchemes")?;
        let (time_scheme, ddt_key) = time_scheme(&sch, &sch_file)?;
        let (convection, bounded_convection) = convection_scheme(&sch, &sch_file)?;
        let sn_grad = sn_grad(&sch, &sch_file)?;
        gradients(&sch, &sch_file, convection)?;

        let fv_options = crate::fv_options::read(case)?;
        let sol_file = path("system/fvSolution");
        let sol = case.read_dict("system/fvSolution")?;
        let piso = Piso::read(&sol, &sol_file)?;

        let turbulence = turbulence(case, (&sch, &sch_file), &sol, (time_scheme, ddt_key))?;
        let full_stress = turbulence.full_stress();
        Ok(Settings {
            nu,
            rho,
            start_time: control.start_time,
            end_time: control.end_time,
            delta_t: control.delta_t,
            write: control.write,
            write_format: control.write_format,
            purge_write: control.purge_write,
            time_scheme,
            convection,
            bounded_convection,
            sn_grad,
            n_correctors: piso.n_correctors,
            n_non_orth: piso.n_non_orth,
            momentum_predictor: piso.momentum_predictor,
            p_ref: piso.p_ref,
            p_solver: piso.p_solver,
            p_final: piso.p_final,
            u_solver: piso.u_solver,
            full_stress,
            turbulence,
            fv_options,
            temperature: None,
        })
    }

    /// Asks for the temperature equation (a coupling with a heat model): reads what it needs
    /// of `case` — `Pr`, `Prt` of `constant/transportProperties`, the T equation's schemes
    /// and the `T` solver ([`crate::temperature::TemperatureSettings::read`]) — so that
    /// [`crate::Fluid::from_case_with`] then reads `T` (and `alphat`, `Tsource` when present)
    /// of the start time and solves the equation each step.
    pub fn enable_temperature(&mut self, case: &Case) -> Result<()> {
        self.temperature = Some(crate::temperature::TemperatureSettings::read(case)?);
        Ok(())
    }
}
