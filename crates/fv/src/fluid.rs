//! The volume-averaged incompressible PISO solver (seed 001 eq. 1–2, seed 002 eq. 3–4,
//! ADR 0004), kinematic pressure p (m²/s²), interstitial velocity U (m/s), voidage ε:
//!
//! * momentum, model A: ∂(εU)/∂t + ∇·(φU) − ∇·(εν∇U) = −ε∇p − (Ksl/ρ)(U − Us) + f/ρ
//!   (model B: −∇p instead of −ε∇p), Ksl implicit, f explicit;
//! * continuity: ∂ε/∂t + ∇·φ = 0 with the face flux φ = (εU)_f·S (the ∂ε/∂t term switchable).
//!
//! One step (Issa's PISO as OpenFOAM's icoFoam/pisoFoam and CFDEM's cfdemSolverPiso arrange
//! it): assemble the momentum matrix with the old-time pressure gradient, optionally solve it
//! (predictor), then `nCorrectors` times: A = mean diagonal, HbyA = H/A, face flux
//! φ* = ε_f (HbyA)_f·S + ddtCorr (the Rhie–Chow-type coupling term of OpenFOAM's `ddtCorr`),
//! solve ∇·(γ∇p) = ∇·φ* + ∂ε/∂t with γ_f = ε_f (ε/A)_f (model A) or ε_f (1/A)_f (model B)
//! (compact Laplacian stencil: the flux φ = φ* − γ_f|S| snGrad p is the Rhie–Chow flux), with
//! `nNonOrthogonalCorrectors` explicit non-orthogonal corrections, and correct
//! U = HbyA − (ε/A)∇p (model B: (1/A)∇p).

// Face and cell loops index several arrays at once, as the equations do.
#![allow(clippy::needless_range_loop)]

use crate::bc::{self, PressureBc, VelocityBc};
use crate::ddt::{CrankNicolsonDdt0, DdtCoeffs};
use crate::error::{FvError, Result};
use crate::fv_options::MeanForce;
use crate::fvc::{self, Field};
use crate::geometry::{FvGeometry, V3};
use crate::ldu::Ldu;
use crate::linsolve::{self, SolveStats};
use crate::settings::{Settings, SnGrad, TimeScheme};
use crate::turbulence::{k_epsilon, KEpsilon, TurbulenceSettings};
use foam::{Case, FieldValues, VolField};
use rayon::prelude::*;
use std::path::Path;

/// How the pressure gradient enters the momentum equation (seed 002 eq. 3–4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// −ε∇p (pressure shared by fluid and particles).
    A,
    /// −∇p (pressure in the fluid phase only).
    B,
}

/// How the face flux next to porous cells carries the time derivative, with
/// [`Fluid::harmonic_faces`] (clear faces always keep OpenFOAM's `ddtCorr`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PorousTimeFlux {
    /// The face's own momentum balance (default): the half-cell resistances in series,
    /// r_c = 1/γ_c = A_c/(ε_c κ_p,c) (s/m² per m of flow path, kinematic units), split into a
    /// steady part r′ = A′/(ε κ_p) (A′ the diagonal without the time derivative: convection,
    /// diffusion, Ksl/ρ) and the time part r_t = T/(ε κ_p) = 1/(κ_p Δt) (T = ε/Δt the Euler
    /// ddt diagonal per volume, 1/s); on the face
    ///
    ///   φ* = γ_f ((H′/κ_p)_f·S + r_t,f φ°),   1/γ_f = r_f = (1 − w) r_P + w r_N,
    ///   r_t,f = (1 − w) r_t,P + w r_t,N,
    ///
    /// H′ = H − ε° U°/Δt the momentum source without the old-time term (m/s² per volume),
    /// φ° the face's own old flux (m³/s). That is Euler's form; the other schemes replace φ°
    /// by their old-time flux term φ_t, the face analogue of the cells' old-time source
    /// (backward (c₀φ° − c₀₀φ°°)/c, CrankNicolson ψ φ° + ψ d₀(φ)/r; see `Fluid::advance`), so
    /// that the face flux follows the cells' time scheme (tests/coupled_time.rs). At steady state (φ = φ°) the face flux solves
    /// r′_f φ = (H′/κ_p)_f·S − |S| snGrad p whatever Δt: the time term cancels exactly, as in
    /// the time-step-independent momentum interpolation of Choi (AIAA J. 37 (1999) 1004) and
    /// Yu, Ozoe & Churchill (Numer. Heat Transfer B 42 (2002) 141), here written for the
    /// series resistances of [`Fluid::harmonic_faces`]. Transiently the face flux relaxes as
    /// the cells' velocities do (the same r′ and r_t, interpolated). The face pressures of the
    /// cell gradient on these faces are weighted by the steady γ′ = ε κ_p/A′ (not γ), so the
    /// cell velocities, which feed H′ through the neighbours' coefficients, are Δt-free too.
    /// Faces between clear cells keep OpenFOAM's forms (pisoFoam's results where ε ≡ 1 and
    /// Ksl ≡ 0). Measured on a heterogeneous frozen bed: steady Δp spread 6.4e-5 across
    /// Δt = 1e-4 … 1e-3 s, against 6.2 % with [`Self::DdtCorr`] (`tests/steady_dt.rs`); the
    /// rest comes from the clear faces' ddtCorr.
    #[default]
    Consistent,
    /// OpenFOAM v1912's `ddtCorr` on every face (the behaviour before issue 17): the old cell
    /// velocities interpolated, corrected by (ε/A)_f·c·(φ° − ε°_f U°_f·S)/Δt with the coupling
    /// coefficient c = 1 − min(|φ° − ε°_f U°_f·S|/|φ°|, 1). At steady state the flux keeps a
    /// term of order Δt·Ksl-jumps: measured +1.5 / +2.7 / +3.3 % of Δp at Δt = 1e-4 / 2.5e-4 /
    /// 5e-4 s on the binary bed (docs/cellsize.md). Kept for comparisons.
    DdtCorr,
}

/// What one time step did.
#[derive(Clone, Debug, PartialEq)]
pub struct StepReport {
    /// The time reached (s).
    pub time: f64,
    /// Momentum solves, one per component (empty without predictor).
    pub momentum: Vec<SolveStats>,
    /// Pressure solves, in order.
    pub pressure: Vec<SolveStats>,
    /// Σ|∇·φ + ∂ε/∂t| V-weighted continuity error after the last corrector (m³/s), relative to
    /// Σ|φ| over the faces.
    pub continuity: f64,
    /// The turbulence model's solves after the correctors (ε, then k; empty when laminar).
    pub turbulence: Vec<SolveStats>,
}

