//! `foamgrain couple`: one-way coupling of a series of LIGGGHTS dumps with a frozen fluid
//! (U, p of a case time directory). Per snapshot it writes, into the time directory
//! `timestep × DEM step`, the fields `voidfraction`, `Ksl`, `Us`, `f` and a LIGGGHTS text dump
//! `particleForces` (id, position, velocity, radius, total fluid force fx fy fz, β), and reports
//! the volume and momentum accounting. In a decomposed case the four fields also go into each
//! `processorN/` piece (the frozen fluid is read from the reconstructed time).

use anyhow::{bail, Context};
use clap::Args;
use couple::frozen::FrozenFluid;
use couple::replay::{expand_glob, DumpReplay};
use couple::{Coupler, CouplingConfig, CouplingStep, FluidSide, ParticleSide};
use dem_io::{Boundary, BoxBounds, ReadOptions, Snapshot};
use foam::{Case, Format};
use serde::Serialize;
use std::path::{Path, PathBuf};
use voidage::Method;

/// Arguments of `foamgrain couple`.
#[derive(Args, Debug)]
pub struct CoupleArgs {
    /// OpenFOAM case (constant/polyMesh, constant/couplingProperties,
    /// constant/transportProperties with rho and nu, optional constant/g).
    #[arg(long, value_name = "DIR")]
    pub case: PathBuf,
    /// LIGGGHTS text or binary dumps; `*` and `?` in the file name (quote the pattern).
    #[arg(long, value_name = "GLOB")]
    pub dumps: PathBuf,
    /// Time directory holding the frozen U and p.
    #[arg(long, value_name = "T", default_value = "0")]
    pub time: String,
    /// Voidage method, overriding couplingProperties' voidFractionModel.
    #[arg(long)]
    pub method: Option<Method>,
    /// DEM time step in s (default: `timestep` of CASE/../DEM/in.liggghts_run).
    #[arg(long, value_name = "S")]
    pub dem_dt: Option<f64>,
    /// Particle density in kg/m³, for dumps without `density` or `mass` columns.
    #[arg(long, value_name = "KG_M3")]
    pub density: Option<f64>,
    /// Column names of binary dumps (space- or comma-separated).
    #[arg(long, value_name = "NAMES", num_args = 1.., value_delimiter = ',',
          default_values_t = dem_io::DEFAULT_BINARY_COLUMNS.map(String::from))]
    pub columns: Vec<String>,
    /// Print one JSON object per snapshot instead of text.
    #[arg(long)]
    pub json: bool,
}

/// One snapshot's accounting. Volumes m³, forces N, β kg/s.
#[derive(Serialize)]
struct Report {
    timestep: u64,
    time: String,
    dump: String,
    particles: usize,
    particle_volume: f64,
    deposited_volume: f64,
    outside_volume: f64,
    particles_outside: usize,
    clipped_volume: f64,
    min_voidage: f64,
    /// Σ_p β over particles feeding Ksl, and Σ_c V_c Ksl_c.
    sum_beta: f64,
    integral_ksl: f64,
    /// Σ_p β (u_f − v) + F_fluid and Σ_c V_c [Ksl_c (U_c − Us_c) − f_c].
    particle_momentum: [f64; 3],
    cell_momentum: [f64; 3],
    /// Σ of the total fluid force on the particles.
    total_fluid_force: [f64; 3],
}

/// Runs the command.
pub fn run(a: &CoupleArgs) -> anyhow::Result<()> {
    let case = Case::open(&a.case)?;
    let config = CouplingConfig::read_case(case.root())?;
    for w in &config.warnings {
        eprintln!("warning: {w}");
    }
    let dem_dt = match a.dem_dt {
        Some(dt) => dt,
        None => deck_time_step(case.root())?,
    };
    let files = expand_glob(&a.dumps)?;
    let cols: Vec<&str> = a
        .columns
        .iter()
        .flat_map(|c| c.split_whitespace())
        .collect();
    let options = ReadOptions::default().with_binary_columns(&cols);
    let mut replay = DumpReplay::open(files, options, dem_dt, a.density)?;
    let mut settings = config.coupler_settings(case.root())?;
    if let Some(m) = a.method {
        settings.method = m;
    }
    let f = fv::frozen::FrozenFields::read(case.root(), &a.time, settings.physics.nu)
        .with_context(|| format!("frozen fluid of time {}", a.time))?;
    let fluid = FrozenFluid::new(f.mesh, f.u, f.p, f.grad_p, f.div_tau, f.time);
    let mut coupler = Coupler::new(fluid.mesh(), settings)?;
    coupler.set_coupling_time_step(settings.coupling_interval as f64 * dem_dt);
    if let Some(s) = config.smoothing {
        coupler.set_smoothing(runner::smoothing::native(fluid.mesh(), s)?);
    }
    coupler.set_ksl_form(config.momentum.ksl_form());
    let pieces = foam::decomposed::pieces(&case, fluid.mesh().n_cells)?;
    loop {
        let step = coupler.exchange(&replay.state(), &fluid.state())?;
        let time = time_name(replay.timestep() as f64 * dem_dt);
        couple::output::write_fields(
            &case.time_path(&time),
            &time,
            fluid.mesh(),
            &step,
            Format::Ascii,
            None,
        )?;
        couple::output::write_fields_decomposed(&pieces, &time, &step, Format::Ascii)?;
        write_forces(&case, &time, &replay, &step, fluid.mesh())?;
        let r = report(&coupler, &replay, &fluid, &step, &time);
        if a.json {
            println!("{}", serde_json::to_string(&r)?);
        } else {
            print_text(&r, settings.method);
        }
        if !replay.next_snapshot()? {
            break;
        }
    }
    Ok(())
}

