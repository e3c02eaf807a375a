//! Typed errors of the LIGGGHTS backends. Each names what it is about: the deck file and line,
//! the exchange file, the particle (by LIGGGHTS tag), the program and the tail of its log.

use std::path::PathBuf;

/// Why a LIGGGHTS operation failed.
#[derive(Debug, thiserror::Error)]
pub enum LiggghtsError {
    /// A deck that cannot be coupled as it is (checked before LIGGGHTS sees it, because any
    /// LIGGGHTS error ends the whole process).
    #[error("{}:{line}: {message}", file.display())]
    Deck {
        /// The deck.
        file: PathBuf,
        /// 1-based line (0 when the problem is the deck as a whole).
        line: usize,
        /// What is wrong and what to do.
        message: String,
    },
    /// Reading the deck (variables, quotes): the deck language's reader names file and line.
    #[error(transparent)]
    DeckSyntax(#[from] liggghts_deck::DeckError),
    /// An I/O error on a named path.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The `liggghts` program failed or stopped.
    #[error("{program} {what}; last lines of {}:\n{tail}", log.display())]
    Program {
        /// The command run (program and arguments).
        program: String,
        /// What happened (`exited with status 1`, `was killed by a signal`, …).
        what: String,
        /// The log (or screen) file whose tail is shown.
        log: PathBuf,
        /// Its last lines.
        tail: String,
    },
    /// A malformed exchange file of the file coupling.
    #[error("{}:{line}: {message}", file.display())]
    Exchange {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A particle whose data cannot be handed over.
    #[error("particle {tag}: {message}")]
    Particle {
        /// Its LIGGGHTS tag (id).
        tag: u64,
        /// What is wrong.
        message: String,
    },
    /// Arrays of inconsistent lengths handed to a side.
    #[error("{what}: expected {expected} values, found {found}")]
    Length {
        /// Which array.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// LIGGGHTS lacks what the coupling reads or writes (per-atom arrays, coupling fixes).
    #[error("{0}")]
    Coupling(String),
    /// A bad argument of the API (step counts, workdir, communicator).
    #[error("{0}")]
    Parameter(String),
}

impl LiggghtsError {
    /// An I/O error on `path`.
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> LiggghtsError {
        LiggghtsError::Io {
            path: path.into(),
            source,
        }
    }
}
