//! `dump ID group custom N FILE columns…`: periodic particle output through `dem-io` (text, or
//! binary when the name ends in `.bin`, as LIGGGHTS decides). A `*` in the name writes one file
//! per snapshot with the step in its place. Values are written at full precision (`dump_modify
//! format` is accepted and has no effect).
//!
//! `dump ID group custom/vtk N FILE columns…` writes the same columns as VTK particles, as
//! LIGGGHTS's `custom/vtk` does: legacy ASCII PolyData for a `.vtk` name, XML PolyData for
//! `.vtp` ([`vtk`]); `x y z` are the points (required), `vx vy vz` become the vector `v` (and
//! likewise `f`, `omega`, `tq`, `f_dragforce`), every other column a scalar array of its name.
//! Without `*` in the name each snapshot replaces the file.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use dem_io::{BoxBounds, DumpFormat, Snapshot};

use crate::atom_value::{self, AtomValue};
use crate::coupling::Coupling;
use crate::error::DemError;
use crate::heat::Heat;
use crate::particles::Particles;

/// The file kind of a dump.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DumpStyle {
    /// `custom`: LIGGGHTS's dump file (text or binary).
    Custom,
    /// `custom/vtk`: VTK particles.
    Vtk,
}

/// One periodic dump.
#[derive(Debug)]
pub struct DumpOutput {
    /// `custom` or `custom/vtk`.
    pub style: DumpStyle,
    /// Dump id.
    pub name: String,
    /// Write every this many steps.
    pub every: u64,
    /// File name (may contain `*`).
    pub path: PathBuf,
    /// Column names.
    pub columns: Vec<String>,
    values: Vec<AtomValue>,
    /// `dump_modify sort id`.
    pub sort_by_id: bool,
    /// Last step written.
    pub last_step: Option<u64>,
    writer: Option<BufWriter<File>>,
}

impl DumpOutput {
    /// Checks the columns ([`atom_value::NAMES`]; a column may be named twice, as LIGGGHTS
    /// allows) and the period; the file is created at the first write.
    pub fn new(
        name: &str,
        every: u64,
        path: PathBuf,
        columns: Vec<String>,
    ) -> Result<DumpOutput, String> {
        DumpOutput::new_in(name, every, path, columns, &[])
    }

    /// [`DumpOutput::new`] with the columns named as [`AtomValue::parse_in`] reads them
    /// (`f_ID[0]` of the fixes in `temperature_fixes` is the temperature).
    pub fn new_in(
        name: &str,
        every: u64,
        path: PathBuf,
        columns: Vec<String>,
        temperature_fixes: &[String],
    ) -> Result<DumpOutput, String> {
        if every == 0 {
            return Err("dump period must be ≥ 1".into());
        }
        if columns.is_empty() {
            return Err("no columns".into());
        }
        let values = columns
            .iter()
            .map(|c| {
                AtomValue::parse_in(c, temperature_fixes).ok_or_else(|| {
                    format!(
                        "unsupported dump column `{c}` (supported: {})",
                        atom_value::NAMES
                    )
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(DumpOutput {
            style: DumpStyle::Custom,
            name: name.to_string(),
            every,
            path,
            columns,
            values,
            sort_by_id: false,
            last_step: None,
            writer: None,
        })
    }

    /// A `custom/vtk` dump: the columns must include `x y z`, the name end in `.vtk` or `.vtp`.
    pub fn new_vtk(
        name: &str,
        every: u64,
        path: PathBuf,
        columns: Vec<String>,
        temperature_fixes: &[String],
    ) -> Result<DumpOutput, String> {
        let d = DumpOutput::new_in(name, every, path, columns, temperature_fixes)?;
        for k in 0..3 {
            if !d.values.contains(&AtomValue::Position(k)) {
                return Err("dump custom/vtk needs the columns x y z".into());
            }
        }
        match d.path.extension().and_then(|e| e.to_str()) {
            Some("vtk" | "vtp") => {}
            _ => {
                return Err(format!(
                    "dump custom/vtk: `{}` must end in .vtk (legacy) or .vtp (XML)",
                    d.path.display()
                ))
            }
        }
        Ok(DumpOutput {
            style: DumpStyle::Vtk,
            ..d
        })
    }

    /// Whether the snapshot of `step` is due and not yet written.
    pub fn is_due(&self, step: u64) -> bool {
        step.is_multiple_of(self.every) && self.last_step != Some(step)
    }

    /// Writes the snapshot of `step` if it is due and not yet written.
    pub fn maybe_write(
        &mut self,
        step: u64,
        p: &Particles,
        coupling: &Coupling,
        heat: Option<&Heat>,
        bounds: BoxBounds,
    ) -> Result<(), DemError> {
        if !self.is_due(step) {
            return Ok(());
        }
        let wildcard = self.path.to_string_lossy().contains('*');
        let file = if wildcard {
            PathBuf::from(self.path.to_string_lossy().replace('*', &step.to_string()))
        } else {
            self.path.clone()
        };
        let io_err = |source| DemError::DumpWrite {
            file: file.clone(),
            source,
        };
        if self.style == DumpStyle::Vtk {
            if let Some(dir) = file.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir).map_err(io_err)?;
            }
            self.write_vtk(&file, p, coupling, heat)?;
            self.last_step = Some(step);
            return Ok(());
        }
        let snap = snapshot(
            step,
            (p, coupling, heat),
            bounds,
            &self.columns,
            &self.values,
            self.sort_by_id,
        );
        if wildcard || self.writer.is_none() {
            if let Some(dir) = file.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir).map_err(io_err)?;
            }
            self.writer = Some(BufWriter::new(File::create(&file).map_err(io_err)?));
        }
        let w = self.writer.as_mut().expect("writer opened above");
        match DumpFormat::from_path(Path::new(&file)) {
            DumpFormat::Binary => dem_io::write_binary(w, &snap),
            DumpFormat::Text => dem_io::write_text(w, &snap),
        }
        .and_then(|_| w.flush())
        .map_err(io_err)?;
        self.last_step = Some(step);
        Ok(())
    }
}

