//! The standard k–ε model (Launder & Spalding 1974, Comput. Methods Appl. Mech. Eng. 3,
//! 269–289) as OpenFOAM v1912's incompressible `kEpsilon` solves it once per time step after
//! the PISO correctors (pisoFoam's `turbulence->correct()`), with k (m²/s²), ε (m²/s³),
//! νt = Cμ k²/ε (m²/s):
//!
//! ```text
//! ∂ε/∂t + ∇·(φε) − ∇·((ν + νt/σε)∇ε) = C1 Cμ k (G/νt) − (⅔C1 − C3)(∇·φ) ε − C2 ε²/k
//! ∂k/∂t + ∇·(φk) − ∇·((ν + νt/σk)∇k) = G − ⅔(∇·φ) k − ε k/k
//! G = νt (∇U : dev(∇U + ∇Uᵀ))      (G/νt evaluated with the current U, νt of the last step)
//! ```
//!
//! in this order: ε first (with k of the last step), then k with the new ε; the sinks C2 ε/k
//! and ε/k implicit, the ∇·φ terms implicit where positive (`SuSp`); ε and k bounded below by
//! `epsilonMin`/`kMin` ([`super::bound`]); then νt. The wall functions
//! ([`super::wall_functions`]) set ε in the wall cells (the rows of the ε equation fixed there)
//! and G there before the equations are assembled. Coefficients (OpenFOAM's defaults): Cμ 0.09,
//! C1 1.44, C2 1.92, C3 0, σk 1, σε 1.3.
//!
//! Volume-averaged flows: CFDEMcoupling's cfdemSolverPiso (CFDEMcoupling-PUBLIC and
//! CFDEMcoupling-PFM, `createFields.H`: `incompressible::turbulenceModel::New(U, phi,
//! laminarTransport)`) hands the model the solver's flux φ = (εU)_f·S and no voidage: the k and
//! ε equations are the single-phase ones above, convected by the superficial flux (∇·φ = −∂ε/∂t
//! enters through the SuSp terms), with G from the interstitial velocity. This module does the
//! same: it is given the fluid's φ. Only the momentum stress carries the voidage,
//! −∇·(ε νeff ∇U) − ∇·(ε νeff dev2(∇Uᵀ)) with νeff = ν + νt (`cfdemCloud::divVoidfractionTau`).

use super::bound::bound;
use super::near_wall;
use super::properties::KEpsilonSettings;
use super::scalar_bc::{self, ScalarBc, TurbulenceField};
use super::scalar_eqn::{ScalarEqn, Transport};
use super::scalar_field::ScalarField;
use super::wall_functions;
use crate::ddt::CrankNicolsonDdt0;
use crate::error::{FvError, Result};
use crate::fvc::{self, Field};
use crate::gather;
use crate::geometry::{FvGeometry, V3};
use crate::linsolve::SolveStats;
use std::path::Path;

/// The model coefficients (dimensionless but the bounds: `k_min` m²/s², `epsilon_min` m²/s³).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KEpsilonCoeffs {
    /// Cμ.
    pub cmu: f64,
    /// C1 (production of ε).
    pub c1: f64,
    /// C2 (destruction of ε).
    pub c2: f64,
    /// C3 (compressibility of ε).
    pub c3: f64,
    /// σk (turbulent Prandtl number of k).
    pub sigma_k: f64,
    /// σε (turbulent Prandtl number of ε).
    pub sigma_eps: f64,
    /// Lower bound of k (`kMin`, OpenFOAM's SMALL = 1e-15 by default).
    pub k_min: f64,
    /// Lower bound of ε (`epsilonMin`).
    pub epsilon_min: f64,
}

impl Default for KEpsilonCoeffs {
    fn default() -> Self {
        KEpsilonCoeffs {
            cmu: 0.09,
            c1: 1.44,
            c2: 1.92,
            c3: 0.0,
            sigma_k: 1.0,
            sigma_eps: 1.3,
            k_min: 1e-15,
            epsilon_min: 1e-15,
        }
    }
}

