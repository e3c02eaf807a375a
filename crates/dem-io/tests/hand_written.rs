//! Hand-written dumps: the accepted variety of the text format, and every kind of bad input
//! reported with its file and line (text) or byte offset (binary).

mod common;

use std::io::Cursor;

use dem_io::{
    write_binary, Boundary, BoxBounds, DumpError, DumpReader, ErrorKind, Location, ReadOptions,
    Selection, Snapshot,
};

fn text_reader(text: &str) -> DumpReader<Cursor<Vec<u8>>> {
    DumpReader::from_reader(
        Cursor::new(text.as_bytes().to_vec()),
        "hand.txt",
        &ReadOptions::default(),
    )
    .unwrap()
}

fn read_text(text: &str) -> Result<Vec<Snapshot>, DumpError> {
    text_reader(text).collect()
}

fn text_err(text: &str) -> DumpError {
    let err = read_text(text).expect_err("input should be rejected");
    assert!(
        err.to_string().starts_with("hand.txt:"),
        "error does not name the file and line: {err}"
    );
    err
}

const HEADER: &str = "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp ff sm\n\
                      0 1\n0 2\n0 3\nITEM: ATOMS id type x y z\n";

#[test]
fn columns_in_any_order_with_g_values_and_trailing_spaces() {
    let text = "ITEM: TIMESTEP\n  42  \nITEM: LABEL\nmy run \nITEM: NUMBER OF ATOMS\n3\n\
                ITEM: BOX BOUNDS pf fs mm\n-1e-05 5.5e+06 \n-0 1\n0 3\n\
                ITEM: ATOMS vz radius z type id y x vx vy \n\
                -0 0.0005 1e-05 1 7 -0 5.5e+06 3 -2.5 \n\
                1.5 1e-3 2 2 8 4 5 6 7\r\n\
                \t9  8 7 1 9 6 5 4 3\n\n\n";
    let snaps = read_text(text).unwrap();
    assert_eq!(snaps.len(), 1);
    let s = &snaps[0];
    assert_eq!(s.timestep, 42);
    assert_eq!(s.label.as_deref(), Some("my run"));
    assert_eq!(s.bounds.lo, [-1e-5, -0.0, 0.0]);
    assert!(s.bounds.lo[1].is_sign_negative());
    assert_eq!(s.bounds.hi, [5.5e6, 1.0, 3.0]);
    use Boundary::*;
    assert_eq!(
        s.bounds.boundary,
        [[Periodic, Fixed], [Fixed, Shrink], [ShrinkMin, ShrinkMin]]
    );
    assert_eq!(s.column("vz").unwrap(), [-0.0, 1.5, 9.0]);
    assert!(s.column("vz").unwrap()[0].is_sign_negative());
    let p = s.particles().unwrap();
    assert_eq!(p.id, [7, 8, 9]);
    assert_eq!(p.atom_type, [1, 2, 1]);
    assert_eq!(p.position[0], [5.5e6, -0.0, 1e-5]);
    assert_eq!(p.position[1], [5.0, 4.0, 2.0]);
    assert_eq!(p.velocity[0], [3.0, -2.5, -0.0]);
    assert_eq!(p.radius, [0.0005, 0.001, 8.0]);
    assert_eq!(p.force, None);
}

