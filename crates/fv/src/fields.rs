//! U and p of one time directory of a case, with their boundary conditions: what the solver
//! starts from and what a frozen-fluid coupler reads; and the face flux `phi` the solver writes
//! next to them.

use crate::bc::{self, PressureBc, VelocityBc};
use crate::error::{FvError, Result};
use crate::geometry::{FvGeometry, V3};
use foam::{FieldValues, PolyMesh, VolField};
use std::path::Path;

/// The velocity and kinematic-pressure fields of a time directory.
#[derive(Clone, Debug)]
pub struct CaseFields {
    /// The `U` file as read (its boundaryField is kept when writing).
    pub u_file: VolField,
    /// The `p` file as read.
    pub p_file: VolField,
    /// Cell velocities (m/s).
    pub u: Vec<V3>,
    /// Cell kinematic pressures (m²/s²).
    pub p: Vec<f64>,
    /// Velocity conditions per patch.
    pub u_bc: Vec<VelocityBc>,
    /// Pressure conditions per patch.
    pub p_bc: Vec<PressureBc>,
    /// The start values of the totalPressure patches, where `p` gives them
    /// ([`bc::read_total_pressure_values`]).
    pub p_b_start: Vec<Option<Vec<f64>>>,
    /// Voidage boundary values per patch from `voidfraction` if the start time has one
    /// (`None`: the owner cell's ε; also for every patch without the file).
    pub eps_bc: Vec<Option<Vec<f64>>>,
    /// The face fluxes of the time directory's `phi` if it has one (a restart), one per face.
    pub phi: Option<Vec<f64>>,
    /// The `voidfraction` file if the time directory has one (its boundaryField is kept when
    /// a coupled run writes the voidage).
    pub eps_file: Option<VolField>,
    /// The pressure gradient the solver used last, from the time directory's `grad(p)` if it
    /// has one (m/s², per cell; written by coupled runs, [`GRAD_P_FILE`]).
    pub grad_p: Option<Vec<V3>>,
}

/// The file of the pressure gradient a coupled run's solver used last (m/s², volVectorField;
/// OpenFOAM's `grad(p)` function object writes a file of that name). With harmonic faces
/// ([`crate::Fluid::harmonic_faces`]) the gradient depends on the last step's coefficients,
/// not on p alone, so a restart reads it instead of computing it from p: the restarted run
/// then predicts the momentum with the gradient the uninterrupted run used.
pub const GRAD_P_FILE: &str = "grad(p)";

fn internal(path: &Path, f: &VolField, n: usize) -> Result<FieldValues> {
    f.internal(n)
        .map_err(|m| FvError::setting(path, "internalField", m))
}

/// Reads `U` and `p` of the time directory `dir` for the mesh `mesh` (geometry `g`).
pub fn read_fields(dir: &Path, mesh: &PolyMesh, g: &FvGeometry) -> Result<CaseFields> {
    let u_path = dir.join("U");
    let p_path = dir.join("p");
    let u_file = VolField::read(&u_path)?;
    let p_file = VolField::read(&p_path)?;
    let FieldValues::Vector(u) = internal(&u_path, &u_file, g.n_cells)? else {
        return Err(FvError::setting(
            &u_path,
            "class",
            "U must be a volVectorField",
        ));
    };
    let FieldValues::Scalar(p) = internal(&p_path, &p_file, g.n_cells)? else {
        return Err(FvError::setting(
            &p_path,
            "class",
            "p must be a volScalarField",
        ));
    };
    let u_bc = bc::read_velocity(&u_path, &u_file, mesh, g)?;
    let p_bc = bc::read_pressure(&p_path, &p_file, mesh, g)?;
    let p_b_start = bc::read_total_pressure_values(&p_path, &p_file, mesh, g)?;
    let eps_path = dir.join("voidfraction");
    let (eps_bc, eps_file) = if eps_path.is_file() {
        let file = VolField::read(&eps_path)?;
        (bc::read_voidage(&eps_path, &file, mesh, g)?, Some(file))
    } else {
        (vec![None; g.patches.len()], None)
    };
    let phi_path = dir.join("phi");
    let phi = if phi_path.is_file() {
        Some(read_phi(&phi_path, g)?)
    } else {
        None
    };
    let grad_path = dir.join(GRAD_P_FILE);
    let grad_p = if grad_path.is_file() {
        let file = VolField::read(&grad_path)?;
        let FieldValues::Vector(v) = internal(&grad_path, &file, g.n_cells)? else {
            return Err(FvError::setting(
                &grad_path,
                "class",
                "grad(p) must be a volVectorField",
            ));
        };
        Some(mesh::v3::from_arrays(&v))
    } else {
        None
    };
    Ok(CaseFields {
        u_file,
        p_file,
        u: mesh::v3::from_arrays(&u),
        p,
        u_bc,
        p_bc,
        p_b_start,
        eps_bc,
        phi,
        eps_file,
        grad_p,
    })
}

