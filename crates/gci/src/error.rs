//! Typed errors: bad tables (naming the file or argument and the line), bad settings, and grids
//! handed over out of order. The binary turns them into messages.

use std::fmt;
use thiserror::Error;

/// Where a row came from: a file and its 1-based line, or a command-line argument and the
/// 1-based position of the item in its comma-separated list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file name (as given) or the argument, e.g. `--cells`.
    pub source: String,
    /// 1-based line in the file, or position in the argument's list.
    pub line: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.source, self.line)
    }
}

/// What went wrong with the input or the settings of a GCI study.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GciError {
    /// The table has no header line.
    #[error("{input}: empty table (expected a header such as `cells,value` or `h,value`)")]
    Empty {
        /// The file name or argument.
        input: String,
    },
    /// The header lacks a required column, or names one twice.
    #[error("{at}: {problem} (header: `{header}`)")]
    Header {
        /// The header line.
        at: Location,
        /// What is missing or repeated.
        problem: String,
        /// The header as read.
        header: String,
    },
    /// A row with more or fewer fields than the header.
    #[error("{at}: {found} fields, the header has {expected}")]
    FieldCount {
        /// The row.
        at: Location,
        /// Fields in the header.
        expected: usize,
        /// Fields in the row.
        found: usize,
    },
    /// A field that does not read as a finite number.
    #[error("{at}: column `{column}`: `{text}` is not a finite number")]
    NotANumber {
        /// The row.
        at: Location,
        /// The column's name.
        column: String,
        /// The field as written.
        text: String,
    },
    /// A cell count, cell size or domain measure that is not > 0.
    #[error("{at}: column `{column}` = {value} must be > 0")]
    NotPositive {
        /// The row.
        at: Location,
        /// The column's name.
        column: String,
        /// The value read.
        value: f64,
    },
    /// Two rows with the same representative cell size: no refinement ratio between them.
    #[error(
        "{at}: the same cell size as {first} (two grids of one size give no refinement ratio)"
    )]
    DuplicateSize {
        /// The later row.
        at: Location,
        /// The earlier row with that size.
        first: Location,
    },
    /// Fewer than three grids: no apparent order can be computed.
    #[error("{input}: {found} grid(s) (last at line {last_line}); the GCI needs at least 3")]
    TooFewGrids {
        /// The file name or argument.
        input: String,
        /// How many rows were read.
        found: usize,
        /// The line of the last row read (0 when none).
        last_line: usize,
    },
    /// The lists given on the command line differ in length.
    #[error("{sizes} has {n_sizes} item(s) but {values} has {n_values}")]
    ListLengths {
        /// The size argument's name.
        sizes: String,
        /// Its length.
        n_sizes: usize,
        /// The value argument's name.
        values: String,
        /// Its length.
        n_values: usize,
    },
    /// A setting out of range (safety factor, …).
    #[error("setting `{name}` = {value} is invalid: {reason}")]
    Setting {
        /// The setting's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range.
        reason: &'static str,
    },
    /// Grids handed to [`crate::triplet::analyse`] not ordered fine to coarse with finite values.
    #[error("grids must have finite values and 0 < h1 < h2 < h3 (got h = {h:?}, φ = {phi:?})")]
    Grids {
        /// The cell sizes given.
        h: [f64; 3],
        /// The values given.
        phi: [f64; 3],
    },
}
