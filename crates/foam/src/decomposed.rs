//! A decomposed case's pieces (`processorN/`, as `decomposePar` writes them): which cell of
//! the whole mesh each local cell is (`constant/polyMesh/cellProcAddressing`), so that a cell
//! field computed on the whole mesh is written into every piece, equal to what `decomposePar`
//! would have written from the reconstructed field.

use crate::case::Case;
use crate::dict::{Item, Value};
use crate::error::{FoamError, Result};
use crate::field::{default_boundary, FieldValues, VolField};
use crate::parser::Format;
use crate::poly_mesh::{Label, PolyMesh};
use std::path::{Path, PathBuf};

/// One `processorN` piece.
#[derive(Clone, Debug)]
pub struct Piece {
    /// N.
    pub rank: usize,
    /// The piece as a case (its root is `processorN/`).
    pub case: Case,
    /// Its mesh (patches include the `processor` patches to its neighbours).
    pub mesh: PolyMesh,
    /// The whole mesh's cell of each local cell.
    pub cells: Vec<Label>,
}

/// The pieces of `case` (empty for an undecomposed case), each checked against the whole mesh
/// of `n_cells` cells: every address in range, and the pieces' cells together covering each
/// whole cell exactly once. Errors name the piece's file.
pub fn pieces(case: &Case, n_cells: usize) -> Result<Vec<Piece>> {
    let mut out = Vec::new();
    let mut seen = vec![0u32; n_cells];
    for (rank, sub) in case.processors()? {
        let mesh = sub.read_mesh()?;
        let dir = sub.mesh_dir();
        let (cells, _) = crate::poly_mesh_io::read_label_list(&dir, "cellProcAddressing")?;
        let file = dir.join("cellProcAddressing");
        if cells.len() != mesh.n_cells {
            return Err(invalid(
                &file,
                format!("{} addresses for {} cells", cells.len(), mesh.n_cells),
            ));
        }
        for &c in &cells {
            let Some(s) = seen.get_mut(c as usize) else {
                return Err(invalid(
                    &file,
                    format!("cell {c} is not a cell of the whole mesh ({n_cells} cells)"),
                ));
            };
            *s += 1;
        }
        out.push(Piece {
            rank,
            case: sub,
            mesh,
            cells,
        });
    }
    if !out.is_empty() {
        if let Some(c) = seen.iter().position(|&s| s != 1) {
            return Err(invalid(
                case.root(),
                format!(
                    "the processor pieces hold cell {c} of the whole mesh {} times (a \
                     decomposition of another mesh? run decomposePar again)",
                    seen[c]
                ),
            ));
        }
    }
    Ok(out)
}

fn invalid(path: &Path, message: String) -> FoamError {
    FoamError::invalid(PathBuf::from(path), message)
}

impl Piece {
    /// The piece's values of a whole-mesh cell field (one value per cell: a scalar, a vector).
    pub fn pick<T: Copy>(&self, whole: &[T]) -> Vec<T> {
        self.cells.iter().map(|&c| whole[c as usize]).collect()
    }

    /// Writes the cell field `name` (dimensions `dims`) into the piece's time directory
    /// `time` (created if needed), with `default_type` boundaries on ordinary patches and, on
    /// its `processor` patches, the values of the cells next to them (what a zero-gradient
    /// field has there; OpenFOAM replaces them with the neighbours' on its first exchange).
    pub fn write_cell_field(
        &self,
        time: &str,
        name: &str,
        dims: [i32; 7],
        values: FieldValues,
        default_type: &str,
        format: Format,
    ) -> Result<PathBuf> {
        let dir = self.case.time_path(time);
        std::fs::create_dir_all(&dir).map_err(|e| FoamError::io(&dir, e))?;
        let mut boundary = default_boundary(&self.mesh.boundary, default_type, None);
        for p in &self.mesh.boundary {
            if !p.patch_type.starts_with("processor") {
                continue;
            }
            let owners = &self.mesh.owner[p.start_face..p.start_face + p.n_faces];
            let item = match &values {
                FieldValues::Scalar(v) => {
                    Item::Scalars(owners.iter().map(|&c| v[c as usize]).collect())
                }
                FieldValues::Vector(v) => {
                    Item::Vectors(owners.iter().map(|&c| v[c as usize]).collect())
                }
            };
            if let Some(Value::Dict(entry)) = boundary.get_mut(&p.name) {
                entry.set(
                    "value",
                    Value::Stream(vec![Item::Word("nonuniform".into()), item]),
                );
            }
        }
        let field = VolField::new(name, time, dims, values, boundary);
        let path = dir.join(name);
        field.write(&path, format)?;
        Ok(path)
    }
}
