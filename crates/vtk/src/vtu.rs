//! A polyMesh with cell (and point) fields as a VTK UnstructuredGrid (`.vtu`).

use std::io::Write as _;
use std::path::Path;

use foam::PolyMesh;

use crate::array::write_array;
use crate::xml;
use crate::{DataArray, Encoding, VtkCells, VtkError};
use atomic_write::write_atomically;

/// Writes `mesh` with cell and point data as a binary UnstructuredGrid. See [`write_vtu_with`].
pub fn write_vtu(
    path: impl AsRef<Path>,
    mesh: &PolyMesh,
    cell_data: &[DataArray<'_>],
    point_data: &[DataArray<'_>],
) -> Result<(), VtkError> {
    write_vtu_with(path, mesh, cell_data, point_data, Encoding::Binary)
}

/// Writes `mesh` as an UnstructuredGrid: hexahedra, tetrahedra and pyramids as VTK's own cell
/// types, every other cell as `VTK_POLYHEDRON` (see [`VtkCells::from_poly_mesh`]).
/// `cell_data` needs one tuple per cell, `point_data` one per mesh point. The file is replaced
/// atomically.
///
/// To write many time steps of one mesh, convert once with [`VtkCells::from_poly_mesh`] and
/// call [`write_vtu_cells`].
pub fn write_vtu_with(
    path: impl AsRef<Path>,
    mesh: &PolyMesh,
    cell_data: &[DataArray<'_>],
    point_data: &[DataArray<'_>],
    encoding: Encoding,
) -> Result<(), VtkError> {
    let path = path.as_ref();
    // Cheap length checks first, before converting the cells.
    xml::check_arrays(path, cell_data, "cell", mesh.n_cells)?;
    xml::check_arrays(path, point_data, "point", mesh.n_points())?;
    let cells = VtkCells::from_poly_mesh(mesh).map_err(|source| VtkError::Mesh {
        path: path.to_path_buf(),
        source,
    })?;
    write_vtu_cells(path, &mesh.points, &cells, cell_data, point_data, encoding)
}

/// Writes an UnstructuredGrid from points and already converted cells.
///
/// Errors: array lengths that differ from the number of cells/points, cell arrays of
/// inconsistent lengths or point ids out of range ([`VtkError::Invalid`]), I/O failures.
pub fn write_vtu_cells(
    path: impl AsRef<Path>,
    points: &[[f64; 3]],
    cells: &VtkCells,
    cell_data: &[DataArray<'_>],
    point_data: &[DataArray<'_>],
    encoding: Encoding,
) -> Result<(), VtkError> {
    let path = path.as_ref();
    let (np, nc) = (points.len(), cells.len());
    check_cells(path, cells, np)?;
    xml::check_arrays(path, cell_data, "cell", nc)?;
    xml::check_arrays(path, point_data, "point", np)?;
    write_atomically(path, |w| {
        xml::open(w, "UnstructuredGrid")?;
        writeln!(
            w,
            "    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">"
        )?;
        xml::attributes(w, "PointData", point_data, encoding)?;
        xml::attributes(w, "CellData", cell_data, encoding)?;
        writeln!(w, "      <Points>")?;
        write_array(w, "Points", points.as_flattened(), 3, encoding)?;
        writeln!(w, "      </Points>\n      <Cells>")?;
        write_array(w, "connectivity", &cells.connectivity, 1, encoding)?;
        write_array(w, "offsets", &cells.offsets, 1, encoding)?;
        let types: Vec<u8> = cells.types.iter().map(|&t| t as u8).collect();
        write_array(w, "types", &types, 1, encoding)?;
        if !cells.face_offsets.is_empty() {
            write_array(w, "faces", &cells.faces, 1, encoding)?;
            write_array(w, "faceoffsets", &cells.face_offsets, 1, encoding)?;
        }
        writeln!(w, "      </Cells>\n    </Piece>")?;
        xml::close(w, "UnstructuredGrid")
    })
    .map_err(|source| VtkError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The structural checks a reader relies on, so that a hand-built [`VtkCells`] cannot produce
/// a file that crashes ParaView.
fn check_cells(path: &Path, c: &VtkCells, n_points: usize) -> Result<(), VtkError> {
    let bad = |message: String| {
        Err(VtkError::Invalid {
            path: path.to_path_buf(),
            message,
        })
    };
    let nc = c.len();
    if c.offsets.len() != nc {
        return bad(format!("{} cell offsets for {nc} cells", c.offsets.len()));
    }
    let mut prev = 0;
    for &o in &c.offsets {
        if o < prev || o as usize > c.connectivity.len() {
            return bad(format!(
                "cell offset {o} out of order or beyond connectivity"
            ));
        }
        prev = o;
    }
    if prev as usize != c.connectivity.len() {
        return bad("cell offsets do not end at the connectivity length".into());
    }
    if let Some(p) = c
        .connectivity
        .iter()
        .find(|&&p| p < 0 || p as usize >= n_points)
    {
        return bad(format!("cell point id {p} but {n_points} points"));
    }
    let has_poly = c.types.contains(&crate::CellType::Polyhedron);
    if has_poly && c.face_offsets.len() != nc {
        return bad(format!(
            "{} face offsets for {nc} cells with polyhedra",
            c.face_offsets.len()
        ));
    }
    if c.face_offsets
        .iter()
        .any(|&o| o > c.faces.len() as i64 || o < -1)
    {
        return bad("face offset beyond the face stream".into());
    }
    if let Some(p) = c.faces.iter().find(|&&p| p < 0) {
        return bad(format!("negative entry {p} in the face stream"));
    }
    Ok(())
}
