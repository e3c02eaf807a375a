//! The fields of a fluid that does not move (`couple::frozen::FrozenFluid`'s): U and p read
//! from a case's time directory, with ∇p and ∇·τ computed once by [`crate::fvc`] (Gauss
//! linear, as OpenFOAM's `fvc::grad` and the viscous stress divergence of its incompressible
//! solvers).
//!
//! Boundary-face values for the operators come from the fields' boundary conditions as `fv`
//! reads them, evaluated for a fluid at rest in time t = the time directory's value: fixed
//! values as given, zero-gradient and the outflow side of `inletOutlet` from the owner cell
//! (the face flux is taken as zero, so `inletOutlet` uses the owner value), slip without its
//! normal component; for p, `fixedFluxPressure` as zero gradient and `totalPressure` as
//! p0 − ½|U_b|².

use crate::bc::{self, PressureBc};
use crate::error::{FvError, Result};
use crate::fvc::{self, Field};
use crate::geometry::{FvGeometry, V3};
use foam::{Case, FieldValues, PolyMesh, VolField};
use std::path::Path;

/// A frozen fluid's mesh and cell fields (module docs).
#[derive(Clone, Debug)]
pub struct FrozenFields {
    /// The case's mesh.
    pub mesh: PolyMesh,
    /// U, m/s.
    pub u: Vec<V3>,
    /// p, as the time directory holds it.
    pub p: Vec<f64>,
    /// ∇p (Gauss linear).
    pub grad_p: Vec<V3>,
    /// ∇·τ = ∇·(ν(∇U + ∇Uᵀ)).
    pub div_tau: Vec<V3>,
    /// The time directory's value, s.
    pub time: f64,
}

impl FrozenFields {
    /// Reads the mesh and `U`, `p` of time directory `time` of the case at `dir`; ν (m²/s)
    /// for ∇·τ = ∇·(ν(∇U + ∇Uᵀ)).
    pub fn read(dir: &Path, time: &str, nu: f64) -> Result<FrozenFields> {
        let case = Case::open(dir)?;
        let mesh = case.read_mesh()?;
        let g = FvGeometry::new(&mesh)?;
        let tdir = case.time_path(time);
        let t: f64 = time.parse().unwrap_or(0.0);
        let u_path = tdir.join("U");
        let p_path = tdir.join("p");
        let u_file = VolField::read(&u_path)?;
        let p_file = VolField::read(&p_path)?;
        let field_err = |path: &Path, m: String| FvError::setting(path, "internalField", m);
        let u = match u_file
            .internal(g.n_cells)
            .map_err(|m| field_err(&u_path, m))?
        {
            FieldValues::Vector(v) => mesh::v3::from_arrays(&v),
            FieldValues::Scalar(_) => {
                return Err(field_err(&u_path, "U must be a volVectorField".into()))
            }
        };
        let p = match p_file
            .internal(g.n_cells)
            .map_err(|m| field_err(&p_path, m))?
        {
            FieldValues::Scalar(v) => v,
            FieldValues::Vector(_) => {
                return Err(field_err(&p_path, "p must be a volScalarField".into()))
            }
        };
        let u_bc = bc::read_velocity(&u_path, &u_file, &mesh, &g)?;
        if let Some(k) = u_bc
            .iter()
            .position(|b| matches!(b, bc::VelocityBc::UniformFixedValueVoidfraction(_)))
        {
            return Err(FvError::setting(
                &u_path,
                format!("boundaryField.{}.type", g.patches[k].name),
                "`uniformFixedValueVoidfraction` divides by the voidage, which a frozen fluid \
                 does not have: use `uniformFixedValue` with the velocity at the patch",
            ));
        }
        let p_bc = bc::read_pressure(&p_path, &p_file, &mesh, &g)?;
        let phi = vec![0.0; g.n_faces()];
        let mut u_b = vec![V3::zeros(); g.n_boundary()];
        let ones = vec![1.0; g.n_boundary()];
        bc::eval_velocity(&g, &u_bc, t, &u, &ones, &phi, &mut u_b);
        let p_b = pressure_boundary(&g, &p_bc, t, &p, &u_b);
        let grad_p = fvc::grad_scalar(&g, &p, &p_b);
        let nu_c = vec![nu; g.n_cells];
        let nu_b = vec![nu; g.n_boundary()];
        let div_tau = fvc::div_viscous_stress(&g, Field::new(&nu_c, &nu_b), Field::new(&u, &u_b));
        Ok(FrozenFields {
            mesh,
            u,
            p,
            grad_p,
            div_tau,
            time: t,
        })
    }
}

/// Boundary-face values of p (module docs).
fn pressure_boundary(
    g: &FvGeometry,
    bcs: &[PressureBc],
    t: f64,
    p: &[f64],
    u_b: &[V3],
) -> Vec<f64> {
    let mut out = vec![0.0; g.n_boundary()];
    for (patch, bc) in g.patches.iter().zip(bcs) {
        for (i, f) in patch.faces.clone().enumerate() {
            let b = f - g.n_internal;
            let owner = p[g.owner[f] as usize];
            out[b] = match bc {
                PressureBc::FixedValue(v) => v[i],
                PressureBc::UniformFixedValue(s) => s.at(t),
                PressureBc::TotalPressure(p0) => {
                    let u = u_b[b];
                    p0[i] - 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
                }
                // A cyclic patch has no boundary faces (its pairs are internal faces).
                PressureBc::ZeroGradient
                | PressureBc::FixedFluxPressure
                | PressureBc::Empty
                | PressureBc::Cyclic => owner,
            };
        }
    }
    out
}
