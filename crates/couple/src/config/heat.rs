//! The heat transfer between fluid and particles ([`HeatSettings`]): CFDEM-PUBLIC's
//! `LaEuScalarTemp` (a `forceModels` entry of `cfdemSolverPisoScalar` cases), the temperature
//! part of its `scalarGeneralExchange` (`cfdemSolverPisoSTM`; the keys at its constructor) and
//! CFDEM-PFM's `heatTransferGunn` (an `energyModels` entry), and the PFM families that come
//! with it
//! (`thermCondModel`, `chemistryModels`). The names are the rows of
//! [`super::registry::FORCES`], [`super::registry::ENERGY`], [`super::registry::THERM_COND`] and
//! [`super::registry::CHEMISTRY`]; this file holds the constructors. What the settings compute
//! is [`crate::heat`].
//!
//! | Props key | `LaEuScalarTemp` | `heatTransferGunn` |
//! |---|---|---|
//! | λ, c_p | `lambda`, `Cp` (required, > 0: CFDEM's fallback to the thermo fields exists only in compressible solvers) | `kf`, `Cp` of `constant/transportProperties` (next to `couplingProperties`) |
//! | Nu | `NuCorrelation` `LiMason` (default), `Deen`, `Gunn` | Gunn (Pr^0.33), `NusseltScalingFactor` (all cells) |
//! | Re | d \|u_f − v\| / ν | ε d \|u_f − v\| / ν, ε ≥ 0.01 |
//! | `maxSource` | bound on \|Tsource\|, K/s | bound on \|Tsource\| ρ c_p, W/m³ |
//! | `interpolation` | switch (default off) | switch (default off) |
//! | refused | `compressible true` | `implicit true` (PFM's default: give `implicit false`), `initPartTemp true`, `expNusselt true`, `calcPartTempField true`, `scaleNuCellsName` other than `all`, coarse graining |
//!
//! `scalarGeneralExchange` (temperature only): `lambda` and `Prandtl` given, ρ c_p =
//! `generalManualProps/cpVolumetric` of `constant/scalarTransportProperties`, Nu of Deen et al.
//! or (`useLiMason true`) Li & Mason with Pr^⅓, Re = ε d |u_f − v| / ν, `maxSource` in W/m³;
//! species, the implicit strategy, `useGeneralCorrelation` and `useCorrectedVoidage` are
//! refused.
//!
//! Field names must be the standard ones ([`TEMPERATURE_FIELD`], [`PARTICLE_TEMPERATURE`],
//! [`PARTICLE_HEAT_FLUX`], [`HEAT_SOURCE_FIELD`]; `velFieldName`, `voidfractionFieldName`,
//! `densityFieldName` as for every model): foamgrain's sides exchange these.

use super::{Built, Given, Reader, Setup};
use crate::error::CoupleError;
use crate::interpolate::Interpolation;
use closures::heat::{check_properties, Nusselt, ReynoldsVelocity, GUNN_PFM_VOIDAGE_FLOOR};
use foam::{Dict, Item};
use std::path::Path;

/// The fluid temperature field (`tempFieldName`).
pub const TEMPERATURE_FIELD: &str = "T";
/// The particles' temperature property (`partTempName`, LIGGGHTS's `fix heat/gran`).
pub const PARTICLE_TEMPERATURE: &str = "Temp";
/// The particles' convective heat flux property (`partHeatFluxName`, LIGGGHTS's `fix
/// couple/cfd/convection`).
pub const PARTICLE_HEAT_FLUX: &str = "convectiveHeatFlux";
/// The fluid's heat source field (`EuFieldName`), K/s.
pub const HEAT_SOURCE_FIELD: &str = "Tsource";

/// Which CFDEM model computes the heat transfer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeatModel {
    /// CFDEM-PUBLIC's `LaEuScalarTemp`.
    LaEuScalarTemp,
    /// CFDEM-PFM's `heatTransferGunn` (explicit).
    HeatTransferGunn,
    /// CFDEM-PFM's `heatTransferRanzMarshall` (explicit; its Props as `heatTransferGunn`'s,
    /// plus `NusseltConstParameter`, 0.6 only).
    HeatTransferRanzMarshall,
    /// CFDEM-PUBLIC's `scalarGeneralExchange`, its temperature part (explicit flux).
    ScalarGeneralExchange,
}

