//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use dem_io::{DumpReader, ReadOptions, Snapshot};

/// Directory of the LIGGGHTS decks and the dumps they produced.
pub fn fixtures() -> PathBuf {
    testkit::fixture("liggghts")
}

/// Reads every snapshot of a file.
pub fn read_all(path: &std::path::Path, options: &ReadOptions) -> Vec<Snapshot> {
    DumpReader::open(path, options)
        .unwrap_or_else(|e| panic!("{e}"))
        .collect::<Result<Vec<_>, _>>()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Asserts two snapshots hold the same columns with bit-identical values.
pub fn assert_same_values(a: &Snapshot, b: &Snapshot) {
    assert_eq!(a.timestep, b.timestep);
    assert_eq!(a.column_names(), b.column_names());
    assert_eq!(a.len(), b.len());
    for ((name, ca), (_, cb)) in a.columns().zip(b.columns()) {
        for (row, (x, y)) in ca.iter().zip(cb).enumerate() {
            assert_eq!(
                x.to_bits(),
                y.to_bits(),
                "step {} column {name} row {row}: {x:e} vs {y:e}",
                a.timestep
            );
        }
    }
}
