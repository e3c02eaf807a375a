//! `fix ID all mesh/surface[/stress] file FILE.stl type T [keywords]`: a triangulated surface
//! read from an ASCII or binary STL file ([`crate::trimesh::stl`]), the file name resolved
//! against the deck's working directory as `read_data` is (LIGGGHTS opens it relative to its
//! current directory: `DEM/` in a CFDEM case).
//!
//! Keywords (LIGGGHTS 3.8's `fix mesh/surface`):
//! - `type T` (required): the material type of the surface;
//! - `scale s`, `move dx dy dz` (m), `rotate axis ax ay az angle θ` (degrees, about the
//!   origin): applied to the vertices in the order given ([`Transform`]);
//! - `precision p` (m, 0 < p ≤ 10⁻³; vertex welding and the face tolerance, default 10⁻⁸);
//!   `curvature θ` (degrees, 0 < θ ≤ 60: neighbours whose normals differ by less are coplanar,
//!   default arccos(1 − 10⁻⁵));
//! - accepted without effect: `verbose yes|no`, `heal auto_remove_duplicates|no`,
//!   `curvature_tolerant yes|no`, `temperature T` and `mass_temperature m` (the native DEM
//!   has no heat transfer; a warning says so), and for `mesh/surface/stress` `stress on|off`,
//!   `reference_point x y z`, `wear off`;
//! - refused, naming the keyword: `surface_vel`, `surface_ang_vel` (moving surfaces),
//!   `region`, `element_exclusion_list`, `min_feature_length`, `extrude_planar`, other wear
//!   models; VTK files.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use mesh::v3::V3;

use crate::error::DemError;
use crate::mesh_wall::MeshSurface;
use crate::trimesh::stl::read_stl;
use crate::trimesh::{MeshOptions, Transform, TriMesh};

/// A parsed `fix mesh/surface`, and the warnings it raised.
pub(crate) struct Parsed {
    /// The surface.
    pub surface: Arc<MeshSurface>,
    /// Warnings for the deck line.
    pub warnings: Vec<String>,
}

fn setup(m: String) -> DemError {
    DemError::Setup(m)
}

fn number(w: &[String], k: usize, what: &str) -> Result<f64, DemError> {
    let s = w
        .get(k)
        .ok_or_else(|| setup(format!("missing {what} (argument {k})")))?;
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| setup(format!("{what}: `{s}` is not a number")))
}

fn word<'w>(w: &'w [String], k: usize, what: &str) -> Result<&'w str, DemError> {
    w.get(k)
        .map(String::as_str)
        .ok_or_else(|| setup(format!("missing {what}")))
}

/// What names the fix in messages: its id and style, and whether it is `mesh/surface/stress`.
struct Head<'w> {
    /// The fix id.
    id: &'w str,
    /// `mesh/surface` or `mesh/surface/stress`.
    style: &'w str,
    /// Whether it is `mesh/surface/stress` (which has more keywords).
    stress: bool,
}

/// What the keywords after `file FILE` set.
struct Keywords {
    /// `type T`.
    material_type: Option<u32>,
    /// `scale`, `move`, `rotate`, in the order given.
    transforms: Vec<Transform>,
    /// `precision`, `curvature`.
    opts: MeshOptions,
    /// Keywords accepted without effect.
    warnings: Vec<String>,
}

/// Parses the fix's words (`w[0]` = `fix`) and reads its file relative to `workdir`.
/// `ntypes` is the number of atom types.
pub(crate) fn parse(w: &[String], workdir: &Path, ntypes: usize) -> Result<Parsed, DemError> {
    let id = word(w, 1, "fix id")?;
    let style = word(w, 3, "fix style")?;
    let stress = style == "mesh/surface/stress";
    let head = Head { id, style, stress };
    let path: PathBuf = workdir.join(file_name(w, style)?);
    let Keywords {
        material_type,
        transforms,
        opts,
        mut warnings,
    } = keywords(w, &head, ntypes)?;
    let material_type =
        material_type.ok_or_else(|| setup(format!("{style} {id}: `type T` is required")))?;
    let stl = read_stl(&path)?;
    let triangles: Vec<[V3; 3]> = stl
        .triangles
        .iter()
        .map(|t| t.map(|p| transforms.iter().fold(p, |p, tr| tr.apply(p))))
        .collect();
    let (mesh, dropped) = TriMesh::new(id, &triangles, &stl.origin, opts);
    if !dropped.origin.is_empty() {
        let what = if stl.binary {
            "triangles"
        } else {
            "facets at lines"
        };
        let list: Vec<String> = dropped
            .origin
            .iter()
            .take(10)
            .map(|o| o.to_string())
            .collect();
        warnings.push(format!(
            "{style} {id}: {} degenerate triangle(s) of {} left out ({what} {}{})",
            dropped.origin.len(),
            path.display(),
            list.join(", "),
            if dropped.origin.len() > 10 {
                ", …"
            } else {
                ""
            }
        ));
    }
    if mesh.is_empty() {
        return Err(DemError::Stl {
            file: path,
            line: None,
            message: "no triangle with a non-zero area".into(),
        });
    }
    Ok(Parsed {
        surface: Arc::new(MeshSurface {
            mesh,
            material_type,
            stress,
        }),
        warnings,
    })
}

