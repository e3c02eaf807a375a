//! A particle side that replays a series of LIGGGHTS dumps (one-way coupling).
//!
//! The snapshots of the given files are taken in order (files in the order given, snapshots
//! in file order); [`ParticleSide::advance`] moves to the next snapshot whatever the number
//! of steps asked (the dump interval is the coupling interval), and the forces the coupler
//! hands over are kept for the caller ([`DumpReplay::forces`]) instead of moving anything.
//! Densities come from a `density` column, else `mass` / (4πr³/3), else the density given
//! to [`DumpReplay::open`]; velocities from `vx vy vz` (zero if absent, with ids required).
//!
//! [`expand_glob`] turns a pattern with `*` and `?` in its file name into the matching files,
//! sorted by the numbers in their names (`dump.500` before `dump.1000`).

use crate::error::{CoupleError, SideError};
use crate::sides::{ParticleSide, ParticleState};
use dem_io::{DumpReader, ReadOptions, Snapshot};
use mesh::v3::V3;
use std::fs::File;
use std::path::{Path, PathBuf};

/// The particles of one snapshot.
#[derive(Clone, Debug, Default)]
struct Frame {
    ids: Vec<u64>,
    position: Vec<V3>,
    velocity: Vec<V3>,
    radius: Vec<f64>,
    density: Vec<f64>,
}

/// Replays dumps (module docs).
pub struct DumpReplay {
    files: Vec<PathBuf>,
    next_file: usize,
    reader: Option<DumpReader<File>>,
    options: ReadOptions,
    density: Option<f64>,
    dt: f64,
    frame: Frame,
    timestep: u64,
    source: PathBuf,
    forces: (Vec<V3>, Vec<f64>, Vec<V3>),
}

impl DumpReplay {
    /// Opens `files` and reads the first snapshot. `dt` is the DEM time step (s) that turns
    /// dump timesteps into times; `density` (kg/m³) is used when a dump has neither a
    /// `density` nor a `mass` column.
    pub fn open(
        files: Vec<PathBuf>,
        options: ReadOptions,
        dt: f64,
        density: Option<f64>,
    ) -> Result<DumpReplay, CoupleError> {
        if files.is_empty() {
            return Err(CoupleError::Parameter("no dump files to replay".into()));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(CoupleError::Parameter(format!(
                "DEM time step {dt} is not a positive number"
            )));
        }
        let mut r = DumpReplay {
            files,
            next_file: 0,
            reader: None,
            options,
            density,
            dt,
            frame: Frame::default(),
            timestep: 0,
            source: PathBuf::new(),
            forces: (Vec::new(), Vec::new(), Vec::new()),
        };
        if !r.next_snapshot()? {
            return Err(CoupleError::Parameter(format!(
                "no snapshot in {}",
                r.files[0].display()
            )));
        }
        Ok(r)
    }

    /// Moves to the next snapshot; `false` (and nothing changed) after the last one.
    pub fn next_snapshot(&mut self) -> Result<bool, CoupleError> {
        loop {
            if let Some(reader) = self.reader.as_mut() {
                if reader.next_header()?.is_some() {
                    let snap = reader.read_body()?;
                    self.load(&snap)?;
                    return Ok(true);
                }
                self.reader = None;
            }
            let Some(path) = self.files.get(self.next_file) else {
                return Ok(false);
            };
            self.reader = Some(DumpReader::open(path, &self.options)?);
            self.next_file += 1;
        }
    }

    fn load(&mut self, snap: &Snapshot) -> Result<(), CoupleError> {
        let radius = snap.radii()?;
        let position = mesh::v3::from_arrays(&snap.positions()?);
        let ids = snap.ids()?;
        let n = ids.len();
        let velocity = snap
            .vectors(["vx", "vy", "vz"])
            .map(|v| mesh::v3::from_arrays(&v))
            .unwrap_or_else(|| vec![V3::zeros(); n]);
        let density = if let Some(d) = snap.column("density") {
            d.to_vec()
        } else if let Some(m) = snap.column("mass") {
            m.iter()
                .zip(&radius)
                .map(|(&m, &r)| m / (4.0 / 3.0 * std::f64::consts::PI * r * r * r))
                .collect()
        } else if let Some(d) = self.density {
            vec![d; n]
        } else {
            return Err(CoupleError::Parameter(format!(
                "{} (timestep {}): no `density` or `mass` column; give the particle density",
                snap.source().display(),
                snap.timestep
            )));
        };
        self.timestep = snap.timestep;
        self.source = snap.source().to_path_buf();
        self.frame = Frame {
            ids,
            position,
            velocity,
            radius,
            density,
        };
        self.forces = (vec![V3::zeros(); n], vec![0.0; n], vec![V3::zeros(); n]);
        Ok(())
    }

    /// The LIGGGHTS timestep of the current snapshot.
    pub fn timestep(&self) -> u64 {
        self.timestep
    }

