//! `foamgrain info`: what a case holds.

use anyhow::Context;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `foamgrain info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// OpenFOAM case directory (holding constant/polyMesh), or one processorN directory.
    #[arg(long, value_name = "DIR")]
    pub case: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct PatchInfo {
    name: String,
    #[serde(rename = "type")]
    patch_type: String,
    faces: usize,
}

#[derive(Serialize)]
struct CaseInfo {
    case: String,
    cells: usize,
    faces: usize,
    internal_faces: usize,
    points: usize,
    patches: Vec<PatchInfo>,
    /// m³, Σ cell volumes computed as OpenFOAM does.
    total_volume: f64,
    bounding_box: [[f64; 3]; 2],
    axis_aligned_hex_grid: Option<[usize; 3]>,
    times: Vec<String>,
    processors: usize,
}

/// Runs the command.
pub fn run(a: &InfoArgs) -> anyhow::Result<()> {
    let case = foam::Case::open(&a.case)?;
    let m = case.read_mesh()?;
    let geom = mesh::MeshGeometry::new(&m)
        .with_context(|| format!("mesh of {}", case.root().display()))?;
    let bb = geom.bounds;
    let info = CaseInfo {
        case: case.root().display().to_string(),
        cells: m.n_cells,
        faces: m.n_faces(),
        internal_faces: m.n_internal_faces(),
        points: m.n_points(),
        patches: m
            .boundary
            .iter()
            .map(|p| PatchInfo {
                name: p.name.clone(),
                patch_type: p.patch_type.clone(),
                faces: p.n_faces,
            })
            .collect(),
        total_volume: geom.total_volume(),
        bounding_box: [bb.min.into(), bb.max.into()],
        axis_aligned_hex_grid: mesh::AxisGrid::detect(&m).map(|g| g.dims()),
        times: case.times()?.into_iter().map(|t| t.name).collect(),
        processors: case.processors()?.len(),
    };
    if a.json {
        println!("{}", serde_json::to_string(&info)?);
        return Ok(());
    }
    println!("case            {}", info.case);
    println!("cells           {}", info.cells);
    println!(
        "faces           {} ({} internal)",
        info.faces, info.internal_faces
    );
    println!("points          {}", info.points);
    println!("total volume    {:.10e} m^3", info.total_volume);
    println!(
        "bounding box    ({} {} {}) .. ({} {} {}) m",
        bb.min[0], bb.min[1], bb.min[2], bb.max[0], bb.max[1], bb.max[2]
    );
    if let Some(d) = info.axis_aligned_hex_grid {
        println!(
            "hex grid        {} x {} x {} axis-aligned cells",
            d[0], d[1], d[2]
        );
    }
    println!("patches         {}", info.patches.len());
    for p in &info.patches {
        println!("  {:<20} {:<16} {} faces", p.name, p.patch_type, p.faces);
    }
    println!("times           {}", info.times.join(" "));
    if info.processors > 0 {
        println!("processors      {}", info.processors);
    }
    Ok(())
}
