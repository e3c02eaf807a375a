//! The typed coupling configuration, read from a CFDEM-style `constant/couplingProperties`.
//!
//! CFDEMcoupling selects a model per family by name (`voidFractionModel divided;`) and reads
//! its parameters from a `<name>Props` sub-dictionary; `forceModels` and `momCoupleModels` are
//! lists of names. [`CouplingConfig::read`] maps those names onto foamgrain's:
//!
//! | CFDEM keyword | accepted values | foamgrain |
//! |---|---|---|
//! | `modelType` | `A`, `B`, `Bfull` | [`closures::model::ModelType`] |
//! | `couplingInterval` | integer ≥ 1 | DEM steps per coupling step |
//! | `voidFractionModel` | `centre`, `divided`, and our `cube`, `correctedCube`, `exact` | [`voidage::Method`]; `<name>Props/alphaMin` the ε floor |
//! | `forceModels` | one drag law of [`closures::DRAG_LAW_NAMES`], `gradPForce`, `viscForce`, `Archimedes` | [`Forces`] |
//! | `momCoupleModels` | `implicitCouple`, `explicitCouple` | [`MomentumCoupling`] |
//! | `locateModel` | `engine`, `engineIB`, `standard`, `turboEngine`, `turboEngineM2M`, `engineSearchMany2Many` | ignored: foamgrain's locator finds the same cells |
//! | `meshMotionModel` | `noMeshMotion` | — |
//! | `regionModel` | `allRegion` | — |
//! | `smoothingModel` | `off` | — |
//! | `averagingModel` | `dense` (`dilute` with a warning) | Us is β-weighted (ADR 0004) |
//! | `dataExchangeModel` | `twoWayMPI`, `twoWayFiles`, `oneWayVTK`, `twoWayM2M`, `noDataExchange` | recorded; its Props' `liggghtsPath` names the coupled deck ([`CouplingConfig::liggghts_path`]) |
//! | `IOModel`, `probeModel`, `clockModel`, `turbulenceModelType`, `checkPeriodicCells` | any | ignored |
//!
//! In a force model's Props, `interpolation true` selects the smooth interpolation
//! ([`crate::Interpolation::Smooth`]; CFDEM interpolates trilinearly, foamgrain averages over the
//! particle's voidage cells), `implForceDEM` (drag applied implicitly every DEM step),
//! `treatForceExplicit` (drag reaction in `f` instead of Ksl), `treatForceDEM` (no reaction
//! on the fluid), `verbose`, `switchingVoidfraction` and the sphericity `phi` (Gidaspow; only
//! `phi 1`, spheres, is accepted) and `…FieldName` entries are
//! understood; a field name other than CFDEM's default is an error, since foamgrain reads the
//! standard names. Any other key, an unknown model name or an unsupported value is a
//! [`CoupleError::Config`] naming the file and the key; `<name>Props` dictionaries of models
//! that are not selected are ignored, as CFDEM does. A Props dictionary may be given under an
//! OpenFOAM pattern key (`"(twoWayMPIProps|M2MProps)"`): it applies to every name it matches. Settings that are accepted but change
//! nothing in foamgrain are listed in [`CouplingConfig::warnings`].

use crate::error::CoupleError;
use crate::interpolate::Interpolation;
use closures::model::ModelType;
use closures::{DragClosure, DragLaw, DEFAULT_VOIDAGE_FLOOR, DRAG_LAW_NAMES};
use foam::{Dict, Item, Value};
use mesh::v3::V3;
use std::path::{Path, PathBuf};
use voidage::Method;

/// The drag force model and how it is coupled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DragSettings {
    /// The law and its voidage floor.
    pub closure: DragClosure,
    /// How U and ε are evaluated at the particle.
    pub interpolation: Interpolation,
    /// `implForceDEM`: the particle gets (β, u_f) and applies β (u_f − v) every DEM step
    /// (default false: the drag force is frozen over the coupling interval).
    pub implicit_dem: bool,
    /// `treatForceExplicit`: the drag's reaction goes into `f` instead of Ksl/Us.
    pub explicit_fluid: bool,
    /// `treatForceDEM`: the drag acts on the particle only.
    pub dem_only: bool,
}

