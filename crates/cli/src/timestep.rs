//! `foamgrain timestep`: DEM and coupling time-step advice, from a CFDEM-layout case
//! (`CFD/constant/{couplingProperties,transportProperties}`, `CFD/system/controlDict`,
//! `DEM/in.liggghts_run` and `DEM/in.liggghts_init`) and/or command-line values (which win).
//!
//! With a case, the fluid's Courant number is also reported as OpenFOAM's solvers print it
//! (`fv::courant`: per cell ½ Δt Σ|φ_f|/V, its mean and max) from the face fluxes `phi` of a
//! written time (`--time`, default the latest time holding `phi`) and the case's `deltaT`
//! (or `--cfd-dt`).

use anyhow::{bail, Context};
use clap::Args;
use closures::{DragClosure, DragLaw};
use couple::timestep::{advise, TimestepInput, COUPLING_FRACTION};
use couple::CouplingConfig;
use foam::{Case, FieldValues, VolField};
use liggghts_deck::{Deck, Materials};
use std::path::{Path, PathBuf};

/// Arguments of `foamgrain timestep`.
#[derive(Args, Debug)]
pub struct TimestepArgs {
    /// The CFD case of a CFDEM-layout run (its `../DEM/in.liggghts_*` decks are read too).
    #[arg(long, value_name = "DIR")]
    pub case: Option<PathBuf>,
    /// Particle radius, m.
    #[arg(long)]
    pub radius: Option<f64>,
    /// Particle density, kg/m³.
    #[arg(long)]
    pub density: Option<f64>,
    /// Young's modulus, Pa.
    #[arg(long)]
    pub young: Option<f64>,
    /// Poisson ratio.
    #[arg(long)]
    pub poisson: Option<f64>,
    /// Coefficient of restitution.
    #[arg(long)]
    pub restitution: Option<f64>,
    /// Impact speed for the Hertz time, m/s.
    #[arg(long, default_value_t = 1.0)]
    pub impact_speed: f64,
    /// Fluid density, kg/m³.
    #[arg(long)]
    pub rho: Option<f64>,
    /// Fluid kinematic viscosity, m²/s.
    #[arg(long)]
    pub nu: Option<f64>,
    /// Drag law for the relaxation time (CFDEM name), default the case's or SchillerNaumannDrag.
    #[arg(long)]
    pub drag: Option<String>,
    /// Voidage at which the drag relaxation time is evaluated.
    #[arg(long, default_value_t = 1.0)]
    pub voidage: f64,
    /// Slip speed at which the drag relaxation time is evaluated, m/s.
    #[arg(long, default_value_t = 0.0)]
    pub slip: f64,
    /// DEM time step, s.
    #[arg(long)]
    pub dem_dt: Option<f64>,
    /// CFD time step, s.
    #[arg(long)]
    pub cfd_dt: Option<f64>,
    /// DEM steps per coupling step.
    #[arg(long)]
    pub coupling_interval: Option<u64>,
    /// Largest fluid speed, m/s (default: max |U| of the case's 0/U; unknown when 0/U is at
    /// rest — the Courant number from a written phi is then the figure to read).
    #[arg(long)]
    pub fluid_speed: Option<f64>,
    /// Smallest cell size, m (default: the smallest cell's V^(1/3)).
    #[arg(long)]
    pub cell_size: Option<f64>,
    /// Time directory of the case whose `phi` gives the Courant number (default: the latest
    /// time holding `phi`).
    #[arg(long, requires = "case")]
    pub time: Option<String>,
}

