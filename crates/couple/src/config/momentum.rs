//! `momCoupleModels`: how the particles' reaction reaches the fluid ([`super::MomentumCoupling`]).
//! The names are the rows of [`super::registry::MOM_COUPLE`]; a constructor per acting model.

use super::registry::MOM_COUPLE;
use super::{Built, Given, Reader, Setup};
use crate::error::CoupleError;
use foam::Dict;

/// Reads the list `momCoupleModels` through [`MOM_COUPLE`].
pub(super) fn read(r: &mut Reader<'_>, top: &Dict, setup: &mut Setup) -> Result<(), CoupleError> {
    let key = MOM_COUPLE.key;
    for name in r.word_list(top, key)? {
        // every listed model's Props must be a dictionary, whatever the model's support
        r.props(top, &name)?;
        r.apply(
            &MOM_COUPLE,
            &Given {
                key,
                name: &name,
                top,
            },
            setup,
        )?;
    }
    Ok(())
}

/// `implicitCouple`: Ksl and Us go to the fluid; `KslLimit` (> 0) caps Ksl.
pub(super) fn implicit(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &["KslLimit", "verbose"])?;
    if props.contains("KslLimit") {
        let key = format!("{dict}/KslLimit");
        let limit = r.number(props, "KslLimit", &key)?;
        if limit.is_nan() || limit <= 0.0 {
            return Err(r.err(&key, format!("{limit} is not > 0")));
        }
        s.momentum.ksl_limit = Some(limit);
    }
    s.momentum.implicit = true;
    Ok(())
}

/// `explicitCouple`: f goes to the fluid.
pub(super) fn explicit(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &["verbose"])?;
    s.momentum.explicit = true;
    Ok(())
}
