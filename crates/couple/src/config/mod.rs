//! The typed coupling configuration, read from a CFDEM-style `constant/couplingProperties`.
//!
//! CFDEMcoupling selects a model per family by name (`voidFractionModel divided;`) and reads
//! its parameters from a `<name>Props` sub-dictionary; `forceModels` and `momCoupleModels` are
//! lists of names. [`CouplingConfig::read`] maps those names onto foamgrain's. Every family is
//! one table in [`registry`], a row per model: its name, aliases, whether it acts, is accepted
//! as it is, warns or is refused, and for an acting model its constructor (in the family's
//! file: `void_fraction`, `forces`, `monitors`, `momentum`, `smoothing`, `commands`), which
//! reads the model's `<name>Props`; this module reads the keys:
//!
//! | CFDEM keyword | foamgrain |
//! |---|---|
//! | `modelType` `A`, `B`, `Bfull` | [`closures::model::ModelType`] |
//! | `couplingInterval` (integer ≥ 1) | DEM steps per coupling step |
//! | `voidFractionModel` `centre`, `divided`, `trilinear`, and our `cube`, `correctedCube`, `exact` (with the other spellings of [`voidage::Method::names`], [`registry::VOIDAGE`]) | [`voidage::Method`]; `<name>Props/alphaMin` the ε floor (CFDEM's default 0.1 for its models, none for ours) |
//! | `forceModels` `virtualMassForce`, `MeiLift`, `SaffmanLift` (`forces.rs` has their keys) | [`Forces::virtual_mass`], [`Forces::mei_lift`], [`Forces::saffman_lift`] |
//! | `forceModels` (one drag law of [`registry::DRAG_LAWS`], closures' list, and [`registry::FORCES`]) | [`Forces`], and the observers of [`Monitors`] |
//! | `momCoupleModels` ([`registry::MOM_COUPLE`]) | [`MomentumCoupling`] |
//! | `locateModel`, `meshMotionModel`, `regionModel`, `smoothingModel`, `averagingModel`, `dataExchangeModel`, `IOModel`, `probeModel` ([`registry::SINGLE_NAME`]) | checked; `IOModel basicIO` writes particles ([`Monitors::basic_io`]); `<dataExchangeModel>Props/liggghtsPath` names the coupled deck ([`CouplingConfig::liggghts_path`]) |
//! | `smoothingModel` `constDiffSmoothing` (`<name>Props`: `smoothingLength`, `lowerLimit`, `upperLimit`), `temporalSmoothing` (`gamma`, `refField voidfraction`, the limits), `constDiffAndTemporalSmoothing` (`smoothingLength`, `smoothingStrength`, the limits) | [`CouplingConfig::smoothing`], [`crate::smoothing`]; `localPSizeDiffSmoothing` (`dSmoothingLength`, `Csmoothing`, the limits) as foamgrain reads it (its source is not public) |
//! | `clockModel` `off`, `standardClock` | [`Monitors::clock`] |
//! | `solveFlow` (switch, default on) | [`CouplingConfig::solve_flow`] |
//! | `useDDTvoidfraction` `b` (∂ε/∂t), `off` (CFDEM's default, also foamgrain's); the key alone (`useDDTvoidfraction;`) is `b`, as CFDEM-PFM reads it | [`CouplingConfig::ddt_voidage`]; `a` (∇·(Us (1 − ε))) is refused |
//! | `forceModels` `LaEuScalarTemp` and `scalarGeneralExchange` (its temperature part; CFDEM-PUBLIC), `energyModels` `heatTransferGunn` (CFDEM-PFM), with PFM's `thermCondModel` and `chemistryModels (off)` ([`registry::ENERGY`], [`registry::THERM_COND`], [`registry::CHEMISTRY`]) | [`CouplingConfig::heat`] ([`heat`] has the keys) |
//! | `debug`, `syncMode`, `checkPeriodicCells`, `turbulenceModelType` | accepted; `debug on` warns (no debug output) |
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
//! OpenFOAM pattern key (`"(twoWayMPIProps|M2MProps)"`): it applies to every name it matches.
//! Settings that are accepted but change nothing in foamgrain are listed, one sentence each,
//! in [`CouplingConfig::warnings`].

pub mod bed_heat;
pub mod commands;
mod forces;
pub mod heat;
mod momentum;
pub mod monitors;
pub mod registry;
mod smoothing;
mod transport;
mod void_fraction;