/// Runs the command.
pub fn run(a: &TimestepArgs) -> anyhow::Result<()> {
    let mut deck = Materials::default();
    let mut config = None;
    let (mut rho, mut nu, mut cfd_dt, mut speed, mut cell) = (None, None, None, None, None);
    if let Some(dir) = &a.case {
        for name in ["in.liggghts_run", "in.liggghts_init"] {
            let path = dir.join("../DEM").join(name);
            if path.is_file() {
                deck = deck.or(Deck::read(&path)?.materials());
            }
        }
        let c = CouplingConfig::read_case(dir)?;
        let (r, n) = couple::config::read_transport(dir)?;
        rho = Some(r);
        nu = Some(n);
        let case = Case::open(dir)?;
        let delta_t = case
            .control_dict()?
            .f64("deltaT")
            .map_err(|e| anyhow::anyhow!("{}: {e}", dir.join("system/controlDict").display()))?;
        cfd_dt = Some(delta_t);
        let mesh = case.read_mesh()?;
        let g = mesh::MeshGeometry::new(&mesh)?;
        cell = g
            .cell_volumes
            .iter()
            .copied()
            .reduce(f64::min)
            .map(f64::cbrt);
        speed = max_speed(dir, mesh.n_cells)?;
        config = Some(c);
        let step = a.cfd_dt.unwrap_or(delta_t);
        match fluid_courant(&case, &mesh, a.time.as_deref(), step)? {
            Some((time, co)) => println!(
                "{:<28} mean {:.6e} max {:.6e} (cell {}; phi of time {time}, deltaT {step:e} s)",
                "fluid Courant number", co.mean, co.max, co.max_cell
            ),
            None => println!(
                "{:<28} (no time directory of {} holds phi: run the case first)",
                "fluid Courant number",
                dir.display()
            ),
        }
    }
    let need = |v: Option<f64>, name: &str| -> anyhow::Result<f64> {
        match v {
            Some(x) => Ok(x),
            None => bail!("--{name} is needed (not found in the case)"),
        }
    };
    let drag = match (&a.drag, &config) {
        (Some(name), _) => DragClosure::from(DragLaw::from_name(name)?),
        (None, Some(c)) => c
            .forces
            .drag
            .map(|d| d.closure)
            .unwrap_or(DragLaw::SchillerNaumann.into()),
        (None, None) => DragLaw::SchillerNaumann.into(),
    };
    let input = TimestepInput {
        radius: need(a.radius.or(deck.radius), "radius")?,
        density: need(a.density.or(deck.density), "density")?,
        young: need(a.young.or(deck.young), "young")?,
        poisson: need(a.poisson.or(deck.poisson), "poisson")?,
        restitution: need(a.restitution.or(deck.restitution), "restitution")?,
        impact_speed: a.impact_speed,
        rho: need(a.rho.or(rho), "rho")?,
        nu: need(a.nu.or(nu), "nu")?,
        drag,
        voidage: a.voidage,
        slip: a.slip,
        dem_dt: a.dem_dt.or(deck.timestep),
        cfd_dt: a.cfd_dt.or(cfd_dt),
        coupling_interval: a
            .coupling_interval
            .or(config.as_ref().map(|c| c.coupling_interval)),
        fluid_speed: a.fluid_speed.or(speed),
        cell_size: a.cell_size.or(cell),
        coupling_fraction: COUPLING_FRACTION,
    };
    let advice = advise(&input)?;
    for (name, value, unit) in advice.rows() {
        match value {
            Some(v) => println!("{name:<28} {v:.6e} {unit}"),
            None => println!("{name:<28} (unknown)"),
        }
    }
    for w in &advice.warnings {
        println!("warning: {w}");
    }
    Ok(())
}

/// max |U| over the cells of `0/U`, if the file exists and the fluid is not at rest there.
fn max_speed(case: &Path, n_cells: usize) -> anyhow::Result<Option<f64>> {
    let path = case.join("0/U");
    if !path.exists() {
        return Ok(None);
    }
    let f = VolField::read(&path)?;
    match f
        .internal(n_cells)
        .map_err(anyhow::Error::msg)
        .with_context(|| path.display().to_string())?
    {
        // a fluid at rest in 0/U (a case started from rest) gives no speed: the CFL row is then
        // unknown, not 0
        FieldValues::Vector(u) => Ok(u
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .reduce(f64::max)
            .filter(|&s| s > 0.0)),
        FieldValues::Scalar(_) => bail!("{}: U must be a volVectorField", path.display()),
    }
}

/// The Courant number of the fluid step `dt` (s) from `phi` of the time `time` (or the latest
/// time holding `phi`), with that time's name; `None` when no time holds `phi`.
fn fluid_courant(
    case: &Case,
    mesh: &foam::PolyMesh,
    time: Option<&str>,
    dt: f64,
) -> anyhow::Result<Option<(String, fv::courant::Courant)>> {
    let path = match time {
        Some(t) => {
            let p = case.time_path(t).join("phi");
            if !p.is_file() {
                bail!("{}: no such file (--time {t})", p.display());
            }
            Some((t.to_owned(), p))
        }
        None => case
            .times()?
            .into_iter()
            .rev()
            .map(|t| (t.name, t.path.join("phi")))
            .find(|(_, p)| p.is_file()),
    };
    let Some((name, path)) = path else {
        return Ok(None);
    };
    let g = fv::geometry::FvGeometry::new(mesh)?;
    let phi = fv::fields::read_phi(&path, &g)?;
    Ok(Some((name, fv::courant::courant(&g, &phi, dt))))
}