/// Reads a `surfaceScalarField` of face fluxes (m³/s) written by [`write_phi`] or by OpenFOAM:
/// `internalField` with one value per internal face, and each non-`empty` patch's `value`
/// (`uniform X` or a list with one value per face). `empty` patches get 0.
pub fn read_phi(path: &Path, g: &FvGeometry) -> Result<Vec<f64>> {
    use foam::Item;
    let file = foam::parse_file(path)?;
    let class = file.header.as_ref().map_or("", |h| h.class.as_str());
    if class != "surfaceScalarField" {
        return Err(FvError::setting(
            path,
            "class",
            format!("`{class}`: expected a surfaceScalarField"),
        ));
    }
    let values = |items: &[Item], n: usize, key: &str| -> Result<Vec<f64>> {
        let v = match items.first().and_then(Item::as_word) {
            Some("uniform") if items.len() == 2 => items[1].as_f64().map(|x| vec![x; n]),
            Some("nonuniform") => items.get(2).and_then(Item::as_f64_list),
            _ => None,
        };
        match v {
            Some(v) if v.len() == n && v.iter().all(|x| x.is_finite()) => Ok(v),
            _ => Err(FvError::setting(
                path,
                key,
                format!("expected `uniform X` or a list of {n} finite values"),
            )),
        }
    };
    let body = &file.body;
    let internal = body
        .stream("internalField")
        .map_err(|e| FvError::setting(path, "internalField", e.0))?;
    let mut phi = values(internal, g.n_mesh_internal, "internalField")?;
    phi.resize(g.n_faces(), 0.0);
    let bf = body
        .dict("boundaryField")
        .map_err(|e| FvError::setting(path, "boundaryField", e.0))?;
    // A cyclic pair's flux is the one of its first patch (the second holds its negative).
    for p in g.patches.iter().filter(|p| !p.is_empty()) {
        let target = match &p.cyclic {
            Some(c) if c.owner_side => c.pair_faces.clone(),
            Some(_) => continue,
            None => p.faces.clone(),
        };
        let key = format!("boundaryField.{}.value", p.name);
        let items = bf
            .dict(&p.name)
            .and_then(|d| d.stream("value"))
            .map_err(|e| FvError::setting(path, &key, e.0))?;
        let v = values(items, target.len(), &key)?;
        phi[target].copy_from_slice(&v);
    }
    Ok(phi)
}

/// Writes the face fluxes `phi` (m³/s, one per face) as OpenFOAM's `surfaceScalarField` file
/// `path`: internal faces in `internalField`, each patch `calculated` with its faces' values
/// (`empty` patches: `empty` with no values; `cyclic` patches: `cyclic` with the flux out of
/// each side, [`crate::FvPatch::face_fluxes`]), as pisoFoam writes `phi`. OpenFOAM's solvers
/// read it back at a restart (`createPhi` reads `phi` when present), so a run continued by
/// OpenFOAM keeps the Rhie–Chow fluxes instead of recomputing them from U.
pub fn write_phi(path: &Path, g: &FvGeometry, phi: &[f64], format: foam::Format) -> Result<()> {
    write_surface_scalar(path, "phi", [0, 3, -1, 0, 0, 0, 0], g, phi, format)
}

/// Writes a surfaceScalarField `object` (one value per solver face, dimensions `dims`) in
/// [`write_phi`]'s layout: OpenFOAM's `phi`, `phi_0` and `ddtCorrDdt0(phi)` files.
pub fn write_surface_scalar(
    path: &Path,
    object: &str,
    dims: [i64; 7],
    g: &FvGeometry,
    phi: &[f64],
    format: foam::Format,
) -> Result<()> {
    use foam::{Dict, Item, Value};
    FvError::check_len(object, phi.len(), g.n_faces())?;
    let list = |v: &[f64]| {
        Value::Stream(vec![
            Item::Word("nonuniform".into()),
            Item::Word("List<scalar>".into()),
            Item::Scalars(v.to_vec()),
        ])
    };
    let mut boundary = Dict::new();
    for p in &g.patches {
        let mut e = Dict::new();
        if p.is_empty() {
            e.set_item("type", Item::Word("empty".into()));
            e.set("value", list(&[]));
        } else if p.is_cyclic() {
            e.set_item("type", Item::Word("cyclic".into()));
            e.set("value", list(&p.face_fluxes(phi)));
        } else {
            e.set_item("type", Item::Word("calculated".into()));
            e.set("value", list(&phi[p.faces.clone()]));
        }
        boundary.set(&p.name, Value::Dict(e));
    }
    let mut body = Dict::new();
    body.set_item("dimensions", Item::Dims(dims.map(Item::Label).to_vec()));
    body.set("internalField", list(&phi[..g.n_mesh_internal]));
    body.set("boundaryField", Value::Dict(boundary));
    let header = foam::Header {
        format,
        arch: foam::Arch::default(),
        class: "surfaceScalarField".into(),
        object: object.into(),
        location: path
            .parent()
            .and_then(Path::file_name)
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        note: None,
    };
    foam::write_dict_file(path, &header, &body)?;
    Ok(())
}
