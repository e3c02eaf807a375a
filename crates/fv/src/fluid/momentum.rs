//! The momentum stage of a PISO step: the matrix of the momentum equation (pisoFoam's
//! `UEqn.H`; CFDEM's cfdemSolverPiso `UEqn.H` for the volume-averaged terms: ε in the time
//! derivative and the stress, the implicit exchange Ksl/ρ, the explicit force f/ρ, the
//! `fvOptions` sources) and the momentum predictor with the old pressure gradient.

use super::{Fluid, GradMemo, Levels, StepReport};
use crate::bc;
use crate::error::Result;
use crate::fvc::{self, Field};
use crate::gather;
use crate::geometry::V3;
use crate::ldu::{Ldu, PAR_MIN};
use crate::linsolve;
use crate::settings::SnGrad;
use rayon::prelude::*;

/// The coefficients of one internal face in the momentum matrix ([`Fluid::face_terms`]).
struct FaceTerms {
    /// Upper and lower coefficient (m³/s).
    upper: f64,
    lower: f64,
    /// Its part of the owner's and the neighbour's diagonal (m³/s).
    d_o: f64,
    d_n: f64,
    /// The non-orthogonal correction's flux, + to the owner's source, − to the neighbour's
    /// (m⁴/s²).
    corr: V3,
}

/// The momentum equation of a step, fixed through its correctors.
pub(super) struct MomentumEqn {
    /// The off-diagonal coefficients of convection and diffusion (the predictor sets the
    /// diagonal of the component it solves).
    pub(super) m: Ldu,
    /// The diagonal per component (m³/s).
    pub(super) diag: Vec<V3>,
    /// The source per component (m⁴/s²).
    pub(super) b: Vec<V3>,
    /// A, the mean of the three diagonals per volume (1/s).
    pub(super) a_mean: Vec<f64>,
    /// 1/A (s).
    pub(super) r_au: Vec<f64>,
}

impl Fluid {
    /// Stage 2: the momentum matrix — convection and diffusion (implicit, [`Self::conv_diff`]),
    /// the full stress's explicit part, the time derivative of εU with the step's scheme
    /// (`lv`), the implicit exchange Ksl/ρ (U − Us), the explicit force f/ρ and the `fvOptions`
    /// sources — and its A = mean diagonal per volume.
    pub(super) fn momentum_matrix(&self, lv: &Levels) -> MomentumEqn {
        let n = self.g.n_cells;
        let rho = self.settings.rho;
        let (dt, ddt_k, old_old) = (lv.dt, lv.ddt_k, &lv.old_old);
        let grad_u = GradMemo::of(self.grad_u_end.as_ref(), &self.g, &self.u, &self.u_b);
        let (nu_f, nu_c, nu_bf) = self.eps_nu_eff(&lv.ef);
        let (cd, cd_diag, cd_b) = self.conv_diff(&nu_f, &grad_u);
        let g = &self.g;
        let m = cd;
        let stress = if self.settings.full_stress {
            let fl = fvc::dev2_transpose_flux(
                g,
                Field::new(&nu_c, &nu_bf),
                Field::new(&self.u, &self.u_b),
                &grad_u,
            );
            fvc::surface_integrate(g, &fl)
        } else {
            vec![V3::zeros(); n]
        };
        // Each cell on its own (in parallel on large meshes; the same bits).
        let cell = |c: usize| {
            let (mut d, mut bc) = (V3::zeros(), V3::zeros());
            let v = g.v[c];
            let ksl = self.ksl[c] / rho * v;
            for k in 0..3 {
                let (ddt, mut old_source) = match self.cn {
                    // OpenFOAM's CrankNicolson fvmDdt: diag c/Δt ε V, source (c/Δt ε°U° + ψ d₀) V
                    Some(_) => (lv.cn_r * self.eps[c] * v, lv.cn_src[c][k] * v),
                    None => (
                        ddt_k.c * self.eps[c] * v / dt,
                        self.eps_old[c] * v / dt * lv.u_old[c][k],
                    ),
                };
                if lv.backward {
                    old_source = ddt_k.c0 * old_source
                        - ddt_k.c00 * (old_old.eps[c] * v / dt * old_old.u[c][k]);
                }
                let mut rhs = cd_b[c][k]
                    + old_source
                    + ksl * self.us[c][k]
                    + v * self.force[c][k] / rho
                    + v * stress[c][k];
                for s in &self.mean_forces {
                    rhs += v * s.source(c)[k];
                }
                d[k] = cd_diag[c][k] + ddt + ksl;
                bc[k] = rhs;
            }
            (d, bc)
        };
        let (diag, b): (Vec<V3>, Vec<V3>) = gather::cells(n, cell).into_iter().unzip();
        let a_mean: Vec<f64> = (0..n)
            .map(|c| (diag[c][0] + diag[c][1] + diag[c][2]) / 3.0 / g.v[c])
            .collect();
        let r_au: Vec<f64> = a_mean.iter().map(|a| 1.0 / a).collect();
        MomentumEqn {
            m,
            diag,
            b,
            a_mean,
            r_au,
        }
    }

