//! Streaming reader over the snapshots of one dump file, text or binary.

use std::fs::File;
use std::io::{Read, Seek};
use std::path::{Path, PathBuf};

use crate::binary::{self, ChunkedHeader};
use crate::error::{DumpError, ErrorKind, Location};
use crate::snapshot::{check_names, Snapshot, SnapshotHeader};
use crate::source::Source;
use crate::text;

/// Columns assumed for binary dumps when the caller names none (the CLI default).
pub const DEFAULT_BINARY_COLUMNS: [&str; 9] =
    ["id", "type", "x", "y", "z", "vx", "vy", "vz", "radius"];

/// Text or binary `dump custom`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DumpFormat {
    /// Text `dump custom` (`ITEM:` headers).
    Text,
    /// Binary `dump custom`.
    Binary,
}

impl DumpFormat {
    /// The format LIGGGHTS would use for this file name: binary if it ends in `.bin`.
    pub fn from_path(path: &Path) -> DumpFormat {
        if path.extension().is_some_and(|e| e == "bin") {
            DumpFormat::Binary
        } else {
            DumpFormat::Text
        }
    }
}

/// How to read a dump.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadOptions {
    /// Format; `None` decides by the file name ([`DumpFormat::from_path`]).
    pub format: Option<DumpFormat>,
    /// Column names of a binary dump, in the order of the `dump custom` command that wrote it.
    /// Ignored for text dumps, which name their columns.
    pub binary_columns: Vec<String>,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            format: None,
            binary_columns: DEFAULT_BINARY_COLUMNS
                .iter()
                .map(|s| s.to_string())
                .collect(),
        }
    }
}

impl ReadOptions {
    /// Forces a format instead of deciding by the file name.
    pub fn with_format(mut self, format: DumpFormat) -> Self {
        self.format = Some(format);
        self
    }

    /// Sets the column names of binary dumps.
    pub fn with_binary_columns<S: AsRef<str>>(mut self, names: &[S]) -> Self {
        self.binary_columns = names.iter().map(|s| s.as_ref().to_string()).collect();
        self
    }
}

/// Which snapshot of a file to read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Selection {
    /// The last snapshot (all others are skipped without decoding).
    #[default]
    Last,
    /// The snapshot at this 0-based position in the file.
    Index(usize),
    /// The first snapshot with this timestep.
    Timestep(u64),
}

/// A header whose body has not been consumed yet, and where that body starts.
#[derive(Clone)]
struct Pending {
    head: ChunkedHeader,
    body_pos: u64,
    body_line: u64,
}

/// Reads the snapshots of one dump one at a time; never holds more than one snapshot.
///
/// Use it as an iterator of `Result<Snapshot, DumpError>`, or step with
/// [`next_header`](DumpReader::next_header) and then [`read_body`](DumpReader::read_body) or
/// [`skip_body`](DumpReader::skip_body), or pick one snapshot with
/// [`select`](DumpReader::select). Skipping does not convert values: text rows are only
/// counted, binary chunks are seeked over.
pub struct DumpReader<R> {
    src: Source<R>,
    format: DumpFormat,
    binary_columns: Vec<String>,
    line: Vec<u8>,
    pending: Option<Pending>,
    next_index: usize,
    failed: bool,
}

impl DumpReader<File> {
    /// Opens a dump file.
    pub fn open(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Self, DumpError> {
        let path = path.as_ref();
        let file = File::open(path)
            .map_err(|e| DumpError::at(path, Location::Unknown, ErrorKind::Io(e)))?;
        let format = options
            .format
            .unwrap_or_else(|| DumpFormat::from_path(path));
        DumpReader::from_reader(file, path, &options.clone().with_format(format))
    }
}

impl<R: Read + Seek> DumpReader<R> {
    /// Reads a dump from any seekable byte source; `name` is used in error messages. Without
    /// [`ReadOptions::format`] the format is decided by `name`.
    pub fn from_reader(
        reader: R,
        name: impl Into<PathBuf>,
        options: &ReadOptions,
    ) -> Result<Self, DumpError> {
        let name = name.into();
        let format = options
            .format
            .unwrap_or_else(|| DumpFormat::from_path(&name));
        if format == DumpFormat::Binary {
            check_names(&options.binary_columns)
                .map_err(|k| DumpError::new(name.clone(), Location::Unknown, k))?;
        }
        Ok(DumpReader {
            src: Source::new(reader, name)?,
            format,
            binary_columns: options.binary_columns.clone(),
            line: Vec::new(),
            pending: None,
            next_index: 0,
            failed: false,
        })
    }

    /// The format being read.
    pub fn format(&self) -> DumpFormat {
        self.format
    }

    /// The file name used in error messages.
    pub fn name(&self) -> &Path {
        self.src.name()
    }