#[test]
fn several_snapshots_triclinic_and_scaled() {
    let text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\n\
                ITEM: BOX BOUNDS xy xz yz pp pp ff\n-1 12 2\n0 11.5 -1\n0 10 1.5\n\
                ITEM: ATOMS id type xs ys zs vx vy vz diameter\n\
                1 1 0.5 0.5 0.5 0 0 0 2\n\
                ITEM: TIMESTEP\n10\nITEM: NUMBER OF ATOMS\n0\n\
                ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\nITEM: ATOMS id\n";
    let snaps = read_text(text).unwrap();
    assert_eq!(snaps.len(), 2);
    let b = snaps[0].bounds;
    assert_eq!(b.tilt, Some([2.0, -1.0, 1.5]));
    // Cell: xlo = −1 − min(0, 2, −1, 1) = 0, xhi = 12 − max(0, 2, −1, 1) = 10,
    // ylo = 0 − min(0, 1.5) = 0, yhi = 11.5 − 1.5 = 10. Centre: (0.5·10 + 0.5·2 − 0.5·1,
    // 0.5·10 + 0.5·1.5, 0.5·10).
    let cell = b.cell();
    assert_eq!(cell.origin, [0.0, 0.0, 0.0]);
    assert_eq!(
        cell.edges,
        [[10.0, 0.0, 0.0], [2.0, 10.0, 0.0], [-1.0, 1.5, 10.0]]
    );
    let p = snaps[0].particles().unwrap();
    assert_eq!(p.position, [[5.5, 5.75, 5.0]]);
    assert_eq!(p.radius, [1.0]);
    assert_eq!(
        BoxBounds::triclinic([0.0; 3], [10.0; 3], [2.0, -1.0, 1.5], b.boundary),
        b
    );
    assert_eq!(snaps[1].timestep, 10);
    assert!(snaps[1].is_empty());
    assert_eq!(snaps[1].column_names(), ["id"]);
}

#[test]
fn selection_skips_snapshots_with_unparsed_rows() {
    // Rows of skipped snapshots are not converted: garbage values there do not matter,
    // but their number does.
    let text = format!("{HEADER}1 1 x y z\n2 1 u v w\n{HEADER}1 1 0 0 0\n2 1 1 1 1\n");
    let mut r = text_reader(&text);
    let s = r.select(Selection::Last).unwrap();
    assert_eq!(s.column("z").unwrap(), [0.0, 1.0]);
    let err = text_reader(&text).select(Selection::Index(0)).unwrap_err();
    assert!(matches!(err.kind, ErrorKind::BadNumber { .. }));
    assert_eq!(err.location, Location::Line(10));
}

#[test]
fn missing_column_names_file_and_column() {
    let s = read_text(&format!("{HEADER}1 1 0 0 0\n2 1 1 1 1\n")).unwrap();
    let err = s[0].particles().unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.starts_with("hand.txt: timestep 100: no column `vx vy vz`"),
        "{msg}"
    );
    assert!(msg.contains("columns: id type x y z"), "{msg}");
    let err = s[0].require("radius").unwrap_err();
    assert!(matches!(err.kind, ErrorKind::MissingColumn { ref column, .. } if column == "radius"));
}

#[test]
fn fractional_id_is_a_bad_value() {
    let s = read_text(&format!("{HEADER}1.5 1 0 0 0\n2 1 1 1 1\n")).unwrap();
    let err = s[0].ids().unwrap_err();
    assert!(
        matches!(err.kind, ErrorKind::BadValue { row: 0, .. }),
        "{err}"
    );
}

fn assert_text_error(text: &str, line: u64, check: impl Fn(&ErrorKind) -> bool) {
    let err = text_err(text);
    assert!(check(&err.kind), "unexpected kind: {err}");
    assert_eq!(err.location, Location::Line(line), "{err}");
}

#[test]
fn too_few_rows_before_next_snapshot() {
    let text = format!("{HEADER}1 1 0 0 0\n{HEADER}1 1 0 0 0\n2 1 0 0 0\n");
    assert_text_error(&text, 11, |k| {
        matches!(
            k,
            ErrorKind::TooFewRows {
                expected: 2,
                found: 1
            }
        )
    });
}

#[test]
fn too_many_rows() {
    let text = format!("{HEADER}1 1 0 0 0\n2 1 0 0 0\n3 1 0 0 0\n");
    let err = text_err(&text);
    assert_eq!(err.location, Location::Line(12));
    assert!(
        err.to_string()
            .contains("more rows than its NUMBER OF ATOMS"),
        "{err}"
    );
}

