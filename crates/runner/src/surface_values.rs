//! OpenFOAM's `surfaceFieldValue` function object (a `functions` entry of `system/controlDict`
//! with `type surfaceFieldValue;`, `regionType patch;`) for the native fluid, which has no
//! function objects of its own. CFDEM's periodicChannel tutorial sums `phi` over its cyclic
//! `inlet`, `outlet` and `wall` patches this way, and its `octave/checkVolFlow.m` reads
//! `CFD/postProcessing/<name>/<startTime>/surfaceFieldValue.dat`. With `--fluid openfoam`
//! grainPisoFoam runs OpenFOAM's own.
//!
//! What is read: `regionType` (`patch` only; `faceZone` and `sampledSurface` are left out
//! with a warning), `name` (the patch), `operation`, `fields` (`phi` in m³/s, the kinematic
//! pressure `p` in m²/s² and `U` in m/s on the patch faces; other names are left out with a
//! warning, as OpenFOAM leaves out a field it does not find), `weightField` (a scalar of those)
//! for the weighted operations, `scaleFactor` (default 1), and `writeControl`/`outputControl`
//! (`timeStep`, the default: after every coupling step; `writeTime`/`outputTime`).
//!
//! The operations, for face values v_f, face areas |S_f| and weights w_f, as OpenFOAM v1912's
//! `surfaceFieldValue::processValues` defines them: `sum` Σ v, `weightedSum` Σ w v, `sumMag`
//! Σ |v| (component-wise for vectors), `average` Σ v / n, `weightedAverage` Σ w v / Σ w,
//! `areaAverage` Σ |S| v / Σ |S|, `weightedAreaAverage` Σ w |S| v / Σ w |S|, `areaIntegrate`
//! Σ |S| v, `weightedAreaIntegrate` Σ w |S| v, `min`, `max` (component-wise for vectors),
//! `areaNormalAverage` Σ S·v / Σ |S| and `areaNormalIntegrate` Σ S·v (vectors only). Every
//! result is multiplied by `scaleFactor`. A weighted average whose weights sum to nothing falls
//! back to the unweighted one, as OpenFOAM's does.
//!
//! The file follows OpenFOAM v1912's layout (checked against icoFoam's and grainPisoFoam's
//! files at `writePrecision` 6 and 10): four header lines (region, number of faces, area, scale
//! factor), a `# Time` line naming the columns `operation(field)`, then one row per sample:
//! the time left-aligned in a column `writePrecision + 8` characters wide, then a tab and each
//! value in scientific notation with `writePrecision` digits after the point (vectors as
//! `(x y z)`).

use crate::error::RunError;
use crate::fluid::{FaceField, PatchFaces, RunFluid};
use crate::plan::ControlDict;
use crate::probes::{word_list, Control};
use foam::Dict;
use mesh::v3::V3;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The patch fields a `surfaceFieldValue` may name, and whether each is a vector.
const FIELDS: [(&str, bool); 3] = [("phi", false), ("p", false), ("U", true)];

/// A `surfaceFieldValue` operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    /// Σ v.
    Sum,
    /// Σ w v.
    WeightedSum,
    /// Σ |v|.
    SumMag,
    /// Σ v / n.
    Average,
    /// Σ w v / Σ w.
    WeightedAverage,
    /// Σ |S| v / Σ |S|.
    AreaAverage,
    /// Σ w |S| v / Σ w |S|.
    WeightedAreaAverage,
    /// Σ |S| v.
    AreaIntegrate,
    /// Σ w |S| v.
    WeightedAreaIntegrate,
    /// The smallest value.
    Min,
    /// The largest value.
    Max,
    /// Σ S·v / Σ |S| (vectors).
    AreaNormalAverage,
    /// Σ S·v (vectors).
    AreaNormalIntegrate,
}

