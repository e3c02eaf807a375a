//! The fluid's material properties and gravity, where CFDEM cases keep them.

use super::Reader;
use crate::error::CoupleError;
use foam::{Dict, Item};
use mesh::v3::V3;
use std::path::Path;

/// Fluid density ρ and kinematic viscosity ν of the OpenFOAM case `case`, in the case's units
/// (kg/m³ and m²/s for SI cases). ν is the last number of `nu` in
/// `constant/transportProperties` (plain `nu 1e-5;`, `nu [0 2 -1 0 0 0 0] 1e-5;` or the old
/// `nu nu [0 2 -1 0 0 0 0] 1e-5;`). ρ is that file's `rho` entry in the same forms; when the
/// file has none, it is the field `0/rho`, CFDEM's convention, which must be uniform (an
/// incompressible solver has one density). Both must be > 0.
pub fn read_transport(case: &Path) -> Result<(f64, f64), CoupleError> {
    let file = case.join("constant").join("transportProperties");
    let d = foam::parse_file(&file)?.body;
    let r = Reader::new(&file);
    let nu = positive(&r, &d, "nu")?;
    let rho = match d.contains("rho") {
        true => positive(&r, &d, "rho")?,
        false => {
            let field = case.join("0").join("rho");
            if !field.is_file() {
                return Err(r.err(
                    "rho",
                    format!(
                        "missing: give the fluid density as `rho` here or as the field {} \
                         (CFDEM's convention)",
                        field.display()
                    ),
                ));
            }
            uniform_density(&field)?
        }
    };
    Ok((rho, nu))
}

fn positive(r: &Reader<'_>, d: &Dict, key: &str) -> Result<f64, CoupleError> {
    let s = d.stream(key).map_err(|e| r.err(key, e.to_string()))?;
    match s.last().and_then(Item::as_f64) {
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(r.err(key, "expected a positive number")),
    }
}

/// The one value of the volScalarField `file` (`internalField uniform ρ;`, or a non-uniform
/// list whose values are all equal).
fn uniform_density(file: &Path) -> Result<f64, CoupleError> {
    let d = foam::parse_file(file)?.body;
    let r = Reader::new(file);
    let s = d
        .stream("internalField")
        .map_err(|e| r.err("internalField", e.to_string()))?;
    let value =
        match s {
            [Item::Word(u), x] if u == "uniform" => x.as_f64(),
            [Item::Word(u), rest @ ..] if u == "nonuniform" => {
                let values = rest.last().and_then(Item::as_f64_list).unwrap_or_default();
                match values.first() {
                    Some(&first) if values.iter().all(|&x| x == first) => Some(first),
                    Some(_) => return Err(r.err(
                        "internalField",
                        "the density varies between cells; the incompressible solvers need one \
                         uniform density",
                    )),
                    None => None,
                }
            }
            _ => None,
        };
    match value {
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(r.err(
            "internalField",
            "expected `uniform ρ` with a positive density",
        )),
    }
}

/// Gravity g (m/s²) from `constant/g` (`value (gx gy gz);`), or `None` without the file.
pub fn read_gravity(case: &Path) -> Result<Option<V3>, CoupleError> {
    let file = case.join("constant").join("g");
    if !file.exists() {
        return Ok(None);
    }
    let d = foam::parse_file(&file)?.body;
    let r = Reader::new(&file);
    d.vector("value")
        .map(|g| Some(V3::from(g)))
        .map_err(|e| r.err("value", e.to_string()))
}
