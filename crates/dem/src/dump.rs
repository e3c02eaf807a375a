//! `dump ID group custom N FILE columns…`: periodic particle output through `dem-io` (text, or
//! binary when the name ends in `.bin`, as LIGGGHTS decides). A `*` in the name writes one file
//! per snapshot with the step in its place. Values are written at full precision (`dump_modify
//! format` is accepted and has no effect).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use dem_io::{BoxBounds, DumpFormat, Snapshot};

use crate::error::DemError;
use crate::particles::Particles;

/// The `dump custom` columns this crate can write.
pub const COLUMNS: &[&str] = &[
    "id", "type", "x", "y", "z", "vx", "vy", "vz", "fx", "fy", "fz", "omegax", "omegay", "omegaz",
    "tqx", "tqy", "tqz", "radius", "diameter", "mass", "density", "ix", "iy", "iz",
];

/// One periodic dump.
#[derive(Debug)]
pub struct DumpOutput {
    /// Dump id.
    pub name: String,
    /// Write every this many steps.
    pub every: u64,
    /// File name (may contain `*`).
    pub path: PathBuf,
    /// Column names.
    pub columns: Vec<String>,
    /// `dump_modify sort id`.
    pub sort_by_id: bool,
    /// Last step written.
    pub last_step: Option<u64>,
    writer: Option<BufWriter<File>>,
}

impl DumpOutput {
    /// Checks the columns and the period; the file is created at the first write.
    pub fn new(
        name: &str,
        every: u64,
        path: PathBuf,
        columns: Vec<String>,
    ) -> Result<DumpOutput, String> {
        if every == 0 {
            return Err("dump period must be ≥ 1".into());
        }
        if columns.is_empty() {
            return Err("no columns".into());
        }
        for (k, c) in columns.iter().enumerate() {
            if columns[..k].contains(c) {
                return Err(format!("dump column `{c}` given twice"));
            }
            if !COLUMNS.contains(&c.as_str()) {
                return Err(format!(
                    "unsupported dump column `{c}` (supported: {})",
                    COLUMNS.join(" ")
                ));
            }
        }
        Ok(DumpOutput {
            name: name.to_string(),
            every,
            path,
            columns,
            sort_by_id: false,
            last_step: None,
            writer: None,
        })
    }

    /// Writes the snapshot of `step` if it is due and not yet written.
    pub fn maybe_write(
        &mut self,
        step: u64,
        p: &Particles,
        bounds: BoxBounds,
    ) -> Result<(), DemError> {
        if !step.is_multiple_of(self.every) || self.last_step == Some(step) {
            return Ok(());
        }
        let snap = snapshot(step, p, bounds, &self.columns, self.sort_by_id);
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

/// A snapshot of the particles with the given columns (checked against [`COLUMNS`]).
pub fn snapshot(
    step: u64,
    p: &Particles,
    bounds: BoxBounds,
    columns: &[String],
    sort_by_id: bool,
) -> Snapshot {
    let mut order: Vec<usize> = (0..p.len()).collect();
    if sort_by_id {
        order.sort_by_key(|&i| p.id[i]);
    }
    let col = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { order.iter().map(|&i| f(i)).collect() };
    let data: Vec<Vec<f64>> = columns
        .iter()
        .map(|c| match c.as_str() {
            "id" => col(&|i| p.id[i] as f64),
            "type" => col(&|i| p.atom_type[i] as f64),
            "x" => col(&|i| p.x[i][0]),
            "y" => col(&|i| p.x[i][1]),
            "z" => col(&|i| p.x[i][2]),
            "vx" => col(&|i| p.v[i][0]),
            "vy" => col(&|i| p.v[i][1]),
            "vz" => col(&|i| p.v[i][2]),
            "fx" => col(&|i| p.f[i][0]),
            "fy" => col(&|i| p.f[i][1]),
            "fz" => col(&|i| p.f[i][2]),
            "omegax" => col(&|i| p.omega[i][0]),
            "omegay" => col(&|i| p.omega[i][1]),
            "omegaz" => col(&|i| p.omega[i][2]),
            "tqx" => col(&|i| p.torque[i][0]),
            "tqy" => col(&|i| p.torque[i][1]),
            "tqz" => col(&|i| p.torque[i][2]),
            "radius" => col(&|i| p.radius[i]),
            "diameter" => col(&|i| 2.0 * p.radius[i]),
            "mass" => col(&|i| p.mass[i]),
            "density" => col(&|i| p.density[i]),
            // no periodic boundaries: image flags are always 0
            _ => col(&|_| 0.0),
        })
        .collect();
    Snapshot::new(step, bounds, columns.to_vec(), data)
        .expect("columns checked unique and of equal length")
}
