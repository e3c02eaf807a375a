//! The PISO correctors of a step (pisoFoam's `pEqn.H`; CFDEM's cfdemSolverPiso `pEqn.H` for
//! the voidage: φ* = ε_f HbyA_f·S, the Laplacian of ε(ε/A) resp. ε/A, ∂ε/∂t in the pressure
//! equation, U = HbyA − (ε/A)∇p resp. (1/A)∇p): HbyA, the predicted flux φ* with ddtCorr or
//! the porous faces' own momentum balance, the pressure equation with its non-orthogonal
//! correctors, the Rhie–Chow flux and the velocity correction.

use super::coefficients::Correctors;
use super::{Fluid, Levels, MomentumEqn, StepReport};
use crate::error::Result;
use crate::fvc::{self, Field};
use crate::gather;
use crate::geometry::{FvGeometry, V3};
use crate::ldu::Ldu;
use crate::linsolve;
use crate::settings::SnGrad;

/// The face fluxes of one corrector (m³/s).
struct CorrectorFluxes {
    /// φ*, the predicted flux with the fixed boundary fluxes.
    star: Vec<f64>,
    /// φ* before the boundary fluxes were fixed (for fixedFluxPressure).
    unconstrained: Vec<f64>,
    /// The flux the corrector starts from (for totalPressure, [`Fluid::eval_p_boundary`]).
    start: Vec<f64>,
}

/// The pressure equation of a corrector.
struct PressureEqn {
    /// The Laplacian ∇·(γ∇p) (symmetric positive definite with a fixed-value patch or ref cell).
    m: Ldu,
    /// Its source: −∇·φ* V − ∂ε/∂t V and the fixed values' and reference's parts (m³/s).
    src: Vec<f64>,
    /// The boundary faces where a pressure condition fixes the value.
    p_fixed: Vec<bool>,
}

impl Fluid {
    /// Stage 5, one PISO corrector (`corr` from 0): HbyA, the predicted flux φ*, the
    /// pressure equation solved ([`Self::solve_pressure`]), the face flux φ = φ* − γ_f|S|
    /// snGrad p and the cell velocities from the new pressure gradient.
    pub(super) fn piso_corrector(
        &mut self,
        corr: usize,
        lv: &Levels,
        eqn: &MomentumEqn,
        cs: &mut Correctors,
        report: &mut StepReport,
    ) -> Result<()> {
        if corr > 0 {
            self.renew_cn_ddt_corr(lv, cs);
        }
        let hbya = self.hbya(eqn);
        let mut phi_star = if self.harmonic_faces {
            self.harmonic_flux(lv, cs, &hbya)
        } else {
            let g = &self.g;
            let hb: Vec<V3> = (g.n_internal..g.n_faces())
                .map(|f| hbya[g.owner[f] as usize])
                .collect();
            let hf = fvc::interpolate(g, Field::new(&hbya, &hb));
            let mut phi_star = self.flux(&lv.ef, &hf);
            for f in 0..g.n_faces() {
                phi_star[f] += cs.ddt_corr[f];
            }
            phi_star
        };
        let g = &self.g;
        let phi_unconstrained = phi_star.clone();
        for f in g.n_internal..g.n_faces() {
            let bi = f - g.n_internal;
            if cs.fixed_flux[bi] {
                phi_star[f] = lv.ef[f] * self.u_b[bi].dot(&g.sf[f]);
            }
        }
        // The flux this corrector starts from decides in- and outflow on totalPressure
        // faces (Self::eval_p_boundary).
        let phi_in = std::mem::replace(&mut self.phi, phi_star.clone());
        self.update_p_boundary(lv.t_new, &cs.gamma_b, &phi_unconstrained, &phi_in);
        let fluxes = CorrectorFluxes {
            star: phi_star,
            unconstrained: phi_unconstrained,
            start: phi_in,
        };
        let last_corr = corr + 1 == self.settings.n_correctors;
        self.solve_pressure(lv.t_new, last_corr, cs, &fluxes, report)?;
        self.update_p_boundary(lv.t_new, &cs.gamma_b, &fluxes.unconstrained, &fluxes.start);
        self.correct_velocity(lv.t_new, cs, &hbya);
        Ok(())
    }

