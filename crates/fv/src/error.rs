//! Errors of the fv crate: every message names the file and key (or the patch, field, cell)
//! that is wrong.

use std::path::PathBuf;

/// An error while setting up or running the fluid solver.
#[derive(Debug, thiserror::Error)]
pub enum FvError {
    /// Reading an OpenFOAM file failed (the message names the file and line).
    #[error(transparent)]
    Foam(#[from] foam::FoamError),
    /// The mesh geometry is invalid (inverted or degenerate cell, bad topology).
    #[error("mesh: {0}")]
    Mesh(#[from] mesh::MeshError),
    /// A setting is missing, malformed or not supported.
    #[error("{}: `{key}`: {msg}", file.display())]
    Setting {
        /// The file holding the setting.
        file: PathBuf,
        /// The keyword (dotted path for nested entries, e.g. `boundaryField.inlet.type`).
        key: String,
        /// What is wrong.
        msg: String,
    },
    /// An input array has the wrong length.
    #[error("{what}: {got} values given, {expected} expected")]
    Length {
        /// Which input.
        what: String,
        /// Its length.
        got: usize,
        /// The length the mesh needs.
        expected: usize,
    },
    /// A value is not finite or out of its range.
    #[error("{what}: {msg}")]
    Value {
        /// Which input (field and cell, …).
        what: String,
        /// What is wrong.
        msg: String,
    },
    /// A linear solver or the time loop diverged.
    #[error("{0}")]
    Diverged(String),
}

impl FvError {
    /// A [`FvError::Setting`] error.
    pub fn setting(
        file: impl Into<PathBuf>,
        key: impl Into<String>,
        msg: impl Into<String>,
    ) -> Self {
        FvError::Setting {
            file: file.into(),
            key: key.into(),
            msg: msg.into(),
        }
    }

    /// The error with a file named relative to a case (such as
    /// [`mesh::cyclic::BOUNDARY_FILE`]) named inside the case directory `root`.
    pub fn in_case(self, root: &std::path::Path) -> Self {
        match self {
            FvError::Setting { file, key, msg } if file.is_relative() => FvError::Setting {
                file: root.join(file),
                key,
                msg,
            },
            other => other,
        }
    }

    /// A mesh error: a patch's ([`mesh::MeshError::Patch`], from the cyclic pairs) as the
    /// setting it names, any other as [`FvError::Mesh`].
    pub fn from_mesh(e: mesh::MeshError) -> Self {
        match e {
            mesh::MeshError::Patch { file, key, msg } => FvError::Setting { file, key, msg },
            other => FvError::Mesh(other),
        }
    }

    /// Checks that `got == expected`.
    pub fn check_len(what: &str, got: usize, expected: usize) -> Result<(), FvError> {
        if got == expected {
            Ok(())
        } else {
            Err(FvError::Length {
                what: what.into(),
                got,
                expected,
            })
        }
    }
}

/// Result type of the fv crate.
pub type Result<T, E = FvError> = std::result::Result<T, E>;
