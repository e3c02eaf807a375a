//! Time per step of the native DEM on the settled 3000-sphere bed of the pour fixture
//! (`liggghts-inputs/pour.in`, state from LIGGGHTS's dump `pour_liggghts.txt`), on 1 and 2
//! threads. Items = particle-steps, so divan's throughput is particle-steps per second.
//! LIGGGHTS's figure for the same bed and deck: see `tests/fixtures/dem/README.md`.

use dem::Simulation;
use dem_io::{read_snapshot, ReadOptions, Selection};
use divan::counter::ItemsCount;
use divan::Bencher;
use liggghts_deck::Deck;

const STEPS: u64 = 100;

fn settled_bed() -> Simulation {
    let fixtures =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/dem");
    // the deck with nothing to insert and no steps: materials, walls, contact model, time step
    let vars = [("np", "0"), ("nsteps", "4")].map(|(a, b)| (a.to_string(), b.to_string()));
    let deck = Deck::read_with_vars(testkit::liggghts_input("pour.in"), &vars).unwrap();
    let dir = std::env::temp_dir().join(format!("dem-bench-{}", std::process::id()));
    let mut sim = Simulation::from_deck(&deck, &dir).unwrap();
    // time the dynamics, not the deck's dump
    assert!(sim.remove_dump("d"));
    let snap = read_snapshot(
        fixtures.join("pour_liggghts.txt"),
        &ReadOptions::default(),
        Selection::Last,
    )
    .unwrap();
    let ps = dem::from_dump::particles_from_snapshot(&snap, &[2500.0, 2000.0]).unwrap();
    sim.add_particles(&ps).unwrap();
    sim.run(STEPS).unwrap();
    let _ = std::fs::remove_dir_all(dir);
    sim
}

#[divan::bench(args = [1, 2], sample_count = 10)]
fn settled_pour_3000(bencher: Bencher, threads: usize) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut sim = pool.install(settled_bed);
    let n = sim.particles.len() as u64;
    bencher
        .counter(ItemsCount::new(n * STEPS))
        .bench_local(|| pool.install(|| sim.run(STEPS).unwrap()));
}

fn main() {
    divan::main();
}