    /// HbyA = H/A per cell (m/s; zero in a direction that is not solved, OpenFOAM's
    /// `fvMatrix::H`) of the momentum equation `eqn` with the current velocity.
    fn hbya(&self, eqn: &MomentumEqn) -> Vec<V3> {
        let g = &self.g;
        let (b, diag, a_mean, r_au) = (&eqn.b, &eqn.diag, &eqn.a_mean, &eqn.r_au);
        // H/A; zero in a direction that is not solved (OpenFOAM's fvMatrix::H).
        // One pass over the rows for the three components: each entry's coefficient read
        // once; each component's off-diagonal sum in row order from 0.0 (Ldu::off_row's).
        let (rows, u) = (&g.rows, &self.u);
        crate::gather::cells(g.n_cells, |c| {
            let mut off = [0.0; 3];
            for k in rows.row(c) {
                let (a, uj) = (eqn.m.coef(rows, k), u[rows.col[k] as usize]);
                for d in 0..3 {
                    off[d] += a * uj[d];
                }
            }
            V3::from_fn(|d, _| {
                if g.solution_dirs[d] {
                    let hv = b[c][d] - off[d] - (diag[c][d] - a_mean[c] * g.v[c]) * u[c][d];
                    hv / g.v[c] * r_au[c]
                } else {
                    0.0
                }
            })
        })
    }

    /// The predicted flux φ* of [`Fluid::harmonic_faces`]: γ_f (HbyA/κ)_f·S + ddtCorr on
    /// internal faces, the owner's half cell on boundary faces, and on the porous faces of
    /// [`super::PorousTimeFlux::Consistent`] their own momentum balance with their old flux.
    fn harmonic_flux(&self, lv: &Levels, cs: &Correctors, hbya: &[V3]) -> Vec<f64> {
        let g = &self.g;
        let n = g.n_cells;
        let (kappa, gamma, ddt_corr) = (&cs.kappa, &cs.gamma, &cs.ddt_corr);
        let pt = &cs.porous;
        // φ* = γ_f (HbyA/κ)_f·S on internal faces: the driving term interpolated
        // like the pressure gradient it balances (Fluid::harmonic_faces).
        let ht: Vec<V3> = (0..n).map(|c| 1.0 / kappa[c] * hbya[c]).collect();
        let htf = interpolate_cells(g, &ht);
        // between clear cells pisoFoam's ε_f (HbyA)_f·S
        let hf = interpolate_cells(g, hbya);
        let ht_steady = self.steady_driving(lv, cs, &ht);
        let htsf = if pt.consistent {
            interpolate_cells(g, &ht_steady)
        } else {
            Vec::new()
        };
        (0..g.n_faces())
            .map(|f| {
                let internal = f < g.n_internal;
                if !internal && g.boundary_empty[f - g.n_internal] {
                    0.0
                } else if pt.consistent && cs.porous_face[f] && internal {
                    // The face's momentum balance with its own old flux.
                    let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
                    let w = g.weight[f];
                    let rtf = (1.0 - w) * pt.r_t[o] + w * pt.r_t[nb_];
                    gamma[f] * (htsf[f].dot(&g.sf[f]) + rtf * pt.phi_t[f])
                } else if pt.consistent && cs.porous_face[f] {
                    // The owner's half cell with the face's old flux.
                    let o = g.owner[f] as usize;
                    gamma[f] * (ht_steady[o].dot(&g.sf[f]) + pt.r_t[o] * pt.phi_t[f])
                } else if internal && !cs.porous_face[f] {
                    lv.ef[f] * hf[f].dot(&g.sf[f]) + ddt_corr[f]
                } else if internal {
                    gamma[f] * htf[f].dot(&g.sf[f]) + ddt_corr[f]
                } else {
                    // The owner's half cell: φ* = γ_c (HbyA_c/κ_c)·S = ε_c HbyA_c·S.
                    let o = g.owner[f] as usize;
                    self.eps[o] * hbya[o].dot(&g.sf[f]) + ddt_corr[f]
                }
            })
            .collect()
    }

