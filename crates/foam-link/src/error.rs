//! Typed errors of the link. Each names what it is about: the case, the solver rank and its
//! log, the cell, the tool that failed.

use std::path::PathBuf;

/// Why the link to grainPisoFoam failed.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// OpenFOAM file errors (they name the file and line).
    #[error(transparent)]
    Foam(#[from] foam::FoamError),
    /// An I/O error on a named path.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A bad or missing entry of a case file.
    #[error("{}: {message}", path.display())]
    Config {
        /// The file.
        path: PathBuf,
        /// What is wrong (with the keyword).
        message: String,
    },
    /// A bad argument of the API (rank count, missing solver binary, world size).
    #[error("{0}")]
    Parameter(String),
    /// An OpenFOAM utility (decomposePar, reconstructPar) failed.
    #[error("{program} -case {} failed ({status}):\n{output}", case.display())]
    Tool {
        /// The program.
        program: String,
        /// The case.
        case: PathBuf,
        /// Its exit status.
        status: String,
        /// The end of its output.
        output: String,
    },
    /// MPI_Comm_spawn failed.
    #[error("cannot spawn {solver} on {ranks} rank(s): {message}", solver = solver.display())]
    Spawn {
        /// The solver binary.
        solver: PathBuf,
        /// Ranks asked for.
        ranks: usize,
        /// MPI's reason.
        message: String,
    },
    /// A solver rank broke the protocol (wrong version, cell map, patch names, lengths).
    #[error("grainPisoFoam rank {rank}: {message} (log: {})", log.display())]
    Protocol {
        /// The solver rank.
        rank: usize,
        /// Its log file.
        log: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A solver rank stopped with an OpenFOAM FatalError and sent its message.
    #[error("grainPisoFoam rank {rank} stopped with an error (log: {}):\n{message}", log.display())]
    SolverError {
        /// The solver rank.
        rank: usize,
        /// Its log file.
        log: PathBuf,
        /// OpenFOAM's message.
        message: String,
    },
    /// A solver process disappeared (killed, a floating-point trap on NaN, a crash).
    #[error(
        "grainPisoFoam rank {rank} (pid {pid}) is gone while the coupler waited for {waiting}; \
         see {} — its last lines:\n{tail}",
        log.display()
    )]
    SolverDied {
        /// The solver rank.
        rank: usize,
        /// Its process id.
        pid: u32,
        /// What the coupler was waiting for.
        waiting: &'static str,
        /// Its log file.
        log: PathBuf,
        /// The last lines of the log.
        tail: String,
    },
    /// Exchange data the solver cannot take (a NaN, ε outside (0, 1], a wrong length).
    #[error("{what} at cell {cell}: {message}")]
    Value {
        /// Which field.
        what: &'static str,
        /// The (global) cell.
        cell: usize,
        /// What is wrong.
        message: String,
    },
    /// Arrays of the wrong length (couple's error, which names the array).
    #[error(transparent)]
    Couple(#[from] couple::CoupleError),
}

impl LinkError {
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> LinkError {
        LinkError::Io {
            path: path.into(),
            source,
        }
    }
}