impl Operation {
    const ALL: [(&'static str, Operation); 13] = [
        ("sum", Operation::Sum),
        ("weightedSum", Operation::WeightedSum),
        ("sumMag", Operation::SumMag),
        ("average", Operation::Average),
        ("weightedAverage", Operation::WeightedAverage),
        ("areaAverage", Operation::AreaAverage),
        ("weightedAreaAverage", Operation::WeightedAreaAverage),
        ("areaIntegrate", Operation::AreaIntegrate),
        ("weightedAreaIntegrate", Operation::WeightedAreaIntegrate),
        ("min", Operation::Min),
        ("max", Operation::Max),
        ("areaNormalAverage", Operation::AreaNormalAverage),
        ("areaNormalIntegrate", Operation::AreaNormalIntegrate),
    ];

    fn parse(word: &str) -> Option<Operation> {
        Self::ALL
            .iter()
            .find(|(n, _)| *n == word)
            .map(|&(_, op)| op)
    }

    fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(_, op)| *op == self)
            .map_or("?", |(n, _)| n)
    }

    /// True for the operations on the normal component of a vector field.
    fn normal(self) -> bool {
        matches!(
            self,
            Operation::AreaNormalAverage | Operation::AreaNormalIntegrate
        )
    }

    fn weighted(self) -> bool {
        matches!(
            self,
            Operation::WeightedSum
                | Operation::WeightedAverage
                | Operation::WeightedAreaAverage
                | Operation::WeightedAreaIntegrate
        )
    }

    /// The operation on scalar face values `v` with areas `a` and weights `w` (1 without a
    /// weight field); `None` for the vector-only ones.
    fn scalar(self, v: &[f64], faces: &PatchFaces, w: &[f64]) -> Option<f64> {
        let a = &faces.mag_sf;
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
        let triple = |x: &[f64], y: &[f64], z: &[f64]| -> f64 {
            x.iter().zip(y).zip(z).map(|((p, q), r)| p * q * r).sum()
        };
        let n = v.len() as f64;
        let wa: Vec<f64> = w.iter().zip(a).map(|(x, y)| x * y).collect();
        Some(match self {
            Operation::Sum => v.iter().sum(),
            Operation::WeightedSum => dot(w, v),
            Operation::SumMag => v.iter().map(|x| x.abs()).sum(),
            Operation::Average => v.iter().sum::<f64>() / n,
            Operation::WeightedAverage => {
                ratio(dot(w, v), w.iter().sum(), || v.iter().sum::<f64>() / n)
            }
            Operation::AreaAverage => dot(a, v) / a.iter().sum::<f64>(),
            Operation::WeightedAreaAverage => ratio(triple(w, a, v), wa.iter().sum(), || {
                dot(a, v) / a.iter().sum::<f64>()
            }),
            Operation::AreaIntegrate => dot(a, v),
            Operation::WeightedAreaIntegrate => triple(w, a, v),
            Operation::Min => v.iter().copied().fold(f64::INFINITY, f64::min),
            Operation::Max => v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Operation::AreaNormalAverage | Operation::AreaNormalIntegrate => return None,
        })
    }

    /// The operation on vector face values `v`: component by component, except the normal
    /// ones, which give the scalar Σ S·v (over Σ |S| for the average).
    fn vector(self, v: &[V3], faces: &PatchFaces, w: &[f64]) -> Value {
        let normal: f64 = v.iter().zip(&faces.sf).map(|(u, s)| u.dot(s)).sum();
        match self {
            Operation::AreaNormalIntegrate => Value::Scalar(normal),
            Operation::AreaNormalAverage => {
                Value::Scalar(normal / faces.mag_sf.iter().sum::<f64>())
            }
            _ => {
                let part = |c: fn(&V3) -> f64| {
                    let x: Vec<f64> = v.iter().map(c).collect();
                    self.scalar(&x, faces, w).unwrap_or(f64::NAN)
                };
                Value::Vector(V3::new(part(|u| u.x), part(|u| u.y), part(|u| u.z)))
            }
        }
    }
}

/// `num / den`, or `fallback()` when the denominator is too small to divide by (OpenFOAM's
/// ROOTVSMALL, 1e-150).
fn ratio(num: f64, den: f64, fallback: impl FnOnce() -> f64) -> f64 {
    match den.abs() > 1e-150 {
        true => num / den,
        false => fallback(),
    }
}

/// One result of an operation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A scalar.
    Scalar(f64),
    /// A vector.
    Vector(V3),
}

