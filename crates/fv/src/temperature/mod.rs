//! The fluid's temperature T (K) as CFDEMcoupling-PUBLIC's `cfdemSolverPisoScalar` solves it
//! (`applications/solvers/cfdemSolverPisoScalar/cfdemSolverPisoScalar.C`), once per time step:
//!
//! ```text
//! ddt(ε,T) − Sp(ddt ε, T) + div(φ,T) − Sp(div φ, T) − laplacian(α_eff ε, T) = Tsource
//! α_eff = ν/Pr + α_t,   α_t = ν_t/Prt
//! ```
//!
//! ε the voidage, φ the superficial face flux (m³/s), ν the molecular viscosity (m²/s), ν_t the
//! k–ε eddy viscosity (0 when laminar), Pr and Prt the laminar and turbulent Prandtl numbers
//! ([`TemperatureSettings`]), Tsource (K/s per cell) the explicit source the coupling hands the
//! fluid ([`crate::Fluid::set_heat_source`], held until set again; the start time's `Tsource`
//! file when it has one, as cfdemSolverPisoScalar reads it, else 0). Discretisation
//! (OpenFOAM v1912): Euler, `fvm::ddt(ε,T)` = (ε T − ε° T°)/Δt and `fvc::ddt(ε)` = (ε − ε°)/Δt,
//! so the time term is ε° (T − T°)/Δt; Gauss convection with `div(phi,T)`'s weights
//! ([`crate::convection`]) minus (∇·φ) T implicit: with a uniform T the convection and the
//! time terms vanish whatever φ and ε do, and the equation is the non-conservative
//! ε ∂T/∂t + φ·∇T = ∇·(α_eff ε ∇T) + Tsource (with a PFM `thermCondModel`,
//! [`TemperatureSettings::bed`], the laminar ε ν/Pr is (k_bed/k_f) ν/Pr, [`conduction`]);
//! Gauss linear Laplacian with the face
//! diffusivity interpolated from the cells' α_eff ε (boundary faces: α_eff,b ε_b, ε_b the
//! `voidfraction` condition's) and the fluid's delta coefficients and non-orthogonal
//! correction. The matrix is [`ScalarEqn::transport`], the solver fvSolution's `T` entry.
//!
//! Where it sits in the step ([`crate::Fluid::advance`]): cfdemSolverPisoScalar solves T after
//! the coupling has set the step's ε and before the momentum predictor, with the face flux
//! `phi = voidfractionf*phiByVoidfraction` — the previous step's interstitial flux times the
//! new face voidage — and α_t from ν_t of the previous step's `turbulence->correct()`. The
//! native step does the same right after its old time levels (`old_time_levels`): ε and ε° are
//! the step's cell voidages ([`crate::Fluid::set_voidage`]'s `current` and `previous`; the
//! coupler passes the previous step's ε as `previous`), φ is
//!
//! ```text
//! φ_T = ε_f (φ° / ε°_f)
//! ```
//!
//! with φ° the fluid's current flux (the last solved step's) and ε_f, ε°_f the face voidages
//! of the step and of the step that formed φ° (`Fluid::eps_faces`: linear inside, the
//! `voidfraction` condition's on boundary faces) — φ°/ε°_f is the native counterpart of
//! CFDEM's `phiByVoidfraction`. After a solved step ε°_f is that step's face voidage (which
//! the coupler's `previous` repeats); on steps that hold the flow
//! ([`crate::Fluid::hold_step`]) it stays the last solved step's while ε moves on, as CFDEM's
//! `phiByVoidfraction` does under `solveFlow off`. On a run's first step φ° is the start
//! time's `phi` (written by a run with the voidage of its last step, ε°) or, without one, the
//! flux of U with ε ≡ 1, U_f·S, which the fluid forms before it has a voidage: then
//! φ_T = ε_f U_f·S, CFDEM's `phi` from its `phiByVoidfraction = U_f·S` at the start. ν_t is the k–ε model's of
//! the previous step. The written `alphat` holds ν_t/Prt of the last solve.
//!
//! Heat: the source enters as Tsource V (K·m³/s) against the time term ε° V (T − T°)/Δt, so a
//! heat rate Q (W) into the gas of a cell of volume V is Tsource = Q/(ρ c_p V) with the whole
//! cell's V — what CFDEM's `LaEuScalarTemp` hands over (−Σ q_p/(ρ c_p V)).
//!
//! Not done: the `backward` and `CrankNicolson` time schemes for T (refused), the radiation
//! source (cfdemSolverPisoScalar's `radiation->ST`; packedBedTemp has no `radiationProperties`,
//! so none there), and T on steps the fluid holds ([`crate::Fluid::hold`], `solveFlow off`),
//! which cfdemSolverPisoScalar still solves.