#[test]
fn truncated_rows_and_headers() {
    assert_text_error(&format!("{HEADER}1 1 0 0 0\n"), 10, |k| {
        matches!(k, ErrorKind::Truncated { .. })
    });
    assert_text_error("ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n", 3, |k| {
        matches!(k, ErrorKind::Truncated { .. })
    });
    assert_text_error(
        "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n0\nITEM: BOX BOUNDS pp pp pp\n0 1\n",
        6,
        |k| matches!(k, ErrorKind::Truncated { .. }),
    );
}

#[test]
fn bad_tokens_and_counts() {
    assert_text_error(
        &format!("{HEADER}1 1 0 0 0\n2 1 0 zero 0\n"),
        11,
        |k| matches!(k, ErrorKind::BadNumber { token, .. } if token == "zero"),
    );
    assert_text_error(&format!("{HEADER}1 1 0 0 0\n2 1 0 0\n"), 11, |k| {
        matches!(
            k,
            ErrorKind::WrongValueCount {
                expected: 5,
                found: 4
            }
        )
    });
    assert_text_error(&format!("{HEADER}1 1 0 0 0 9 9\n2 1 0 0 0\n"), 10, |k| {
        matches!(
            k,
            ErrorKind::WrongValueCount {
                expected: 5,
                found: 7
            }
        )
    });
    assert_text_error(&format!("{HEADER}1 1 0 0 0\n\n"), 11, |k| {
        matches!(k, ErrorKind::WrongValueCount { found: 0, .. })
    });
    assert_text_error(&HEADER.replace("\n100\n", "\n-3\n"), 2, |k| {
        matches!(k, ErrorKind::BadNumber { .. })
    });
    assert_text_error(&HEADER.replace("\n2\n", "\n2 3\n"), 4, |k| {
        matches!(k, ErrorKind::BadNumber { .. })
    });
    assert_text_error(&HEADER.replace("0 2\n", "0 2 7\n"), 7, |k| {
        matches!(k, ErrorKind::Unexpected { .. })
    });
}

#[test]
fn bad_headers() {
    // a column named twice: LIGGGHTS writes `type type` when a deck names it twice (CFDEM-PFM's
    // tutorials do); equal values are read, different ones are an error at `ITEM: ATOMS`
    let twice = HEADER.replace("id type x", "id type type");
    let s = read_text(&format!("{twice}1 2 2 0 0\n2 1 1 1 1\n")).unwrap();
    assert_eq!(s[0].column("type").unwrap(), [2.0, 1.0]);
    assert_text_error(
        &format!("{twice}1 2 3 0 0\n2 1 1 1 1\n"),
        9,
        |k| matches!(k, ErrorKind::DuplicateColumn(c) if c == "type"),
    );
    assert_text_error(
        &HEADER.replace("pp ff sm", "pp fx sm"),
        5,
        |k| matches!(k, ErrorKind::BadBoundary(b) if b == "fx"),
    );
    assert_text_error(&HEADER.replace("pp ff sm", "pp ff"), 5, |k| {
        matches!(k, ErrorKind::BadBoundary(_))
    });
    assert_text_error(
        &HEADER.replace("NUMBER OF ATOMS", "NUMBER OF BEES"),
        3,
        |k| matches!(k, ErrorKind::UnknownItem(i) if i == "NUMBER OF BEES"),
    );
    assert_text_error(&HEADER.replace("ITEM: NUMBER OF ATOMS\n2\n", ""), 7, |k| {
        matches!(k, ErrorKind::MissingItem("NUMBER OF ATOMS"))
    });
    assert_text_error(
        &HEADER.replace("ITEM: ATOMS id type x y z", "ITEM: ATOMS"),
        9,
        |k| matches!(k, ErrorKind::NoColumns),
    );
    assert_text_error("hello\n", 1, |k| matches!(k, ErrorKind::Unexpected { .. }));
    assert_text_error(&format!("{HEADER}{HEADER}"), 10, |k| {
        matches!(k, ErrorKind::TooFewRows { found: 0, .. })
    });
}

