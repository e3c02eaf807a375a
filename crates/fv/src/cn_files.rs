//! The files of `CrankNicolson ψ`'s state at a write time, as OpenFOAM v1912 writes and reads
//! them, so that a run continued from a written time — by the native fluid or by OpenFOAM —
//! goes on as the uninterrupted run ([`crate::ddt::CrankNicolsonDdt0`]).
//!
//! What OpenFOAM writes (measured with Debian's pisoFoam, `ddtSchemes default CrankNicolson
//! 0.9`, into every time directory it writes): the stored derivatives `ddt0(U)`,
//! `ddtCorrDdt0(U)` (volVectorFields, m/s²) and `ddtCorrDdt0(phi)` (surfaceScalarField, m³/s²)
//! — `CrankNicolsonDdtScheme` registers each as `AUTO_WRITE`, and reads it `MUST_READ` from the
//! start directory when the file is there on the run's first step — and the old levels `U_0`
//! and `phi_0` (`GeometricField::storeOldTime` makes the old level `AUTO_WRITE` once an old-old
//! level exists, and `readOldTimeIfPresent` reads `<field>_0` with the field). Boundary values
//! of a ddt0 field are `calculated` (the constraint types on `empty` and `cyclic` patches).
//! pisoFoam run 0 → T with a write at T/2 and pisoFoam restarted from T/2 write the same bits
//! at T (checked: `tests/cn_restart.rs`). With the `ddt0(…)` file missing OpenFOAM starts that
//! field's scheme afresh (zero, Euler on the first step); with `U_0` missing it takes the old
//! level for the one before, which turns the first update into d₀ ← −ψ d₀ (measured: 7.9e-3 of
//! the lid speed after 20 steps of the skewed cavity), so the native reader refuses that.
//!
//! The VANS names are grainPisoFoam's: `ddt0(voidfraction,U)` (fvm::ddt(voidfraction, U)),
//! `ddt0(voidfraction)` (the continuity equation's fvc::ddt(voidfraction)) and
//! `voidfraction_0`.

use crate::bc;
use crate::error::{FvError, Result};
use crate::geometry::{FvGeometry, V3};
use foam::{Dict, FieldValues, Item, PolyMesh, Value, VolField};
use std::path::Path;

/// `ddtCorr`'s stored derivative of the old velocity (volVectorField, m/s²).
pub const CORR_U: &str = "ddtCorrDdt0(U)";
/// `ddtCorr`'s stored derivative of the face flux (surfaceScalarField, m³/s²).
pub const CORR_PHI: &str = "ddtCorrDdt0(phi)";

/// The native bracket's stored derivative of ε_f U_f·S (surfaceScalarField, m³/s²; not an
/// OpenFOAM file: for constant ε it is `ddtCorrDdt0(U)` interpolated, which a restart uses
/// when this file is missing, exactly so for pisoFoam's cases).
pub const CORR_EPS_U: &str = "ddtCorrDdt0(voidfractionPhiU)";
/// The porous faces' stored derivative of φ (surfaceScalarField, m³/s²; native, updated once
/// per step; a restart without it starts from `ddtCorrDdt0(phi)`).
pub const POROUS_PHI: &str = "ddt0(porousPhi)";

/// The momentum equation's stored derivative: `ddt0(U)` for a plain case, grainPisoFoam's
/// `ddt0(voidfraction,U)` when the case has a `voidfraction` field.
pub fn momentum_name(vans: bool) -> &'static str {
    if vans {
        "ddt0(voidfraction,U)"
    } else {
        "ddt0(U)"
    }
}

/// The continuity equation's stored ∂ε/∂t (volScalarField, 1/s).
pub const VOIDAGE: &str = "ddt0(voidfraction)";

/// The file of a field's old level (`U_0`).
pub fn old_name(field: &str) -> String {
    format!("{field}_0")
}

/// A value a volume field holds per cell and boundary face: a scalar or a vector.
pub trait CellValue: Copy + Default {
    /// The cell values as [`FieldValues`].
    fn values(v: &[Self]) -> FieldValues;
    /// The cell values of [`FieldValues`] of this kind.
    fn from_values(v: FieldValues) -> Option<Vec<Self>>;
    /// One value (`uniform X`).
    fn one(i: &Item) -> Option<Self>;
    /// A list of values.
    fn list(i: &Item) -> Option<Vec<Self>>;
    /// A list as a file item.
    fn item(v: &[Self]) -> Item;
}

impl CellValue for f64 {
    fn values(v: &[Self]) -> FieldValues {
        FieldValues::Scalar(v.to_vec())
    }
    fn from_values(v: FieldValues) -> Option<Vec<Self>> {
        match v {
            FieldValues::Scalar(v) => Some(v),
            FieldValues::Vector(_) => None,
        }
    }
    fn one(i: &Item) -> Option<Self> {
        i.as_f64()
    }
    fn list(i: &Item) -> Option<Vec<Self>> {
        i.as_f64_list()
    }
    fn item(v: &[Self]) -> Item {
        Item::Scalars(v.to_vec())
    }
}

