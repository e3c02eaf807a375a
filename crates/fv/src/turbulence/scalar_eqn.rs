//! The transport equation of a cell scalar x (k or ε) as OpenFOAM v1912 assembles
//! `fvm::ddt(x) + fvm::div(phi, x) − fvm::laplacian(Γ, x) == sources` (Jasak 1996, PhD thesis,
//! Imperial College, ch. 3): implicit Euler in time, Gauss convection with the face weights of
//! [`crate::convection`] (optionally `bounded`: minus (∇·φ) x), Gauss linear Laplacian with
//! the face diffusivity Γ_f and the explicit non-orthogonal correction, boundary faces in the
//! value/gradient-coefficient form of [`super::scalar_bc`]. Units: with x in u, the rows are in
//! u·m³/s (the equation integrated over the cell).
//!
//! The boundary contributions are kept apart from the internal ones, as OpenFOAM keeps its
//! `internalCoeffs`/`boundaryCoeffs`, so that [`ScalarEqn::set_values`] (OpenFOAM's
//! `fvMatrix::setValues`, used by `epsilonWallFunction`) gives the same rows.

// Face and cell loops index several arrays at once, as the equations do.
#![allow(clippy::needless_range_loop)]

use super::scalar_bc::ScalarBc;
use crate::convection::Convection;
use crate::ddt::CrankNicolsonDdt0;
use crate::error::Result;
use crate::fvc;
use crate::gather;
use crate::geometry::FvGeometry;
use crate::ldu::Ldu;
use crate::linsolve::{self, SolveStats};
use crate::settings::LinearSolver;

/// What a scalar transport equation's terms are discretised with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalarScheme {
    /// `div(phi,x)` interpolation: `Linear`, `Upwind` or `LimitedLinear(ψ)`.
    pub convection: Convection,
    /// `bounded Gauss …`.
    pub bounded: bool,
    /// The linear solver of fvSolution for x.
    pub solver: LinearSolver,
    /// `ddt(x)`: `None` Euler, `Some(ψ)` OpenFOAM's `CrankNicolson ψ`.
    pub crank_nicolson: Option<f64>,
}

/// The assembled equation of one scalar.
#[derive(Clone, Debug)]
pub struct ScalarEqn {
    /// Internal coefficients (diagonal without boundary contributions).
    pub m: Ldu,
    /// Source without boundary contributions (u·m³/s).
    pub source: Vec<f64>,
    /// The boundary faces' diagonal contributions summed per owner cell.
    pub b_diag: Vec<f64>,
    /// The boundary faces' source contributions summed per owner cell.
    pub b_source: Vec<f64>,
}

/// The inputs of [`ScalarEqn::transport`] that describe the flow and the mesh's Laplacian.
pub struct Transport<'a> {
    /// Face fluxes φ (m³/s), one per face.
    pub phi: &'a [f64],
    /// Laplacian delta coefficient per face (1/m).
    pub lap_dc: &'a [f64],
    /// Apply the explicit non-orthogonal correction (`corrected`).
    pub corrected: bool,
    /// Time step (s).
    pub dt: f64,
    /// `CrankNicolson ψ`: the step's rate c/Δt (1/s) and the equation's stored derivative
    /// ([`CrankNicolsonDdt0`], begun for this step); `None`: Euler.
    pub crank_nicolson: Option<(f64, &'a CrankNicolsonDdt0<f64>)>,
    /// `fvm::ddt(w, x)` instead of `fvm::ddt(x)` (Euler only): the weight per cell at the new
    /// and the old time, (w, w°) — OpenFOAM v1912's `EulerDdtScheme::fvmDdt(rho, vf)`: diagonal
    /// w V/Δt, source w° x° V/Δt. `None`: w ≡ 1 (k and ε).
    pub ddt_weight: Option<(&'a [f64], &'a [f64])>,
    /// ∇·φ per cell (1/s, [`fvc::surface_integrate`] of `phi`) when the caller has it, for
    /// the `bounded` term; `None`: computed here.
    pub div_phi: Option<&'a [f64]>,
}

