//! LIGGGHTS particle files: reading and writing `dump custom` files, text and binary, and
//! restart files ([`restart`]).
//!
//! # What this crate owns
//! The on-disk particle format of LIGGGHTS 3.8.0 (as packaged by Debian; the layout is the one
//! of LAMMPS's `dump custom` of that era) and its in-memory form:
//! - [`Snapshot`]: one timestep as a structure of arrays — timestep, optional label, box
//!   ([`BoxBounds`], including triclinic tilt and the boundary flags), column names and one
//!   `f64` vector per column — and [`Particles`], a typed view (id, type, position, velocity,
//!   radius, optional force, angular velocity, density, mass).
//! - [`DumpReader`]: a streaming reader over the snapshots of one file. It holds at most one
//!   snapshot; selecting one ([`Selection`]: last, by index, by timestep) steps over the others
//!   without converting their values (text rows are counted, binary chunks seeked over).
//! - [`write_text`], [`write_binary`], [`DumpWriter`]: writers producing files LIGGGHTS-compatible
//!   readers accept and that read back bit for bit.
//! - [`restart`]: LIGGGHTS 3.8 restart files of `atom_style granular` (`write_restart` /
//!   `read_restart`): a typed model (header records, groups, pair style, fix states, per-atom
//!   records with the contact history), a reader whose errors name the file and byte, and a
//!   writer that reproduces a file it read byte for byte.
//!
//! # Invariant
//! Every snapshot handed out has unique column names and columns of equal length, and its values
//! are exactly the values in the file (no unit conversion, no reordering; rows stay in file
//! order, which for LIGGGHTS is unsorted unless `dump_modify sort id`). Any input — truncated,
//! corrupt or hostile — yields a [`DumpError`] naming the file and the line (text) or byte
//! offset (binary), never a panic, and no allocation larger than the rest of the file implies.
//!
//! # Units
//! Values are in the units of the simulation, SI for `units si` (m, m/s, N, rad/s, kg/m³, kg).
//!
//! # Formats
//! Text (see [`text`](crate#text-format)) and binary (see [`binary layout`](crate#binary-format)).
//! Reference: the `dump` command of the LIGGGHTS 3.x / LAMMPS documentation, checked against
//! output of Debian's `liggghts` 3.8.0 (fixtures in `tests/fixtures/liggghts/`).
//!
//! ## Text format
//! `ITEM: TIMESTEP`, the step, optionally `ITEM: LABEL` and a label line, `ITEM: NUMBER OF
//! ATOMS`, the count, `ITEM: BOX BOUNDS` with two boundary letters per axis (`p f s m`, e.g.
//! `mm mm ff`; triclinic: `xy xz yz pp pp ff` and `lo hi tilt` lines), three bound lines,
//! `ITEM: ATOMS` with the column names, then one row per particle. Columns come in any order,
//! values in any form `strtod` accepts (`%g` by default: `1e-05`, `-0`, `5.5e+06`, `3`),
//! separated by spaces (LIGGGHTS leaves a trailing one). Snapshots follow each other.
//! LIGGGHTS prints box bounds with `%g` even when `dump_modify format` gives the values full
//! precision.
//!
//! ## Binary format
//! Per snapshot: i64 timestep, i64 particle count, i32 triclinic flag, 6 × i32 boundary codes
//! (0 p, 1 f, 2 s, 3 m), 6 × f64 bounds (`xlo xhi ylo yhi zlo zhi`), 3 × f64 tilt `xy xz yz`
//! if triclinic, i32 values per row, i32 chunk count; per chunk (one per MPI rank) an i32 value
//! count `n` and `n` f64 values, row-major. Little-endian. No column names: pass them in
//! [`ReadOptions::binary_columns`] (default [`DEFAULT_BINARY_COLUMNS`]).
//!
//! # Example
//! ```no_run
//! use dem_io::{read_snapshot, ReadOptions, Selection};
//! let snap = read_snapshot("post/dump.bin", &ReadOptions::default(), Selection::Last)?;
//! let p = snap.particles()?;
//! println!("step {}: {} particles, first at {:?}", snap.timestep, p.len(), p.position[0]);
//! # Ok::<(), dem_io::DumpError>(())
//! ```

#![warn(missing_docs)]

mod binary;
mod bounds;
mod error;
mod reader;
pub mod restart;
mod snapshot;
mod source;
mod text;

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

pub use binary::{write_binary, write_binary_chunks};
pub use bounds::{Boundary, BoxBounds, Cell};
pub use error::{DumpError, ErrorKind, Location, IN_MEMORY};
pub use reader::{
    read_snapshot, DumpFormat, DumpReader, ReadOptions, Selection, DEFAULT_BINARY_COLUMNS,
};
pub use snapshot::{Particles, Snapshot, SnapshotHeader};
pub use text::write_text;

/// Writes successive snapshots to one dump, text or binary.
pub struct DumpWriter<W: Write> {
    out: W,
    format: DumpFormat,
    chunks: usize,
}

impl DumpWriter<BufWriter<File>> {
    /// Creates (truncates) `path`; without `format` the format follows the name (`.bin` is
    /// binary), as in LIGGGHTS.
    pub fn create(path: impl AsRef<Path>, format: Option<DumpFormat>) -> io::Result<Self> {
        let path = path.as_ref();
        let format = format.unwrap_or_else(|| DumpFormat::from_path(path));
        Ok(DumpWriter::new(BufWriter::new(File::create(path)?), format))
    }
}

impl<W: Write> DumpWriter<W> {
    /// Writes snapshots in `format` to `out`.
    pub fn new(out: W, format: DumpFormat) -> Self {
        DumpWriter {
            out,
            format,
            chunks: 1,
        }
    }

    /// Number of chunks per binary snapshot (as written by that many MPI ranks; default 1).
    pub fn with_chunks(mut self, chunks: usize) -> Self {
        self.chunks = chunks.max(1);
        self
    }

    /// Appends one snapshot.
    pub fn write(&mut self, snapshot: &Snapshot) -> io::Result<()> {
        match self.format {
            DumpFormat::Text => write_text(&mut self.out, snapshot),
            DumpFormat::Binary => write_binary_chunks(&mut self.out, snapshot, self.chunks),
        }
    }

    /// Flushes and returns the underlying writer.
    pub fn finish(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}