/// `timestep` of the DEM deck next to a CFDEM-layout case.
fn deck_time_step(case: &Path) -> anyhow::Result<f64> {
    let deck = case.join("../DEM/in.liggghts_run");
    if !deck.is_file() {
        bail!("no --dem-dt given and there is no {}", deck.display());
    }
    match liggghts_deck::Deck::read(&deck)?.time_step() {
        Some(dt) if dt > 0.0 => Ok(dt),
        _ => bail!("{}: no `timestep` line; give --dem-dt", deck.display()),
    }
}

pub use couple::output::time_name;

fn write_forces(
    case: &Case,
    time: &str,
    replay: &DumpReplay,
    s: &CouplingStep,
    mesh: &foam::PolyMesh,
) -> anyhow::Result<()> {
    let st = replay.state();
    let col = |f: &dyn Fn(usize) -> f64| (0..st.len()).map(f).collect::<Vec<f64>>();
    let c = &s.forces.particles;
    let names = "id x y z vx vy vz radius fx fy fz beta"
        .split(' ')
        .map(String::from)
        .collect();
    let data = vec![
        col(&|i| st.ids[i] as f64),
        col(&|i| st.position[i][0]),
        col(&|i| st.position[i][1]),
        col(&|i| st.position[i][2]),
        col(&|i| st.velocity[i][0]),
        col(&|i| st.velocity[i][1]),
        col(&|i| st.velocity[i][2]),
        col(&|i| st.radius[i]),
        col(&|i| c[i].total[0]),
        col(&|i| c[i].total[1]),
        col(&|i| c[i].total[2]),
        col(&|i| c[i].beta_dem.max(c[i].beta_fluid)),
    ];
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &mesh.points {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let snap = Snapshot::new(
        replay.timestep(),
        BoxBounds::orthogonal(lo, hi, Boundary::Fixed),
        names,
        data,
    )?;
    let path = case.time_path(time).join("particleForces");
    let mut out = Vec::new();
    dem_io::write_text(&mut out, &snap)?;
    foam::write_atomic(&path, &out).with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

fn report(
    coupler: &Coupler,
    replay: &DumpReplay,
    fluid: &FrozenFluid,
    s: &CouplingStep,
    time: &str,
) -> Report {
    let vols = coupler.voidage_mesh().cell_volumes();
    let u = fluid.state().u;
    let v = replay.state().velocity;
    let mut particle_momentum = [0.0; 3];
    let mut total = [0.0; 3];
    let mut sum_beta = 0.0;
    for (c, v) in s.forces.particles.iter().zip(v) {
        sum_beta += c.beta_fluid;
        for a in 0..3 {
            particle_momentum[a] += c.beta_fluid * (c.u_f[a] - v[a]) + c.f_fluid[a];
            total[a] += c.total[a];
        }
    }
    let ex = &s.exchange;
    let mut cell_momentum = [0.0; 3];
    for c in 0..vols.len() {
        for a in 0..3 {
            cell_momentum[a] += vols[c] * (ex.ksl[c] * (u[c][a] - ex.us[c][a]) - ex.f[c][a]);
        }
    }
    Report {
        timestep: replay.timestep(),
        time: time.to_string(),
        dump: replay.source().display().to_string(),
        particles: s.placement.len(),
        particle_volume: s.deposit.particle_volume,
        deposited_volume: s.deposit.deposited_volume,
        outside_volume: s.deposit.outside_volume,
        particles_outside: s.deposit.particles_outside,
        clipped_volume: s.voidage.clipped_volume,
        min_voidage: s.voidage.min_epsilon,
        sum_beta,
        integral_ksl: ex.total_ksl(vols),
        particle_momentum,
        cell_momentum,
        total_fluid_force: total,
    }
}

fn print_text(r: &Report, method: Method) {
    println!(
        "timestep {} (time {}): {} particles, {method} voidage",
        r.timestep, r.time, r.particles
    );
    println!(
        "  particle volume {:.6e} m³ = deposited {:.6e} + outside {:.6e} ({} particles outside); \
         clipped {:.3e}; min voidage {:.4}",
        r.particle_volume,
        r.deposited_volume,
        r.outside_volume,
        r.particles_outside,
        r.clipped_volume,
        r.min_voidage
    );
    println!(
        "  Σβ {:.6e} kg/s = ∫Ksl {:.6e}; momentum particles {:?} N, cells {:?} N",
        r.sum_beta, r.integral_ksl, r.particle_momentum, r.cell_momentum
    );
    println!(
        "  total fluid force on particles {:?} N",
        r.total_fluid_force
    );
}