    /// H′/κ_p per cell: HbyA/κ (`ht`) without the old-time source ε° U°/Δt of the step's
    /// scheme ([`super::PorousTimeFlux::Consistent`]; empty when it is not in use).
    fn steady_driving(&self, lv: &Levels, cs: &Correctors, ht: &[V3]) -> Vec<V3> {
        let pt = &cs.porous;
        let (ddt_k, old_old, u_old) = (lv.ddt_k, &lv.old_old, &lv.u_old);
        let is_cn = self.cn.is_some();
        // H′/κ_p: the same without the old-time source ε° U°/Δt (PorousTimeFlux).
        if pt.consistent {
            (0..self.g.n_cells)
                .map(|c| match lv.backward {
                    // CrankNicolson: H_ddt/κ_p = (c/Δt ε°U° + ψ d₀)/κ_p
                    _ if is_cn => ht[c] - pt.cn_h[c],
                    // H_ddt/κ_p = (c₀ ε°U° − c₀₀ ε°°U°°)/(κ_p Δt)
                    true => {
                        ht[c]
                            - pt.r_t[c] / ddt_k.c
                                * (ddt_k.c0 * self.eps_old[c] * u_old[c]
                                    - ddt_k.c00 * old_old.eps[c] * old_old.u[c])
                    }
                    false => ht[c] - self.eps_old[c] * pt.r_t[c] * u_old[c],
                })
                .collect()
        } else {
            Vec::new()
        }
    }

    /// The pressure equation ∇·(γ∇p) = ∇·φ* + ∂ε/∂t of a corrector: the compact Laplacian
    /// with the fixed boundary values, the source, and `pRefCell` when no condition fixes
    /// the level.
    fn pressure_eqn(&self, cs: &Correctors, phi_star: &[f64]) -> PressureEqn {
        let g = &self.g;
        let (n, nb) = (g.n_cells, g.n_boundary());
        let gamma = &cs.gamma;
        // Pressure matrix (symmetric positive definite with a fixed-value patch or ref cell).
        let mut pm = Ldu::zeros(g);
        let p_fixed: Vec<bool> = {
            let mut v = vec![false; nb];
            for (patch, bc) in g.patches.iter().zip(&self.p_bc) {
                if bc.fixes_value() {
                    for bi in patch.boundary_range(g.n_internal) {
                        v[bi] = true;
                    }
                }
            }
            v
        };
        // γ_f|S|δ per face (in parallel), each cell's sum over its faces in face order
        // (crate::gather: the face loops' bits).
        let coef: Vec<f64> = crate::gather::over(0..g.n_faces())
            .map(|f| gamma[f] * g.mag_sf[f] * self.lap_dc[f])
            .collect();
        for f in 0..g.n_internal {
            pm.upper[f] = -coef[f];
            pm.lower[f] = -coef[f];
        }
        let fixed = |f: usize| f >= g.n_internal && p_fixed[f - g.n_internal];
        let div_star = fvc::surface_integrate(g, phi_star);
        let sums = gather::face_sums(
            g,
            |_| (0.0, 0.0),
            |(d, s), f, _| {
                if f < g.n_internal {
                    (d + coef[f], s)
                } else if fixed(f) {
                    (d + coef[f], s + coef[f] * self.p_b[f - g.n_internal])
                } else {
                    (d, s)
                }
            },
        );
        let mut src = gather::cells(n, |c| {
            let mut s = sums[c].1 - div_star[c] * g.v[c];
            if self.ddt_voidage {
                s -= g.v[c] * cs.ddt_eps[c];
            }
            s
        });
        for (d, s) in pm.diag.iter_mut().zip(&sums) {
            *d = s.0;
        }
        if !cs.fixes_p {
            let (rc, rv) = self.settings.p_ref;
            let d = pm.diag[rc];
            src[rc] += d * rv;
            pm.diag[rc] += d;
        }
        PressureEqn {
            m: pm,
            src,
            p_fixed,
        }
    }

