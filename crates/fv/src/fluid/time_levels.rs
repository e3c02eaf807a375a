//! The first and last stages of a PISO step: the time levels the step starts from with its
//! time scheme's coefficients (OpenFOAM v1912's `EulerDdtScheme`, `backwardDdtScheme` and
//! `CrankNicolsonDdtScheme` with the fields' `oldTime()` levels, [`crate::ddt`]), and the
//! bookkeeping that ends the step (the clock, the level kept for the next step).

use super::{grad_memo, Fluid, OldLevel};
use crate::ddt::DdtCoeffs;
use crate::fvc::{self, Field};
use crate::gather;
use crate::geometry::V3;
use crate::settings::TimeScheme;

/// The levels one step starts from and its time scheme's coefficients, fixed through the step.
pub(super) struct Levels {
    /// The step (s).
    pub(super) dt: f64,
    /// The time the step reaches (s).
    pub(super) t_new: f64,
    /// U° at cells (m/s).
    pub(super) u_old: Vec<V3>,
    /// U° at boundary faces (m/s).
    pub(super) u_b_old: Vec<V3>,
    /// φ° (m³/s).
    pub(super) phi_old: Vec<f64>,
    /// ε at faces ([`Fluid::eps_faces`]).
    pub(super) ef: Vec<f64>,
    /// ε° at faces.
    pub(super) ef_old: Vec<f64>,
    /// The scheme is `backward`.
    pub(super) backward: bool,
    /// `backward`'s coefficients c, c₀, c₀₀ (Euler's for the other schemes).
    pub(super) ddt_k: DdtCoeffs,
    /// `backward`'s old-old level (empty for the other schemes).
    pub(super) old_old: OldLevel,
    /// ε°° at faces (`backward` only).
    pub(super) ef_oo: Vec<f64>,
    /// U°_f·S (m³/s).
    pub(super) q_old: Vec<f64>,
    /// ddtCorr's face difference D° = φ° − ε°_f U°_f·S (m³/s).
    pub(super) d_old: Vec<f64>,
    /// `CrankNicolson ψ`: r = c/Δt (1/s; 0 for the other schemes).
    pub(super) cn_r: f64,
    /// `CrankNicolson ψ`: the old-time source r ε°U° + ψ d₀ per cell (m/s²; empty for the
    /// other schemes).
    pub(super) cn_src: Vec<V3>,
}

impl Fluid {
    /// Stage 1 of a step of `dt`: keeps the old level U°, U°_b, φ°, evaluates the velocity
    /// boundary conditions at the new time, forms ε and ε° at faces, `backward`'s
    /// coefficients and old-old level (on the first step: the old level, with c₀₀ ≈ 0, as
    /// OpenFOAM's `U.oldTime().oldTime()` is then the old field), ddtCorr's old face
    /// quantities, and begins the step of each `CrankNicolson ψ` derivative.
    pub(super) fn old_time_levels(&mut self, dt: f64) -> Levels {
        let t_new = self.time + dt;
        let u_old = self.u.clone();
        let u_b_old = self.u_b.clone();
        let phi_old = self.phi.clone();
        self.update_u_boundary(t_new);
        // ε_f and ε°_f from the kept faces when ε or ε° holds the kept cells' bits (the same
        // values as interpolating again).
        let kept = self.eps_faces_kept.take();
        let kept_for = |eps: &[f64]| {
            kept.as_ref()
                .filter(|(cells, _)| grad_memo::same_values(cells, eps))
                .map(|(_, faces)| faces.clone())
        };
        let ef = kept_for(&self.eps).unwrap_or_else(|| self.eps_faces(&self.eps));
        let ef_old = if grad_memo::same_values(&self.eps_old, &self.eps) {
            ef.clone()
        } else {
            kept_for(&self.eps_old).unwrap_or_else(|| self.eps_faces(&self.eps_old))
        };
        self.eps_faces_kept = Some((self.eps.clone(), ef.clone()));
        // backward's coefficients and old-old level (on the first step: the old level, with
        // c₀₀ ≈ 0, as OpenFOAM's U.oldTime().oldTime() is then the old field)
        let backward = self.settings.time_scheme == TimeScheme::Backward;
        let ddt_k = match &self.old_old {
            _ if !backward => DdtCoeffs::EULER,
            Some((_, dt0)) => DdtCoeffs::backward(dt, *dt0, false),
            None => DdtCoeffs::backward(dt, dt, true),
        };
        let old_old = match self.old_old.take() {
            Some((level, _)) if backward => level,
            _ if backward => OldLevel {
                u: u_old.clone(),
                u_b: u_b_old.clone(),
                phi: phi_old.clone(),
                eps: self.eps_old.clone(),
            },
            _ => OldLevel::default(),
        };
        let ef_oo = if backward {
            self.eps_faces(&old_old.eps)
        } else {
            Vec::new()
        };

        let g = &self.g;
        let uf_old = fvc::interpolate(g, Field::new(&u_old, &u_b_old));
        // U°_f·S and ddtCorr's face difference D° = φ° − ε°_f U°_f·S (m³/s)
        // (each face on its own: in parallel on large meshes, the same bits)
        let q_old: Vec<f64> = gather::cells(g.n_faces(), |f| uf_old[f].dot(&g.sf[f]));
        let d_old: Vec<f64> = gather::cells(g.n_faces(), |f| phi_old[f] - ef_old[f] * q_old[f]);
        let mut lv = Levels {
            dt,
            t_new,
            u_old,
            u_b_old,
            phi_old,
            ef,
            ef_old,
            backward,
            ddt_k,
            old_old,
            ef_oo,
            q_old,
            d_old,
            cn_r: 0.0,
            cn_src: Vec::new(),
        };
        // CrankNicolson ψ: each stored derivative begins the step once ([`CrankNicolsonDdt0`]);
        // `cn_r` = c/Δt (1/s), `cn_src` = c/Δt ε°U° + ψ d₀ per cell (m/s²).
        if let Some(s) = self.cn.as_mut() {
            (lv.cn_r, lv.cn_src) = s.begin_step(&self.g, &lv, &self.eps_old);
        }
        lv
    }

    /// The last stage of a step: the clock moves to `lv.t_new`, and the step's old level is
    /// kept as `backward`'s old-old level or `CrankNicolson ψ`'s `_0` files.
    pub(super) fn end_step(&mut self, lv: Levels) {
        self.time = lv.t_new;
        self.time_index += 1;
        // the old level of this step: backward's old-old level, CrankNicolson's `_0` files
        let level = || OldLevel {
            u: lv.u_old,
            u_b: lv.u_b_old,
            phi: lv.phi_old,
            eps: self.eps_old.clone(),
        };
        if lv.backward {
            self.old_old = Some((level(), lv.dt));
        } else if self.cn.is_some() {
            self.cn_prev = Some((level(), lv.dt));
        }
    }
}
