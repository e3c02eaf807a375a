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
//! `runner::native::smoothing`). [`DiffusionStep::solve_local`] solves the same step with a
//! length per cell, L_f² = (L_o² + L_n²)/2 on each face (symmetric, so Σ V x is conserved as
//! well), assembled for that call (`localPSizeDiffSmoothing`).

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
        let l2 = length * length;
        let a = assemble(&g, |_| l2);
        Ok(DiffusionStep { g, a })
    }

    /// The cell volumes V_c, m³ (one per cell: the length of the fields [`DiffusionStep::solve`]
    /// takes).
    pub fn volumes(&self) -> &[f64] {
        &self.g.v
    }

    /// x₀ → x in place (module docs); `what` names the field in the solver's errors.
    pub fn solve(&self, x: &mut [f64], what: &str) -> Result<SolveStats> {
        solve(&self.g, &self.a, x, what)
    }

    /// x₀ → x in place with the length L_c² (m², `l2`, one per cell) instead of the step's
    /// own (module docs).
    pub fn solve_local(&self, x: &mut [f64], l2: &[f64], what: &str) -> Result<SolveStats> {
        let g = &self.g;
        let a = assemble(g, |f| {
            0.5 * (l2[g.owner[f] as usize] + l2[g.neighbour[f] as usize])
        });
        solve(g, &a, x, what)
    }
}

/// V + Σ_f L_f² |S_f| δ_f (−∇²) with `l2(f)` the L² of internal face f.
fn assemble(g: &FvGeometry, l2: impl Fn(usize) -> f64) -> Ldu {
    let mut a = Ldu::zeros(g);
    a.diag.clone_from(&g.v);
    for f in 0..g.n_internal {
        let c = l2(f) * g.mag_sf[f] * g.delta_coeff[f];
        a.upper[f] = -c;
        a.lower[f] = -c;
        a.diag[g.owner[f] as usize] += c;
        a.diag[g.neighbour[f] as usize] += c;
    }
    a
}

/// x₀ → x for the operator `a` (PCG/DIC to 1e-14).
fn solve(g: &FvGeometry, a: &Ldu, x: &mut [f64], what: &str) -> Result<SolveStats> {
    let b: Vec<f64> = x.iter().zip(&g.v).map(|(e, v)| e * v).collect();
    let controls = SolverControls {
        tolerance: 1e-14,
        rel_tol: 0.0,
        max_iter: 1000,
        min_iter: 0,
    };
    pcg(a, g, &b, x, Preconditioner::Dic, &controls, what)
}