impl ScalarEqn {
    /// ddt(x) + div(φ, x) − laplacian(Γ, x) for the cell values `x` (current, for the
    /// convection weights and the non-orthogonal correction), the old-time values `x_old`, the
    /// boundary values `x_b` (evaluated, one per boundary face), conditions `bcs` and the face
    /// diffusivity `gamma_f` (m²/s, one per face).
    #[allow(clippy::too_many_arguments)]
    pub fn transport(
        g: &FvGeometry,
        flow: &Transport<'_>,
        scheme: &ScalarScheme,
        x: &[f64],
        x_old: &[f64],
        x_b: &[f64],
        bcs: &[ScalarBc],
        gamma_f: &[f64],
    ) -> ScalarEqn {
        let n = g.n_cells;
        let phi = flow.phi;
        let mut m = Ldu::zeros(g);
        let mut source = vec![0.0; n];
        let weights = scheme
            .convection
            .scalar_weights(g, phi, x, x_b)
            .expect("settings admit only scalar schemes for k and epsilon");
        // The faces' coefficients in parallel, each cell's diagonal and source gathered
        // over its faces in face order (crate::gather: the face loops' bits).
        let ni = g.n_internal;
        let (lower, upper): (Vec<f64>, Vec<f64>) = crate::gather::over(0..ni)
            .map(|f| {
                let w = weights[f];
                let gam = gamma_f[f] * g.mag_sf[f] * flow.lap_dc[f];
                (-w * phi[f] - gam, -w * phi[f] + phi[f] - gam)
            })
            .unzip();
        m.lower = lower;
        m.upper = upper;
        // On an orthogonal mesh the correction is zero (skipped: the same bits).
        let corr: Vec<f64> = if flow.corrected && !g.orthogonal {
            let gx = fvc::grad_scalar(g, x, x_b);
            crate::gather::over(0..ni)
                .map(|f| {
                    let (o, nb) = (g.owner[f] as usize, g.neighbour[f] as usize);
                    let w = g.weight[f];
                    let gf = w * (gx[o] - gx[nb]) + gx[nb];
                    gamma_f[f] * g.mag_sf[f] * g.corr_vec[f].dot(&gf)
                })
                .collect()
        } else {
            Vec::new()
        };
        let sums = gather::face_sums(
            g,
            |_| (0.0, 0.0),
            |(d, s), f, own| match (f < ni, own) {
                (false, _) => (d, s),
                (true, true) => (
                    d - m.lower[f],
                    if corr.is_empty() { s } else { s + corr[f] },
                ),
                (true, false) => (
                    d - m.upper[f],
                    if corr.is_empty() { s } else { s - corr[f] },
                ),
            },
        );
        for (c, (d, s)) in sums.into_iter().enumerate() {
            m.diag[c] = d;
            source[c] = s;
        }
        debug_assert!(
            flow.crank_nicolson.is_none() || flow.ddt_weight.is_none(),
            "a weighted ddt is Euler only"
        );
        if let Some((r, cn)) = flow.crank_nicolson {
            // OpenFOAM's CrankNicolson fvmDdt: diag c/Δt V, source (c/Δt x⁰ + ψ d₀) V
            for c in 0..n {
                m.diag[c] += r * g.v[c];
                source[c] += cn.old_part(c, r, x_old[c]) * g.v[c];
            }
        } else if let Some((w, w_old)) = flow.ddt_weight {
            let rdt = 1.0 / flow.dt;
            for c in 0..n {
                m.diag[c] += rdt * w[c] * g.v[c];
                source[c] += rdt * w_old[c] * x_old[c] * g.v[c];
            }
        } else {
            let rdt = 1.0 / flow.dt;
            gather::each_mut(&mut m.diag, |c, d| *d += rdt * g.v[c]);
            gather::each_mut(&mut source, |c, s| *s += rdt * x_old[c] * g.v[c]);
        }
        if scheme.bounded {
            let own;
            let div_phi = match flow.div_phi {
                Some(d) => d,
                None => {
                    own = fvc::surface_integrate(g, phi);
                    &own[..]
                }
            };
            gather::each_mut(&mut m.diag, |c, d| *d -= g.v[c] * div_phi[c]);
        }
        let mut b_diag = vec![0.0; n];
        let mut b_source = vec![0.0; n];
        for (p, bc) in g.patches.iter().zip(bcs) {
            if *bc == ScalarBc::Empty {
                continue;
            }
            for (i, f) in p.faces.clone().enumerate() {
                let b = f - g.n_internal;
                let o = g.owner[f] as usize;
                let vi = bc.value_coeff(phi[f]);
                let vb = bc.fixed_part(i, phi[f], x_b[b]);
                let gam = gamma_f[f] * g.mag_sf[f] * flow.lap_dc[f];
                b_diag[o] += phi[f] * vi + gam * (1.0 - vi);
                b_source[o] += -phi[f] * vb + gam * vb;
            }
        }
        ScalarEqn {
            m,
            source,
            b_diag,
            b_source,
        }
    }

