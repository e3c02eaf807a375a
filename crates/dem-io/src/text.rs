//! Text `dump custom` files: header parsing, row parsing or skipping, and writing.
//!
//! A snapshot is
//! ```text
//! ITEM: TIMESTEP
//! 3000
//! ITEM: LABEL                      (optional, `dump_modify … label`)
//! SETTLE
//! ITEM: NUMBER OF ATOMS
//! 200
//! ITEM: BOX BOUNDS mm mm ff        (triclinic: `ITEM: BOX BOUNDS xy xz yz pp pp ff`)
//! -0.01 0.01                       (triclinic: `lo_bound hi_bound tilt` per line)
//! -0.01 0.01
//! 0 0.03
//! ITEM: ATOMS id type x y z …
//! 127 1 0.0058 …                   (NUMBER OF ATOMS rows, any column order)
//! ```
//! repeated for every snapshot. `ITEM: UNITS` and `ITEM: TIME` (newer LAMMPS) are skipped.

use std::fmt::Write as _;
use std::io::{self, Read, Seek, Write};

use crate::bounds::{Boundary, BoxBounds};
use crate::error::{shorten, DumpError, ErrorKind};
use crate::snapshot::{check_names, Snapshot, SnapshotHeader};
use crate::source::Source;

fn is_blank(line: &[u8]) -> bool {
    line.iter().all(u8::is_ascii_whitespace)
}

fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(u8::is_ascii_whitespace)
        .filter(|t| !t.is_empty())
}

fn parse_f64(tok: &[u8]) -> Option<f64> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

fn parse_u64(tok: &[u8]) -> Option<u64> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

/// The text after `ITEM:` on a header line, trimmed, if the line is one.
fn item_of(line: &[u8]) -> Option<String> {
    let rest = line.trim_ascii_start().strip_prefix(b"ITEM:")?;
    Some(String::from_utf8_lossy(rest).trim().to_string())
}

/// Reads the next line or fails with "file ends early: expected {expected}".
fn need_line<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut Vec<u8>,
    expected: &str,
) -> Result<(), DumpError> {
    if src.read_line(buf)? {
        Ok(())
    } else {
        Err(src.line_err(ErrorKind::Truncated {
            expected: expected.to_string(),
        }))
    }
}

/// Reads a line holding exactly one non-negative integer.
fn single_u64<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut Vec<u8>,
    what: &'static str,
) -> Result<u64, DumpError> {
    need_line(src, buf, what)?;
    let mut toks = tokens(buf);
    let value = match (toks.next(), toks.next()) {
        (Some(t), None) => parse_u64(t),
        _ => None,
    };
    value.ok_or_else(|| {
        src.line_err(ErrorKind::BadNumber {
            what,
            token: shorten(buf),
        })
    })
}

/// Parses the flags after `BOX BOUNDS`: optional `xy xz yz`, then three two-letter flags.
fn parse_box_flags(rest: &str) -> Result<(bool, [[Boundary; 2]; 3]), ErrorKind> {
    let mut words: Vec<&str> = rest.split_whitespace().collect();
    let triclinic = words.first() == Some(&"xy");
    if triclinic {
        if words.get(1..3) != Some(&["xz", "yz"][..]) {
            return Err(ErrorKind::BadBoundary(rest.to_string()));
        }
        words.drain(..3);
    }
    let mut boundary = [[Boundary::Periodic; 2]; 3];
    match words.len() {
        // Very old dumps have no flags; LAMMPS's reader assumes periodic then too.
        0 => {}
        3 => {
            for (axis, word) in words.iter().enumerate() {
                let b = word.as_bytes();
                let pair = (b.len() == 2)
                    .then(|| Some([Boundary::from_letter(b[0])?, Boundary::from_letter(b[1])?]))
                    .flatten();
                boundary[axis] = pair.ok_or_else(|| ErrorKind::BadBoundary(word.to_string()))?;
            }
        }
        _ => return Err(ErrorKind::BadBoundary(rest.to_string())),
    }
    Ok((triclinic, boundary))
}