#[test]
fn absurd_atom_count_does_not_allocate() {
    // 10¹⁵ rows × 5 columns would be 40 PB; the reader reserves only what the file can hold.
    let text = HEADER.replace("\n2\n", "\n1000000000000000\n");
    assert_text_error(
        &format!("{text}1 1 0 0 0\n"),
        10,
        |k| matches!(k, ErrorKind::Truncated { expected } if expected == "1000000000000000 rows, found 1"),
    );
}

#[test]
fn binary_garbage_read_as_text_fails_quickly() {
    let garbage: Vec<u8> = (0..3_000_000u32).map(|i| (i % 251) as u8 | 1).collect();
    let mut r =
        DumpReader::from_reader(Cursor::new(garbage), "x.txt", &ReadOptions::default()).unwrap();
    let err = r.next_header().unwrap_err();
    assert!(matches!(err.kind, ErrorKind::LineTooLong(_)), "{err}");
}

// ---------------------------------------------------------------- binary

fn names(n: &[&str]) -> Vec<String> {
    n.iter().map(|s| s.to_string()).collect()
}

/// A valid two-snapshot binary dump with columns `id x`, written by the crate's writer (whose
/// layout the LIGGGHTS fixtures pin down).
fn two_snapshots() -> Vec<u8> {
    let bounds = BoxBounds::orthogonal([0.0; 3], [1.0; 3], Boundary::Periodic);
    let mut out = Vec::new();
    for step in [5, 10] {
        let s = Snapshot::new(
            step,
            bounds,
            names(&["id", "x"]),
            vec![vec![1.0, 2.0, 3.0], vec![0.25, 0.5, 0.75]],
        )
        .unwrap();
        write_binary(&mut out, &s).unwrap();
    }
    out
}

/// Size of one snapshot above: header 100 bytes + chunk size 4 + 6 values.
const SNAP: usize = 100 + 4 + 6 * 8;

fn read_bin(bytes: Vec<u8>, cols: &[&str]) -> Result<Vec<Snapshot>, DumpError> {
    let opts = ReadOptions::default().with_binary_columns(cols);
    DumpReader::from_reader(Cursor::new(bytes), "hand.bin", &opts)
        .unwrap()
        .collect()
}

fn assert_bin_error(bytes: Vec<u8>, byte: u64, check: impl Fn(&ErrorKind) -> bool) {
    let err = read_bin(bytes, &["id", "x"]).expect_err("input should be rejected");
    assert!(check(&err.kind), "unexpected kind: {err}");
    assert_eq!(err.location, Location::Byte(byte), "{err}");
    assert!(
        err.to_string()
            .starts_with(&format!("hand.bin (byte {byte}): ")),
        "{err}"
    );
}

