//! One implicit diffusion step of a cell field x over a length L (m),
//!
//!   x − L² ∇²x = x₀   ⇒   V_c x_c − Σ_f L² |S_f| δ_f (x_N − x_c) = V_c x₀,c,
//!
//! with zero gradient at the boundary (no flux through it: Σ V x is conserved to the solver's
//! tolerance) and across cyclic pairs as across internal faces. δ_f is OpenFOAM's
//! non-orthogonal delta coefficient 1/max(n̂·d, 0.05 |d|) ([`FvGeometry::delta_coeff`]), the
//! implicit part of `Gauss linear corrected`; the explicit non-orthogonal correction is left
//! out (zero on orthogonal meshes). The matrix is assembled once per mesh and solved by PCG
//! with DIC to 1e-14 of the normalised residual. CFDEM-PFM's `constDiffSmoothing` of the
//! voidage is this step (`couple::smoothing`, on the native discretisation through
//! `runner::native::smoothing`).

use crate::error::Result;
use crate::geometry::FvGeometry;
use crate::ldu::Ldu;
use crate::linsolve::{pcg, Preconditioner, SolveStats, SolverControls};
use foam::PolyMesh;

/// The operator V + L²·(−∇²) on one mesh, assembled once (module docs).
#[derive(Debug)]
pub struct DiffusionStep {
    g: FvGeometry,
    a: Ldu,
}

impl DiffusionStep {
    /// The operator on `mesh` for the length `length` (m).
    pub fn new(mesh: &PolyMesh, length: f64) -> Result<Self> {
        let g = FvGeometry::new(mesh)?;
        let mut a = Ldu::zeros(&g);
        a.diag.clone_from(&g.v);
        let l2 = length * length;
        for f in 0..g.n_internal {
            let c = l2 * g.mag_sf[f] * g.delta_coeff[f];
            a.upper[f] = -c;
            a.lower[f] = -c;
            a.diag[g.owner[f] as usize] += c;
            a.diag[g.neighbour[f] as usize] += c;
        }
        Ok(DiffusionStep { g, a })
    }

    /// The cell volumes V_c, m³ (one per cell: the length of the fields [`DiffusionStep::solve`]
    /// takes).
    pub fn volumes(&self) -> &[f64] {
        &self.g.v
    }

    /// x₀ → x in place (module docs); `what` names the field in the solver's errors.
    pub fn solve(&self, x: &mut [f64], what: &str) -> Result<SolveStats> {
        let g = &self.g;
        let b: Vec<f64> = x.iter().zip(&g.v).map(|(e, v)| e * v).collect();
        let controls = SolverControls {
            tolerance: 1e-14,
            rel_tol: 0.0,
            max_iter: 1000,
            min_iter: 0,
        };
        pcg(&self.a, g, &b, x, Preconditioner::Dic, &controls, what)
    }
}