fn read_bounds<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut Vec<u8>,
    rest: &str,
) -> Result<BoxBounds, DumpError> {
    let (triclinic, boundary) = parse_box_flags(rest).map_err(|k| src.line_err(k))?;
    let per_line = if triclinic { 3 } else { 2 };
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    let mut tilt = [0.0; 3];
    for axis in 0..3 {
        need_line(src, buf, "three box bound lines")?;
        let mut vals = [0.0; 3];
        let mut count = 0;
        for tok in tokens(buf) {
            if count < per_line {
                vals[count] = parse_f64(tok).ok_or_else(|| {
                    src.line_err(ErrorKind::BadNumber {
                        what: "a box bound",
                        token: shorten(tok),
                    })
                })?;
            }
            count += 1;
        }
        if count != per_line {
            return Err(src.line_err(ErrorKind::Unexpected {
                expected: format!("{per_line} numbers (box bounds)"),
                found: shorten(buf),
            }));
        }
        lo[axis] = vals[0];
        hi[axis] = vals[1];
        tilt[axis] = vals[2];
    }
    Ok(BoxBounds {
        lo,
        hi,
        tilt: triclinic.then_some(tilt),
        boundary,
    })
}

/// Reads one snapshot header, leaving the source at its first row. `Ok(None)` at end of file
/// (blank lines between snapshots and at the end are allowed).
pub(crate) fn read_header<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut Vec<u8>,
    index: usize,
) -> Result<Option<SnapshotHeader>, DumpError> {
    let offset = loop {
        let start = src.pos();
        if !src.read_line(buf)? {
            return Ok(None);
        }
        if !is_blank(buf) {
            break start;
        }
    };
    let mut timestep = None;
    let mut label = None;
    let mut natoms = None;
    let mut bounds = None;
    loop {
        let item = item_of(buf).ok_or_else(|| {
            let numeric = tokens(buf).next().and_then(parse_f64).is_some();
            let expected = match (timestep.is_some(), index > 0 && numeric) {
                (true, _) => "an ITEM: line",
                (false, true) => {
                    "ITEM: TIMESTEP (the previous snapshot has more rows than its NUMBER OF ATOMS)"
                }
                (false, false) => "ITEM: TIMESTEP",
            };
            src.line_err(ErrorKind::Unexpected {
                expected: expected.into(),
                found: shorten(buf),
            })
        })?;
        let twice = || {
            src.line_err(ErrorKind::BadHeader(format!(
                "`ITEM: {item}` twice in one snapshot"
            )))
        };
        match item.as_str() {
            "TIMESTEP" => {
                if timestep.is_some() {
                    return Err(twice());
                }
                timestep = Some(single_u64(src, buf, "the timestep")?);
            }
            "NUMBER OF ATOMS" => {
                if natoms.is_some() {
                    return Err(twice());
                }
                natoms = Some(single_u64(src, buf, "the number of atoms")?);
            }
            "LABEL" => {
                if label.is_some() {
                    return Err(twice());
                }
                need_line(src, buf, "the label")?;
                label = Some(String::from_utf8_lossy(buf).trim().to_string());
            }
            "UNITS" | "TIME" => need_line(src, buf, "the value of the item")?,
            _ if item == "BOX BOUNDS" || item.starts_with("BOX BOUNDS ") => {
                if bounds.is_some() {
                    return Err(twice());
                }
                bounds = Some(read_bounds(src, buf, &item["BOX BOUNDS".len()..])?);
            }
            _ if item == "ATOMS" || item.starts_with("ATOMS ") => {
                let columns: Vec<String> = item["ATOMS".len()..]
                    .split_whitespace()
                    .map(str::to_string)
                    .collect();
                check_names(&columns).map_err(|k| src.line_err(k))?;
                let missing = |what| src.line_err(ErrorKind::MissingItem(what));
                let timestep = timestep.ok_or_else(|| missing("TIMESTEP"))?;
                let natoms = natoms.ok_or_else(|| missing("NUMBER OF ATOMS"))?;
                let bounds = bounds.ok_or_else(|| missing("BOX BOUNDS"))?;
                return Ok(Some(SnapshotHeader {
                    timestep,
                    label,
                    natoms,
                    bounds,
                    columns,
                    index,
                    offset,
                }));
            }
            _ => return Err(src.line_err(ErrorKind::UnknownItem(item.clone()))),
        }
        need_line(src, buf, "ITEM: ATOMS")?;
    }
}

/// Reads row `row` of `natoms` into `buf`, failing at end of file or at the next header.
fn next_row<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut Vec<u8>,
    natoms: u64,
    row: u64,
) -> Result<(), DumpError> {
    if !src.read_line(buf)? {
        return Err(src.line_err(ErrorKind::Truncated {
            expected: format!("{natoms} rows, found {row}"),
        }));
    }
    if buf.trim_ascii_start().starts_with(b"ITEM:") {
        return Err(src.line_err(ErrorKind::TooFewRows {
            expected: natoms,
            found: row,
        }));
    }
    Ok(())
}

