//! CFDEM-PFM's `thermCondModel`s, the fluid's conduction in a bed ([`BedConductivity`]; the
//! rows of [`super::registry::THERM_COND`]). The fluid's temperature equation applies them
//! (the native one: `fv::temperature::conduction`, with A = k_s/λ, λ the heat model's fluid
//! conductivity); grainPisoFoam's T equation has no per-cell conductivity, so the runner
//! refuses them with that fluid.
//!
//! | model | Props keys |
//! |---|---|
//! | `SyamlalThermCond` | `voidfractionFieldName` (standard) |
//! | `ZehnerSchluenderThermCond` | `thermalConductivities (k_s)` (W/(m·K), required, one type: several types need the particles' types averaged per cell, refused), `partKsFieldName` (`partKs`), `voidfractionFieldName` |

use super::{Built, Given, Reader, Setup};
use foam::Dict;

/// A `thermCondModel` and its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BedConductivity {
    /// `SyamlalThermCond`: k_bed = (1 − √(1 − ε)) k_f (Syamlal & Gidaspow 1985).
    Syamlal,
    /// `ZehnerSchluenderThermCond`: Zehner & Schlünder's (1970) stagnant bed conductivity.
    ZehnerSchluender {
        /// The particles' thermal conductivity k_s, W/(m·K).
        ks: f64,
    },
}

impl BedConductivity {
    /// The CFDEM-PFM name.
    pub fn name(self) -> &'static str {
        match self {
            BedConductivity::Syamlal => "SyamlalThermCond",
            BedConductivity::ZehnerSchluender { .. } => "ZehnerSchluenderThermCond",
        }
    }
}

/// The model's setting into `s`.
fn set(s: &mut Setup, model: BedConductivity) -> Built {
    s.bed = Some(model);
    Ok(())
}

/// `SyamlalThermCond` (CFDEM-PFM): no parameters.
pub(super) fn syamlal(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &[])?;
    set(s, BedConductivity::Syamlal)
}

/// `ZehnerSchluenderThermCond` (CFDEM-PFM): `thermalConductivities (k_s)`.
pub(super) fn zehner_schluender(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &["thermalConductivities", "partKsFieldName"])?;
    if let Some(name) = r.opt_word(props, "partKsFieldName", &format!("{dict}/partKsFieldName"))? {
        if name != "partKs" {
            return Err(r.err(
                &format!("{dict}/partKsFieldName"),
                format!("foamgrain names the field `partKs`, not `{name}`"),
            ));
        }
    }
    let ks = conductivities(r, props, dict)?;
    set(s, BedConductivity::ZehnerSchluender { ks })
}

/// The one k_s (> 0, W/(m·K)) of `thermalConductivities`.
fn conductivities(r: &Reader, props: &Dict, dict: &str) -> Result<f64, super::CoupleError> {
    let path = format!("{dict}/thermalConductivities");
    let listed = match props.stream("thermalConductivities") {
        Ok([item]) | Ok([foam::Item::Label(_), item]) => item.as_f64_list(),
        Err(_) => {
            return Err(r.err(
                &path,
                "missing: the particles' thermal conductivity k_s, W/(m·K) (PFM: `provide \
                 list of thermal conductivities`)",
            ))
        }
        _ => None,
    };
    match listed.as_deref() {
        Some([ks]) if ks.is_finite() && *ks > 0.0 => Ok(*ks),
        Some([ks]) => Err(r.err(&path, format!("{ks} is not a positive conductivity"))),
        Some(list) if list.len() > 1 => Err(r.err(
            &path,
            format!(
                "{} particle types: per-type conductivities (averaged per cell from the \
                 particles' types) are not supported; give one k_s",
                list.len()
            ),
        )),
        _ => Err(r.err(
            &path,
            "expected a list of conductivities `( k_s )`, W/(m·K)",
        )),
    }
}

/// `wallHeatTransferYagi` (CFDEM-PFM `energyModels`): the walls' heat into the fluid
/// ([`crate::wall_heat`]); the faces are read with the start time's fields
/// ([`crate::wall_heat::WallHeat::read`]), λ and c_p are the heat model's.
#[derive(Clone, Debug, PartialEq)]
pub struct WallHeatSettings {
    /// `wallTempName`: the wall temperature field of the start time.
    pub wall_temp_name: String,
    /// `voidfractionMax`: ε above which the wall transfers nothing.
    pub eps_max: f64,
    /// `maxSource`, W/m³, if given.
    pub max_source: Option<f64>,
}

