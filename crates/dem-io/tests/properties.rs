//! Property tests: exact write → read round trips, and no panic on any input.

mod common;

use std::io::Cursor;

use common::assert_same_values;
use dem_io::{
    write_binary_chunks, write_text, Boundary, BoxBounds, DumpFormat, DumpReader, ReadOptions,
    Selection, Snapshot,
};
use proptest::prelude::*;

fn boundary() -> impl Strategy<Value = Boundary> {
    prop_oneof![
        Just(Boundary::Periodic),
        Just(Boundary::Fixed),
        Just(Boundary::Shrink),
        Just(Boundary::ShrinkMin),
    ]
}

/// Any finite value, including −0, subnormals and integers.
fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => any::<f64>().prop_filter("finite", |v| v.is_finite()),
        1 => prop::num::f64::SUBNORMAL | prop::num::f64::NEGATIVE | prop::num::f64::ZERO,
        1 => (-1_000_000i64..1_000_000).prop_map(|i| i as f64),
        1 => Just(-0.0),
        1 => -1e3f64..1e3,
    ]
}

fn bounds() -> impl Strategy<Value = BoxBounds> {
    (
        prop::array::uniform3(value()),
        prop::array::uniform3(value()),
        prop::option::of(prop::array::uniform3(value())),
        prop::array::uniform3(prop::array::uniform2(boundary())),
    )
        .prop_map(|(lo, hi, tilt, boundary)| BoxBounds {
            lo,
            hi,
            tilt,
            boundary,
        })
}

const NAMES: [&str; 12] = [
    "id",
    "type",
    "x",
    "y",
    "z",
    "vx",
    "vy",
    "vz",
    "radius",
    "density",
    "f_force[1]",
    "c_1",
];

/// 1–12 unique column names in random order.
fn names() -> impl Strategy<Value = Vec<String>> {
    (Just(NAMES.to_vec()).prop_shuffle(), 1usize..=NAMES.len())
        .prop_map(|(names, n)| names[..n].iter().map(|s| s.to_string()).collect())
}

/// A snapshot with the given columns, 0–40 rows, random box, timestep and label.
fn snapshot_with(names: Vec<String>) -> impl Strategy<Value = Snapshot> {
    (
        0usize..40,
        0u64..=i64::MAX as u64,
        bounds(),
        prop::option::of("[A-Za-z0-9_][A-Za-z0-9_ .-]{0,20}[A-Za-z0-9_]"),
    )
        .prop_flat_map(move |(nrows, step, b, label)| {
            let names = names.clone();
            prop::collection::vec(prop::collection::vec(value(), nrows), names.len()).prop_map(
                move |data| {
                    let s = Snapshot::new(step, b, names.clone(), data).unwrap();
                    match &label {
                        Some(l) => s.with_label(l.clone()),
                        None => s,
                    }
                },
            )
        })
}

/// 1–3 snapshots sharing one column layout (as in one file).
fn snapshots() -> impl Strategy<Value = Vec<Snapshot>> {
    names().prop_flat_map(|n| prop::collection::vec(snapshot_with(n), 1..4))
}

fn read_back(bytes: Vec<u8>, format: DumpFormat, names: &[String]) -> Vec<Snapshot> {
    let opts = ReadOptions::default()
        .with_format(format)
        .with_binary_columns(names);
    DumpReader::from_reader(Cursor::new(bytes), "prop", &opts)
        .unwrap()
        .collect::<Result<Vec<_>, _>>()
        .unwrap_or_else(|e| panic!("{e}"))
}

fn assert_same_bounds(a: &BoxBounds, b: &BoxBounds) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.lo), bits(&b.lo));
    assert_eq!(bits(&a.hi), bits(&b.hi));
    assert_eq!(a.tilt.map(|t| bits(&t)), b.tilt.map(|t| bits(&t)));
    assert_eq!(a.boundary, b.boundary);
}

