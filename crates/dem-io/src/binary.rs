//! Binary `dump custom` files (LIGGGHTS writes them when the file name ends in `.bin`).
//!
//! Layout of one snapshot, little-endian (the byte order of the machine that wrote it; every
//! platform Debian's LIGGGHTS runs on is little-endian), verified against Debian's LIGGGHTS
//! 3.8.0 (serial and 2 MPI ranks):
//!
//! | bytes | type | content |
//! |---|---|---|
//! | 8 | i64 | timestep |
//! | 8 | i64 | number of particles `natoms` |
//! | 4 | i32 | triclinic flag (0 or 1) |
//! | 24 | 6 × i32 | boundary codes x-lo x-hi y-lo y-hi z-lo z-hi (0 p, 1 f, 2 s, 3 m) |
//! | 48 | 6 × f64 | xlo xhi ylo yhi zlo zhi (bounding box if triclinic) |
//! | 24 | 3 × f64 | xy xz yz, only if triclinic |
//! | 4 | i32 | values per row `ncols` |
//! | 4 | i32 | number of chunks (one per MPI rank) |
//!
//! then per chunk an i32 `n` (values in the chunk, a multiple of `ncols`, possibly 0) followed by
//! `n` f64 values, row-major. The chunks together hold `natoms × ncols` values. Column names are
//! not stored: the reader is told them. Only little-endian files are read; a big-endian file
//! fails the header checks (triclinic flag, boundary codes, counts) or the chunk checks.

use std::io::{self, Read, Seek, Write};

use crate::bounds::{Boundary, BoxBounds};
use crate::error::{DumpError, ErrorKind, Location};
use crate::snapshot::{Snapshot, SnapshotHeader};
use crate::source::Source;

/// Values decoded per block while reading a chunk.
const BLOCK_VALUES: usize = 8192;

/// A header as read, with what the body reader needs beyond [`SnapshotHeader`] (text dumps
/// use it with `nchunks = 0`).
#[derive(Clone)]
pub(crate) struct ChunkedHeader {
    pub(crate) header: SnapshotHeader,
    pub(crate) nchunks: u32,
}

fn i32_at(b: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(b[at..at + 4].try_into().expect("4 bytes"))
}

fn i64_at(b: &[u8], at: usize) -> i64 {
    i64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
}

fn f64_at(b: &[u8], at: usize) -> f64 {
    f64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
}

/// Fills `buf` or fails with a truncation error at the first missing byte.
fn fill<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut [u8],
    expected: &str,
) -> Result<(), DumpError> {
    let start = src.pos();
    src.read_exact(buf)?.map_err(|got| {
        src.byte_err(
            start + got as u64,
            ErrorKind::Truncated {
                expected: expected.to_string(),
            },
        )
    })
}

/// Reads one snapshot header, leaving the source at the first chunk. `Ok(None)` at end of file.
pub(crate) fn read_header<R: Read + Seek>(
    src: &mut Source<R>,
    columns: &[String],
    index: usize,
) -> Result<Option<ChunkedHeader>, DumpError> {
    let offset = src.pos();
    if src.remaining() == 0 {
        return Ok(None);
    }
    let mut head = [0u8; 44];
    fill(src, &mut head, "a snapshot header")?;
    let name = src.name().to_path_buf();
    let bad = |at: u64, msg: String| {
        DumpError::at(
            &name,
            Location::Byte(offset + at),
            ErrorKind::BadHeader(msg),
        )
    };
    let timestep = i64_at(&head, 0);
    if timestep < 0 {
        // Newer LAMMPS writes -(length of "DUMPCUSTOM") and that string first.
        if (1..=64).contains(&-timestep) && head[8..].starts_with(b"DUMPCUSTOM") {
            return Err(src.byte_err(offset, ErrorKind::UnsupportedFormat));
        }
        return Err(bad(0, format!("negative timestep {timestep}")));
    }
    let natoms = i64_at(&head, 8);
    if natoms < 0 {
        return Err(bad(8, format!("negative number of atoms {natoms}")));
    }
    let triclinic = match i32_at(&head, 16) {
        0 => false,
        1 => true,
        t => return Err(bad(16, format!("triclinic flag {t} (expected 0 or 1)"))),
    };
    let mut boundary = [[Boundary::Periodic; 2]; 3];
    for k in 0..6 {
        let at = 20 + 4 * k;
        let code = i32_at(&head, at);
        boundary[k / 2][k % 2] = Boundary::from_code(code).ok_or_else(|| {
            src.byte_err(offset + at as u64, ErrorKind::BadBoundary(code.to_string()))
        })?;
    }
    let nbox = if triclinic { 9 } else { 6 };
    let mut rest = [0u8; 9 * 8 + 8];
    let rest = &mut rest[..nbox * 8 + 8];
    fill(src, rest, "the box bounds and column count")?;
    let v: Vec<f64> = (0..nbox).map(|k| f64_at(rest, 8 * k)).collect();
    let ncols_at = offset + 44 + 8 * nbox as u64;
    let ncols = i32_at(rest, 8 * nbox);
    let nchunks = i32_at(rest, 8 * nbox + 4);
    if usize::try_from(ncols).ok() != Some(columns.len()) {
        return Err(src.byte_err(
            ncols_at,
            ErrorKind::ColumnCountMismatch {
                in_file: ncols.max(0) as usize,
                given: columns.len(),
                names: columns.join(" "),
            },
        ));
    }
    let nchunks = u32::try_from(nchunks).map_err(|_| {
        bad(
            ncols_at + 4 - offset,
            format!("negative chunk count {nchunks}"),
        )
    })?;
    let bounds = BoxBounds {
        lo: [v[0], v[2], v[4]],
        hi: [v[1], v[3], v[5]],
        tilt: triclinic.then(|| [v[6], v[7], v[8]]),
        boundary,
    };
    Ok(Some(ChunkedHeader {
        header: SnapshotHeader {
            timestep: timestep as u64,
            label: None,
            natoms: natoms as u64,
            bounds,
            columns: columns.to_vec(),
            index,
            offset,
        },
        nchunks,
    }))
}