/// What the model needs of the flow at the end of a time step.
pub struct Flow<'a> {
    /// ∇U at cells (1/s), of `u` and `u_b` (Gauss linear, [`fvc::grad_vector`]).
    pub grad_u: &'a [crate::fvc::Tensor],
    /// Cell velocities (m/s).
    pub u: &'a [V3],
    /// Boundary-face velocities (m/s).
    pub u_b: &'a [V3],
    /// Face fluxes φ (m³/s).
    pub phi: &'a [f64],
    /// Kinematic viscosity ν (m²/s).
    pub nu: f64,
    /// Time step (s).
    pub dt: f64,
    /// Laplacian delta coefficient per face (1/m).
    pub lap_dc: &'a [f64],
    /// Explicit non-orthogonal correction of the Laplacians.
    pub corrected: bool,
}

/// The k–ε model's state on a mesh.
#[derive(Clone, Debug)]
pub struct KEpsilon {
    settings: KEpsilonSettings,
    k: ScalarField,
    epsilon: ScalarField,
    nut: ScalarField,
    /// Wall distance y of each boundary face (m): OpenFOAM's `nearWallDist` on `wall` patches
    /// ([`near_wall`]), 0 elsewhere.
    y: Vec<f64>,
    /// 1/(number of `epsilonWallFunction` faces of the owner) on those faces, else 0.
    wall_weight: Vec<f64>,
    /// `CrankNicolson ψ`'s stored derivatives of ε and k (for the fields whose scheme it
    /// is), created at the first step as OpenFOAM creates its `ddt0(epsilon)`, `ddt0(k)`.
    cn: [Option<CrankNicolsonDdt0<f64>>; 2],
}

/// What one call of [`KEpsilon::correct`] solved.
#[derive(Clone, Debug, PartialEq)]
pub struct CorrectReport {
    /// The ε solve.
    pub epsilon: SolveStats,
    /// The k solve.
    pub k: SolveStats,
}

impl KEpsilon {
    /// Reads `k`, `epsilon` and `nut` of the time directory `dir`, bounds k and ε and computes
    /// νt (OpenFOAM's constructor and `validate()`); `nu` is the kinematic viscosity (m²/s).
    pub fn read(
        dir: &Path,
        mesh: &foam::PolyMesh,
        g: &FvGeometry,
        settings: KEpsilonSettings,
        nu: f64,
    ) -> Result<KEpsilon> {
        let k = ScalarField::read(dir, "k", g, |path, file| {
            scalar_bc::read(path, file, mesh, g, TurbulenceField::K)
        })?;
        let epsilon = ScalarField::read(dir, "epsilon", g, |path, file| {
            scalar_bc::read(path, file, mesh, g, TurbulenceField::Epsilon)
        })?;
        let nut = ScalarField::read(dir, "nut", g, |path, file| {
            scalar_bc::read(path, file, mesh, g, TurbulenceField::Nut)
        })?;
        for (pi, (p, bc)) in g.patches.iter().zip(&epsilon.bcs).enumerate() {
            if matches!(bc, ScalarBc::EpsilonWallFunction { .. })
                && !matches!(nut.bcs[pi], ScalarBc::NutkWallFunction(_))
            {
                return Err(FvError::setting(
                    dir.join("nut"),
                    format!("boundaryField.{}.type", p.name),
                    "epsilonWallFunction in `epsilon` needs nutkWallFunction here",
                ));
            }
        }
        let y = near_wall::near_wall_distances(mesh, g);
        let mut count = vec![0usize; g.n_cells];
        for (p, bc) in g.patches.iter().zip(&epsilon.bcs) {
            if matches!(bc, ScalarBc::EpsilonWallFunction { .. }) {
                for f in p.faces.clone() {
                    count[g.owner[f] as usize] += 1;
                }
            }
        }
        let mut wall_weight = vec![0.0; g.n_boundary()];
        for (p, bc) in g.patches.iter().zip(&epsilon.bcs) {
            if matches!(bc, ScalarBc::EpsilonWallFunction { .. }) {
                for f in p.faces.clone() {
                    wall_weight[f - g.n_internal] = 1.0 / count[g.owner[f] as usize] as f64;
                }
            }
        }
        let mut m = KEpsilon {
            settings,
            k,
            epsilon,
            nut,
            y,
            wall_weight,
            cn: [None, None],
        };
        let c = m.settings.coeffs;
        bound(g, &mut m.k.cells, &mut m.k.boundary, c.k_min);
        bound(
            g,
            &mut m.epsilon.cells,
            &mut m.epsilon.boundary,
            c.epsilon_min,
        );
        m.correct_nut(g, nu);
        Ok(m)
    }