/// One `surfaceFieldValue` function object on a patch.
#[derive(Debug)]
pub struct SurfaceValue {
    /// The function object's name (the `functions` key): its output directory.
    pub name: String,
    /// The patch (`name` entry).
    pub patch: String,
    /// The operation.
    pub operation: Operation,
    /// The fields, in the `fields` order.
    pub fields: Vec<String>,
    /// The weight field of a weighted operation.
    pub weight: Option<String>,
    /// `scaleFactor`.
    pub scale: f64,
    /// When it samples.
    pub control: Control,
    precision: usize,
    /// `<case>/postProcessing/<name>/<startTime>/surfaceFieldValue.dat`.
    path: PathBuf,
    /// The file's text so far, without its header (written at the first sample, when the
    /// patch's faces are known).
    text: String,
}

/// The `surfaceFieldValue` function objects of a case.
#[derive(Debug, Default)]
pub struct SurfaceValues {
    /// In controlDict order.
    pub objects: Vec<SurfaceValue>,
}

impl SurfaceValues {
    /// Reads the `surfaceFieldValue` entries of `<cfd>/system/controlDict`. `patches` are the
    /// mesh's patch names. Returns them and the warnings (objects or fields left out). A
    /// malformed entry is an error naming the file and the key.
    pub fn read(
        cfd: &Path,
        control: &ControlDict,
        start_name: &str,
        patches: &[String],
    ) -> Result<(SurfaceValues, Vec<String>), RunError> {
        let path = &control.path;
        let err = |message: String| RunError::Setup {
            file: path.clone(),
            message,
        };
        let precision = crate::probes::write_precision(&control.body).map_err(err)?;
        let mut out = SurfaceValues::default();
        let mut warnings = Vec::new();
        let Some(functions) = control.body.opt_dict("functions") else {
            return Ok((out, warnings));
        };
        for key in functions.keys() {
            let Some(d) = functions.opt_dict(key) else {
                continue;
            };
            if d.word("type").ok() != Some("surfaceFieldValue") {
                continue;
            }
            match read_one(path, key, d, patches, precision)? {
                Ok((object, mut w)) => {
                    warnings.append(&mut w);
                    out.objects.push(SurfaceValue {
                        path: cfd
                            .join("postProcessing")
                            .join(key)
                            .join(start_name)
                            .join("surfaceFieldValue.dat"),
                        ..object
                    });
                }
                Err(left_out) => warnings.push(left_out),
            }
        }
        Ok((out, warnings))
    }

    /// True without objects.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// Samples the objects due at `time` (every [`Control::TimeStep`] one, the
    /// [`Control::WriteTime`] ones when `write` is set) on `fluid`'s patches and rewrites their
    /// files. A patch or field the fluid does not hold leaves its columns empty.
    pub(crate) fn sample<F: RunFluid>(
        &mut self,
        time: f64,
        write: bool,
        fluid: &F,
    ) -> Result<(), RunError> {
        for o in &mut self.objects {
            if o.control == Control::WriteTime && !write {
                continue;
            }
            let Some(faces) = fluid.patch_faces(&o.patch) else {
                continue;
            };
            if o.text.is_empty() {
                o.text = o.header(&faces);
            }
            let weights = match &o.weight {
                Some(w) => match fluid.patch_field(&o.patch, w) {
                    Some(FaceField::Scalar(w)) => w,
                    _ => vec![f64::NAN; faces.mag_sf.len()],
                },
                None => vec![1.0; faces.mag_sf.len()],
            };
            let width = o.precision + 8;
            let _ = write!(o.text, "{:<width$}", couple::output::time_name(time));
            for f in &o.fields {
                let value = match fluid.patch_field(&o.patch, f) {
                    Some(FaceField::Scalar(v)) => {
                        o.operation.scalar(&v, &faces, &weights).map(Value::Scalar)
                    }
                    Some(FaceField::Vector(v)) => Some(o.operation.vector(&v, &faces, &weights)),
                    None => None,
                };
                o.text.push('\t');
                if let Some(v) = value {
                    o.text.push_str(&format_value(v, o.scale, o.precision));
                }
            }
            o.text.push('\n');
            o.write()?;
        }
        Ok(())
    }
}