/// The native fluid solver on one case.
pub struct Fluid {
    /// The case settings.
    pub settings: Settings,
    /// Pressure-gradient form.
    pub model: Model,
    /// Include ∂ε/∂t in the pressure equation.
    pub ddt_voidage: bool,
    /// Resistance-consistent faces for porous jumps (default false: OpenFOAM's linear form).
    /// When true, the face flux coefficient is the harmonic mean of the cells' γ = εκ
    /// (κ = κ_p/A, κ_p = ε for model A, 1 for B): the half-cell resistances in series,
    /// 1/γ_f = (1−w)/γ_P + w/γ_N (w = d_fN/d_PN, the linear weight of the owner); the predicted
    /// flux is γ_f (HbyA/κ)_f·S, and the face pressure of the cell gradient that corrects U is
    /// the flux-continuous one, p_f = (w γ_P p_P + (1−w) γ_N p_N)/(w γ_P + (1−w) γ_N). On a
    /// boundary face the owner's half cell alone: γ_b = γ_P and φ*_b = ε_P HbyA_P·S, whatever
    /// ε the boundary condition holds (so a fixedFluxPressure inlet under a bed keeps the
    /// bed's half cell). All reduce to the linear forms where κ and ε are uniform; where Ksl
    /// jumps by orders of magnitude (the surface of a packed bed, a bed on an inlet) they keep
    /// the resistances in series, so the pressure drop of a bed of N cells is that of N cells,
    /// not N − 1 (Patankar, Numerical Heat Transfer and Fluid Flow, 1980, §4.2-3).
    pub harmonic_faces: bool,
    /// Cell velocities from the face fluxes near jumps of the flux coefficient (default false:
    /// OpenFOAM's U = HbyA − κ∇p everywhere). Where γ = εκ changes by more than 10× across a
    /// face (the surface of a packed bed, where Ksl jumps by orders of magnitude) the free cell
    /// next to it sees a pressure gradient spoilt by the bed's, and U = HbyA − κ∇p overshoots
    /// (measured 2.6× the plug-flow velocity next to the face, decaying in an odd–even pattern
    /// over a few cells) although the fluxes are right. With this option the cells within 3
    /// layers of such a face take U_c = R_c/ε_c, R = [`fvc::reconstruct`] of the fluxes φ
    /// (measured: plug flow to 2e-4); elsewhere nothing changes (the cavity gives the same
    /// bits). Not used everywhere because the reconstruction alone loses what the fluxes do
    /// not carry (the tangential velocity at walls: 18 % of the lid speed on the 20×20 cavity).
    pub reconstruct_u: bool,
    /// The time term of the face flux on faces next to porous cells (ε < 1 or Ksl > 0) when
    /// [`Self::harmonic_faces`] is on; see [`PorousTimeFlux`]. Without `harmonic_faces` every
    /// face keeps OpenFOAM's linear forms and `ddtCorr`.
    pub porous_time_flux: PorousTimeFlux,
    case: Case,
    g: FvGeometry,
    u_bc: Vec<VelocityBc>,
    p_bc: Vec<PressureBc>,
    u_file: VolField,
    p_file: VolField,
    eps_file: Option<VolField>,
    time: f64,
    time_index: usize,
    u: Vec<V3>,
    u_b: Vec<V3>,
    p: Vec<f64>,
    p_b: Vec<f64>,
    phi: Vec<f64>,
    grad_p: Vec<V3>,
    eps: Vec<f64>,
    eps_old: Vec<f64>,
    ksl: Vec<f64>,
    us: Vec<V3>,
    force: Vec<V3>,
    /// Prescribed boundary voidage per patch (`None`: the owner's ε), from `voidfraction`.
    eps_bc: Vec<Option<Vec<f64>>>,
    /// Laplacian delta coefficient per face for the chosen snGrad scheme.
    lap_dc: Vec<f64>,
    /// The k–ε model when `turbulenceProperties` selects it.
    turbulence: Option<KEpsilon>,
    /// The `fvOptions` mean-velocity sources ([`crate::fv_options`]).
    mean_forces: Vec<MeanForce>,
    /// The level before the current one and the step that led from it (`backward` only;
    /// `None` before the run's first step).
    old_old: Option<(OldLevel, f64)>,
    /// `CrankNicolson ψ`'s stored derivatives (`None` for the other schemes).
    cn: Option<CnState>,
    /// `CrankNicolson ψ`: the old level of the last step and that step (s), written with the
    /// derivatives as OpenFOAM's `U_0`, `phi_0`, `voidfraction_0` ([`crate::cn_files`]).
    cn_prev: Option<(OldLevel, f64)>,
}

/// The `CrankNicolson ψ` state of the fluid's fields ([`CrankNicolsonDdt0`]), each updated as
/// often per step as OpenFOAM v1912 updates its `ddt0(…)` field (once per call of the scheme).
#[derive(Clone, Debug)]
struct CnState {
    /// Of εU per cell, then per boundary face (m/s²; OpenFOAM's `ddt0(voidfraction,U)`,
    /// `ddt0(U)` for ε ≡ 1; the matrix uses the cells', the file holds both).
    momentum: CrankNicolsonDdt0<V3>,
    /// Of the face flux φ (m³/s²; ddtCorr's `ddtCorrDdt0(phi)`, updated once per corrector).
    flux_phi: CrankNicolsonDdt0<f64>,
    /// Of ε_f U_f·S, the interpolated old velocity's flux weighted by the face voidage
    /// (m³/s²; for ε ≡ 1 ddtCorr's `ddtCorrDdt0(U)`, interpolated: the interpolation is
    /// linear, so the recursion on the face values is the interpolated recursion on the cells
    /// and boundary faces; updated once per corrector). Weighted so that both stored
    /// derivatives of the bracket ([`cn_flux_corr`]) are of the same quantity: ε°_f d₀(U_f·S)
    /// in its place left ψ U_f·S ∂ε_f/∂t in the bracket when ε changes in time, and the face
    /// flux of a drag relaxation with ε(t) then missed its closed form by ~3 % of Us at every
    /// Δt (tests/coupled_time.rs).
    flux_u: CrankNicolsonDdt0<f64>,
    /// Of U per cell, then per boundary face (m/s²; OpenFOAM's `ddtCorrDdt0(U)`): the
    /// recursion OpenFOAM keeps, carried only to write it into time directories and read it
    /// back (pisoFoam and the native fluid restart from each other's files); the bracket
    /// uses `flux_u`, which equals its interpolated flux when ε is constant in time.
    flux_u_file: CrankNicolsonDdt0<V3>,
    /// Of ε per cell, then per boundary face (1/s; `ddt0(voidfraction)`, the continuity equation's ∂ε/∂t; updated
    /// once per step: grainPisoFoam evaluates `fvc::ddt(voidfraction)` once per step too.
    /// Updating it on every pressure equation and continuity error, as v1912 does on every
    /// call, applied the recursion d₀ ← r₀(ε° − ε°°) − ψ d₀ m times per step: a lagging
    /// derivative, and with ψ = 1 and m even a d₀ that never changed, so ∂ε/∂t did not
    /// converge with Δt (tests/coupled_time.rs, the column).
    voidage: CrankNicolsonDdt0<f64>,
    /// Of the face flux φ for the porous faces' own momentum balance (m³/s²;
    /// [`PorousTimeFlux::Consistent`]; updated once per step, as the cells' `momentum`).
    porous_flux: CrankNicolsonDdt0<f64>,
}

impl CnState {
    /// The state before a run's first step.
    fn new(psi: f64) -> CnState {
        CnState {
            momentum: CrankNicolsonDdt0::new(psi),
            flux_phi: CrankNicolsonDdt0::with_late_old_old(psi),
            flux_u: CrankNicolsonDdt0::new(psi),
            flux_u_file: CrankNicolsonDdt0::new(psi),
            voidage: CrankNicolsonDdt0::new(psi),
            porous_flux: CrankNicolsonDdt0::new(psi),
        }
    }
}

/// The fields of one earlier time level (`backward`'s old-old level, [`crate::ddt`]).
#[derive(Clone, Debug, Default)]
struct OldLevel {
    /// Cell velocities (m/s).
    u: Vec<V3>,
    /// Boundary-face velocities (m/s).
    u_b: Vec<V3>,
    /// Face fluxes (m³/s).
    phi: Vec<f64>,
    /// Cell voidage.
    eps: Vec<f64>,
}

impl Fluid {
    /// Reads a case: mesh, `system/` and `constant/` settings, U and p of the start time
    /// (model A, ∂ε/∂t on, ε = 1, no exchange terms until set).
    pub fn from_case(dir: impl AsRef<Path>) -> Result<Fluid> {
        let case = Case::open(dir.as_ref())?;
        let settings = Settings::read(&case)?;
        let mesh = case.read_mesh()?;
        let g = FvGeometry::new(&mesh).map_err(|e| e.in_case(case.root()))?;
        let start = start_dir(&case, settings.start_time)?;
        let fields = crate::fields::read_fields(&start, &mesh, &g)?;
        let turbulence = match &settings.turbulence {
            TurbulenceSettings::KEpsilon(s) => Some(KEpsilon::read(
                &start,
                &mesh,
                &g,
                (**s).clone(),
                settings.nu,
            )?),
            _ => None,
        };
        let (pref_cell, _) = settings.p_ref;
        if pref_cell >= g.n_cells {
            return Err(FvError::setting(
                case.root().join("system/fvSolution"),
                "PISO.pRefCell",
                format!("cell {pref_cell} does not exist ({} cells)", g.n_cells),
            ));
        }
        let mean_forces = settings
            .fv_options
            .iter()
            .map(|s| MeanForce::new(s.clone(), g.n_cells, &start))
            .collect::<Result<Vec<_>>>()?;
        let mut fl = Self::build(case, settings, g, fields, turbulence)?;
        fl.mean_forces = mean_forces;
        fl.read_cn_state(&start, &mesh)?;
        Ok(fl)
    }

