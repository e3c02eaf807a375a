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
//!
//! [`Fluid::advance`] runs the step as named stages, each in its module: `time_levels` (the
//! old time levels, the time scheme's coefficients and history, and the bookkeeping that
//! ends the step), `momentum` (the momentum matrix and predictor), `coefficients` (what the
//! correctors share: the pressure equation's face coefficients, ddtCorr, the porous faces'
//! time terms, ∂ε/∂t), `correctors` (one PISO corrector: HbyA, predicted flux, pressure
//! equation, Rhie–Chow flux, velocity correction); `cn_state` holds `CrankNicolson ψ`'s
//! stored derivatives and their reading and writing ([`crate::cn_files`]).

// Face and cell loops index several arrays at once, as the equations do.
#![allow(clippy::needless_range_loop)]

mod cn_state;
mod coefficients;
mod correctors;
mod grad_memo;
mod momentum;
mod time_levels;

use cn_state::CnState;
use grad_memo::GradMemo;
use momentum::MomentumEqn;
use time_levels::Levels;

use crate::bc::{self, PressureBc, VelocityBc};
use crate::error::{FvError, Result};
use crate::fv_options::MeanForce;
use crate::fvc::{self, Field};
use crate::geometry::{FvGeometry, V3};
use crate::linsolve::SolveStats;
use crate::settings::{Settings, SnGrad, TimeScheme};
use crate::temperature::{HeatFlow, Temperature};
use crate::turbulence::{k_epsilon, KEpsilon, TurbulenceSettings};
use foam::{Case, FieldValues, VolField};
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
    /// (backward (c₀φ° − c₀₀φ°°)/c, CrankNicolson ψ φ° + ψ d₀(φ)/r; see the `coefficients`
    /// stage of `Fluid::advance`), so that the face flux follows the cells' time scheme
    /// (tests/coupled_time.rs). At steady state (φ = φ°) the face flux solves
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
    /// The temperature solve before the momentum predictor (`None` without heat).
    pub temperature: Option<SolveStats>,
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
    ///
    /// Only faces next to a porous cell (ε < 1 or Ksl > 0 on either side) take these forms;
    /// faces between two clear cells keep pisoFoam's linear ε_f κ_f, ε_f (HbyA)_f·S + ddtCorr
    /// and linear face pressure, as grainPisoFoam's `porousFaces.H` does. With the series forms
    /// on clear faces too (before 2026-11-29), CrankNicolson 0.9 at Courant numbers 14–20
    /// diverged where grainPisoFoam does not (`openfoam-cases/pneumatic-conveying-full`,
    /// docs/pneumatic-conveying.md). The likely mechanism: where κ = 1/A varies across clear
    /// faces (the convection-dominated entry of the conveyor's tube) the old-time part of
    /// the predicted flux, γ_f (H/κ)_f·S, is weighted by the harmonic γ_f while ddtCorr's
    /// bracket is weighted by the linear (ε/A)_f, so the cells' old velocities and CN's
    /// stored derivatives stay in the face flux with weight γ_f − (ε/A)_f instead of
    /// cancelling; the clear cavity with the series forms on every face differed from icoFoam
    /// by 8.6e-3 of the lid speed (`tests/cavity.rs`).
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
    /// The temperature equation when [`Settings::temperature`] asks for it.
    heat: Option<Temperature>,
    /// ∇U at the end of the last step (the turbulence model's), for the next momentum matrix.
    grad_u_end: Option<GradMemo>,
    /// ε at faces ([`Self::eps_faces`]) with the cell values it was formed from: a step
    /// whose ε holds the same bits (a fluid without particles: every step) takes it
    /// instead of interpolating again.
    eps_faces_kept: Option<(Vec<f64>, Vec<f64>)>,
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
        Fluid::from_case_with(case, settings, &mesh)
    }

    /// [`Fluid::from_case`] with the case's settings and mesh read already (a coupled run
    /// reads each once and hands them on).
    pub fn from_case_with(case: Case, settings: Settings, mesh: &foam::PolyMesh) -> Result<Fluid> {
        let g = FvGeometry::new(mesh).map_err(|e| e.in_case(case.root()))?;
        let start = start_dir(&case, settings.start_time)?;
        let fields = crate::fields::read_fields(&start, mesh, &g)?;
        let turbulence = match &settings.turbulence {
            TurbulenceSettings::KEpsilon(s) => Some(KEpsilon::read(
                &start,
                mesh,
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
        if let Some(ts) = fl.settings.temperature {
            fl.heat = Some(Temperature::read(&start, mesh, &fl.g, ts, &fl.phi)?);
        }
        fl.read_cn_state(&start, mesh)?;
        Ok(fl)
    }

    /// Whether the case is a VANS one (it has a `voidfraction` field): the names of
    /// grainPisoFoam's CrankNicolson files ([`crate::cn_files`]).
    fn is_vans(&self) -> bool {
        self.eps_file.is_some()
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
            heat: None,
            grad_u_end: None,
            eps_faces_kept: None,
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
    ///
    /// With heat the temperature is held too; cfdemSolverPisoScalar solves its T equation also
    /// when the flow is not solved, which [`Self::hold_step`] does step by step.
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

    /// One step of `dt` seconds on a held flow (CFDEM's `solveFlow off` in
    /// cfdemSolverPisoScalar): U, p and φ stay as they are, the clock and the schemes' history
    /// as [`Self::hold`] leaves them, and with heat the temperature equation is solved with the
    /// step's voidage ([`Self::set_voidage`]) and the held flux rescaled by it
    /// ([`crate::temperature`]). Returns the temperature solve (`None` without heat).
    pub fn hold_step(&mut self, dt: f64) -> Result<Option<SolveStats>> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(FvError::Value {
                what: "time step".into(),
                msg: format!("{dt} is not a positive number"),
            });
        }
        let stats = match self.heat.is_some() {
            true => {
                let (ef, ef_old) = (self.eps_faces(&self.eps), self.eps_faces(&self.eps_old));
                let phi_old = self.phi.clone();
                self.heat_step(dt, &phi_old, &ef, &ef_old)?
            }
            false => None,
        };
        self.hold(dt);
        Ok(stats)
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
        fvc::interpolate(&self.g, Field::new(eps, &self.eps_boundary(eps)))
    }

    /// ε on the boundary faces: the `voidfraction` file's fixed value where it has one, else
    /// the owner cell's (CFDEM's zeroGradient patches after `correctBoundaryConditions`).
    fn eps_boundary(&self, eps: &[f64]) -> Vec<f64> {
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
        b
    }

    /// φ = ε_f U_f·S with U_f linearly interpolated (boundary: U_b).
    fn flux_of_u(&self) -> Vec<f64> {
        let ef = self.eps_faces(&self.eps);
        let uf = fvc::interpolate(&self.g, Field::new(&self.u, &self.u_b));
        self.flux(&ef, &uf)
    }

    fn flux(&self, ef: &[f64], uf: &[V3]) -> Vec<f64> {
        crate::gather::over(0..self.g.n_faces())
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
        let eps_b = self.eps_boundary(&self.eps);
        bc::eval_velocity(&self.g, &self.u_bc, t, &self.u, &eps_b, &self.phi, &mut ub);
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

    /// Advances by `dt` seconds (one PISO step), in the stages of pisoFoam's and CFDEM's
    /// cfdemSolverPiso's time loop: the old time levels and the time scheme's history
    /// (`Self::old_time_levels`), with heat the temperature equation
    /// (`Self::solve_temperature`, where cfdemSolverPisoScalar solves it), the momentum
    /// matrix (`Self::momentum_matrix`) and predictor (`Self::momentum_predictor`), the coefficients the correctors share
    /// (`Self::corrector_coeffs`: γ_f, ddtCorr, the porous faces' time terms, ∂ε/∂t),
    /// `nCorrectors` PISO correctors (`Self::piso_corrector`: pressure equation, flux and
    /// velocity), the continuity error, the turbulence model (`Self::correct_turbulence`)
    /// and the clock (`Self::end_step`).
    pub fn advance(&mut self, dt: f64) -> Result<StepReport> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(FvError::Value {
                what: "time step".into(),
                msg: format!("{dt} is not a positive number"),
            });
        }
        let lv = self.old_time_levels(dt);
        // cfdemSolverPisoScalar's T equation, before the momentum predictor
        let temperature = self.solve_temperature(&lv)?;
        let mut eqn = self.momentum_matrix(&lv);
        let mut report = StepReport {
            time: lv.t_new,
            momentum: Vec::new(),
            pressure: Vec::new(),
            continuity: 0.0,
            turbulence: Vec::new(),
            temperature,
        };
        self.momentum_predictor(&lv, &mut eqn, &mut report)?;
        let mut cs = self.corrector_coeffs(&lv, &eqn);
        for corr in 0..self.settings.n_correctors {
            self.piso_corrector(corr, &lv, &eqn, &mut cs, &mut report)?;
        }
        report.continuity = self.continuity_error(&cs.ddt_eps);
        if !self.u.iter().all(|v| v.iter().all(|x| x.is_finite())) {
            return Err(FvError::Diverged(format!(
                "velocity is not finite at t = {}",
                lv.t_new
            )));
        }
        report.turbulence = self.correct_turbulence(dt)?;
        if let Some(h) = &mut self.heat {
            h.flux_formed_with(lv.ef.clone());
        }
        self.end_step(lv);
        Ok(report)
    }

    /// [`StepReport::continuity`]: Σ|∇·φ + ∂ε/∂t| V over the cells after the last corrector
    /// (m³/s; `ddt_eps` the step's ∂ε/∂t, 1/s, counted when [`Self::ddt_voidage`] is on)
    /// relative to Σ|φ| over the faces (pisoFoam's `continuityErrs.H` reports the V-weighted
    /// mean of |∇·φ| Δt instead).
    fn continuity_error(&self, ddt_eps: &[f64]) -> f64 {
        let g = &self.g;
        let div = fvc::surface_integrate(g, &self.phi);
        let mut err = 0.0;
        for c in 0..g.n_cells {
            let mut r = div[c] * g.v[c];
            if self.ddt_voidage {
                r += g.v[c] * ddt_eps[c];
            }
            err += r.abs();
        }
        let scale_phi: f64 = self.phi.iter().map(|x| x.abs()).sum::<f64>() + 1e-300;
        err / scale_phi
    }

    /// The turbulence model's step after the correctors with the corrected U and φ
    /// (pisoFoam's `turbulence->correct()`, [`KEpsilon::correct`]): its solves (ε, then k;
    /// none when laminar or with `turbulence off`).
    fn correct_turbulence(&mut self, dt: f64) -> Result<Vec<SolveStats>> {
        let Some(t) = &mut self.turbulence else {
            return Ok(Vec::new());
        };
        let grad_u = self
            .grad_u_end
            .insert(GradMemo::compute(&self.g, &self.u, &self.u_b));
        let flow = k_epsilon::Flow {
            grad_u: grad_u.grad(),
            u: &self.u,
            u_b: &self.u_b,
            phi: &self.phi,
            nu: self.settings.nu,
            dt,
            lap_dc: &self.lap_dc,
            corrected: self.settings.sn_grad == SnGrad::Corrected,
        };
        Ok(match t.correct(&self.g, &flow)? {
            Some(r) => vec![r.epsilon, r.k],
            None => Vec::new(),
        })
    }

    /// The temperature step (cfdemSolverPisoScalar's T equation, [`crate::temperature`]) at
    /// the start of a step, after its old time levels `lv`: ε and ε° of the step, the face
    /// flux ε_f φ°/ε°_f, ν_t of the previous step. `None` without heat.
    fn solve_temperature(&mut self, lv: &Levels) -> Result<Option<SolveStats>> {
        self.heat_step(lv.dt, &lv.phi_old, &lv.ef, &lv.ef_old)
    }

    /// The temperature equation over `dt` with the flux `phi_old` and the face voidages `ef`,
    /// `ef_old` of the step ([`crate::temperature::HeatFlow`]); `None` without heat.
    fn heat_step(
        &mut self,
        dt: f64,
        phi_old: &[f64],
        ef: &[f64],
        ef_old: &[f64],
    ) -> Result<Option<SolveStats>> {
        let Some(heat) = &mut self.heat else {
            return Ok(None);
        };
        let nut = self
            .turbulence
            .as_ref()
            .map(|t| (t.nut(), t.nut_boundary()));
        let flow = HeatFlow {
            phi_old,
            ef,
            ef_old,
            eps: &self.eps,
            eps_old: &self.eps_old,
            dt,
            nu: self.settings.nu,
            nut,
            lap_dc: &self.lap_dc,
            corrected: self.settings.sn_grad == SnGrad::Corrected,
        };
        heat.solve(&self.g, &flow).map(Some)
    }

    /// The fluid's temperature per cell (K), when the case has heat
    /// ([`Settings::enable_temperature`]).
    pub fn temperature(&self) -> Option<&[f64]> {
        self.heat.as_ref().map(Temperature::cells)
    }

    /// The temperature per boundary face (K), when the case has heat.
    pub fn temperature_boundary(&self) -> Option<&[f64]> {
        self.heat.as_ref().map(Temperature::boundary)
    }

    /// The held temperature source Tsource per cell (K/s), when the case has heat.
    pub fn heat_source(&self) -> Option<&[f64]> {
        self.heat.as_ref().map(Temperature::source)
    }

    /// Sets the temperature equation's explicit source Tsource (K/s per cell, finite), held
    /// over the following steps until set again: a heat rate Q (W) into the gas of cell c is
    /// Tsource = Q/(ρ c_p V_c) with the whole cell's volume (the time term carries ε; CFDEM's
    /// `LaEuScalarTemp`). An error without heat or with the wrong length.
    pub fn set_heat_source(&mut self, s: &[f64]) -> Result<()> {
        match &mut self.heat {
            Some(h) => h.set_source(&self.g, s),
            None => Err(FvError::Value {
                what: "Tsource".into(),
                msg: "the fluid solves no temperature (Settings::enable_temperature was not \
                      called)"
                    .into(),
            }),
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
    /// [`crate::fields::GRAD_P_FILE`], which a run started from that time reads; with heat
    /// `T`, `Tsource` and `alphat` (when the start time had it), which a run started from that
    /// time reads back.
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
        if let Some(h) = &self.heat {
            h.write(&self.g, &dir, fmt)?;
        }
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
        self.run_observed(None, |_, _| Ok(()))
    }

    /// [`Fluid::run`] to `end_time` (the controlDict's when `None`), calling `observe` after
    /// every step and every write. Writes follow the controlDict's `writeControl` and
    /// `writeInterval`, and always at the last step; with `purgeWrite N` only the last N
    /// directories this run wrote are kept, as OpenFOAM's `Time::writeTime` does. An error
    /// from `observe` ends the run with it.
    pub fn run_observed(
        &mut self,
        end_time: Option<f64>,
        mut observe: impl FnMut(&Fluid, RunEvent<'_>) -> Result<()>,
    ) -> Result<usize> {
        let dt = self.settings.delta_t;
        let end = end_time.unwrap_or(self.settings.end_time);
        let n_steps = ((end - self.time) / dt - 1e-9).ceil().max(0.0) as usize;
        let mut next_write = self.time;
        let mut written: std::collections::VecDeque<String> = Default::default();
        for step in 1..=n_steps {
            let report = self.advance(dt)?;
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
            let write = write || step == n_steps;
            observe(
                self,
                RunEvent::Step {
                    index: step,
                    of: n_steps,
                    report: &report,
                    writes: write,
                },
            )?;
            if write {
                let name = self.time_name();
                self.write(&name)?;
                written.push_back(name.clone());
                self.purge(&mut written)?;
                observe(self, RunEvent::Wrote { name: &name })?;
            }
        }
        Ok(n_steps)
    }

    /// Removes the oldest of the `written` directories beyond `purgeWrite` (none when 0).
    fn purge(&self, written: &mut std::collections::VecDeque<String>) -> Result<()> {
        let keep = self.settings.purge_write;
        while keep > 0 && written.len() > keep {
            let Some(old) = written.pop_front() else {
                break;
            };
            let dir = self.case.time_path(&old);
            std::fs::remove_dir_all(&dir).map_err(|e| FvError::Value {
                what: dir.display().to_string(),
                msg: format!("purgeWrite could not remove it: {e}"),
            })?;
        }
        Ok(())
    }
}

/// What [`Fluid::run_observed`] reports.
#[derive(Debug)]
pub enum RunEvent<'a> {
    /// Step `index` of `of` is done.
    Step {
        /// 1-based.
        index: usize,
        /// Steps of the run.
        of: usize,
        /// The step's solves.
        report: &'a StepReport,
        /// The step ends at a write time (its directory is written next).
        writes: bool,
    },
    /// The time directory `name` was written.
    Wrote {
        /// Its name.
        name: &'a str,
    },
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
