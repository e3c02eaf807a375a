//! Particles as VTK PolyData (`.vtp`): points, one `VTK_VERTEX` per point, point data.

use std::io::Write as _;
use std::path::Path;

use crate::array::write_array;
use crate::xml;
use crate::{DataArray, Encoding, VtkError};
use atomic_write::write_atomically;

/// Writes particles as binary PolyData. See [`write_vtp_with`].
pub fn write_vtp(
    path: impl AsRef<Path>,
    points: &[[f64; 3]],
    point_data: &[DataArray<'_>],
) -> Result<(), VtkError> {
    write_vtp_with(path, points, point_data, Encoding::Binary)
}

/// Writes particles as PolyData: the positions as Float64 points, one vertex cell per point
/// (so ParaView draws them without a Glyph filter), and `point_data` (one tuple per point) as
/// point arrays. The file is replaced atomically.
///
/// Errors: an array whose length differs from `points.len()` ([`VtkError::Length`]), an empty
/// or repeated array name, and I/O failures — each naming `path`.
pub fn write_vtp_with(
    path: impl AsRef<Path>,
    points: &[[f64; 3]],
    point_data: &[DataArray<'_>],
    encoding: Encoding,
) -> Result<(), VtkError> {
    let path = path.as_ref();
    let n = points.len();
    xml::check_arrays(path, point_data, "point", n)?;
    write_atomically(path, |w| {
        xml::open(w, "PolyData")?;
        writeln!(
            w,
            "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" \
             NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
        )?;
        xml::attributes(w, "PointData", point_data, encoding)?;
        writeln!(w, "      <Points>")?;
        write_array(w, "Points", points.as_flattened(), 3, encoding)?;
        writeln!(w, "      </Points>\n      <Verts>")?;
        let ids: Vec<i64> = (0..n as i64).collect();
        write_array(w, "connectivity", &ids, 1, encoding)?;
        let ends: Vec<i64> = (1..=n as i64).collect();
        write_array(w, "offsets", &ends, 1, encoding)?;
        writeln!(w, "      </Verts>\n    </Piece>")?;
        xml::close(w, "PolyData")
    })
    .map_err(|source| VtkError::Io {
        path: path.to_path_buf(),
        source,
    })
}