/// Which forces act (other than drag), with their interpolation.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Forces {
    /// The drag model, if any.
    pub drag: Option<DragSettings>,
    /// `gradPForce`: −V_p ρ ∇p, with the interpolation of ∇p.
    pub grad_p: Option<Interpolation>,
    /// `viscForce`: V_p ρ ∇·τ, with the interpolation of ∇·τ.
    pub viscous: Option<Interpolation>,
    /// `Archimedes`: −ρ V_p g.
    pub archimedes: bool,
}

/// `momCoupleModels`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct MomentumCoupling {
    /// `implicitCouple`: Ksl and Us are handed to the fluid.
    pub implicit: bool,
    /// `explicitCouple`: f is handed to the fluid.
    pub explicit: bool,
    /// `implicitCoupleProps/KslLimit`, kg/(m³·s), if given.
    pub ksl_limit: Option<f64>,
}

/// The voidage model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoidageSettings {
    /// How particle volume is shared among cells.
    pub method: Method,
    /// `alphaMin`: the ε floor (clipping is reported), if given.
    pub alpha_min: Option<f64>,
}

/// The typed content of `couplingProperties`.
#[derive(Clone, Debug, PartialEq)]
pub struct CouplingConfig {
    /// The file read.
    pub file: PathBuf,
    /// `modelType`.
    pub model: ModelType,
    /// `couplingInterval`: DEM steps per coupling step.
    pub coupling_interval: u64,
    /// `voidFractionModel` and its Props.
    pub voidage: VoidageSettings,
    /// `forceModels` and their Props.
    pub forces: Forces,
    /// `momCoupleModels`.
    pub momentum: MomentumCoupling,
    /// `dataExchangeModel`, as written.
    pub data_exchange: String,
    /// `<dataExchangeModel>Props/liggghtsPath`: the coupled LIGGGHTS deck, relative to the
    /// OpenFOAM case directory as CFDEM resolves it (`../DEM/in.liggghts_run`), if given.
    pub liggghts_path: Option<PathBuf>,
    /// Accepted settings without effect in foamgrain, one sentence each naming the key.
    pub warnings: Vec<String>,
}

/// CFDEM's `voidFractionModel` names and ours.
const VOIDAGE_NAMES: [(&str, Method); 8] = [
    ("centre", Method::Centre),
    ("divided", Method::Divided),
    ("trilinear", Method::Trilinear),
    ("cube", Method::Cube),
    ("correctedCube", Method::CorrectedCube),
    ("corrected-cube", Method::CorrectedCube),
    ("exact", Method::Exact),
    ("exactVoidFraction", Method::Exact),
];

/// CFDEM's voidage models foamgrain does not implement, with the nearest of ours.
const VOIDAGE_UNSUPPORTED: [(&str, &str); 4] = [
    ("bigParticle", "cube or exact"),
    ("GaussVoidFraction", "exact"),
    ("IBVoidFraction", "exact"),
    ("dividedSmooth", "divided or exact"),
];

const LOCATE_NAMES: [&str; 6] = [
    "engine",
    "engineIB",
    "standard",
    "turboEngine",
    "turboEngineM2M",
    "engineSearchMany2Many",
];

const DATA_EXCHANGE_NAMES: [&str; 5] = [
    "twoWayMPI",
    "twoWayFiles",
    "oneWayVTK",
    "twoWayM2M",
    "noDataExchange",
];

/// Top-level keys read for their value; every other key must be a `…Props` dictionary.
const IGNORED_KEYS: [&str; 5] = [
    "IOModel",
    "probeModel",
    "clockModel",
    "turbulenceModelType",
    "checkPeriodicCells",
];

/// Standard field names of CFDEM's Props `…FieldName` keys.
const FIELD_NAMES: [(&str, &str); 12] = [
    ("velFieldName", "U"),
    ("velocityFieldName", "U"),
    ("voidfractionFieldName", "voidfraction"),
    ("granVelFieldName", "Us"),
    ("UsFieldName", "Us"),
    ("pFieldName", "p"),
    ("densityFieldName", "rho"),
    ("gravityFieldName", "g"),
    ("KslFieldName", "Ksl"),
    ("fFieldName", "f"),
    ("divTauFieldName", "divTau"),
    ("phiFieldName", "phi"),
];

/// Reader state: the file name for errors and the collected warnings.
struct Reader<'a> {
    file: &'a Path,
    warnings: Vec<String>,
}