    /// Turbulent viscosity νt at cells (m²/s).
    pub fn nut(&self) -> &[f64] {
        &self.nut.cells
    }

    /// Forgets the stored derivatives of `CrankNicolson ψ`: the next step is Euler, as a run's
    /// first ([`crate::Fluid::hold`]).
    pub fn restart_time_schemes(&mut self) {
        self.cn = [None, None];
    }

    /// νt on the boundary faces (m²/s; the wall function's value on walls).
    pub fn nut_boundary(&self) -> &[f64] {
        &self.nut.boundary
    }

    /// k at cells (m²/s²).
    pub fn k(&self) -> &[f64] {
        &self.k.cells
    }

    /// ε at cells (m²/s³).
    pub fn epsilon(&self) -> &[f64] {
        &self.epsilon.cells
    }

    /// The settings the model runs with.
    pub fn settings(&self) -> &KEpsilonSettings {
        &self.settings
    }

    /// νt = Cμ k²/ε at cells; on the boundary: `calculated` from the faces' k and ε,
    /// zero gradient, fixed values kept, `nutkWallFunction` from the wall cell's k
    /// (OpenFOAM's `correctNut`).
    fn correct_nut(&mut self, g: &FvGeometry, nu: f64) {
        let cmu = self.settings.coeffs.cmu;
        let (k, eps) = (&self.k.cells, &self.epsilon.cells);
        gather::each_mut(&mut self.nut.cells, |c, nut| {
            *nut = cmu * (k[c] * k[c]) / eps[c];
        });
        for (p, bc) in g.patches.iter().zip(&self.nut.bcs) {
            for f in p.faces.clone() {
                let b = f - g.n_internal;
                let o = g.owner[f] as usize;
                match bc {
                    ScalarBc::Calculated => {
                        let k = self.k.boundary[b];
                        self.nut.boundary[b] = cmu * (k * k) / self.epsilon.boundary[b];
                    }
                    ScalarBc::ZeroGradient => self.nut.boundary[b] = self.nut.cells[o],
                    ScalarBc::NutkWallFunction(law) => {
                        self.nut.boundary[b] =
                            wall_functions::nut_wall(law, self.y[b], self.k.cells[o], nu);
                    }
                    _ => {}
                }
            }
        }
    }

    /// The face diffusivity ν + νt/σ (m²/s) of a k or ε equation, linearly interpolated.
    fn diffusivity(&self, g: &FvGeometry, sigma: f64, nu: f64) -> Vec<f64> {
        let nut = &self.nut.cells;
        let cells: Vec<f64> = gather::cells(nut.len(), |c| nut[c] / sigma + nu);
        let b: Vec<f64> = self.nut.boundary.iter().map(|&n| n / sigma + nu).collect();
        fvc::interpolate(g, Field::new(&cells, &b))
    }

    /// One step of the model with the flow at the end of the PISO correctors (see the module
    /// doc for the equations and their order). With `turbulence off` nothing changes.
    pub fn correct(&mut self, g: &FvGeometry, flow: &Flow<'_>) -> Result<Option<CorrectReport>> {
        if !self.settings.active {
            return Ok(None);
        }
        let n = g.n_cells;
        let div_u = fvc::surface_integrate(g, flow.phi);
        let g_by_nu = production_by_nut(flow.grad_u);
        let nut = &self.nut.cells;
        let mut prod: Vec<f64> = gather::cells(n, |i| nut[i] * g_by_nu[i]);
        let k_old = self.k.cells.clone();
        let eps_old = self.epsilon.cells.clone();
        let (eps_r, k_r) = self.begin_time_schemes(&k_old, &eps_old, flow.dt);
        let wall_cells = self.apply_wall_functions(g, flow, &mut prod);
        let step = Step {
            flow,
            div_u,
            k_old,
            eps_old,
        };
        let eps_stats = self.solve_epsilon(g, &step, eps_r, &g_by_nu, &wall_cells)?;
        let k_stats = self.solve_k(g, &step, k_r, &prod)?;
        self.correct_nut(g, flow.nu);
        if let Some(i) = self.nut.cells.iter().position(|v| !v.is_finite()) {
            return Err(FvError::Diverged(format!(
                "k-epsilon: nut is not finite in cell {i}"
            )));
        }
        Ok(Some(CorrectReport {
            epsilon: eps_stats,
            k: k_stats,
        }))
    }

