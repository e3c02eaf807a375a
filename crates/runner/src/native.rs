//! The native backends as coupling sides: the `fv` PISO solver as a [`FluidSide`] and the
//! `dem` simulation as a [`ParticleSide`].

use crate::fluid::RunFluid;
use couple::blend::{blend_scalar, fraction};
use couple::{
    CouplingStep, ExchangeFields, FluidSide, FluidState, ParticleSide, ParticleState, SideError,
};
use dem::deck::exec::{DeckEvent, Session};
use dem::Simulation;
use foam::PolyMesh;
use fv::Fluid;
use liggghts_deck::Deck;
use mesh::v3::V3;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};

/// The native fluid solver as the fluid side.
///
/// A coupling interval Δt_c is advanced in `round(Δt_c / deltaT)` PISO steps of equal length
/// (`deltaT` from `system/controlDict`), and ε is blended linearly from the interval's old to
/// its new field over those steps (CFDEM's time blending, [`couple::blend`]); Ksl, Us and f
/// are held for the interval.
pub struct NativeFluid {
    fluid: Fluid,
    mesh: PolyMesh,
    div_tau: Vec<V3>,
    eps_old: Vec<f64>,
    eps_new: Vec<f64>,
    /// The ε the solver saw last (the "previous" field of the next step).
    eps_last: Vec<f64>,
    steps_done: u64,
    /// `solveFlow`: false holds U and p while the clock moves.
    solve_flow: bool,
    /// The fluid fields added mass and lift ask for ([`NativeFluid::request`]), `None` unless
    /// asked.
    vorticity: Option<Vec<V3>>,
    ddt_u: Option<Vec<V3>>,
    /// U before the last PISO step and that step's length (for ∂U/∂t), when DU/Dt is asked.
    u_before: Option<(Vec<V3>, f64)>,
    /// Whether the k–ε fields go into the state (`KochHillRWDrag`,
    /// [`NativeFluid::request_turbulence`]).
    turbulence: bool,
}

impl NativeFluid {
    /// [`NativeFluid::open`] on a case whose settings nobody has read yet (a study's copy of
    /// a case): reads them first.
    pub fn open_case(
        cfd: &Path,
        model: fv::Model,
        ddt_voidage: bool,
        solve_flow: bool,
        rho: f64,
    ) -> Result<NativeFluid, SideError> {
        let settings = fv::settings::Settings::read(&foam::Case::open(cfd)?)?;
        NativeFluid::open(cfd, settings, model, ddt_voidage, solve_flow, rho)
    }

    /// Reads the OpenFOAM case `cfd` (mesh and start fields; its `settings` — controlDict,
    /// fvSchemes, fvSolution — the caller has read), with the model, the
    /// ∂ε/∂t switch, whether the flow is solved (`solveFlow`; when false the clock moves
    /// and U, p stay as read) and the coupling's fluid density `rho` (kg/m³).
    ///
    /// The solver divides Ksl and f by `rho`, which replaces the density `fv` read itself:
    /// the coupling reads ρ where CFDEM cases keep it ([`couple::config::read_transport`]:
    /// `transportProperties`' `rho`, else the field `0/rho`), and `fv` knows only the first
    /// (1 without it). Two densities would make the pressure ρ_coupling/ρ_fluid times the
    /// pressure of the drag the particles feel (ErgunTestMPI, ρ 10 only in `0/rho`: a 10×
    /// pressure gradient force lifted the bed and the coupled oscillation grew until it blew up).
    pub fn open(
        cfd: &Path,
        settings: fv::settings::Settings,
        model: fv::Model,
        ddt_voidage: bool,
        solve_flow: bool,
        rho: f64,
    ) -> Result<NativeFluid, SideError> {
        if !(rho.is_finite() && rho > 0.0) {
            return Err(format!("fluid density {rho} kg/m³ is not a positive number").into());
        }
        let case = foam::Case::open(cfd)?;
        let mesh = case.read_mesh()?;
        let mut fluid = Fluid::from_case_with(case, settings, &mesh)?;
        fluid.settings.rho = rho;
        fluid.model = model;
        fluid.ddt_voidage = ddt_voidage;
        fluid.harmonic_faces = true;
        let n = mesh.n_cells;
        let div_tau = fluid.div_tau();
        Ok(NativeFluid {
            fluid,
            mesh,
            div_tau,
            eps_old: vec![1.0; n],
            eps_new: vec![1.0; n],
            eps_last: vec![1.0; n],
            steps_done: 0,
            solve_flow,
            vorticity: None,
            ddt_u: None,
            u_before: None,
            turbulence: false,
        })
    }

    /// The solver (time, fields, settings, writing time directories).
    pub fn fluid(&self) -> &Fluid {
        &self.fluid
    }