/// `wallHeatTransferYagiProps` keys (PFM's constructor).
const YAGI_KEYS: [&str; 8] = [
    "verbose",
    "implicit",
    "QWallFluidName",
    "QWallFluidCoeffName",
    "wallTempName",
    "tempFieldName",
    "voidfractionMax",
    "maxSource",
];

/// `wallHeatTransferYagi` (CFDEM-PFM): `wallTempName` and `voidfractionMax` required,
/// `implicit false` required (PFM's default is implicit), `maxSource` (W/m³, > 0).
pub(super) fn wall_heat_transfer_yagi(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    let at = |key: &str| format!("{dict}/{key}");
    r.check_props(props, dict, &YAGI_KEYS)?;
    if r.opt_switch(props, "implicit", &at("implicit"))? != Some(false) {
        return Err(r.err(
            &at("implicit"),
            "wallHeatTransferYagi is implicit unless `implicit false;` (PFM's default is \
             true); foamgrain hands the fluid an explicit source (the wall heat from T at the \
             coupling time, held over the interval): set `implicit false;`",
        ));
    }
    if let Some(t) = r.opt_word(props, "tempFieldName", &at("tempFieldName"))? {
        if t != super::heat::TEMPERATURE_FIELD {
            return Err(r.err(
                &at("tempFieldName"),
                format!("foamgrain heats `T`, not `{t}`"),
            ));
        }
    }
    let wall_temp_name = r
        .word(props, "wallTempName", &at("wallTempName"))?
        .to_string();
    let eps_max = r.number(props, "voidfractionMax", &at("voidfractionMax"))?;
    let max_source = super::heat::max_source(r, props, dict)?;
    if s.wall.is_some() {
        return Err(r.err(g.key, "`wallHeatTransferYagi` twice"));
    }
    s.wall = Some(WallHeatSettings {
        wall_temp_name,
        eps_max,
        max_source,
    });
    Ok(())
}

/// `heatTransferInterGrain` (CFDEM-PFM `energyModels`): the particles' continuum conduction
/// ([`crate::inter_grain`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterGrainSettings {
    /// The particles' conductivity k_s, W/(m·K) (`thermalConductivities`, one type).
    pub ks: f64,
    /// `kMax`, W/(m·K), if given (> 0).
    pub k_max: Option<f64>,
}

/// `heatTransferInterGrainProps` keys (PFM's constructor).
const INTER_GRAIN_KEYS: [&str; 12] = [
    "verbose",
    "implicit",
    "calcTotalHeatFlux",
    "radiativeHeatTransfer",
    "QPartPartName",
    "partHeatFluxName",
    "prescribedVoidfractionFieldName",
    "thermalConductivities",
    "thermalCapacities",
    "thermalEmissivities",
    "coarseGrainingFactors",
    "kMax",
];

/// `heatTransferInterGrain` (CFDEM-PFM): `thermalConductivities (k_s)` required (one type),
/// `kMax`; the implicit particle-temperature solve, radiation and coarse graining refused.
pub(super) fn heat_transfer_inter_grain(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    let at = |key: &str| format!("{dict}/{key}");
    r.check_props(props, dict, &INTER_GRAIN_KEYS)?;
    for (key, why) in [
        (
            "implicit",
            "the implicit particle-temperature solve is not implemented",
        ),
        (
            "radiativeHeatTransfer",
            "radiation between particles is not implemented",
        ),
    ] {
        if r.opt_switch(props, key, &at(key))? == Some(true) {
            return Err(r.err(&at(key), format!("`true` is not supported: {why}")));
        }
    }
    for key in ["thermalEmissivities", "coarseGrainingFactors"] {
        if props.contains(key) {
            return Err(r.err(
                &at(key),
                "not supported (radiation and coarse graining of heatTransferInterGrain)",
            ));
        }
    }
    if let Some(name) = r.opt_word(
        props,
        "prescribedVoidfractionFieldName",
        &at("prescribedVoidfractionFieldName"),
    )? {
        if name != "voidfraction" {
            return Err(r.err(
                &at("prescribedVoidfractionFieldName"),
                format!("foamgrain uses the coupling's `voidfraction`, not `{name}`"),
            ));
        }
    }
    let ks = conductivities(r, props, dict)?;
    let k_max = match props.contains("kMax") {
        true => match r.number(props, "kMax", &at("kMax"))? {
            x if x > 0.0 => Some(x),
            // PFM: kMax ≤ 0 is no cap
            _ => None,
        },
        false => None,
    };
    if s.inter_grain.is_some() {
        return Err(r.err(g.key, "`heatTransferInterGrain` twice"));
    }
    s.inter_grain = Some(InterGrainSettings { ks, k_max });
    Ok(())
}
