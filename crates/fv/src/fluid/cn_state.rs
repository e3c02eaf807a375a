//! `CrankNicolson ψ`'s state of the fluid ([`crate::ddt::CrankNicolsonDdt0`] per field, as
//! OpenFOAM v1912's `CrankNicolsonDdtScheme` keeps its `ddt0(…)` fields): its stored
//! derivatives, their start of each step, the ddtCorr bracket they give, and their reading
//! from a start directory and writing into time directories in OpenFOAM's files
//! ([`crate::cn_files`]).

use super::{Fluid, Levels, OldLevel};
use crate::bc;
use crate::cn_files::{self, missing_file, previous_step, read_cells, read_vol, write_vol};
use crate::ddt::CrankNicolsonDdt0;
use crate::error::{FvError, Result};
use crate::fvc::{self, Field};
use crate::geometry::{FvGeometry, V3};
use foam::FieldValues;
use std::path::Path;

/// The `CrankNicolson ψ` state of the fluid's fields ([`CrankNicolsonDdt0`]), each updated as
/// often per step as OpenFOAM v1912 updates its `ddt0(…)` field (once per call of the scheme).
#[derive(Clone, Debug)]
pub(super) struct CnState {
    /// Of εU per cell, then per boundary face (m/s²; OpenFOAM's `ddt0(voidfraction,U)`,
    /// `ddt0(U)` for ε ≡ 1; the matrix uses the cells', the file holds both).
    pub(super) momentum: CrankNicolsonDdt0<V3>,
    /// Of the face flux φ (m³/s²; ddtCorr's `ddtCorrDdt0(phi)`, updated once per corrector).
    pub(super) flux_phi: CrankNicolsonDdt0<f64>,
    /// Of ε_f U_f·S, the interpolated old velocity's flux weighted by the face voidage
    /// (m³/s²; for ε ≡ 1 ddtCorr's `ddtCorrDdt0(U)`, interpolated: the interpolation is
    /// linear, so the recursion on the face values is the interpolated recursion on the cells
    /// and boundary faces; updated once per corrector). Weighted so that both stored
    /// derivatives of the bracket ([`cn_flux_corr`]) are of the same quantity: ε°_f d₀(U_f·S)
    /// in its place left ψ U_f·S ∂ε_f/∂t in the bracket when ε changes in time, and the face
    /// flux of a drag relaxation with ε(t) then missed its closed form by ~3 % of Us at every
    /// Δt (tests/coupled_time.rs).
    pub(super) flux_u: CrankNicolsonDdt0<f64>,
    /// Of U per cell, then per boundary face (m/s²; OpenFOAM's `ddtCorrDdt0(U)`): the
    /// recursion OpenFOAM keeps, carried only to write it into time directories and read it
    /// back (pisoFoam and the native fluid restart from each other's files); the bracket
    /// uses `flux_u`, which equals its interpolated flux when ε is constant in time.
    pub(super) flux_u_file: CrankNicolsonDdt0<V3>,
    /// Of ε per cell, then per boundary face (1/s; `ddt0(voidfraction)`, the continuity equation's ∂ε/∂t; updated
    /// once per step: grainPisoFoam evaluates `fvc::ddt(voidfraction)` once per step too.
    /// Updating it on every pressure equation and continuity error, as v1912 does on every
    /// call, applied the recursion d₀ ← r₀(ε° − ε°°) − ψ d₀ m times per step: a lagging
    /// derivative, and with ψ = 1 and m even a d₀ that never changed, so ∂ε/∂t did not
    /// converge with Δt (tests/coupled_time.rs, the column).
    pub(super) voidage: CrankNicolsonDdt0<f64>,
    /// Of the face flux φ for the porous faces' own momentum balance (m³/s²;
    /// [`super::PorousTimeFlux::Consistent`]; updated once per step, as the cells' `momentum`).
    pub(super) porous_flux: CrankNicolsonDdt0<f64>,
}

impl CnState {
    /// The state before a run's first step.
    pub(super) fn new(psi: f64) -> CnState {
        CnState {
            momentum: CrankNicolsonDdt0::new(psi),
            flux_phi: CrankNicolsonDdt0::with_late_old_old(psi),
            flux_u: CrankNicolsonDdt0::new(psi),
            flux_u_file: CrankNicolsonDdt0::new(psi),
            voidage: CrankNicolsonDdt0::new(psi),
            porous_flux: CrankNicolsonDdt0::new(psi),
        }
    }

