//! What CFDEM's cases give grainPisoFoam differently from foamgrain's: the fluid density as a
//! uniform `0/rho` field instead of `rho` in transportProperties, and no `0/f` (nor other
//! coupling fields). The run must equal the one with foamgrain's inputs, field for field.

use foam_solver_tests::case::max_abs_diff;
use foam_solver_tests::{grain_piso_foam, TestCase};

#[test]
fn rho_from_the_zero_folder_and_missing_coupling_fields() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    let ours = TestCase::new("column");
    ours.run(&solver);
    let cfdem = TestCase::new("column");
    cfdem.edit("constant/transportProperties", "rho             10;", "");
    // 0/rho: Ksl's file (same patches) with the density's name, dimensions and value
    let rho: String = std::fs::read_to_string(cfdem.dir.join("0/Ksl"))
        .unwrap()
        .lines()
        .map(|l| match l.trim_start() {
            t if t.starts_with("internalField") => "internalField   uniform 10;".to_string(),
            t if t.starts_with("object") => "    object      rho;".to_string(),
            t if t.starts_with("dimensions") => "dimensions      [1 -3 0 0 0 0 0];".to_string(),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(cfdem.dir.join("0/rho"), rho).unwrap();
    std::fs::remove_file(cfdem.dir.join("0/f")).unwrap();
    let log = cfdem.run(&solver);
    assert!(log.contains("no 0/f: created"), "{log}");
    assert!(log.contains("rho 10 kg/m^3"), "{log}");
    let d = max_abs_diff(&ours.scalars("0.02", "p"), &cfdem.scalars("0.02", "p"));
    assert_eq!(d, 0.0, "p");
    let (a, b) = (ours.vectors("0.02", "U"), cfdem.vectors("0.02", "U"));
    assert_eq!(a, b);
    // a restart from the last written time, which has no rho (CFDEM's ErgunTestMPI_restart
    // restarts at 0.05 with only 0/rho): the density of 0/rho
    let restart = cfdem.duplicate();
    restart.edit(
        "system/controlDict",
        "startFrom       startTime;",
        "startFrom       latestTime;",
    );
    restart.edit(
        "system/controlDict",
        "endTime         0.02;",
        "endTime         0.03;",
    );
    assert!(!restart.dir.join("0.02/rho").exists());
    let log = restart.run(&solver);
    assert!(log.contains("rho 10 kg/m^3"), "{log}");
    assert!(log.contains("Time = 0.03\n"), "{log}");
    // a varying 0/rho is refused, naming it
    let bad = TestCase::new("column");
    bad.edit("constant/transportProperties", "rho             10;", "");
    let mut rho_cells = vec![10.0; 60];
    rho_cells[3] = 11.0;
    std::fs::write(
        bad.dir.join("0/rho"),
        std::fs::read_to_string(cfdem.dir.join("0/rho")).unwrap(),
    )
    .unwrap();
    bad.set_field("rho", foam::FieldValues::Scalar(rho_cells));
    let (ok, log) = bad.try_run(&solver);
    assert!(
        !ok && log.contains("rho") && log.contains("uniform"),
        "{log}"
    );
}

/// CFDEM-PFM's `useDDTvoidfraction;` (the key alone, its voidfractionTest) switches ∂ε/∂t on,
/// as `useDDTvoidfraction b;` does: the same log line and the same fields.
#[test]
fn the_bare_ddt_key_is_b() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    let run = |line: &str| {
        let case = TestCase::new("column");
        case.edit(
            "constant/couplingProperties",
            "modelType       \"A\";",
            &format!("modelType       \"A\";\n{line}"),
        );
        let log = case.run(&solver);
        (case, log)
    };
    let (b, log_b) = run("useDDTvoidfraction b;");
    let (bare, log_bare) = run("useDDTvoidfraction;");
    let (_, log_none) = run("");
    assert!(log_b.contains("ddtVoidfraction on"), "{log_b}");
    assert!(log_bare.contains("ddtVoidfraction on"), "{log_bare}");
    assert!(log_none.contains("ddtVoidfraction off"), "{log_none}");
    assert_eq!(b.vectors("0.02", "U"), bare.vectors("0.02", "U"));
}