impl Reader<'_> {
    fn err(&self, key: &str, message: impl Into<String>) -> CoupleError {
        CoupleError::Config {
            file: self.file.to_path_buf(),
            key: key.to_string(),
            message: message.into(),
        }
    }

    /// The single word (or quoted string) of entry `key`.
    fn word<'d>(&self, d: &'d Dict, key: &str, path: &str) -> Result<&'d str, CoupleError> {
        match d.get(key) {
            None => Err(self.err(path, "missing")),
            Some(Value::Stream(s)) if s.len() == 1 && s[0].as_word().is_some() => {
                Ok(s[0].as_word().expect("checked"))
            }
            Some(_) => Err(self.err(path, "expected one word")),
        }
    }

    fn opt_word<'d>(
        &self,
        d: &'d Dict,
        key: &str,
        path: &str,
    ) -> Result<Option<&'d str>, CoupleError> {
        match d.contains(key) {
            true => self.word(d, key, path).map(Some),
            false => Ok(None),
        }
    }

    /// The number of entry `key` in `d`.
    fn number(&self, d: &Dict, key: &str, path: &str) -> Result<f64, CoupleError> {
        d.f64(key)
            .map_err(|e| self.err(path, e.to_string()))
            .and_then(|x| {
                if x.is_finite() {
                    Ok(x)
                } else {
                    Err(self.err(path, "not a finite number"))
                }
            })
    }

    fn switch(&self, d: &Dict, key: &str, path: &str) -> Result<bool, CoupleError> {
        d.switch(key).map_err(|e| self.err(path, e.to_string()))
    }

    /// A list of words (`forceModels ( a b c );`).
    fn word_list(&self, d: &Dict, key: &str) -> Result<Vec<String>, CoupleError> {
        let stream = d.stream(key).map_err(|e| self.err(key, e.to_string()))?;
        let items = match stream {
            [Item::List(items)] => items,
            [Item::Label(_), Item::List(items)] => items,
            _ => return Err(self.err(key, "expected a list of names `( name … )`")),
        };
        items
            .iter()
            .map(|i| {
                i.as_word()
                    .map(str::to_string)
                    .ok_or_else(|| self.err(key, format!("expected a name, found a {}", i.kind())))
            })
            .collect()
    }

    /// The `<name>Props` dictionary (empty if absent), found as OpenFOAM finds a keyword: the
    /// exact key first, then a quoted pattern key matching it, the last one written winning
    /// (CFDEM's tutorials write `"(twoWayMPIProps|M2MProps)" { … }`).
    fn props(&self, top: &Dict, name: &str) -> Result<Dict, CoupleError> {
        let key = format!("{name}Props");
        match top.resolve(&key, &[]).map(|e| &e.value) {
            None => Ok(Dict::new()),
            Some(Value::Dict(d)) => Ok(d.clone()),
            Some(Value::Stream(_)) => Err(self.err(&key, "expected a dictionary")),
        }
    }

    /// Checks every key of `props` is in `known` or a standard `…FieldName`.
    fn check_props(&self, props: &Dict, dict: &str, known: &[&str]) -> Result<(), CoupleError> {
        for key in props.keys() {
            let path = format!("{dict}/{key}");
            if let Some((_, standard)) = FIELD_NAMES.iter().find(|(k, _)| *k == key) {
                let given = self.word(props, key, &path)?;
                if given != *standard {
                    return Err(self.err(
                        &path,
                        format!("foamgrain reads the field `{standard}`, not `{given}`"),
                    ));
                }
            } else if !known.contains(&key) {
                let mut valid: Vec<&str> = known.to_vec();
                valid.push("…FieldName");
                return Err(self.err(
                    &path,
                    format!("unknown or unsupported key; valid: {}", valid.join(", ")),
                ));
            }
        }
        Ok(())
    }

    fn interpolation(&self, props: &Dict, dict: &str) -> Result<Interpolation, CoupleError> {
        let on = props.contains("interpolation")
            && self.switch(props, "interpolation", &format!("{dict}/interpolation"))?;
        Ok(if on {
            Interpolation::Smooth
        } else {
            Interpolation::Cell
        })
    }
}

impl CouplingConfig {
    /// Reads and checks `path` (a `couplingProperties` file).
    pub fn read(path: &Path) -> Result<CouplingConfig, CoupleError> {
        let parsed = foam::parse_file(path)?;
        CouplingConfig::from_dict(&parsed.body, path)
    }

    /// Reads `constant/couplingProperties` of a case.
    pub fn read_case(case: &Path) -> Result<CouplingConfig, CoupleError> {
        CouplingConfig::read(&case.join("constant").join("couplingProperties"))
    }

