//! One cell scalar of the native fluid read from a time directory — cell values, boundary
//! values, the conditions of [`super::scalar_bc`] and the file it came from — and written back
//! as OpenFOAM writes it: k, ε, νt of the k–ε model and the temperature fields
//! ([`crate::temperature`]).

use super::scalar_bc::{self, ScalarBc};
use crate::error::{FvError, Result};
use crate::geometry::FvGeometry;
use foam::{FieldValues, Item, Value, VolField};
use std::path::Path;

/// One cell scalar with its boundary values, conditions and the file it came from.
#[derive(Clone, Debug)]
pub(crate) struct ScalarField {
    /// Cell values.
    pub(crate) cells: Vec<f64>,
    /// Boundary-face values, one per boundary face.
    pub(crate) boundary: Vec<f64>,
    /// The condition of each patch.
    pub(crate) bcs: Vec<ScalarBc>,
    /// The file as read (its boundaryField is kept when writing).
    pub(crate) file: VolField,
}

impl ScalarField {
    /// Reads `dir/name` (a volScalarField, finite values) with the conditions `bcs` reads from
    /// it (given the path and the parsed file); start values of the boundary: prescribed
    /// ones, the file's `value` of inletOutlet/calculated/wall functions where it has one,
    /// else the owner's value (OpenFOAM's start-up).
    pub(crate) fn read(
        dir: &Path,
        name: &str,
        g: &FvGeometry,
        bcs: impl FnOnce(&Path, &VolField) -> Result<Vec<ScalarBc>>,
    ) -> Result<Self> {
        let path = dir.join(name);
        let file = VolField::read(&path)?;
        let cells = match file.internal(g.n_cells) {
            Ok(FieldValues::Scalar(v)) => v,
            Ok(FieldValues::Vector(_)) => {
                return Err(FvError::setting(
                    &path,
                    "class",
                    format!("{name} must be a volScalarField"),
                ))
            }
            Err(m) => return Err(FvError::setting(&path, "internalField", m)),
        };
        if let Some(c) = cells.iter().position(|v| !v.is_finite()) {
            return Err(FvError::setting(
                &path,
                "internalField",
                format!("cell {c}: not finite"),
            ));
        }
        let bcs = bcs(&path, &file)?;
        // Start values: prescribed ones, the file's `value` of inletOutlet/calculated/wall
        // functions where it has one, else the owner's value (OpenFOAM's start-up).
        let mut boundary: Vec<f64> = g.owner[g.n_internal..]
            .iter()
            .map(|&o| cells[o as usize])
            .collect();
        let bf = file.boundary();
        for (p, bc) in g.patches.iter().zip(&bcs) {
            let keeps_file_value = matches!(
                bc,
                ScalarBc::InletOutlet(_) | ScalarBc::Calculated | ScalarBc::NutkWallFunction(_)
            );
            if !keeps_file_value {
                continue;
            }
            let value = bf
                .dict(&p.name)
                .ok()
                .and_then(|d| d.stream("value").ok())
                .and_then(|s| patch_values(s, p.faces.len()));
            if let Some(v) = value {
                boundary[p.boundary_range(g.n_internal)].copy_from_slice(&v);
            }
        }
        let mut f = ScalarField {
            cells,
            boundary,
            bcs,
            file,
        };
        let zero_phi = vec![0.0; g.n_faces()];
        // Fixed values and zero gradients now (inletOutlet keeps its file value until the
        // first solve, as OpenFOAM's starts with valueFraction 0).
        let mut b = f.boundary.clone();
        scalar_bc::evaluate(g, &f.bcs, &f.cells, &zero_phi, &mut b);
        for (p, bc) in g.patches.iter().zip(&f.bcs) {
            if !matches!(bc, ScalarBc::InletOutlet(_)) {
                for i in p.boundary_range(g.n_internal) {
                    f.boundary[i] = b[i];
                }
            }
        }
        Ok(f)
    }

    /// The boundary values of the cell values under the conditions, with the face fluxes `phi`
    /// ([`scalar_bc::evaluate`]).
    pub(crate) fn evaluate(&mut self, g: &FvGeometry, phi: &[f64]) {
        scalar_bc::evaluate(g, &self.bcs, &self.cells, phi, &mut self.boundary);
    }

    /// Writes the field to `path` with the file's boundaryField, each non-constraint patch's
    /// `value` the current boundary values.
    pub(crate) fn write(&self, g: &FvGeometry, path: &Path, format: foam::Format) -> Result<()> {
        let mut f = self.file.clone();
        f.set_internal(FieldValues::Scalar(self.cells.clone()))
            .map_err(|m| FvError::Value {
                what: path.display().to_string(),
                msg: m,
            })?;
        if let Some(Value::Dict(bf)) = f.body.get_mut("boundaryField") {
            for p in g.patches.iter().filter(|p| !p.is_empty() && !p.is_cyclic()) {
                if let Some(Value::Dict(e)) = bf.get_mut(&p.name) {
                    let v = self.boundary[p.boundary_range(g.n_internal)].to_vec();
                    e.set(
                        "value",
                        Value::Stream(vec![
                            Item::Word("nonuniform".into()),
                            Item::Word("List<scalar>".into()),
                            Item::Scalars(v),
                        ]),
                    );
                }
            }
        }
        f.write(path, format)?;
        Ok(())
    }
}

/// `uniform X` or `nonuniform List<scalar> N(…)` with `n` values.
pub(crate) fn patch_values(items: &[Item], n: usize) -> Option<Vec<f64>> {
    match items.first().and_then(Item::as_word) {
        Some("uniform") => items.get(1).and_then(Item::as_f64).map(|v| vec![v; n]),
        Some("nonuniform") => items
            .get(2)
            .and_then(Item::as_f64_list)
            .filter(|v| v.len() == n),
        _ => None,
    }
}
