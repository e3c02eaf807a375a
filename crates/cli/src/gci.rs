//! `foamgrain gci`: the Grid Convergence Index (Celik et al. 2008) of a grid-refinement study,
//! from a CSV table (`cells` or `h`, optional `volume`/`area`/`length`, value columns) or from
//! command-line lists; a table per quantity and successive grid triplet, or one JSON document.

use anyhow::{bail, Context};
use clap::Args;
use gci::{analyse_study, Dim, GridTable, Outcome, Settings, SizeKind, Triplet, Warning};
use std::path::PathBuf;

/// Arguments of `foamgrain gci`.
#[derive(Args, Debug)]
pub struct GciArgs {
    /// CSV table, one row per grid: a header naming `cells` (cell counts) or `h` (cell sizes),
    /// optionally `volume`, `area` or `length` (the domain measure), and one or more value
    /// columns. Blank lines and `#` lines are skipped.
    #[arg(value_name = "FILE", required_unless_present = "values")]
    pub file: Option<PathBuf>,
    /// Cell counts of the grids, comma separated (instead of FILE; with --values).
    #[arg(long, value_delimiter = ',', conflicts_with_all = ["file", "sizes"], requires = "values")]
    pub cells: Option<Vec<f64>>,
    /// Representative cell sizes h of the grids, comma separated (instead of FILE).
    #[arg(
        long,
        value_delimiter = ',',
        conflicts_with = "file",
        requires = "values"
    )]
    pub sizes: Option<Vec<f64>>,
    /// The value on each grid, in the order of --cells or --sizes.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with = "file"
    )]
    pub values: Option<Vec<f64>>,
    /// Space dimensions for h from cell counts: h = (V/N)^(1/3) for 3, (A/N)^(1/2) for 2.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(1..=3))]
    pub dim: u8,
    /// Safety factor Fs of GCI_fine (Celik et al.: 1.25 for three or more grids).
    #[arg(long, default_value_t = 1.25)]
    pub safety: f64,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(a: &GciArgs) -> anyhow::Result<()> {
    let settings = Settings::with_safety_factor(a.safety)?;
    let Some(dim) = Dim::from_number(a.dim) else {
        bail!("--dim must be 1, 2 or 3");
    };
    let table = match (&a.file, &a.cells, &a.sizes, &a.values) {
        (Some(file), ..) => {
            let text = std::fs::read_to_string(file)
                .with_context(|| format!("cannot read {}", file.display()))?;
            GridTable::parse_csv(&text, &file.display().to_string())?
        }
        (None, Some(cells), None, Some(values)) => {
            GridTable::from_lists(SizeKind::Cells, cells, "--cells", values, "--values")?
        }
        (None, None, Some(sizes), Some(values)) => {
            GridTable::from_lists(SizeKind::H, sizes, "--sizes", values, "--values")?
        }
        _ => bail!("give a CSV FILE, or --cells (or --sizes) together with --values"),
    };
    let mut studies = Vec::with_capacity(table.quantities.len());
    for (q, name) in table.quantities.iter().enumerate() {
        let triplets = analyse_study(&table.grids(q, dim), &settings)?;
        studies.push((name.as_str(), q, triplets));
    }
    if a.json {
        println!("{}", json(&table, dim, &settings, &studies)?);
    } else {
        let rows_word = if a.file.is_some() { "lines" } else { "items" };
        for (name, q, triplets) in &studies {
            print_study(rows_word, &table, dim, &settings, name, *q, triplets);
        }
    }
    Ok(())
}

type Study<'a> = (&'a str, usize, Vec<Triplet>);

fn json(
    table: &GridTable,
    dim: Dim,
    settings: &Settings,
    studies: &[Study],
) -> anyhow::Result<String> {
    let size_key = match table.size_kind {
        SizeKind::Cells => "cells",
        SizeKind::H => "h_given",
    };
    let quantities = studies
        .iter()
        .map(|(name, q, triplets)| {
            let grids: Vec<_> = table
                .rows
                .iter()
                .map(|row| {
                    serde_json::json!({
                        "line": row.at.line,
                        size_key: row.size,
                        "h": table.h(row, dim),
                        "value": row.values[*q],
                    })
                })
                .collect();
            let triplets = triplets
                .iter()
                .map(|t| {
                    let mut v = serde_json::to_value(t)?;
                    v["lines"] = serde_json::json!(t.grids.map(|i| table.rows[i].at.line));
                    Ok(v)
                })
                .collect::<Result<Vec<_>, serde_json::Error>>()?;
            Ok(serde_json::json!({ "name": name, "grids": grids, "triplets": triplets }))
        })
        .collect::<Result<Vec<_>, serde_json::Error>>()?;
    let doc = serde_json::json!({
        "source": table.source,
        "dim": dim,
        "safety_factor": settings.safety_factor,
        "quantities": quantities,
    });
    Ok(serde_json::to_string_pretty(&doc)?)
}