/// `maxSource`: the bound on a cell's heat source, in the unit its model gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MaxSource {
    /// On |Tsource|, K/s (`LaEuScalarTemp`).
    KelvinPerSecond(f64),
    /// On |Tsource| ρ c_p, W/m³ (`heatTransferGunn`'s `QPartFluid`).
    WattPerCubicMetre(f64),
}

impl MaxSource {
    /// The bound on |Tsource|, K/s, for the fluid's volumetric heat capacity `rho_cp`
    /// (J/(m³·K)).
    pub fn kelvin_per_second(self, rho_cp: f64) -> f64 {
        match self {
            MaxSource::KelvinPerSecond(x) => x,
            MaxSource::WattPerCubicMetre(x) => x / rho_cp,
        }
    }
}

/// The heat transfer model and its parameters (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatSettings {
    /// The CFDEM model.
    pub model: HeatModel,
    /// The Nusselt law.
    pub nusselt: Nusselt,
    /// The velocity of the particle Reynolds number.
    pub reynolds: ReynoldsVelocity,
    /// ε below this is raised to it in Re and Nu (0: none).
    pub voidage_floor: f64,
    /// Factor on Nu (`NusseltScalingFactor`, 1 without).
    pub nusselt_scale: f64,
    /// The fluid's thermal conductivity λ, W/(m·K).
    pub lambda: f64,
    /// The fluid's specific heat capacity c_p, J/(kg·K) (`scalarGeneralExchange`: its
    /// volumetric `cpVolumetric` over ρ).
    pub cp: f64,
    /// The Prandtl number when the model gives it (`scalarGeneralExchange`'s `Prandtl`);
    /// `None`: c_p ν ρ / λ.
    pub prandtl: Option<f64>,
    /// `maxSource`, if given.
    pub max_source: Option<MaxSource>,
    /// How U, T and ε are evaluated at a particle.
    pub interpolation: Interpolation,
}

impl HeatSettings {
    /// `Ok` if the parameters are in range (λ, c_p, a given Pr, the Nu factor and a
    /// `maxSource` finite and > 0, the ε floor in [0, 1)), else an error naming the first bad
    /// one. The configuration reader gives only such settings; [`crate::Coupler::new`] checks
    /// those built otherwise.
    pub fn check(&self) -> Result<(), CoupleError> {
        check_properties("heat transfer", self.lambda, self.cp)?;
        let max = self.max_source.map(|m| match m {
            MaxSource::KelvinPerSecond(x) | MaxSource::WattPerCubicMetre(x) => x,
        });
        let positive = [
            ("Prandtl", self.prandtl),
            ("NusseltScalingFactor", Some(self.nusselt_scale)),
            ("maxSource", max),
        ];
        for (what, x) in positive {
            if let Some(x) = x.filter(|x| !(x.is_finite() && *x > 0.0)) {
                return Err(CoupleError::Parameter(format!(
                    "heat transfer: {what} {x} is not a positive number"
                )));
            }
        }
        if !(0.0..1.0).contains(&self.voidage_floor) {
            return Err(CoupleError::Parameter(format!(
                "heat transfer: voidage floor {} is not in [0, 1)",
                self.voidage_floor
            )));
        }
        Ok(())
    }
}

/// Reads a list family (`energyModels`, `chemistryModels`) through its table.
pub(super) fn read_list(
    r: &mut Reader<'_>,
    top: &Dict,
    family: &super::registry::Family,
    setup: &mut Setup,
) -> Result<(), CoupleError> {
    let key = family.key;
    if !top.contains(key) {
        return Ok(());
    }
    for name in r.word_list(top, key)? {
        r.props(top, &name)?;
        let given = Given {
            key,
            name: &name,
            top,
        };
        r.apply(family, &given, setup)?;
    }
    Ok(())
}

/// A heat model's setting into `s`, refusing a second one.
fn set(r: &Reader<'_>, g: &Given<'_>, s: &mut Setup, heat: HeatSettings) -> Built {
    if s.heat.is_some() {
        return Err(r.err(g.key, format!("`{}`: a second heat transfer model", g.name)));
    }
    s.heat = Some(heat);
    Ok(())
}

