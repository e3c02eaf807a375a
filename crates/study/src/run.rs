//! One steady run: a frozen bed on one grid with one voidage method at one inlet velocity.
//!
//! 1. A work copy of the case's `CFD/` (`0/`, `constant/`, `system/`) gets the grid's
//!    `system/blockMeshDict` and `constant/polyMesh` from the template ([`crate::template`])
//!    and the inlet velocity in `0/U` (a `fixedValue` along the column axis, superficial — the
//!    inlet holds no particles).
//! 2. The native fluid ([`runner::native::NativeFluid`]) and a [`couple::Coupler`] with the
//!    case's coupling settings and the method asked for are built; the particles are the
//!    [`FrozenParticles`] of the packed bed, whose DEM step is the fluid's `deltaT` divided by
//!    `couplingInterval`, so that one coupling step is one fluid step.
//! 3. Coupling steps follow until the pressure drop and the total drag are steady
//!    ([`crate::steady`]) or `max_steps` is reached (the run is then marked not steady).
//!
//! Recorded (means over the last window of the steady-state criterion): the pressure drop ρ(p̄_inlet − p̄_outlet) (area means over the patches, Pa); the
//! total drag Σ_p β_p (u_f,p − v_p)·ê (N, ê the column axis, β as handed to the fluid's Ksl);
//! the total fluid force on the particles Σ_p F_p·ê (N: drag, pressure-gradient and viscous
//! forces — what balances A·Δp in a steady bed); at the last step, the spread of ε over the cells wholly inside
//! the bed ([`crate::spread`]); the smallest ε and the solid volume removed by the voidage
//! floor.

use crate::error::{io_err, StudyError};
use crate::frozen::FrozenParticles;
use crate::pack::PackedBed;
use crate::spread::{cells_in_layers, voidage_spread, Spread};
use crate::steady::{SteadyCriterion, SteadyMonitor};
use crate::template::Template;
use couple::{Coupler, CouplerSettings, FluidSide, ParticleSide};
use foam::{Item, Value, VolField};
use mesh::v3::V3;
use runner::native::NativeFluid;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use voidage::Method;

/// What every run of a study shares.
pub struct RunContext<'a> {
    /// The case's `CFD/` directory.
    pub cfd: &'a Path,
    /// The mesh template.
    pub template: &'a Template,
    /// The frozen bed.
    pub bed: &'a PackedBed,
    /// The case's coupling settings (the method is replaced per run).
    pub settings: CouplerSettings,
    /// The fluid model.
    pub model: fv::Model,
    /// `couplingInterval`.
    pub coupling_interval: u64,
    /// Unit vector up the column (against gravity).
    pub axis: V3,
    /// Inlet and outlet patch names.
    pub inlet: &'a str,
    /// The outlet patch.
    pub outlet: &'a str,
    /// The bed's extent along the axis, m: (floor, top).
    pub bed_range: (f64, f64),
    /// When a run is steady.
    pub criterion: SteadyCriterion,
    /// Largest number of coupling (= fluid) steps per run.
    pub max_steps: u64,
    /// Where the work cases go (one subdirectory per grid).
    pub work: &'a Path,
}

/// The outcome of one run (module docs for the quantities).
#[derive(Clone, Debug, Serialize)]
pub struct RunResult {
    /// Cells per direction.
    pub n: [usize; 3],
    /// Number of cells.
    pub cells: usize,
    /// The voidage method.
    pub method: String,
    /// Superficial inlet velocity, m/s.
    pub velocity: f64,
    /// ρ (p̄_inlet − p̄_outlet), Pa.
    pub pressure_drop: f64,
    /// Σ β (u_f − v)·ê, N.
    pub drag: f64,
    /// Σ F·ê over all fluid forces, N.
    pub fluid_force: f64,
    /// ε over the cells wholly inside the bed (`None` if no layer of cells fits in it).
    pub spread: Option<Spread>,
    /// Smallest cell ε before clipping.
    pub min_voidage: f64,
    /// Solid volume removed by the voidage floor, m³.
    pub clipped_volume: f64,
    /// Fluid steps taken.
    pub steps: u64,
    /// True when the steady-state criterion was met.
    pub steady: bool,
    /// The largest relative difference of the last two window means of Δp, drag and force.
    pub last_change: f64,
    /// The largest (max − min)/mean of Δp, drag and force over the last window.
    pub fluctuation: f64,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
}

fn fluid_err(case: &Path) -> impl FnOnce(couple::SideError) -> StudyError + '_ {
    move |e| StudyError::Fluid {
        case: case.to_owned(),
        message: e.to_string(),
    }
}

/// Copies `from` into `to` recursively, leaving out `constant/polyMesh` and time
/// directories other than `0`.
fn copy_case(from: &Path, to: &Path, top: bool) -> Result<(), StudyError> {
    std::fs::create_dir_all(to).map_err(io_err(to))?;
    for e in std::fs::read_dir(from).map_err(io_err(from))? {
        let e = e.map_err(io_err(from))?;
        let name = e.file_name().to_string_lossy().into_owned();
        let path = e.path();
        if path.is_dir() {
            let keep = if top {
                matches!(name.as_str(), "0" | "constant" | "system")
            } else {
                name != "polyMesh"
            };
            if keep {
                copy_case(&path, &to.join(&name), false)?;
            }
        } else if !top {
            std::fs::copy(&path, to.join(&name)).map_err(io_err(&path))?;
        }
    }
    Ok(())
}

