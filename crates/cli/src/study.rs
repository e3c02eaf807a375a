//! `foamgrain study cellsize CASE`: the cell-size study of a frozen bed (crate `study`).

use anyhow::Context;
use clap::{Args, Subcommand};
use std::path::PathBuf;
use study::{StudyEvent, StudyOptions};

/// Studies over many runs of one case.
#[derive(Subcommand, Debug)]
pub enum StudyCommand {
    /// Cell-size study of a frozen bed (Volk, Ghia & Liu 2018): re-meshes the case from its
    /// `CFD/system/blockMeshDict.template` for each cell size, runs the fluid to steady state
    /// through the packed bed for each voidage method and velocity, and reports the drag
    /// against Gidaspow's and Ergun's laws on the measured bed, the voidage spread in the bed
    /// and the GCI of every grid triplet (CSV, JSON, PNG plots).
    Cellsize(CellsizeArgs),
}

/// Arguments of `foamgrain study cellsize`.
#[derive(Args, Debug)]
pub struct CellsizeArgs {
    /// The case (CFDEM layout, with CFD/system/blockMeshDict.template and a DEM init deck),
    /// e.g. openfoam-cases/binary-bed.
    pub case: PathBuf,
    /// Dimensionless cell sizes Δx/d₃₂: cell edge over the bed's Sauter-mean diameter (the
    /// paper's definition; 2 means cells two diameters wide).
    #[arg(long, value_delimiter = ',', default_values_t = [1.0, 1.5, 2.0, 3.0, 4.0, 6.0])]
    pub dx_over_d: Vec<f64>,
    /// Cell sizes as cells per Sauter-mean diameter, d₃₂/Δx (the reciprocal of
    /// --dx-over-d; replaces it when given).
    #[arg(long, value_delimiter = ',', conflicts_with = "dx_over_d")]
    pub cells_per_d: Vec<f64>,
    /// Voidage methods (centre, divided, trilinear, cube, corrected-cube, exact, bigParticle);
    /// default all but trilinear and bigParticle.
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<voidage::Method>,
    /// Superficial velocities as fractions of the bed's minimum fluidisation velocity.
    #[arg(long, value_delimiter = ',', default_values_t = [0.5, 0.9])]
    pub velocities: Vec<f64>,
    /// Largest number of fluid steps per run.
    #[arg(long, default_value_t = 4000)]
    pub max_steps: u64,
    /// Steady-state tolerance: relative change of the window means of Δp and drag.
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Pack the bed again even if the packed file exists.
    #[arg(long)]
    pub repack: bool,
    /// Output directory (default CASE/postProcessing/cellsize).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// Runs the command.
pub fn run(c: &StudyCommand) -> anyhow::Result<()> {
    let StudyCommand::Cellsize(a) = c;
    let mut o = StudyOptions {
        dx_over_d: a.dx_over_d.clone(),
        velocities: a.velocities.clone(),
        max_steps: a.max_steps,
        repack: a.repack,
        output: a.output.clone(),
        ..StudyOptions::default()
    };
    if !a.cells_per_d.is_empty() {
        if let Some(bad) = a.cells_per_d.iter().find(|&&x| !(x > 0.0 && x.is_finite())) {
            anyhow::bail!("--cells-per-d {bad}: must be a positive number");
        }
        o.dx_over_d = a.cells_per_d.iter().map(|x| 1.0 / x).collect();
    }
    if !a.methods.is_empty() {
        o.methods = a.methods.clone();
    }
    if let Some(t) = a.tolerance {
        o.criterion.tolerance = t;
    }
    let report = study::cellsize(&a.case, &o, &mut |e| match e {
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
    })
    .with_context(|| format!("cell-size study of {}", a.case.display()))?;
    let dir = o
        .output
        .clone()
        .unwrap_or_else(|| a.case.join("postProcessing/cellsize"));
    let files = study::write_outputs(&report, &dir)
        .with_context(|| format!("writing the study's outputs to {}", dir.display()))?;
    for f in files {
        println!("{}", f.display());
    }
    eprintln!(
        "{} runs in {:.1} s (packing {:.1} s)",
        report.rows.len(),
        report.run_seconds,
        report.pack_seconds
    );
    Ok(())
}