/// `x` with six significant digits, fixed notation for moderate magnitudes.
fn num(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor();
    if (-3.0..6.0).contains(&e) {
        format!("{:.*}", (5.0 - e) as usize, x)
    } else {
        format!("{x:.5e}")
    }
}

fn percent(x: f64) -> String {
    format!("{} %", num(100.0 * x))
}

/// Prints the triplets of quantity `q`; `rows_word` names what the locations count ("lines"
/// of a file, "items" of a command-line list).
fn print_study(
    rows_word: &str,
    table: &GridTable,
    dim: Dim,
    settings: &Settings,
    name: &str,
    q: usize,
    triplets: &[Triplet],
) {
    println!(
        "{}: {name} — {} grids, {}-D, Fs = {}",
        table.source,
        table.rows.len(),
        dim.number(),
        settings.safety_factor
    );
    for (k, t) in triplets.iter().enumerate() {
        let rows = t.grids.map(|i| &table.rows[i]);
        let lines = format!(
            "{rows_word} {}",
            rows.map(|r| r.at.line.to_string()).join(", ")
        );
        println!("\ntriplet {} of {} ({lines})", k + 1, triplets.len());
        println!(
            "  {:<14}{:>14}{:>14}{:>14}",
            "", "fine 1", "medium 2", "coarse 3"
        );
        if table.size_kind == SizeKind::Cells {
            let cells = rows.map(|r| r.size.to_string());
            println!(
                "  {:<14}{:>14}{:>14}{:>14}",
                "cells", cells[0], cells[1], cells[2]
            );
        }
        let h = t.h.map(num);
        println!("  {:<14}{:>14}{:>14}{:>14}", "h", h[0], h[1], h[2]);
        let phi = rows.map(|r| r.values[q].to_string());
        println!("  {:<14}{:>14}{:>14}{:>14}", "φ", phi[0], phi[1], phi[2]);
        println!("  {:<14}{}, {}", "r21, r32", num(t.r21), num(t.r32));
        println!("  {:<14}{}", "behaviour", t.behaviour);
        match &t.outcome {
            Outcome::Undefined(why) => println!("  {why}"),
            Outcome::Estimate(e) => {
                let how = match e.method {
                    gci::Method::FixedPoint => "fixed-point iteration",
                    gci::Method::Bisection => "bisection",
                };
                println!(
                    "  {:<14}{}   ({how}, {} steps)",
                    "p",
                    num(e.p),
                    e.iterations
                );
                println!("  {:<14}{}", "φ_ext^21", num(e.phi_ext21));
                println!("  {:<14}{}", "φ_ext^32", num(e.phi_ext32));
                match &e.relative {
                    Some(r) => {
                        println!("  {:<14}{}", "e_a^21", percent(r.e_a21));
                        println!("  {:<14}{}", "e_ext^21", percent(r.e_ext21));
                        println!("  {:<14}{}", "GCI_fine^21", percent(r.gci_fine21));
                    }
                    None => println!("  relative errors undefined: φ1 = 0 or φ_ext^21 = 0"),
                }
                if t.behaviour == gci::Behaviour::OscillatoryConvergence {
                    println!(
                        "  note: oscillatory convergence (ε32/ε21 < 0); the extrapolation \
                         assumes monotone convergence, treat φ_ext and GCI as indicative"
                    );
                }
            }
        }
        for w in &t.warnings {
            let Warning::SmallRatio { pair, r } = w;
            let which = match pair {
                gci::Pair::R21 => "r21",
                gci::Pair::R32 => "r32",
            };
            eprintln!(
                "warning: {}: {name}, {lines}: {which} = {} < {} (Celik et al. recommend r > 1.3)",
                table.source,
                num(*r),
                settings.min_ratio
            );
        }
    }
    println!();
}
