//! The coefficients the PISO correctors of a step share (pisoFoam's `pEqn.H`, CFDEM's
//! cfdemSolverPiso `pEqn.H`, with [`Fluid::harmonic_faces`] and [`PorousTimeFlux`] the native
//! porous faces): the pressure equation's flux coefficient γ_f, OpenFOAM v1912's `ddtCorr`,
//! the porous faces' time terms, the cells whose velocity comes from the fluxes
//! ([`Fluid::reconstruct_u`]) and the continuity equation's ∂ε/∂t.

use super::cn_state::cn_flux_corr;
use super::{Fluid, Levels, MomentumEqn, PorousTimeFlux};
use crate::bc::{self, PressureBc};
use crate::fvc::{self, Field};
use crate::gather;
use crate::geometry::{FvGeometry, V3};

/// What the correctors of one step hold fixed (but ddtCorr, which `CrankNicolson ψ` renews
/// in each corrector).
pub(super) struct Correctors {
    /// Boundary faces whose flux the velocity condition fixes ([`bc::flux_fixed`]).
    pub(super) fixed_flux: Vec<bool>,
    /// A pressure condition fixes the level (else `pRefCell` does).
    pub(super) fixes_p: bool,
    /// κ = κ_p/A per cell (s; κ_p = ε for model A, 1 for B).
    pub(super) kappa: Vec<f64>,
    /// γ_c = ε_c κ_c: the cell's flux coefficient (φ = γ (H/κ − ∇p)·S).
    pub(super) gam_c: Vec<f64>,
    /// γ_f per face: the pressure Laplacian's coefficient.
    pub(super) gamma: Vec<f64>,
    /// γ_f on the boundary faces.
    pub(super) gamma_b: Vec<f64>,
    /// The faces next to porous cells ([`porous_faces`]) with [`Fluid::harmonic_faces`]:
    /// they take the series resistances; faces between two clear cells keep pisoFoam's
    /// linear forms (all false without `harmonic_faces`).
    pub(super) porous_face: Vec<bool>,
    /// ddtCorr per face (m³/s).
    pub(super) ddt_corr: Vec<f64>,
    /// `CrankNicolson ψ`: ddtCorr's factor (ε/A)_f × coupling coefficient per face.
    pub(super) cn_corr_w: Vec<f64>,
    /// The porous faces' time terms.
    pub(super) porous: PorousTime,
    /// The cells whose velocity comes from the fluxes ([`Fluid::reconstruct_u`]; empty
    /// without it).
    pub(super) jump_zone: Vec<bool>,
    /// ∂ε/∂t of the continuity equation (1/s), with the momentum's time scheme.
    pub(super) ddt_eps: Vec<f64>,
}

/// The time terms of the faces next to porous cells ([`PorousTimeFlux::Consistent`]; empty
/// vectors when it is not in use).
pub(super) struct PorousTime {
    /// [`PorousTimeFlux::Consistent`] with [`Fluid::harmonic_faces`].
    pub(super) consistent: bool,
    /// The time resistance r_t = 1/(κ_p Δt) per cell (s/m², kinematic; backward: T = c ε/Δt,
    /// CrankNicolson: T = c/Δt ε, grainPisoFoam's ddtUEqn.A()).
    pub(super) r_t: Vec<f64>,
    /// CrankNicolson's old-time source over κ_p (m/s² per κ_p), for H′.
    pub(super) cn_h: Vec<V3>,
    /// The steady flux coefficient γ′ = ε κ_p/A′ per cell.
    pub(super) gam_steady: Vec<f64>,
    /// The faces' old-time flux term φ_t (m³/s).
    pub(super) phi_t: Vec<f64>,
}

impl Fluid {
    /// Stage 4: the coefficients the correctors share, from the step's levels `lv` and the
    /// momentum equation's A (`eqn`).
    pub(super) fn corrector_coeffs(&self, lv: &Levels, eqn: &MomentumEqn) -> Correctors {
        let g = &self.g;
        let fixed_flux = bc::flux_fixed(g, &self.u_bc, &self.phi);
        let fixes_p = self.p_bc.iter().any(PressureBc::fixes_value);
        let porous_face = match self.harmonic_faces {
            true => porous_faces(g, &self.eps, &self.ksl),
            false => vec![false; g.n_faces()],
        };
        let (kappa, gam_c, gamma) = self.flux_coefficient(lv, &eqn.r_au, &porous_face);
        let gamma_b: Vec<f64> = gamma[g.n_internal..].to_vec();
        let (ddt_corr, cn_corr_w) = self.ddt_corr(lv, &eqn.r_au);
        let porous = self.porous_time(lv, &eqn.a_mean, &gam_c);
        let jump_zone = if self.reconstruct_u {
            jump_zone(&self.g, &gam_c, JUMP_RATIO, JUMP_LAYERS)
        } else {
            Vec::new()
        };
        let ddt_eps = self.voidage_rate(lv);
        Correctors {
            fixed_flux,
            fixes_p,
            kappa,
            gam_c,
            gamma,
            gamma_b,
            porous_face,
            ddt_corr,
            cn_corr_w,
            porous,
            jump_zone,
            ddt_eps,
        }
    }