/// Parses the rows of a snapshot whose header was just read, into one vector per column.
pub(crate) fn read_body<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut Vec<u8>,
    header: &SnapshotHeader,
) -> Result<Vec<Vec<f64>>, DumpError> {
    let ncols = header.columns.len();
    // Every value takes at least two bytes (a digit and a separator): reserve no more than the
    // rest of the file can hold, so a corrupt count cannot make us allocate.
    let fits = src.remaining() / (2 * ncols as u64);
    let reserve = usize::try_from(header.natoms.min(fits)).unwrap_or(usize::MAX);
    let mut cols: Vec<Vec<f64>> = (0..ncols).map(|_| Vec::with_capacity(reserve)).collect();
    for row in 0..header.natoms {
        next_row(src, buf, header.natoms, row)?;
        let mut found = 0;
        for tok in tokens(buf) {
            if found < ncols {
                let v = parse_f64(tok).ok_or_else(|| {
                    src.line_err(ErrorKind::BadNumber {
                        what: "a value",
                        token: shorten(tok),
                    })
                })?;
                cols[found].push(v);
            }
            found += 1;
        }
        if found != ncols {
            return Err(src.line_err(ErrorKind::WrongValueCount {
                expected: ncols,
                found,
            }));
        }
    }
    Ok(cols)
}

/// Steps over the rows of a snapshot without converting any value.
pub(crate) fn skip_body<R: Read + Seek>(
    src: &mut Source<R>,
    buf: &mut Vec<u8>,
    header: &SnapshotHeader,
) -> Result<(), DumpError> {
    for row in 0..header.natoms {
        next_row(src, buf, header.natoms, row)?;
    }
    Ok(())
}

/// Appends `v` so that parsing it gives back the same `f64` bit for bit (see [`write_text`]).
pub(crate) fn push_value(s: &mut String, v: f64) {
    let r = if v.fract() == 0.0 && v.abs() < 1e16 {
        write!(s, "{v}")
    } else {
        write!(s, "{v:e}")
    };
    r.expect("writing to a String cannot fail");
}

const FLUSH_AT: usize = 1 << 16;

/// Writes one snapshot as a LIGGGHTS text `dump custom` snapshot.
///
/// The layout is LIGGGHTS's (including the trailing space after each value), but every value,
/// box bounds included (LIGGGHTS uses `%g` there), reads back bit for bit: integers below 10¹⁶
/// plainly (`286`, `-0`), anything else in the shortest scientific form that round-trips
/// (`5e-4`, `1.3089969389957471e-6`); C's `strtod` reads both. The label, if any, is written
/// as `ITEM: LABEL` after the timestep (LIGGGHTS itself writes it only for orthogonal boxes);
/// it must not contain a newline, and surrounding spaces are not preserved. Append several
/// snapshots to one writer for a multi-snapshot file. Output goes out in blocks of about
/// 64 KiB, so `out` need not be buffered. Non-finite values are written as `NaN`/`inf`.
pub fn write_text<W: Write>(out: &mut W, snapshot: &Snapshot) -> io::Result<()> {
    let mut s = String::with_capacity(FLUSH_AT + 4096);
    let b = &snapshot.bounds;
    let _ = write!(s, "ITEM: TIMESTEP\n{}\n", snapshot.timestep);
    if let Some(label) = &snapshot.label {
        if label.contains('\n') {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "a dump label cannot contain a newline",
            ));
        }
        let _ = writeln!(s, "ITEM: LABEL\n{label}");
    }
    let _ = write!(
        s,
        "ITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS ",
        snapshot.len()
    );
    if b.tilt.is_some() {
        s.push_str("xy xz yz ");
    }
    s.push_str(&b.boundary_string());
    s.push('\n');
    for axis in 0..3 {
        push_value(&mut s, b.lo[axis]);
        s.push(' ');
        push_value(&mut s, b.hi[axis]);
        if let Some(t) = b.tilt {
            s.push(' ');
            push_value(&mut s, t[axis]);
        }
        s.push('\n');
    }
    s.push_str("ITEM: ATOMS ");
    for name in snapshot.column_names() {
        s.push_str(name);
        s.push(' ');
    }
    s.push('\n');
    let cols: Vec<&[f64]> = snapshot.columns().map(|(_, c)| c).collect();
    for row in 0..snapshot.len() {
        for c in &cols {
            push_value(&mut s, c[row]);
            s.push(' ');
        }
        s.push('\n');
        if s.len() >= FLUSH_AT {
            out.write_all(s.as_bytes())?;
            s.clear();
        }
    }
    out.write_all(s.as_bytes())
}
