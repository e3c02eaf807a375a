//! The coupler's share of README's main job, on its own: one [`Coupler::exchange`] (locate,
//! voidage shares, ε, interpolation, forces, Ksl/Us/f) per coupling step of the Ergun case
//! (`openfoam-cases/ergun`: its O-grid of 4480 hexahedra, its `couplingProperties` — divided
//! voidage, Gidaspow drag, gradP, viscous and Archimedes forces, model A — and its ρ, ν, g),
//! with 10 000 spheres of d = 1 mm, ρ_p = 2000 kg/m³ at random in the bed region (r < 12 mm,
//! 0 < z < 15.5 mm, where the packed bed lies), uniform upward flow. Between steps every
//! particle moves by up to 10 µm (a coupling interval of the run moves them less), so the cell
//! hints of the previous step are used as in the run; steps are recycled as `Coupler::run`
//! does.
//!
//! Prints the median wall time per step, and the CPU time per step over all threads, which
//! depends less on the other load of a shared machine, for each method. In the main job one
//! coupled step took 160–410 ms of wall time on the loaded 2-core development machine (DEM
//! ≈ 84 %), so issue 17's target of at most 5 % for the coupling is 8–20 ms per step.
//! `docs/speed.md` has the figures measured.
//!
//! Run: `cargo bench -p couple --bench ergun_coupling`; `ERGUN_STEPS` sets the steps timed
//! (default 60), `ERGUN_METHODS` a comma-separated list of voidage methods (default: the
//! case's `divided`, then centre and exact).

use couple::config::CouplingConfig;
use couple::{Coupler, FluidState, ParticleState};
use mesh::v3::V3;
use std::path::Path;
use std::time::Instant;
use testkit::{cpu_seconds, SplitMix};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../openfoam-cases/ergun/CFD");
    let mesh = foam::read_poly_mesh(&case.join("constant/polyMesh")).expect("the Ergun mesh");
    let config = CouplingConfig::read_case(&case).expect("the Ergun couplingProperties");
    let case_settings = config.coupler_settings(&case).expect("the Ergun settings");
    let steps: usize = std::env::var("ERGUN_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let methods = std::env::var("ERGUN_METHODS").unwrap_or_else(|_| "divided,centre,exact".into());

    let n = 10_000;
    let mut rng = SplitMix(29);
    let mut pos = Vec::with_capacity(n);
    while pos.len() < n {
        let (x, y) = (
            0.012 * (2.0 * rng.unit() - 1.0),
            0.012 * (2.0 * rng.unit() - 1.0),
        );
        if x * x + y * y < 0.012 * 0.012 {
            pos.push(V3::new(x, y, 0.0005 + 0.015 * rng.unit()));
        }
    }
    let ids: Vec<u64> = (1..=n as u64).collect();
    let vel = vec![V3::zeros(); n];
    let rad = vec![0.0005; n];
    let den = vec![2000.0; n];
    let cells = mesh.n_cells;
    let u = vec![V3::new(0.0, 0.0, 0.01); cells];
    let p = vec![0.0; cells];
    let grad_p = vec![V3::new(0.0, 0.0, -8000.0); cells];
    let div_tau = vec![V3::zeros(); cells];
    let fluid = FluidState {
        vorticity: None,
        ddt_u: None,
        turbulence: None,
        temperature: None,
        u: &u,
        p: &p,
        grad_p: &grad_p,
        div_tau: &div_tau,
    };
    println!(
        "Ergun case coupling step: {} cells, {} particles, {} threads, {} steps",
        cells,
        n,
        rayon::current_num_threads(),
        steps
    );
    for name in methods.split(',') {
        let mut settings = case_settings;
        settings.method = name.parse().expect("a voidage method");
        let mut coupler = Coupler::new(&mesh, settings).expect("a coupler on the Ergun mesh");
        let mut moving = pos.clone();
        let mut walk = SplitMix(31);
        let (mut wall, mut cpu) = (Vec::new(), Vec::new());
        for k in 0..steps + 3 {
            for x in &mut moving {
                *x += V3::from_fn(|_, _| 1e-5 * (2.0 * walk.unit() - 1.0));
            }
            let particles = ParticleState {
                temperature: None,
                ids: &ids,
                position: &moving,
                velocity: &vel,
                radius: &rad,
                density: &den,
            };
            let (t, c) = (Instant::now(), cpu_seconds());
            let step = coupler
                .exchange(&particles, &fluid)
                .expect("a coupling step");
            let (dt, dc) = (t.elapsed().as_secs_f64(), cpu_seconds() - c);
            coupler.recycle(std::hint::black_box(step));
            // The first steps locate without hints and fault the buffers in.
            if k >= 3 {
                wall.push(dt);
                cpu.push(dc);
            }
        }
        println!(
            "{:>15}: {:7.3} ms per step (wall median), {:7.3} ms CPU per step, {:>10.0} particles/s",
            name,
            1e3 * median(wall.clone()),
            1e3 * median(cpu),
            n as f64 / median(wall)
        );
    }
}