    /// PISO steps done so far.
    pub fn steps_done(&self) -> u64 {
        self.steps_done
    }
}

impl FluidSide for NativeFluid {
    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError> {
        if self.steps_done == 0 {
            // The start: the solver has seen no voidage yet; ∂ε/∂t starts from the first
            // interval's old field, not from the ε = 1 the solver was created with.
            self.eps_last.clone_from_slice(fields.voidage_old);
        }
        self.eps_old.clone_from_slice(fields.voidage_old);
        self.eps_new.clone_from_slice(fields.voidage_new);
        self.fluid
            .set_exchange(&fields.exchange.ksl, &fields.exchange.us)?;
        self.fluid.set_force(&fields.exchange.f)?;
        if let Some(s) = fields.heat_source {
            self.fluid.set_heat_source(s)?;
        }
        Ok(())
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        let base = self.fluid.settings.delta_t;
        let n = (dt / base).round().max(1.0) as u64;
        let h = dt / n as f64;
        if !self.solve_flow && self.fluid.temperature().is_none() {
            self.fluid.hold(dt);
            return Ok(());
        }
        let mut eps = Vec::new();
        for k in 1..=n {
            // the last step ends on the new field exactly (k·h/dt may round below 1), as a
            // run restarted at the interval's end starts from it
            let alpha = match k == n {
                true => 1.0,
                false => fraction(k as f64 * h, 0.0, dt),
            };
            blend_scalar(&self.eps_old, &self.eps_new, alpha, &mut eps);
            self.fluid.set_voidage(&eps, &self.eps_last)?;
            if k == n && self.ddt_u.is_some() {
                self.u_before = Some((self.fluid.u().to_vec(), h));
            }
            if self.solve_flow {
                self.fluid.advance(h)?;
            } else {
                // `solveFlow off` with heat: the flow is held, T is still solved (as
                // cfdemSolverPisoScalar does)
                self.fluid.hold_step(h)?;
            }
            std::mem::swap(&mut self.eps_last, &mut eps);
            self.steps_done += 1;
        }
        self.div_tau = self.fluid.div_tau();
        self.update_requested();
        Ok(())
    }

    fn state(&self) -> FluidState<'_> {
        FluidState {
            temperature: self.fluid.temperature(),
            u: self.fluid.u(),
            p: self.fluid.p(),
            grad_p: self.fluid.grad_p(),
            div_tau: &self.div_tau,
            vorticity: self.vorticity.as_deref(),
            ddt_u: self.ddt_u.as_deref(),
            turbulence: match self.turbulence {
                true => self.fluid.turbulence().map(|t| couple::Turbulence {
                    k: t.k(),
                    epsilon: t.epsilon(),
                }),
                false => None,
            },
        }
    }
}

impl NativeFluid {
    /// Computes, from now on after every advance, the fields added mass and lift ask for
    /// ([`couple::config::Forces::needs_vorticity`], `needs_ddt_u`): the vorticity ∇ × U
    /// ([`fv::fvc::curl`], OpenFOAM's `fvc::curl(U)`) and CFDEM's DU/Dt = ∂U/∂t + ∇·(φU)
    /// (Euler ∂U/∂t over the last PISO step, zero before the first; [`fv::fvc::div_flux_linear`]
    /// with the solver's φ = (εU)_f·S, as CFDEM's `fvc::div(phi, U)`).
    pub fn request(&mut self, vorticity: bool, ddt_u: bool) {
        self.vorticity = vorticity.then(Vec::new);
        self.ddt_u = ddt_u.then(Vec::new);
        self.update_requested();
    }

    /// Hands the k–ε model's k and ε to the coupling from now on (`KochHillRWDrag`); an error
    /// when the case's fluid is laminar.
    pub fn request_turbulence(&mut self) -> Result<(), String> {
        match self.fluid.turbulence() {
            Some(_) => {
                self.turbulence = true;
                Ok(())
            }
            None => Err(
                "KochHillRWDrag needs the fluid's k and epsilon: the case's \
                 constant/turbulenceProperties must select RAS kEpsilon"
                    .into(),
            ),
        }
    }

    /// The requested fields of the fluid now.
    fn update_requested(&mut self) {
        let g = self.fluid.geometry();
        let (u, u_b) = (self.fluid.u(), self.fluid.u_boundary());
        if let Some(w) = self.vorticity.as_mut() {
            *w = fv::fvc::curl(g, u, u_b);
        }
        if let Some(d) = self.ddt_u.as_mut() {
            let mut a = fv::fvc::div_flux_linear(g, self.fluid.phi(), u, u_b);
            if let Some((before, dt)) = &self.u_before {
                for ((a, u), b) in a.iter_mut().zip(u).zip(before) {
                    *a += (*u - *b) / *dt;
                }
            }
            *d = a;
        }
    }
}