    /// The file of the current snapshot.
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// The forces last set for the current snapshot: F_ext (N), β (kg/s), u_f (m/s).
    pub fn forces(&self) -> (&[V3], &[f64], &[V3]) {
        (&self.forces.0, &self.forces.1, &self.forces.2)
    }
}

impl ParticleSide for DumpReplay {
    fn advance(&mut self, _steps: u64) -> Result<(), SideError> {
        if self.next_snapshot()? {
            Ok(())
        } else {
            Err(format!("no snapshot after timestep {}", self.timestep).into())
        }
    }

    fn time_step(&self) -> f64 {
        self.dt
    }

    fn time(&self) -> f64 {
        self.timestep as f64 * self.dt
    }

    fn state(&self) -> ParticleState<'_> {
        ParticleState {
            temperature: None,
            ids: &self.frame.ids,
            position: &self.frame.position,
            velocity: &self.frame.velocity,
            radius: &self.frame.radius,
            density: &self.frame.density,
        }
    }

    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError> {
        let n = self.frame.ids.len();
        if f_ext.len() != n || beta.len() != n || u_f.len() != n {
            return Err(format!("forces for {} particles, expected {n}", f_ext.len()).into());
        }
        self.forces = (f_ext.to_vec(), beta.to_vec(), u_f.to_vec());
        Ok(())
    }
}

/// The files matching `pattern`, whose last component may hold `*` (any run of characters)
/// and `?` (one character); sorted by the numbers in their names, then by name. A pattern
/// without wildcards is returned as is if the file exists.
pub fn expand_glob(pattern: &Path) -> Result<Vec<PathBuf>, CoupleError> {
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = match pattern.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if dir.to_string_lossy().contains(['*', '?']) {
        return Err(CoupleError::Parameter(format!(
            "{}: wildcards are allowed in the file name only",
            pattern.display()
        )));
    }
    if !name.contains(['*', '?']) {
        return if pattern.is_file() {
            Ok(vec![pattern.to_path_buf()])
        } else {
            Err(CoupleError::Parameter(format!(
                "{}: no such file",
                pattern.display()
            )))
        };
    }
    let entries = std::fs::read_dir(&dir).map_err(|source| CoupleError::Io {
        path: dir.clone(),
        source,
    })?;
    let pat: Vec<char> = name.chars().collect();
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .filter(|e| e.path().is_file())
        .filter(|e| {
            wildcard_match(
                &pat,
                &e.file_name().to_string_lossy().chars().collect::<Vec<_>>(),
            )
        })
        .map(|e| e.path())
        .collect();
    if files.is_empty() {
        return Err(CoupleError::Parameter(format!(
            "{}: no file matches",
            pattern.display()
        )));
    }
    files.sort_by_key(|p| {
        let n = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        (numbers(&n), n)
    });
    Ok(files)
}

/// The runs of decimal digits in `s`, as numbers (saturating).
fn numbers(s: &str) -> Vec<u128> {
    s.split(|c: char| !c.is_ascii_digit())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap_or(u128::MAX))
        .collect()
}

/// `*` and `?` matching of `name` against `pat` (iterative, with backtracking to the last `*`).
fn wildcard_match(pat: &[char], name: &[char]) -> bool {
    let (mut p, mut n) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while n < name.len() {
        if p < pat.len() && (pat[p] == '?' || pat[p] == name[n]) {
            p += 1;
            n += 1;
        } else if p < pat.len() && pat[p] == '*' {
            star = Some((p, n));
            p += 1;
        } else if let Some((sp, sn)) = star {
            p = sp + 1;
            n = sn + 1;
            star = Some((sp, sn + 1));
        } else {
            return false;
        }
    }
    pat[p..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(p: &str, n: &str) -> bool {
        wildcard_match(
            &p.chars().collect::<Vec<_>>(),
            &n.chars().collect::<Vec<_>>(),
        )
    }

    #[test]
    fn wildcards() {
        assert!(m("dump*.txt", "dump1000.txt"));
        assert!(m("dump*.txt", "dump.txt"));
        assert!(!m("dump*.txt", "dump1000.bin"));
        assert!(m("d?mp*", "dump"));
        assert!(!m("d?mp", "dmp"));
        assert!(m("*a*b", "xxaxxb"));
        assert!(!m("*a*b", "xxaxxbc"));
        assert!(m("*", ""));
    }

    #[test]
    fn numeric_order() {
        let dir = tempfile::tempdir().unwrap();
        for n in ["dump.1000", "dump.500", "dump.20000", "other.1"] {
            std::fs::write(dir.path().join(n), "").unwrap();
        }
        let got = expand_glob(&dir.path().join("dump.*")).unwrap();
        let names: Vec<_> = got
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["dump.500", "dump.1000", "dump.20000"]);
        let e = expand_glob(&dir.path().join("none*"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no file matches"), "{e}");
    }
}
