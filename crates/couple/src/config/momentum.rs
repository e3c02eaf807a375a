//! `momCoupleModels`: how the particles' reaction reaches the fluid ([`super::MomentumCoupling`]).
//! The names are the rows of [`super::registry::MOM_COUPLE`]; a constructor per acting model.

use super::registry::MOM_COUPLE;
use super::{Built, Given, MomentumCoupling, Reader, Setup};
use crate::error::CoupleError;
use crate::ksl::UsAveraging;
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

/// `implicitCouple`: Ksl and Us go to the fluid. Its Props: `KslForm` (`conserving`, the
/// default: foamgrain's Σ w β / V; `CFDEM`: CFDEM's |Σ F| / (V |U − Us|), [`crate::ksl`]),
/// `KslLimit` (> 0, kg/(m³ s): the cap of CFDEM's form, default 10¹⁰) and `minAlphaP` (in
/// [0, 1]: CFDEM's form gives Ksl = 0 where ε ≥ 1 − minAlphaP; default 10⁻¹⁵).
pub(super) fn implicit(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &["KslLimit", "KslForm", "minAlphaP", "verbose"],
    )?;
    if props.contains("KslLimit") {
        let key = format!("{dict}/KslLimit");
        let limit = r.number(props, "KslLimit", &key)?;
        if limit.is_nan() || limit <= 0.0 {
            return Err(r.err(&key, format!("{limit} is not > 0")));
        }
        s.momentum.ksl_limit = Some(limit);
    }
    if props.contains("minAlphaP") {
        let key = format!("{dict}/minAlphaP");
        let m = r.number(props, "minAlphaP", &key)?;
        if !(0.0..=1.0).contains(&m) {
            return Err(r.err(&key, format!("{m} is not in [0, 1]")));
        }
        s.momentum.min_alpha_p = Some(m);
    }
    if props.contains("KslForm") {
        let key = format!("{dict}/KslForm");
        s.momentum.cfdem_ksl = match r.word(props, "KslForm", &key)? {
            "conserving" => false,
            "CFDEM" => true,
            w => {
                return Err(r.err(
                    &key,
                    format!("unknown Ksl form `{w}`; valid: conserving, CFDEM"),
                ))
            }
        };
    }
    s.momentum.implicit = true;
    Ok(())
}

/// `averagingModel dilute`: CFDEM's form takes Us of a cell as the last particle's velocity
/// ([`crate::ksl::UsAveraging::Dilute`]).
pub(super) fn dilute(_: &mut Reader, _: &Given, s: &mut Setup) -> Built {
    s.momentum.averaging = UsAveraging::Dilute;
    Ok(())
}

/// A warning when `averagingModel dilute` is given without CFDEM's Ksl form: the conserving
/// form's Us is always the β-weighted average.
pub(super) fn check_averaging(r: &mut Reader, m: &MomentumCoupling) {
    if m.averaging == UsAveraging::Dilute && !m.cfdem_ksl {
        r.warn(
            "averagingModel dilute: acts with `implicitCoupleProps { KslForm CFDEM; }` only; \
             foamgrain's conserving Ksl keeps Us the β-weighted average of the particle \
             velocities (dense)"
                .into(),
        );
    }
}

/// `explicitCouple`: f goes to the fluid.
pub(super) fn explicit(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &["verbose"])?;
    s.momentum.explicit = true;
    Ok(())
}