/// The file name of `file FILE` (`w[4..6]`): an STL file.
fn file_name<'w>(w: &'w [String], style: &str) -> Result<&'w str, DemError> {
    match word(w, 4, "`file`")? {
        "file" => {}
        "generate" | "fix" => {
            return Err(setup(format!(
                "{style}: only `file FILE.stl` is supported, not `{}`",
                w[4]
            )))
        }
        o => return Err(setup(format!("{style}: expected `file`, found `{o}`"))),
    }
    let file = word(w, 5, "STL file name")?;
    if file.to_ascii_lowercase().ends_with(".vtk") {
        return Err(setup(format!(
            "{style}: VTK mesh files are not supported ({file}); use STL"
        )));
    }
    Ok(file)
}

/// Reads the keywords after `file FILE` (from `w[6]`).
fn keywords(w: &[String], head: &Head<'_>, ntypes: usize) -> Result<Keywords, DemError> {
    let Head { id, style, stress } = *head;
    let mut material_type = None;
    let mut transforms = Vec::new();
    let mut opts = MeshOptions::default();
    let mut warnings = Vec::new();
    let mut k = 6;
    while k < w.len() {
        let kw = w[k].as_str();
        let yes_no = |what: &str, allowed: &[&str]| -> Result<(), DemError> {
            let v = word(w, k + 1, &format!("value after `{what}`"))?;
            if allowed.contains(&v) {
                Ok(())
            } else {
                Err(setup(format!(
                    "{what}: `{v}` (expected {})",
                    allowed.join(" or ")
                )))
            }
        };
        match kw {
            "type" => {
                let t = number(w, k + 1, "type")?;
                if t < 1.0 || t.fract() != 0.0 || t as usize > ntypes {
                    return Err(setup(format!(
                        "type {} outside the atom types 1..={ntypes}",
                        w[k + 1]
                    )));
                }
                material_type = Some(t as u32);
                k += 2;
            }
            "scale" | "move" | "rotate" => {
                let (transform, n) = transform(w, k)?;
                transforms.push(transform);
                k += n;
            }
            "precision" => {
                let p = number(w, k + 1, "precision")?;
                if !(p > 0.0 && p <= 1e-3) {
                    return Err(setup(format!(
                        "precision {p}: 0 < precision ≤ 0.001 required"
                    )));
                }
                opts.precision = p;
                k += 2;
            }
            "curvature" => {
                let c = number(w, k + 1, "curvature")?;
                if !(c > 0.0 && c <= 60.0) {
                    return Err(setup(format!(
                        "curvature {c}: 0° < curvature ≤ 60° required"
                    )));
                }
                opts.coplanar_cos = (c * std::f64::consts::PI / 180.0).cos();
                k += 2;
            }
            "verbose" | "curvature_tolerant" => {
                yes_no(kw, &["yes", "no"])?;
                k += 2;
            }
            "heal" => {
                yes_no(kw, &["auto_remove_duplicates", "no"])?;
                k += 2;
            }
            "temperature" | "mass_temperature" => {
                number(w, k + 1, kw)?;
                warnings.push(format!(
                    "{style} {id}: `{kw}` has no effect (the native DEM has no heat transfer)"
                ));
                k += 2;
            }
            "stress" if stress => {
                yes_no(kw, &["on", "off"])?;
                k += 2;
            }
            "wear" if stress => {
                yes_no(kw, &["off"])?;
                k += 2;
            }
            "reference_point" if stress => {
                for j in 1..=3 {
                    number(w, k + j, "reference_point")?;
                }
                k += 4;
            }
            o => {
                let why = match o {
                    "surface_vel" | "surface_ang_vel" => " (moving surfaces are not supported)",
                    _ => "",
                };
                return Err(setup(format!(
                    "{style} keyword `{o}` is not supported{why}"
                )));
            }
        }
    }
    Ok(Keywords {
        material_type,
        transforms,
        opts,
        warnings,
    })
}

/// The transform of the keyword `w[k]` (`scale`, `move` or `rotate`) and the number of words
/// it takes.
fn transform(w: &[String], k: usize) -> Result<(Transform, usize), DemError> {
    match w[k].as_str() {
        "scale" => {
            let s = number(w, k + 1, "scale")?;
            if s <= 0.0 {
                return Err(setup(format!("scale {s} must be > 0")));
            }
            Ok((Transform::Scale(s), 2))
        }
        "move" => {
            let d = V3::new(
                number(w, k + 1, "move dx")?,
                number(w, k + 2, "move dy")?,
                number(w, k + 3, "move dz")?,
            );
            Ok((Transform::Move(d), 4))
        }
        _ => {
            if word(w, k + 1, "`axis`")? != "axis" || word(w, k + 5, "`angle`")? != "angle" {
                return Err(setup("expected `rotate axis ax ay az angle θ`".into()));
            }
            let axis = V3::new(
                number(w, k + 2, "axis x")?,
                number(w, k + 3, "axis y")?,
                number(w, k + 4, "axis z")?,
            );
            // LIGGGHTS's limit on the axis length
            if axis.norm() < 1e-5 {
                return Err(setup("rotate: the axis has (almost) zero length".into()));
            }
            let degrees = number(w, k + 6, "rotate angle")?;
            Ok((Transform::Rotate { axis, degrees }, 7))
        }
    }
}
