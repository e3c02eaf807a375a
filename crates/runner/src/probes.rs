//! OpenFOAM's `probes` function object (a `functions` entry of `system/controlDict` with
//! `type probes;`) for the native fluid, which has no function objects of its own: CFDEM's
//! Ergun tutorials compare the Ergun equation with the pressure difference of two probes, read
//! by their post-processing scripts from `CFD/postProcessing/<name>/<startTime>/p`.
//!
//! What is read: `probeLocations` (points, m), `fields` (any of the coupled run's cell fields
//! `p`, `U`, `voidfraction`, `Ksl`, `Us`, `f`, `rho`; other names are left out with one
//! warning, as OpenFOAM leaves out fields it does not hold), and `writeControl`/`outputControl`
//! (`timeStep`, the default, samples after every coupling step; `writeTime`/`outputTime` at the
//! write times). A point outside the mesh is left out with a warning (OpenFOAM: "Did not find
//! location … Skipping location"). The value is the one of the cell holding the point (OpenFOAM's
//! default, `interpolationScheme cell`).
//!
//! The file layout follows OpenFOAM v1912's `probes::writeValues`: a header line
//! `# Probe i (x y z)` per point, the probe-index and `Time` header lines, then one row per
//! sample, the time and each probe's value to `writePrecision` significant digits (6 by
//! default) in columns `writePrecision + 7` characters wide (vectors as `(x y z)`). With `--fluid openfoam` grainPisoFoam runs OpenFOAM's own probes instead.

use crate::error::RunError;
use crate::monitors::{Field, StepFields};
use crate::plan::ControlDict;
use foam::{Dict, Item};
use mesh::v3::V3;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The fields of a run with heat a probe may also sample (scalars).
const HEAT_FIELDS: [&str; 2] = ["T", "Tsource"];

/// The fields a probe may sample, and whether each is a vector.
const FIELDS: [(&str, bool); 7] = [
    ("p", false),
    ("voidfraction", false),
    ("Ksl", false),
    ("rho", false),
    ("U", true),
    ("Us", true),
    ("f", true),
];

/// When a probe set samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// After every coupling step.
    TimeStep,
    /// At the write times.
    WriteTime,
}

/// One `probes` function object.
#[derive(Debug)]
pub struct ProbeSet {
    /// The function object's name (the `functions` key, or its `name` entry).
    pub name: String,
    /// The points found in the mesh and the cell holding each.
    pub points: Vec<(V3, usize)>,
    /// The sampled fields, in the `fields` order.
    pub fields: Vec<String>,
    /// When it samples.
    pub control: Control,
    /// Significant digits (controlDict's `writePrecision`, OpenFOAM's default 6).
    precision: usize,
    /// `<case>/postProcessing/<name>/<startTime>`.
    dir: PathBuf,
    /// Each field's file text so far (rewritten whole at every write).
    text: Vec<String>,
}

/// The `probes` function objects of a case.
#[derive(Debug, Default)]
pub struct Probes {
    /// The sets, in controlDict order.
    pub sets: Vec<ProbeSet>,
}

impl Probes {
    /// Reads the `probes` entries of the case's `system/controlDict` (`cfd`: the case, where
    /// `postProcessing/` goes; `heat`: the run solves T, so `T` and `Tsource` may be probed) and locates their points in
    /// `mesh` (`locate` gives the cell holding a point). Returns the probes and the warnings
    /// (fields or points left out). A malformed entry is an error naming the file and the key.
    pub fn read(
        cfd: &Path,
        control: &ControlDict,
        start_name: &str,
        heat: bool,
        locate: &dyn Fn(V3) -> Option<usize>,
    ) -> Result<(Probes, Vec<String>), RunError> {
        let heat_fields = HEAT_FIELDS.map(|n| (n, false));
        let available: Vec<(&str, bool)> = FIELDS
            .iter()
            .chain(if heat { &heat_fields[..] } else { &[] })
            .copied()
            .collect();
        Probes::read_fields(cfd, control, start_name, &available, locate)
    }

