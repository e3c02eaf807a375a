//! `smoothingModel`: CFDEM-PFM's smoothing of the ε the fluid gets ([`crate::smoothing`]). The
//! names are the rows of [`super::registry::SMOOTHING`]; `constDiffSmoothing`,
//! `temporalSmoothing`, `constDiffAndTemporalSmoothing` and `localPSizeDiffSmoothing` (whose
//! source is not public: foamgrain's reading of it is in [`crate::smoothing`]) act.

use super::{Built, Given, Reader, Setup};
use crate::error::CoupleError;
use crate::smoothing::{SmoothingModel, SmoothingSettings};
use foam::Dict;

/// The number of `key` in `props` (the dictionary `dict`), required as PFM reads it.
fn required(
    r: &Reader,
    props: &Dict,
    dict: &str,
    key: &str,
    model: &str,
) -> Result<f64, CoupleError> {
    let path = format!("{dict}/{key}");
    match props.contains(key) {
        true => r.number(props, key, &path),
        false => Err(r.err(&path, format!("missing ({model} needs it)"))),
    }
}

/// Sets `model` if its settings are usable, else the error names the key at fault.
fn set(r: &Reader, dict: &str, model: SmoothingModel, s: &mut Setup) -> Built {
    match model.problem() {
        Some((key, why)) => Err(r.err(&format!("{dict}/{key}"), why)),
        None => {
            s.smoothing = Some(model);
            Ok(())
        }
    }
}

/// The keys of the spatial smoothing's Props every model with one reads (with `verbose`).
const SPATIAL_KEYS: [&str; 4] = ["lowerLimit", "upperLimit", "smoothingLength", "verbose"];

/// `lowerLimit`, `upperLimit` and `smoothingLength` of `props`.
fn spatial(
    r: &Reader,
    props: &Dict,
    dict: &str,
    model: &str,
) -> Result<SmoothingSettings, CoupleError> {
    Ok(SmoothingSettings {
        length: required(r, props, dict, "smoothingLength", model)?,
        lower: required(r, props, dict, "lowerLimit", model)?,
        upper: required(r, props, dict, "upperLimit", model)?,
    })
}

/// `constDiffSmoothingProps` ([`crate::smoothing`]): `smoothingLength` (m, required: PFM's
/// alternative, a `smoothingLengthField` read from the case, is not read), `lowerLimit` and
/// `upperLimit` (required, as PFM reads them); `smoothingLengthReference` (PFM's length for the
/// Us reference field, which foamgrain does not smooth) and `verbose` are accepted.
pub(super) fn const_diff(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    let known = [
        &SPATIAL_KEYS[..],
        &[
            "smoothingLengthReference",
            "smoothingLengthFieldName",
            "smoothingLengthReferenceFieldName",
        ],
    ]
    .concat();
    r.check_props(props, dict, &known)?;
    let settings = spatial(r, props, dict, "constDiffSmoothing")?;
    set(r, dict, SmoothingModel::ConstDiff(settings), s)
}

/// `temporalSmoothingProps`: `lowerLimit`, `upperLimit`, `gamma` (≥ 0) and `refField`
/// (required, as PFM reads them); the reference of the voidage's relaxation is the fluid's ε,
/// so `refField` must name it (`voidfraction`). `verbose` is accepted.
pub(super) fn temporal(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &["lowerLimit", "upperLimit", "refField", "gamma", "verbose"],
    )?;
    let model = "temporalSmoothing";
    let path = format!("{dict}/refField");
    if !props.contains("refField") {
        return Err(r.err(&path, format!("missing ({model} needs it)")));
    }
    let field = r.word(props, "refField", &path)?;
    if field != "voidfraction" {
        return Err(r.err(
            &path,
            format!(
                "`{field}`: the voidage is relaxed towards the fluid's voidage, refField \
                 voidfraction (foamgrain smooths no other field)"
            ),
        ));
    }
    let smoothing = SmoothingModel::Temporal {
        gamma: required(r, props, dict, "gamma", model)?,
        lower: required(r, props, dict, "lowerLimit", model)?,
        upper: required(r, props, dict, "upperLimit", model)?,
    };
    set(r, dict, smoothing, s)
}

/// `constDiffAndTemporalSmoothingProps`: `lowerLimit`, `upperLimit`, `smoothingLength` (m) and
/// `smoothingStrength` (γ ≥ 0), required as PFM reads them; `smoothingLengthReferenceField`
/// (the Us reference field's length, not smoothed here), `correctBoundary` (PFM applies it to
/// vector fields only) and `verbose` are accepted. PFM's optional `refField` (one combined
/// solve towards a named field instead of the relaxation from the last smoothed ε) is refused.
pub(super) fn const_diff_and_temporal(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    let known = [
        &SPATIAL_KEYS[..],
        &[
            "smoothingLengthReferenceField",
            "smoothingStrength",
            "correctBoundary",
            "refField",
        ],
    ]
    .concat();
    r.check_props(props, dict, &known)?;
    let model = "constDiffAndTemporalSmoothing";
    if props.contains("refField") {
        return Err(r.err(
            &format!("{dict}/refField"),
            "not supported: without it the voidage is relaxed from the last smoothed voidage, \
             as PFM does; remove the key",
        ));
    }
    if props.contains("correctBoundary") {
        let path = format!("{dict}/correctBoundary");
        r.switch(props, "correctBoundary", &path)?;
    }
    let gamma = required(r, props, dict, "smoothingStrength", model)?;
    let spatial = spatial(r, props, dict, model)?;
    set(
        r,
        dict,
        SmoothingModel::ConstDiffAndTemporal { spatial, gamma },
        s,
    )
}

/// `localPSizeDiffSmoothingProps` (the keys of CFDEM's ErgunTestMPI and PFM's tutorials):
/// `lowerLimit`, `upperLimit`, `dSmoothingLength` (m, the length where no particle is) and
/// `Csmoothing` (the length per particle diameter), all required; `verbose` is accepted. Its
/// source is not public: [`crate::smoothing`] says what foamgrain makes of it.
pub(super) fn local_p_size_diff(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "lowerLimit",
            "upperLimit",
            "dSmoothingLength",
            "Csmoothing",
            "verbose",
        ],
    )?;
    let model = "localPSizeDiffSmoothing";
    let spatial = SmoothingSettings {
        length: required(r, props, dict, "dSmoothingLength", model)?,
        lower: required(r, props, dict, "lowerLimit", model)?,
        upper: required(r, props, dict, "upperLimit", model)?,
    };
    let c = required(r, props, dict, "Csmoothing", model)?;
    let model = SmoothingModel::LocalPSizeDiff { spatial, c };
    match model.problem() {
        // the length's key here is dSmoothingLength
        Some(("smoothingLength", why)) => Err(r.err(&format!("{dict}/dSmoothingLength"), why)),
        _ => set(r, dict, model, s),
    }
}
