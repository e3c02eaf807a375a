//! The crate's error type: every failure names what it is about (deck file and line, property,
//! particle, dump file).

use std::path::PathBuf;

pub use liggghts_deck::DeckLocation;

/// Every failure of building or running a simulation.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DemError {
    /// A deck command is unknown, unsupported or malformed.
    #[error("{at}: {message}")]
    Deck {
        /// Where.
        at: DeckLocation,
        /// What is wrong.
        message: String,
    },
    /// The deck cannot be read (missing file, malformed line or variable).
    #[error(transparent)]
    DeckRead(#[from] liggghts_deck::DeckError),
    /// Material properties are missing or out of range.
    #[error("material properties: {0}")]
    Material(String),
    /// A particle's data is invalid (non-positive radius or density, unknown type, NaN).
    #[error("particle {id}: {message}")]
    Particle {
        /// The particle id.
        id: u64,
        /// What is wrong.
        message: String,
    },
    /// The simulation set-up is inconsistent (no time step, no contact model, …).
    #[error("{0}")]
    Setup(String),
    /// Coupling data of the wrong length or non-finite.
    #[error("coupling data: {0}")]
    Coupling(String),
    /// Reading a dump failed.
    #[error(transparent)]
    Dump(#[from] dem_io::DumpError),
    /// An STL file of `fix mesh/surface` is missing, short or malformed.
    #[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Stl {
        /// The file.
        file: PathBuf,
        /// 1-based line of an ASCII file, when the fault is on one.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// Writing a dump failed.
    #[error("cannot write dump {file}: {source}")]
    DumpWrite {
        /// The file.
        file: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
}