/// Reads a chunk's value count and checks it against what the snapshot still needs.
fn chunk_len<R: Read + Seek>(
    src: &mut Source<R>,
    chunk: u32,
    head: &ChunkedHeader,
    done: u64,
    total: u64,
) -> Result<u64, DumpError> {
    let at = src.pos();
    let mut b = [0u8; 4];
    fill(
        src,
        &mut b,
        &format!("the size of chunk {} of {}", chunk + 1, head.nchunks),
    )?;
    let n = i32::from_le_bytes(b);
    let ncols = head.header.columns.len() as u64;
    let bad = |msg: String| src.byte_err(at, ErrorKind::BadChunk(msg));
    let n = u64::try_from(n).map_err(|_| bad(format!("negative size {n}")))?;
    if n % ncols != 0 {
        return Err(bad(format!(
            "{n} values is not a multiple of {ncols} columns"
        )));
    }
    if n > total - done {
        return Err(bad(format!(
            "{n} more values exceed the {total} of {} atoms × {ncols} columns",
            head.header.natoms
        )));
    }
    if n * 8 > src.remaining() {
        return Err(src.byte_err(
            at + 4,
            ErrorKind::Truncated {
                expected: format!("{n} values ({} bytes), {} remain", n * 8, src.remaining()),
            },
        ));
    }
    Ok(n)
}

/// `natoms × ncols`, the number of values the chunks must hold.
fn total_values<R: Read + Seek>(src: &Source<R>, head: &ChunkedHeader) -> Result<u64, DumpError> {
    let h = &head.header;
    h.natoms.checked_mul(h.columns.len() as u64).ok_or_else(|| {
        src.byte_err(
            h.offset + 8,
            ErrorKind::BadHeader(format!(
                "{} atoms × {} columns overflows",
                h.natoms,
                h.columns.len()
            )),
        )
    })
}

/// Checks that all chunks together held exactly the announced number of values.
fn check_total<R: Read + Seek>(
    src: &Source<R>,
    head: &ChunkedHeader,
    done: u64,
    total: u64,
) -> Result<(), DumpError> {
    if done == total {
        return Ok(());
    }
    Err(src.byte_err(
        src.pos(),
        ErrorKind::BadChunk(format!(
            "{} chunks hold {done} values, but {} atoms × {} columns need {total}",
            head.nchunks,
            head.header.natoms,
            head.header.columns.len()
        )),
    ))
}