    /// The configuration held by `top`, the body of the file `file` (named in errors).
    pub fn from_dict(top: &Dict, file: &Path) -> Result<CouplingConfig, CoupleError> {
        let mut r = Reader {
            file,
            warnings: Vec::new(),
        };
        let model_name = r.word(top, "modelType", "modelType")?;
        let model =
            ModelType::from_name(model_name).map_err(|e| r.err("modelType", e.to_string()))?;
        let interval = top
            .label("couplingInterval")
            .map_err(|e| r.err("couplingInterval", e.to_string()))?;
        if interval < 1 {
            return Err(r.err("couplingInterval", format!("{interval} is not ≥ 1")));
        }
        let voidage = read_voidage(&r, top)?;
        let forces = read_forces(&mut r, top)?;
        let momentum = read_momentum(&r, top)?;
        check_fixed_models(&mut r, top)?;
        let data_exchange = match r.opt_word(top, "dataExchangeModel", "dataExchangeModel")? {
            Some(w) if DATA_EXCHANGE_NAMES.contains(&w) => w.to_string(),
            Some(w) => {
                return Err(r.err(
                    "dataExchangeModel",
                    format!(
                        "unknown model `{w}`; valid: {}",
                        DATA_EXCHANGE_NAMES.join(", ")
                    ),
                ))
            }
            None => "twoWayMPI".to_string(),
        };
        let exchange_props = r.props(top, &data_exchange)?;
        let liggghts_path = match exchange_props.contains("liggghtsPath") {
            true => {
                let key = format!("{data_exchange}Props/liggghtsPath");
                Some(PathBuf::from(r.word(
                    &exchange_props,
                    "liggghtsPath",
                    &key,
                )?))
            }
            false => None,
        };
        for e in top.entries() {
            let key = e.keyword.as_str();
            let known = [
                "modelType",
                "couplingInterval",
                "voidFractionModel",
                "forceModels",
                "momCoupleModels",
                "locateModel",
                "meshMotionModel",
                "regionModel",
                "smoothingModel",
                "averagingModel",
                "dataExchangeModel",
            ];
            // a pattern key is the Props of whichever models it matches
            let props = key.ends_with("Props") || e.pattern;
            if !(known.contains(&key) || IGNORED_KEYS.contains(&key) || props) {
                return Err(r.err(key, "unknown or unsupported key"));
            }
        }
        Ok(CouplingConfig {
            file: file.to_path_buf(),
            model,
            coupling_interval: interval as u64,
            voidage,
            forces,
            momentum,
            data_exchange,
            liggghts_path,
            warnings: r.warnings,
        })
    }
}

fn read_voidage(r: &Reader<'_>, top: &Dict) -> Result<VoidageSettings, CoupleError> {
    let name = r.word(top, "voidFractionModel", "voidFractionModel")?;
    let method = match VOIDAGE_NAMES.iter().find(|(n, _)| *n == name) {
        Some(&(_, m)) => m,
        None => {
            let msg = match VOIDAGE_UNSUPPORTED.iter().find(|(n, _)| *n == name) {
                Some((_, instead)) => format!("`{name}` is not supported; use {instead}"),
                None => format!(
                    "unknown model `{name}`; valid: {}",
                    VOIDAGE_NAMES.map(|(n, _)| n).join(", ")
                ),
            };
            return Err(r.err("voidFractionModel", msg));
        }
    };
    let props = r.props(top, name)?;
    let dict = format!("{name}Props");
    r.check_props(
        &props,
        &dict,
        &["alphaMin", "scaleUpVol", "weight", "porosity", "verbose"],
    )?;
    let alpha_min = match props.contains("alphaMin") {
        true => {
            let key = format!("{dict}/alphaMin");
            let a = r.number(&props, "alphaMin", &key)?;
            if !(0.0..1.0).contains(&a) {
                return Err(r.err(&key, format!("{a} is not in [0, 1)")));
            }
            Some(a)
        }
        false => None,
    };
    for key in ["scaleUpVol", "weight", "porosity"] {
        if props.contains(key) {
            let path = format!("{dict}/{key}");
            let x = r.number(&props, key, &path)?;
            if x != 1.0 {
                return Err(r.err(
                    &path,
                    format!("{x} is not supported (only 1: particle volumes are not scaled)"),
                ));
            }
        }
    }
    Ok(VoidageSettings { method, alpha_min })
}

/// The non-drag force models foamgrain implements.
const OTHER_FORCES: [&str; 3] = ["gradPForce", "viscForce", "Archimedes"];

