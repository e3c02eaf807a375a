//! LIGGGHTS in-process on every rank of MPI_COMM_WORLD (run under `mpirun -np 2`; the test
//! `tests/link_ranks.rs` does): each rank fills only its share of the forces and sends nonsense
//! for the rest, which LIGGGHTS must never see; every rank must get all particles back.
//! Exits with status 1 (and a message) when a velocity misses v = (g + F/m) t.

use couple::ParticleSide;
use mesh::v3::V3;
use mpi::topology::Communicator;
use std::path::Path;

fn main() {
    let universe = mpi::initialize().expect("MPI initialised once");
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/decks/falling.in");
    let dir = std::env::args().nth(1).expect("usage: two_ranks WORKDIR");
    let mut lig = liggghts::LiggghtsDem::open(&world, &deck, Path::new(&dir), &[]).unwrap();
    let n = lig.state().len();
    let mine = lig.share_range();
    // F = (0, 0, 1e-6·tag) N on the own share, 1 N (nonsense) elsewhere
    let f: Vec<V3> = (0..n)
        .map(|i| {
            if mine.contains(&i) {
                V3::new(0.0, 0.0, 1e-6 * (i + 1) as f64)
            } else {
                V3::repeat(1.0)
            }
        })
        .collect();
    lig.set_forces(&f, &vec![0.0; n], &vec![V3::zeros(); n])
        .unwrap();
    lig.advance(100).unwrap();
    let m = 2000.0 * std::f64::consts::PI / 6.0 * 1e-9;
    let t = 100.0 * lig.time_step();
    let s = lig.state();
    let mut ok = s.ids == [1, 2, 3];
    for i in 0..n {
        let v = (-9.81 + 1e-6 * (i + 1) as f64 / m) * t;
        ok &= (s.velocity[i][2] - v).abs() <= 1e-12 * v.abs() && s.velocity[i][0] == 0.0;
    }
    println!(
        "rank {rank} of {size}: share {mine:?}, ids {:?}, vz {:?}",
        s.ids,
        s.velocity.iter().map(|v| v[2]).collect::<Vec<_>>()
    );
    drop(lig);
    drop(universe);
    if !ok {
        eprintln!("rank {rank}: velocities do not match v = (g + F/m) t");
        std::process::exit(1);
    }
}
