//! Errors of the foam crate. Every error names the file; parse errors also name the line and the
//! byte offset where the problem was found (byte offsets matter inside binary lists).

use std::path::PathBuf;

/// Where in a file a problem was found: 1-based line and 0-based byte offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Location {
    /// 1-based line number (lines inside binary blocks are not counted).
    pub line: usize,
    /// 0-based byte offset from the start of the file.
    pub byte: usize,
}

/// An error while reading or writing OpenFOAM files.
#[derive(Debug, thiserror::Error)]
pub enum FoamError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The file's text or binary content is malformed.
    #[error("{}: line {}, byte {}: {msg}", path.display(), at.line, at.byte)]
    Parse {
        /// The file.
        path: PathBuf,
        /// Where the problem was found.
        at: Location,
        /// What is wrong.
        msg: String,
    },
    /// The file parsed but its content is inconsistent or unsupported (missing entry, wrong
    /// class, list length that does not match the mesh, …).
    #[error("{}: {msg}", path.display())]
    Invalid {
        /// The file (or directory).
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
}

impl FoamError {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        FoamError::Io {
            path: path.into(),
            source,
        }
    }

    pub(crate) fn invalid(path: impl Into<PathBuf>, msg: impl Into<String>) -> Self {
        FoamError::Invalid {
            path: path.into(),
            msg: msg.into(),
        }
    }
}

/// Result type of the foam crate.
pub type Result<T, E = FoamError> = std::result::Result<T, E>;