/// Checks that the field-name keys present in `props` name the standard fields.
fn standard_names(
    r: &Reader<'_>,
    props: &Dict,
    dict: &str,
    names: &[(&str, &str)],
) -> Result<(), CoupleError> {
    for (key, standard) in names {
        if let Some(given) = r.opt_word(props, key, &format!("{dict}/{key}"))? {
            if given != *standard {
                return Err(r.err(
                    &format!("{dict}/{key}"),
                    format!("foamgrain exchanges `{standard}`, not `{given}`"),
                ));
            }
        }
    }
    Ok(())
}

/// `maxSource` (> 0) of `props`, if given.
pub(super) fn max_source(
    r: &Reader<'_>,
    props: &Dict,
    dict: &str,
) -> Result<Option<f64>, CoupleError> {
    if !props.contains("maxSource") {
        return Ok(None);
    }
    let key = format!("{dict}/maxSource");
    let x = r.number(props, "maxSource", &key)?;
    match x > 0.0 {
        true => Ok(Some(x)),
        false => Err(r.err(&key, format!("{x} is not > 0"))),
    }
}

/// A required positive number `key` of `props`.
fn positive(
    r: &Reader<'_>,
    props: &Dict,
    dict: &str,
    key: &str,
    what: &str,
) -> Result<f64, CoupleError> {
    let path = format!("{dict}/{key}");
    if !props.contains(key) {
        return Err(r.err(
            &path,
            format!(
                "missing: the fluid's {what} (CFDEM falls back to the thermo fields of a \
                 compressible solver, which foamgrain does not have)"
            ),
        ));
    }
    let x = r.number(props, key, &path)?;
    match x > 0.0 {
        true => Ok(x),
        false => Err(r.err(&path, format!("{x} is not > 0"))),
    }
}

/// `LaEuScalarTemp` (CFDEM-PUBLIC): `LaEuScalarTempProps` (module docs).
pub(super) fn la_eu_scalar_temp(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "tempFieldName",
            "partTempName",
            "partHeatFluxName",
            "EuFieldName",
            "lambda",
            "Cp",
            "NuCorrelation",
            "maxSource",
            "interpolation",
            "compressible",
            "verbose",
            "scalarViscosity",
        ],
    )?;
    if r.opt_switch(props, "compressible", &format!("{dict}/compressible"))? == Some(true) {
        return Err(r.err(
            &format!("{dict}/compressible"),
            "`true` needs a compressible solver (the source in W/m³ and c_p from the thermo); \
             foamgrain's fluids are incompressible: remove it or set it false",
        ));
    }
    // CFDEM requires tempFieldName (no default)
    r.word(props, "tempFieldName", &format!("{dict}/tempFieldName"))?;
    standard_names(r, props, dict, &la_eu_names())?;
    let lambda = positive(r, props, dict, "lambda", "thermal conductivity λ, W/(m·K)")?;
    let cp = positive(r, props, dict, "Cp", "specific heat capacity c_p, J/(kg·K)")?;
    let nusselt = match r.opt_word(props, "NuCorrelation", &format!("{dict}/NuCorrelation"))? {
        None => Nusselt::LiMason,
        Some(name) => Nusselt::from_name(name)
            .map_err(|e| r.err(&format!("{dict}/NuCorrelation"), e.to_string()))?,
    };
    let heat = HeatSettings {
        model: HeatModel::LaEuScalarTemp,
        nusselt,
        reynolds: ReynoldsVelocity::Interstitial,
        voidage_floor: 0.0,
        nusselt_scale: 1.0,
        lambda,
        cp,
        prandtl: None,
        max_source: max_source(r, props, dict)?.map(MaxSource::KelvinPerSecond),
        interpolation: r.interpolation(props, dict)?,
    };
    set(r, g, s, heat)
}

/// The field-name keys of `LaEuScalarTempProps` and their standard values.
fn la_eu_names() -> [(&'static str, &'static str); 4] {
    [
        ("tempFieldName", TEMPERATURE_FIELD),
        ("partTempName", PARTICLE_TEMPERATURE),
        ("partHeatFluxName", PARTICLE_HEAT_FLUX),
        ("EuFieldName", HEAT_SOURCE_FIELD),
    ]
}