    /// Stage 3: the mean-velocity sources take 1/A of the matrix (`fvOptions.constrain`), and
    /// with `momentumPredictor` the momentum equation is solved component by component with
    /// the old pressure gradient, −κ_p ∇p° (pisoFoam's `solve(UEqn == -fvc::grad(p))`; model
    /// A's −ε∇p° as CFDEM's cfdemSolverPiso), the velocity's boundary values evaluated and the
    /// mean-velocity sources' correction applied.
    pub(super) fn momentum_predictor(
        &mut self,
        lv: &Levels,
        eqn: &mut MomentumEqn,
        report: &mut StepReport,
    ) -> Result<()> {
        // The mean-velocity sources take 1/A of this matrix (fvOptions.constrain).
        for s in &mut self.mean_forces {
            s.constrain(&eqn.r_au);
        }
        if !self.settings.momentum_predictor {
            return Ok(());
        }
        let g = &self.g;
        let n = g.n_cells;
        let solver = self.settings.u_solver;
        // The components are independent solves of matrices that differ in the diagonal
        // only: on large meshes they run side by side (each solve's arithmetic unchanged, so
        // the same bits as one after the other).
        let dirs: Vec<usize> = (0..3).filter(|&k| g.solution_dirs[k]).collect();
        // A smoothSolver sweeps in parallel on large meshes, as the other components' solves
        // run: OpenFOAM's sequential sweep on several threads where the mesh's numbering
        // allows (crate::sweep::pipeline, the same bits), else in the hybrid block order
        // (crate::sweep).
        let method = match solver.method {
            linsolve::Method::Smooth(sm) => linsolve::Method::Smooth(linsolve::Smoother {
                // (the hybrid blocks where the pipeline waits per block of rows, a 2-D
                // numbering: faster there, crate::sweep::pipeline)
                hybrid: g.rows.pipeline().is_none_or(|p| p.is_gated()),
                ..sm
            }),
            other => other,
        };
        let rhs_of = |k: usize| -> Vec<f64> {
            gather::cells(n, |c| {
                eqn.b[c][k] - g.v[c] * self.kappa_p(c) * self.grad_p[c][k]
            })
        };
        let x_of = |k: usize| -> Vec<f64> { self.u.iter().map(|v| v[k]).collect() };
        let diag_of = |k: usize| -> Vec<f64> { eqn.diag.iter().map(|d| d[k]).collect() };
        let what = |k: usize| ["Ux", "Uy", "Uz"][k];
        let solved: Vec<(Vec<f64>, linsolve::SolveStats)> = match method {
            // A smoothSolver relaxes the components side by side in each sweep
            // (linsolve::smooth_components: the bits of the solves one after another).
            linsolve::Method::Smooth(sm) => {
                let diags: Vec<Vec<f64>> = dirs.iter().map(|&k| diag_of(k)).collect();
                let rhs: Vec<Vec<f64>> = dirs.iter().map(|&k| rhs_of(k)).collect();
                let mut xs: Vec<Vec<f64>> = dirs.iter().map(|&k| x_of(k)).collect();
                let names: Vec<&str> = dirs.iter().map(|&k| what(k)).collect();
                let q = linsolve::Components {
                    diags: &diags,
                    b: &rhs,
                    what: &names,
                };
                let stats =
                    linsolve::smooth_components(&eqn.m, g, &q, &mut xs, sm, &solver.controls)?;
                xs.into_iter().zip(stats).collect()
            }
            _ => {
                let solve_one = |k: usize| -> Result<(Vec<f64>, linsolve::SolveStats)> {
                    let mut m = eqn.m.clone();
                    m.diag = diag_of(k);
                    let (rhs, mut x) = (rhs_of(k), x_of(k));
                    let s =
                        linsolve::solve(method, &m, g, &rhs, &mut x, &solver.controls, what(k))?;
                    Ok((x, s))
                };
                let solved: Vec<Result<(Vec<f64>, linsolve::SolveStats)>> = if n >= PAR_MIN {
                    dirs.par_iter().map(|&k| solve_one(k)).collect()
                } else {
                    dirs.iter().map(|&k| solve_one(k)).collect()
                };
                solved.into_iter().collect::<Result<_>>()?
            }
        };
        for (&k, (x, s)) in dirs.iter().zip(solved) {
            report.momentum.push(s);
            for c in 0..n {
                self.u[c][k] = x[c];
            }
        }
        self.update_u_boundary(lv.t_new);
        for s in &mut self.mean_forces {
            s.correct(&self.g.v, &self.eps, &mut self.u);
        }
        Ok(())
    }