pub use commands::LiggghtsCommands;

pub use bed_heat::{BedConductivity, InterGrainSettings, WallHeatSettings};
pub use heat::{HeatModel, HeatSettings, MaxSource};
pub use monitors::Monitors;
pub use transport::{read_gravity, read_transport};

use crate::error::CoupleError;
use crate::interpolate::Interpolation;
use closures::model::ModelType;
use closures::DragClosure;
use commands::ScheduledCommand;
use foam::{Dict, Item, Value};
use mesh::v3::V3;
use registry::Support;
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

/// CFDEM's `noDrag`: removes the fluid forces of the force models (foamgrain requires it last
/// in `forceModels`, so it applies to all of them, as CFDEM's does to those listed before it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct NoDrag {
    /// `noDEMForce`: the particles get no fluid force either (default false: they keep it).
    pub no_dem_force: bool,
    /// `keepCFDForce`: the fluid keeps the particles' reaction (default false: it gets none).
    pub keep_cfd_force: bool,
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
    /// `noDrag`, if listed.
    pub no_drag: Option<NoDrag>,
    /// `virtualMassForce`: the added mass, if listed ([`crate::forces`] applies it).
    pub virtual_mass: Option<VirtualMassSettings>,
    /// `MeiLift`: CFDEM's shear lift ([`closures::forces::cfdem_mei_lift`]), if listed.
    pub mei_lift: Option<LiftSettings>,
    /// `SaffmanLift`: Saffman's (1965) lift ([`closures::forces::saffman_lift`]), if listed.
    pub saffman_lift: Option<LiftSettings>,
    /// `KochHillRWDrag`: the drag (Koch–Hill, in `drag`) sees a random-walk fluctuation in
    /// the fluid's k–ε fields ([`crate::random_walk`]).
    pub random_walk: Option<crate::random_walk::RandomWalkSettings>,
}

impl Forces {
    /// Whether a force model needs the fluid's vorticity ∇ × U ([`crate::FluidState::vorticity`]).
    pub fn needs_vorticity(&self) -> bool {
        self.mei_lift.is_some() || self.saffman_lift.is_some()
    }

    /// Whether a force model needs the fluid's DU/Dt = ∂U/∂t + ∇·(φU)
    /// ([`crate::FluidState::ddt_u`]): `virtualMassForce` with `splitUrelCalculation`.
    pub fn needs_ddt_u(&self) -> bool {
        self.virtual_mass.is_some_and(|v| v.split)
    }

    /// Whether a force model needs the fluid's k and ε ([`crate::FluidState::turbulence`]):
    /// `KochHillRWDrag`.
    pub fn needs_turbulence(&self) -> bool {
        self.random_walk.is_some()
    }
}

/// `virtualMassForce` (CFDEM-PUBLIC and CFDEM-PFM): F = C_add ρ V_p a_rel on the particle,
/// explicit, its reaction in `f` unless `treatForceDEM` ([`crate::forces`] has the two forms).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VirtualMassSettings {
    /// `Cadd`, the added-mass coefficient (default 0.5, a sphere's).
    pub c_add: f64,
    /// `splitUrelCalculation`: the fluid part is the fluid's DU/Dt at the particle (default
    /// false, CFDEM-PFM's: the change of u_f − v since the last coupling step).
    pub split: bool,
    /// How U (and DU/Dt) are evaluated at the particle.
    pub interpolation: Interpolation,
    /// `treatForceDEM`: the particle only, no reaction on the fluid.
    pub dem_only: bool,
}

/// `MeiLift` and `SaffmanLift`: an explicit lift force, its reaction in `f` unless
/// `treatForceDEM`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiftSettings {
    /// How U and ∇ × U are evaluated at the particle.
    pub interpolation: Interpolation,
    /// `MeiLift`'s `useSecondOrderTerms` (CFDEM-PUBLIC): Loth & Dorgan's spin term.
    pub second_order: bool,
    /// `treatForceDEM`: the particle only, no reaction on the fluid.
    pub dem_only: bool,
}
/// `momCoupleModels`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct MomentumCoupling {
    /// `implicitCouple`: Ksl and Us are handed to the fluid.
    pub implicit: bool,
    /// `explicitCouple`: f is handed to the fluid.
    pub explicit: bool,
    /// `implicitCoupleProps/KslLimit`, kg/(m³·s), if given (applied by CFDEM's Ksl form).
    pub ksl_limit: Option<f64>,
    /// `implicitCoupleProps/KslForm CFDEM`: CFDEM's Ksl = |Σ F| / (V |U − Us|) instead of
    /// foamgrain's conserving Σ w β / V ([`crate::ksl`]).
    pub cfdem_ksl: bool,
    /// `implicitCoupleProps/minAlphaP`, if given: CFDEM's form gives Ksl = 0 where
    /// ε ≥ 1 − minAlphaP.
    pub min_alpha_p: Option<f64>,
    /// `averagingModel`: how CFDEM's form averages Us.
    pub averaging: crate::ksl::UsAveraging,
}

