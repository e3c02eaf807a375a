//! A fluid side that does not move: U and p read from a case's time directory (or given),
//! with ∇p and ∇·τ computed once by `fv::fvc` (Gauss linear, as OpenFOAM's `fvc::grad` and
//! the viscous stress divergence of its incompressible solvers).
//!
//! Boundary-face values for the operators come from the fields' boundary conditions as `fv`
//! reads them, evaluated for a fluid at rest in time t = the time directory's value: fixed
//! values as given, zero-gradient and the outflow side of `inletOutlet` from the owner cell
//! (the face flux is taken as zero, so `inletOutlet` uses the owner value), slip without its
//! normal component; for p, `fixedFluxPressure` as zero gradient and `totalPressure` as
//! p0 − ½|U_b|². [`FluidSide::advance`] only moves the clock; the exchange fields are kept
//! ([`FrozenFluid::last_exchange`]) for the caller to write.

use crate::error::{CoupleError, SideError};
use crate::exchange::Exchange;
use crate::sides::{ExchangeFields, FluidSide, FluidState};
use foam::{Case, FieldValues, PolyMesh, VolField};
use fv::bc::{self, PressureBc};
use fv::fvc::{self, Field};
use fv::FvGeometry;
use mesh::v3::V3;
use std::path::Path;

/// A frozen fluid (module docs).
#[derive(Clone, Debug)]
pub struct FrozenFluid {
    mesh: PolyMesh,
    u: Vec<V3>,
    p: Vec<f64>,
    grad_p: Vec<V3>,
    div_tau: Vec<V3>,
    time: f64,
    last: Option<(Vec<f64>, Exchange)>,
}

impl FrozenFluid {
    /// Uniform velocity `u` (m/s) and zero pressure on `mesh`: ∇p = ∇·τ = 0.
    pub fn uniform(mesh: PolyMesh, u: V3) -> FrozenFluid {
        let n = mesh.n_cells;
        FrozenFluid {
            mesh,
            u: vec![u; n],
            p: vec![0.0; n],
            grad_p: vec![V3::zeros(); n],
            div_tau: vec![V3::zeros(); n],
            time: 0.0,
            last: None,
        }
    }

    /// Reads the mesh and `U`, `p` of time directory `time` of the case at `dir`; ν (m²/s)
    /// for ∇·τ = ∇·(ν(∇U + ∇Uᵀ)).
    pub fn read(dir: &Path, time: &str, nu: f64) -> Result<FrozenFluid, CoupleError> {
        let case = Case::open(dir)?;
        let mesh = case.read_mesh()?;
        let g = FvGeometry::new(&mesh).map_err(|e| CoupleError::Parameter(e.to_string()))?;
        let tdir = case.time_path(time);
        let t: f64 = time.parse().unwrap_or(0.0);
        let u_path = tdir.join("U");
        let p_path = tdir.join("p");
        let u_file = VolField::read(&u_path)?;
        let p_file = VolField::read(&p_path)?;
        let field_err = |path: &Path, m: String| CoupleError::Config {
            file: path.to_path_buf(),
            key: "internalField".into(),
            message: m,
        };
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
        let fv_err = |e: fv::FvError| CoupleError::Parameter(e.to_string());
        let u_bc = bc::read_velocity(&u_path, &u_file, &mesh, &g).map_err(fv_err)?;
        let p_bc = bc::read_pressure(&p_path, &p_file, &mesh, &g).map_err(fv_err)?;
        let phi = vec![0.0; g.n_faces()];
        let mut u_b = vec![V3::zeros(); g.n_boundary()];
        bc::eval_velocity(&g, &u_bc, t, &u, &phi, &mut u_b);
        let p_b = pressure_boundary(&g, &p_bc, t, &p, &u_b);
        let grad_p = fvc::grad_scalar(&g, &p, &p_b);
        let nu_c = vec![nu; g.n_cells];
        let nu_b = vec![nu; g.n_boundary()];
        let div_tau = fvc::div_viscous_stress(&g, Field::new(&nu_c, &nu_b), Field::new(&u, &u_b));
        Ok(FrozenFluid {
            mesh,
            u,
            p,
            grad_p,
            div_tau,
            time: t,
            last: None,
        })
    }

    /// The last exchange received: ε (new) and Ksl, Us, f.
    pub fn last_exchange(&self) -> Option<&(Vec<f64>, Exchange)> {
        self.last.as_ref()
    }

    /// The clock, s.
    pub fn time(&self) -> f64 {
        self.time
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

impl FluidSide for FrozenFluid {
    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError> {
        self.last = Some((fields.voidage_new.to_vec(), fields.exchange.clone()));
        Ok(())
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.time += dt;
        Ok(())
    }

    fn state(&self) -> FluidState<'_> {
        FluidState {
            u: &self.u,
            p: &self.p,
            grad_p: &self.grad_p,
            div_tau: &self.div_tau,
        }
    }
}
