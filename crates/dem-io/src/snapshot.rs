//! The data model: one snapshot as a structure of arrays, and a typed particle view of it.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::bounds::BoxBounds;
use crate::error::{DumpError, ErrorKind, Location, IN_MEMORY};

/// Everything a dump says about a snapshot before its rows.
#[derive(Debug, Clone, PartialEq)]
pub struct SnapshotHeader {
    /// Timestep number (`ITEM: TIMESTEP`).
    pub timestep: u64,
    /// Text of `ITEM: LABEL` (set by `dump_modify … label`), if any. Binary dumps have none.
    pub label: Option<String>,
    /// Number of particles (rows).
    pub natoms: u64,
    /// Box bounds and boundary conditions.
    pub bounds: BoxBounds,
    /// Column names in file order (from `ITEM: ATOMS`, or given by the caller for binary dumps).
    pub columns: Vec<String>,
    /// 0-based position of the snapshot in its file.
    pub index: usize,
    /// Byte offset of the snapshot's first header byte in its file.
    pub offset: u64,
}

/// One snapshot: header data plus one `f64` vector per column (structure of arrays).
///
/// Invariant: column names are unique and every column has [`Snapshot::len`] values. Values are
/// what the dump holds, in the simulation's units (SI for `units si`: m, m/s, N, rad/s, kg/m³, kg).
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Timestep number.
    pub timestep: u64,
    /// `ITEM: LABEL` text, if any.
    pub label: Option<String>,
    /// Box bounds and boundary conditions.
    pub bounds: BoxBounds,
    source: PathBuf,
    names: Vec<String>,
    data: Vec<Vec<f64>>,
}

/// Checks that column names are non-empty, whitespace-free and unique.
pub(crate) fn check_names(names: &[String]) -> Result<(), ErrorKind> {
    if names.is_empty() {
        return Err(ErrorKind::NoColumns);
    }
    for n in names {
        if n.is_empty() || n.chars().any(char::is_whitespace) {
            return Err(ErrorKind::BadHeader(format!("invalid column name `{n}`")));
        }
    }
    Ok(())
}

/// A column named twice must carry the same values both times: LIGGGHTS writes a column twice
/// when the deck names it twice (`dump … id type type x y z`, as in CFDEM-PFM's tutorials), and
/// [`Snapshot::column`] gives the first; two different columns of one name are an error.
pub(crate) fn check_duplicates(names: &[String], data: &[Vec<f64>]) -> Result<(), ErrorKind> {
    let mut first: HashMap<&str, usize> = HashMap::with_capacity(names.len());
    for (k, n) in names.iter().enumerate() {
        match first.get(n.as_str()) {
            Some(&j) if data[j] != data[k] => return Err(ErrorKind::DuplicateColumn(n.clone())),
            Some(_) => {}
            None => {
                first.insert(n, k);
            }
        }
    }
    Ok(())
}

impl Snapshot {
    /// Builds a snapshot from column names and column data (same order, equal lengths).
    ///
    /// Errors: no columns, empty names, a name given twice with different values, columns of
    /// unequal length. The snapshot's
    /// source is [`IN_MEMORY`]; change it with [`Snapshot::with_source`].
    pub fn new(
        timestep: u64,
        bounds: BoxBounds,
        names: Vec<String>,
        data: Vec<Vec<f64>>,
    ) -> Result<Snapshot, DumpError> {
        let err = |kind| DumpError::new(IN_MEMORY, Location::Unknown, kind);
        check_names(&names).map_err(err)?;
        if names.len() != data.len() {
            return Err(err(ErrorKind::ColumnCountMismatch {
                in_file: data.len(),
                given: names.len(),
                names: names.join(" "),
            }));
        }
        check_duplicates(&names, &data).map_err(err)?;
        let n = data[0].len();
        for (name, col) in names.iter().zip(&data) {
            if col.len() != n {
                return Err(err(ErrorKind::ColumnLength {
                    column: name.clone(),
                    expected: n,
                    found: col.len(),
                }));
            }
        }
        Ok(Snapshot {
            timestep,
            label: None,
            bounds,
            source: PathBuf::from(IN_MEMORY),
            names,
            data,
        })
    }

    /// Assembles a snapshot read by a reader (names already checked, lengths equal).
    pub(crate) fn from_parts(
        header: SnapshotHeader,
        source: &Path,
        data: Vec<Vec<f64>>,
    ) -> Snapshot {
        debug_assert_eq!(header.columns.len(), data.len());
        Snapshot {
            timestep: header.timestep,
            label: header.label,
            bounds: header.bounds,
            source: source.to_path_buf(),
            names: header.columns,
            data,
        }
    }

    /// Sets the label written as `ITEM: LABEL`.
    pub fn with_label(mut self, label: impl Into<String>) -> Snapshot {
        self.label = Some(label.into());
        self
    }

    /// Sets the file name used in error messages.
    pub fn with_source(mut self, source: impl Into<PathBuf>) -> Snapshot {
        self.source = source.into();
        self
    }