    /// Solves the corrector's pressure equation ([`Self::pressure_eqn`]) once and once more
    /// per non-orthogonal corrector, each time with the explicit non-orthogonal correction of
    /// the last solution (`pFinal`'s solver on the last corrector's last solve); then sets
    /// the Rhie–Chow face flux φ = φ* − (γ_f|S|δ (p_N − p_P) + the non-orthogonal flux)
    /// (OpenFOAM's `phi = phiHbyA - pEqn.flux()`) and p.
    fn solve_pressure(
        &mut self,
        t_new: f64,
        last_corr: bool,
        cs: &Correctors,
        fluxes: &CorrectorFluxes,
        report: &mut StepReport,
    ) -> Result<()> {
        let peq = self.pressure_eqn(cs, &fluxes.star);
        let g = &self.g;
        let gamma = &cs.gamma;
        let corrected = self.settings.sn_grad == SnGrad::Corrected;
        let mut p = std::mem::take(&mut self.p);
        let mut nonorth_flux = vec![0.0; g.n_internal];
        for nonorth in 0..=self.settings.n_non_orth {
            let mut rhs = peq.src.clone();
            // On an orthogonal mesh the correction is zero (skipped: the same bits).
            if corrected && !g.orthogonal {
                let gp = fvc::grad_scalar(g, &p, &self.p_b);
                crate::gather::each_mut(&mut nonorth_flux, |f, nf| {
                    let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
                    let w = g.weight[f];
                    let gf: V3 = V3::from_fn(|i, _| w * (gp[o][i] - gp[nb_][i]) + gp[nb_][i]);
                    *nf = gamma[f] * g.mag_sf[f] * g.corr_vec[f].dot(&gf);
                });
                let nf = &nonorth_flux;
                rhs = gather::face_sums(
                    g,
                    |c| peq.src[c],
                    |r, f, own| match (f < g.n_internal, own) {
                        (false, _) => r,
                        (true, true) => r + nf[f],
                        (true, false) => r - nf[f],
                    },
                );
            }
            let last = last_corr && nonorth == self.settings.n_non_orth;
            let ctl = if last {
                &self.settings.p_final
            } else {
                &self.settings.p_solver
            };
            let s = linsolve::solve(ctl.method, &peq.m, g, &rhs, &mut p, &ctl.controls, "p")?;
            report.pressure.push(s);
            if nonorth < self.settings.n_non_orth {
                // The next correction's ∇p sees the boundary values of this solution
                // (OpenFOAM's solve ends with p.correctBoundaryConditions()).
                let mut pb = std::mem::take(&mut self.p_b);
                self.eval_p_boundary(
                    t_new,
                    &p,
                    &cs.gamma_b,
                    &fluxes.unconstrained,
                    &fluxes.start,
                    &mut pb,
                );
                self.p_b = pb;
            }
        }
        let phi_star = &fluxes.star;
        // Rhie–Chow face flux from the pressure solution.
        let lap_dc = &self.lap_dc;
        crate::gather::each_mut(&mut self.phi[..g.n_internal], |f, phi| {
            let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
            *phi = phi_star[f]
                - (gamma[f] * g.mag_sf[f] * lap_dc[f] * (p[nb_] - p[o]) + nonorth_flux[f]);
        });
        for f in g.n_internal..g.n_faces() {
            let bi = f - g.n_internal;
            if peq.p_fixed[bi] {
                let o = g.owner[f] as usize;
                self.phi[f] =
                    phi_star[f] - gamma[f] * g.mag_sf[f] * self.lap_dc[f] * (self.p_b[bi] - p[o]);
            }
        }
        self.p = p;
        Ok(())
    }

