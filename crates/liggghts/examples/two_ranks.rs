//! LIGGGHTS in-process on every rank of MPI_COMM_WORLD (run under `mpirun -np 2`; the test
//! `tests/link_ranks.rs` does): each rank sees only the particles its LIGGGHTS rank owns and
//! sets the forces of those alone. Prints each rank's tags; exits with status 1 (and a message)
//! when a velocity misses v = (g + F/m) t or the ranks' tags are not a partition of 1..=3.
//! With a second argument `heat` it runs `tests/decks/heated.in` instead and checks that each
//! rank heats its own particles by the flux it hands over, T = T0 + q t/(m c).

use couple::ParticleSide;
use mesh::v3::V3;
use mpi::collective::CommunicatorCollectives;
use mpi::topology::Communicator;
use std::path::Path;

fn main() {
    let universe = mpi::initialize().expect("MPI initialised once");
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let dir = std::env::args()
        .nth(1)
        .expect("usage: two_ranks WORKDIR [heat]");
    if std::env::args().nth(2).as_deref() == Some("heat") {
        return heat(world, Path::new(&dir));
    }
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/decks/falling.in");
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

/// The heat variant (module docs): q = 1e-3·tag W on each rank's own particles for 100 steps.
fn heat(world: mpi::topology::SimpleCommunicator, dir: &Path) {
    let rank = world.rank();
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/decks/heated.in");
    let mut lig = liggghts::LiggghtsDem::open(&world, &deck, dir, &[]).unwrap();
    let ids = lig.state().ids.to_vec();
    let q: Vec<f64> = ids.iter().map(|&t| 1e-3 * t as f64).collect();
    lig.set_heat_flux(&q).unwrap();
    lig.advance(100).unwrap();
    let (m, c) = (2000.0 * std::f64::consts::PI / 6.0 * 1e-9, 500.0);
    let t = 100.0 * lig.time_step();
    let temps = lig
        .state()
        .temperature
        .expect("the deck has heat/gran")
        .to_vec();
    let mut ok = temps.len() == ids.len();
    for (i, &id) in ids.iter().enumerate() {
        let expected = 300.0 + 1e-3 * id as f64 * t / (m * c);
        ok &= (temps[i] - expected).abs() <= 1e-12 * expected;
    }
    let n = [ids.len() as i32];
    let mut total = [0i32];
    world.all_reduce_into(
        &n[..],
        &mut total[..],
        mpi::collective::SystemOperation::sum(),
    );
    ok &= total[0] == 3 && n[0] < 3;
    println!("rank {rank}: heat ids {ids:?}, T {temps:?}, particles over ranks {total:?}");
    drop(lig);
    if !ok {
        eprintln!("rank {rank}: temperatures do not match T0 + q t/(m c), or particles not split");
        std::process::exit(1);
    }
}