    /// Whether the case is a VANS one (it has a `voidfraction` field): the names of
    /// grainPisoFoam's CrankNicolson files ([`crate::cn_files`]).
    fn is_vans(&self) -> bool {
        self.eps_file.is_some()
    }

    /// Continues `CrankNicolson ψ` from the start directory `dir` when it holds the scheme's
    /// files ([`crate::cn_files`]): all of `ddt0(U)` (`ddt0(voidfraction,U)`),
    /// `ddtCorrDdt0(U)`, `ddtCorrDdt0(phi)` (and `ddt0(voidfraction)`) with the old levels
    /// `U_0`, `phi_0` (`voidfraction_0`). None of them: the scheme starts afresh, Euler on the
    /// first step, as OpenFOAM's does without the files. Some but not all, or a file that
    /// does not fit the mesh: an error naming it.
    fn read_cn_state(&mut self, dir: &Path, mesh: &foam::PolyMesh) -> Result<()> {
        use crate::cn_files::{self, read_vol};
        let Some(psi) = self.cn.as_ref().map(|s| s.momentum.psi()) else {
            return Ok(());
        };
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
            return Ok(());
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
        bc::eval_velocity(g, &self.u_bc, t0, &u0, &phi0, &mut u0_b);
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

    /// Writes `CrankNicolson ψ`'s files into the time directory `dir` ([`crate::cn_files`];
    /// nothing before the scheme's first step or for other schemes).
    fn write_cn_state(&self, dir: &Path, fmt: foam::Format) -> Result<()> {
        use crate::cn_files::{self, write_vol};
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

    fn build(
        case: Case,
        settings: Settings,
        g: FvGeometry,
        fields: crate::fields::CaseFields,
        turbulence: Option<KEpsilon>,
    ) -> Result<Fluid> {
        let n = g.n_cells;
        let nb = g.n_boundary();
        let lap_dc = match settings.sn_grad {
            SnGrad::Orthogonal => (0..g.n_faces())
                .map(|f| {
                    if f < g.n_internal {
                        1.0 / g.delta[f].norm()
                    } else {
                        g.delta_coeff[f]
                    }
                })
                .collect(),
            _ => g.delta_coeff.clone(),
        };
        let cn = match settings.time_scheme {
            TimeScheme::CrankNicolson(psi) => Some(CnState::new(psi)),
            _ => None,
        };
        let mut fl = Fluid {
            model: Model::A,
            ddt_voidage: true,
            harmonic_faces: false,
            reconstruct_u: false,
            porous_time_flux: PorousTimeFlux::Consistent,
            time: settings.start_time,
            time_index: 0,
            settings,
            case,
            u_b: vec![V3::zeros(); nb],
            p_b: vec![0.0; nb],
            phi: vec![0.0; g.n_faces()],
            grad_p: vec![V3::zeros(); n],
            eps: vec![1.0; n],
            eps_old: vec![1.0; n],
            ksl: vec![0.0; n],
            us: vec![V3::zeros(); n],
            force: vec![V3::zeros(); n],
            lap_dc,
            turbulence,
            mean_forces: Vec::new(),
            old_old: None,
            cn,
            cn_prev: None,
            g,
            u_bc: fields.u_bc,
            p_bc: fields.p_bc,
            eps_bc: fields.eps_bc,
            u_file: fields.u_file,
            p_file: fields.p_file,
            eps_file: fields.eps_file,
            u: fields.u,
            p: fields.p,
        };
        fl.update_u_boundary(fl.time);
        // The start time's `phi` when it has one (a restart), else the flux of U (OpenFOAM's
        // createPhi).
        fl.phi = match fields.phi {
            Some(phi) => phi,
            None => fl.flux_of_u(),
        };
        fl.update_u_boundary(fl.time);
        let gamma_b = vec![0.0; nb];
        let phi = fl.phi.clone();
        fl.update_p_boundary(fl.time, &gamma_b, &phi, &phi);
        // totalPressure patches start from the file's `value` (bc::read_total_pressure_values)
        for (patch, start) in fl.g.patches.iter().zip(&fields.p_b_start) {
            if let Some(v) = start {
                fl.p_b[patch.boundary_range(fl.g.n_internal)].copy_from_slice(v);
            }
        }
        // The gradient the last step used when the start time has it (a coupled run's
        // restart, fields::GRAD_P_FILE), else the Gauss gradient of p.
        fl.grad_p = match fields.grad_p {
            Some(g) => g,
            None => fvc::grad_scalar(&fl.g, &fl.p, &fl.p_b),
        };
        Ok(fl)
    }

    /// The finite-volume geometry.
    pub fn geometry(&self) -> &FvGeometry {
        &self.g
    }

    /// Current time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Moves the clock on by `dt` seconds without solving: U, p and φ stay as they are
    /// (CFDEM's `solveFlow off`, where the particles and the voidage go on over a fixed flow).
    ///
    /// The time schemes' history ends here: the stored derivatives of `CrankNicolson ψ` (of
    /// U, φ, ε, k, ε_turb) and `backward`'s old-old level describe the steps before the hold,
    /// not the held interval, so the next solved step starts the schemes afresh (Euler, as a
    /// run's first step, or a restart without `ddt0` files) instead of using them as the
    /// previous step's. grainPisoFoam and CFDEM's solvers, which skip the equations, keep
    /// them and continue the recursion with the derivative from before the hold.
    pub fn hold(&mut self, dt: f64) {
        self.time += dt;
        if let Some(s) = &mut self.cn {
            *s = CnState::new(s.momentum.psi());
        }
        self.cn_prev = None;
        self.old_old = None;
        if let Some(t) = &mut self.turbulence {
            t.restart_time_schemes();
        }
    }

    /// Number of steps taken.
    pub fn time_index(&self) -> usize {
        self.time_index
    }

    /// Cell velocities (m/s).
    pub fn u(&self) -> &[V3] {
        &self.u
    }

    /// Boundary-face velocities (m/s).
    pub fn u_boundary(&self) -> &[V3] {
        &self.u_b
    }

    /// Cell kinematic pressures (m²/s²).
    pub fn p(&self) -> &[f64] {
        &self.p
    }

    /// Boundary-face kinematic pressures (m²/s²).
    pub fn p_boundary(&self) -> &[f64] {
        &self.p_b
    }

    /// Face fluxes φ = (εU)_f·S (m³/s), one per face (0 on `empty` faces).
    pub fn phi(&self) -> &[f64] {
        &self.phi
    }

    /// ∇p at cells (m/s², Gauss linear, the gradient used in the last velocity correction).
    pub fn grad_p(&self) -> &[V3] {
        &self.grad_p
    }

    /// The effective viscosity νeff = ν + νt (m²/s) at cells and on boundary faces (ν alone
    /// without a turbulence model).
    pub fn nu_eff(&self) -> (Vec<f64>, Vec<f64>) {
        let nu = self.settings.nu;
        match &self.turbulence {
            Some(t) => (
                t.nut().iter().map(|&n| n + nu).collect(),
                t.nut_boundary().iter().map(|&n| n + nu).collect(),
            ),
            None => (vec![nu; self.g.n_cells], vec![nu; self.g.n_boundary()]),
        }
    }

    /// The `fvOptions` mean-velocity sources (their force G and last uncorrected mean).
    pub fn mean_forces(&self) -> &[MeanForce] {
        &self.mean_forces
    }

    /// The k–ε model's state, when the case selects it.
    pub fn turbulence(&self) -> Option<&KEpsilon> {
        self.turbulence.as_ref()
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

    /// ∇·τ at cells (m/s²) for the particles' viscous force: ∇·(ν(∇U + ∇Uᵀ)) of the current
    /// velocity ([`fvc::div_viscous_stress`]) with the molecular ν of `transportProperties`,
    /// also when a turbulence model is on. This is the stress CFDEM's `viscForce` applies
    /// (`forceSubModel::divTauField` takes `turbulence.nu()`, the laminar viscosity, not
    /// `nuEff`) and the one grainPisoFoam sends (`mpiCouplingSource.H`, `nu_`); the fluid's own
    /// momentum equation keeps ν + νt ([`Fluid::nu_eff`]).
    pub fn div_tau(&self) -> Vec<V3> {
        let nu = self.settings.nu;
        let (nu_c, nu_b) = (vec![nu; self.g.n_cells], vec![nu; self.g.n_boundary()]);
        fvc::div_viscous_stress(
            &self.g,
            Field::new(&nu_c, &nu_b),
            Field::new(&self.u, &self.u_b),
        )
    }

    fn check_cells<T>(&self, what: &str, v: &[T]) -> Result<()> {
        FvError::check_len(what, v.len(), self.g.n_cells)
    }

    /// Sets the voidage ε of the coming step (`current`) and of the previous one (`previous`,
    /// for ∂(εU)/∂t and ∂ε/∂t). Each value must be in (0, 1].
    pub fn set_voidage(&mut self, current: &[f64], previous: &[f64]) -> Result<()> {
        self.check_cells("voidage", current)?;
        self.check_cells("previous voidage", previous)?;
        for (what, v) in [("voidage", current), ("previous voidage", previous)] {
            if let Some(c) = v.iter().position(|&e| !(e > 0.0 && e <= 1.0)) {
                return Err(FvError::Value {
                    what: format!("{what} at cell {c}"),
                    msg: format!("{} is not in (0, 1]", v[c]),
                });
            }
        }
        self.eps.copy_from_slice(current);
        self.eps_old.copy_from_slice(previous);
        Ok(())
    }

    /// Sets the implicit exchange: Ksl (kg/(m³·s), ≥ 0) and Us (m/s) per cell (ADR 0004).
    pub fn set_exchange(&mut self, ksl: &[f64], us: &[V3]) -> Result<()> {
        self.check_cells("Ksl", ksl)?;
        self.check_cells("Us", us)?;
        if let Some(c) = ksl.iter().position(|&k| !(k >= 0.0 && k.is_finite())) {
            return Err(FvError::Value {
                what: format!("Ksl at cell {c}"),
                msg: format!("{} is not a finite non-negative number", ksl[c]),
            });
        }
        if let Some(c) = us.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
            return Err(FvError::Value {
                what: format!("Us at cell {c}"),
                msg: "not finite".into(),
            });
        }
        self.ksl.copy_from_slice(ksl);
        self.us.copy_from_slice(us);
        Ok(())
    }

    /// Sets the explicit force density f (N/m³) the particles exert on the fluid (ADR 0004).
    pub fn set_force(&mut self, f: &[V3]) -> Result<()> {
        self.check_cells("f", f)?;
        if let Some(c) = f.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
            return Err(FvError::Value {
                what: format!("f at cell {c}"),
                msg: "not finite".into(),
            });
        }
        self.force.copy_from_slice(f);
        Ok(())
    }

    /// ε at every face: linear interpolation inside; on boundary faces the `voidfraction`
    /// file's fixed value where it has one (CFDEM's inlets and outlets: 1), else the owner's.
    fn eps_faces(&self, eps: &[f64]) -> Vec<f64> {
        let g = &self.g;
        let mut b: Vec<f64> = g.owner[g.n_internal..]
            .iter()
            .map(|&o| eps[o as usize])
            .collect();
        for (patch, fixed) in g.patches.iter().zip(&self.eps_bc) {
            if let Some(v) = fixed {
                for (k, f) in patch.faces.clone().enumerate() {
                    b[f - g.n_internal] = v[k];
                }
            }
        }
        fvc::interpolate(g, Field::new(eps, &b))
    }

    /// φ = ε_f U_f·S with U_f linearly interpolated (boundary: U_b).
    fn flux_of_u(&self) -> Vec<f64> {
        let ef = self.eps_faces(&self.eps);
        let uf = fvc::interpolate(&self.g, Field::new(&self.u, &self.u_b));
        self.flux(&ef, &uf)
    }

    fn flux(&self, ef: &[f64], uf: &[V3]) -> Vec<f64> {
        (0..self.g.n_faces())
            .into_par_iter()
            .map(|f| {
                if f >= self.g.n_internal && self.g.boundary_empty[f - self.g.n_internal] {
                    0.0
                } else {
                    ef[f] * uf[f].dot(&self.g.sf[f])
                }
            })
            .collect()
    }

    fn update_u_boundary(&mut self, t: f64) {
        let mut ub = std::mem::take(&mut self.u_b);
        bc::eval_velocity(&self.g, &self.u_bc, t, &self.u, &self.phi, &mut ub);
        self.u_b = ub;
    }

    /// Boundary pressure values at time `t`; `gamma_b` the pressure-Laplacian coefficient and
    /// `phi_star` the unconstrained predicted flux on boundary faces, for fixedFluxPressure;
    /// `phi_in` the flux whose sign tells totalPressure faces in- from outflow (see
    /// [`Self::eval_p_boundary`]).
    fn update_p_boundary(&mut self, t: f64, gamma_b: &[f64], phi_star: &[f64], phi_in: &[f64]) {
        let mut pb = std::mem::take(&mut self.p_b);
        self.eval_p_boundary(t, &self.p, gamma_b, phi_star, phi_in, &mut pb);
        self.p_b = pb;
    }

    /// The boundary pressure values of the cell pressures `p` into `pb` (see
    /// [`Self::update_p_boundary`]). totalPressure faces take p0 − ½|U_b|² where `phi_in` < 0:
    /// inside a PISO corrector `phi_in` is the flux the corrector started from (the previous
    /// corrector's, or the previous step's on the first), as OpenFOAM v1912 evaluates the
    /// condition when it assembles the pressure equation, before `phi` is updated — with U_b
    /// of the previous corrector, the value stays fixed through the corrector's solves and
    /// the velocity correction that follows them.
    fn eval_p_boundary(
        &self,
        t: f64,
        p: &[f64],
        gamma_b: &[f64],
        phi_star: &[f64],
        phi_in: &[f64],
        pb: &mut [f64],
    ) {
        bc::eval_pressure(&self.g, &self.p_bc, t, p, &self.u_b, phi_in, pb);
        let g = &self.g;
        for (patch, bc) in g.patches.iter().zip(&self.p_bc) {
            if *bc != PressureBc::FixedFluxPressure {
                continue;
            }
            for f in patch.faces.clone() {
                let b = f - g.n_internal;
                let den = gamma_b[b] * g.mag_sf[f] * self.lap_dc[f];
                if den > 0.0 {
                    pb[b] += (phi_star[f] - self.phi[f]) / den;
                }
            }
        }
    }

    /// Advances by `dt` seconds (one PISO step).
    pub fn advance(&mut self, dt: f64) -> Result<StepReport> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(FvError::Value {
                what: "time step".into(),
                msg: format!("{dt} is not a positive number"),
            });
        }
        let t_new = self.time + dt;
        let g = &self.g;
        let (n, nb) = (g.n_cells, g.n_boundary());
        let u_old = self.u.clone();
        let u_b_old = self.u_b.clone();
        let phi_old = self.phi.clone();
        let rho = self.settings.rho;
        self.update_u_boundary(t_new);
        let ef = self.eps_faces(&self.eps);
        let ef_old = self.eps_faces(&self.eps_old);
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
        let q_old: Vec<f64> = (0..g.n_faces()).map(|f| uf_old[f].dot(&g.sf[f])).collect();
        let d_old: Vec<f64> = (0..g.n_faces())
            .map(|f| phi_old[f] - ef_old[f] * q_old[f])
            .collect();
        // CrankNicolson ψ: each stored derivative begins the step once ([`CrankNicolsonDdt0`]);
        // `cn_r` = c/Δt (1/s), `cn_src` = c/Δt ε°U° + ψ d₀ per cell (m/s²).
        let (cn_r, cn_src) = match self.cn.as_mut() {
            Some(s) => {
                let (mom_old, eps_old_ext) =
                    cn_old_levels(g, &u_old, &u_b_old, &ef_old, &self.eps_old);
                let r = s.momentum.begin_step(&mom_old, dt);
                s.flux_phi.begin_step(&phi_old, dt);
                let eq_old: Vec<f64> = (0..g.n_faces()).map(|f| ef_old[f] * q_old[f]).collect();
                s.flux_u.begin_step(&eq_old, dt);
                s.flux_u_file
                    .begin_step(&[&u_old[..], &u_b_old[..]].concat(), dt);
                s.voidage.begin_step(&eps_old_ext, dt);
                s.porous_flux.begin_step(&phi_old, dt);
                let src = (0..n)
                    .map(|c| s.momentum.old_part(c, r, mom_old[c]))
                    .collect();
                (r, src)
            }
            None => (0.0, Vec::new()),
        };
        let cn = self.cn.as_ref();
        let is_cn = cn.is_some();