    /// [`Probes::read`] for a run that holds the fields `available` (name, whether a vector);
    /// a probed field not among them is left out with a warning, as OpenFOAM does.
    pub fn read_fields(
        cfd: &Path,
        control: &ControlDict,
        start_name: &str,
        available: &[(&str, bool)],
        locate: &dyn Fn(V3) -> Option<usize>,
    ) -> Result<(Probes, Vec<String>), RunError> {
        let path = &control.path;
        let err = |message: String| RunError::Setup {
            file: path.clone(),
            message,
        };
        let mut probes = Probes::default();
        let mut warnings = Vec::new();
        let precision = write_precision(&control.body).map_err(err)?;
        let Some(functions) = control.body.opt_dict("functions") else {
            return Ok((probes, warnings));
        };
        for key in functions.keys() {
            let Some(d) = functions.opt_dict(key) else {
                continue;
            };
            if d.word("type").ok() != Some("probes") {
                continue;
            }
            let at = |k: &str| format!("functions/{key}/{k}");
            let name = d.word("name").unwrap_or(key).to_string();
            let points =
                read_points(d).map_err(|m| err(format!("{}: {m}", at("probeLocations"))))?;
            let mut found = Vec::new();
            for p in points {
                match locate(p) {
                    Some(c) => found.push((p, c)),
                    None => warnings.push(format!(
                        "{}: {}: point ({} {} {}) is outside the mesh; left out",
                        path.display(),
                        at("probeLocations"),
                        p.x,
                        p.y,
                        p.z
                    )),
                }
            }
            let mut fields = Vec::new();
            let mut left_out = Vec::new();
            for f in word_list(d, "fields").map_err(|m| err(format!("{}: {m}", at("fields"))))? {
                if available.iter().any(|(n, _)| *n == f) {
                    fields.push(f);
                } else {
                    left_out.push(f);
                }
            }
            if !left_out.is_empty() {
                warnings.push(format!(
                    "{}: {}: {} not held by the native run; not probed (probed: {})",
                    path.display(),
                    at("fields"),
                    left_out.join(" "),
                    available
                        .iter()
                        .map(|(n, _)| *n)
                        .collect::<Vec<_>>()
                        .join(" ")
                ));
            }
            let control =
                read_control(d).map_err(|m| err(format!("{}: {m}", at("writeControl"))))?;
            let header = header(&found, precision);
            probes.sets.push(ProbeSet {
                precision,
                dir: cfd.join("postProcessing").join(&name).join(start_name),
                text: vec![header; fields.len()],
                name,
                points: found,
                fields,
                control,
            });
        }
        Ok((probes, warnings))
    }

    /// True without probe sets.
    pub fn is_empty(&self) -> bool {
        self.sets.is_empty()
    }

    /// Samples the sets due at `time` (every set with [`Control::TimeStep`], and the
    /// [`Control::WriteTime`] ones when `write` is set) and rewrites their files.
    pub(crate) fn sample(
        &mut self,
        time: f64,
        write: bool,
        fields: &StepFields<'_>,
    ) -> Result<(), RunError> {
        self.sample_with(time, write, &|name| fields.get(name))
    }

    /// [`Probes::sample`] with the fields given by name (`get` gives each field
    /// [`Probes::read_fields`] accepted).
    pub(crate) fn sample_with<'f>(
        &mut self,
        time: f64,
        write: bool,
        get: &dyn Fn(&str) -> Field<'f>,
    ) -> Result<(), RunError> {
        for set in &mut self.sets {
            if set.control == Control::WriteTime && !write {
                continue;
            }
            let (digits, width) = (set.precision, set.precision + 7);
            let g = |x: f64| sig(x, digits);
            for (name, text) in set.fields.iter().zip(&mut set.text) {
                let _ = write!(text, "{:>width$}", couple::output::time_name(time));
                let field = get(name);
                for &(_, c) in &set.points {
                    let value = match &field {
                        Field::Scalar(phi) => g(phi[c]),
                        Field::Vector(u) => {
                            let v = u[c];
                            format!("({} {} {})", g(v.x), g(v.y), g(v.z))
                        }
                    };
                    let _ = write!(text, " {value:>width$}");
                }
                text.push('\n');
            }
            set.write()?;
        }
        Ok(())
    }
}

impl ProbeSet {
    fn write(&self) -> Result<(), RunError> {
        let io = |path: &Path| {
            let path = path.to_owned();
            move |source| RunError::Io { path, source }
        };
        std::fs::create_dir_all(&self.dir).map_err(io(&self.dir))?;
        for (name, text) in self.fields.iter().zip(&self.text) {
            let path = self.dir.join(name);
            atomic_write::write_atomically(&path, |w| w.write_all(text.as_bytes()))
                .map_err(io(&path))?;
        }
        Ok(())
    }
}

