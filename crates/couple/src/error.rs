//! Typed errors of the coupler. Each names what it is about: the file and key of a
//! configuration entry, the particle (index and id), the side that failed.

use std::path::PathBuf;

/// An error of a [`crate::ParticleSide`] or [`crate::FluidSide`] implementation.
pub type SideError = Box<dyn std::error::Error + Send + Sync>;

/// Why a coupling operation failed.
#[derive(Debug, thiserror::Error)]
pub enum CoupleError {
    /// A name that none of the known ones matches.
    #[error("unknown {what} `{name}`; valid: {valid}")]
    Unknown {
        /// What kind of name.
        what: &'static str,
        /// The name given.
        name: String,
        /// The accepted names.
        valid: String,
    },
    /// A bad or unsupported entry of a configuration file.
    #[error("{}: `{key}`: {message}", file.display())]
    Config {
        /// The file.
        file: PathBuf,
        /// The keyword (with its dictionary, `dividedProps/alphaMin`).
        key: String,
        /// What is wrong.
        message: String,
    },
    /// A particle whose data cannot be coupled.
    #[error("particle {index}{}: {message}", id.map(|i| format!(" (id {i})")).unwrap_or_default())]
    Particle {
        /// 0-based index in the particle arrays.
        index: usize,
        /// The particle id, when known.
        id: Option<u64>,
        /// What is wrong.
        message: String,
    },
    /// Arrays of inconsistent lengths handed over by a side.
    #[error("{what}: expected {expected} values, found {found}")]
    Length {
        /// Which array.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// A bad parameter (command line or API).
    #[error("{0}")]
    Parameter(String),
    /// OpenFOAM file errors (they name the file and line).
    #[error(transparent)]
    Foam(#[from] foam::FoamError),
    /// LIGGGHTS dump errors (they name the file and line or byte).
    #[error(transparent)]
    Dump(#[from] dem_io::DumpError),
    /// Voidage errors (they name the particle).
    #[error(transparent)]
    Voidage(#[from] voidage::VoidageError),
    /// Mesh errors.
    #[error(transparent)]
    Mesh(#[from] mesh::MeshError),
    /// Closure parameter errors.
    #[error(transparent)]
    Closure(#[from] closures::ClosureError),
    /// A side failed.
    #[error("{side} side: {source}")]
    Side {
        /// `particle` or `fluid`.
        side: &'static str,
        /// Its error.
        source: SideError,
    },
    /// An I/O error on a named path.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}