/// Reads one entry: the object and its warnings, or (inner `Err`) the one-line warning that
/// leaves it out.
#[allow(clippy::type_complexity)]
fn read_one(
    path: &Path,
    key: &str,
    d: &Dict,
    patches: &[String],
    precision: usize,
) -> Result<Result<(SurfaceValue, Vec<String>), String>, RunError> {
    let at = |k: &str| format!("{}: functions/{key}/{k}", path.display());
    let err = |k: &str, message: String| RunError::Setup {
        file: path.to_owned(),
        message: format!("functions/{key}/{k}: {message}"),
    };
    let region = d.word("regionType").unwrap_or("patch");
    if region != "patch" {
        return Ok(Err(format!(
            "{}: `{region}` is not run by the native fluid (it sums over patches only); \
             {key} left out",
            at("regionType")
        )));
    }
    let patch = d
        .word("name")
        .map_err(|_| err("name", "expected the patch's name".into()))?
        .to_string();
    if !patches.contains(&patch) {
        return Err(err(
            "name",
            format!(
                "no patch `{patch}` in the mesh (patches: {})",
                patches.join(" ")
            ),
        ));
    }
    let op_word = d
        .word("operation")
        .map_err(|_| err("operation", "expected an operation word".into()))?;
    let Some(operation) = Operation::parse(op_word) else {
        return Ok(Err(format!(
            "{}: `{op_word}` is not run by the native fluid (it runs {}); {key} left out",
            at("operation"),
            Operation::ALL.map(|(n, _)| n).join(" ")
        )));
    };
    let mut warnings = Vec::new();
    let (mut fields, mut left_out, mut not_vectors) = (Vec::new(), Vec::new(), Vec::new());
    for f in word_list(d, "fields").map_err(|m| err("fields", m))? {
        match FIELDS.iter().find(|(n, _)| *n == f) {
            Some((_, true)) => fields.push(f),
            Some((_, false)) if !operation.normal() => fields.push(f),
            Some(_) => not_vectors.push(f),
            None => left_out.push(f),
        }
    }
    if !left_out.is_empty() {
        warnings.push(format!(
            "{}: {} not held on patches by the native fluid; not processed (held: {})",
            at("fields"),
            left_out.join(" "),
            FIELDS.map(|(n, _)| n).join(" ")
        ));
    }
    if !not_vectors.is_empty() {
        warnings.push(format!(
            "{}: {} not processed: `{op_word}` takes vector fields",
            at("fields"),
            not_vectors.join(" ")
        ));
    }
    let weight = match operation.weighted() {
        false => None,
        true => {
            let w = d
                .word("weightField")
                .map_err(|_| err("weightField", format!("`{op_word}` needs a weightField")))?;
            match FIELDS.iter().find(|(n, _)| *n == w) {
                Some((_, false)) => Some(w.to_string()),
                _ => {
                    return Err(err(
                        "weightField",
                        format!("`{w}` is not a scalar patch field of the native fluid (phi, p)"),
                    ))
                }
            }
        }
    };
    let scale = d
        .f64_or("scaleFactor", 1.0)
        .map_err(|_| err("scaleFactor", "expected a number".into()))?;
    let control = crate::probes::read_control(d).map_err(|m| err("writeControl", m))?;
    Ok(Ok((
        SurfaceValue {
            name: key.to_string(),
            patch,
            operation,
            fields,
            weight,
            scale,
            control,
            precision,
            path: PathBuf::new(),
            text: String::new(),
        },
        warnings,
    )))
}

impl SurfaceValue {
    /// OpenFOAM's header: region, faces, area and scale factor, then the column names.
    fn header(&self, faces: &PatchFaces) -> String {
        let p = self.precision;
        let area: f64 = faces.mag_sf.iter().sum();
        // a comment pads its text to the column width less "# "; a header value pads its
        // name likewise and follows it with ": " (OpenFOAM's writeFile)
        let w = p + 6;
        let mut h = String::new();
        let _ = writeln!(h, "# {:<w$}patch {}", "Region type : ", self.patch);
        let _ = writeln!(h, "# {:<w$}: {}", "Faces", faces.mag_sf.len());
        let _ = writeln!(h, "# {:<w$}: {}", "Area", sci(area, p));
        let _ = writeln!(h, "# {:<w$}: {}", "Scale factor", sci(self.scale, p));
        let _ = write!(h, "# {:<w$}", "Time");
        for f in &self.fields {
            let _ = write!(h, "\t{}({f})", self.operation.name());
        }
        h.push('\n');
        h
    }

