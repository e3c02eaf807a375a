//! grainPisoFoam on 2 ranks through the link: each rank gets only its cells (simple 2 × 1 × 1
//! through the porous block) and the assembled fields equal the serial run fed the same
//! fields from files; `finish` reconstructs the written time. A case without a
//! decomposeParDict gets one written.

mod common;
use common::*;
use foam_link::OpenFoamFluid;
use foam_solver_tests::TestCase;

#[test]
fn two_ranks_through_the_link_match_the_serial_prescribed_run() {
    let Some(solver) = tools() else {
        return;
    };
    let universe = universe();
    let world = universe.world();

    let (case, fields) = porous_cavity();
    let (u_files, p_files) = run_prescribed(&case, &fields, &solver);

    let linked = case.duplicate();
    let mut fluid = OpenFoamFluid::spawn(&world, &linked.dir, 2, &solver).unwrap();
    assert_eq!(fluid.ranks(), 2);
    assert_eq!(fluid.decomposition().map(|d| d.wrote_dict), Some(false));
    let map = fluid.rank_map();
    assert_eq!(map.cells_of(0).len() + map.cells_of(1).len(), 256);
    assert_eq!(
        map.cells_of(0).len(),
        128,
        "simple 2 x 1 x 1 halves the 16 x 16 cells"
    );
    run_link(&mut fluid, &fields);
    let state = couple::FluidSide::state(&fluid);
    let du = rel_diff_v(state.u, &u_files);
    let dp = rel_diff(state.p, &p_files);
    eprintln!("2 ranks via the link vs serial prescribed files: U {du:.2e}, p {dp:.2e}");
    // As the solver's own serial-vs-parallel test: the processor-local DIC preconditioner
    // changes the iterates, not the converged solution (PCG tolerance 1e-12).
    assert!(du < 1e-8 && dp < 1e-8, "U {du:e}, p {dp:e}");
    let logs = fluid.logs();
    assert!(logs.iter().all(|l| l.is_file()), "{logs:?}");
    fluid.write().unwrap();
    fluid.finish().unwrap();
    let du_file = rel_diff_v(&mesh::v3::from_arrays(&linked.vectors(END, "U")), &u_files);
    assert!(du_file < 1e-8, "reconstructed {END}/U: {du_file:e}");

    // No decomposeParDict: a simple one along the longest axis (z for the column) is written.
    let column = TestCase::new("column");
    let dict = column.dir.join("system/decomposeParDict");
    let _ = std::fs::remove_file(&dict);
    let fluid = OpenFoamFluid::spawn(&world, &column.dir, 2, &solver).unwrap();
    assert_eq!(fluid.decomposition().map(|d| d.wrote_dict), Some(true));
    let text = std::fs::read_to_string(&dict).unwrap();
    assert!(text.contains("n (1 1 2);"), "{text}");
    assert_eq!(
        fluid.rank_map().cells_of(1)[0],
        30,
        "the upper half of the column"
    );
    fluid.finish().unwrap();
}
