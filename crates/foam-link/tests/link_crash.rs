//! A solver that fails never hangs the coupler: an OpenFOAM FatalError after the handshake
//! (an unknown linear solver in fvSolution) comes back with OpenFOAM's message and the log; a
//! rank killed with SIGKILL is noticed through its pid and named with its log; bad exchange
//! values are refused before they reach the solver.

mod common;
use common::*;
use foam_link::{LinkError, OpenFoamFluid};
use std::time::{Duration, Instant};

#[test]
fn fatal_errors_and_killed_ranks_end_the_link_with_a_named_error() {
    let Some(solver) = tools() else {
        return;
    };
    let universe = universe();
    let world = universe.world();
    let (case, fields) = porous_cavity();
    let (old, new) = interval_voidage(&fields, 0);
    let input = foam_link::protocol::FieldsIn {
        eps_old: &old,
        eps_new: &new,
        ksl: &fields.ksl,
        us: &fields.us,
        f: &fields.f,
    };

    // 1. A FatalError in the first step (fvSolution's p solver does not exist).
    let bad = case.duplicate();
    bad.edit("system/fvSolution", "PCG", "NoSuchSolver");
    let mut fluid = OpenFoamFluid::spawn(&world, &bad.dir, 1, &solver).unwrap();
    fluid.set_fields(&input).unwrap();
    let t = Instant::now();
    let err = fluid.advance_interval(STEPS as f64 * DT).unwrap_err();
    eprintln!("FatalError after {:?}: {err}", t.elapsed());
    match &err {
        LinkError::SolverError { rank, log, message } => {
            assert_eq!(*rank, 0);
            assert!(message.contains("NoSuchSolver"), "{message}");
            assert!(log.ends_with("log.grainPisoFoam") && log.is_file());
        }
        other => panic!("expected SolverError, got {other}"),
    }
    drop(fluid);

    // 2. Rank 1 of 2 killed while the coupler waits.
    let killed = case.duplicate();
    let mut fluid = OpenFoamFluid::spawn(&world, &killed.dir, 2, &solver).unwrap();
    let pids = fluid.pids();
    assert_eq!(pids.len(), 2);
    let status = std::process::Command::new("kill")
        .args(["-9", &pids[1].to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    fluid.set_fields(&input).unwrap();
    let t = Instant::now();
    let err = fluid.advance_interval(STEPS as f64 * DT).unwrap_err();
    eprintln!("killed rank noticed after {:?}: {err}", t.elapsed());
    assert!(t.elapsed() < Duration::from_secs(30));
    match &err {
        LinkError::SolverDied { rank, pid, log, .. } => {
            assert_eq!((*rank, *pid), (1, pids[1]));
            assert!(log.ends_with("log.grainPisoFoam.1"), "{}", log.display());
        }
        other => panic!("expected SolverDied, got {other}"),
    }
    assert!(err.to_string().contains("log.grainPisoFoam.1"));
    drop(fluid);
    // The other rank is ended too.
    let t = Instant::now();
    while foam_link::alive::is_alive(pids[0]) {
        assert!(t.elapsed() < Duration::from_secs(10), "rank 0 still runs");
        std::thread::sleep(Duration::from_millis(20));
    }

    // 3. A NaN in Ksl is refused naming the field and the cell (the solver would trap it).
    let fine = case.duplicate();
    let mut fluid = OpenFoamFluid::spawn(&world, &fine.dir, 1, &solver).unwrap();
    let mut ksl = fields.ksl.clone();
    ksl[17] = f64::NAN;
    let err = fluid
        .set_fields(&foam_link::protocol::FieldsIn { ksl: &ksl, ..input })
        .unwrap_err();
    assert!(err.to_string().contains("Ksl at cell 17"), "{err}");
    fluid.finish().unwrap();
}