/// Area-weighted mean of boundary values over a patch; `None` without the patch.
fn patch_mean<T: Copy>(
    g: &fv::FvGeometry,
    name: &str,
    values: &[T],
    mut f: impl FnMut(T, usize) -> f64,
) -> Option<f64> {
    let p = g.patches.iter().find(|p| p.name == name)?;
    let (mut sum, mut area) = (0.0, 0.0);
    for face in p.faces.clone() {
        let a = g.mag_sf[face];
        sum += f(values[face - g.n_internal], face) * a;
        area += a;
    }
    (area > 0.0).then(|| sum / area)
}

/// The solver faces of patch `p` and the sign that turns their area vectors out of the domain
/// on this side: its own faces, or a cyclic patch's pair faces (whose S_f points out of the
/// side listed first, [`fv::CyclicSide`]).
fn solver_faces(p: &fv::FvPatch) -> (std::ops::Range<usize>, f64) {
    match &p.cyclic {
        Some(c) => (c.pair_faces.clone(), if c.owner_side { 1.0 } else { -1.0 }),
        None => (p.faces.clone(), 1.0),
    }
}

impl RunFluid for NativeFluid {
    fn time(&self) -> f64 {
        self.fluid.time()
    }

    fn patch_pressure(&self, name: &str) -> Option<f64> {
        patch_mean(
            self.fluid.geometry(),
            name,
            self.fluid.p_boundary(),
            |p, _| p,
        )
    }

    fn inflow_velocity(&self, name: &str) -> Option<f64> {
        // the face fluxes φ = ε_f U_f·S_f the solver conserves (superficial), as grainPisoFoam
        // reports them: on a pressure-driven inlet they differ from the boundary velocity
        let g = self.fluid.geometry();
        let p = g.patches.iter().find(|p| p.name == name)?;
        let flux: f64 = p.face_fluxes(self.fluid.phi()).iter().sum();
        let area: f64 = g.mag_sf[solver_faces(p).0].iter().sum();
        (area > 0.0).then(|| -flux / area)
    }

    fn patch_faces(&self, name: &str) -> Option<crate::fluid::PatchFaces> {
        let g = self.fluid.geometry();
        let p = g.patches.iter().find(|p| p.name == name)?;
        let (faces, sign) = solver_faces(p);
        Some(crate::fluid::PatchFaces {
            sf: g.sf[faces.clone()].iter().map(|s| *s * sign).collect(),
            mag_sf: g.mag_sf[faces].to_vec(),
        })
    }

    fn patch_field(&self, name: &str, field: &str) -> Option<crate::fluid::FaceField> {
        use crate::fluid::FaceField;
        let g = self.fluid.geometry();
        let p = g.patches.iter().find(|p| p.name == name)?;
        if field == "phi" {
            return Some(FaceField::Scalar(p.face_fluxes(self.fluid.phi())));
        }
        // a cyclic patch's values are the linear interpolation across its pair faces, as
        // OpenFOAM evaluates a coupled patch field; another patch's are its boundary values
        let (faces, _) = solver_faces(p);
        let interp = |face: usize| {
            let w = g.weight[face];
            (w, g.owner[face] as usize, g.neighbour[face] as usize)
        };
        match field {
            "p" => Some(FaceField::Scalar(match p.is_cyclic() {
                true => faces
                    .map(|f| {
                        let (w, o, n) = interp(f);
                        w * self.fluid.p()[o] + (1.0 - w) * self.fluid.p()[n]
                    })
                    .collect(),
                false => self.fluid.p_boundary()[p.boundary_range(g.n_internal)].to_vec(),
            })),
            "U" => Some(FaceField::Vector(match p.is_cyclic() {
                true => faces
                    .map(|f| {
                        let (w, o, n) = interp(f);
                        self.fluid.u()[o] * w + self.fluid.u()[n] * (1.0 - w)
                    })
                    .collect(),
                false => self.fluid.u_boundary()[p.boundary_range(g.n_internal)].to_vec(),
            })),
            _ => None,
        }
    }

    fn write_time(
        &mut self,
        cfd: &Path,
        mesh: &PolyMesh,
        step: &CouplingStep,
    ) -> Result<String, SideError> {
        let name = self.fluid.time_name();
        self.fluid.write(&name)?;
        couple::output::write_fields(
            &cfd.join(&name),
            &name,
            mesh,
            step,
            foam::Format::Ascii,
            self.fluid.voidfraction_file(),
        )?;
        Ok(name)
    }
}