/// CFDEM force models foamgrain does not implement (a clear error rather than "unknown").
const FORCES_UNSUPPORTED: [&str; 6] = [
    "virtualMassForce",
    "MeiLift",
    "SaffmanLift",
    "ArchimedesIB",
    "ShirgaonkarIB",
    "noDrag",
];

fn read_forces(r: &mut Reader<'_>, top: &Dict) -> Result<Forces, CoupleError> {
    let names = r.word_list(top, "forceModels")?;
    let mut forces = Forces::default();
    for name in &names {
        let dict = format!("{name}Props");
        let props = r.props(top, name)?;
        if let Ok(law) = DragLaw::from_name(name) {
            if forces.drag.is_some() {
                return Err(r.err("forceModels", format!("a second drag law `{name}`")));
            }
            let mut known = vec![
                "interpolation",
                "implForceDEM",
                "treatForceExplicit",
                "treatForceDEM",
                "verbose",
            ];
            if matches!(law, DragLaw::Gidaspow { .. }) {
                known.extend(["switchingVoidfraction", "phi"]);
            }
            r.check_props(&props, &dict, &known)?;
            if props.contains("phi") {
                // CFDEM's GidaspowDragProps carry the sphericity `phi`; spheres have 1, and
                // only spheres are supported.
                let key = format!("{dict}/phi");
                let phi = r.number(&props, "phi", &key)?;
                if phi != 1.0 {
                    return Err(r.err(
                        &key,
                        format!("sphericity {phi}: only spheres (phi 1) are supported"),
                    ));
                }
            }
            let mut law = law;
            if props.contains("switchingVoidfraction") {
                let key = format!("{dict}/switchingVoidfraction");
                law = DragLaw::Gidaspow {
                    switch_voidage: r.number(&props, "switchingVoidfraction", &key)?,
                };
            }
            let closure = DragClosure::new(law, DEFAULT_VOIDAGE_FLOOR)
                .map_err(|e| r.err(&dict, e.to_string()))?;
            let flag = |key: &str| -> Result<bool, CoupleError> {
                match props.contains(key) {
                    true => r.switch(&props, key, &format!("{dict}/{key}")),
                    false => Ok(false),
                }
            };
            let settings = DragSettings {
                closure,
                interpolation: r.interpolation(&props, &dict)?,
                implicit_dem: flag("implForceDEM")?,
                explicit_fluid: flag("treatForceExplicit")?,
                dem_only: flag("treatForceDEM")?,
            };
            forces.drag = Some(settings);
            continue;
        }
        match name.as_str() {
            "gradPForce" | "viscForce" => {
                r.check_props(
                    &props,
                    &dict,
                    &["interpolation", "verbose", "treatForceExplicit"],
                )?;
                let interp = r.interpolation(&props, &dict)?;
                if name == "gradPForce" {
                    forces.grad_p = Some(interp);
                } else {
                    forces.viscous = Some(interp);
                }
            }
            "Archimedes" => {
                r.check_props(&props, &dict, &["verbose", "treatForceDEM"])?;
                forces.archimedes = true;
            }
            _ if FORCES_UNSUPPORTED.contains(&name.as_str()) => {
                return Err(r.err("forceModels", format!("`{name}` is not supported")));
            }
            _ => {
                let mut valid: Vec<&str> = DRAG_LAW_NAMES.iter().map(|(n, _)| *n).collect();
                valid.extend(OTHER_FORCES);
                return Err(r.err(
                    "forceModels",
                    format!("unknown force model `{name}`; valid: {}", valid.join(", ")),
                ));
            }
        }
    }
    Ok(forces)
}

fn read_momentum(r: &Reader<'_>, top: &Dict) -> Result<MomentumCoupling, CoupleError> {
    let mut m = MomentumCoupling::default();
    for name in r.word_list(top, "momCoupleModels")? {
        let dict = format!("{name}Props");
        let props = r.props(top, &name)?;
        match name.as_str() {
            "implicitCouple" => {
                r.check_props(&props, &dict, &["KslLimit", "verbose"])?;
                if props.contains("KslLimit") {
                    let key = format!("{dict}/KslLimit");
                    let limit = r.number(&props, "KslLimit", &key)?;
                    if limit.is_nan() || limit <= 0.0 {
                        return Err(r.err(&key, format!("{limit} is not > 0")));
                    }
                    m.ksl_limit = Some(limit);
                }
                m.implicit = true;
            }
            "explicitCouple" => {
                r.check_props(&props, &dict, &["verbose"])?;
                m.explicit = true;
            }
            "off" | "noCouple" => {}
            _ => {
                return Err(r.err(
                    "momCoupleModels",
                    format!("unknown model `{name}`; valid: implicitCouple, explicitCouple, off"),
                ))
            }
        }
    }
    Ok(m)
}