    /// κ_p: ε for model A (−ε∇p), 1 for model B (−∇p).
    pub(super) fn kappa_p(&self, c: usize) -> f64 {
        match self.model {
            super::Model::A => self.eps[c],
            super::Model::B => 1.0,
        }
    }

    /// κ = κ_p/A and γ_c = ε κ per cell, and the flux coefficient γ_f per face: ε_f κ_f
    /// (cfdemSolverPiso's `rUAfvoidfraction` for model A), with [`Fluid::harmonic_faces`] the
    /// half-cell resistances in series on the faces next to porous cells (`porous_face`) and
    /// on boundary faces.
    fn flux_coefficient(
        &self,
        lv: &Levels,
        r_au: &[f64],
        porous_face: &[bool],
    ) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let g = &self.g;
        let n = g.n_cells;
        let ef = &lv.ef;
        // Each value on its own (gather::cells: in parallel on large meshes, the same bits).
        let kappa: Vec<f64> = gather::cells(n, |c| self.kappa_p(c) * r_au[c]);
        let kappa_b: Vec<f64> = g.owner[g.n_internal..]
            .iter()
            .map(|&o| kappa[o as usize])
            .collect();
        let kappa_f = fvc::interpolate(g, Field::new(&kappa, &kappa_b));
        // γ_c = ε_c κ_c: the cell's flux coefficient (φ = γ (H/κ − ∇p)·S).
        let gam_c: Vec<f64> = gather::cells(n, |c| self.eps[c] * kappa[c]);
        let gamma: Vec<f64> = gather::cells(g.n_faces(), |f| {
            if porous_face[f] && f < g.n_internal {
                // Two half-cell resistances in series: the owner's half is the fraction
                // 1 − w of the centre distance (w = d_fN/d_PN, OpenFOAM's weight).
                let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
                let w = g.weight[f];
                1.0 / ((1.0 - w) / gam_c[o] + w / gam_c[nb_])
            } else if self.harmonic_faces && f >= g.n_internal {
                // A boundary face closes the owner's half cell: its coefficient is the
                // cell's, whatever ε the boundary condition holds (a bed on an inlet).
                gam_c[g.owner[f] as usize]
            } else {
                ef[f] * kappa_f[f]
            }
        });
        (kappa, gam_c, gamma)
    }

    /// ddtCorr (OpenFOAM v1912 `ddtCorr` with ddtPhiCoeff −1, its `fvcDdtPhiCorr` of the
    /// step's scheme, times (ε/A)_f) per face, and for `CrankNicolson ψ` its factor (ε/A)_f ×
    /// coupling coefficient per face, for the later correctors.
    fn ddt_corr(&self, lv: &Levels, r_au: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let g = &self.g;
        let n = g.n_cells;
        let (dt, ddt_k, old_old) = (lv.dt, lv.ddt_k, &lv.old_old);
        let (phi_old, d_old) = (&lv.phi_old, &lv.d_old);
        let uf_oo = if lv.backward {
            fvc::interpolate(g, Field::new(&old_old.u, &old_old.u_b))
        } else {
            Vec::new()
        };
        let erau: Vec<f64> = gather::cells(n, |c| self.eps[c] * r_au[c]);
        let erau_b: Vec<f64> = g.owner[g.n_internal..]
            .iter()
            .map(|&o| erau[o as usize])
            .collect();
        let erau_f = fvc::interpolate(g, Field::new(&erau, &erau_b));
        // ddtCorr (OpenFOAM v1912 `ddtCorr` with ddtPhiCoeff −1): on internal faces and on the
        // boundary faces of patches whose velocity condition does not fix the value
        // (zeroGradient, inletOutlet, slip; zero on `empty` faces).
        let corr_face: Vec<bool> = {
            let mut v = vec![true; g.n_faces()];
            for (patch, bc) in g.patches.iter().zip(&self.u_bc) {
                if bc.fixes_value() || patch.is_empty() {
                    v[patch.faces.clone()].iter_mut().for_each(|x| *x = false);
                }
            }
            v
        };
        let cn = self.cn.as_ref();
        let ddt_corr: Vec<f64> = gather::cells(g.n_faces(), |f| {
            if !corr_face[f] {
                return 0.0;
            }
            let diff = d_old[f];
            let coeff = 1.0 - (diff.abs() / (phi_old[f].abs() + 1e-15)).min(1.0);
            if lv.backward {
                // backward's fvcDdtPhiCorr: the coefficient from the old level alone
                let diff_oo = old_old.phi[f] - lv.ef_oo[f] * uf_oo[f].dot(&g.sf[f]);
                let diff = ddt_k.c0 * diff - ddt_k.c00 * diff_oo;
                return erau_f[f] * coeff * diff / dt;
            }
            if let Some(s) = cn {
                // CrankNicolson's fvcDdtPhiCorr: (c/Δt φ° + ψ d₀(φ)) − (c/Δt ε°_f U°_f·S
                // + ψ d₀(ε_f U_f·S)) in place of D°/Δt
                return erau_f[f]
                    * coeff
                    * cn_flux_corr(s, f, lv.cn_r, phi_old[f], lv.ef_old[f], lv.q_old[f]);
            }
            erau_f[f] * coeff * diff / dt
        });
        // CrankNicolson: ddtCorr's factor (ε/A)_f × coupling coefficient per face, for the
        // later correctors, where v1912 updates ddtCorr's ddt0 again (CrankNicolsonDdt0)
        let cn_corr_w: Vec<f64> = match cn.is_some() {
            true => (0..g.n_faces())
                .map(|f| {
                    if !corr_face[f] {
                        return 0.0;
                    }
                    let diff = d_old[f];
                    let coeff = 1.0 - (diff.abs() / (phi_old[f].abs() + 1e-15)).min(1.0);
                    erau_f[f] * coeff
                })
                .collect(),
            false => Vec::new(),
        };
        (ddt_corr, cn_corr_w)
    }

    /// The porous faces' time terms of [`PorousTimeFlux::Consistent`] (grainPisoFoam's
    /// `porousFaces`), from the step's levels `lv`, A (`a_mean`) and γ_c (`gam_c`).
    fn porous_time(&self, lv: &Levels, a_mean: &[f64], gam_c: &[f64]) -> PorousTime {
        let g = &self.g;
        let n = g.n_cells;
        let (dt, ddt_k, cn_r) = (lv.dt, lv.ddt_k, lv.cn_r);
        let cn = self.cn.as_ref();
        // Faces next to porous cells (Correctors::porous_face) take the consistent time term
        // (PorousTimeFlux): their time resistance r_t = 1/(κ_p Δt) per cell (s/m², kinematic).
        let consistent = self.harmonic_faces && self.porous_time_flux == PorousTimeFlux::Consistent;
        // (backward: T = c ε/Δt, CrankNicolson: T = c/Δt ε, grainPisoFoam's ddtUEqn.A())
        let r_t: Vec<f64> = (0..n)
            .map(|c| match cn {
                Some(_) => cn_r / self.kappa_p(c),
                None => ddt_k.c / (self.kappa_p(c) * dt),
            })
            .collect();
        // CrankNicolson's old-time source over κ_p (m/s² per κ_p), for H′ below
        let cn_h: Vec<V3> = match cn.is_some() && consistent {
            true => (0..n).map(|c| lv.cn_src[c] / self.kappa_p(c)).collect(),
            false => Vec::new(),
        };
        // The steady flux coefficient γ′ = ε κ_p/A′ (A′ = A − ε/Δt, the diagonal without the
        // time derivative) weighs the face pressures of ∇p on porous faces, so that the cell
        // velocities U = HbyA − κ∇p, and through H′ the face fluxes, reach a steady state that
        // does not depend on Δt (PorousTimeFlux::Consistent). A cell whose A′ is not positive
        // (possible only without Ksl) keeps γ.
        let gam_steady: Vec<f64> = if consistent {
            (0..n)
                .map(|c| {
                    let a_steady = match cn {
                        Some(_) => a_mean[c] - cn_r * self.eps[c],
                        None => a_mean[c] - ddt_k.c * self.eps[c] / dt,
                    };
                    if a_steady > 0.0 {
                        self.eps[c] * self.kappa_p(c) / a_steady
                    } else {
                        gam_c[c]
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let phi_t = self.porous_old_flux(lv, consistent);
        PorousTime {
            consistent,
            r_t,
            cn_h,
            gam_steady,
            phi_t,
        }
    }

    /// The porous faces' old-time flux term φ_t (empty unless `consistent`).
    fn porous_old_flux(&self, lv: &Levels, consistent: bool) -> Vec<f64> {
        let g = &self.g;
        let (ddt_k, cn_r, phi_old, old_old) = (lv.ddt_k, lv.cn_r, &lv.phi_old, &lv.old_old);
        // The porous faces' old-time flux term φ_t: with it the face's time derivative is the
        // cells' scheme applied to the face flux, r_t (φ − φ_t) = (c/Δt)(φ − φ_t)/κ_p:
        // Euler φ_t = φ°; backward φ_t = (c₀ φ° − c₀₀ φ°°)/c; CrankNicolson ψ
        // φ_t = φ° + ψ d₀(φ)/r, r = c/Δt, d₀(φ) the face flux's stored derivative (the cells'
        // old-time source r ε°U° + ψ d₀(εU), written for the face). φ° alone there would make
        // the face derivative (1 + ψ)(φ − φ°)/Δt resp. c (φ − φ°)/Δt, an inertia (1 + ψ) resp.
        // 1.5 times the cells' whatever Δt (tests/coupled_time.rs).
        match (consistent, self.cn.as_ref(), lv.backward) {
            (false, _, _) => Vec::new(),
            (true, Some(s), _) => (0..g.n_faces())
                .map(|f| s.porous_flux.old_part(f, cn_r, phi_old[f]) / cn_r)
                .collect(),
            (true, None, true) => (0..g.n_faces())
                .map(|f| (ddt_k.c0 * phi_old[f] - ddt_k.c00 * old_old.phi[f]) / ddt_k.c)
                .collect(),
            (true, None, false) => phi_old.clone(),
        }
    }

    /// ∂ε/∂t of the continuity equation (1/s) with the momentum's time scheme
    /// (grainPisoFoam's and CFDEM's `fvc::ddt(voidfraction)`).
    fn voidage_rate(&self, lv: &Levels) -> Vec<f64> {
        let (dt, ddt_k, old_old) = (lv.dt, lv.ddt_k, &lv.old_old);
        // ∂ε/∂t of the continuity equation (1/s), with the momentum's time scheme
        (0..self.g.n_cells)
            .map(|c| match (lv.backward, self.cn.as_ref()) {
                (true, _) => {
                    (ddt_k.c * self.eps[c] - ddt_k.c0 * self.eps_old[c]
                        + ddt_k.c00 * old_old.eps[c])
                        / dt
                }
                // CrankNicolson's fvcDdt: c/Δt (ε − ε°) − ψ d₀
                (false, Some(s)) => s.voidage.explicit(c, lv.cn_r, self.eps[c], self.eps_old[c]),
                (false, None) => (self.eps[c] - self.eps_old[c]) / dt,
            })
            .collect()
    }

    /// `CrankNicolson ψ` in a corrector after the first: ddtCorr's stored derivatives are
    /// evaluated again (v1912 updates them on each call of `fvcDdtPhiCorr`) and ddtCorr renewed
    /// with them.
    pub(super) fn renew_cn_ddt_corr(&mut self, lv: &Levels, cs: &mut Correctors) {
        let Some(s) = self.cn.as_mut() else {
            return;
        };
        s.flux_phi.evaluate_again();
        s.flux_u.evaluate_again();
        s.flux_u_file.evaluate_again();
        let s = &*s;
        cs.ddt_corr = (0..self.g.n_faces())
            .map(|f| {
                cs.cn_corr_w[f]
                    * cn_flux_corr(s, f, lv.cn_r, lv.phi_old[f], lv.ef_old[f], lv.q_old[f])
            })
            .collect();
    }
}

/// Faces next to a porous cell (ε < 1 or Ksl > 0): internal faces with such a cell on either
/// side, boundary faces of such an owner (grainPisoFoam's `porousFaces` mask).
fn porous_faces(g: &FvGeometry, eps: &[f64], ksl: &[f64]) -> Vec<bool> {
    let porous = |c: u32| eps[c as usize] < 1.0 || ksl[c as usize] > 0.0;
    (0..g.n_faces())
        .map(|f| porous(g.owner[f]) || (f < g.n_internal && porous(g.neighbour[f])))
        .collect()
}

/// Ratio of neighbouring cells' flux coefficients γ = εκ that counts as a jump for
/// [`Fluid::reconstruct_u`].
const JUMP_RATIO: f64 = 10.0;
/// Cell layers on each side of a jump whose velocity [`Fluid::reconstruct_u`] takes from the
/// fluxes.
const JUMP_LAYERS: usize = 3;

/// Marks the cells within `layers` cell layers (face neighbours) of an internal face across
/// which γ changes by more than `ratio`.
fn jump_zone(g: &FvGeometry, gamma: &[f64], ratio: f64, layers: usize) -> Vec<bool> {
    let mut zone = vec![false; g.n_cells];
    for f in 0..g.n_internal {
        let (o, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
        if gamma[o] > ratio * gamma[n] || gamma[n] > ratio * gamma[o] {
            zone[o] = true;
            zone[n] = true;
        }
    }
    for _ in 1..layers {
        let mut next = zone.clone();
        for f in 0..g.n_internal {
            let (o, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
            if zone[o] || zone[n] {
                next[o] = true;
                next[n] = true;
            }
        }
        zone = next;
    }
    zone
}
