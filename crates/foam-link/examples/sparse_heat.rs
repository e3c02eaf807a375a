//! The heat channel (crates/foam-solver-tests/cases/heat-channel) on 2 coupler ranks × 2
//! grainPisoFoam ranks through the sparse exchange with heat, for `tests/link_sparse_heat.rs`:
//! run under `mpirun -np 2` as `sparse_heat CASE SOLVER OUT`.
//!
//! Every coupler rank gives the solver ranks the block's cells it touches (40 mm < x < 60 mm;
//! rank 0 all of them, rank 1 those with 45 mm < x < 55 mm, on both solver ranks): ε = 0.6,
//! and shares of Ksl = 500 kg/(m³ s) and Tsource = −5 K/s (rank 0: 300 and −2 where rank 1
//! touches, 500 and −5 elsewhere; rank 1: 200 and −3), three intervals of 0.1 s, the last with
//! the whole state. Rank 0 watches every third cell, last first, and max |U|/∛V (the protocol's
//! watch) before the first interval. Rank 0 writes to OUT, one value a line: `reply_T CELL T`
//! (the T the sparse reply gave rank 0 at the start of interval 3, i.e. after two intervals),
//! `outlet I Σφ Σφ T_b` after each interval, `watch_U CELL Ux Uy Uz` and `watch_cfl X` (max
//! |U|/∛V, 1/s) after the second, `T CELL T` after the third. Exits 1 when a reply's summed volume or
//! lowest-rank flag is wrong, or when rank 0's fluid shows T after an advance without the
//! whole state (it would be stale) or none after one with it.

use couple::ranks::{owner_reply_width, CellOwners};
use foam::{Case, Label};
use foam_link::{protocol::FieldsIn, OpenFoamFluid, SpawnOptions};
use mesh::MeshGeometry;
use mpi::traits::*;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Solid volume each coupler rank deposits in each of its cells, m³ (checked in the reply).
const SOLID: f64 = 1e-9;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, case, solver, out] = &args[..] else {
        eprintln!("usage: sparse_heat CASE SOLVER OUT");
        std::process::exit(2);
    };
    let (case, solver) = (PathBuf::from(case), PathBuf::from(solver));
    foam_link::prepare_environment();
    let universe = mpi::initialize().expect("MPI");
    let world = universe.world();
    let rank = world.rank() as usize;
    assert_eq!(world.size(), 2, "run under mpirun -np 2");
    let mesh = Case::open(&case).unwrap().read_mesh().unwrap();
    let g = MeshGeometry::new(&mesh).unwrap();
    let x = |c: usize| g.cell_centres[c][0];
    let shared = |c: usize| x(c) > 0.045 && x(c) < 0.055;
    let mine: Vec<Label> = (0..g.cell_centres.len())
        .filter(|&c| x(c) > 0.04 && x(c) < 0.06 && (rank == 0 || shared(c)))
        .map(|c| c as Label)
        .collect();
    let heat = SpawnOptions {
        heat: true,
        cfdem_ksl: None,
        vorticity: false,
        ddt_u: false,
    };
    let (mut fluid, mut cells) =
        OpenFoamFluid::spawn_ranked_with(&world, &case, 2, &solver, heat).unwrap();
    let watched: Vec<usize> = (0..g.cell_centres.len()).rev().step_by(3).collect();
    if let Some(f) = fluid.as_mut() {
        f.watch(&watched, true).unwrap();
    }
    let mut text = String::new();
    let width = owner_reply_width(true);
    for i in 0..3 {
        let solid = vec![SOLID; mine.len()];
        let reply = cells.deposit(&mine, &solid).unwrap();
        assert_eq!(reply.len(), mine.len() * width);
        for (&c, r) in mine.iter().zip(reply.chunks_exact(width)) {
            let both = shared(c as usize);
            let want = if both { 2.0 * SOLID } else { SOLID };
            let lowest = if rank == 0 { 1.0 } else { 0.0 };
            if (r[0] - want).abs() > 1e-24 || r[1] != lowest {
                eprintln!(
                    "rank {rank}, cell {c}: summed volume {} (want {want}), flag {}",
                    r[0], r[1]
                );
                std::process::exit(1);
            }
            if rank == 0 && i == 2 {
                writeln!(text, "reply_T {c} {:.17e}", r[width - 1]).unwrap();
            }
        }
        let mut sums = Vec::with_capacity(mine.len() * 9);
        for &c in &mine {
            let (ksl, ts) = match (rank, shared(c as usize)) {
                (0, true) => (300.0, -2.0),
                (0, false) => (500.0, -5.0),
                _ => (200.0, -3.0),
            };
            sums.extend_from_slice(&[0.6, ksl, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, ts]);
        }
        cells.exchange(&sums).unwrap();
        if let Some(f) = fluid.as_mut() {
            let empty = FieldsIn {
                eps_old: &[],
                eps_new: &[],
                ksl: &[],
                us: &[],
                f: &[],
            };
            f.set_whole(i == 2);
            f.set_fields_with_heat(&empty, Some(&[])).unwrap();
            f.advance_interval(0.1).unwrap();
            if f.temperature().is_some() != (i == 2) {
                eprintln!("interval {i}: T on rank 0 without the whole state, or none with it");
                std::process::exit(1);
            }
            let o = f.patch("outlet").unwrap();
            writeln!(
                text,
                "outlet {i} {:.17e} {:.17e}",
                o.flux,
                o.t_flux.unwrap()
            )
            .unwrap();
            if i == 1 {
                let w = f.watched().expect("watching without whole replies");
                for (&c, u) in watched.iter().zip(&w.u) {
                    writeln!(text, "watch_U {c} {:.17e} {:.17e} {:.17e}", u.x, u.y, u.z).unwrap();
                }
                writeln!(text, "watch_cfl {:.17e}", w.u_by_size.unwrap()).unwrap();
            }
            if i == 2 && f.watched().is_some() {
                eprintln!("interval 2: watched values while the replies carry the whole state");
                std::process::exit(1);
            }
        }
        world.barrier();
    }
    if let Some(f) = fluid {
        for (c, t) in f.temperature().unwrap().iter().enumerate() {
            writeln!(text, "T {c} {t:.17e}").unwrap();
        }
        f.finish().unwrap();
        std::fs::write(out, text).unwrap();
    }
    world.barrier();
}