    /// Each field's `CrankNicolson ψ` state begins its step from the old values `k_old`,
    /// `eps_old`: the rates c/Δt (1/s) of ε and k (`None`: Euler).
    fn begin_time_schemes(
        &mut self,
        k_old: &[f64],
        eps_old: &[f64],
        dt: f64,
    ) -> (Option<f64>, Option<f64>) {
        let (eps_cn, k_cn) = (
            self.settings.epsilon.crank_nicolson,
            self.settings.k.crank_nicolson,
        );
        let cn = &mut self.cn;
        let eps_r = eps_cn.map(|psi| {
            cn[0]
                .get_or_insert_with(|| CrankNicolsonDdt0::new(psi))
                .begin_step(eps_old, dt)
        });
        let k_r = k_cn.map(|psi| {
            cn[1]
                .get_or_insert_with(|| CrankNicolsonDdt0::new(psi))
                .begin_step(k_old, dt)
        });
        (eps_r, k_r)
    }

    /// Wall functions: ε and G in the wall cells (G into `prod`), ε on the wall faces; returns
    /// the wall cells, once per wall face.
    fn apply_wall_functions(
        &mut self,
        g: &FvGeometry,
        flow: &Flow<'_>,
        prod: &mut [f64],
    ) -> Vec<usize> {
        let n = g.n_cells;
        let mut eps0 = vec![0.0; n];
        let mut g0 = vec![0.0; n];
        let mut wall_cells = Vec::new();
        for (pi, (p, bc)) in g.patches.iter().zip(&self.epsilon.bcs).enumerate() {
            let ScalarBc::EpsilonWallFunction { low_re } = *bc else {
                continue;
            };
            let ScalarBc::NutkWallFunction(law) = self.nut.bcs[pi] else {
                unreachable!("checked on read");
            };
            for f in p.faces.clone() {
                let b = f - g.n_internal;
                let o = g.owner[f] as usize;
                let grad_w = g.delta_coeff[f] * (flow.u_b[b] - flow.u[o]);
                let (e, gg) = wall_functions::epsilon_and_g(
                    &law,
                    low_re,
                    self.wall_weight[b],
                    self.y[b],
                    self.k.cells[o],
                    flow.nu,
                    self.nut.boundary[b],
                    grad_w.norm(),
                );
                eps0[o] += e;
                g0[o] += gg;
                wall_cells.push(o);
            }
        }
        for (p, bc) in g.patches.iter().zip(&self.epsilon.bcs) {
            if matches!(bc, ScalarBc::EpsilonWallFunction { .. }) {
                for f in p.faces.clone() {
                    self.epsilon.boundary[f - g.n_internal] = eps0[g.owner[f] as usize];
                }
            }
        }
        for &o in &wall_cells {
            prod[o] = g0[o];
            self.epsilon.cells[o] = eps0[o];
        }
        wall_cells
    }

    /// The ε equation with k of the last step (`eps_r`: its CrankNicolson rate), the rows of
    /// the `wall_cells` fixed to their wall-function ε; then ε's boundary values and bound.
    fn solve_epsilon(
        &mut self,
        g: &FvGeometry,
        step: &Step<'_>,
        eps_r: Option<f64>,
        g_by_nu: &[f64],
        wall_cells: &[usize],
    ) -> Result<SolveStats> {
        let n = g.n_cells;
        let c = self.settings.coeffs;
        let gamma = self.diffusivity(g, c.sigma_eps, step.flow.nu);
        let eps_transport = step.transport(eps_r.zip(self.cn[0].as_ref()));
        let mut eqn = ScalarEqn::transport(
            g,
            &eps_transport,
            &self.settings.epsilon,
            &self.epsilon.cells,
            &step.eps_old,
            &self.epsilon.boundary,
            &self.epsilon.bcs,
            &gamma,
        );
        let k_old = &step.k_old;
        let src: Vec<f64> = gather::cells(n, |i| c.c1 * g_by_nu[i] * c.cmu * k_old[i]);
        eqn.add_source(g, &src);
        let div_u = &step.div_u;
        let susp: Vec<f64> = gather::cells(n, |i| ((2.0 / 3.0) * c.c1 - c.c3) * div_u[i]);
        eqn.add_susp(g, &susp, &self.epsilon.cells);
        let eps = &self.epsilon.cells;
        let sp: Vec<f64> = gather::cells(n, |i| c.c2 * eps[i] / k_old[i]);
        eqn.add_sp(g, &sp);
        let values: Vec<f64> = wall_cells.iter().map(|&o| self.epsilon.cells[o]).collect();
        eqn.set_values(g, wall_cells, &values, &mut self.epsilon.cells);
        let solver = self.settings.epsilon.solver;
        let eps_stats = eqn.solve(g, &solver, &mut self.epsilon.cells, "epsilon")?;
        self.epsilon.evaluate(g, step.flow.phi);
        bound(
            g,
            &mut self.epsilon.cells,
            &mut self.epsilon.boundary,
            c.epsilon_min,
        );
        Ok(eps_stats)
    }

