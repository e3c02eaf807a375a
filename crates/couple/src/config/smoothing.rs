//! `smoothingModel`: CFDEM-PFM's smoothing of the ε the fluid gets ([`crate::smoothing`]). The
//! names are the rows of [`super::registry::SMOOTHING`]; `constDiffSmoothing` is the one that
//! acts.

use super::{Built, Given, Reader, Setup};
use crate::error::CoupleError;

/// `constDiffSmoothingProps` ([`crate::smoothing`]): `smoothingLength` (m, required: PFM's
/// alternative, a `smoothingLengthField` read from the case, is not read), `lowerLimit` and
/// `upperLimit` (required, as PFM reads them); `smoothingLengthReference` (PFM's length for the
/// Us reference field, which foamgrain does not smooth) and `verbose` are accepted.
pub(super) fn const_diff(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "lowerLimit",
            "upperLimit",
            "smoothingLength",
            "smoothingLengthReference",
            "smoothingLengthFieldName",
            "smoothingLengthReferenceFieldName",
            "verbose",
        ],
    )?;
    let number = |key: &str| -> Result<f64, CoupleError> {
        let path = format!("{dict}/{key}");
        match props.contains(key) {
            true => r.number(props, key, &path),
            false => Err(r.err(&path, "missing (constDiffSmoothing needs it)")),
        }
    };
    let settings = crate::smoothing::SmoothingSettings {
        length: number("smoothingLength")?,
        lower: number("lowerLimit")?,
        upper: number("upperLimit")?,
    };
    match settings.problem() {
        Some((key, why)) => Err(r.err(&format!("{dict}/{key}"), why)),
        None => {
            s.smoothing = Some(settings);
            Ok(())
        }
    }
}