    /// The file the snapshot was read from ([`IN_MEMORY`] if built in memory).
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.data[0].len()
    }

    /// `true` if the snapshot has no particles.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Column names in file order.
    pub fn column_names(&self) -> &[String] {
        &self.names
    }

    /// All columns in file order.
    pub fn columns(&self) -> impl Iterator<Item = (&str, &[f64])> {
        self.names
            .iter()
            .map(String::as_str)
            .zip(self.data.iter().map(Vec::as_slice))
    }

    /// The values of column `name`, if present.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(&self.data[i])
    }

    /// The values of column `name`, or an error naming the file and the missing column.
    pub fn require(&self, name: &str) -> Result<&[f64], DumpError> {
        self.column(name).ok_or_else(|| self.missing(name))
    }

    /// Takes the snapshot apart into column names and column data.
    pub fn into_columns(self) -> (Vec<String>, Vec<Vec<f64>>) {
        (self.names, self.data)
    }

    fn missing(&self, what: &str) -> DumpError {
        DumpError::new(
            self.source.clone(),
            Location::Unknown,
            ErrorKind::MissingColumn {
                timestep: self.timestep,
                column: what.to_string(),
                available: self.names.join(" "),
            },
        )
    }

    /// First of several alternative column triples that is fully present.
    fn triple(&self, names: [&str; 3]) -> Option<[&[f64]; 3]> {
        Some([
            self.column(names[0])?,
            self.column(names[1])?,
            self.column(names[2])?,
        ])
    }

    /// Three columns zipped into vectors, or `None` if any is absent.
    pub fn vectors(&self, names: [&str; 3]) -> Option<Vec<[f64; 3]>> {
        self.triple(names).map(zip3)
    }

    /// Particle positions (m). Taken from `x y z`, else `xu yu zu` (unwrapped), else scaled
    /// `xs ys zs` or `xsu ysu zsu` converted with the box (exact cell for triclinic boxes).
    pub fn positions(&self) -> Result<Vec<[f64; 3]>, DumpError> {
        if let Some(p) = self
            .vectors(["x", "y", "z"])
            .or_else(|| self.vectors(["xu", "yu", "zu"]))
        {
            return Ok(p);
        }
        let scaled = self
            .triple(["xs", "ys", "zs"])
            .or_else(|| self.triple(["xsu", "ysu", "zsu"]))
            .ok_or_else(|| self.missing("x y z (or xu yu zu, xs ys zs, xsu ysu zsu)"))?;
        let cell = self.bounds.cell();
        Ok(zip3(scaled)
            .into_iter()
            .map(|s| cell.to_cartesian(s))
            .collect())
    }

    /// Particle radii (m): `radius`, else `diameter` / 2.
    pub fn radii(&self) -> Result<Vec<f64>, DumpError> {
        if let Some(r) = self.column("radius") {
            return Ok(r.to_vec());
        }
        match self.column("diameter") {
            Some(d) => Ok(d.iter().map(|d| 0.5 * d).collect()),
            None => Err(self.missing("radius (or diameter)")),
        }
    }

    fn integers<T: TryFrom<u64>>(
        &self,
        name: &str,
        what: &'static str,
    ) -> Result<Vec<T>, DumpError> {
        let col = self.require(name)?;
        col.iter()
            .enumerate()
            .map(|(row, &v)| {
                let ok = v >= 0.0 && v.fract() == 0.0 && v <= 9_007_199_254_740_992.0;
                ok.then(|| T::try_from(v as u64).ok())
                    .flatten()
                    .ok_or_else(|| {
                        DumpError::new(
                            self.source.clone(),
                            Location::Unknown,
                            ErrorKind::BadValue {
                                timestep: self.timestep,
                                column: name.to_string(),
                                row,
                                value: v,
                                what,
                            },
                        )
                    })
            })
            .collect()
    }

    /// Particle ids (`id` column), checked to be non-negative integers.
    pub fn ids(&self) -> Result<Vec<u64>, DumpError> {
        self.integers("id", "particle id")
    }

    /// Particle types (`type` column), checked to be non-negative integers below 2³².
    pub fn types(&self) -> Result<Vec<u32>, DumpError> {
        self.integers("type", "particle type")
    }

    /// Builds the typed particle view. Requires `id`, `type`, a position triple (see
    /// [`Snapshot::positions`]), `vx vy vz` and a radius (see [`Snapshot::radii`]); the
    /// optional quantities are filled when their columns are present.
    pub fn particles(&self) -> Result<Particles, DumpError> {
        let velocity = self
            .vectors(["vx", "vy", "vz"])
            .ok_or_else(|| self.missing("vx vy vz"))?;
        Ok(Particles {
            id: self.ids()?,
            atom_type: self.types()?,
            position: self.positions()?,
            velocity,
            radius: self.radii()?,
            force: self.vectors(["fx", "fy", "fz"]),
            omega: self.vectors(["omegax", "omegay", "omegaz"]),
            density: self.column("density").map(<[f64]>::to_vec),
            mass: self.column("mass").map(<[f64]>::to_vec),
        })
    }
}

fn zip3(c: [&[f64]; 3]) -> Vec<[f64; 3]> {
    c[0].iter()
        .zip(c[1])
        .zip(c[2])
        .map(|((&x, &y), &z)| [x, y, z])
        .collect()
}

/// Typed per-particle data of one snapshot, in the snapshot's row order (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct Particles {
    /// Particle ids (LIGGGHTS tags).
    pub id: Vec<u64>,
    /// Particle types (`type` column).
    pub atom_type: Vec<u32>,
    /// Centre positions (m).
    pub position: Vec<[f64; 3]>,
    /// Translational velocities (m/s).
    pub velocity: Vec<[f64; 3]>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Forces (N), if `fx fy fz` are present.
    pub force: Option<Vec<[f64; 3]>>,
    /// Angular velocities (rad/s), if `omegax omegay omegaz` are present.
    pub omega: Option<Vec<[f64; 3]>>,
    /// Densities (kg/m³), if `density` is present.
    pub density: Option<Vec<f64>>,
    /// Masses (kg), if `mass` is present.
    pub mass: Option<Vec<f64>>,
}

impl Particles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// `true` if there are no particles.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }
}
