//! `voidFractionModel`: the voidage method ([`voidage::Method`]) and its Props. The names are
//! the rows of [`super::registry::VOIDAGE`] (spellings from [`voidage::Method::names`]); one
//! constructor per method, all reading the same keys ([`props`]).

use super::registry::VOIDAGE;
use super::{Built, Given, Reader, Setup, VoidageSettings};
use crate::error::CoupleError;
use foam::Dict;
use voidage::Method;

/// Reads `voidFractionModel` (required) through [`VOIDAGE`].
pub(super) fn read(
    r: &mut Reader<'_>,
    top: &Dict,
    setup: &mut Setup,
) -> Result<VoidageSettings, CoupleError> {
    let key = VOIDAGE.key;
    let name = r.word(top, key, key)?;
    r.apply(&VOIDAGE, &Given { key, name, top }, setup)?;
    setup
        .voidage
        .ok_or_else(|| r.err(key, format!("`{name}` selects no voidage method")))
}

/// `centre`.
pub(super) fn centre(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    props(r, g, s, Method::Centre)
}

/// `divided`.
pub(super) fn divided(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    props(r, g, s, Method::Divided)
}

/// `trilinear`.
pub(super) fn trilinear(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    props(r, g, s, Method::Trilinear)
}

/// `cube` (foamgrain's).
pub(super) fn cube(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    props(r, g, s, Method::Cube)
}

/// `correctedCube` (foamgrain's).
pub(super) fn corrected_cube(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    props(r, g, s, Method::CorrectedCube)
}

/// `exact` (foamgrain's).
pub(super) fn exact(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    props(r, g, s, Method::Exact)
}

/// `bigParticle` (CFDEM's): the common Props and CFDEM's `maxCellsPerParticle` (required, as
/// CFDEM reads it; a positive whole number, which bounds nothing here:
/// `voidage::Method::BigParticle`).
pub(super) fn big_particle(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    let path = format!("{dict}/maxCellsPerParticle");
    if !props.contains("maxCellsPerParticle") {
        return Err(r.err(&path, "missing (bigParticle needs it)"));
    }
    let n = r.number(props, "maxCellsPerParticle", &path)?;
    if !(n >= 1.0 && n.fract() == 0.0) {
        return Err(r.err(&path, format!("{n} is not a positive whole number")));
    }
    props_with(r, g, s, Method::BigParticle, &["maxCellsPerParticle"])
}

/// `GaussVoidFraction` (CFDEM's, which stops on it): the common Props and CFDEM's
/// `maxCellsPerParticle` (read, bounds nothing). The weights are normalised
/// (`voidage::Method::Gauss`), unlike CFDEM's, which add up to about 8 times the particle
/// volume: one warning line says so.
pub(super) fn gauss(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    if props.contains("maxCellsPerParticle") {
        let path = format!("{dict}/maxCellsPerParticle");
        let n = r.number(props, "maxCellsPerParticle", &path)?;
        if !(n >= 1.0 && n.fract() == 0.0) {
            return Err(r.err(&path, format!("{n} is not a positive whole number")));
        }
    }
    props_with(r, g, s, Method::Gauss, &["maxCellsPerParticle"])?;
    r.warn(GAUSS_WARNING.to_owned());
    Ok(())
}

/// The warning of `GaussVoidFraction`.
pub const GAUSS_WARNING: &str = "voidFractionModel GaussVoidFraction: foamgrain normalises the \
    Gaussian weights e^(-d^2/(2 r^2)) V_cell over the cells within 3 r so that each particle's \
    volume is conserved exactly; CFDEM's code does not normalise them (they add up to about 8 \
    times the particle volume, and CFDEM stops on this model)";

/// The Props every voidage method reads: `alphaMin` (the ε floor, in [0, 1)), and CFDEM's
/// `scaleUpVol`, `weight`, `porosity` (only 1) and `verbose`.
fn props(
    r: &mut Reader<'_>,
    g: &Given<'_>,
    s: &mut Setup,
    method: Method,
) -> Result<(), CoupleError> {
    props_with(r, g, s, method, &[])
}

/// [`props`] accepting also the keys `extra` (read by the method's constructor).
fn props_with(
    r: &mut Reader<'_>,
    g: &Given<'_>,
    s: &mut Setup,
    method: Method,
    extra: &[&str],
) -> Result<(), CoupleError> {
    let (props, dict) = &g.props(r)?;
    let mut known = vec!["alphaMin", "scaleUpVol", "weight", "porosity", "verbose"];
    known.extend_from_slice(extra);
    r.check_props(props, dict, &known)?;
    let alpha_min = match props.contains("alphaMin") {
        true => {
            let key = format!("{dict}/alphaMin");
            let a = r.number(props, "alphaMin", &key)?;
            if !(0.0..1.0).contains(&a) {
                return Err(r.err(&key, format!("{a} is not in [0, 1)")));
            }
            Some(a)
        }
        // CFDEM's own models default to alphaMin 0.1 (every voidFractionModel of
        // CFDEMcoupling-PUBLIC reads it with that default); foamgrain's cube, correctedCube and
        // exact have no floor unless one is given
        false => method.cfdem_name().is_some().then_some(0.1),
    };
    for key in ["scaleUpVol", "weight", "porosity"] {
        if props.contains(key) {
            let path = format!("{dict}/{key}");
            let x = r.number(props, key, &path)?;
            if x != 1.0 {
                return Err(r.err(
                    &path,
                    format!("{x} is not supported (only 1: particle volumes are not scaled)"),
                ));
            }
        }
    }
    s.voidage = Some(VoidageSettings { method, alpha_min });
    Ok(())
}
