//! CFDEM's Ksl form over the sparse exchange (issue 28), for `tests/link_sparse_ksl.rs`: the
//! porous cavity (crates/foam-solver-tests/cases/cavity) on 2 coupler ranks × 2 grainPisoFoam
//! ranks, run under `mpirun -np 2` as `sparse_ksl CASE SOLVER OUT`.
//!
//! Every coupler rank touches the porous block's cells (rank 0 all of them, rank 1 those with
//! 0.045 m < x < 0.075 m, on both solver ranks) and gives, per cell, ε = 0.6, a conserving
//! Σ Ksl of 123 (which CFDEM's form must ignore) and CFDEM's sums: share w_q (1 and 0.5),
//! particle velocity v_q ((0.01, 0, 0) and (0, 0.02, 0) m/s) and drag F_q = K_q V (U − v_q)
//! with U of the cell from the sparse reply, K_0 = 300 (900 in every fourth cell, above the
//! KslLimit of 1000 together with rank 1's) and K_1 = 200 kg/(m³ s). Two intervals of 5 steps,
//! each with the whole state, so rank 0's fluid has the solver's Ksl and Us. Rank 1 sends its
//! sums to rank 0, which forms Ksl and Us from the sums added in rank order with
//! [`couple::ksl::form_cfdem`] (the coupler's own formation, as with the fluid on rank 0) and
//! writes to OUT per interval and cell `ksl I CELL SOLVER RUST` and `us I CELL SOLVER(3)
//! RUST(3)`.

use couple::ksl::{CfdemKsl, CfdemSums, UsAveraging};
use couple::ranks::{owner_reply_width, owner_sums_width, CellOwners};
use foam::{Case, Label};
use foam_link::{protocol::FieldsIn, OpenFoamFluid, SpawnOptions};
use mesh::v3::V3;
use mesh::MeshGeometry;
use mpi::traits::*;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The settings of CFDEM's form in this run.
pub const KSL: CfdemKsl = CfdemKsl {
    limit: 1000.0,
    max_voidage: 0.99,
    averaging: UsAveraging::Dense,
};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, case, solver, out] = &args[..] else {
        eprintln!("usage: sparse_ksl CASE SOLVER OUT");
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
    let n = g.cell_centres.len();
    let block = |c: usize| {
        let x = g.cell_centres[c];
        x[0] > 0.03 && x[0] < 0.09 && x[1] < 0.05
    };
    let shared = |c: usize| g.cell_centres[c][0] > 0.045 && g.cell_centres[c][0] < 0.075;
    let mine: Vec<Label> = (0..n)
        .filter(|&c| block(c) && (rank == 0 || shared(c)))
        .map(|c| c as Label)
        .collect();
    let options = SpawnOptions {
        heat: false,
        cfdem_ksl: Some(KSL),
        vorticity: false,
        ddt_u: false,
    };
    let (mut fluid, mut cells) =
        OpenFoamFluid::spawn_ranked_with(&world, &case, 2, &solver, options).unwrap();
    let mut text = String::new();
    let (reply_width, width) = (owner_reply_width(false), owner_sums_width(false, true));
    let (w, v, k) = match rank {
        0 => (1.0, V3::new(0.01, 0.0, 0.0), 300.0),
        _ => (0.5, V3::new(0.0, 0.02, 0.0), 200.0),
    };
    for i in 0..2 {
        let reply = cells.deposit(&mine, &vec![1e-9; mine.len()]).unwrap();
        let mut u = vec![V3::zeros(); n];
        let mut sums = Vec::with_capacity(mine.len() * width);
        for (&c, r) in mine.iter().zip(reply.chunks_exact(reply_width)) {
            let c = c as usize;
            u[c] = V3::new(r[2], r[3], r[4]);
            let k = if rank == 0 && c.is_multiple_of(4) {
                900.0
            } else {
                k
            };
            let f = (u[c] - v) * (k * g.cell_volumes[c]);
            sums.extend_from_slice(&[0.6, 123.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
            sums.extend_from_slice(&[f[0], f[1], f[2], w, w * v[0], w * v[1], w * v[2]]);
        }
        cells.exchange(&sums).unwrap();
        let root = world.process_at_rank(0);
        if rank == 1 {
            root.send(&sums[..]);
            world.barrier();
            continue;
        }
        let (other, _) = world.process_at_rank(1).receive_vec::<f64>();
        // rank 0's sums, then rank 1's, per cell: the owners' order
        let mut cfdem = CfdemSums::new(n, UsAveraging::Dense);
        let mut add = |cells: &[usize], s: &[f64]| {
            for (&c, r) in cells.iter().zip(s.chunks_exact(width)) {
                let mut rec = Vec::new();
                cfdem.record(c, &mut rec);
                for (a, b) in rec.iter_mut().zip(&r[8..]) {
                    *a += b;
                }
                cfdem.set(c, &rec);
            }
        };
        let all: Vec<usize> = mine.iter().map(|&c| c as usize).collect();
        let theirs: Vec<usize> = all.iter().copied().filter(|&c| shared(c)).collect();
        add(&all, &sums);
        add(&theirs, &other);
        let mut eps = vec![1.0; n];
        for &c in &all {
            eps[c] = 0.6;
        }
        let (mut ksl, mut us) = (vec![0.0; n], vec![V3::zeros(); n]);
        couple::ksl::form_cfdem(&KSL, &cfdem, &u, &eps, &g.cell_volumes, &mut ksl, &mut us);
        let f = fluid.as_mut().unwrap();
        let empty = FieldsIn {
            eps_old: &[],
            eps_new: &[],
            ksl: &[],
            us: &[],
            f: &[],
        };
        f.set_whole(true);
        f.set_fields(&empty).unwrap();
        f.advance_interval(5.0 * f.delta_t()).unwrap();
        let held = f.held_fields().expect("the whole state");
        for &c in &all {
            writeln!(text, "ksl {i} {c} {:.17e} {:.17e}", held.ksl[c], ksl[c]).unwrap();
            let (a, b) = (held.us[c], us[c]);
            writeln!(
                text,
                "us {i} {c} {:.17e} {:.17e} {:.17e} {:.17e} {:.17e} {:.17e}",
                a[0], a[1], a[2], b[0], b[1], b[2]
            )
            .unwrap();
        }
        world.barrier();
    }
    if let Some(f) = fluid {
        f.finish().unwrap();
        std::fs::write(out, text).unwrap();
    }
    world.barrier();
}
