//! In-process LIGGGHTS (feature `link`; needs libliggghts and the `liggghts` binary):
//! - `exchange_10k`: one exchange for 10,000 spheres — the pull of id, x, v, radius, density
//!   (`refresh`) and the push of dragforce, Ksl, uf (`set_forces`), separately;
//! - `ergun_interval`: one coupling interval (50 DEM steps) of the Ergun run deck on its
//!   10,000-sphere bed (packed by the case's init deck with the binary, 3000 settling steps),
//!   LIGGGHTS in-process vs the native DEM (1 rayon thread each; LIGGGHTS is serial).
//!
//! `cargo bench -p liggghts --features link`. MPI is initialised once in `main`.
//!
//! Measured on the 2-core development machine (shared, medians): pull 90 µs + push 72 µs per
//! exchange of 10,000 spheres with rank-local arrays (236 µs + 196 µs with CFDEM's
//! `data_liggghts_to_of`/`data_of_to_liggghts` over `[maxtag]` buffers, 2026-11); Ergun interval 477 ms in LIGGGHTS (9.5 ms per step) vs
//! 308 ms native on one thread (6.2 ms per step); stage 1 (10,000 spheres, 3000 steps) 14.7 s.

use couple::ParticleSide;
use divan::counter::ItemsCount;
use divan::Bencher;
use liggghts::LiggghtsDem;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

struct Held(Option<LiggghtsDem>);
// SAFETY: divan runs these benchmarks on the main thread only (threads = 1); the handle is
// never used concurrently.
unsafe impl Send for Held {}

static GRID: Mutex<Held> = Mutex::new(Held(None));
static ERGUN: Mutex<Held> = Mutex::new(Held(None));

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("liggghts-bench-{name}-{}", std::process::id()));
    std::fs::create_dir_all(d.join("post")).unwrap();
    d
}

/// 10,000 spheres (d = 1 mm) on a 25 × 20 × 20 simple-cubic lattice, 1.5 mm apart.
fn grid_deck(dir: &Path) -> PathBuf {
    let deck = dir.join("in.grid");
    std::fs::write(
        &deck,
        "atom_style granular\natom_modify map array\ncommunicate single vel yes\n\
         boundary f f f\nnewton off\nunits si\n\
         region reg block 0 0.0375 0 0.03 0 0.03 units box\ncreate_box 1 reg\n\
         neighbor 0.0002 bin\nneigh_modify delay 0\n\
         fix m1 all property/global youngsModulus peratomtype 5.e6\n\
         fix m2 all property/global poissonsRatio peratomtype 0.45\n\
         fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n\
         fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
         pair_style gran model hertz tangential history\npair_coeff * *\ntimestep 0.00001\n\
         lattice sc 0.0015 origin 0.5 0.5 0.5\ncreate_atoms 1 region reg\n\
         set group all diameter 0.001 density 2000\n\
         fix cfd all couple/cfd couple_every 50 mpi\nfix cfd2 all couple/cfd/force/implicit\n\
         fix integr all nve/sphere\n",
    )
    .unwrap();
    deck
}

#[divan::bench(sample_count = 20)]
fn exchange_10k_pull(bencher: Bencher) {
    let mut held = GRID.lock().unwrap();
    let dem = held.0.as_mut().unwrap();
    assert_eq!(dem.state().len(), 10_000);
    bencher
        .counter(ItemsCount::new(10_000u64))
        .bench_local(|| dem.refresh().unwrap());
}

#[divan::bench(sample_count = 20)]
fn exchange_10k_push(bencher: Bencher) {
    let mut held = GRID.lock().unwrap();
    let dem = held.0.as_mut().unwrap();
    let n = dem.state().len();
    let f = vec![mesh::v3::V3::new(1e-9, 0.0, 0.0); n];
    let beta = vec![1e-6; n];
    let u = vec![mesh::v3::V3::new(0.0, 0.0, 0.01); n];
    bencher
        .counter(ItemsCount::new(n as u64))
        .bench_local(|| dem.set_forces(&f, &beta, &u).unwrap());
}

const INTERVAL: u64 = 50;

#[divan::bench(sample_count = 5)]
fn ergun_interval_liggghts(bencher: Bencher) {
    let mut held = ERGUN.lock().unwrap();
    let dem = held.0.as_mut().unwrap();
    let n = dem.state().len() as u64;
    bencher
        .counter(ItemsCount::new(n * INTERVAL))
        .bench_local(|| dem.advance(INTERVAL).unwrap());
}

#[divan::bench(sample_count = 5)]
fn ergun_interval_native(bencher: Bencher) {
    let dir = ergun_dir();
    let deck = root().join("openfoam-cases/ergun/DEM/in.liggghts_run");
    let stripped = liggghts::CouplingDeck::read(&deck, &[])
        .unwrap()
        .without_runs();
    let d = liggghts_deck::Deck::parse(&stripped, &deck, &[]).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut sim = pool
        .install(|| dem::Simulation::from_deck(&d, &dir))
        .unwrap();
    sim.remove_dump("dmp");
    pool.install(|| sim.run(INTERVAL)).unwrap();
    let n = sim.particles.len() as u64;
    bencher
        .counter(ItemsCount::new(n * INTERVAL))
        .bench_local(|| pool.install(|| sim.run(INTERVAL).unwrap()));
}

fn ergun_dir() -> PathBuf {
    scratch("ergun")
}

fn main() {
    let universe = mpi::initialize().expect("MPI initialised once");
    let world = universe.world();
    let grid_dir = scratch("grid");
    GRID.lock().unwrap().0 =
        Some(LiggghtsDem::open(&world, &grid_deck(&grid_dir), &grid_dir, &[]).unwrap());
    // stage 1: the Ergun bed (10,000 spheres, 3000 settling steps instead of 20,000)
    let ergun = ergun_dir();
    let dem_dir = root().join("openfoam-cases/ergun/DEM");
    let vars = [("tsettle".to_string(), "3000".to_string())];
    let run = liggghts::run_deck(&dem_dir.join("in.liggghts_init"), &ergun, &vars, "init").unwrap();
    eprintln!(
        "stage 1 (LIGGGHTS binary): {:.1} s",
        run.elapsed.as_secs_f64()
    );
    let mut lig = LiggghtsDem::open(&world, &dem_dir.join("in.liggghts_run"), &ergun, &[]).unwrap();
    lig.command("undump dmp").unwrap();
    lig.advance(INTERVAL).unwrap();
    ERGUN.lock().unwrap().0 = Some(lig);
    divan::main();
    GRID.lock().unwrap().0 = None;
    ERGUN.lock().unwrap().0 = None;
    let _ = std::fs::remove_dir_all(grid_dir);
    let _ = std::fs::remove_dir_all(ergun);
    drop(universe);
}