/// Model families with one supported choice (or a harmless set).
fn check_fixed_models(r: &mut Reader<'_>, top: &Dict) -> Result<(), CoupleError> {
    let fixed: [(&str, &[&str]); 4] = [
        ("meshMotionModel", &["noMeshMotion"]),
        ("regionModel", &["allRegion"]),
        ("smoothingModel", &["off", "noSmoothing"]),
        ("locateModel", &LOCATE_NAMES),
    ];
    for (key, valid) in fixed {
        if let Some(w) = r.opt_word(top, key, key)? {
            if !valid.contains(&w) {
                return Err(r.err(
                    key,
                    format!("`{w}` is not supported; valid: {}", valid.join(", ")),
                ));
            }
        }
    }
    match r.opt_word(top, "averagingModel", "averagingModel")? {
        None | Some("dense") => {}
        Some("dilute") => r.warnings.push(format!(
            "{}: averagingModel dilute: foamgrain's Us is always the β-weighted average of \
             the particle velocities (dense)",
            r.file.display()
        )),
        Some(w) => {
            return Err(r.err(
                "averagingModel",
                format!("unknown model `{w}`; valid: dense, dilute"),
            ))
        }
    }
    Ok(())
}

/// Fluid density ρ (kg/m³) and kinematic viscosity ν (m²/s) from
/// `constant/transportProperties` of `case`: the last number of the `rho` and `nu` entries
/// (plain `nu 1e-5;` or with dimensions `nu [0 2 -1 0 0 0 0] 1e-5;` or the old
/// `nu nu [0 2 -1 0 0 0 0] 1e-5;`). Both must be present and > 0.
pub fn read_transport(case: &Path) -> Result<(f64, f64), CoupleError> {
    let file = case.join("constant").join("transportProperties");
    let d = foam::parse_file(&file)?.body;
    let r = Reader {
        file: &file,
        warnings: Vec::new(),
    };
    let get = |key: &str| -> Result<f64, CoupleError> {
        let s = d.stream(key).map_err(|e| r.err(key, e.to_string()))?;
        match s.last().and_then(Item::as_f64) {
            Some(x) if x.is_finite() && x > 0.0 => Ok(x),
            _ => Err(r.err(key, "expected a positive number")),
        }
    };
    Ok((get("rho")?, get("nu")?))
}

/// Gravity g (m/s²) from `constant/g` (`value (gx gy gz);`), or `None` without the file.
pub fn read_gravity(case: &Path) -> Result<Option<V3>, CoupleError> {
    let file = case.join("constant").join("g");
    if !file.exists() {
        return Ok(None);
    }
    let d = foam::parse_file(&file)?.body;
    let r = Reader {
        file: &file,
        warnings: Vec::new(),
    };
    d.vector("value")
        .map(|g| Some(V3::from(g)))
        .map_err(|e| r.err("value", e.to_string()))
}

impl CouplingConfig {
    /// The coupler's settings for this configuration in the OpenFOAM case `case`: ρ and ν from
    /// `constant/transportProperties`, g from `constant/g` (required when `Archimedes` is on;
    /// zero otherwise when the file is absent).
    pub fn coupler_settings(&self, case: &Path) -> Result<crate::CouplerSettings, CoupleError> {
        let (rho, nu) = read_transport(case)?;
        let gravity = match read_gravity(case)? {
            Some(g) => g,
            None if self.forces.archimedes => {
                return Err(CoupleError::Config {
                    file: case.join("constant").join("g"),
                    key: "Archimedes".into(),
                    message: "the Archimedes force needs gravity: constant/g is missing".into(),
                })
            }
            None => V3::zeros(),
        };
        Ok(crate::CouplerSettings {
            method: self.voidage.method,
            alpha_min: self.voidage.alpha_min,
            coupling_interval: self.coupling_interval,
            physics: crate::Physics {
                rho,
                nu,
                gravity,
                model: self.model,
                forces: self.forces,
                implicit_couple: self.momentum.implicit,
            },
        })
    }
}