/// A valid text and binary dump used as the base of the corruption tests.
fn valid_files() -> (Vec<u8>, Vec<u8>) {
    let b = BoxBounds::triclinic(
        [0.0; 3],
        [1.0, 2.0, 3.0],
        [0.1, -0.2, 0.3],
        [[Boundary::Periodic; 2]; 3],
    );
    let names: Vec<String> = ["id", "type", "x", "y", "z", "vx", "vy", "vz", "radius"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let (mut text, mut bin) = (Vec::new(), Vec::new());
    for step in [0u64, 100, 200] {
        let data: Vec<Vec<f64>> = (0..names.len())
            .map(|c| {
                (0..7)
                    .map(|r| (r * 10 + c) as f64 * 0.37 + step as f64)
                    .collect()
            })
            .collect();
        let s = Snapshot::new(step, b, names.clone(), data).unwrap();
        write_text(&mut text, &s).unwrap();
        write_binary_chunks(&mut bin, &s, 2).unwrap();
    }
    (text, bin)
}

/// Reads everything a reader yields and every selection; only `Ok`/`Err` may come back.
fn exercise(bytes: Vec<u8>, format: DumpFormat) {
    let opts = ReadOptions::default().with_format(format);
    let mut r = DumpReader::from_reader(Cursor::new(bytes.clone()), "fuzz", &opts).unwrap();
    // The reader stops after its first error, so this ends.
    for s in r.by_ref().flatten() {
        let _ = s.particles();
    }
    for sel in [
        Selection::Last,
        Selection::Index(1),
        Selection::Timestep(100),
    ] {
        let mut r = DumpReader::from_reader(Cursor::new(bytes.clone()), "fuzz", &opts).unwrap();
        let _ = r.select(sel);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn text_round_trip_is_exact(snaps in snapshots()) {
        let mut bytes = Vec::new();
        for s in &snaps {
            write_text(&mut bytes, s).unwrap();
        }
        let back = read_back(bytes, DumpFormat::Text, &[]);
        prop_assert_eq!(back.len(), snaps.len());
        for (a, b) in snaps.iter().zip(&back) {
            assert_same_values(a, b);
            assert_same_bounds(&a.bounds, &b.bounds);
            prop_assert_eq!(&a.label, &b.label);
        }
    }

    #[test]
    fn binary_round_trip_is_exact(snaps in snapshots(), chunks in 1usize..5) {
        let names = snaps[0].column_names().to_vec();
        let mut bytes = Vec::new();
        for s in &snaps {
            write_binary_chunks(&mut bytes, s, chunks).unwrap();
        }
        let back = read_back(bytes, DumpFormat::Binary, &names);
        prop_assert_eq!(back.len(), snaps.len());
        for (a, b) in snaps.iter().zip(&back) {
            assert_same_values(a, b);
            assert_same_bounds(&a.bounds, &b.bounds);
            prop_assert_eq!(&b.label, &None);
        }
    }

    #[test]
    fn garbage_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..2000)) {
        exercise(bytes.clone(), DumpFormat::Text);
        exercise(bytes, DumpFormat::Binary);
    }

    #[test]
    fn truncated_files_never_panic(cut in 0.0f64..1.0) {
        let (text, bin) = valid_files();
        let t = (cut * text.len() as f64) as usize;
        let b = (cut * bin.len() as f64) as usize;
        exercise(text[..t].to_vec(), DumpFormat::Text);
        exercise(bin[..b].to_vec(), DumpFormat::Binary);
    }

    #[test]
    fn corrupted_files_never_panic(
        edits in prop::collection::vec((0.0f64..1.0, any::<u8>()), 1..8),
    ) {
        let (mut text, mut bin) = valid_files();
        for (at, byte) in &edits {
            let t = (*at * text.len() as f64) as usize;
            let b = (*at * bin.len() as f64) as usize;
            text[t] = *byte;
            bin[b] = *byte;
        }
        exercise(text, DumpFormat::Text);
        exercise(bin, DumpFormat::Binary);
    }
}

#[test]
fn valid_base_files_read_completely() {
    // The corruption tests start from files that are valid: check that here once.
    let (text, bin) = valid_files();
    for (bytes, format) in [(text, DumpFormat::Text), (bin, DumpFormat::Binary)] {
        let names: Vec<String> = dem_io::DEFAULT_BINARY_COLUMNS
            .iter()
            .map(|s| s.to_string())
            .collect();
        let snaps = read_back(bytes, format, &names);
        assert_eq!(snaps.len(), 3);
        assert_eq!(snaps[2].timestep, 200);
        assert_eq!(
            snaps[2].column("vx").unwrap()[6],
            (60 + 5) as f64 * 0.37 + 200.0
        );
        assert!(snaps[2].bounds.is_triclinic());
    }
}
