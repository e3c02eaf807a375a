//! Bad input stops grainPisoFoam with a message naming the file and the key or field.

use foam::FieldValues;
use foam_solver_tests::{grain_piso_foam, TestCase};

/// Runs the solver on `case` (after `spoil` edits it); the run must fail and its output must
/// contain every string of `names`.
fn assert_refused(spoil: impl Fn(&TestCase), names: &[&str]) {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    let case = TestCase::new("column");
    spoil(&case);
    let (ok, log) = case.try_run(&solver);
    assert!(!ok, "the solver accepted the case:\n{log}");
    for name in names {
        assert!(
            log.contains(name),
            "the message does not name `{name}`:\n{log}"
        );
    }
}

#[test]
fn a_voidfraction_outside_zero_one_is_refused_naming_the_field() {
    assert_refused(
        |case| {
            let mut eps = vec![1.0; 60];
            eps[7] = 0.0;
            case.set_field("voidfraction", FieldValues::Scalar(eps));
        },
        &["0/voidfraction", "(0, 1]"],
    );
}

#[test]
fn an_unknown_model_type_is_refused_naming_the_key_and_the_choices() {
    assert_refused(
        |case| case.edit("constant/couplingProperties", "\"A\"", "\"C\""),
        &["couplingProperties", "modelType", "A, B, Bfull"],
    );
}

#[test]
fn a_ksl_with_wrong_dimensions_is_refused_naming_the_field() {
    assert_refused(
        |case| case.edit("0/Ksl", "[1 -3 -1 0 0 0 0]", "[0 0 -1 0 0 0 0]"),
        &["0/Ksl", "ADR 0004"],
    );
}

#[test]
fn an_unknown_coupling_source_is_refused_listing_the_valid_ones() {
    assert_refused(
        |case| {
            case.edit(
                "constant/couplingProperties",
                "couplingInterval 1;",
                "couplingInterval 1;\ngrainPisoFoamProps { couplingSource sockets; }",
            )
        },
        &[
            "couplingSource",
            "\"sockets\"",
            "valid: frozen, prescribed, mpi",
        ],
    );
}

#[test]
fn the_mpi_source_without_the_coupler_is_refused_saying_so() {
    assert_refused(
        |case| {
            case.edit(
                "constant/couplingProperties",
                "couplingInterval 1;",
                "couplingInterval 1;\ngrainPisoFoamProps { couplingSource mpi; }",
            )
        },
        &[
            "couplingSource mpi",
            "not started by foamgrain's coupler",
            "foam-link",
        ],
    );
}