    /// The k equation with the new ε (`k_r`: its CrankNicolson rate, `prod` the production
    /// G); then k's boundary values and bound.
    fn solve_k(
        &mut self,
        g: &FvGeometry,
        step: &Step<'_>,
        k_r: Option<f64>,
        prod: &[f64],
    ) -> Result<SolveStats> {
        let n = g.n_cells;
        let c = self.settings.coeffs;
        let gamma = self.diffusivity(g, c.sigma_k, step.flow.nu);
        let k_transport = step.transport(k_r.zip(self.cn[1].as_ref()));
        let mut eqn = ScalarEqn::transport(
            g,
            &k_transport,
            &self.settings.k,
            &self.k.cells,
            &step.k_old,
            &self.k.boundary,
            &self.k.bcs,
            &gamma,
        );
        eqn.add_source(g, prod);
        let div_u = &step.div_u;
        let susp: Vec<f64> = gather::cells(n, |i| (2.0 / 3.0) * div_u[i]);
        eqn.add_susp(g, &susp, &self.k.cells);
        let (eps, k_old) = (&self.epsilon.cells, &step.k_old);
        let sp: Vec<f64> = gather::cells(n, |i| eps[i] / k_old[i]);
        eqn.add_sp(g, &sp);
        let solver = self.settings.k.solver;
        let k_stats = eqn.solve(g, &solver, &mut self.k.cells, "k")?;
        self.k.evaluate(g, step.flow.phi);
        bound(g, &mut self.k.cells, &mut self.k.boundary, c.k_min);
        Ok(k_stats)
    }

    /// Writes `k`, `epsilon` and `nut` into the time directory `dir` (cell values and the
    /// patches' `value` entries).
    pub fn write(&self, g: &FvGeometry, dir: &Path, format: foam::Format) -> Result<()> {
        self.k.write(g, &dir.join("k"), format)?;
        self.epsilon.write(g, &dir.join("epsilon"), format)?;
        self.nut.write(g, &dir.join("nut"), format)
    }
}

/// What one step of the model keeps fixed while it solves ε and k.
struct Step<'a> {
    /// The flow at the end of the PISO correctors.
    flow: &'a Flow<'a>,
    /// ∇·φ at cells (m³/s per m³).
    div_u: Vec<f64>,
    /// k of the last step (m²/s²).
    k_old: Vec<f64>,
    /// ε of the last step (m²/s³).
    eps_old: Vec<f64>,
}

impl Step<'_> {
    /// The transport terms of a k or ε equation with its `CrankNicolson ψ` rate and state.
    fn transport<'s>(
        &'s self,
        crank_nicolson: Option<(f64, &'s CrankNicolsonDdt0<f64>)>,
    ) -> Transport<'s> {
        Transport {
            phi: self.flow.phi,
            lap_dc: self.flow.lap_dc,
            corrected: self.flow.corrected,
            dt: self.flow.dt,
            crank_nicolson,
            ddt_weight: None,
            div_phi: Some(&self.div_u),
        }
    }
}

/// G/νt = ∇U : dev(∇U + ∇Uᵀ) (1/s²) per cell from ∇U.
fn production_by_nut(grad_u: &[crate::fvc::Tensor]) -> Vec<f64> {
    gather::cells(grad_u.len(), |c| {
        let t = &grad_u[c];
        let s = t + t.transpose();
        let tr = s[(0, 0)] + s[(1, 1)] + s[(2, 2)];
        let mut d = s;
        for i in 0..3 {
            d[(i, i)] -= tr / 3.0;
        }
        let mut sum = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                sum += t[(i, j)] * d[(i, j)];
            }
        }
        sum
    })
}
