//! The parts of a VTK XML file shared by the writers.

use std::io::{self, Write};
use std::path::Path;

use crate::{DataArray, Encoding, VtkError};

/// `<?xml?>` and the opening `VTKFile` and dataset elements.
pub(crate) fn open<W: Write>(w: &mut W, dataset: &str) -> io::Result<()> {
    write!(
        w,
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"{dataset}\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n  <{dataset}>\n"
    )
}

/// Closes what [`open`] opened.
pub(crate) fn close<W: Write>(w: &mut W, dataset: &str) -> io::Result<()> {
    write!(w, "  </{dataset}>\n</VTKFile>\n")
}

/// A `<PointData>` or `<CellData>` section (omitted when there are no arrays).
pub(crate) fn attributes<W: Write>(
    w: &mut W,
    element: &str,
    arrays: &[DataArray<'_>],
    enc: Encoding,
) -> io::Result<()> {
    if arrays.is_empty() {
        return Ok(());
    }
    writeln!(w, "      <{element}>")?;
    for a in arrays {
        a.write(w, enc)?;
    }
    writeln!(w, "      </{element}>")
}

/// Checks that every array has `expected` tuples and that names are unique and non-empty.
pub(crate) fn check_arrays(
    path: &Path,
    arrays: &[DataArray<'_>],
    location: &'static str,
    expected: usize,
) -> Result<(), VtkError> {
    for (i, a) in arrays.iter().enumerate() {
        if a.len() != expected {
            return Err(VtkError::Length {
                path: path.to_path_buf(),
                name: a.name.to_string(),
                location,
                expected,
                found: a.len(),
            });
        }
        if a.name.is_empty() || arrays[..i].iter().any(|b| b.name == a.name) {
            return Err(VtkError::Invalid {
                path: path.to_path_buf(),
                message: format!(
                    "{location} data array name `{}` is empty or repeated",
                    a.name
                ),
            });
        }
    }
    Ok(())
}