    /// ε νeff at faces (m²/s): the product formed at cells and boundary faces (ε of the
    /// boundary the `voidfraction` condition's) and interpolated linearly, as
    /// grainPisoFoam's and CFDEM's `voidfraction*nuEff` fields are; also the cell and
    /// boundary values.
    fn eps_nu_eff(&self, ef: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let g = &self.g;
        let (nu_c, nu_b) = self.nu_eff();
        let a_c: Vec<f64> = (0..g.n_cells).map(|c| self.eps[c] * nu_c[c]).collect();
        let a_b: Vec<f64> = (0..g.n_boundary())
            .map(|b| ef[g.n_internal + b] * nu_b[b])
            .collect();
        let a_f = fvc::interpolate(g, Field::new(&a_c, &a_b));
        (a_f, a_c, a_b)
    }

    /// Convection (flux φ, current) and diffusion (ε νeff at faces, `nu_f`) of the momentum
    /// equation: off-diagonal matrix, per-component diagonal and source (including boundary
    /// contributions and the explicit non-orthogonal correction). The faces' terms are formed
    /// in parallel and each cell gathers its faces' in face order ([`crate::gather`]: the bits
    /// of OpenFOAM's scatter loops).
    fn conv_diff(&self, nu_f: &[f64], grad_u: &[crate::fvc::Tensor]) -> (Ldu, Vec<V3>, Vec<V3>) {
        let g = &self.g;
        let ni = g.n_internal;
        let corrected = self.settings.sn_grad == SnGrad::Corrected;
        let conv = self.settings.convection;
        let weights = conv.weights(g, &self.phi, &self.u, &self.u_b, grad_u);
        let faces: Vec<FaceTerms> = crate::gather::over(0..ni)
            .map(|f| self.face_terms(f, weights[f], nu_f, grad_u, corrected))
            .collect();
        let (upper, lower): (Vec<f64>, Vec<f64>) = crate::gather::over(0..faces.len())
            .map(|f| (faces[f].upper, faces[f].lower))
            .unzip();
        let m = Ldu {
            diag: vec![0.0; g.n_cells],
            upper,
            lower,
        };
        let vi = bc::velocity_value_coeffs(g, &self.u_bc, &self.phi);
        let (u, u_b) = (&self.u, &self.u_b);
        let sums = gather::face_sums(
            g,
            |_| (V3::zeros(), V3::zeros()),
            |(mut d, mut b), f, own| {
                if f < ni {
                    let t = &faces[f];
                    let dd = if own { t.d_o } else { t.d_n };
                    for k in 0..3 {
                        d[k] += dd;
                    }
                    if corrected {
                        for j in 0..3 {
                            if own {
                                b[j] += t.corr[j];
                            } else {
                                b[j] -= t.corr[j];
                            }
                        }
                    }
                } else {
                    // The boundary face's part: with U_b = vi ⊙ U_P + vb, the implicit
                    // φ vi + a_f|S|δ (1 − vi) and the explicit (−φ + a_f|S|δ) vb.
                    let bi = f - ni;
                    let o = g.owner[f] as usize;
                    let phi = self.phi[f];
                    let gam = nu_f[f] * g.mag_sf[f] * self.lap_dc[f];
                    for k in 0..3 {
                        d[k] += phi * vi[bi][k] + gam * (1.0 - vi[bi][k]);
                        let vb = u_b[bi][k] - vi[bi][k] * u[o][k];
                        b[k] += -phi * vb + gam * vb;
                    }
                }
                (d, b)
            },
        );
        let (mut diag, mut b): (Vec<V3>, Vec<V3>) =
            crate::gather::over(0..sums.len()).map(|c| sums[c]).unzip();
        // linearUpwind's explicit part: the source loses V ∇·(φ c) (OpenFOAM's
        // `fvm += fvc::surfaceIntegrate(faceFlux*correction)`).
        if let Some(corr) = conv.correction(g, &self.phi, &self.u, grad_u) {
            let mut flux: Vec<V3> = (0..g.n_internal).map(|f| self.phi[f] * corr[f]).collect();
            flux.resize(g.n_faces(), V3::zeros());
            let div = fvc::surface_integrate(g, &flux);
            for c in 0..g.n_cells {
                for k in 0..3 {
                    b[c][k] -= g.v[c] * div[c][k];
                }
            }
        }
        // `bounded`: minus (∇·φ) U, implicit (OpenFOAM's `fvm::Sp(fvc::surfaceIntegrate(phi), U)`).
        if self.settings.bounded_convection {
            let div_phi = fvc::surface_integrate(g, &self.phi);
            for c in 0..g.n_cells {
                for k in 0..3 {
                    diag[c][k] -= g.v[c] * div_phi[c];
                }
            }
        }
        (m, diag, b)
    }