impl DumpOutput {
    /// One `custom/vtk` snapshot.
    fn write_vtk(
        &self,
        file: &Path,
        p: &Particles,
        coupling: &Coupling,
        heat: Option<&Heat>,
    ) -> Result<(), DemError> {
        let mut order: Vec<usize> = (0..p.len()).collect();
        if self.sort_by_id {
            order.sort_by_key(|&i| p.id[i]);
        }
        let col = |v: AtomValue| -> Vec<f64> {
            order.iter().map(|&i| v.get(p, coupling, heat, i)).collect()
        };
        let points: Vec<[f64; 3]> = order.iter().map(|&i| p.x[i].into()).collect();
        let mut scalars: Vec<(String, Vec<f64>)> = Vec::new();
        let mut ints: Vec<(String, Vec<i64>)> = Vec::new();
        let mut vectors: Vec<(String, Vec<[f64; 3]>)> = Vec::new();
        for (name, &v) in self.columns.iter().zip(&self.values) {
            let stem = match v {
                AtomValue::Position(_) => continue,
                AtomValue::Velocity(_) => Some("v"),
                AtomValue::Force(_) => Some("f"),
                AtomValue::Omega(_) => Some("omega"),
                AtomValue::Torque(_) => Some("tq"),
                AtomValue::DragForce(_) => Some("f_dragforce"),
                _ => None,
            };
            let triplet = stem.and_then(|stem| {
                let names: [String; 3] = match stem {
                    "f_dragforce" => [1, 2, 3].map(|k| format!("f_dragforce[{k}]")),
                    s => ["x", "y", "z"].map(|c| format!("{s}{c}")),
                };
                names
                    .iter()
                    .all(|n| self.columns.contains(n))
                    .then_some((stem, names))
            });
            match triplet {
                Some((stem, names)) => {
                    if vectors.iter().any(|(n, _)| n == stem) {
                        continue;
                    }
                    let c: Vec<Vec<f64>> = names
                        .iter()
                        .map(|n| col(AtomValue::parse(n).expect("a dump column")))
                        .collect();
                    let vec = (0..order.len())
                        .map(|i| [c[0][i], c[1][i], c[2][i]])
                        .collect();
                    vectors.push((stem.to_string(), vec));
                }
                None if scalars.iter().any(|(n, _)| n == name)
                    || ints.iter().any(|(n, _)| n == name) => {}
                None if matches!(v, AtomValue::Id | AtomValue::Type) => {
                    ints.push((name.clone(), col(v).iter().map(|&x| x as i64).collect()))
                }
                None => scalars.push((name.clone(), col(v))),
            }
        }
        let mut arrays: Vec<vtk::DataArray> = Vec::new();
        arrays.extend(ints.iter().map(|(n, v)| vtk::DataArray::int64(n, v)));
        arrays.extend(vectors.iter().map(|(n, v)| vtk::DataArray::vector(n, v)));
        arrays.extend(scalars.iter().map(|(n, v)| vtk::DataArray::scalar(n, v)));
        let written = match file.extension().and_then(|e| e.to_str()) {
            Some("vtp") => vtk::write_vtp(file, &points, &arrays),
            _ => vtk::write_legacy_vtk(
                file,
                &format!("foamgrain dump {}", self.name),
                &points,
                &arrays,
            ),
        };
        written.map_err(|e| DemError::DumpWrite {
            file: file.to_path_buf(),
            source: std::io::Error::other(e.to_string()),
        })
    }
}

/// A snapshot of the particles with the given columns and the values they name.
fn snapshot(
    step: u64,
    (p, coupling, heat): (&Particles, &Coupling, Option<&Heat>),
    bounds: BoxBounds,
    columns: &[String],
    values: &[AtomValue],
    sort_by_id: bool,
) -> Snapshot {
    let mut order: Vec<usize> = (0..p.len()).collect();
    if sort_by_id {
        order.sort_by_key(|&i| p.id[i]);
    }
    let data: Vec<Vec<f64>> = values
        .iter()
        .map(|v| order.iter().map(|&i| v.get(p, coupling, heat, i)).collect())
        .collect();
    Snapshot::new(step, bounds, columns.to_vec(), data)
        .expect("columns named twice carry the same values; all columns have one length")
}