    /// Each stored derivative begins the step `lv.dt` from the old levels of `lv` and the
    /// old cell voidage `eps_old` ([`CrankNicolsonDdt0::begin_step`]): returns the rate
    /// r = c/Δt (1/s) and the momentum's old-time source r ε°U° + ψ d₀ per cell (m/s²).
    pub(super) fn begin_step(
        &mut self,
        g: &FvGeometry,
        lv: &Levels,
        eps_old: &[f64],
    ) -> (f64, Vec<V3>) {
        let (u_old, u_b_old, phi_old) = (&lv.u_old, &lv.u_b_old, &lv.phi_old);
        let (ef_old, q_old, dt) = (&lv.ef_old, &lv.q_old, lv.dt);
        let (mom_old, eps_old_ext) = cn_old_levels(g, u_old, u_b_old, ef_old, eps_old);
        let r = self.momentum.begin_step(&mom_old, dt);
        self.flux_phi.begin_step(phi_old, dt);
        let eq_old: Vec<f64> = (0..g.n_faces()).map(|f| ef_old[f] * q_old[f]).collect();
        self.flux_u.begin_step(&eq_old, dt);
        self.flux_u_file
            .begin_step(&[&u_old[..], &u_b_old[..]].concat(), dt);
        self.voidage.begin_step(&eps_old_ext, dt);
        self.porous_flux.begin_step(phi_old, dt);
        let src = (0..g.n_cells)
            .map(|c| self.momentum.old_part(c, r, mom_old[c]))
            .collect();
        (r, src)
    }
}

