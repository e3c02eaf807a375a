//! `dump ID group custom N FILE columns…`: periodic particle output through `dem-io` (text, or
//! binary when the name ends in `.bin`, as LIGGGHTS decides). A `*` in the name writes one file
//! per snapshot with the step in its place. Values are written at full precision (`dump_modify
//! format` is accepted and has no effect).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use dem_io::{BoxBounds, DumpFormat, Snapshot};

use crate::atom_value::{self, AtomValue};
use crate::coupling::Coupling;
use crate::error::DemError;
use crate::particles::Particles;

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
        if every == 0 {
            return Err("dump period must be ≥ 1".into());
        }
        if columns.is_empty() {
            return Err("no columns".into());
        }
        let values = columns
            .iter()
            .map(|c| {
                AtomValue::parse(c).ok_or_else(|| {
                    format!(
                        "unsupported dump column `{c}` (supported: {})",
                        atom_value::NAMES
                    )
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(DumpOutput {
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

    /// Writes the snapshot of `step` if it is due and not yet written.
    pub fn maybe_write(
        &mut self,
        step: u64,
        p: &Particles,
        coupling: &Coupling,
        bounds: BoxBounds,
    ) -> Result<(), DemError> {
        if !step.is_multiple_of(self.every) || self.last_step == Some(step) {
            return Ok(());
        }
        let snap = snapshot(
            step,
            p,
            coupling,
            bounds,
            &self.columns,
            &self.values,
            self.sort_by_id,
        );
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

/// A snapshot of the particles with the given columns and the values they name.
fn snapshot(
    step: u64,
    p: &Particles,
    coupling: &Coupling,
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
        .map(|v| order.iter().map(|&i| v.get(p, coupling, i)).collect())
        .collect();
    Snapshot::new(step, bounds, columns.to_vec(), data)
        .expect("columns named twice carry the same values; all columns have one length")
}
