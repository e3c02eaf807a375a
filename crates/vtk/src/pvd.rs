//! ParaView collection files (`.pvd`): a time series of datasets that opens as an animation.

use std::io::Write as _;
use std::path::Path;

use crate::array::escape_attr;
use crate::VtkError;
use atomic_write::write_atomically;

/// Writes a `.pvd` collection listing `(time, file)` pairs, e.g. one `.vtp` per particle
/// snapshot. ParaView resolves relative names against the `.pvd`'s directory: a file given by
/// a path that starts with the `.pvd`'s directory (both absolute, or both relative to the
/// same working directory) is written relative to it, so the series can be moved as a whole;
/// any other path is written as given, i.e. a relative one must already be relative to the
/// `.pvd`'s directory. Entries are written in the order given; several
/// files at one time are numbered as parts `0, 1, …` of that time step. The file is replaced
/// atomically, so rewriting it after every snapshot keeps a readable series while a run goes on.
///
/// Errors: a non-finite time or a non-UTF-8 file name ([`VtkError::Invalid`]), I/O failures.
pub fn write_pvd<P: AsRef<Path>>(
    path: impl AsRef<Path>,
    entries: &[(f64, P)],
) -> Result<(), VtkError> {
    let path = path.as_ref();
    let invalid = |message: String| VtkError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let base = path.parent().unwrap_or(Path::new(""));
    let mut rows = Vec::with_capacity(entries.len());
    for (i, (time, file)) in entries.iter().enumerate() {
        if !time.is_finite() {
            return Err(invalid(format!("entry {i} has time {time}")));
        }
        let file = file.as_ref();
        let rel = if base.as_os_str().is_empty() {
            file
        } else {
            file.strip_prefix(base).unwrap_or(file)
        };
        let name = rel
            .to_str()
            .ok_or_else(|| invalid(format!("file name {} is not UTF-8", rel.display())))?;
        let part = entries[..i].iter().filter(|(t, _)| t == time).count();
        rows.push(format!(
            "    <DataSet timestep=\"{time:?}\" group=\"\" part=\"{part}\" file=\"{}\"/>\n",
            escape_attr(name)
        ));
    }
    write_atomically(path, |w| {
        w.write_all(
            b"<?xml version=\"1.0\"?>\n\
              <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        )?;
        for r in &rows {
            w.write_all(r.as_bytes())?;
        }
        w.write_all(b"  </Collection>\n</VTKFile>\n")
    })
    .map_err(|source| VtkError::Io {
        path: path.to_path_buf(),
        source,
    })
}