    /// The velocity correction U = HbyA − κ∇p with the new pressure's gradient (the
    /// flux-continuous one of [`Fluid::harmonic_faces`], else Gauss linear; near γ jumps
    /// with [`Fluid::reconstruct_u`] U = R/ε from the fluxes), then the velocity's boundary
    /// values at `t_new` and the mean-velocity sources' correction.
    fn correct_velocity(&mut self, t_new: f64, cs: &Correctors, hbya: &[V3]) {
        let n = self.g.n_cells;
        let kappa = &cs.kappa;
        self.grad_p = if self.harmonic_faces {
            flux_consistent_grad(
                &self.g,
                &self.p,
                &self.p_b,
                &cs.gam_c,
                &cs.porous_face,
                cs.porous.consistent.then_some(&cs.porous.gam_steady[..]),
            )
        } else {
            fvc::grad_scalar(&self.g, &self.p, &self.p_b)
        };
        if self.reconstruct_u {
            let r = fvc::reconstruct(&self.g, &self.phi);
            let near = &cs.jump_zone;
            for c in 0..n {
                self.u[c] = if near[c] {
                    1.0 / self.eps[c] * r[c]
                } else {
                    hbya[c] - (kappa[c] * self.grad_p[c])
                };
            }
        } else {
            let grad_p = &self.grad_p;
            gather::each_mut(&mut self.u, |c, u| *u = hbya[c] - (kappa[c] * grad_p[c]));
        }
        self.update_u_boundary(t_new);
        for s in &mut self.mean_forces {
            s.correct(&self.g.v, &self.eps, &mut self.u);
        }
    }
}

/// Gauss gradient of the cell pressures `p` (boundary values `p_b`) with the flux-continuous
/// face pressure of [`Fluid::harmonic_faces`] on the internal faces `porous` marks (next to
/// porous cells): p_f weights each side by its flux coefficient γ = εκ over its distance to
/// the face, p_f = (w γ_P p_P + (1−w) γ_N p_N)/(w γ_P + (1−w) γ_N). `gamma` per cell, or
/// `steady` per cell when given (the steady γ′ of [`PorousTimeFlux::Consistent`]). Faces
/// between clear cells take pisoFoam's linear face value p_N + w (p_P − p_N).
fn flux_consistent_grad(
    g: &FvGeometry,
    p: &[f64],
    p_b: &[f64],
    gamma: &[f64],
    porous: &[bool],
    steady: Option<&[f64]>,
) -> Vec<V3> {
    let mut sum = vec![V3::zeros(); g.n_cells];
    for f in 0..g.n_internal {
        let (o, nb) = (g.owner[f] as usize, g.neighbour[f] as usize);
        let w = g.weight[f];
        if !porous[f] {
            let pf = p[nb] + w * (p[o] - p[nb]);
            for i in 0..3 {
                sum[o][i] += pf * g.sf[f][i];
                sum[nb][i] -= pf * g.sf[f][i];
            }
            continue;
        }
        let kappa = steady.unwrap_or(gamma);
        let (a, b) = (w * kappa[o], (1.0 - w) * kappa[nb]);
        let pf = (a * p[o] + b * p[nb]) / (a + b);
        for i in 0..3 {
            sum[o][i] += pf * g.sf[f][i];
            sum[nb][i] -= pf * g.sf[f][i];
        }
    }
    for f in g.n_internal..g.n_faces() {
        let o = g.owner[f] as usize;
        let pf = p_b[f - g.n_internal];
        for i in 0..3 {
            sum[o][i] += pf * g.sf[f][i];
        }
    }
    for (c, s) in sum.iter_mut().enumerate() {
        for x in s.iter_mut() {
            *x /= g.v[c];
        }
    }
    sum
}

/// Linear interpolation of a cell field to the faces, boundary faces taking the owner's value.
fn interpolate_cells(g: &FvGeometry, cells: &[V3]) -> Vec<V3> {
    let b: Vec<V3> = g.owner[g.n_internal..]
        .iter()
        .map(|&o| cells[o as usize])
        .collect();
    fvc::interpolate(g, Field::new(cells, &b))
}