    /// Reads the next snapshot's header (skipping the body of a previous header not yet
    /// consumed). `Ok(None)` at the end of the file.
    pub fn next_header(&mut self) -> Result<Option<SnapshotHeader>, DumpError> {
        if self.pending.is_some() {
            self.skip_body()?;
        }
        let index = self.next_index;
        let head = match self.format {
            DumpFormat::Text => text::read_header(&mut self.src, &mut self.line, index)?
                .map(|header| ChunkedHeader { header, nchunks: 0 }),
            DumpFormat::Binary => binary::read_header(&mut self.src, &self.binary_columns, index)?,
        };
        let Some(head) = head else {
            return Ok(None);
        };
        self.next_index += 1;
        let header = head.header.clone();
        self.pending = Some(Pending {
            head,
            body_pos: self.src.pos(),
            body_line: self.src.line(),
        });
        Ok(Some(header))
    }

    fn take_pending(&mut self) -> Result<Pending, DumpError> {
        self.pending.take().ok_or_else(|| {
            DumpError::at(
                self.src.name(),
                Location::Unknown,
                ErrorKind::NoPendingHeader,
            )
        })
    }

    /// Reads the rows of the snapshot whose header [`next_header`](DumpReader::next_header)
    /// just returned.
    pub fn read_body(&mut self) -> Result<Snapshot, DumpError> {
        let p = self.take_pending()?;
        let data = match self.format {
            DumpFormat::Text => text::read_body(&mut self.src, &mut self.line, &p.head.header)?,
            DumpFormat::Binary => binary::read_body(&mut self.src, &p.head)?,
        };
        crate::snapshot::check_duplicates(&p.head.header.columns, &data).map_err(|kind| {
            // the `ITEM: ATOMS` line (text) or the chunk (binary) that names the columns
            let at = match self.format {
                DumpFormat::Text => Location::Line(p.body_line),
                DumpFormat::Binary => Location::Byte(p.body_pos),
            };
            DumpError::at(self.src.name(), at, kind)
        })?;
        Ok(Snapshot::from_parts(p.head.header, self.src.name(), data))
    }

    /// Steps over the rows of the pending snapshot without converting them (still checking
    /// that the snapshot is complete).
    pub fn skip_body(&mut self) -> Result<(), DumpError> {
        let p = self.take_pending()?;
        match self.format {
            DumpFormat::Text => text::skip_body(&mut self.src, &mut self.line, &p.head.header),
            DumpFormat::Binary => binary::skip_body(&mut self.src, &p.head),
        }
    }

    /// Headers of all remaining snapshots (bodies skipped).
    pub fn headers(&mut self) -> Result<Vec<SnapshotHeader>, DumpError> {
        let mut out = Vec::new();
        while let Some(h) = self.next_header()? {
            out.push(h);
        }
        if self.pending.is_some() {
            self.skip_body()?;
        }
        Ok(out)
    }

    /// Reads the selected snapshot among the remaining ones, skipping the others cheaply.
    /// [`Selection::Last`] scans to the end, then seeks back to the last snapshot's rows.
    pub fn select(&mut self, selection: Selection) -> Result<Snapshot, DumpError> {
        let mut last: Option<Pending> = None;
        let mut count = 0;
        while let Some(h) = self.next_header()? {
            count += 1;
            let hit = match selection {
                Selection::Last => {
                    last = self.pending.clone();
                    false
                }
                Selection::Index(i) => h.index == i,
                Selection::Timestep(t) => h.timestep == t,
            };
            if hit {
                return self.read_body();
            }
            self.skip_body()?;
        }
        let what = match selection {
            Selection::Last => "at all".to_string(),
            Selection::Index(i) => format!("with index {i} (read {count} snapshots)"),
            Selection::Timestep(t) => format!("with timestep {t} (read {count} snapshots)"),
        };
        let p = last.ok_or_else(|| {
            DumpError::at(
                self.src.name(),
                Location::Unknown,
                ErrorKind::NotFound(what),
            )
        })?;
        self.src.seek_to(p.body_pos, p.body_line)?;
        self.pending = Some(p);
        self.read_body()
    }
}

impl<R: Read + Seek> Iterator for DumpReader<R> {
    type Item = Result<Snapshot, DumpError>;

    /// The next snapshot; after the first error the iterator ends.
    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let result = match self.next_header() {
            Ok(None) => return None,
            Ok(Some(_)) => self.read_body(),
            Err(e) => Err(e),
        };
        self.failed = result.is_err();
        Some(result)
    }
}

/// Opens `path` and reads the selected snapshot.
pub fn read_snapshot(
    path: impl AsRef<Path>,
    options: &ReadOptions,
    selection: Selection,
) -> Result<Snapshot, DumpError> {
    DumpReader::open(path, options)?.select(selection)
}
