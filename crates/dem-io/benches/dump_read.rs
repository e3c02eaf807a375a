//! Read speed of a 10⁶-particle snapshot (`id type x y z vx vy vz radius`), text and binary.
//!
//! The files are generated once into a temporary directory: text with full precision (what
//! [`dem_io::write_text`] writes, 17 significant digits), text with 6 significant digits (like
//! LIGGGHTS's default `%g`), and binary. `read_*` parse the snapshot into columns; `skip_*` step
//! over it as [`dem_io::Selection`] does for snapshots that are not selected.
//! Run with `cargo bench -p dem-io --bench dump_read`; divan reports items/s (particles) and
//! bytes/s (file size).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use dem_io::{
    write_binary, write_text, Boundary, BoxBounds, DumpReader, ReadOptions, Snapshot,
    DEFAULT_BINARY_COLUMNS,
};
use divan::counter::{BytesCount, ItemsCount};
use divan::Bencher;

const PARTICLES: usize = 1_000_000;

fn main() {
    divan::main();
}

struct Files {
    _dir: tempfile::TempDir,
    text_full: PathBuf,
    text_g: PathBuf,
    binary: PathBuf,
}

/// A deterministic pseudo-random snapshot in a 0.1 m box.
fn snapshot() -> Snapshot {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut data: Vec<Vec<f64>> = (0..9).map(|_| Vec::with_capacity(PARTICLES)).collect();
    for i in 0..PARTICLES {
        data[0].push((i + 1) as f64);
        data[1].push(1.0 + (i % 2) as f64);
        for col in &mut data[2..5] {
            col.push(0.1 * next());
        }
        for col in &mut data[5..8] {
            col.push(next() - 0.5);
        }
        data[8].push(0.0005 + 0.0002 * next());
    }
    let names = DEFAULT_BINARY_COLUMNS
        .iter()
        .map(|s| s.to_string())
        .collect();
    let bounds = BoxBounds::orthogonal([0.0; 3], [0.1; 3], Boundary::Fixed);
    Snapshot::new(1000, bounds, names, data).unwrap()
}

/// Rewrites a full-precision text dump with 6 significant digits, as `%g` would.
fn shorten_digits(full: &Path, out: &Path) {
    let text = std::fs::read_to_string(full).unwrap();
    let mut w = BufWriter::new(File::create(out).unwrap());
    for (i, line) in text.lines().enumerate() {
        if i < 9 {
            writeln!(w, "{line}").unwrap();
            continue;
        }
        for tok in line.split_whitespace() {
            let v: f64 = tok.parse().unwrap();
            if v.fract() == 0.0 {
                write!(w, "{v} ").unwrap();
            } else {
                write!(w, "{v:.5e} ").unwrap();
            }
        }
        writeln!(w).unwrap();
    }
}

fn files() -> &'static Files {
    static FILES: OnceLock<Files> = OnceLock::new();
    FILES.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let snap = snapshot();
        let text_full = dir.path().join("big.txt");
        let text_g = dir.path().join("big_g.txt");
        let binary = dir.path().join("big.bin");
        write_text(
            &mut BufWriter::new(File::create(&text_full).unwrap()),
            &snap,
        )
        .unwrap();
        write_binary(&mut BufWriter::new(File::create(&binary).unwrap()), &snap).unwrap();
        shorten_digits(&text_full, &text_g);
        Files {
            _dir: dir,
            text_full,
            text_g,
            binary,
        }
    })
}

fn counters<'a, 'b>(bencher: Bencher<'a, 'b>, path: &Path) -> Bencher<'a, 'b> {
    let bytes = std::fs::metadata(path).unwrap().len();
    bencher
        .counter(ItemsCount::new(PARTICLES))
        .counter(BytesCount::new(bytes))
}

impl Files {
    fn path(&self, kind: &str) -> &Path {
        match kind {
            "text_full_precision" => &self.text_full,
            "text_6_digits" => &self.text_g,
            "binary" => &self.binary,
            _ => unreachable!("unknown file kind {kind}"),
        }
    }
}

const KINDS: [&str; 3] = ["text_full_precision", "text_6_digits", "binary"];

fn read_first(path: &Path) -> Snapshot {
    let mut r = DumpReader::open(path, &ReadOptions::default()).unwrap();
    r.next_header().unwrap().unwrap();
    r.read_body().unwrap()
}

/// Parse the snapshot into columns.
#[divan::bench(args = KINDS, sample_count = 3, sample_size = 1)]
fn read(bencher: Bencher, kind: &str) {
    let path = files().path(kind);
    counters(bencher, path).bench(|| read_first(path));
}

/// Step over the snapshot as a selection does (text: count rows; binary: seek over chunks).
#[divan::bench(args = KINDS, sample_count = 3, sample_size = 1)]
fn skip(bencher: Bencher, kind: &str) {
    let path = files().path(kind);
    counters(bencher, path).bench(|| {
        let mut r = DumpReader::open(path, &ReadOptions::default()).unwrap();
        r.headers().unwrap().len()
    });
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn write_text_full_precision(bencher: Bencher) {
    let snap = read_first(&files().binary);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w.txt");
    counters(bencher, &files().text_full).bench(|| {
        write_text(&mut File::create(&out).unwrap(), &snap).unwrap();
    });
}