/// Decodes the chunks of a snapshot whose header was just read, into one vector per column.
/// Memory beyond the result: one block of 64 KiB.
pub(crate) fn read_body<R: Read + Seek>(
    src: &mut Source<R>,
    head: &ChunkedHeader,
) -> Result<Vec<Vec<f64>>, DumpError> {
    let ncols = head.header.columns.len();
    let natoms = usize::try_from(head.header.natoms).unwrap_or(usize::MAX);
    let total = total_values(src, head)?;
    // Reserve no more than the rest of the file can hold: a corrupt count cannot make us
    // allocate; the chunks then fail to add up.
    let fits = src.remaining() / (8 * ncols as u64);
    let reserve = natoms.min(usize::try_from(fits).unwrap_or(usize::MAX));
    let mut cols: Vec<Vec<f64>> = (0..ncols).map(|_| Vec::with_capacity(reserve)).collect();
    let mut block = vec![0u8; BLOCK_VALUES * 8];
    let mut done = 0;
    let mut col = 0;
    for chunk in 0..head.nchunks {
        let n = chunk_len(src, chunk, head, done, total)?;
        let mut left = n as usize;
        while left > 0 {
            let m = left.min(BLOCK_VALUES);
            fill(src, &mut block[..8 * m], "chunk values")?;
            for bytes in block[..8 * m].chunks_exact(8) {
                cols[col].push(f64::from_le_bytes(bytes.try_into().expect("8 bytes")));
                col += 1;
                if col == ncols {
                    col = 0;
                }
            }
            left -= m;
        }
        done += n;
    }
    check_total(src, head, done, total)?;
    Ok(cols)
}

/// Steps over the chunks of a snapshot, reading only their sizes.
pub(crate) fn skip_body<R: Read + Seek>(
    src: &mut Source<R>,
    head: &ChunkedHeader,
) -> Result<(), DumpError> {
    let total = total_values(src, head)?;
    let mut done = 0;
    for chunk in 0..head.nchunks {
        let n = chunk_len(src, chunk, head, done, total)?;
        src.skip(n * 8)?;
        done += n;
    }
    check_total(src, head, done, total)
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// Writes one snapshot as a LIGGGHTS binary `dump custom` snapshot in one chunk (as a serial
/// LIGGGHTS run does; more chunks only if one would exceed 2³¹−1 values). Column names and the
/// label are not part of the format. Append several snapshots for a multi-snapshot file.
pub fn write_binary<W: Write>(out: &mut W, snapshot: &Snapshot) -> io::Result<()> {
    write_binary_chunks(out, snapshot, 1)
}

/// Like [`write_binary`], with the rows split into `chunks` nearly equal chunks, as a run on
/// `chunks` MPI ranks would write them (at least one chunk; empty chunks are allowed).
pub fn write_binary_chunks<W: Write>(
    out: &mut W,
    snapshot: &Snapshot,
    chunks: usize,
) -> io::Result<()> {
    let n = snapshot.len();
    let cols: Vec<&[f64]> = snapshot.columns().map(|(_, c)| c).collect();
    let ncols = cols.len();
    let max_rows = (i32::MAX as usize / ncols).max(1);
    let chunks = chunks.max(1).max(n.div_ceil(max_rows));
    let b = &snapshot.bounds;
    let mut head = Vec::with_capacity(128);
    let timestep = i64::try_from(snapshot.timestep)
        .map_err(|_| invalid(format!("timestep {} exceeds i64", snapshot.timestep)))?;
    head.extend_from_slice(&timestep.to_le_bytes());
    head.extend_from_slice(&(n as i64).to_le_bytes());
    head.extend_from_slice(&i32::from(b.tilt.is_some()).to_le_bytes());
    for pair in &b.boundary {
        for side in pair {
            head.extend_from_slice(&side.code().to_le_bytes());
        }
    }
    for axis in 0..3 {
        head.extend_from_slice(&b.lo[axis].to_le_bytes());
        head.extend_from_slice(&b.hi[axis].to_le_bytes());
    }
    if let Some(t) = b.tilt {
        for v in t {
            head.extend_from_slice(&v.to_le_bytes());
        }
    }
    let as_i32 = |v: usize, what: &str| {
        i32::try_from(v).map_err(|_| invalid(format!("{what} {v} exceeds i32")))
    };
    head.extend_from_slice(&as_i32(ncols, "column count")?.to_le_bytes());
    head.extend_from_slice(&as_i32(chunks, "chunk count")?.to_le_bytes());
    out.write_all(&head)?;

    let mut block: Vec<u8> = Vec::with_capacity(BLOCK_VALUES * 8 + ncols * 8);
    let mut start = 0;
    for c in 0..chunks {
        let end = n * (c + 1) / chunks;
        let values = (end - start) * ncols;
        out.write_all(&as_i32(values, "chunk size")?.to_le_bytes())?;
        for row in start..end {
            for col in &cols {
                block.extend_from_slice(&col[row].to_le_bytes());
            }
            if block.len() >= BLOCK_VALUES * 8 {
                out.write_all(&block)?;
                block.clear();
            }
        }
        out.write_all(&block)?;
        block.clear();
        start = end;
    }
    Ok(())
}
