//! Writing a coupling step's cell fields into an OpenFOAM time directory, under CFDEM's names:
//! `voidfraction` (ε), `Ksl` (kg/(m³·s)), `Us` (m/s) and `f` (N/m³), ADR 0004.

use crate::error::CoupleError;
use crate::step::CouplingStep;
use foam::{default_boundary, FieldValues, Format, PolyMesh, VolField};
use std::path::Path;

/// Writes ε, Ksl, Us and f of `step` into the time directory `dir` (created if needed),
/// whose name `time` becomes each file's `location`. Boundaries are `zeroGradient`, except
/// that `voidfraction` keeps the boundaryField of `voidfraction_template` when given (the
/// start time's file, as OpenFOAM writes a field with its boundary conditions: a fluid
/// started from this time reads its boundary voidage there). Each file is written atomically.
pub fn write_fields(
    dir: &Path,
    time: &str,
    mesh: &PolyMesh,
    step: &CouplingStep,
    format: Format,
    voidfraction_template: Option<&VolField>,
) -> Result<(), CoupleError> {
    std::fs::create_dir_all(dir).map_err(|source| CoupleError::Io {
        path: dir.to_owned(),
        source,
    })?;
    for (name, dims, values) in fields_of(step) {
        match voidfraction_template {
            Some(template) if name == "voidfraction" => {
                let mut field = template.clone();
                field
                    .set_internal(values)
                    .map_err(|m| CoupleError::Parameter(format!("voidfraction: {m}")))?;
                field.write(&dir.join(name), format)?;
            }
            _ => write_cell_field(dir, time, mesh, name, dims, values, format)?,
        }
    }
    Ok(())
}

/// Writes the fields of [`write_fields`] (with `zeroGradient` boundaries) into the time
/// directory `time` of each piece of a decomposed case ([`foam::decomposed::pieces`]), each
/// piece's cells picked from the whole mesh's fields: the files `decomposePar` would make of
/// the whole case's.
pub fn write_fields_decomposed(
    pieces: &[foam::decomposed::Piece],
    time: &str,
    step: &CouplingStep,
    format: Format,
) -> Result<(), CoupleError> {
    for (name, dims, values) in fields_of(step) {
        for piece in pieces {
            let picked = match &values {
                FieldValues::Scalar(v) => FieldValues::Scalar(piece.pick(v)),
                FieldValues::Vector(v) => FieldValues::Vector(piece.pick(v)),
            };
            piece.write_cell_field(time, name, dims, picked, "zeroGradient", format)?;
        }
    }
    Ok(())
}

/// ε, Ksl, Us and f of `step` with their names and dimensions.
fn fields_of(step: &CouplingStep) -> [(&'static str, [i32; 7], FieldValues); 4] {
    [
        (
            "voidfraction",
            [0; 7],
            FieldValues::Scalar(step.voidage.epsilon.clone()),
        ),
        (
            "Ksl",
            [1, -3, -1, 0, 0, 0, 0],
            FieldValues::Scalar(step.exchange.ksl.clone()),
        ),
        (
            "Us",
            [0, 1, -1, 0, 0, 0, 0],
            FieldValues::Vector(mesh::v3::to_arrays(&step.exchange.us)),
        ),
        (
            "f",
            [1, -2, -2, 0, 0, 0, 0],
            FieldValues::Vector(mesh::v3::to_arrays(&step.exchange.f)),
        ),
    ]
}

/// Writes one cell field `name` (dimensions `dims`, OpenFOAM's 7 exponents) with
/// `zeroGradient` boundaries into the existing time directory `dir`, atomically.
pub fn write_cell_field(
    dir: &Path,
    time: &str,
    mesh: &PolyMesh,
    name: &str,
    dims: [i32; 7],
    values: FieldValues,
    format: Format,
) -> Result<(), CoupleError> {
    let field = VolField::new(
        name,
        time,
        dims,
        values,
        default_boundary(&mesh.boundary, "zeroGradient", None),
    );
    field.write(&dir.join(name), format)?;
    Ok(())
}

/// OpenFOAM's name of the time directory for `t` seconds ([`foam::case::time_name`]).
pub use foam::case::time_name;
