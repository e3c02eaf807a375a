//! Errors of a run ([`RunError`]) and of reading a case ([`LayoutError`]): each names the
//! file or the side it comes from.

use std::path::{Path, PathBuf};

/// Errors finding or reading a case; every message names the file or directory.
#[derive(Debug, thiserror::Error)]
pub enum LayoutError {
    /// A required directory or file is missing.
    #[error("{path}: {what} not found (a CFDEM-layout case has CFD/ and DEM/ folders)")]
    Missing {
        /// The missing path.
        path: PathBuf,
        /// What it should have been.
        what: &'static str,
    },
    /// A dictionary failed to parse.
    #[error(transparent)]
    Foam(#[from] foam::FoamError),
    /// `couplingProperties` is invalid.
    #[error(transparent)]
    Coupling(#[from] couple::CoupleError),
    /// A dictionary entry is missing or has the wrong type or value.
    #[error("{path}: {msg}")]
    Entry {
        /// The dictionary file.
        path: PathBuf,
        /// What is wrong, naming the key.
        msg: String,
    },
}

/// Errors of a run; each names the file or the side it comes from.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The case layout or validationDict.
    #[error(transparent)]
    Layout(#[from] LayoutError),
    /// The coupling configuration or a coupling step.
    #[error(transparent)]
    Couple(#[from] couple::CoupleError),
    /// A LIGGGHTS deck that cannot be read (file, line).
    #[error(transparent)]
    Deck(#[from] liggghts_deck::DeckError),
    /// The native DEM (deck, setup, run).
    #[error(transparent)]
    Dem(#[from] dem::DemError),
    /// The native fluid.
    #[error("fluid: {0}")]
    Fluid(couple::SideError),
    /// A setting that cannot work together with another.
    #[error("{file}: {message}")]
    Setup {
        /// The file with the offending setting.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Writing an output.
    #[error("{}: {source}", path.display())]
    Io {
        /// The output.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Writing a field.
    #[error(transparent)]
    Foam(#[from] foam::FoamError),
    /// Writing particles.
    #[error(transparent)]
    Vtk(#[from] vtk::VtkError),
    /// Drawing a plot.
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// A backend that is not available or failed to start.
    #[error("{0}")]
    Backend(String),
    /// A validation check that cannot be evaluated (a measurement or parameter it needs is
    /// missing); the message names it.
    #[error("check: {0}")]
    Check(String),
}

pub(crate) fn setup_err(file: &Path, message: String) -> RunError {
    RunError::Setup {
        file: file.to_owned(),
        message,
    }
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_owned(),
        source,
    }
}
