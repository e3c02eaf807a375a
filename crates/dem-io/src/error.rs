//! The one error type of the crate: what went wrong, in which file, and where.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// Name used as [`DumpError::file`] for snapshots built in memory rather than read from a file.
pub const IN_MEMORY: &str = "<in-memory snapshot>";

/// Where in a file an error was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// Not tied to a position (e.g. a column missing from a snapshot already read).
    Unknown,
    /// 1-based line number in a text dump.
    Line(u64),
    /// 0-based byte offset in a binary dump.
    Byte(u64),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Unknown => Ok(()),
            Location::Line(n) => write!(f, ":{n}"),
            Location::Byte(b) => write!(f, " (byte {b})"),
        }
    }
}

/// Every failure of reading, selecting or interpreting a dump.
///
/// Displays as `file:line: message` (text), `file (byte N): message` (binary) or
/// `file: message`. Match on [`DumpError::kind`] to react to a particular failure.
#[derive(Debug)]
pub struct DumpError {
    /// The file (or stream name) the error belongs to.
    pub file: PathBuf,
    /// Line (text) or byte offset (binary) where the problem was detected.
    pub location: Location,
    /// What went wrong.
    pub kind: ErrorKind,
}

impl DumpError {
    /// Builds an error for `file` at `location`.
    pub fn new(file: impl Into<PathBuf>, location: Location, kind: ErrorKind) -> Self {
        DumpError {
            file: file.into(),
            location,
            kind,
        }
    }

    pub(crate) fn at(file: &Path, location: Location, kind: ErrorKind) -> Self {
        DumpError::new(file.to_path_buf(), location, kind)
    }
}

impl fmt::Display for DumpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}: {}", self.file.display(), self.location, self.kind)
    }
}

impl std::error::Error for DumpError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ErrorKind::Io(e) => Some(e),
            _ => None,
        }
    }
}

/// The reasons a dump can be rejected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The operating system failed to open, read or seek.
    #[error("I/O error: {0}")]
    Io(#[source] io::Error),
    /// The file ends where more data was required.
    #[error("file ends early: expected {expected}")]
    Truncated {
        /// What was still expected.
        expected: String,
    },
    /// A text header line other than the one required at this point.
    #[error("expected `{expected}`, found `{found}`")]
    Unexpected {
        /// The line (or item) required.
        expected: String,
        /// What the file has instead (shortened).
        found: String,
    },
    /// `ITEM: X` that LIGGGHTS/LAMMPS dump custom never writes.
    #[error("unknown header item `ITEM: {0}`")]
    UnknownItem(String),
    /// The snapshot header ended (`ITEM: ATOMS`) without a required item.
    #[error("snapshot header lacks `ITEM: {0}`")]
    MissingItem(&'static str),
    /// A token that should be a number is not.
    #[error("cannot read {what} from `{token}`")]
    BadNumber {
        /// What the token should have been (e.g. "a value", "the timestep").
        what: &'static str,
        /// The offending token (shortened).
        token: String,
    },
    /// A text row with more or fewer values than there are columns.
    #[error("row has {found} values, the header names {expected} columns")]
    WrongValueCount {
        /// Number of columns named by `ITEM: ATOMS`.
        expected: usize,
        /// Number of values found on the row.
        found: usize,
    },
    /// The next snapshot starts before `NUMBER OF ATOMS` rows were read.
    #[error("snapshot has {found} rows, but NUMBER OF ATOMS says {expected}")]
    TooFewRows {
        /// Rows announced by the header.
        expected: u64,
        /// Rows actually present.
        found: u64,
    },
    /// A line longer than the reader accepts (the file is probably not a text dump).
    #[error("line longer than {0} bytes (is this a binary dump read as text?)")]
    LineTooLong(usize),
    /// A boundary flag other than p, f, s, m (text) or 0..=3 (binary).
    #[error("invalid boundary `{0}` (expected two of p f s m per axis, or codes 0..=3)")]
    BadBoundary(String),
    /// A header value that cannot be right (negative count, triclinic flag not 0/1, …).
    #[error("invalid header: {0}")]
    BadHeader(String),
    /// A binary chunk whose size does not fit the header.
    #[error("bad chunk: {0}")]
    BadChunk(String),
    /// The same column name appears twice with different values.
    #[error("column `{0}` appears twice with different values")]
    DuplicateColumn(String),
    /// A column list with no names.
    #[error("no column names given")]
    NoColumns,
    /// Binary header column count differs from the number of names the caller gave.
    #[error("binary dump has {in_file} columns but {given} column names were given ({names})")]
    ColumnCountMismatch {
        /// Columns per row according to the file.
        in_file: usize,
        /// Names supplied by the caller.
        given: usize,
        /// The supplied names, space separated.
        names: String,
    },
    /// Column data of different lengths handed to [`crate::Snapshot::new`].
    #[error("column `{column}` has {found} values, expected {expected}")]
    ColumnLength {
        /// The column.
        column: String,
        /// Length of the first column.
        expected: usize,
        /// Length of this column.
        found: usize,
    },
    /// A column needed for the requested quantity is not in the snapshot.
    #[error("timestep {timestep}: no column `{column}` (columns: {available})")]
    MissingColumn {
        /// Timestep of the snapshot.
        timestep: u64,
        /// The column (or alternatives) that was needed.
        column: String,
        /// The columns present, space separated.
        available: String,
    },
    /// A value that cannot stand for what its column means (e.g. a fractional `id`).
    #[error("timestep {timestep}: column `{column}` row {row}: {value} is not a valid {what}")]
    BadValue {
        /// Timestep of the snapshot.
        timestep: u64,
        /// The column.
        column: String,
        /// 0-based row index.
        row: usize,
        /// The value found.
        value: f64,
        /// What was expected (e.g. "particle id").
        what: &'static str,
    },
    /// Binary dumps of LAMMPS since 2019 start with a magic string; LIGGGHTS never writes it.
    #[error("binary dump in the newer LAMMPS layout (magic string header) is not supported")]
    UnsupportedFormat,
    /// No snapshot matches the selection.
    #[error("no snapshot {0}")]
    NotFound(String),
    /// [`crate::DumpReader::read_body`] or `skip_body` called without a pending header.
    #[error("no snapshot header pending: call next_header first")]
    NoPendingHeader,
}

/// Shortens untrusted text for error messages.
pub(crate) fn shorten(bytes: &[u8]) -> String {
    const MAX: usize = 60;
    let s = String::from_utf8_lossy(bytes);
    let s = s.trim_end();
    if s.chars().count() > MAX {
        let mut out: String = s.chars().take(MAX).collect();
        out.push('…');
        out
    } else {
        s.to_string()
    }
}
