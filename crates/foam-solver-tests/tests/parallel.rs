//! Serial and `-parallel` runs of grainPisoFoam give the same fields (to the linear solvers'
//! tolerance): the cavity with a porous block (ε = 0.6, Ksl, Us) and an explicit force
//! density f in it, decomposed `simple` 2 × 1 × 1 and `hierarchical` 1 × 2 × 1 (Debian's
//! OpenFOAM has no scotch/metis) so the processor boundary crosses the porous block.

use foam::FieldValues;
use foam_solver_tests::case::{flatten, max_abs, max_abs_diff};
use foam_solver_tests::{grain_piso_foam, TestCase};

#[test]
fn two_ranks_reproduce_the_serial_run_with_porous_region_and_force() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    if !(testkit::tool("mpirun") && testkit::tool("decomposePar")) {
        return;
    }
    let serial = TestCase::new("cavity");
    let porous = serial.cavity_porous_block();
    let pick = |inside: f64, outside: f64| -> Vec<f64> {
        porous
            .iter()
            .map(|&b| if b { inside } else { outside })
            .collect()
    };
    serial.set_field("voidfraction", FieldValues::Scalar(pick(0.6, 1.0)));
    serial.set_field("Ksl", FieldValues::Scalar(pick(2000.0, 0.0)));
    let vec_pick = |inside: [f64; 3]| -> Vec<[f64; 3]> {
        porous
            .iter()
            .map(|&b| if b { inside } else { [0.0; 3] })
            .collect()
    };
    serial.set_field("Us", FieldValues::Vector(vec_pick([0.05, 0.0, 0.0])));
    serial.set_field("f", FieldValues::Vector(vec_pick([0.0, -500.0, 0.0])));
    let simple = serial.duplicate();
    let hierarchical = serial.duplicate();
    hierarchical.edit(
        "system/decomposeParDict",
        "method          simple;\ncoeffs          { n (2 1 1); }",
        "method          hierarchical;\ncoeffs          { n (1 2 1); order xyz; }",
    );

    serial.run(&solver);
    let time = "0.2";
    let u = flatten(&serial.vectors(time, "U"));
    let p = serial.scalars(time, "p");
    // The coupling fields are written back unchanged (frozen source).
    let eps = serial.scalars(time, "voidfraction");
    assert_eq!(eps, pick(0.6, 1.0));

    for (method, parallel) in [("simple", &simple), ("hierarchical", &hierarchical)] {
        let log = parallel.run_parallel(&solver, 2);
        assert!(log.contains("nProcs : 2"), "not a 2-rank run:\n{log}");
        let du = max_abs_diff(&u, &flatten(&parallel.vectors(time, "U"))) / max_abs(&u);
        let dp = max_abs_diff(&p, &parallel.scalars(time, "p")) / max_abs(&p);
        eprintln!(
            "serial vs 2 ranks ({method}): max|ΔU|/max|U| = {du:.3e}, max|Δp|/max|p| = {dp:.3e}"
        );
        // The pressure solver (PCG, tolerance 1e-12) and the processor-local DIC
        // preconditioner change the iterates, not the converged solution.
        assert!(du < 1e-8 && dp < 1e-8, "{method}: ΔU {du:e}, Δp {dp:e}");
        assert_eq!(parallel.scalars(time, "voidfraction"), eps);
    }
}
