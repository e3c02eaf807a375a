//! grainPisoFoam's temperature equation (issue 27; `grainPisoFoam/heatTransport.H`) on the
//! `heat-channel` case: a 2-D laminar channel (40 × 10 cells, 100 mm × 10 mm, inlet U 0.01 m/s
//! and T 1 K, bottom wall T 0.5 K, top wall adiabatic, ν 1e-4 m²/s, Pr 0.7).
//!
//! References: Debian's `scalarTransportFoam` (an independent solver of ∂T/∂t + ∇·(φT) −
//! ∇·(D_T∇T) = 0) on the same face flux; and the flow of the same case without heat.

use foam_solver_tests::case::max_abs_diff;
use foam_solver_tests::{grain_piso_foam, TestCase};

/// The channel flow after 2 s (200 steps of 10 ms; developed over the 1 s viscous time
/// h²/ν), heat off, with U, p and φ written at t = 2 s.
fn developed_flow(solver: &std::path::Path) -> TestCase {
    let flow = TestCase::new("heat-channel");
    flow.edit(
        "constant/couplingProperties",
        "heat            on;",
        "heat            off;",
    );
    flow.edit(
        "system/controlDict",
        "endTime         3;",
        "endTime         2;",
    );
    flow.edit(
        "system/controlDict",
        "writeInterval   100;",
        "writeInterval   200;",
    );
    let log = flow.run(solver);
    assert!(!log.contains("Solving for T"), "heat off solves no T");
    flow
}

/// A copy of `flow` restarting at t = 2 s with the template's T (0 K inside) and running to
/// t = 3 s.
fn restart_with_t(flow: &TestCase) -> TestCase {
    let case = flow.duplicate();
    std::fs::copy(case.dir.join("0/T"), case.dir.join("2/T")).unwrap();
    case.edit(
        "system/controlDict",
        "startTime       0;",
        "startTime       2;",
    );
    case.edit(
        "system/controlDict",
        "endTime         2;",
        "endTime         3;",
    );
    case.edit(
        "system/controlDict",
        "writeInterval   200;",
        "writeInterval   100;",
    );
    case
}

/// With ε ≡ 1 and no Tsource the equation is scalarTransportFoam's with D_T = ν/Pr. With
/// `solveFlow off` grainPisoFoam convects T with the φ read at t = 2 s (φ_T = ε_f φ/ε_f = φ
/// exactly), the flux scalarTransportFoam reads too, with the same `div(phi,T)` (Gauss
/// limitedLinear 1, CFDEM's packedBedTemp) and laplacian; the extra terms of the averaged form
/// (ε ∂T/∂t with ε = 1, −T ∂ε/∂t = 0, −T ∇·φ ≈ 1e-16) vanish to round-off. Both solve T to
/// 1e-13: T must agree to 1e-11 K (measured 3.2e-14 K) after 100 steps.
#[test]
fn temperature_equals_scalar_transport_foam_on_the_same_flux() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    let flow = developed_flow(&solver);

    let grain = restart_with_t(&flow);
    grain.edit(
        "constant/couplingProperties",
        "heat            off;",
        "heat            on;",
    );
    std::fs::write(
        grain.dir.join("constant/couplingProperties"),
        std::fs::read_to_string(grain.dir.join("constant/couplingProperties")).unwrap()
            + "solveFlow off;\n",
    )
    .unwrap();
    let log = grain.run(&solver);
    assert!(log.contains("Solving for T"), "{log}");

    let reference = restart_with_t(&flow);
    let nu_by_pr = 1e-4 / 0.7;
    std::fs::write(
        reference.dir.join("constant/transportProperties"),
        std::fs::read_to_string(reference.dir.join("constant/transportProperties")).unwrap()
            + &format!("DT {nu_by_pr:e};\n"),
    )
    .unwrap();
    reference.run_tool("scalarTransportFoam", &[]);

    let t = grain.scalars("3", "T");
    let t_ref = reference.scalars("3", "T");
    let d = max_abs_diff(&t, &t_ref);
    let (lo, hi) = t_ref
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    eprintln!("grainPisoFoam vs scalarTransportFoam: max |ΔT| = {d:.2e} K (T in [{lo}, {hi}] K)");
    // The comparison is not between uniform fields: the front has entered and the wall heats.
    assert!(lo < 0.6 && hi > 0.9, "T in [{lo}, {hi}]");
    assert!(d < 1e-11, "max |ΔT| = {d:e} K");
    // T, Tsource and alphat are written at write times.
    for name in ["T", "Tsource", "alphat"] {
        assert!(grain.dir.join("3").join(name).is_file(), "3/{name}");
    }
}

/// Heat on changes nothing of the flow (T does not act on U or p): 50 steps with and
/// without heat give the same U, p and φ, value for value; heat off needs no `0/T`.
#[test]
fn heat_leaves_the_flow_unchanged_and_heat_off_needs_no_t() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    let with_heat = TestCase::new("heat-channel");
    with_heat.edit(
        "system/controlDict",
        "endTime         3;",
        "endTime         0.5;",
    );
    with_heat.edit(
        "system/controlDict",
        "writeInterval   100;",
        "writeInterval   50;",
    );
    let without = with_heat.duplicate();
    without.edit(
        "constant/couplingProperties",
        "heat            on;",
        "heat            off;",
    );
    std::fs::remove_file(without.dir.join("0/T")).unwrap();
    let log = with_heat.run(&solver);
    assert!(log.contains("Solving for T"), "{log}");
    let log = without.run(&solver);
    assert!(
        !log.contains("Solving for T") && !log.contains("Tsource"),
        "{log}"
    );
    for name in ["U", "p", "phi"] {
        let a = std::fs::read_to_string(with_heat.dir.join("0.5").join(name)).unwrap();
        let b = std::fs::read_to_string(without.dir.join("0.5").join(name)).unwrap();
        assert!(a == b, "0.5/{name} differs with heat on");
    }
    assert!(!without.dir.join("0.5/T").exists());
}

/// Heat on without `0/T`, or without `Pr`, stops with OpenFOAM's error naming the file.
#[test]
fn heat_without_t_or_pr_is_a_clear_error() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    let no_t = TestCase::new("heat-channel");
    std::fs::remove_file(no_t.dir.join("0/T")).unwrap();
    let (ok, out) = no_t.try_run(&solver);
    assert!(!ok, "{out}");
    assert!(out.contains("0/T"), "{out}");

    let no_pr = TestCase::new("heat-channel");
    no_pr.edit("constant/transportProperties", "Pr              0.7;", "");
    let (ok, out) = no_pr.try_run(&solver);
    assert!(!ok, "{out}");
    assert!(
        out.contains("transportProperties") && out.contains("no Pr"),
        "{out}"
    );
}