/// `heatTransferGunnProps` keys that must stay off (or at their default), with why.
const GUNN_OFF: [(&str, &str); 3] = [
    (
        "initPartTemp",
        "particle temperatures come from the DEM (`fix heat/gran initial_temperature`)",
    ),
    (
        "expNusselt",
        "a prescribed Nusselt field is not implemented",
    ),
    (
        "calcPartTempField",
        "the particle temperature field is not written",
    ),
];

/// `heatTransferGunn` (CFDEM-PFM): `heatTransferGunnProps` (module docs), λ and c_p from
/// `kf` and `Cp` of `constant/transportProperties` next to the `couplingProperties` read.
pub(super) fn heat_transfer_gunn(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    pfm_heat(r, g, s, HeatModel::HeatTransferGunn)
}

/// `heatTransferRanzMarshall` (CFDEM-PFM): Ranz & Marshall's Nu = 2 + 0.6 Re^½ Pr^⅓
/// ([`Nusselt::RanzMarshall`]) on the superficial Re with PFM's ε floor 0.01, and
/// `heatTransferGunn`'s Props and checks; `NusseltConstParameter` (PFM: the 0.6, warned
/// outside [0.6, 1.8]) must be 0.6.
pub(super) fn heat_transfer_ranz_marshall(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    pfm_heat(r, g, s, HeatModel::HeatTransferRanzMarshall)
}

/// The PFM energy model `model` (`heatTransferGunn` or `heatTransferRanzMarshall`).
fn pfm_heat(r: &mut Reader, g: &Given, s: &mut Setup, model: HeatModel) -> Built {
    let (props, dict) = &g.props(r)?;
    let name = g.name;
    if model == HeatModel::HeatTransferRanzMarshall && props.contains("NusseltConstParameter") {
        let key = format!("{dict}/NusseltConstParameter");
        let c = r.number(props, "NusseltConstParameter", &key)?;
        if c != 0.6 {
            return Err(r.err(
                &key,
                format!("{c}: only Ranz & Marshall's 0.6 is supported"),
            ));
        }
    }
    r.check_props(
        props,
        dict,
        &[
            "NusseltConstParameter",
            "partTempName",
            "partHeatFluxName",
            "tempFieldName",
            "QPartFluidName",
            "QPartFluidCoeffName",
            "interpolation",
            "verbose",
            "implicit",
            "calcTotalHeatFlux",
            "initPartTemp",
            "Tmin",
            "Tmax",
            "expNusselt",
            "calcPartTempField",
            "partRefTemp",
            "NusseltScalingFactor",
            "scaleNuCellsName",
            "maxSource",
            "scale",
            "coarseGrainingFactors",
        ],
    )?;
    r.word(props, "partTempName", &format!("{dict}/partTempName"))?;
    standard_names(
        r,
        props,
        dict,
        &[
            ("tempFieldName", TEMPERATURE_FIELD),
            ("partTempName", PARTICLE_TEMPERATURE),
            ("partHeatFluxName", PARTICLE_HEAT_FLUX),
            ("QPartFluidName", "QPartFluid"),
            ("QPartFluidCoeffName", "QPartFluidCoeff"),
            ("scaleNuCellsName", "all"),
        ],
    )?;
    let implicit = r.opt_switch(props, "implicit", &format!("{dict}/implicit"))?;
    if implicit != Some(false) {
        return Err(r.err(
            &format!("{dict}/implicit"),
            format!(
                "{name} is implicit unless `implicit false;` (PFM's default is true); \
                 foamgrain's fluid takes an explicit heat source only (q from T_f at the \
                 coupling time, held over the interval): set `implicit false;`"
            ),
        ));
    }
    for (key, why) in GUNN_OFF {
        if r.opt_switch(props, key, &format!("{dict}/{key}"))? == Some(true) {
            return Err(r.err(
                &format!("{dict}/{key}"),
                format!("`true` is not supported: {why}"),
            ));
        }
    }
    for key in ["scale", "coarseGrainingFactors"] {
        if props.contains(key) {
            return Err(r.err(&format!("{dict}/{key}"), "coarse graining is not supported"));
        }
    }
    let nusselt_scale = match props.contains("NusseltScalingFactor") {
        true => {
            let key = format!("{dict}/NusseltScalingFactor");
            let x = r.number(props, "NusseltScalingFactor", &key)?;
            if x <= 0.0 {
                return Err(r.err(&key, format!("{x} is not > 0")));
            }
            x
        }
        false => 1.0,
    };
    let (lambda, cp) = transport_heat(r.file)?;
    let heat = HeatSettings {
        model,
        nusselt: match model {
            HeatModel::HeatTransferRanzMarshall => Nusselt::RanzMarshall,
            _ => Nusselt::GunnPfm,
        },
        reynolds: ReynoldsVelocity::Superficial,
        voidage_floor: GUNN_PFM_VOIDAGE_FLOOR,
        nusselt_scale,
        lambda,
        cp,
        prandtl: None,
        max_source: max_source(r, props, dict)?.map(MaxSource::WattPerCubicMetre),
        interpolation: r.interpolation(props, dict)?,
    };
    set(r, g, s, heat)
}

