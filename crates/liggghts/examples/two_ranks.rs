//! LIGGGHTS in-process on every rank of MPI_COMM_WORLD (run under `mpirun -np 2`; the test
//! `tests/link_ranks.rs` does): each rank sees only the particles its LIGGGHTS rank owns and
//! sets the forces of those alone. Prints each rank's tags; exits with status 1 (and a message)
//! when a velocity misses v = (g + F/m) t or the ranks' tags are not a partition of 1..=3.

use couple::ParticleSide;
use mesh::v3::V3;
use mpi::collective::CommunicatorCollectives;
use mpi::topology::Communicator;
use std::path::Path;

fn main() {
    let universe = mpi::initialize().expect("MPI initialised once");
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/decks/falling.in");
    let dir = std::env::args().nth(1).expect("usage: two_ranks WORKDIR");
    let mut lig = liggghts::LiggghtsDem::open(&world, &deck, Path::new(&dir), &[]).unwrap();
    // F = (0, 0, 1e-6·tag) N on this rank's particles
    let ids = lig.state().ids.to_vec();
    let f: Vec<V3> = ids
        .iter()
        .map(|&t| V3::new(0.0, 0.0, 1e-6 * t as f64))
        .collect();
    let n = ids.len();
    lig.set_forces(&f, &vec![0.0; n], &vec![V3::zeros(); n])
        .unwrap();
    lig.advance(100).unwrap();
    let m = 2000.0 * std::f64::consts::PI / 6.0 * 1e-9;
    let t = 100.0 * lig.time_step();
    let s = lig.state();
    let mut ok = true;
    for i in 0..s.len() {
        let v = (-9.81 + 1e-6 * s.ids[i] as f64 / m) * t;
        ok &= (s.velocity[i][2] - v).abs() <= 1e-12 * v.abs() && s.velocity[i][0] == 0.0;
    }
    // every tag on exactly one rank
    let mut count = [0i32; 3];
    for &t in s.ids {
        count[t as usize - 1] += 1;
    }
    let mut total = [0i32; 3];
    world.all_reduce_into(
        &count[..],
        &mut total[..],
        mpi::collective::SystemOperation::sum(),
    );
    ok &= total == [1, 1, 1];
    println!(
        "rank {rank} of {size}: ids {:?}, vz {:?}, owners per tag {total:?}",
        s.ids,
        s.velocity.iter().map(|v| v[2]).collect::<Vec<_>>()
    );
    drop(lig);
    drop(universe);
    if !ok {
        eprintln!("rank {rank}: velocities do not match v = (g + F/m) t, or tags not partitioned");
        std::process::exit(1);
    }
}