    /// Adds the implicit sink `fvm::Sp(c, x)`: c V to the diagonal (c in 1/s per cell).
    pub fn add_sp(&mut self, g: &FvGeometry, c: &[f64]) {
        gather::each_mut(&mut self.m.diag, |i, d| *d += g.v[i] * c[i]);
    }

    /// Adds `fvm::SuSp(c, x)`: implicit where c > 0, explicit (−c x V to the source) where
    /// c < 0, so the diagonal never loses dominance (c in 1/s per cell).
    pub fn add_susp(&mut self, g: &FvGeometry, c: &[f64], x: &[f64]) {
        gather::each_mut(&mut self.m.diag, |i, d| *d += g.v[i] * c[i].max(0.0));
        gather::each_mut(&mut self.source, |i, s| *s -= g.v[i] * c[i].min(0.0) * x[i]);
    }

    /// Adds the explicit source s V (s in u/s per cell).
    pub fn add_source(&mut self, g: &FvGeometry, s: &[f64]) {
        gather::each_mut(&mut self.source, |i, b| *b += g.v[i] * s[i]);
    }

    /// Fixes x in `cells` to `values` (OpenFOAM's `fvMatrix::setValues`): each row becomes
    /// d x_c = d v (d its internal diagonal), the coupling to its neighbours moves into their
    /// sources and its boundary contributions are dropped. `x` gets the values too. Cells are
    /// processed in order; a cell may appear more than once.
    pub fn set_values(&mut self, g: &FvGeometry, cells: &[usize], values: &[f64], x: &mut [f64]) {
        for (&c, &v) in cells.iter().zip(values) {
            x[c] = v;
            self.source[c] = v * self.m.diag[c];
            for &f in g.faces_of(c) {
                let f = f as usize;
                if f < g.n_internal {
                    if g.owner[f] as usize == c {
                        self.source[g.neighbour[f] as usize] -= self.m.lower[f] * v;
                    } else {
                        self.source[g.owner[f] as usize] -= self.m.upper[f] * v;
                    }
                    self.m.upper[f] = 0.0;
                    self.m.lower[f] = 0.0;
                }
            }
            self.b_diag[c] = 0.0;
            self.b_source[c] = 0.0;
        }
    }

    /// Solves for `x` (its values are the initial guess) with `solver`; `what` names the field
    /// in solver messages.
    pub fn solve(
        mut self,
        g: &FvGeometry,
        solver: &LinearSolver,
        x: &mut [f64],
        what: &str,
    ) -> Result<SolveStats> {
        let (b_diag, b_source) = (&self.b_diag, &self.b_source);
        gather::each_mut(&mut self.m.diag, |c, d| *d += b_diag[c]);
        gather::each_mut(&mut self.source, |c, s| *s += b_source[c]);
        linsolve::solve(
            solver.method,
            &self.m,
            g,
            &self.source,
            x,
            &solver.controls,
            what,
        )
    }
}
