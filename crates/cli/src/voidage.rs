//! `foamgrain voidage`: the void fraction of a LIGGGHTS snapshot on an OpenFOAM mesh, written
//! as the volScalarField `voidfraction` of a time directory.

use crate::args::DumpArgs;
use anyhow::{bail, Context};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use dem_io::read_snapshot;
use foam::{default_boundary, Case, FieldValues, Format, VolField};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;
use voidage::{Method, ParticleSet, VoidageMesh};

/// Arguments of `foamgrain voidage`.
#[derive(Args, Debug)]
pub struct VoidageArgs {
    /// OpenFOAM case directory (holding constant/polyMesh).
    #[arg(long, value_name = "DIR")]
    pub case: PathBuf,
    #[command(flatten)]
    pub dump: DumpArgs,
    /// How a particle's volume is shared among cells: the cell of its centre (`centre`),
    /// CFDEM's 29 marker points (`divided`), CFDEM's trilinear weights over the 8 nearest cell
    /// centres (`trilinear`, grids of equal axis-aligned cells only), the circumscribing cube
    /// (`cube`), Khawaja's corrected cube (`corrected-cube`) or the exact sphere ∩ cell volume
    /// (`exact`).
    #[arg(long, value_parser = PossibleValuesParser::new(Method::ALL.map(|m| m.name()))
        .map(|s| s.parse::<Method>().expect("a possible value")))]
    pub method: Method,
    /// Time directory to write `voidfraction` into (created if missing). A decomposed case
    /// (`processorN/`) also gets each piece's share of the field in `processorN/<time>/`.
    #[arg(long, value_name = "NAME", default_value = "0")]
    pub time: String,
    /// Lower bound for the void fraction: cells below it are clipped and the solid volume
    /// removed by clipping is reported. Default: unclipped.
    #[arg(long, value_name = "X")]
    pub alpha_min: Option<f64>,
    /// Print one JSON object (the last line of stdout) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// What the command did, printed as text or JSON. Volumes in m³, times in s.
#[derive(Serialize)]
struct Report {
    method: &'static str,
    case: String,
    output: String,
    /// Processor pieces of a decomposed case that got their part of the field.
    pieces: usize,
    dump: String,
    timestep: u64,
    cells: usize,
    axis_aligned_grid: bool,
    particles: usize,
    particle_volume: f64,
    deposited_volume: f64,
    outside_volume: f64,
    particles_outside: usize,
    particles_partly_outside: usize,
    /// |particle − deposited − outside| / particle volume.
    conservation_error: f64,
    alpha_min: Option<f64>,
    clipped_volume: f64,
    clipped_cells: usize,
    /// Smallest void fraction before clipping.
    min_voidage: f64,
    /// Cells holding more solid than their volume (before clipping).
    negative_cells: usize,
    /// Wall time of locating the particles and depositing their volumes (no file I/O).
    voidage_seconds: f64,
    /// Wall time of the whole command.
    total_seconds: f64,
}

/// Runs the command.
pub fn run(a: &VoidageArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    if a.time.is_empty() || a.time == "." || a.time == ".." || a.time.contains(['/', '\\']) {
        bail!(
            "--time must be a time directory name such as 0 or 0.5, not `{}`",
            a.time
        );
    }
    let case = foam::Case::open(&a.case)?;
    let mesh = case.read_mesh()?;
    let snap = read_snapshot(&a.dump.dump, &a.dump.read_options(), a.dump.selection()?)?;
    let positions = snap.positions()?;
    let radii = snap.radii()?;
    let ids = snap
        .column("id")
        .is_some()
        .then(|| snap.ids())
        .transpose()?;
    let vm =
        VoidageMesh::new(&mesh).with_context(|| format!("mesh of {}", case.root().display()))?;
    vm.check_method(a.method)
        .with_context(|| format!("mesh of {}", case.root().display()))?;
    let set = ParticleSet {
        positions: mesh::v3::as_vectors(&positions),
        radii: &radii,
        ids: ids.as_deref(),
    };
    let t = Instant::now();
    let dep = vm
        .deposit(a.method, &set)
        .with_context(|| format!("dump {}", a.dump.dump.display()))?;
    let voidage_seconds = t.elapsed().as_secs_f64();
    let eps = vm.voidage(&dep, a.alpha_min)?;
    let output = write_field(&case, &a.time, &mesh, eps.epsilon.clone())?;
    let pieces = foam::decomposed::pieces(&case, mesh.n_cells)?;
    for piece in &pieces {
        piece.write_cell_field(
            &a.time,
            "voidfraction",
            [0; 7],
            FieldValues::Scalar(piece.pick(&eps.epsilon)),
            "zeroGradient",
            Format::Ascii,
        )?;
    }
    let r = Report {
        method: a.method.name(),
        case: case.root().display().to_string(),
        output: output.display().to_string(),
        pieces: pieces.len(),
        dump: a.dump.dump.display().to_string(),
        timestep: snap.timestep,
        cells: vm.n_cells(),
        axis_aligned_grid: vm.axis_grid().is_some(),
        particles: dep.particles,
        particle_volume: dep.particle_volume,
        deposited_volume: dep.deposited_volume,
        outside_volume: dep.outside_volume,
        particles_outside: dep.particles_outside,
        particles_partly_outside: dep.particles_partly_outside,
        conservation_error: dep.conservation_error(),
        alpha_min: a.alpha_min,
        clipped_volume: eps.clipped_volume,
        clipped_cells: eps.clipped_cells,
        min_voidage: eps.min_epsilon,
        negative_cells: eps.negative_cells,
        voidage_seconds,
        total_seconds: start.elapsed().as_secs_f64(),
    };
    if a.json {
        println!("{}", serde_json::to_string(&r)?);
    } else {
        print_text(&r);
    }
    Ok(())
}

/// Writes `voidfraction` (dimensionless, zeroGradient on ordinary patches) into time `name`.
fn write_field(
    case: &Case,
    name: &str,
    mesh: &foam::PolyMesh,
    eps: Vec<f64>,
) -> anyhow::Result<PathBuf> {
    let dir = case.time_path(name);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let field = VolField::new(
        "voidfraction",
        name,
        [0; 7],
        FieldValues::Scalar(eps),
        default_boundary(&mesh.boundary, "zeroGradient", None),
    );
    let path = dir.join("voidfraction");
    field.write(&path, Format::Ascii)?;
    Ok(path)
}

fn print_text(r: &Report) {
    println!(
        "{} voidage of {} particles on {} cells",
        r.method, r.particles, r.cells
    );
    println!(
        "  particle volume {:.6e} m³ = deposited {:.6e} + outside the mesh {:.6e} \
         (residual {:.1e})",
        r.particle_volume, r.deposited_volume, r.outside_volume, r.conservation_error
    );
    if r.particles_outside + r.particles_partly_outside > 0 {
        println!(
            "  {} particles outside the mesh, {} partly outside",
            r.particles_outside, r.particles_partly_outside
        );
    }
    println!(
        "  min voidage {:.6} ({} cells below 0)",
        r.min_voidage, r.negative_cells
    );
    if let Some(a) = r.alpha_min {
        println!(
            "  clipped at {a}: {} cells, {:.6e} m³ of solid removed",
            r.clipped_cells, r.clipped_volume
        );
    }
    println!(
        "  wrote {} (voidage {:.3} s, total {:.3} s)",
        r.output, r.voidage_seconds, r.total_seconds
    );
    if r.pieces > 0 {
        println!(
            "  and its part into each of the {} processor pieces",
            r.pieces
        );
    }
}
