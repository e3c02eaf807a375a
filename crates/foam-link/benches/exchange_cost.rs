//! The cost of one coupling exchange with grainPisoFoam for the Ergun mesh
//! (`openfoam-cases/ergun/CFD`, 4480 cells) on 2 ranks: bytes each way and the coupler's time
//! packing, transferring (copy, match, scatter) and waiting for the solver, per interval of
//! one PISO step (Δt = 5e-4 s). Run: `cargo bench -p foam-link --features mpi` (needs
//! OpenFOAM, Open MPI and the solver that `openfoam-cases/solver/build.sh` builds; prints a
//! note and exits otherwise). Not divan: each sample is one interval of a live MPI link, and
//! MPI can be initialised once per process.
//!
//! Measured on the shared 2-core machine (oversubscribed, other builds running): 322 624 B
//! sent and 358 560 B received per interval; pack 0.05 ms, transfer 3–13 ms (sends complete
//! when the yielding solver ranks take them), waiting for the solver 59–66 ms per PISO step.

use foam_link::protocol::FieldsIn;
use foam_link::OpenFoamFluid;

const INTERVALS: usize = 40;

fn main() {
    let Some(solver) = foam_solver_tests::grain_piso_foam() else {
        eprintln!("note: OpenFOAM or the solver missing: no benchmark");
        return;
    };
    foam_link::prepare_environment();
    let universe = mpi::initialize().expect("MPI");
    let tmp = tempfile::tempdir().unwrap();
    let case = tmp.path().join("CFD");
    let source = testkit::repo_root().join("openfoam-cases/ergun/CFD");
    testkit::copy_inputs(&source, &case);
    let mut fluid = OpenFoamFluid::spawn(&universe.world(), &case, 2, &solver).unwrap();
    let n = fluid.rank_map().n_cells();
    // A bed in the lower third of the cells by index (values only matter to the solver).
    let eps: Vec<f64> = (0..n).map(|c| if c < n / 3 { 0.45 } else { 1.0 }).collect();
    let ksl: Vec<f64> = eps
        .iter()
        .map(|&e| if e < 1.0 { 3.0e4 } else { 0.0 })
        .collect();
    let zeros = vec![mesh::v3::V3::zeros(); n];
    let dt = fluid.delta_t();
    let mut first = None;
    for i in 0..INTERVALS {
        fluid
            .set_fields(&FieldsIn {
                eps_old: &eps,
                eps_new: &eps,
                ksl: &ksl,
                us: &zeros,
                f: &zeros,
            })
            .unwrap();
        fluid.advance_interval(dt).unwrap();
        if i == 0 {
            // The first interval includes the solver's start-up: measure from the second.
            first = Some(fluid.stats());
        }
    }
    let s0 = first.unwrap();
    let s = fluid.stats();
    let k = (s.intervals - s0.intervals) as f64;
    let ms = |a: f64, b: f64| 1e3 * (a - b) / k;
    let (sent, received) = foam_link::protocol::advance_bytes(n, 2, fluid.patches().len());
    println!(
        "exchange, {n} cells on 2 ranks, {k} intervals of 1 step: sent {sent} B, received \
         {received} B per interval; coupler per interval: pack {:.3} ms, transfer {:.3} ms, \
         waiting for the solver {:.3} ms",
        ms(s.pack_seconds, s0.pack_seconds),
        ms(s.transfer_seconds, s0.transfer_seconds),
        ms(s.wait_seconds, s0.wait_seconds),
    );
    assert_eq!(s.bytes_sent, s.intervals * sent as u64);
    fluid.finish().unwrap();
}
