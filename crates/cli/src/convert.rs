//! `foamgrain convert`: LIGGGHTS dumps to VTK PolyData (`.vtp`), OpenFOAM cases to VTK
//! UnstructuredGrid (`.vtu`, polyhedral cells included), with `.pvd` series for animations.

use crate::args::DumpArgs;
use anyhow::{bail, Context};
use clap::{Args, Subcommand};
use dem_io::{DumpReader, Snapshot};
use foam::{Case, FieldValues, VolField};
use std::path::{Path, PathBuf};
use vtk::{DataArray, Encoding};

/// What to convert.
#[derive(Subcommand, Debug)]
pub enum ConvertCommand {
    /// A LIGGGHTS dump to VTK particles (.vtp): one snapshot, or every snapshot plus a .pvd.
    Dump(DumpConvert),
    /// An OpenFOAM mesh and its volScalar/volVectorFields to a VTK unstructured grid (.vtu).
    Case(CaseConvert),
}

/// Arguments of `foamgrain convert dump`.
#[derive(Args, Debug)]
pub struct DumpConvert {
    #[command(flatten)]
    dump: DumpArgs,
    /// Convert every snapshot: writes `OUT/<stem>_<timestep>.vtp` and `OUT/<stem>.pvd`.
    #[arg(long)]
    all: bool,
    /// Output file (.vtp), or directory with --all. Default: next to the dump.
    #[arg(short, long, value_name = "PATH")]
    output: Option<PathBuf>,
    /// Write human-readable ASCII VTK instead of base64 binary.
    #[arg(long)]
    ascii: bool,
}

/// Arguments of `foamgrain convert case`.
#[derive(Args, Debug)]
pub struct CaseConvert {
    /// OpenFOAM case directory (or one processorN directory).
    #[arg(long, value_name = "DIR")]
    case: PathBuf,
    /// Time directory to convert: a name such as `0.5`, `latest` (default), or `all`.
    #[arg(long, default_value = "latest")]
    time: String,
    /// Fields to include (comma-separated). Default: every volScalarField and volVectorField.
    #[arg(long, value_delimiter = ',')]
    fields: Vec<String>,
    /// Output .vtu file (one time) or directory (`--time all`). Default: CASE/VTK/.
    #[arg(short, long, value_name = "PATH")]
    output: Option<PathBuf>,
    /// Write human-readable ASCII VTK instead of base64 binary.
    #[arg(long)]
    ascii: bool,
}

/// Runs the command.
pub fn run(c: &ConvertCommand) -> anyhow::Result<()> {
    match c {
        ConvertCommand::Dump(a) => dump(a),
        ConvertCommand::Case(a) => case(a),
    }
}

fn encoding(ascii: bool) -> Encoding {
    if ascii {
        Encoding::Ascii
    } else {
        Encoding::Binary
    }
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .map_or_else(|| "out".into(), |s| s.to_string_lossy().into_owned())
}

/// Position columns, which become the points rather than arrays.
const POSITION_COLUMNS: [&str; 9] = ["x", "y", "z", "xs", "ys", "zs", "xu", "yu", "zu"];

/// Column triples written as one vector array, named after the array.
const VECTOR_COLUMNS: [(&str, [&str; 3]); 5] = [
    ("v", ["vx", "vy", "vz"]),
    ("f", ["fx", "fy", "fz"]),
    ("omega", ["omegax", "omegay", "omegaz"]),
    ("tq", ["tqx", "tqy", "tqz"]),
    ("mu", ["mux", "muy", "muz"]),
];

fn write_snapshot(s: &Snapshot, path: &Path, enc: Encoding) -> anyhow::Result<()> {
    let points = s.positions()?;
    let mut vectors = Vec::new();
    let mut used: Vec<&str> = POSITION_COLUMNS.to_vec();
    for (name, cols) in VECTOR_COLUMNS {
        if let Some(v) = s.vectors(cols) {
            vectors.push((name, v));
            used.extend(cols);
        }
    }
    let ints: Vec<(&str, Vec<i64>)> = ["id", "type"]
        .into_iter()
        .filter_map(|n| {
            let c = s.column(n)?;
            Some((n, c.iter().map(|&x| x as i64).collect()))
        })
        .collect();
    used.extend(["id", "type"]);
    let mut arrays: Vec<DataArray> = ints.iter().map(|(n, v)| DataArray::int64(n, v)).collect();
    arrays.extend(vectors.iter().map(|(n, v)| DataArray::vector(n, v)));
    for (name, values) in s.columns() {
        if !used.contains(&name) {
            arrays.push(DataArray::scalar(name, values));
        }
    }
    vtk::write_vtp_with(path, &points, &arrays, enc)?;
    Ok(())
}