impl MomentumCoupling {
    /// The Ksl form these settings select (CFDEM's defaults for what is not given).
    pub fn ksl_form(&self) -> crate::ksl::KslForm {
        use crate::ksl::{CfdemKsl, KslForm};
        if !self.cfdem_ksl {
            return KslForm::Conserving;
        }
        let d = CfdemKsl::default();
        KslForm::Cfdem(CfdemKsl {
            limit: self.ksl_limit.unwrap_or(d.limit),
            max_voidage: self.min_alpha_p.map_or(d.max_voidage, |m| 1.0 - m),
            averaging: self.averaging,
        })
    }
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
    /// The observing models: `fieldStore`, `particleCellVolume`, `volWeightedAverage`,
    /// `clockModel standardClock`, `IOModel basicIO`.
    pub monitors: Monitors,
    /// `solveFlow` (default true): when off the fluid is not solved (U and p stay as read) while
    /// the particles, the voidage and the exchange fields go on.
    pub solve_flow: bool,
    /// `smoothingModel` `constDiffSmoothing`, `temporalSmoothing` or
    /// `constDiffAndTemporalSmoothing`: the model and its settings ([`crate::smoothing`]);
    /// `None` for `off`.
    pub smoothing: Option<crate::smoothing::SmoothingModel>,
    /// `useDDTvoidfraction`: `b` puts ∂ε/∂t into the continuity equation, `off` leaves it out.
    /// Without the key it is left out, as CFDEM's default (`off`) does.
    pub ddt_voidage: bool,
    /// The heat transfer (`LaEuScalarTemp` or `heatTransferGunn`), `None` without one.
    pub heat: Option<HeatSettings>,
    /// CFDEM-PFM's `thermCondModel` (`SyamlalThermCond`, `ZehnerSchluenderThermCond`): the
    /// fluid's bed conductivity ([`bed_heat`]); `None` for `noTherm` or without the key.
    pub bed_conduction: Option<BedConductivity>,
    /// CFDEM-PFM's `wallHeatTransferYagi` (an `energyModels` entry beside the heat transfer
    /// model), `None` without it.
    pub wall_heat: Option<WallHeatSettings>,
    /// CFDEM-PFM's `heatTransferInterGrain` (an `energyModels` entry beside the heat transfer
    /// model), `None` without it.
    pub inter_grain: Option<InterGrainSettings>,
    /// `dataExchangeModel`, as written.
    pub data_exchange: String,
    /// `<dataExchangeModel>Props/liggghtsPath`: the coupled LIGGGHTS deck, relative to the
    /// OpenFOAM case directory as CFDEM resolves it (`../DEM/in.liggghts_run`), if given.
    pub liggghts_path: Option<PathBuf>,
    /// Accepted settings without effect in foamgrain, one sentence each naming the key.
    pub warnings: Vec<String>,
}

/// Top-level keys that name nothing foamgrain needs: read, never acted on.
const ACCEPTED_KEYS: [&str; 3] = ["syncMode", "checkPeriodicCells", "turbulenceModelType"];

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

/// The typed settings of the acting models, as their constructors ([`registry::Build`]) set
/// them while a family's reader walks the names of a case's `couplingProperties` or
/// `liggghtsCommands`.
#[derive(Clone, Debug, PartialEq, Default)]
struct Setup {
    /// `voidFractionModel`.
    voidage: Option<VoidageSettings>,
    /// `forceModels`' forces.
    forces: Forces,
    /// The observers (`forceModels`' auxiliary models, `clockModel`, `IOModel`).
    monitors: Monitors,
    /// `momCoupleModels`.
    momentum: MomentumCoupling,
    /// `smoothingModel`.
    smoothing: Option<crate::smoothing::SmoothingModel>,
    /// `liggghtsCommandModels`' commands, in the list's order.
    commands: Vec<ScheduledCommand>,
    /// The position (from 0) in `liggghtsCommandModels` of the model being read: an
    /// `execute` at position i reads `executeProps<i>`.
    position: usize,
    /// The heat transfer model.
    heat: Option<HeatSettings>,
    /// `thermCondModel`.
    bed: Option<BedConductivity>,
    /// `wallHeatTransferYagi`.
    wall: Option<WallHeatSettings>,
    /// `heatTransferInterGrain`.
    inter_grain: Option<InterGrainSettings>,
}

