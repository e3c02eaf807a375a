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