        // --- momentum matrix: convection + diffusion (implicit), time derivative, Ksl.
        let grad_u = fvc::grad_vector(&self.g, &self.u, &self.u_b);
        let (nu_f, nu_c, nu_bf) = self.eps_nu_eff(&ef);
        let (cd, cd_diag, cd_b) = self.conv_diff(&nu_f, &grad_u);
        let g = &self.g;
        let mut m = cd;
        let mut diag: Vec<V3> = vec![V3::zeros(); n];
        let mut b: Vec<V3> = vec![V3::zeros(); n];
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
        for k in 0..3 {
            for c in 0..n {
                let v = g.v[c];
                let ksl = self.ksl[c] / rho * v;
                let (ddt, mut old_source) = match cn {
                    // OpenFOAM's CrankNicolson fvmDdt: diag c/Δt ε V, source (c/Δt ε°U° + ψ d₀) V
                    Some(_) => (cn_r * self.eps[c] * v, cn_src[c][k] * v),
                    None => (
                        ddt_k.c * self.eps[c] * v / dt,
                        self.eps_old[c] * v / dt * u_old[c][k],
                    ),
                };
                if backward {
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
                diag[c][k] = cd_diag[c][k] + ddt + ksl;
                b[c][k] = rhs;
            }
        }

        // --- momentum predictor with the old pressure gradient.
        let mut report = StepReport {
            time: t_new,
            momentum: Vec::new(),
            pressure: Vec::new(),
            continuity: 0.0,
            turbulence: Vec::new(),
        };
        let kappa_p = |c: usize| match self.model {
            Model::A => self.eps[c],
            Model::B => 1.0,
        };
        // The mean-velocity sources take 1/A of this matrix (fvOptions.constrain).
        let a_mean: Vec<f64> = (0..n)
            .map(|c| (diag[c][0] + diag[c][1] + diag[c][2]) / 3.0 / g.v[c])
            .collect();
        let r_au: Vec<f64> = a_mean.iter().map(|a| 1.0 / a).collect();
        for s in &mut self.mean_forces {
            s.constrain(&r_au);
        }
        if self.settings.momentum_predictor {
            let solver = self.settings.u_solver;
            for k in (0..3).filter(|&k| g.solution_dirs[k]) {
                m.diag = diag.iter().map(|d| d[k]).collect();
                let rhs: Vec<f64> = (0..n)
                    .map(|c| b[c][k] - g.v[c] * kappa_p(c) * self.grad_p[c][k])
                    .collect();
                let mut x: Vec<f64> = self.u.iter().map(|v| v[k]).collect();
                let what = ["Ux", "Uy", "Uz"][k];
                let s =
                    linsolve::solve(solver.method, &m, g, &rhs, &mut x, &solver.controls, what)?;
                report.momentum.push(s);
                for c in 0..n {
                    self.u[c][k] = x[c];
                }
            }
            let mut ub = std::mem::take(&mut self.u_b);
            bc::eval_velocity(&self.g, &self.u_bc, t_new, &self.u, &self.phi, &mut ub);
            self.u_b = ub;
            for s in &mut self.mean_forces {
                s.correct(&self.g.v, &self.eps, &mut self.u);
            }
        }

        // --- PISO correctors.
        let g = &self.g;
        let fixed_flux = bc::flux_fixed(g, &self.u_bc, &self.phi);
        let fixes_p = self.p_bc.iter().any(PressureBc::fixes_value);
        let uf_oo = if backward {
            fvc::interpolate(g, Field::new(&old_old.u, &old_old.u_b))
        } else {
            Vec::new()
        };
        let kappa: Vec<f64> = (0..n).map(|c| kappa_p(c) * r_au[c]).collect();
        let kappa_b: Vec<f64> = g.owner[g.n_internal..]
            .iter()
            .map(|&o| kappa[o as usize])
            .collect();
        let kappa_f = fvc::interpolate(g, Field::new(&kappa, &kappa_b));
        // γ_c = ε_c κ_c: the cell's flux coefficient (φ = γ (H/κ − ∇p)·S).
        let gam_c: Vec<f64> = (0..n).map(|c| self.eps[c] * kappa[c]).collect();
        let gamma: Vec<f64> = (0..g.n_faces())
            .map(|f| {
                if self.harmonic_faces && f < g.n_internal {
                    // Two half-cell resistances in series: the owner's half is the fraction
                    // 1 − w of the centre distance (w = d_fN/d_PN, OpenFOAM's weight).
                    let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
                    let w = g.weight[f];
                    1.0 / ((1.0 - w) / gam_c[o] + w / gam_c[nb_])
                } else if self.harmonic_faces {
                    // A boundary face closes the owner's half cell: its coefficient is the
                    // cell's, whatever ε the boundary condition holds (a bed on an inlet).
                    gam_c[g.owner[f] as usize]
                } else {
                    ef[f] * kappa_f[f]
                }
            })
            .collect();
        let gamma_b: Vec<f64> = gamma[g.n_internal..].to_vec();
        let erau: Vec<f64> = (0..n).map(|c| self.eps[c] * r_au[c]).collect();
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
        let mut ddt_corr: Vec<f64> = (0..g.n_faces())
            .map(|f| {
                if !corr_face[f] {
                    return 0.0;
                }
                let diff = d_old[f];
                let coeff = 1.0 - (diff.abs() / (phi_old[f].abs() + 1e-15)).min(1.0);
                if backward {
                    // backward's fvcDdtPhiCorr: the coefficient from the old level alone
                    let diff_oo = old_old.phi[f] - ef_oo[f] * uf_oo[f].dot(&g.sf[f]);
                    let diff = ddt_k.c0 * diff - ddt_k.c00 * diff_oo;
                    return erau_f[f] * coeff * diff / dt;
                }
                if let Some(s) = cn {
                    // CrankNicolson's fvcDdtPhiCorr: (c/Δt φ° + ψ d₀(φ)) − (c/Δt ε°_f U°_f·S
                    // + ψ d₀(ε_f U_f·S)) in place of D°/Δt
                    return erau_f[f]
                        * coeff
                        * cn_flux_corr(s, f, cn_r, phi_old[f], ef_old[f], q_old[f]);
                }
                erau_f[f] * coeff * diff / dt
            })
            .collect();
        // CrankNicolson: ddtCorr's factor (ε/A)_f × coupling coefficient per face, for the
        // later correctors, where v1912 updates ddtCorr's ddt0 again (CrankNicolsonDdt0)
        let cn_corr_w: Vec<f64> = match is_cn {
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
        // Faces next to porous cells take the consistent time term (PorousTimeFlux): their
        // time resistance r_t = 1/(κ_p Δt) per cell (s/m², kinematic) and the mask.
        let consistent = self.harmonic_faces && self.porous_time_flux == PorousTimeFlux::Consistent;
        let porous_face = if consistent {
            porous_faces(g, &self.eps, &self.ksl)
        } else {
            vec![false; g.n_faces()]
        };
        // (backward: T = c ε/Δt, CrankNicolson: T = c/Δt ε, grainPisoFoam's ddtUEqn.A())
        let r_t: Vec<f64> = (0..n)
            .map(|c| match cn {
                Some(_) => cn_r / kappa_p(c),
                None => ddt_k.c / (kappa_p(c) * dt),
            })
            .collect();
        // CrankNicolson's old-time source over κ_p (m/s² per κ_p), for H′ below
        let cn_h: Vec<V3> = match is_cn && consistent {
            true => (0..n).map(|c| cn_src[c] / kappa_p(c)).collect(),
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
                        self.eps[c] * kappa_p(c) / a_steady
                    } else {
                        gam_c[c]
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        // The porous faces' old-time flux term φ_t: with it the face's time derivative is the
        // cells' scheme applied to the face flux, r_t (φ − φ_t) = (c/Δt)(φ − φ_t)/κ_p:
        // Euler φ_t = φ°; backward φ_t = (c₀ φ° − c₀₀ φ°°)/c; CrankNicolson ψ
        // φ_t = φ° + ψ d₀(φ)/r, r = c/Δt, d₀(φ) the face flux's stored derivative (the cells'
        // old-time source r ε°U° + ψ d₀(εU), written for the face). φ° alone there would make
        // the face derivative (1 + ψ)(φ − φ°)/Δt resp. c (φ − φ°)/Δt, an inertia (1 + ψ) resp.
        // 1.5 times the cells' whatever Δt (tests/coupled_time.rs).
        let phi_t: Vec<f64> = match (consistent, cn, backward) {
            (false, _, _) => Vec::new(),
            (true, Some(s), _) => (0..g.n_faces())
                .map(|f| s.porous_flux.old_part(f, cn_r, phi_old[f]) / cn_r)
                .collect(),
            (true, None, true) => (0..g.n_faces())
                .map(|f| (ddt_k.c0 * phi_old[f] - ddt_k.c00 * old_old.phi[f]) / ddt_k.c)
                .collect(),
            (true, None, false) => phi_old.clone(),
        };
        let jump_zone = if self.reconstruct_u {
            jump_zone(&self.g, &gam_c, JUMP_RATIO, JUMP_LAYERS)
        } else {
            Vec::new()
        };
        // ∂ε/∂t of the continuity equation (1/s), with the momentum's time scheme
        let ddt_eps: Vec<f64> = (0..n)
            .map(|c| match (backward, cn) {
                (true, _) => {
                    (ddt_k.c * self.eps[c] - ddt_k.c0 * self.eps_old[c]
                        + ddt_k.c00 * old_old.eps[c])
                        / dt
                }
                // CrankNicolson's fvcDdt: c/Δt (ε − ε°) − ψ d₀
                (false, Some(s)) => s.voidage.explicit(c, cn_r, self.eps[c], self.eps_old[c]),
                (false, None) => (self.eps[c] - self.eps_old[c]) / dt,
            })
            .collect();
        let n_corr = self.settings.n_correctors;
        for corr in 0..n_corr {
            if let (true, Some(s)) = (corr > 0, self.cn.as_mut()) {
                s.flux_phi.evaluate_again();
                s.flux_u.evaluate_again();
                s.flux_u_file.evaluate_again();
                let s = &*s;
                ddt_corr = (0..self.g.n_faces())
                    .map(|f| {
                        cn_corr_w[f] * cn_flux_corr(s, f, cn_r, phi_old[f], ef_old[f], q_old[f])
                    })
                    .collect();
            }
            let g = &self.g;
            // H/A; zero in a direction that is not solved (OpenFOAM's fvMatrix::H).
            let mut hbya: Vec<V3> = vec![V3::zeros(); n];
            for k in (0..3).filter(|&k| g.solution_dirs[k]) {
                let uk: Vec<f64> = self.u.iter().map(|v| v[k]).collect();
                hbya.par_iter_mut().enumerate().for_each(|(c, h)| {
                    let hv =
                        b[c][k] - m.off_row(g, c, &uk) - (diag[c][k] - a_mean[c] * g.v[c]) * uk[c];
                    h[k] = hv / g.v[c] * r_au[c];
                });
            }
            let hb: Vec<V3> = (g.n_internal..g.n_faces())
                .map(|f| hbya[g.owner[f] as usize])
                .collect();
            let mut phi_star = if self.harmonic_faces {
                // φ* = γ_f (HbyA/κ)_f·S on internal faces: the driving term interpolated
                // like the pressure gradient it balances (Fluid::harmonic_faces).
                let ht: Vec<V3> = (0..n).map(|c| 1.0 / kappa[c] * hbya[c]).collect();
                let htf = interpolate_cells(g, &ht);
                // H′/κ_p: the same without the old-time source ε° U°/Δt (PorousTimeFlux).
                let ht_steady: Vec<V3> = if consistent {
                    (0..n)
                        .map(|c| match backward {
                            // CrankNicolson: H_ddt/κ_p = (c/Δt ε°U° + ψ d₀)/κ_p
                            _ if is_cn => ht[c] - cn_h[c],
                            // H_ddt/κ_p = (c₀ ε°U° − c₀₀ ε°°U°°)/(κ_p Δt)
                            true => {
                                ht[c]
                                    - r_t[c] / ddt_k.c
                                        * (ddt_k.c0 * self.eps_old[c] * u_old[c]
                                            - ddt_k.c00 * old_old.eps[c] * old_old.u[c])
                            }
                            false => ht[c] - self.eps_old[c] * r_t[c] * u_old[c],
                        })
                        .collect()
                } else {
                    Vec::new()
                };
                let htsf = if consistent {
                    interpolate_cells(g, &ht_steady)
                } else {
                    Vec::new()
                };
                (0..g.n_faces())
                    .map(|f| {
                        let internal = f < g.n_internal;
                        if !internal && g.boundary_empty[f - g.n_internal] {
                            0.0
                        } else if porous_face[f] && internal {
                            // The face's momentum balance with its own old flux.
                            let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
                            let w = g.weight[f];
                            let rtf = (1.0 - w) * r_t[o] + w * r_t[nb_];
                            gamma[f] * (htsf[f].dot(&g.sf[f]) + rtf * phi_t[f])
                        } else if porous_face[f] {
                            // The owner's half cell with the face's old flux.
                            let o = g.owner[f] as usize;
                            gamma[f] * (ht_steady[o].dot(&g.sf[f]) + r_t[o] * phi_t[f])
                        } else if internal {
                            gamma[f] * htf[f].dot(&g.sf[f]) + ddt_corr[f]
                        } else {
                            // The owner's half cell: φ* = γ_c (HbyA_c/κ_c)·S = ε_c HbyA_c·S.
                            let o = g.owner[f] as usize;
                            self.eps[o] * hbya[o].dot(&g.sf[f]) + ddt_corr[f]
                        }
                    })
                    .collect()
            } else {
                let hf = fvc::interpolate(g, Field::new(&hbya, &hb));
                let mut phi_star = self.flux(&ef, &hf);
                for f in 0..g.n_faces() {
                    phi_star[f] += ddt_corr[f];
                }
                phi_star
            };
            let phi_unconstrained = phi_star.clone();
            for f in g.n_internal..g.n_faces() {
                let bi = f - g.n_internal;
                if fixed_flux[bi] {
                    phi_star[f] = ef[f] * self.u_b[bi].dot(&g.sf[f]);
                }
            }
            // The flux this corrector starts from decides in- and outflow on totalPressure
            // faces (Self::eval_p_boundary).
            let phi_in = std::mem::replace(&mut self.phi, phi_star.clone());
            self.update_p_boundary(t_new, &gamma_b, &phi_unconstrained, &phi_in);
            let g = &self.g;
            // Pressure matrix (symmetric positive definite with a fixed-value patch or ref cell).
            let mut pm = Ldu::zeros(g);
            let mut src = vec![0.0; n];
            for f in 0..g.n_internal {
                let c = gamma[f] * g.mag_sf[f] * self.lap_dc[f];
                pm.upper[f] = -c;
                pm.lower[f] = -c;
                pm.diag[g.owner[f] as usize] += c;
                pm.diag[g.neighbour[f] as usize] += c;
            }
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
            for f in g.n_internal..g.n_faces() {
                let bi = f - g.n_internal;
                if p_fixed[bi] {
                    let c = gamma[f] * g.mag_sf[f] * self.lap_dc[f];
                    let o = g.owner[f] as usize;
                    pm.diag[o] += c;
                    src[o] += c * self.p_b[bi];
                }
            }
            let div_star = fvc::surface_integrate(g, &phi_star);
            for c in 0..n {
                src[c] -= div_star[c] * g.v[c];
                if self.ddt_voidage {
                    src[c] -= g.v[c] * ddt_eps[c];
                }
            }
            if !fixes_p {
                let (rc, rv) = self.settings.p_ref;
                let d = pm.diag[rc];
                src[rc] += d * rv;
                pm.diag[rc] += d;
            }
            let last_corr = corr + 1 == n_corr;
            let corrected = self.settings.sn_grad == SnGrad::Corrected;
            let mut p = std::mem::take(&mut self.p);
            let mut nonorth_flux = vec![0.0; g.n_internal];
            for nonorth in 0..=self.settings.n_non_orth {
                let mut rhs = src.clone();
                if corrected {
                    let gp = fvc::grad_scalar(g, &p, &self.p_b);
                    for f in 0..g.n_internal {
                        let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
                        let w = g.weight[f];
                        let gf: V3 = V3::from_fn(|i, _| w * (gp[o][i] - gp[nb_][i]) + gp[nb_][i]);
                        nonorth_flux[f] = gamma[f] * g.mag_sf[f] * g.corr_vec[f].dot(&gf);
                    }
                    for f in 0..g.n_internal {
                        rhs[g.owner[f] as usize] += nonorth_flux[f];
                        rhs[g.neighbour[f] as usize] -= nonorth_flux[f];
                    }
                }
                let last = last_corr && nonorth == self.settings.n_non_orth;
                let ctl = if last {
                    &self.settings.p_final
                } else {
                    &self.settings.p_solver
                };
                let s = linsolve::solve(ctl.method, &pm, g, &rhs, &mut p, &ctl.controls, "p")?;
                report.pressure.push(s);
                if nonorth < self.settings.n_non_orth {
                    // The next correction's ∇p sees the boundary values of this solution
                    // (OpenFOAM's solve ends with p.correctBoundaryConditions()).
                    let mut pb = std::mem::take(&mut self.p_b);
                    self.eval_p_boundary(t_new, &p, &gamma_b, &phi_unconstrained, &phi_in, &mut pb);
                    self.p_b = pb;
                }
            }
            // Rhie–Chow face flux from the pressure solution.
            for f in 0..g.n_internal {
                let (o, nb_) = (g.owner[f] as usize, g.neighbour[f] as usize);
                self.phi[f] = phi_star[f]
                    - (gamma[f] * g.mag_sf[f] * self.lap_dc[f] * (p[nb_] - p[o]) + nonorth_flux[f]);
            }
            for f in g.n_internal..g.n_faces() {
                let bi = f - g.n_internal;
                if p_fixed[bi] {
                    let o = g.owner[f] as usize;
                    self.phi[f] = phi_star[f]
                        - gamma[f] * g.mag_sf[f] * self.lap_dc[f] * (self.p_b[bi] - p[o]);
                }
            }
            self.p = p;
            self.update_p_boundary(t_new, &gamma_b, &phi_unconstrained, &phi_in);
            self.grad_p = if self.harmonic_faces {
                flux_consistent_grad(
                    &self.g,
                    &self.p,
                    &self.p_b,
                    &gam_c,
                    (&gam_steady, &porous_face),
                )
            } else {
                fvc::grad_scalar(&self.g, &self.p, &self.p_b)
            };
            if self.reconstruct_u {
                let r = fvc::reconstruct(&self.g, &self.phi);
                let near = &jump_zone;
                for c in 0..n {
                    self.u[c] = if near[c] {
                        1.0 / self.eps[c] * r[c]
                    } else {
                        hbya[c] - (kappa[c] * self.grad_p[c])
                    };
                }
            } else {
                for c in 0..n {
                    let k = kappa[c];
                    self.u[c] = hbya[c] - (k * self.grad_p[c]);
                }
            }
            self.update_u_boundary(t_new);
            for s in &mut self.mean_forces {
                s.correct(&self.g.v, &self.eps, &mut self.u);
            }
        }
        let g = &self.g;
        let div = fvc::surface_integrate(g, &self.phi);
        let mut err = 0.0;
        for c in 0..n {
            let mut r = div[c] * g.v[c];
            if self.ddt_voidage {
                r += g.v[c] * ddt_eps[c];
            }
            err += r.abs();
        }
        let scale_phi: f64 = self.phi.iter().map(|x| x.abs()).sum::<f64>() + 1e-300;
        report.continuity = err / scale_phi;
        if !self.u.iter().all(|v| v.iter().all(|x| x.is_finite())) {
            return Err(FvError::Diverged(format!(
                "velocity is not finite at t = {t_new}"
            )));
        }
        if let Some(t) = &mut self.turbulence {
            let flow = k_epsilon::Flow {
                u: &self.u,
                u_b: &self.u_b,
                phi: &self.phi,
                nu: self.settings.nu,
                dt,
                lap_dc: &self.lap_dc,
                corrected: self.settings.sn_grad == SnGrad::Corrected,
            };
            if let Some(r) = t.correct(&self.g, &flow)? {
                report.turbulence = vec![r.epsilon, r.k];
            }
        }
        self.time = t_new;
        self.time_index += 1;
        // the old level of this step: backward's old-old level, CrankNicolson's `_0` files
        let level = || OldLevel {
            u: u_old,
            u_b: u_b_old,
            phi: phi_old,
            eps: self.eps_old.clone(),
        };
        if backward {
            self.old_old = Some((level(), dt));
        } else if self.cn.is_some() {
            self.cn_prev = Some((level(), dt));
        }
        Ok(report)
    }

    /// Convection (flux φ, current) and diffusion (ε νeff at faces, `nu_f`) of the momentum
    /// equation: off-diagonal matrix, per-component diagonal and source (including boundary
    /// contributions and the explicit non-orthogonal correction).
    fn conv_diff(&self, nu_f: &[f64], grad_u: &[crate::fvc::Tensor]) -> (Ldu, Vec<V3>, Vec<V3>) {
        let g = &self.g;
        let mut m = Ldu::zeros(g);
        let mut diag = vec![V3::zeros(); g.n_cells];
        let mut b = vec![V3::zeros(); g.n_cells];
        let corrected = self.settings.sn_grad == SnGrad::Corrected;
        let conv = self.settings.convection;
        let weights = conv.weights(g, &self.phi, &self.u, &self.u_b, grad_u);
        for f in 0..g.n_internal {
            let (o, nn) = (g.owner[f] as usize, g.neighbour[f] as usize);
            let phi = self.phi[f];
            let w = weights[f];
            let gam = nu_f[f] * g.mag_sf[f] * self.lap_dc[f];
            m.upper[f] = phi * (1.0 - w) - gam;
            m.lower[f] = -phi * w - gam;
            let d_o = phi * w + gam;
            let d_n = -phi * (1.0 - w) + gam;
            for k in 0..3 {
                diag[o][k] += d_o;
                diag[nn][k] += d_n;
            }
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
                    b[o][j] += c * s;
                    b[nn][j] -= c * s;
                }
            }
        }
        let vi = bc::velocity_value_coeffs(g, &self.u_bc, &self.phi);
        self.add_boundary_terms(nu_f, &vi, &self.u_b, Some(&mut diag), &mut b);
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

    /// Adds the boundary faces' part of convection and diffusion: with the face value
    /// U_b = vi ⊙ U_P + vb (vi from [`bc::velocity_value_coeffs`], `u_b` the face values), the
    /// implicit φ vi + a_f|S|δ (1 − vi) to `diag` (when given) and the explicit
    /// (−φ + a_f|S|δ) vb to `b` (a_f = ε νeff at the face, `nu_f`).
    fn add_boundary_terms(
        &self,
        nu_f: &[f64],
        vi: &[V3],
        u_b: &[V3],
        mut diag: Option<&mut Vec<V3>>,
        b: &mut [V3],
    ) {
        let g = &self.g;
        for f in g.n_internal..g.n_faces() {
            let bi = f - g.n_internal;
            if g.boundary_empty[bi] {
                continue;
            }
            let o = g.owner[f] as usize;
            let phi = self.phi[f];
            let gam = nu_f[f] * g.mag_sf[f] * self.lap_dc[f];
            for k in 0..3 {
                if let Some(d) = diag.as_deref_mut() {
                    d[o][k] += phi * vi[bi][k] + gam * (1.0 - vi[bi][k]);
                }
                let vb = u_b[bi][k] - vi[bi][k] * self.u[o][k];
                b[o][k] += -phi * vb + gam * vb;
            }
        }
    }

    /// The patches as `constant/polyMesh/boundary` names them (name, type, faces).
    fn patches(&self) -> Vec<foam::Patch> {
        self.g
            .patches
            .iter()
            .map(|p| foam::Patch {
                name: p.name.clone(),
                patch_type: p.patch_type.clone(),
                n_faces: p.mesh_faces.len(),
                start_face: p.mesh_faces.start,
                extra: Vec::new(),
            })
            .collect()
    }

    /// The start time's `voidfraction` file, if it has one (its boundaryField is what the
    /// solver takes the boundary voidage from).
    pub fn voidfraction_file(&self) -> Option<&VolField> {
        self.eps_file.as_ref()
    }

    /// Writes `U` and `p` (and `phi` as a surfaceScalarField) into the time directory `name`
    /// of the case, keeping the start files' boundaryField entries; with
    /// [`Self::harmonic_faces`] also the pressure gradient of the last step,
    /// [`crate::fields::GRAD_P_FILE`], which a run started from that time reads.
    pub fn write(&self, name: &str) -> Result<()> {
        let dir = self.case.time_path(name);
        std::fs::create_dir_all(&dir).map_err(|e| FvError::Value {
            what: dir.display().to_string(),
            msg: e.to_string(),
        })?;
        let fmt = self.settings.write_format;
        let mut u = self.u_file.clone();
        u.set_internal(FieldValues::Vector(mesh::v3::to_arrays(&self.u)))
            .map_err(|m| FvError::Value {
                what: "U".into(),
                msg: m,
            })?;
        u.write(&dir.join("U"), fmt)?;
        let mut p = self.p_file.clone();
        p.set_internal(FieldValues::Scalar(self.p.clone()))
            .map_err(|m| FvError::Value {
                what: "p".into(),
                msg: m,
            })?;
        self.set_total_pressure_values(&mut p);
        p.write(&dir.join("p"), fmt)?;
        crate::fields::write_phi(&dir.join("phi"), &self.g, &self.phi, fmt)?;
        if let Some(t) = &self.turbulence {
            t.write(&self.g, &dir, fmt)?;
        }
        for s in &self.mean_forces {
            s.write(&dir, fmt)?;
        }
        self.write_cn_state(&dir, fmt)?;
        if self.harmonic_faces {
            let grad = VolField::new(
                crate::fields::GRAD_P_FILE,
                name,
                [0, 1, -2, 0, 0, 0, 0],
                FieldValues::Vector(mesh::v3::to_arrays(&self.grad_p)),
                foam::field::default_boundary(&self.patches(), "zeroGradient", None),
            );
            grad.write(&dir.join(crate::fields::GRAD_P_FILE), fmt)?;
        }
        Ok(())
    }

    /// Puts the current boundary values of the totalPressure patches into their `value`
    /// entries (what OpenFOAM writes, and what a run started from the time reads back).
    fn set_total_pressure_values(&self, p: &mut VolField) {
        let Some(foam::Value::Dict(bf)) = p.body.get_mut("boundaryField") else {
            return;
        };
        for (patch, bc) in self.g.patches.iter().zip(&self.p_bc) {
            if !matches!(bc, PressureBc::TotalPressure(_)) {
                continue;
            }
            if let Some(foam::Value::Dict(e)) = bf.get_mut(&patch.name) {
                let v = self.p_b[patch.boundary_range(self.g.n_internal)].to_vec();
                e.set(
                    "value",
                    foam::Value::Stream(vec![
                        foam::Item::Word("nonuniform".into()),
                        foam::Item::Word("List<scalar>".into()),
                        foam::Item::Scalars(v),
                    ]),
                );
            }
        }
    }

    /// The directory name OpenFOAM would give the current time ([`foam::case::time_name`]).
    pub fn time_name(&self) -> String {
        foam::case::time_name(self.time)
    }

    /// Runs the case as its controlDict says (start to end time, writing time directories);
    /// returns the number of steps.
    pub fn run(&mut self) -> Result<usize> {
        let dt = self.settings.delta_t;
        let n_steps = ((self.settings.end_time - self.time) / dt - 1e-9)
            .ceil()
            .max(0.0) as usize;
        let mut next_write = self.time;
        for step in 1..=n_steps {
            self.advance(dt)?;
            let write = match self.settings.write {
                crate::settings::WriteControl::TimeStep(n) => step % n == 0,
                crate::settings::WriteControl::RunTime(t) => {
                    if self.time >= next_write + t - 1e-9 * dt {
                        next_write += t;
                        true
                    } else {
                        false
                    }
                }
            };
            if write || step == n_steps {
                self.write(&self.time_name())?;
            }
        }
        Ok(n_steps)
    }
}

/// `CrankNicolson ψ`'s old levels of εU and ε (cells, then boundary faces) from U° (cells
/// `u`, boundary faces `u_b`), ε° per face `ef` and per cell `eps`.
fn cn_old_levels(
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
fn cn_flux_corr(s: &CnState, f: usize, r: f64, phi_old: f64, ef_old: f64, q_old: f64) -> f64 {
    s.flux_phi.old_part(f, r, phi_old) - s.flux_u.old_part(f, r, ef_old * q_old)
}

/// The error of a file a restart needs.
fn missing_file(dir: &Path, name: &str) -> FvError {
    FvError::setting(
        dir.join(name),
        "CrankNicolson",
        "the restart needs this file",
    )
}

/// The cell values of the volume field `name` in `dir` (a `U_0` or `voidfraction_0`, whose
/// boundary entries are the field's conditions).
fn read_cells<T: crate::cn_files::CellValue>(dir: &Path, name: &str, n: usize) -> Result<Vec<T>> {
    let path = dir.join(name);
    let file = VolField::read(&path)?;
    let v = file
        .internal(n)
        .map_err(|m| FvError::setting(&path, "internalField", m))?;
    T::from_values(v).ok_or_else(|| FvError::setting(&path, "class", "wrong kind of field"))
}

/// The step that led to the time directory `dir` (s): `deltaT` of OpenFOAM's `uniform/time`
/// when it is there, else `None`.
fn previous_step(dir: &Path) -> Result<Option<f64>> {
    let path = dir.join("uniform/time");
    if !path.is_file() {
        return Ok(None);
    }
    let file = foam::parse_file(&path)?;
    let dt = file
        .body
        .f64("deltaT")
        .map_err(|e| FvError::setting(&path, "deltaT", e.0))?;
    Ok(Some(dt))
}

/// The time directory to start from.
fn start_dir(case: &Case, start: f64) -> Result<std::path::PathBuf> {
    let times = case.times()?;
    times
        .iter()
        .find(|t| (t.value - start).abs() <= 1e-12 * start.abs().max(1.0))
        .map(|t| t.path.clone())
        .ok_or_else(|| {
            FvError::setting(
                case.root().join("system/controlDict"),
                "startTime",
                format!("there is no time directory for {start}"),
            )
        })
}

/// Gauss gradient of the cell pressures `p` (boundary values `p_b`) with the flux-continuous
/// face pressure of [`Fluid::harmonic_faces`] on internal faces: p_f weights each side by its
/// flux coefficient γ = εκ over its distance to the face, p_f = (w γ_P p_P + (1−w) γ_N p_N)/
/// (w γ_P + (1−w) γ_N). `gamma` per cell; on the faces `steady.1` marks (empty: none) the
/// per-cell `steady.0` instead (the steady γ′ of [`PorousTimeFlux::Consistent`]).
fn flux_consistent_grad(
    g: &FvGeometry,
    p: &[f64],
    p_b: &[f64],
    gamma: &[f64],
    steady: (&[f64], &[bool]),
) -> Vec<V3> {
    let mut sum = vec![V3::zeros(); g.n_cells];
    for f in 0..g.n_internal {
        let (o, nb) = (g.owner[f] as usize, g.neighbour[f] as usize);
        let w = g.weight[f];
        let kappa = if steady.1.get(f).copied().unwrap_or(false) {
            steady.0
        } else {
            gamma
        };
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