fn dump(a: &DumpConvert) -> anyhow::Result<()> {
    let enc = encoding(a.ascii);
    let opts = a.dump.read_options();
    if !a.all {
        let s = dem_io::read_snapshot(&a.dump.dump, &opts, a.dump.selection()?)?;
        let out = a
            .output
            .clone()
            .unwrap_or_else(|| a.dump.dump.with_extension("vtp"));
        write_snapshot(&s, &out, enc)?;
        println!(
            "wrote {} ({} particles, timestep {})",
            out.display(),
            s.len(),
            s.timestep
        );
        return Ok(());
    }
    let dir = a.output.clone().unwrap_or_else(|| {
        a.dump
            .dump
            .parent()
            .unwrap_or(Path::new("."))
            .join(format!("{}_vtk", stem(&a.dump.dump)))
    });
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let base = stem(&a.dump.dump);
    let mut series = Vec::new();
    for snapshot in DumpReader::open(&a.dump.dump, &opts)? {
        let s = snapshot?;
        let name = format!("{base}_{}.vtp", s.timestep);
        write_snapshot(&s, &dir.join(&name), enc)?;
        series.push((s.timestep as f64, name));
    }
    if series.is_empty() {
        bail!("{}: the dump holds no snapshot", a.dump.dump.display());
    }
    let pvd = dir.join(format!("{base}.pvd"));
    vtk::write_pvd(&pvd, &series)?;
    println!("wrote {} snapshots and {}", series.len(), pvd.display());
    Ok(())
}

/// The volume fields of one time directory, in name order.
fn read_fields(
    dir: &Path,
    only: &[String],
    n_cells: usize,
) -> anyhow::Result<Vec<(String, FieldValues)>> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for want in only {
        if !names.contains(want) {
            bail!("{}: no field `{want}`", dir.display());
        }
    }
    let mut out = Vec::new();
    for name in names {
        if !only.is_empty() && !only.contains(&name) {
            continue;
        }
        let path = dir.join(&name);
        let class = match foam::read_header(&path) {
            Ok(Some(h)) => h.class,
            _ => continue, // not a FoamFile (e.g. a log): not a field
        };
        if class != "volScalarField" && class != "volVectorField" {
            if !only.is_empty() {
                bail!("{}: class {class} cannot be converted", path.display());
            }
            eprintln!("note: skipping {} ({class})", path.display());
            continue;
        }
        let f = VolField::read(&path)?;
        let values = f
            .internal(n_cells)
            .map_err(|m| anyhow::anyhow!("{}: {m}", path.display()))?;
        out.push((name, values));
    }
    Ok(out)
}

fn case(a: &CaseConvert) -> anyhow::Result<()> {
    let case = Case::open(&a.case)?;
    let mesh = case.read_mesh()?;
    let times = case.times()?;
    let selected: Vec<_> = match a.time.as_str() {
        "all" => times,
        "latest" => times.into_iter().last().into_iter().collect(),
        name => {
            let t = times
                .into_iter()
                .find(|t| t.name == name)
                .with_context(|| format!("{}: no time directory `{name}`", a.case.display()))?;
            vec![t]
        }
    };
    let base = stem(case.root().canonicalize()?.as_path());
    let series = a.time == "all";
    let out_dir = match (&a.output, series) {
        (Some(p), true) => p.clone(),
        (Some(p), false) => p.parent().unwrap_or(Path::new(".")).to_path_buf(),
        (None, _) => case.root().join("VTK"),
    };
    let cells = vtk::VtkCells::from_poly_mesh(&mesh)?;
    let mut written = Vec::new();
    // A case without time directories still converts its mesh alone.
    let steps: Vec<Option<foam::TimeDir>> = if selected.is_empty() {
        vec![None]
    } else {
        selected.into_iter().map(Some).collect()
    };
    for t in steps {
        let fields = match &t {
            Some(t) => read_fields(&t.path, &a.fields, mesh.n_cells)?,
            None => Vec::new(),
        };
        let label = t.as_ref().map_or("mesh".to_string(), |t| t.name.clone());
        let path = match (&a.output, series) {
            (Some(p), false) => p.clone(),
            _ => out_dir.join(format!("{base}_{label}.vtu")),
        };
        let arrays: Vec<DataArray> = fields
            .iter()
            .map(|(n, v)| match v {
                FieldValues::Scalar(s) => DataArray::scalar(n, s),
                FieldValues::Vector(v) => DataArray::vector(n, v),
            })
            .collect();
        vtk::write_vtu_cells(&path, &mesh.points, &cells, &arrays, &[], encoding(a.ascii))?;
        println!(
            "wrote {} ({} cells; fields: {})",
            path.display(),
            mesh.n_cells,
            fields
                .iter()
                .map(|f| f.0.as_str())
                .collect::<Vec<_>>()
                .join(" ")
        );
        written.push((t.map_or(0.0, |t| t.value), path));
    }
    if series {
        let pvd = out_dir.join(format!("{base}.pvd"));
        let entries: Vec<(f64, PathBuf)> = written
            .into_iter()
            .map(|(t, p)| (t, PathBuf::from(p.file_name().unwrap())))
            .collect();
        vtk::write_pvd(&pvd, &entries)?;
        println!("wrote {}", pvd.display());
    }
    Ok(())
}
