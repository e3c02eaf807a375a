//! U and p of one time directory of a case, with their boundary conditions: what the solver
//! starts from and what a frozen-fluid coupler reads.

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
    /// Voidage boundary values per patch from `voidfraction` if the start time has one
    /// (`None`: the owner cell's ε; also for every patch without the file).
    pub eps_bc: Vec<Option<Vec<f64>>>,
}

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
    let eps_path = dir.join("voidfraction");
    let eps_bc = if eps_path.is_file() {
        bc::read_voidage(&eps_path, &VolField::read(&eps_path)?, mesh, g)?
    } else {
        vec![None; g.patches.len()]
    };
    Ok(CaseFields {
        u_file,
        p_file,
        u,
        p,
        u_bc,
        p_bc,
        eps_bc,
    })
}