impl Fluid {
    /// Continues `CrankNicolson ψ` from the start directory `dir` when it holds the scheme's
    /// files ([`crate::cn_files`]): all of `ddt0(U)` (`ddt0(voidfraction,U)`),
    /// `ddtCorrDdt0(U)`, `ddtCorrDdt0(phi)` (and `ddt0(voidfraction)`) with the old levels
    /// `U_0`, `phi_0` (`voidfraction_0`). None of them: the scheme starts afresh, Euler on the
    /// first step, as OpenFOAM's does without the files. Some but not all, or a file that
    /// does not fit the mesh: an error naming it.
    pub(super) fn read_cn_state(&mut self, dir: &Path, mesh: &foam::PolyMesh) -> Result<()> {
        let Some(psi) = self.cn.as_ref().map(|s| s.momentum.psi()) else {
            return Ok(());
        };
        if !self.cn_files_present(dir)? {
            return Ok(());
        }
        let vans = self.is_vans();
        let g = &self.g;
        let need = |name: &str, v: Option<Vec<f64>>| v.ok_or_else(|| missing_file(dir, name));
        let vneed = |name: &str, v: Option<Vec<V3>>| v.ok_or_else(|| missing_file(dir, name));
        let mom_name = cn_files::momentum_name(vans);
        let d_mom = vneed(mom_name, read_vol::<V3>(dir, mom_name, mesh, g)?)?;
        let d_u = vneed(
            cn_files::CORR_U,
            read_vol::<V3>(dir, cn_files::CORR_U, mesh, g)?,
        )?;
        let d_phi = crate::fields::read_phi(&dir.join(cn_files::CORR_PHI), g)?;
        let u0 = read_cells::<V3>(dir, "U_0", g.n_cells)?;
        let phi0 = crate::fields::read_phi(&dir.join("phi_0"), g)?;
        let eps0 = match vans {
            true => read_cells::<f64>(dir, "voidfraction_0", g.n_cells)?,
            false => vec![1.0; g.n_cells],
        };
        let d_eps = match vans {
            true => Some(need(
                cn_files::VOIDAGE,
                read_vol::<f64>(dir, cn_files::VOIDAGE, mesh, g)?,
            )?),
            false => None,
        };
        let dt0 = previous_step(dir)?;
        // the old level's boundary values as the solver evaluated them then
        let t0 = self.time - dt0.unwrap_or(self.settings.delta_t);
        let mut u0_b = vec![V3::zeros(); g.n_boundary()];
        let eps0_b = self.eps_boundary(&eps0);
        bc::eval_velocity(g, &self.u_bc, t0, &u0, &eps0_b, &phi0, &mut u0_b);
        let ef0 = self.eps_faces(&eps0);
        let (mom0, eps0_ext) = cn_old_levels(&self.g, &u0, &u0_b, &ef0, &eps0);
        // the bracket's d₀(ε_f U_f·S): its native file, or (a directory of pisoFoam's) from
        // d₀(U) as ε°_f (d₀(U))_f·S, exact to round-off when ε is constant in time (linear
        // interpolation commutes with the recursion), otherwise without d₀(ε_f) U_f·S for the
        // first step after the restart
        let q_of = |cells: &[V3], bnd: &[V3]| -> Vec<f64> {
            let uf = fvc::interpolate(&self.g, Field::new(cells, bnd));
            (0..self.g.n_faces())
                .map(|f| uf[f].dot(&self.g.sf[f]))
                .collect()
        };
        let n = g.n_cells;
        let d_q = q_of(&d_u[..n], &d_u[n..]);
        let q0 = q_of(&u0, &u0_b);
        let d_eq: Vec<f64> = match dir.join(cn_files::CORR_EPS_U) {
            p if p.is_file() => crate::fields::read_phi(&p, g)?,
            _ => (0..g.n_faces()).map(|f| ef0[f] * d_q[f]).collect(),
        };
        let eq0: Vec<f64> = (0..g.n_faces()).map(|f| ef0[f] * q0[f]).collect();
        let s = self.cn.as_mut().expect("checked above");
        s.momentum = CrankNicolsonDdt0::restarted(psi, d_mom, mom0, dt0);
        s.flux_u = CrankNicolsonDdt0::restarted(psi, d_eq, eq0, dt0);
        s.flux_u_file =
            CrankNicolsonDdt0::restarted(psi, d_u, [u0.clone(), u0_b.clone()].concat(), dt0);
        // the porous faces' d₀(φ) (updated once per step): its native file, or (a directory of
        // pisoFoam's, which has no porous faces) ddtCorrDdt0(phi), the same flux's derivative
        // updated once per corrector
        let d_porous = match dir.join(cn_files::POROUS_PHI) {
            p if p.is_file() => crate::fields::read_phi(&p, g)?,
            _ => d_phi.clone(),
        };
        s.porous_flux = CrankNicolsonDdt0::restarted(psi, d_porous, phi0.clone(), dt0);
        s.flux_phi = CrankNicolsonDdt0::restarted(psi, d_phi, phi0.clone(), dt0);
        if let Some(d) = d_eps {
            s.voidage = CrankNicolsonDdt0::restarted(psi, d, eps0_ext, dt0);
        }
        self.cn_prev = Some((
            OldLevel {
                u: u0,
                u_b: u0_b,
                phi: phi0,
                eps: eps0,
            },
            dt0.unwrap_or(self.settings.delta_t),
        ));
        Ok(())
    }

    /// Whether the start directory `dir` holds `CrankNicolson ψ`'s files: none of them
    /// (`false`), all of them (`true`), or some but not all (an error naming them; see
    /// [`Self::read_cn_state`]).
    fn cn_files_present(&self, dir: &Path) -> Result<bool> {
        let vans = self.is_vans();
        let mut ddt0_names = vec![
            cn_files::momentum_name(vans),
            cn_files::CORR_U,
            cn_files::CORR_PHI,
        ];
        if vans {
            ddt0_names.push(cn_files::VOIDAGE);
        }
        let (present, missing): (Vec<&str>, Vec<&str>) =
            ddt0_names.iter().partition(|n| dir.join(n).is_file());
        if present.is_empty() {
            return Ok(false);
        }
        let mut old_names = vec!["U", "phi"];
        if vans {
            old_names.push("voidfraction");
        }
        let missing_old: Vec<String> = old_names
            .iter()
            .map(|f| cn_files::old_name(f))
            .filter(|n| !dir.join(n).is_file())
            .collect();
        if !missing.is_empty() || !missing_old.is_empty() {
            let all: Vec<String> = (missing.iter().map(|s| s.to_string()))
                .chain(missing_old)
                .collect();
            return Err(FvError::setting(
                dir.join(present[0]),
                "CrankNicolson",
                format!(
                    "the restart of CrankNicolson needs {} next to it in {}; remove the                      ddt0 files to restart the scheme with an Euler step",
                    all.join(", "),
                    dir.display()
                ),
            ));
        }
        Ok(true)
    }