fn put_i32(b: &mut [u8], at: usize, v: i32) {
    b[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

#[test]
fn binary_reads_back() {
    let snaps = read_bin(two_snapshots(), &["id", "x"]).unwrap();
    assert_eq!(snaps.len(), 2);
    assert_eq!(snaps[1].timestep, 10);
    assert_eq!(snaps[1].column("x").unwrap(), [0.25, 0.5, 0.75]);
    assert_eq!(two_snapshots().len(), 2 * SNAP);
}

#[test]
fn binary_truncated_anywhere_in_the_second_snapshot() {
    let full = two_snapshots();
    // Header cut: error at the first missing byte.
    assert_bin_error(full[..SNAP + 30].to_vec(), (SNAP + 30) as u64, |k| {
        matches!(k, ErrorKind::Truncated { .. })
    });
    // Values cut: the chunk of 6 values (48 bytes) has only 16 bytes left.
    assert_bin_error(full[..SNAP + 120].to_vec(), (SNAP + 104) as u64, |k| {
        matches!(k, ErrorKind::Truncated { .. })
    });
    // Cut right after the chunk size.
    assert_bin_error(full[..SNAP + 102].to_vec(), (SNAP + 102) as u64, |k| {
        matches!(k, ErrorKind::Truncated { .. })
    });
}

#[test]
fn binary_chunks_must_add_up() {
    // Two chunks (as from two MPI ranks) holding 4 + 6 values where 3 atoms × 2 columns = 6.
    let mut b = two_snapshots()[..100].to_vec();
    put_i32(&mut b, 96, 2);
    b.extend_from_slice(&4i32.to_le_bytes());
    b.extend_from_slice(&[0u8; 32]);
    b.extend_from_slice(&6i32.to_le_bytes());
    b.extend_from_slice(&[0u8; 48]);
    assert_bin_error(b, 136, |k| matches!(k, ErrorKind::BadChunk(_)));
}

#[test]
fn binary_bad_chunk_sizes() {
    let mut b = two_snapshots();
    put_i32(&mut b, 100, 5); // not a multiple of 2 columns
    assert_bin_error(b, 100, |k| matches!(k, ErrorKind::BadChunk(_)));
    let mut b = two_snapshots();
    put_i32(&mut b, 100, -2);
    assert_bin_error(b, 100, |k| matches!(k, ErrorKind::BadChunk(_)));
    let mut b = two_snapshots();
    put_i32(&mut b, 100, 4); // fewer values than 3 atoms × 2 columns: found after the chunk
    assert_bin_error(b, 136, |k| matches!(k, ErrorKind::BadChunk(_)));
}

#[test]
fn binary_bad_header_fields() {
    let mut b = two_snapshots();
    b[8..16].copy_from_slice(&(1i64 << 60).to_le_bytes()); // absurd: no huge allocation
    assert_bin_error(b, 152, |k| matches!(k, ErrorKind::BadChunk(_)));
    let mut b = two_snapshots();
    b[8..16].copy_from_slice(&(i64::MAX).to_le_bytes());
    assert_bin_error(b, 152, |k| matches!(k, ErrorKind::BadChunk(_)));
    let mut b = two_snapshots();
    b[8..16].copy_from_slice(&(-1i64).to_le_bytes());
    assert_bin_error(b, 8, |k| matches!(k, ErrorKind::BadHeader(_)));
    let mut b = two_snapshots();
    put_i32(&mut b, 16, 7);
    assert_bin_error(b, 16, |k| matches!(k, ErrorKind::BadHeader(_)));
    let mut b = two_snapshots();
    put_i32(&mut b, 32, 4);
    assert_bin_error(
        b,
        32,
        |k| matches!(k, ErrorKind::BadBoundary(c) if c == "4"),
    );
    let mut b = two_snapshots();
    put_i32(&mut b, 96, i32::MAX); // chunk 2 would be read from the next snapshot's header
    assert_bin_error(b, 152, |k| matches!(k, ErrorKind::BadChunk(_)));
    let mut b = two_snapshots();
    b[0..8].copy_from_slice(&(-10i64).to_le_bytes());
    b[8..18].copy_from_slice(b"DUMPCUSTOM");
    assert_bin_error(b, 0, |k| matches!(k, ErrorKind::UnsupportedFormat));
}

#[test]
fn binary_column_names_must_match_and_be_unique() {
    let err = read_bin(two_snapshots(), &["id", "x", "y"]).unwrap_err();
    assert!(matches!(
        err.kind,
        ErrorKind::ColumnCountMismatch {
            in_file: 2,
            given: 3,
            ..
        }
    ));
    assert_eq!(err.location, Location::Byte(92));
    // two different columns given one name: an error at the first snapshot's chunk
    let err = read_bin(two_snapshots(), &["id", "id"]).unwrap_err();
    assert!(
        matches!(err.kind, ErrorKind::DuplicateColumn(ref c) if c == "id"),
        "{err}"
    );
}

#[test]
fn read_body_without_header_is_an_error_not_a_panic() {
    let mut r = text_reader(HEADER);
    let err = r.read_body().unwrap_err();
    assert!(matches!(err.kind, ErrorKind::NoPendingHeader));
}