/// `kf` (W/(m·K)) and `Cp` (J/(kg·K)) of the `transportProperties` next to
/// `coupling_properties` (CFDEM-PFM's energy models read them there).
fn transport_heat(coupling_properties: &Path) -> Result<(f64, f64), CoupleError> {
    let file = coupling_properties.with_file_name("transportProperties");
    let d = foam::parse_file(&file)?.body;
    let r = Reader::new(&file);
    let value = |key: &str| -> Result<f64, CoupleError> {
        if !d.contains(key) {
            return Err(r.err(
                key,
                "missing: heatTransferGunn reads the fluid's `kf` and `Cp` here",
            ));
        }
        let s = d.stream(key).map_err(|e| r.err(key, e.to_string()))?;
        s.last()
            .and_then(Item::as_f64)
            .ok_or_else(|| r.err(key, "expected a number"))
    };
    let (kf, cp) = (value("kf")?, value("Cp")?);
    check_properties("heatTransferGunn", kf, cp).map_err(|e| {
        let key = if kf.is_finite() && kf > 0.0 {
            "Cp"
        } else {
            "kf"
        };
        r.err(key, e.to_string())
    })?;
    Ok((kf, cp))
}

/// `scalarGeneralExchangeProps` keys foamgrain reads (its temperature part).
const GENERAL_EXCHANGE_KEYS: [&str; 21] = [
    "tempFieldName",
    "partTempName",
    "partHeatFluxName",
    "partHeatTransCoeffName",
    "partHeatFluidName",
    "lambda",
    "Prandtl",
    "useLiMason",
    "useGeneralCorrelation",
    "generalCorrelationParameters",
    "partSpeciesNames",
    "partSpeciesFluxNames",
    "partSpeciesTransCoeffNames",
    "partSpeciesFluidNames",
    "DMolecular",
    "maxSource",
    "interpolation",
    "verbose",
    "verboseToDisk",
    "scalarViscosity",
    "useCorrectedVoidage",
];

/// The species lists of `scalarGeneralExchangeProps`: CFDEM requires them; foamgrain exchanges
/// temperature only, so they must be empty.
const SPECIES_LISTS: [&str; 5] = [
    "partSpeciesNames",
    "partSpeciesFluxNames",
    "partSpeciesTransCoeffNames",
    "partSpeciesFluidNames",
    "DMolecular",
];

