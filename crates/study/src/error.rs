//! Errors of a study; each names the file, the grid or the run it comes from.

use std::path::PathBuf;

/// What can go wrong in a study.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The case layout (CFD/, DEM/, decks).
    #[error(transparent)]
    Layout(#[from] runner::layout::LayoutError),
    /// The coupling configuration or a coupling step.
    #[error(transparent)]
    Couple(#[from] couple::CoupleError),
    /// A LIGGGHTS deck that cannot be read (file, line).
    #[error(transparent)]
    Deck(#[from] liggghts_deck::DeckError),
    /// The native DEM (packing, reading the packed bed).
    #[error(transparent)]
    Dem(#[from] dem::DemError),
    /// An OpenFOAM file.
    #[error(transparent)]
    Foam(#[from] foam::FoamError),
    /// The native fluid.
    #[error("fluid ({case}): {message}")]
    Fluid {
        /// The work case of the run.
        case: PathBuf,
        /// The solver's message.
        message: String,
    },
    /// The blockMesh template.
    #[error("{}: {message}", path.display())]
    Template {
        /// The template file.
        path: PathBuf,
        /// What is wrong, naming the key or placeholder.
        message: String,
    },
    /// A run that did not reach its steady state.
    #[error("{run}: not steady after {steps} fluid steps (last relative change {change:.3e}, tolerance {tolerance:.1e})")]
    NotSteady {
        /// Which grid, method and velocity.
        run: String,
        /// Steps taken.
        steps: u64,
        /// The last relative change of the monitored quantities.
        change: f64,
        /// The tolerance asked for.
        tolerance: f64,
    },
    /// An option that cannot work (empty list, non-positive size, …).
    #[error("{0}")]
    Option(String),
    /// A case parameter that cannot work with the study.
    #[error("{}: {message}", file.display())]
    Setup {
        /// The file holding it.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Reading or writing a file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Drawing a plot.
    #[error(transparent)]
    Plot(#[from] runner::plot::PlotError),
    /// The Grid Convergence Index.
    #[error(transparent)]
    Gci(#[from] gci::GciError),
}

/// `map_err` helper for I/O on `path`.
pub(crate) fn io_err(path: &std::path::Path) -> impl FnOnce(std::io::Error) -> StudyError + '_ {
    move |source| StudyError::Io {
        path: path.to_owned(),
        source,
    }
}