pub mod bc;
pub mod conduction;
pub mod settings;

pub use conduction::BedConduction;
pub use settings::TemperatureSettings;

use crate::error::{FvError, Result};
use crate::fvc::{self, Field};
use crate::geometry::FvGeometry;
use crate::linsolve::SolveStats;
use crate::turbulence::scalar_bc::{self, ScalarBc};
use crate::turbulence::scalar_eqn::{ScalarEqn, Transport};
use crate::turbulence::scalar_field::ScalarField;
use foam::{FieldValues, VolField};
use std::path::Path;

/// The temperature's state: T with its conditions, α_t when the case has `alphat`, and the
/// held source.
#[derive(Clone, Debug)]
pub struct Temperature {
    settings: TemperatureSettings,
    t: ScalarField,
    alphat: Option<ScalarField>,
    /// Tsource (K/s per cell).
    source: ScalarField,
    /// The face voidage the fluid's flux φ° was formed with.
    flux_voidage: FluxVoidage,
}

/// The face voidage the fluid's current flux was formed with (the divisor that turns it into
/// CFDEM's `phiByVoidfraction`).
#[derive(Clone, Debug)]
enum FluxVoidage {
    /// ε ≡ 1: the flux of U of a start without `phi`, formed before the fluid has a voidage.
    Unit,
    /// The previous step's, ε°_f: a start from a `phi` file (written with the voidage of the
    /// run's last step).
    Previous,
    /// These face values: the last step that solved the flow ([`Temperature::flux_formed_with`]).
    Faces(Vec<f64>),
}

/// What the T equation of a step takes from the fluid's step (see the module documentation).
pub struct HeatFlow<'a> {
    /// φ°, the previous step's final face flux (m³/s), one per face.
    pub phi_old: &'a [f64],
    /// ε at faces of the step (`current`).
    pub ef: &'a [f64],
    /// ε at faces of the previous step (the one φ° was formed with on a restart's first step).
    pub ef_old: &'a [f64],
    /// ε per cell of the step.
    pub eps: &'a [f64],
    /// ε° per cell.
    pub eps_old: &'a [f64],
    /// The step (s).
    pub dt: f64,
    /// Molecular kinematic viscosity ν (m²/s).
    pub nu: f64,
    /// ν_t at cells and boundary faces (m²/s), `None` when laminar.
    pub nut: Option<(&'a [f64], &'a [f64])>,
    /// Laplacian delta coefficient per face (1/m).
    pub lap_dc: &'a [f64],
    /// Explicit non-orthogonal correction of the Laplacian.
    pub corrected: bool,
}