/// `scalarGeneralExchange` (CFDEM-PUBLIC, cfdemSolverPisoSTM), its temperature part: the
/// explicit heat flux (`partHeatFluxName`) with λ and Pr given (`lambda`, `Prandtl`), Nu of
/// Deen et al. or, with `useLiMason true`, Li & Mason with Pr^⅓, Re on the superficial slip;
/// the fluid's volumetric heat capacity is `generalManualProps/cpVolumetric` of
/// `constant/scalarTransportProperties` and ρ the case's (so c_p = cpVolumetric/ρ);
/// `maxSource` bounds the source in W/m³. Species (non-empty species lists, Eulerian fields
/// other than T), the implicit strategy (`partHeatTransCoeffName`/`partHeatFluidName`), the
/// general correlation and the corrected voidage are refused.
pub(super) fn scalar_general_exchange(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    let at = |key: &str| format!("{dict}/{key}");
    r.check_props(props, dict, &GENERAL_EXCHANGE_KEYS)?;
    for key in ["tempFieldName", "partTempName", "partHeatFluxName"] {
        // CFDEM requires the first two; without a flux name its explicit strategy is off
        r.word(props, key, &at(key))?;
    }
    standard_names(r, props, dict, &la_eu_names()[..3])?;
    for key in ["partHeatTransCoeffName", "partHeatFluidName"] {
        if r.opt_word(props, key, &at(key))?
            .is_some_and(|w| w != "none")
        {
            return Err(r.err(
                &at(key),
                "the implicit strategy (transfer coefficient and fluid value to the DEM) is not \
                 supported; foamgrain hands the explicit flux `partHeatFluxName` over",
            ));
        }
    }
    for key in SPECIES_LISTS {
        if !r.word_list_at(props, key, &at(key))?.is_empty() {
            return Err(r.err(
                &at(key),
                "species exchange is not implemented; foamgrain's scalarGeneralExchange couples \
                 temperature only (give empty lists `( )`)",
            ));
        }
    }
    for key in ["useGeneralCorrelation", "useCorrectedVoidage"] {
        if r.opt_switch(props, key, &at(key))? == Some(true) {
            return Err(r.err(&at(key), "`true` is not supported"));
        }
    }
    let lambda = positive(r, props, dict, "lambda", "thermal conductivity λ, W/(m·K)")?;
    let pr = positive(r, props, dict, "Prandtl", "Prandtl number")?;
    let nusselt = match r.opt_switch(props, "useLiMason", &at("useLiMason"))? {
        Some(true) => Nusselt::LiMasonCubeRoot,
        _ => Nusselt::Deen,
    };
    let rho_cp = scalar_transport_heat(r.file)?;
    let case = r
        .file
        .parent()
        .and_then(Path::parent)
        .unwrap_or(Path::new("."));
    let (rho, _) = super::read_transport(case)?;
    let heat = HeatSettings {
        model: HeatModel::ScalarGeneralExchange,
        nusselt,
        reynolds: ReynoldsVelocity::Superficial,
        voidage_floor: 0.0,
        nusselt_scale: 1.0,
        lambda,
        cp: rho_cp / rho,
        prandtl: Some(pr),
        max_source: max_source(r, props, dict)?.map(MaxSource::WattPerCubicMetre),
        interpolation: r.interpolation(props, dict)?,
    };
    set(r, g, s, heat)
}

/// `generalManualProps/cpVolumetric` (J/(m³·K), > 0) of the `scalarTransportProperties` next
/// to `coupling_properties`, whose `eulerianFields` must be `( T )`.
fn scalar_transport_heat(coupling_properties: &Path) -> Result<f64, CoupleError> {
    let file = coupling_properties.with_file_name("scalarTransportProperties");
    let top = foam::parse_file(&file)?.body;
    let r = Reader::new(&file);
    let model = r.word(&top, "scalarTransportModel", "scalarTransportModel")?;
    if model != "generalManual" {
        return Err(r.err(
            "scalarTransportModel",
            format!("`{model}` is not supported; foamgrain reads generalManual's temperature"),
        ));
    }
    let d = match top.get("generalManualProps") {
        Some(foam::Value::Dict(d)) => d,
        _ => return Err(r.err("generalManualProps", "missing or not a dictionary")),
    };
    let fields = r.word_list_at(d, "eulerianFields", "generalManualProps/eulerianFields")?;
    if fields != [TEMPERATURE_FIELD] {
        return Err(r.err(
            "generalManualProps/eulerianFields",
            format!(
                "({}): foamgrain transports the temperature `T` only (species are not \
                 implemented)",
                fields.join(" ")
            ),
        ));
    }
    if d.contains("cpVolumetricFieldName") {
        return Err(r.err(
            "generalManualProps/cpVolumetricFieldName",
            "a heat capacity field is not supported; give the constant `cpVolumetric`",
        ));
    }
    let key = "generalManualProps/cpVolumetric";
    if !d.contains("cpVolumetric") {
        return Err(r.err(
            key,
            "missing: the fluid's volumetric heat capacity ρ c_p, J/(m³·K)",
        ));
    }
    let x = r.number(d, "cpVolumetric", key)?;
    match x > 0.0 {
        true => Ok(x),
        false => Err(r.err(key, format!("{x} is not > 0"))),
    }
}
