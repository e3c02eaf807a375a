//! Arguments shared by several commands.

use clap::Args;
use dem_io::{ReadOptions, Selection, DEFAULT_BINARY_COLUMNS};
use std::path::PathBuf;

/// Which LIGGGHTS dump to read and how.
#[derive(Args, Debug, Clone)]
pub struct DumpArgs {
    /// LIGGGHTS `dump custom` file: text, or binary when the name ends in `.bin`.
    #[arg(long, value_name = "FILE")]
    pub dump: PathBuf,
    /// Column names of a binary dump, in the order of its `dump custom` command (binary dumps
    /// carry no names). Space- or comma-separated.
    #[arg(long, value_name = "NAMES", num_args = 1.., value_delimiter = ',',
          default_values_t = DEFAULT_BINARY_COLUMNS.map(String::from))]
    pub columns: Vec<String>,
    /// Snapshot to read: `last` (default), `first`, or a 0-based index in the file.
    #[arg(long, default_value = "last", conflicts_with = "timestep")]
    pub snapshot: String,
    /// Read the snapshot with this LIGGGHTS timestep instead.
    #[arg(long)]
    pub timestep: Option<u64>,
}

impl DumpArgs {
    /// Reader options from the arguments (column names split on spaces too).
    pub fn read_options(&self) -> ReadOptions {
        let cols: Vec<&str> = self
            .columns
            .iter()
            .flat_map(|c| c.split_whitespace())
            .collect();
        ReadOptions::default().with_binary_columns(&cols)
    }

    /// The snapshot selection.
    pub fn selection(&self) -> anyhow::Result<Selection> {
        if let Some(t) = self.timestep {
            return Ok(Selection::Timestep(t));
        }
        Ok(match self.snapshot.as_str() {
            "last" => Selection::Last,
            "first" => Selection::Index(0),
            s => Selection::Index(s.parse().map_err(|_| {
                anyhow::anyhow!("--snapshot must be `last`, `first` or an index, not `{s}`")
            })?),
        })
    }
}

/// Sets the number of rayon worker threads from a `--np`/`--threads` option (`flag` names it in
/// the error); `None` keeps rayon's default (all cores).
pub fn set_threads(n: Option<usize>, flag: &str) -> anyhow::Result<()> {
    let Some(n) = n else {
        return Ok(());
    };
    if n == 0 {
        anyhow::bail!("{flag} must be at least 1");
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| anyhow::anyhow!("setting the thread count: {e}"))
}

/// A progress bar drawn on stderr with `template` (indicatif's syntax), or `None` when stderr is
/// not a terminal (logs and pipes get plain lines instead).
pub fn progress_bar(len: u64, template: &str) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(len);
        b.set_style(
            indicatif::ProgressStyle::with_template(template)
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    })
}