/// Where a native deck's screen output goes: LIGGGHTS's log file (`DEM/log.liggghts`, or the
/// file the deck's `log` command names), and the warnings, kept for the run's log.
struct DemLog {
    file: Option<BufWriter<File>>,
    warnings: Vec<String>,
    error: Option<String>,
}

impl DemLog {
    fn open(&mut self, path: &Path, append: bool) {
        if let Some(mut f) = self.file.take() {
            let _ = f.flush();
        }
        let file = dem::deck::open_output(path, append);
        match file {
            Ok(f) => self.file = Some(BufWriter::new(f)),
            Err(e) => {
                self.error
                    .get_or_insert(format!("cannot open the DEM log {}: {e}", path.display()));
            }
        }
    }

    fn line(&mut self, text: &str) {
        if let Some(f) = &mut self.file {
            if let Err(e) = writeln!(f, "{text}").and_then(|_| f.flush()) {
                self.error
                    .get_or_insert(format!("cannot write the DEM log: {e}"));
            }
        }
    }

    fn event(&mut self, e: DeckEvent, deck: &Path) {
        match e {
            DeckEvent::Output(l) => self.line(&l),
            DeckEvent::Log { path, append } => match path {
                Some(p) => self.open(&p, append),
                None => self.file = None,
            },
            DeckEvent::Warning { line, message } => {
                let w = format!("{}:{line}: {message}", deck.display());
                self.line(&format!("WARNING: {w}"));
                self.warnings.push(w);
            }
            DeckEvent::RunStart { .. } | DeckEvent::Progress { .. } => {}
        }
    }
}

/// Executes `deck` on the native DEM in `dem_dir` (its relative paths resolve there, as
/// LIGGGHTS's in its working directory), its screen output going to `dem_dir/log.liggghts` or
/// where its `log` command says; the deck's warnings are passed to `warn`.
pub fn run_native_deck(
    deck: &Deck,
    dem_dir: &Path,
    warn: &mut dyn FnMut(String),
) -> Result<NativeDem, dem::DemError> {
    let log = Arc::new(Mutex::new(DemLog {
        file: None,
        warnings: Vec::new(),
        error: None,
    }));
    lock(&log).open(&dem_dir.join("log.liggghts"), false);
    let sink = Arc::clone(&log);
    let file = deck.file.clone();
    let mut session = Session::new(dem_dir, move |e| lock(&sink).event(e, &file));
    let result = session
        .execute(deck)
        .and_then(|_| session.simulation().map(|_| ()));
    for w in std::mem::take(&mut lock(&log).warnings) {
        warn(w);
    }
    result?;
    if let Some(e) = lock(&log).error.take() {
        return Err(dem::DemError::Setup(e));
    }
    Ok(NativeDem { session, log })
}

fn lock(log: &Mutex<DemLog>) -> std::sync::MutexGuard<'_, DemLog> {
    // a panic while holding the lock cannot leave the log inconsistent: use it anyway
    log.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The native DEM as the particle side: the run deck's [`Session`], continued between
/// exchanges as CFDEM continues LIGGGHTS (thermo rows, `fix print`s and dumps as the deck
/// says).
pub struct NativeDem {
    session: Session<'static>,
    log: Arc<Mutex<DemLog>>,
}

impl NativeDem {
    /// The simulation (particles, dumps, step count).
    pub fn sim(&self) -> &Simulation {
        self.session
            .sim()
            .expect("run_native_deck builds the simulation")
    }

    fn log_error(&self) -> Result<(), SideError> {
        match lock(&self.log).error.take() {
            Some(e) => Err(e.into()),
            None => Ok(()),
        }
    }
}

impl ParticleSide for NativeDem {
    fn advance(&mut self, steps: u64) -> Result<(), SideError> {
        self.session.advance(steps)?;
        self.log_error()
    }

    /// Any deck command (CFDEM's `liggghtsCommands`: `write_restart`, `run`, `fix`…), with the
    /// run deck's variables.
    fn command(&mut self, command: &str) -> Result<(), SideError> {
        self.session
            .command_text(command, Path::new("liggghtsCommands"))?;
        self.log_error()
    }

    fn time_step(&self) -> f64 {
        self.sim().dt()
    }

    fn time(&self) -> f64 {
        self.sim().time()
    }

    fn state(&self) -> ParticleState<'_> {
        let p = &self.sim().particles;
        ParticleState {
            temperature: self.sim().temperature(),
            ids: &p.id,
            position: &p.x,
            velocity: &p.v,
            radius: &p.radius,
            density: &p.density,
        }
    }

    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError> {
        self.session.simulation()?.set_coupling(f_ext, beta, u_f)?;
        Ok(())
    }

    fn set_heat_flux(&mut self, q: &[f64]) -> Result<(), SideError> {
        self.session.simulation()?.set_convective_heat_flux(q)?;
        Ok(())
    }
}