/// Sets the inlet patch of `0/U` in `cfd` to a fixed value `u` along `axis`, and the
/// internal field to the same (a start close to the solution).
fn set_inlet_velocity(cfd: &Path, inlet: &str, u: V3) -> Result<(), StudyError> {
    let path = cfd.join("0/U");
    let mut f = VolField::read(&path)?;
    let vec = Item::List(u.iter().map(|&x| Item::Scalar(x)).collect());
    let uniform = Value::Stream(vec![Item::Word("uniform".into()), vec.clone()]);
    let Some(Value::Dict(bf)) = f.body.get_mut("boundaryField") else {
        return Err(StudyError::Setup {
            file: path,
            message: "boundaryField is not a dictionary".into(),
        });
    };
    let Some(Value::Dict(p)) = bf.get_mut(inlet) else {
        return Err(StudyError::Setup {
            file: path,
            message: format!("boundaryField has no patch `{inlet}`"),
        });
    };
    p.set("type", Value::Stream(vec![Item::Word("fixedValue".into())]));
    p.set("value", uniform.clone());
    f.body.set("internalField", uniform);
    f.write(&path, foam::Format::Ascii)?;
    Ok(())
}

/// Area-weighted mean of the boundary pressure over the patch `name` (kinematic, m²/s²).
fn patch_mean_pressure(fluid: &fv::Fluid, name: &str) -> Option<f64> {
    let g = fluid.geometry();
    let p = g.patches.iter().find(|p| p.name == name)?;
    let (mut s, mut a) = (0.0, 0.0);
    for f in p.faces.clone() {
        s += fluid.p_boundary()[f - g.n_internal] * g.mag_sf[f];
        a += g.mag_sf[f];
    }
    (a > 0.0).then_some(s / a)
}

/// The layer planes of the template's box along z for `nz` layers.
pub fn z_planes(template: &Template, nz: usize) -> Vec<f64> {
    mesh::build::graded_planes(template.lo[2], template.hi[2], nz.max(1), 1.0)
}

impl RunContext<'_> {
    /// Runs one grid `n` with `method` at superficial velocity `velocity` (m/s).
    pub fn run(
        &self,
        n: [usize; 3],
        method: Method,
        velocity: f64,
    ) -> Result<RunResult, StudyError> {
        let t0 = Instant::now();
        let work: PathBuf = self.work.join(format!("grid-{}x{}x{}", n[0], n[1], n[2]));
        if work.exists() {
            std::fs::remove_dir_all(&work).map_err(io_err(&work))?;
        }
        copy_case(self.cfd, &work, true)?;
        let mesh = self.template.write_case_mesh(&work, n)?;
        let ax = self.axis;
        set_inlet_velocity(&work, self.inlet, velocity * ax)?;

        let rho = self.settings.physics.rho;
        let mut fluid =
            NativeFluid::open_case(&work, self.model, true, true, rho).map_err(fluid_err(&work))?;
        for patch in [self.inlet, self.outlet] {
            if !fluid
                .fluid()
                .geometry()
                .patches
                .iter()
                .any(|p| p.name == patch)
            {
                return Err(StudyError::Setup {
                    file: self.template.path.clone(),
                    message: format!("the mesh has no patch `{patch}`"),
                });
            }
        }
        let dt_fluid = fluid.fluid().settings.delta_t;
        let mut particles =
            FrozenParticles::new(self.bed.clone(), dt_fluid / self.coupling_interval as f64)
                .map_err(fluid_err(&work))?;
        let mut settings = self.settings;
        settings.method = method;
        let mut coupler = Coupler::new(&mesh, settings)?;
        // The voidage before the first step, so that ε old = ε new from the start (no ∂ε/∂t).
        coupler.exchange(&particles.state(), &fluid.state())?;

        let zs = z_planes(self.template, n[2]);
        let bed_cells = cells_in_layers(n, &zs, self.bed_range.0, self.bed_range.1);
        let mut monitor = SteadyMonitor::new();
        let mut last = None;
        let mut steady = false;
        for _ in 0..self.max_steps {
            let step = coupler.step(&mut particles, &mut fluid)?;
            let p_in = patch_mean_pressure(fluid.fluid(), self.inlet).unwrap_or(0.0);
            let p_out = patch_mean_pressure(fluid.fluid(), self.outlet).unwrap_or(0.0);
            let dp = rho * (p_in - p_out);
            let state = particles.state();
            let (mut drag, mut force) = (0.0, 0.0);
            for (i, c) in step.forces.particles.iter().enumerate() {
                let slip = c.u_f - state.velocity[i];
                drag += c.beta_fluid * slip.dot(&ax);
                force += c.total.dot(&ax);
            }
            monitor.push(&[dp, drag, force]);
            let spread = voidage_spread(
                &step.voidage.epsilon,
                coupler.voidage_mesh().cell_volumes(),
                &bed_cells,
            );
            last = Some((
                spread,
                step.voidage.min_epsilon,
                step.voidage.clipped_volume,
            ));
            coupler.recycle(step);
            if monitor.is_steady(&self.criterion) {
                steady = true;
                break;
            }
        }
        let (spread, min_voidage, clipped_volume) =
            last.ok_or_else(|| StudyError::Option("max_steps must be at least 1".into()))?;
        let mean = monitor.mean(&self.criterion);
        let (pressure_drop, drag, fluid_force) = (mean[0], mean[1], mean[2]);
        Ok(RunResult {
            n,
            cells: mesh.n_cells,
            method: method.name().into(),
            velocity,
            pressure_drop,
            drag,
            fluid_force,
            spread,
            min_voidage,
            clipped_volume,
            steps: monitor.len() as u64,
            steady,
            last_change: monitor.last_change(&self.criterion),
            fluctuation: monitor.fluctuation(&self.criterion),
            seconds: t0.elapsed().as_secs_f64(),
        })
    }
}