    /// Writes `CrankNicolson ψ`'s files into the time directory `dir` ([`crate::cn_files`];
    /// nothing before the scheme's first step or for other schemes).
    pub(super) fn write_cn_state(&self, dir: &Path, fmt: foam::Format) -> Result<()> {
        let (Some(s), Some((prev, _))) = (&self.cn, &self.cn_prev) else {
            return Ok(());
        };
        let (Some(d_mom), Some(d_u), Some(d_phi), Some(d_eps)) = (
            s.momentum.ddt0(),
            s.flux_u_file.ddt0(),
            s.flux_phi.ddt0(),
            s.voidage.ddt0(),
        ) else {
            return Ok(());
        };
        let g = &self.g;
        let vans = self.is_vans();
        let accel = [0, 1, -2, 0, 0, 0, 0];
        write_vol(dir, cn_files::momentum_name(vans), accel, &d_mom, g, fmt)?;
        write_vol(dir, cn_files::CORR_U, accel, &d_u, g, fmt)?;
        for (name, d) in [
            (cn_files::CORR_PHI, Some(d_phi)),
            (cn_files::CORR_EPS_U, s.flux_u.ddt0()),
            (cn_files::POROUS_PHI, s.porous_flux.ddt0()),
        ] {
            if let Some(d) = d {
                let path = dir.join(name);
                crate::fields::write_surface_scalar(
                    &path,
                    name,
                    [0, 3, -2, 0, 0, 0, 0],
                    g,
                    &d,
                    fmt,
                )?;
            }
        }
        let mut u0 = self.u_file.clone();
        u0.header.object = "U_0".into();
        u0.set_internal(FieldValues::Vector(mesh::v3::to_arrays(&prev.u)))
            .map_err(|m| FvError::Value {
                what: "U_0".into(),
                msg: m,
            })?;
        u0.write(&dir.join("U_0"), fmt)?;
        crate::fields::write_surface_scalar(
            &dir.join("phi_0"),
            "phi_0",
            [0, 3, -1, 0, 0, 0, 0],
            g,
            &prev.phi,
            fmt,
        )?;
        if let (true, Some(file)) = (vans, &self.eps_file) {
            write_vol(
                dir,
                cn_files::VOIDAGE,
                [0, 0, -1, 0, 0, 0, 0],
                &d_eps,
                g,
                fmt,
            )?;
            let mut e0 = file.clone();
            e0.header.object = "voidfraction_0".into();
            e0.set_internal(FieldValues::Scalar(prev.eps.clone()))
                .map_err(|m| FvError::Value {
                    what: "voidfraction_0".into(),
                    msg: m,
                })?;
            e0.write(&dir.join("voidfraction_0"), fmt)?;
        }
        Ok(())
    }
}

/// `CrankNicolson ψ`'s old levels of εU and ε (cells, then boundary faces) from U° (cells
/// `u`, boundary faces `u_b`), ε° per face `ef` and per cell `eps`.
pub(super) fn cn_old_levels(
    g: &FvGeometry,
    u: &[V3],
    u_b: &[V3],
    ef: &[f64],
    eps: &[f64],
) -> (Vec<V3>, Vec<f64>) {
    let nb = g.n_boundary();
    let ef_b = &ef[g.n_internal..];
    let mom = (u.iter().zip(eps).map(|(&u, &e)| u * e))
        .chain((0..nb).map(|b| u_b[b] * ef_b[b]))
        .collect();
    let eps = eps.iter().chain(ef_b).copied().collect();
    (mom, eps)
}

/// `CrankNicolson ψ`'s ddtCorr bracket on face `f` (m³/s²):
/// (r φ° + ψ d₀(φ)) − (r ε°_f U°_f·S + ψ d₀(ε_f U_f·S)), r = c/Δt (OpenFOAM v1912
/// `CrankNicolsonDdtScheme::fvcDdtPhiCorr`, there with ε ≡ 1); `phi_old` φ°, `ef_old` ε°_f,
/// `q_old` U°_f·S.
pub(super) fn cn_flux_corr(
    s: &CnState,
    f: usize,
    r: f64,
    phi_old: f64,
    ef_old: f64,
    q_old: f64,
) -> f64 {
    s.flux_phi.old_part(f, r, phi_old) - s.flux_u.old_part(f, r, ef_old * q_old)
}
