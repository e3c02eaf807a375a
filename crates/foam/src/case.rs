//! The layout of an OpenFOAM case: `system/`, `constant/`, time directories (sorted by their
//! numeric value) and `processorN/` sub-cases of a decomposed run.

use crate::dict::Dict;
use crate::error::{FoamError, Result};
use crate::parser::parse_file;
use crate::poly_mesh::PolyMesh;
use std::path::{Path, PathBuf};

/// An OpenFOAM case directory (or one `processorN` part of a decomposed case).
#[derive(Clone, Debug)]
pub struct Case {
    root: PathBuf,
}

/// A time directory.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeDir {
    /// Directory name as written (`0`, `0.005`, `1e-05`).
    pub name: String,
    /// Its numeric value, s.
    pub value: f64,
    /// Full path.
    pub path: PathBuf,
}

impl Case {
    /// Opens a case: the directory must exist and hold `constant/`.
    pub fn open(root: impl Into<PathBuf>) -> Result<Case> {
        let root = root.into();
        if !root.is_dir() {
            return Err(FoamError::invalid(&root, "case directory does not exist"));
        }
        if !root.join("constant").is_dir() {
            return Err(FoamError::invalid(
                &root,
                "not an OpenFOAM case: there is no constant/ directory",
            ));
        }
        Ok(Case { root })
    }

    /// The case directory.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// `constant/polyMesh`.
    pub fn mesh_dir(&self) -> PathBuf {
        self.root.join("constant").join("polyMesh")
    }

    /// Reads and checks the mesh.
    pub fn read_mesh(&self) -> Result<PolyMesh> {
        crate::read_poly_mesh(&self.mesh_dir())
    }

    /// Time directories sorted by value (names that are not numbers are ignored).
    pub fn times(&self) -> Result<Vec<TimeDir>> {
        let rd = std::fs::read_dir(&self.root).map_err(|e| FoamError::io(&self.root, e))?;
        let mut times = Vec::new();
        for entry in rd {
            let entry = entry.map_err(|e| FoamError::io(&self.root, e))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let Ok(value) = name.parse::<f64>() else {
                continue;
            };
            if value.is_finite() && entry.path().is_dir() {
                times.push(TimeDir {
                    name,
                    value,
                    path: entry.path(),
                });
            }
        }
        times.sort_by(|a, b| a.value.total_cmp(&b.value));
        Ok(times)
    }

    /// The last time directory, if any.
    pub fn latest_time(&self) -> Result<Option<TimeDir>> {
        Ok(self.times()?.pop())
    }

    /// The directory of time `name` (which need not exist yet).
    pub fn time_path(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }

    /// Parses a dictionary file given relative to the case, e.g. `system/controlDict`.
    pub fn read_dict(&self, rel: &str) -> Result<Dict> {
        Ok(parse_file(&self.root.join(rel))?.body)
    }

    /// `system/controlDict`.
    pub fn control_dict(&self) -> Result<Dict> {
        self.read_dict("system/controlDict")
    }

    /// The `processorN` sub-cases, ordered by N (empty for an undecomposed case).
    pub fn processors(&self) -> Result<Vec<(usize, Case)>> {
        let rd = std::fs::read_dir(&self.root).map_err(|e| FoamError::io(&self.root, e))?;
        let mut out = Vec::new();
        for entry in rd {
            let entry = entry.map_err(|e| FoamError::io(&self.root, e))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if let Some(n) = name.strip_prefix("processor").and_then(|n| n.parse().ok()) {
                out.push((n, Case::open(entry.path())?));
            }
        }
        out.sort_by_key(|(n, _)| *n);
        Ok(out)
    }
}

/// OpenFOAM's name of the time directory for `t` seconds, as `Time::timeName` writes it with
/// `timeFormat general` (a C `%g`, [`cfmt::format_g`]): decimal, or scientific below 1e-4 with
/// a signed two-digit exponent (`2e-05`, as pisoFoam names Δt 2e-5 s), to 12 significant
/// digits. 12 digits drop a sum's round-off (`0.010000000000000005` → `0.01`) and keep distinct
/// times distinct (OpenFOAM's `timePrecision` is 6 and grows when names would collide; at 6 it
/// also writes times of 10⁶ s and more in scientific notation, which no CFD-DEM run reaches).
pub fn time_name(t: f64) -> String {
    cfmt::format_g(t, 12)
}

#[cfg(test)]
mod time_name_tests {
    use super::time_name;

    /// Names as Debian's OpenFOAM v1912 writes them (pisoFoam with `timeFormat general`:
    /// `2e-05` for Δt 2e-5 s), and a time summed from Δt without its round-off.
    #[test]
    fn time_names_are_openfoams() {
        let summed: f64 = (0..20).map(|_| 5e-4).sum();
        assert_eq!(format!("{summed}"), "0.010000000000000005");
        assert_eq!(time_name(summed), "0.01");
        assert_eq!(time_name(0.0005), "0.0005");
        assert_eq!(time_name(1e-4), "0.0001");
        assert_eq!(time_name(2e-5), "2e-05");
        assert_eq!(time_name(4e-5), "4e-05");
        assert_eq!(time_name(1.5e-7), "1.5e-07");
        assert_eq!(time_name(0.1), "0.1");
        assert_eq!(time_name(0.0), "0");
        assert_eq!(time_name(2.1), "2.1");
        assert_eq!(time_name(123456.0), "123456");
    }
}
