//! Peak memory of reading one large snapshot, to check the "≤ ~3× the snapshot" bound.
//!
//! ```text
//! cargo run --release -p dem-io --example peak_memory -- generate DIR [PARTICLES]
//! cargo run --release -p dem-io --example peak_memory -- read DIR/big.txt
//! cargo run --release -p dem-io --example peak_memory -- read DIR/big.bin
//! ```
//! `generate` writes `big.txt` and `big.bin` (three snapshots each, columns
//! `id type x y z vx vy vz radius`); `read` selects the last snapshot, builds the
//! [`dem_io::Particles`] view, and prints the peak resident set size (`VmHWM` from
//! `/proc/self/status`, Linux only) against the size of the snapshot's values. Run `read` in
//! a fresh process per file so the peak belongs to that read alone.

use std::fs::File;
use std::path::Path;

use dem_io::{
    read_snapshot, Boundary, BoxBounds, DumpWriter, ReadOptions, Selection, Snapshot,
    DEFAULT_BINARY_COLUMNS,
};

/// `VmHWM` (peak resident set) in bytes, if the platform reports it.
fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

fn generate(dir: &Path, n: usize) -> Result<(), Box<dyn std::error::Error>> {
    let names: Vec<String> = DEFAULT_BINARY_COLUMNS
        .iter()
        .map(|s| s.to_string())
        .collect();
    let bounds = BoxBounds::orthogonal([0.0; 3], [0.1; 3], Boundary::Fixed);
    let mut text = DumpWriter::create(dir.join("big.txt"), None)?;
    let mut bin = DumpWriter::create(dir.join("big.bin"), None)?;
    for step in [0u64, 1000, 2000] {
        let data: Vec<Vec<f64>> = (0..names.len())
            .map(|c| {
                (0..n)
                    .map(|i| match c {
                        0 => (i + 1) as f64,
                        1 => 1.0,
                        _ => ((i * 7919 + c * 104_729 + step as usize) % 1_000_003) as f64 * 1e-7,
                    })
                    .collect()
            })
            .collect();
        let snap = Snapshot::new(step, bounds, names.clone(), data)?;
        text.write(&snap)?;
        bin.write(&snap)?;
    }
    text.finish()?;
    bin.finish()?;
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("generate") if args.len() >= 2 => {
            let n = args.get(2).map_or(Ok(1_000_000), |s| s.parse())?;
            generate(Path::new(&args[1]), n)
        }
        Some("read") if args.len() == 2 => {
            let before = peak_rss().unwrap_or(0);
            let snap = read_snapshot(&args[1], &ReadOptions::default(), Selection::Last)?;
            let after_read = peak_rss().unwrap_or(0);
            let particles = snap.particles()?;
            let after_view = peak_rss().unwrap_or(0);
            let size = (snap.len() * snap.column_names().len() * 8) as u64;
            let file = File::open(&args[1])?.metadata()?.len();
            println!(
                "{}: file {:.1} MiB, last snapshot {} particles = {:.1} MiB of values",
                args[1],
                mib(file),
                particles.len(),
                mib(size)
            );
            println!(
                "peak RSS: {:.1} MiB at start, {:.1} MiB after reading ({:.2}× the snapshot), \
                 {:.1} MiB after building Particles",
                mib(before),
                mib(after_read),
                after_read as f64 / size as f64,
                mib(after_view)
            );
            Ok(())
        }
        _ => Err("usage: peak_memory generate DIR [PARTICLES] | peak_memory read FILE".into()),
    }
}
