//! Particles as a legacy VTK file (`.vtk`, "DataFile Version 2.0", ASCII PolyData): what
//! LIGGGHTS's `dump custom/vtk` writes for a `.vtk` name, read by ParaView and VTK's
//! `vtkPolyDataReader`.
//!
//! Layout (VTK file-format specification, "Simple Legacy Formats"): the header lines, `DATASET
//! POLYDATA`, `POINTS n double` with the positions, `VERTICES n 2n` with one vertex per point
//! (so ParaView draws them without a Glyph filter), then `POINT_DATA n` and `FIELD FieldData k`
//! with each array as `name components n double|int|vtktypeint64` (field arrays, unlike a second
//! `SCALARS` block, are read by every reader without `ReadAllScalarsOn`). Values
//! are written with Rust's shortest round-trip form, so they read back exactly; non-finite
//! values are refused (VTK's ASCII reader does not take them).

use std::io::Write as _;
use std::path::Path;

use atomic_write::write_atomically;

use crate::xml::check_arrays;
use crate::{DataArray, Values, VtkError};

/// Writes particles as a legacy ASCII PolyData file (replaced atomically).
///
/// Errors: an array whose length differs from `points.len()`, an empty or repeated name or a
/// name with blanks, a non-finite value, I/O failures — each naming `path`.
pub fn write_legacy_vtk(
    path: impl AsRef<Path>,
    title: &str,
    points: &[[f64; 3]],
    point_data: &[DataArray<'_>],
) -> Result<(), VtkError> {
    let path = path.as_ref();
    let n = points.len();
    check_arrays(path, point_data, "point", n)?;
    let invalid = |message: String| VtkError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    if let Some(a) = point_data
        .iter()
        .find(|a| a.name.contains(char::is_whitespace))
    {
        return Err(invalid(format!("array name `{}` has blanks", a.name)));
    }
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if !finite(points.as_flattened()) {
        return Err(invalid("a point is not finite".into()));
    }
    for a in point_data {
        let ok = match a.values {
            Values::Scalar(v) => finite(v),
            Values::Vector(v) => finite(v.as_flattened()),
            Values::Int64(_) | Values::Int32(_) => true,
        };
        if !ok {
            return Err(invalid(format!(
                "array `{}` has a non-finite value",
                a.name
            )));
        }
    }
    // the title line holds at most 256 characters and no newline
    let title: String = title.chars().filter(|&c| c != '\n').take(255).collect();
    write_atomically(path, |w| {
        writeln!(
            w,
            "# vtk DataFile Version 2.0\n{title}\nASCII\nDATASET POLYDATA"
        )?;
        writeln!(w, "POINTS {n} double")?;
        for p in points {
            writeln!(w, "{} {} {}", p[0], p[1], p[2])?;
        }
        writeln!(w, "VERTICES {n} {}", 2 * n)?;
        for i in 0..n {
            writeln!(w, "1 {i}")?;
        }
        if point_data.is_empty() {
            return Ok(());
        }
        writeln!(w, "POINT_DATA {n}\nFIELD FieldData {}", point_data.len())?;
        for a in point_data {
            match a.values {
                Values::Scalar(v) => {
                    writeln!(w, "{} 1 {n} double", a.name)?;
                    v.iter().try_for_each(|x| writeln!(w, "{x}"))?;
                }
                Values::Int64(v) => {
                    writeln!(w, "{} 1 {n} vtktypeint64", a.name)?;
                    v.iter().try_for_each(|x| writeln!(w, "{x}"))?;
                }
                Values::Int32(v) => {
                    writeln!(w, "{} 1 {n} int", a.name)?;
                    v.iter().try_for_each(|x| writeln!(w, "{x}"))?;
                }
                Values::Vector(v) => {
                    writeln!(w, "{} 3 {n} double", a.name)?;
                    v.iter()
                        .try_for_each(|x| writeln!(w, "{} {} {}", x[0], x[1], x[2]))?;
                }
            }
        }
        Ok(())
    })
    .map_err(|source| VtkError::Io {
        path: path.to_path_buf(),
        source,
    })
}