    /// The terms of internal face `f` in the momentum matrix, for the convection weight `w`
    /// of the owner, ε νeff at the faces `nu_f` and ∇U `grad_u` (OpenFOAM's `fvm::div` and
    /// `fvm::laplacian` coefficients, and with `corrected` the non-orthogonal flux
    /// a_f|S| k·(∇U)_f of `laplacian(…, U)`'s explicit part).
    fn face_terms(
        &self,
        f: usize,
        w: f64,
        nu_f: &[f64],
        grad_u: &[crate::fvc::Tensor],
        corrected: bool,
    ) -> FaceTerms {
        let g = &self.g;
        let (o, nn) = (g.owner[f] as usize, g.neighbour[f] as usize);
        let phi = self.phi[f];
        let gam = nu_f[f] * g.mag_sf[f] * self.lap_dc[f];
        let mut corr = V3::zeros();
        if corrected {
            let wf = g.weight[f];
            let kv = g.corr_vec[f];
            let c = nu_f[f] * g.mag_sf[f];
            for j in 0..3 {
                let mut s = 0.0;
                for i in 0..3 {
                    s += kv[i]
                        * (wf * (grad_u[o][(i, j)] - grad_u[nn][(i, j)]) + grad_u[nn][(i, j)]);
                }
                corr[j] = c * s;
            }
        }
        FaceTerms {
            upper: phi * (1.0 - w) - gam,
            lower: -phi * w - gam,
            d_o: phi * w + gam,
            d_n: -phi * (1.0 - w) + gam,
            corr,
        }
    }
}
