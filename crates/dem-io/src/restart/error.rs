//! Errors of reading a restart file: what is wrong, in which file, at which byte.

use std::fmt;
use std::io;
use std::path::PathBuf;

/// Every failure of reading a restart file. Displays as `file (byte N): message`, or
/// `file: message` when the problem has no position (e.g. the file cannot be opened).
#[derive(Debug)]
pub struct RestartError {
    /// The file (or stream name) being read.
    pub file: PathBuf,
    /// 0-based byte offset of the record (or value) found wrong.
    pub offset: Option<u64>,
    /// What is wrong.
    pub kind: RestartErrorKind,
}

impl RestartError {
    pub(crate) fn at(file: &std::path::Path, offset: u64, kind: RestartErrorKind) -> Self {
        RestartError {
            file: file.to_path_buf(),
            offset: Some(offset),
            kind,
        }
    }
}

impl fmt::Display for RestartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.offset {
            Some(b) => write!(f, "{} (byte {b}): {}", self.file.display(), self.kind),
            None => write!(f, "{}: {}", self.file.display(), self.kind),
        }
    }
}

impl std::error::Error for RestartError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            RestartErrorKind::Io(e) => Some(e),
            _ => None,
        }
    }
}

/// The reasons a restart file is refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RestartErrorKind {
    /// The operating system failed to open or read the file.
    #[error("I/O error: {0}")]
    Io(#[source] io::Error),
    /// The file ends where more data was required.
    #[error("file ends early: expected {expected}")]
    Truncated {
        /// What was still expected.
        expected: String,
    },
    /// The file does not start like a LIGGGHTS restart file (a version record).
    #[error("not a LIGGGHTS restart file: it starts with {found}")]
    NotRestart {
        /// The first bytes, shown as text or hex.
        found: String,
    },
    /// A restart file of LAMMPS from 2015 on (magic string first); LIGGGHTS never writes it.
    #[error(
        "a LAMMPS restart file in the newer layout (magic string first), not a LIGGGHTS 3.8 one"
    )]
    NewerLammps,
    /// A version other than LIGGGHTS 3.8.x.
    #[error("restart file of `{found}`: only LIGGGHTS 3.8 restart files are supported")]
    UnsupportedVersion {
        /// The version string in the file.
        found: String,
    },
    /// Integer sizes of a build other than LIGGGHTS's default (smallint, tagint 4; bigint 8).
    #[error("{what} has {found} bytes in this file; LIGGGHTS's default build (read here) uses {expected}")]
    IntegerSize {
        /// Which integer type.
        what: &'static str,
        /// Its size in the file.
        found: i32,
        /// The size supported.
        expected: i32,
    },
    /// An atom style other than `granular` (or its twin `sphere`).
    #[error(
        "atom style `{found}`: only `atom_style granular` (sphere) restart files are supported"
    )]
    UnsupportedAtomStyle {
        /// The style in the file.
        found: String,
    },
    /// A record flag the section does not have: the rest of the file cannot be located.
    #[error("unknown flag {flag} in the {section} section")]
    UnknownFlag {
        /// The section (header, type arrays, force fields).
        section: &'static str,
        /// The flag read.
        flag: i32,
    },
    /// A header record LIGGGHTS 3.8.0 always writes is missing.
    #[error("the header lacks the {0} record")]
    MissingRecord(&'static str),
    /// A force-field style whose restart data has no stated length, so it cannot be read or
    /// stepped over (only `pair_style gran` is known).
    #[error(
        "{kind} style `{style}` in the force-field section: only `pair_style gran` is supported"
    )]
    UnsupportedStyle {
        /// pair, bond, angle, dihedral or improper.
        kind: &'static str,
        /// The style name.
        style: String,
    },
    /// A value that cannot be right (negative count, string without its NUL, …).
    #[error("{0}")]
    BadRecord(String),
    /// An atom record that does not fit the layout of the atom style or of its fixes.
    #[error("atom record {index} (0-based, in file order): {message}")]
    BadAtom {
        /// Index of the record in the file.
        index: u64,
        /// What is wrong.
        message: String,
    },
    /// The chunks hold another number of atoms than the header states.
    #[error("the header states {header} atoms, the chunks hold {found}")]
    AtomCount {
        /// Atoms according to the header.
        header: u64,
        /// Atom records found.
        found: u64,
    },
    /// Bytes after the last chunk.
    #[error("{0} bytes follow the last chunk of atoms")]
    TrailingBytes(u64),
}
