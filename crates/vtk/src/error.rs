//! The one error type of the crate. Every variant names the file being written.

use std::io;
use std::path::PathBuf;

/// What went wrong while writing a VTK file.
#[derive(Debug, thiserror::Error)]
pub enum VtkError {
    /// Creating, writing, syncing or renaming the file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The output file (not the temporary it was written through).
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
    /// A data array does not have one value per point (or per cell).
    #[error(
        "{}: {location} data array `{name}` has {found} values but there are {expected} {location}s",
        path.display()
    )]
    Length {
        /// The output file.
        path: PathBuf,
        /// Name of the offending array.
        name: String,
        /// `point` or `cell`.
        location: &'static str,
        /// Number of points or cells.
        expected: usize,
        /// Number of tuples in the array.
        found: usize,
    },
    /// The mesh cannot be written: it fails [`foam::PolyMesh::check`].
    #[error("{}: invalid mesh: {source}", path.display())]
    Mesh {
        /// The output file.
        path: PathBuf,
        /// What is wrong with the mesh.
        #[source]
        source: foam::TopologyError,
    },
    /// Invalid input that is neither a length nor a mesh problem (e.g. a non-finite time step).
    #[error("{}: {message}", path.display())]
    Invalid {
        /// The output file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}