/// The header of a probe file: one `# Probe i (x y z)` line per point, then the index and
/// `Time` lines.
fn header(points: &[(V3, usize)], digits: usize) -> String {
    let width = digits + 7;
    let g = |x: f64| sig(x, digits);
    let mut h = String::new();
    for (i, (p, _)) in points.iter().enumerate() {
        let _ = writeln!(h, "# Probe {i} ({} {} {})", g(p.x), g(p.y), g(p.z));
    }
    let _ = write!(h, "#{:>w$}", "Probe", w = width - 1);
    for i in 0..points.len() {
        let _ = write!(h, " {i:>width$}");
    }
    let _ = writeln!(h, "\n#{:>w$}", "Time", w = width - 1);
    h
}

/// `x` to `digits` significant digits, shortest form.
fn sig(x: f64, digits: usize) -> String {
    let rounded: f64 = format!("{x:.*e}", digits.saturating_sub(1))
        .parse()
        .unwrap_or(x);
    format!("{rounded}")
}

fn read_points(d: &Dict) -> Result<Vec<V3>, String> {
    let items = list(d, "probeLocations")?;
    items
        .iter()
        .map(|it| match it {
            Item::List(c) if c.len() == 3 => {
                let x: Vec<f64> = c.iter().filter_map(Item::as_f64).collect();
                (x.len() == 3)
                    .then(|| V3::new(x[0], x[1], x[2]))
                    .ok_or_else(|| format!("`{it:?}` is not a point (x y z)"))
            }
            other => Ok(other
                .as_vector()
                .map(|[x, y, z]| V3::new(x, y, z))
                .ok_or_else(|| format!("`{other:?}` is not a point (x y z)"))?),
        })
        .collect()
}

/// controlDict's `writePrecision` (significant digits; OpenFOAM's default 6).
pub(crate) fn write_precision(control_dict: &Dict) -> Result<usize, String> {
    match control_dict.get("writePrecision") {
        None => Ok(6),
        Some(_) => match control_dict.label("writePrecision") {
            Ok(n) if (1..=17).contains(&n) => Ok(n as usize),
            _ => Err("writePrecision: expected a whole number 1 to 17".into()),
        },
    }
}

/// A function object's `writeControl` (or the older `outputControl`), `timeStep` by default.
pub(crate) fn read_control(d: &Dict) -> Result<Control, String> {
    match d
        .word("writeControl")
        .or_else(|_| d.word("outputControl"))
        .unwrap_or("timeStep")
    {
        "timeStep" => Ok(Control::TimeStep),
        "writeTime" | "outputTime" => Ok(Control::WriteTime),
        other => Err(format!(
            "`{other}`; the native fluid's function objects take timeStep or writeTime"
        )),
    }
}

/// The words of `key ( … );`, e.g. a function object's `fields`.
pub(crate) fn word_list(d: &Dict, key: &str) -> Result<Vec<String>, String> {
    list(d, key)?
        .iter()
        .map(|it| {
            it.as_word()
                .map(str::to_string)
                .ok_or_else(|| format!("`{it:?}` is not a field name"))
        })
        .collect()
}

/// The numbers of `key ( … );` (with or without a length before the list).
pub(crate) fn number_list(d: &Dict, key: &str) -> Result<Vec<f64>, String> {
    if let [Item::Scalars(v)] | [Item::Label(_), Item::Scalars(v)] =
        d.stream(key).map_err(|e| e.to_string())?
    {
        return Ok(v.clone());
    }
    list(d, key)?
        .iter()
        .map(|i| i.as_f64().ok_or_else(|| format!("`{i:?}` is not a number")))
        .collect()
}

/// The items of `key ( … );` (with or without a length before the list).
fn list(d: &Dict, key: &str) -> Result<Vec<Item>, String> {
    match d.stream(key).map_err(|e| e.to_string())? {
        [Item::List(items)] | [Item::Label(_), Item::List(items)] => Ok(items.clone()),
        [Item::Vectors(v)] | [Item::Label(_), Item::Vectors(v)] => Ok(v
            .iter()
            .map(|&[x, y, z]| Item::List(vec![Item::Scalar(x), Item::Scalar(y), Item::Scalar(z)]))
            .collect()),
        other => Err(format!("expected a list, found `{other:?}`")),
    }
}