/// What a constructor returns: its setting is set in the [`Setup`], or the error.
type Built = Result<(), CoupleError>;

/// A selected model name, as a constructor gets it.
struct Given<'a> {
    /// The family's key (`forceModels`), for errors.
    key: &'a str,
    /// The name as written (the CFDEM name or an alias).
    name: &'a str,
    /// The dictionary holding the key (and the `<name>Props`).
    top: &'a Dict,
}

impl Given<'_> {
    /// The model's `<name>Props` ([`Reader::props`]) and that dictionary's name.
    fn props(&self, r: &Reader<'_>) -> Result<(Dict, String), CoupleError> {
        Ok((r.props(self.top, self.name)?, format!("{}Props", self.name)))
    }
}

/// Reader state: the file name for errors and the collected warnings.
struct Reader<'a> {
    file: &'a Path,
    warnings: Vec<String>,
}

impl<'a> Reader<'a> {
    fn new(file: &'a Path) -> Reader<'a> {
        Reader {
            file,
            warnings: Vec::new(),
        }
    }

    fn err(&self, key: &str, message: impl Into<String>) -> CoupleError {
        CoupleError::Config {
            file: self.file.to_path_buf(),
            key: key.to_string(),
            message: message.into(),
        }
    }

    /// Records a warning, prefixed with the file.
    fn warn(&mut self, message: String) {
        self.warnings
            .push(format!("{}: {message}", self.file.display()));
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

    /// The switch `key` if present.
    fn opt_switch(&self, d: &Dict, key: &str, path: &str) -> Result<Option<bool>, CoupleError> {
        match d.contains(key) {
            true => self.switch(d, key, path).map(Some),
            false => Ok(None),
        }
    }

    /// A list of words (`forceModels ( a b c );`).
    fn word_list(&self, d: &Dict, key: &str) -> Result<Vec<String>, CoupleError> {
        self.word_list_at(d, key, key)
    }

    /// A list of words or strings of entry `key`, named `path` in errors.
    fn word_list_at(&self, d: &Dict, key: &str, path: &str) -> Result<Vec<String>, CoupleError> {
        let stream = d.stream(key).map_err(|e| self.err(path, e.to_string()))?;
        let items = match stream {
            [Item::List(items)] => items,
            [Item::Label(_), Item::List(items)] => items,
            _ => return Err(self.err(path, "expected a list of names `( name … )`")),
        };
        items
            .iter()
            .map(|i| {
                i.as_word()
                    .map(str::to_string)
                    .ok_or_else(|| self.err(path, format!("expected a name, found a {}", i.kind())))
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

    /// Applies a family's table to the name of `given`: calls the row's constructor when it
    /// acts (`Ok(true)`), accepts it without action otherwise (`Ok(false)`; a warning is
    /// recorded for [`Support::Warn`]), an error for a refused or unknown name.
    fn apply(
        &mut self,
        family: &registry::Family,
        given: &Given<'_>,
        setup: &mut Setup,
    ) -> Result<bool, CoupleError> {
        let (key, name) = (given.key, given.name);
        match family.support(name) {
            Some(Support::Acts(build)) => {
                (build.0)(self, given, setup)?;
                Ok(true)
            }
            Some(Support::Same) => Ok(false),
            Some(Support::Warn(why)) => {
                self.warn(format!("{key} {name}: {why}"));
                Ok(false)
            }
            Some(Support::Refuse(instead)) => {
                Err(self.err(key, format!("`{name}` is not supported ({instead})")))
            }
            None => Err(self.err(
                key,
                format!("unknown model `{name}`; valid: {}", family.valid_names()),
            )),
        }
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
        let mut r = Reader::new(file);
        let model_name = r.word(top, "modelType", "modelType")?;
        let model =
            ModelType::from_name(model_name).map_err(|e| r.err("modelType", e.to_string()))?;
        let interval = top
            .label("couplingInterval")
            .map_err(|e| r.err("couplingInterval", e.to_string()))?;
        if interval < 1 {
            return Err(r.err("couplingInterval", format!("{interval} is not ≥ 1")));
        }
        let mut setup = Setup::default();
        let voidage = void_fraction::read(&mut r, top, &mut setup)?;
        forces::read_forces(&mut r, top, &mut setup)?;
        momentum::read(&mut r, top, &mut setup)?;
        for family in [&registry::ENERGY, &registry::CHEMISTRY] {
            heat::read_list(&mut r, top, family, &mut setup)?;
        }
        for family in registry::SINGLE_NAME.iter().chain([&registry::CLOCK]) {
            let key = family.key;
            if let Some(name) = r.opt_word(top, key, key)? {
                r.apply(family, &Given { key, name, top }, &mut setup)?;
            }
        }
        momentum::check_averaging(&mut r, &setup.momentum);
        if (setup.wall.is_some() || setup.inter_grain.is_some()) && setup.heat.is_none() {
            return Err(r.err(
                "energyModels",
                "wallHeatTransferYagi and heatTransferInterGrain need a heat transfer model \
                 beside them (heatTransferGunn, LaEuScalarTemp…): without one there are no \
                 fluid and particle temperatures to couple, and its λ and c_p are the wall \
                 law's",
            ));
        }
        if let (Some(bed), None) = (setup.bed, setup.heat) {
            r.warn(format!(
                "thermCondModel {}: no heat transfer model is selected, so the fluid solves no \
                 temperature and the bed conductivity has no effect",
                bed.name()
            ));
        }
        let data_exchange = r
            .opt_word(top, "dataExchangeModel", "dataExchangeModel")?
            .unwrap_or("twoWayMPI")
            .to_string();
        let solve_flow = r.opt_switch(top, "solveFlow", "solveFlow")?.unwrap_or(true);
        // CFDEM-PFM switches ∂ε/∂t on by the key alone (`useDDTvoidfraction;`, its
        // voidfractionTest); a word after the key is read as CFDEM-PUBLIC reads it (PFM would
        // take even `off` as on, but no PFM case writes a word there)
        let bare_ddt = top.stream("useDDTvoidfraction").is_ok_and(|s| s.is_empty());
        let ddt_voidage = match bare_ddt {
            true => Some("b"),
            false => r.opt_word(top, "useDDTvoidfraction", "useDDTvoidfraction")?,
        };
        let ddt_voidage = match ddt_voidage {
            Some("b") => true,
            None | Some("off") => false,
            Some("a") => {
                return Err(r.err(
                    "useDDTvoidfraction",
                    "`a` (∂ε/∂t as ∇·(Us (1 − ε))) is not supported; use `b` (the time \
                     derivative of the voidage) or `off`",
                ))
            }
            Some(w) => {
                return Err(r.err(
                    "useDDTvoidfraction",
                    format!("unknown choice `{w}`; valid: a, b, off"),
                ))
            }
        };
        if r.opt_switch(top, "debug", "debug")? == Some(true) {
            r.warn("debug on: foamgrain writes no CFDEM debug output".into());
        }
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
                "energyModels",
                "chemistryModels",
                "clockModel",
                "solveFlow",
                "useDDTvoidfraction",
                "debug",
            ];
            let family = registry::SINGLE_NAME.iter().any(|f| f.key == key);
            // a pattern key is the Props of whichever models it matches
            let props = key.ends_with("Props") || e.pattern;
            if !(known.contains(&key) || family || ACCEPTED_KEYS.contains(&key) || props) {
                return Err(r.err(key, "unknown or unsupported key"));
            }
        }
        Ok(CouplingConfig {
            file: file.to_path_buf(),
            model,
            coupling_interval: interval as u64,
            voidage,
            forces: setup.forces,
            momentum: setup.momentum,
            monitors: setup.monitors,
            solve_flow,
            ddt_voidage,
            smoothing: setup.smoothing,
            heat: setup.heat,
            bed_conduction: setup.bed,
            wall_heat: setup.wall,
            inter_grain: setup.inter_grain,
            data_exchange,
            liggghts_path,
            warnings: r.warnings,
        })
    }
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
            heat: self.heat,
        })
    }
}