impl Temperature {
    /// Reads `T` (it must exist), `alphat` and `Tsource` (when present) of the time directory
    /// `dir` (`alphat` only with Pr and Prt), with the conditions of [`bc`]; `phi` the start
    /// time's face fluxes (inletOutlet):
    /// the directory's `phi` when it has one, else the flux of U with ε ≡ 1.
    pub fn read(
        dir: &Path,
        mesh: &foam::PolyMesh,
        g: &FvGeometry,
        settings: TemperatureSettings,
        phi: &[f64],
    ) -> Result<Temperature> {
        let t_path = dir.join("T");
        if !t_path.is_file() {
            return Err(FvError::setting(
                &t_path,
                "T",
                "missing: a case with heat needs the start time's temperature field T",
            ));
        }
        let mut t = ScalarField::read(dir, "T", g, |path, file| {
            bc::read_temperature(path, file, mesh, g)
        })?;
        // inletOutlet faces as OpenFOAM evaluates them with the start flux
        t.evaluate(g, phi);
        // PFM's constant DT reads no alphat (its solver has no turbulent diffusivity)
        let with_alphat = settings.diffusivity.turbulent_prandtl().is_some();
        let alphat = if with_alphat && dir.join("alphat").is_file() {
            Some(ScalarField::read(dir, "alphat", g, |path, file| {
                bc::read_alphat(path, file, mesh, g, &t.bcs)
            })?)
        } else {
            None
        };
        let source = if dir.join("Tsource").is_file() {
            ScalarField::read(dir, "Tsource", g, |_, _| Ok(zero_gradient(g)))?
        } else {
            let location = dir
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned());
            let file = VolField::new(
                "Tsource",
                &location,
                [0, 0, -1, 1, 0, 0, 0],
                FieldValues::Scalar(vec![0.0; g.n_cells]),
                foam::field::default_boundary(&mesh.boundary, "zeroGradient", None),
            );
            ScalarField {
                cells: vec![0.0; g.n_cells],
                boundary: vec![0.0; g.n_boundary()],
                bcs: zero_gradient(g),
                file,
            }
        };
        Ok(Temperature {
            settings,
            t,
            alphat,
            source,
            flux_voidage: match dir.join("phi").is_file() {
                true => FluxVoidage::Previous,
                false => FluxVoidage::Unit,
            },
        })
    }

    /// T per cell (K).
    pub fn cells(&self) -> &[f64] {
        &self.t.cells
    }

    /// T per boundary face (K).
    pub fn boundary(&self) -> &[f64] {
        &self.t.boundary
    }

    /// The held source Tsource per cell (K/s).
    pub fn source(&self) -> &[f64] {
        &self.source.cells
    }

    /// Sets the source Tsource (K/s per cell, finite), held until set again.
    pub fn set_source(&mut self, g: &FvGeometry, s: &[f64]) -> Result<()> {
        FvError::check_len("Tsource", s.len(), g.n_cells)?;
        if let Some(c) = s.iter().position(|v| !v.is_finite()) {
            return Err(FvError::Value {
                what: format!("Tsource at cell {c}"),
                msg: format!("{} is not finite", s[c]),
            });
        }
        self.source.cells.copy_from_slice(s);
        self.source.evaluate(g, &vec![0.0; g.n_faces()]);
        Ok(())
    }

    /// One step of the T equation (see the module documentation): its solve.
    pub fn solve(&mut self, g: &FvGeometry, flow: &HeatFlow<'_>) -> Result<SolveStats> {
        // CFDEM's phi = voidfractionf*phiByVoidfraction at this point of the step
        let divisor = match &self.flux_voidage {
            FluxVoidage::Unit => None,
            FluxVoidage::Previous => Some(flow.ef_old),
            FluxVoidage::Faces(v) => Some(&v[..]),
        };
        let phi: Vec<f64> = match divisor {
            None => (0..g.n_faces())
                .map(|f| flow.ef[f] * flow.phi_old[f])
                .collect(),
            Some(d) => (0..g.n_faces())
                .map(|f| match d[f] > 0.0 {
                    true => flow.ef[f] * (flow.phi_old[f] / d[f]),
                    false => 0.0,
                })
                .collect(),
        };
        let gamma_f = self.diffusivity(g, flow);
        let t_old = self.t.cells.clone();
        let transport = Transport {
            phi: &phi,
            lap_dc: flow.lap_dc,
            corrected: flow.corrected,
            dt: flow.dt,
            crank_nicolson: None,
            ddt_weight: Some((flow.eps, flow.eps_old)),
            div_phi: None,
        };
        let scheme = self.settings.scheme;
        let mut eqn = ScalarEqn::transport(
            g,
            &transport,
            &scheme,
            &self.t.cells,
            &t_old,
            &self.t.boundary,
            &self.t.bcs,
            &gamma_f,
        );
        // − Sp(fvc::ddt(ε), T), − Sp(fvc::div(φ), T)
        let rdt = 1.0 / flow.dt;
        let ddt_eps: Vec<f64> = (0..g.n_cells)
            .map(|c| -(rdt * (flow.eps[c] - flow.eps_old[c])))
            .collect();
        eqn.add_sp(g, &ddt_eps);
        let div_phi: Vec<f64> = fvc::surface_integrate(g, &phi).iter().map(|d| -d).collect();
        eqn.add_sp(g, &div_phi);
        eqn.add_source(g, &self.source.cells);
        let stats = eqn.solve(g, &scheme.solver, &mut self.t.cells, "T")?;
        if let Some(c) = self.t.cells.iter().position(|v| !v.is_finite()) {
            return Err(FvError::Diverged(format!("T is not finite at cell {c}")));
        }
        self.t.evaluate(g, &phi);
        Ok(stats)
    }

    /// Records the face voidage `ef` the fluid formed its new flux with (after a step that
    /// solved the flow): the next T steps divide the flux by it, held steps too.
    pub fn flux_formed_with(&mut self, ef: Vec<f64>) {
        self.flux_voidage = FluxVoidage::Faces(ef);
    }

    /// The face diffusivity α_eff ε (m²/s) of the step, interpolated linearly from the cells'
    /// and boundary faces' products (as OpenFOAM interpolates the field `alphaEff*voidfraction`),
    /// after updating α_t = ν_t/Prt (cells; boundary faces by α_t's conditions, `calculated`
    /// and the accepted wall functions ν_t,b/Prt; without an `alphat` file ν_t,b/Prt).
    fn diffusivity(&mut self, g: &FvGeometry, flow: &HeatFlow<'_>) -> Vec<f64> {
        let alpha = self.settings.diffusivity.laminar(flow.nu);
        let zeros = (vec![0.0; g.n_cells], vec![0.0; g.n_boundary()]);
        let (nut_c, nut_b) = flow.nut.unwrap_or((&zeros.0, &zeros.1));
        // PFM's constant DT has no turbulent part (and reads no alphat)
        let prt = self.settings.diffusivity.turbulent_prandtl();
        let (mut at_c, mut at_b): (Vec<f64>, Vec<f64>) = match prt {
            Some(prt) => (
                nut_c.iter().map(|n| n / prt).collect(),
                nut_b.iter().map(|n| n / prt).collect(),
            ),
            None => zeros.clone(),
        };
        if let Some(a) = &mut self.alphat {
            a.cells.clone_from(&at_c);
            for (p, bc) in g.patches.iter().zip(&a.bcs) {
                if *bc == ScalarBc::Calculated {
                    for i in p.boundary_range(g.n_internal) {
                        a.boundary[i] = at_b[i];
                    }
                }
            }
            scalar_bc::evaluate(
                g,
                &a.bcs,
                &a.cells,
                &vec![0.0; g.n_faces()],
                &mut a.boundary,
            );
            at_c.clone_from(&a.cells);
            at_b.clone_from(&a.boundary);
        }
        let (mut cells, mut b): (Vec<f64>, Vec<f64>) = (
            (0..g.n_cells)
                .map(|c| (alpha + at_c[c]) * flow.eps[c])
                .collect(),
            (0..g.n_boundary())
                .map(|i| (alpha + at_b[i]) * flow.ef[g.n_internal + i])
                .collect(),
        );
        if let Some(bed) = self.settings.bed {
            // ε k_f → k_bed(ε) in the laminar part; boundary faces ε_b k_bed(ε_o)/ε_o
            // (PFM's zeroGradient thCond)
            let ratio: Vec<f64> = flow.eps.iter().map(|&e| bed.ratio(e)).collect();
            for (c, d) in cells.iter_mut().enumerate() {
                *d = alpha * ratio[c] + at_c[c] * flow.eps[c];
            }
            for (i, d) in b.iter_mut().enumerate() {
                let f = g.n_internal + i;
                let o = g.owner[f] as usize;
                let per_eps = ratio[o] / flow.eps[o];
                *d = (alpha * per_eps + at_b[i]) * flow.ef[f];
            }
        }
        fvc::interpolate(g, Field::new(&cells, &b))
    }

    /// Writes `T`, `Tsource` and (when the case has it) `alphat` into the time directory `dir`.
    pub fn write(&self, g: &FvGeometry, dir: &Path, format: foam::Format) -> Result<()> {
        self.t.write(g, &dir.join("T"), format)?;
        self.source.write(g, &dir.join("Tsource"), format)?;
        if let Some(a) = &self.alphat {
            a.write(g, &dir.join("alphat"), format)?;
        }
        Ok(())
    }
}

/// Zero-gradient conditions on every patch (`empty` and `cyclic` ones their own): Tsource's,
/// whose boundary values are only written.
fn zero_gradient(g: &FvGeometry) -> Vec<ScalarBc> {
    g.patches
        .iter()
        .map(|p| match () {
            _ if p.is_empty() => ScalarBc::Empty,
            _ if p.is_cyclic() => ScalarBc::Cyclic,
            _ => ScalarBc::ZeroGradient,
        })
        .collect()
}