    fn write(&self) -> Result<(), RunError> {
        let io = |path: &Path| {
            let path = path.to_owned();
            move |source| RunError::Io { path, source }
        };
        if let Some(dir) = self.path.parent() {
            std::fs::create_dir_all(dir).map_err(io(dir))?;
        }
        atomic_write::write_atomically(&self.path, |w| w.write_all(self.text.as_bytes()))
            .map_err(io(&self.path))
    }
}

/// A result times `scale`, as OpenFOAM writes it.
fn format_value(v: Value, scale: f64, digits: usize) -> String {
    match v {
        Value::Scalar(x) => sci(scale * x, digits),
        Value::Vector(u) => format!(
            "({} {} {})",
            sci(scale * u.x, digits),
            sci(scale * u.y, digits),
            sci(scale * u.z, digits)
        ),
    }
}

/// `x` in C's `%.{digits}e` form (`-4.081169e-04`), which OpenFOAM's scientific stream writes.
fn sci(x: f64, digits: usize) -> String {
    cfmt::format_e(x, digits)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn faces() -> PatchFaces {
        // three faces of areas 1, 2, 3 m², normal +x
        let mag_sf = vec![1.0, 2.0, 3.0];
        PatchFaces {
            sf: mag_sf.iter().map(|&a| V3::new(a, 0.0, 0.0)).collect(),
            mag_sf,
        }
    }

    #[test]
    fn the_header_at_six_digits_is_openfoams() {
        // grainPisoFoam's (OpenFOAM v1912's) header for CFDEM's periodicChannel `volFlow_inlet`
        let object = SurfaceValue {
            name: "volFlow_inlet".into(),
            patch: "inlet".into(),
            operation: Operation::Sum,
            fields: vec!["phi".into()],
            weight: None,
            scale: 1.0,
            control: Control::TimeStep,
            precision: 6,
            path: PathBuf::new(),
            text: String::new(),
        };
        let faces = PatchFaces {
            sf: vec![V3::new(-1.5625e-4, 0.0, 0.0); 64],
            mag_sf: vec![1.5625e-4; 64],
        };
        assert_eq!(
            object.header(&faces),
            "# Region type : patch inlet\n# Faces       : 64\n# Area        : 1.000000e-02\n\
             # Scale factor: 1.000000e+00\n# Time        \tsum(phi)\n"
        );
    }

    #[test]
    fn operations_match_their_definitions_on_a_small_patch() {
        let f = faces();
        let v = [1.0, -2.0, 4.0];
        let ones = [1.0; 3];
        let w = [0.5, 1.0, 2.0];
        let s = |op: Operation, w: &[f64]| op.scalar(&v, &f, w).unwrap();
        assert_eq!(s(Operation::Sum, &ones), 3.0);
        assert_eq!(s(Operation::SumMag, &ones), 7.0);
        assert_eq!(s(Operation::Average, &ones), 1.0);
        assert_eq!(s(Operation::AreaIntegrate, &ones), 1.0 - 4.0 + 12.0);
        assert_eq!(s(Operation::AreaAverage, &ones), 9.0 / 6.0);
        assert_eq!(s(Operation::WeightedSum, &w), 0.5 - 2.0 + 8.0);
        assert_eq!(s(Operation::WeightedAverage, &w), 6.5 / 3.5);
        assert_eq!(s(Operation::WeightedAreaIntegrate, &w), 0.5 - 4.0 + 24.0);
        assert_eq!(s(Operation::WeightedAreaAverage, &w), 20.5 / 8.5);
        assert_eq!(s(Operation::Min, &ones), -2.0);
        assert_eq!(s(Operation::Max, &ones), 4.0);
        // weights summing to zero: the unweighted average, as OpenFOAM falls back to
        assert_eq!(s(Operation::WeightedAverage, &[1.0, -1.0, 0.0]), 1.0);
        // a uniform velocity (2, 1, 0) m/s through the patch: Σ S·U = 2 × 6 m³/s
        let u = [V3::new(2.0, 1.0, 0.0); 3];
        assert_eq!(
            Operation::AreaNormalIntegrate.vector(&u, &f, &ones),
            Value::Scalar(12.0)
        );
        assert_eq!(
            Operation::AreaNormalAverage.vector(&u, &f, &ones),
            Value::Scalar(2.0)
        );
        assert_eq!(
            Operation::AreaAverage.vector(&u, &f, &ones),
            Value::Vector(V3::new(2.0, 1.0, 0.0))
        );
    }
}