impl CellValue for V3 {
    fn values(v: &[Self]) -> FieldValues {
        FieldValues::Vector(mesh::v3::to_arrays(v))
    }
    fn from_values(v: FieldValues) -> Option<Vec<Self>> {
        match v {
            FieldValues::Vector(v) => Some(mesh::v3::from_arrays(&v)),
            FieldValues::Scalar(_) => None,
        }
    }
    fn one(i: &Item) -> Option<Self> {
        bc::as_v3(i)
    }
    fn list(i: &Item) -> Option<Vec<Self>> {
        bc::vec_list(i)
    }
    fn item(v: &[Self]) -> Item {
        Item::Vectors(mesh::v3::to_arrays(v))
    }
}

/// Writes the volume field `name` into the time directory `dir`: `ext` holds the cell values
/// then one value per boundary face (the solver's boundary arrays); each patch is
/// `calculated` with its faces' values, `empty` and `cyclic` patches get their constraint
/// type, as OpenFOAM writes a ddt0 field. `dims`: the 7 SI exponents.
pub fn write_vol<T: CellValue>(
    dir: &Path,
    name: &str,
    dims: [i32; 7],
    ext: &[T],
    g: &FvGeometry,
    format: foam::Format,
) -> Result<()> {
    let n = g.n_cells;
    FvError::check_len(name, ext.len(), n + g.n_boundary())?;
    let mut boundary = Dict::new();
    for p in &g.patches {
        let mut e = Dict::new();
        if p.is_empty() || p.is_cyclic() {
            e.set_item("type", Item::Word(p.patch_type.clone()));
        } else {
            e.set_item("type", Item::Word("calculated".into()));
            let r = p.boundary_range(g.n_internal);
            e.set(
                "value",
                Value::Stream(vec![
                    Item::Word("nonuniform".into()),
                    T::item(&ext[n + r.start..n + r.end]),
                ]),
            );
        }
        boundary.set(&p.name, Value::Dict(e));
    }
    let location = dir
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let f = VolField::new(name, &location, dims, T::values(&ext[..n]), boundary);
    f.write(&dir.join(name), format)?;
    Ok(())
}

/// Reads the volume field `name` of the time directory `dir` as [`write_vol`] writes it
/// (cell values, then the boundary faces' `value`s; `empty` patches 0, `cyclic` patches have
/// no boundary faces in the solver). `Ok(None)` when the file is not there; a file of the
/// wrong class, size or patch layout is an error naming it.
pub fn read_vol<T: CellValue>(
    dir: &Path,
    name: &str,
    mesh: &PolyMesh,
    g: &FvGeometry,
) -> Result<Option<Vec<T>>> {
    let path = dir.join(name);
    if !path.is_file() {
        return Ok(None);
    }
    let file = VolField::read(&path)?;
    let n = g.n_cells;
    let cells = file
        .internal(n)
        .map_err(|m| FvError::setting(&path, "internalField", m))?;
    let mut ext = T::from_values(cells).ok_or_else(|| {
        FvError::setting(
            &path,
            "class",
            format!("`{}`: wrong kind", file.header.class),
        )
    })?;
    ext.resize(n + g.n_boundary(), T::default());
    let per_patch = bc::read_all(&path, &file, mesh, g, |e, t| match t {
        "empty" => Ok((None, true)),
        "cyclic" => Ok((None, false)),
        _ => Ok((Some(e.values("value", T::one, T::list)?), false)),
    })?;
    for (p, v) in g.patches.iter().zip(per_patch) {
        if let Some(v) = v {
            let r = p.boundary_range(g.n_internal);
            ext[n + r.start..n + r.end].copy_from_slice(&v);
        }
    }
    Ok(Some(ext))
}

/// The error of a file a restart needs.
pub(crate) fn missing_file(dir: &Path, name: &str) -> FvError {
    FvError::setting(
        dir.join(name),
        "CrankNicolson",
        "the restart needs this file",
    )
}

/// The cell values of the volume field `name` in `dir` (a `U_0` or `voidfraction_0`, whose
/// boundary entries are the field's conditions).
pub(crate) fn read_cells<T: CellValue>(dir: &Path, name: &str, n: usize) -> Result<Vec<T>> {
    let path = dir.join(name);
    let file = VolField::read(&path)?;
    let v = file
        .internal(n)
        .map_err(|m| FvError::setting(&path, "internalField", m))?;
    T::from_values(v).ok_or_else(|| FvError::setting(&path, "class", "wrong kind of field"))
}

/// The step that led to the time directory `dir` (s): `deltaT` of OpenFOAM's `uniform/time`
/// when it is there, else `None`.
pub(crate) fn previous_step(dir: &Path) -> Result<Option<f64>> {
    let path = dir.join("uniform/time");
    if !path.is_file() {
        return Ok(None);
    }
    let file = foam::parse_file(&path)?;
    let dt = file
        .body
        .f64("deltaT")
        .map_err(|e| FvError::setting(&path, "deltaT", e.0))?;
    Ok(Some(dt))
}
