//! Runs a cell-size study from the command line (the library behind
//! `foamgrain study cellsize`):
//!
//! ```sh
//! cargo run --release -p study --example cellsize -- CASE \
//!     [--dx-over-d 1,1.5,2,3,4,6] [--methods centre,divided,cube,corrected-cube,exact] \
//!     [--velocities 0.5,0.9] [--max-steps N] [--tolerance T] [--repack] [-o DIR]
//! ```
//!
//! `--dx-over-d` is the cell edge over the Sauter-mean diameter; `--velocities` are fractions
//! of the bed's minimum fluidisation velocity. Writes `cellsize.csv`, `cellsize.json` and PNG
//! plots to `DIR` (default `CASE/postProcessing/cellsize`).

use std::path::PathBuf;
use std::process::ExitCode;
use study::{StudyEvent, StudyOptions};

fn list(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(|x| x.trim().parse::<f64>().map_err(|e| format!("`{x}`: {e}")))
        .collect()
}

fn parse() -> Result<(PathBuf, StudyOptions), String> {
    let mut args = std::env::args().skip(1);
    let mut case = None;
    let mut o = StudyOptions::default();
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or_else(|| format!("{a} needs a value"));
        match a.as_str() {
            "--dx-over-d" => o.dx_over_d = list(&value()?)?,
            "--velocities" => o.velocities = list(&value()?)?,
            "--methods" => {
                o.methods = value()?
                    .split(',')
                    .map(|m| {
                        m.trim()
                            .parse::<voidage::Method>()
                            .map_err(|e| e.to_string())
                    })
                    .collect::<Result<_, _>>()?
            }
            "--max-steps" => o.max_steps = value()?.parse().map_err(|e| format!("{e}"))?,
            "--tolerance" => {
                o.criterion.tolerance = value()?.parse().map_err(|e| format!("{e}"))?
            }
            "--repack" => o.repack = true,
            "-o" | "--output" => o.output = Some(PathBuf::from(value()?)),
            _ if case.is_none() && !a.starts_with('-') => case = Some(PathBuf::from(&a)),
            _ => return Err(format!("unknown argument `{a}`")),
        }
    }
    Ok((case.ok_or("usage: cellsize CASE [options]")?, o))
}

fn main() -> ExitCode {
    let (case, opts) = match parse() {
        Ok(x) => x,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let report = study::cellsize(&case, &opts, &mut |e| {
        match e {
        StudyEvent::Message(m) => eprintln!("{m}"),
        StudyEvent::Run {
            done,
            total,
            result,
        } => eprintln!(
            "[{done}/{total}] {:<14} U/Umf {:.2}  dx/d32 {:.3} ({:>6} cells)  F/A {:9.3} Pa  dp {:9.3} Pa  error {:+7.2} %  std(eps) {}  {} steps{}  {:.1} s",
            result.run.method,
            result.fraction,
            result.cell_size.over_sauter,
            result.run.cells,
            result.force_per_area,
            result.run.pressure_drop,
            100.0 * result.error,
            result
                .run
                .spread
                .map_or("-".into(), |s| format!("{:.4}", s.std)),
            result.run.steps,
            if result.run.steady { "" } else { " (NOT steady)" },
            result.run.seconds
        ),
    }
    });
    let report = match report {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let dir = opts
        .output
        .clone()
        .unwrap_or_else(|| case.join("postProcessing/cellsize"));
    match study::write_outputs(&report, &dir) {
        Ok(files) => {
            for f in files {
                println!("{}", f.display());
            }
            eprintln!(
                "{} runs in {:.1} s (packing {:.1} s)",
                report.rows.len(),
                report.run_seconds,
                report.pack_seconds
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
