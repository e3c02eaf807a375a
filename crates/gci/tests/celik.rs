//! The GCI procedure against independent references:
//! - Celik et al. (2008) Table 1, the worked example (three 2-D backward-facing-step
//!   quantities), to the digits the table prints;
//! - synthetic fields with a known order, φ(h) = φ0 + C h^p0, where p and φ_ext are exact;
//! - divergent and oscillatory inputs, classified by construction.

use approx::assert_abs_diff_eq;
use gci::{analyse, analyse_study, representative_size, Behaviour, Dim, Grid, Outcome, Settings};
use gci::{Method, Undefined, Warning};

/// `x` printed with `decimals` decimals equals `table` (the table's rounding).
fn rounds_to(x: f64, decimals: i32, table: f64) -> bool {
    let scale = 10f64.powi(decimals);
    ((x * scale).round() - table * scale).abs() < 0.5
}

/// One column of Celik et al. (2008) Table 1 as printed: cell counts N1–N3, φ1–φ3, r21, r32,
/// the behaviour, and p and φ_ext^21 with the number of decimals printed.
struct Column {
    cells: [f64; 3],
    phi: [f64; 3],
    r21: f64,
    r32: f64,
    behaviour: Behaviour,
    p: (f64, i32),
    phi_ext: (f64, i32),
}

/// Celik et al. (2008) Table 1. The first column (dimensionless reattachment length) used
/// N = 18000, 8000, 4500; the two axial-velocity columns (x/H = 8 at y = 0.0526 and at
/// y = 0.652) used N = 18000, 4500, 980, whence r21 = 2.0 and r32 = 2.143 (2-D:
/// h = (A/N)^(1/2)). The third column is the paper's oscillatory example.
fn table1() -> [Column; 3] {
    use Behaviour::{MonotonicConvergence as Mono, OscillatoryConvergence as Osc};
    let col = |cells, phi, r21, r32, behaviour, p, phi_ext| Column {
        cells,
        phi,
        r21,
        r32,
        behaviour,
        p: (p, 2),
        phi_ext: (phi_ext, 4),
    };
    let coarse = [18000.0, 4500.0, 980.0];
    [
        col(
            [18e3, 8e3, 4.5e3],
            [6.063, 5.972, 5.863],
            1.5,
            1.333,
            Mono,
            1.53,
            6.1685,
        ),
        col(
            coarse,
            [10.7880, 10.7250, 10.6050],
            2.0,
            2.143,
            Mono,
            0.75,
            10.8801,
        ),
        col(
            coarse,
            [6.0042, 5.9624, 6.0909],
            2.0,
            2.143,
            Osc,
            1.51,
            6.0269,
        ),
    ]
}

#[test]
fn celik_table_1_ratios_orders_and_extrapolated_values() {
    for (i, c) in table1().iter().enumerate() {
        let h = c.cells.map(|n| representative_size(1.0, n, Dim::Two));
        let t = analyse(h, c.phi, &Settings::default()).unwrap();
        assert!(rounds_to(t.r21, 3, c.r21), "column {i}: r21 {}", t.r21);
        assert!(rounds_to(t.r32, 3, c.r32), "column {i}: r32 {}", t.r32);
        assert_eq!(t.behaviour, c.behaviour, "column {i}");
        let e = t.estimate().unwrap();
        assert!(rounds_to(e.p, c.p.1, c.p.0), "column {i}: p {}", e.p);
        assert!(
            rounds_to(e.phi_ext21, c.phi_ext.1, c.phi_ext.0),
            "column {i}: φ_ext {}",
            e.phi_ext21
        );
    }
}

#[test]
fn celik_table_1_first_column_errors_and_gci() {
    // Table 1, reattachment length: e_a^21 = 1.5 %, e_ext^21 = 1.7 %, GCI_fine^21 = 2.2 %.
    let h = [18000.0, 8000.0, 4500.0].map(|n| representative_size(1.0, n, Dim::Two));
    let t = analyse(h, [6.063, 5.972, 5.863], &Settings::default()).unwrap();
    let r = t.estimate().unwrap().relative.unwrap();
    assert!(rounds_to(100.0 * r.e_a21, 1, 1.5), "{r:?}");
    assert!(rounds_to(100.0 * r.e_ext21, 1, 1.7), "{r:?}");
    assert!(rounds_to(100.0 * r.gci_fine21, 1, 2.2), "{r:?}");
}

#[test]
fn relative_errors_agree_with_eqs_5_to_7_evaluated_by_hand_on_the_table_values() {
    // For every column: eqs. (5)–(7) evaluated on the *table's* rounded p and φ_ext (not on our
    // solver's output) bound ours within what that rounding allows.
    for (i, c) in table1().iter().enumerate() {
        let h = c.cells.map(|n| representative_size(1.0, n, Dim::Two));
        let t = analyse(h, c.phi, &Settings::default()).unwrap();
        let r = t.estimate().unwrap().relative.unwrap();
        let (p, ext) = (c.p.0, c.phi_ext.0);
        let e_a = ((c.phi[0] - c.phi[1]) / c.phi[0]).abs();
        let e_ext = ((ext - c.phi[0]) / ext).abs();
        let gci = 1.25 * e_a / (t.r21.powf(p) - 1.0);
        assert!(
            approx::abs_diff_eq!(r.e_a21, e_a, epsilon = 1e-15),
            "column {i}"
        );
        // φ_ext carries ±5e-5 from the table's rounding: δe_ext ≲ 5e-5/|φ_ext|.
        assert!(
            approx::abs_diff_eq!(r.e_ext21, e_ext, epsilon = 6e-5 / ext.abs()),
            "column {i}: {r:?}"
        );
        // p carries ±5e-3: δGCI/GCI ≈ r^p ln r/(r^p − 1)·5e-3 < 1.5 % here.
        assert!(
            ((r.gci_fine21 - gci) / gci).abs() < 0.015,
            "column {i}: {r:?}"
        );
    }
}

#[test]
fn synthetic_field_of_known_order_is_recovered_to_1e_10() {
    // φ(h) = φ0 + C h^p0 on grids of unequal ratios: eq. (3a)'s root is p0 exactly and eq. (4)
    // extrapolates to φ0 exactly (up to round-off).
    let phi0 = 3.25;
    for &(p0, c) in &[
        (1.0, 0.8),
        (2.0, -5.0),
        (1.37, 2.0),
        (2.9, 40.0),
        (0.6, 0.1),
    ] {
        for &(r21, r32) in &[(1.5, 4.0 / 3.0), (2.0, 2.143), (1.3, 1.9), (2.0, 1.35)] {
            let h = [0.05, 0.05 * r21, 0.05 * r21 * r32];
            let phi = h.map(|h: f64| phi0 + c * h.powf(p0));
            let t = analyse(h, phi, &Settings::default()).unwrap();
            assert_eq!(t.behaviour, Behaviour::MonotonicConvergence);
            let e = t.estimate().unwrap();
            assert!(
                approx::abs_diff_eq!(e.p, p0, epsilon = 1e-10),
                "p0 {p0} r {r21}, {r32}: {e:?}"
            );
            assert!(
                approx::abs_diff_eq!(e.phi_ext21, phi0, epsilon = 1e-10),
                "p0 {p0}: {e:?}"
            );
            assert!(
                approx::abs_diff_eq!(e.phi_ext32, phi0, epsilon = 1e-10),
                "p0 {p0}: {e:?}"
            );
            // GCI_fine = Fs·|φ1 − φ_ext|/|φ1| for an exact model (eqs. 4, 5, 7).
            let r = e.relative.unwrap();
            let exact = 1.25 * ((phi[0] - phi0) / phi[0]).abs();
            assert_abs_diff_eq!(r.gci_fine21, exact, epsilon = 1e-10 * exact.max(1.0));
        }
    }
}

#[test]
fn alternating_field_gives_its_order_and_is_flagged_oscillatory() {
    // φ_i = φ0 + (−1)^i C h_i^p0 is the s = −1 model of eq. (3b): p is recovered, and the
    // triplet is classified as oscillatory.
    let (phi0, c, p0) = (1.0, 0.4, 1.8);
    let h: [f64; 3] = [0.1, 0.17, 0.3];
    let phi = [
        phi0 - c * h[0].powf(p0),
        phi0 + c * h[1].powf(p0),
        phi0 - c * h[2].powf(p0),
    ];
    let t = analyse(h, phi, &Settings::default()).unwrap();
    assert_eq!(t.behaviour, Behaviour::OscillatoryConvergence);
    assert_abs_diff_eq!(t.estimate().unwrap().p, p0, epsilon = 1e-10);
}

#[test]
fn divergent_and_flat_inputs_are_classified_not_numbers() {
    let h = [1.0, 2.0, 4.0];
    let cases = [
        // The change doubles on each refinement: φ moves away from any limit.
        (
            [1.0, 1.2, 1.3],
            Behaviour::MonotonicDivergence,
            Undefined::MonotonicDivergence,
        ),
        // Growing oscillation.
        (
            [1.0, 1.2, 1.1],
            Behaviour::OscillatoryDivergence,
            Undefined::OscillatoryDivergence,
        ),
        (
            [1.0, 1.0, 1.3],
            Behaviour::ZeroChangeFine,
            Undefined::ZeroChangeFine,
        ),
        (
            [1.0, 1.2, 1.2],
            Behaviour::ZeroChangeCoarse,
            Undefined::ZeroChangeCoarse,
        ),
        ([2.5, 2.5, 2.5], Behaviour::NoChange, Undefined::NoChange),
    ];
    for (phi, behaviour, why) in cases {
        let t = analyse(h, phi, &Settings::default()).unwrap();
        assert_eq!(t.behaviour, behaviour, "{phi:?}");
        assert_eq!(t.outcome, Outcome::Undefined(why), "{phi:?}");
        assert!(t.estimate().is_none());
    }
}

#[test]
fn eq_3a_alone_would_report_a_positive_order_for_a_divergent_sequence() {
    // The reason for classifying first: with r = 2 and |ε32/ε21| = 1/2, eq. (3a) gives
    // p = |ln ½|/ln 2 = 1 — a plausible-looking number for a sequence that diverges.
    let (eps21, eps32) = (0.2_f64, 0.1_f64);
    let naive = (eps32 / eps21).ln().abs() / 2f64.ln();
    assert_abs_diff_eq!(naive, 1.0, epsilon = 1e-15);
    let t = analyse([1.0, 2.0, 4.0], [1.0, 1.2, 1.3], &Settings::default()).unwrap();
    assert_eq!(
        t.outcome,
        Outcome::Undefined(Undefined::MonotonicDivergence)
    );
}

#[test]
fn small_ratios_are_warned_and_safety_factor_scales_the_gci() {
    let h = [1.0, 1.2, 2.0];
    let phi = h.map(|h: f64| 1.0 + 0.1 * h * h);
    let t = analyse(h, phi, &Settings::default()).unwrap();
    assert_eq!(
        t.warnings,
        [Warning::SmallRatio {
            pair: gci::Pair::R21,
            r: 1.2
        }]
    );
    let base = t.estimate().unwrap().relative.unwrap().gci_fine21;
    let three = analyse(h, phi, &Settings::with_safety_factor(3.0).unwrap()).unwrap();
    let scaled = three.estimate().unwrap().relative.unwrap().gci_fine21;
    assert_abs_diff_eq!(scaled / base, 3.0 / 1.25, epsilon = 1e-14);
    assert!(Settings::with_safety_factor(0.0).is_err());
    assert!(Settings::with_safety_factor(f64::NAN).is_err());
}

#[test]
fn zero_fine_value_leaves_relative_errors_undefined() {
    // φ1 = 0: e_a = |φ1 − φ2|/|φ1| has no meaning; p and φ_ext still do.
    let h = [1.0, 2.0, 4.0];
    let phi = [0.0, 0.3, 1.5];
    let t = analyse(h, phi, &Settings::default()).unwrap();
    let e = t.estimate().unwrap();
    assert_abs_diff_eq!(e.p, 2.0, epsilon = 1e-14);
    assert_abs_diff_eq!(e.phi_ext21, (-0.1), epsilon = 1e-14);
    assert!(e.relative.is_none());
}

#[test]
fn four_grids_give_two_successive_triplets_in_any_input_order() {
    // φ = 1 + h² on h = 1, 2, 4, 8 given shuffled: triplets (1,2,4) and (2,4,8), both p = 2.
    let grids = [8.0, 1.0, 4.0, 2.0].map(|h: f64| Grid {
        h,
        value: 1.0 + h * h,
    });
    let ts = analyse_study(&grids, &Settings::default()).unwrap();
    assert_eq!(ts.len(), 2);
    assert_eq!(ts[0].h, [1.0, 2.0, 4.0]);
    assert_eq!(ts[1].h, [2.0, 4.0, 8.0]);
    assert_eq!(ts[0].grids, [1, 3, 2]);
    assert_eq!(ts[1].grids, [3, 2, 0]);
    for t in &ts {
        let e = t.estimate().unwrap();
        assert_abs_diff_eq!(e.p, 2.0, epsilon = 1e-14);
        assert_abs_diff_eq!(e.phi_ext21, 1.0, epsilon = 1e-13);
        assert_eq!(e.method, Method::FixedPoint);
    }
    assert!(analyse_study(&grids[..2], &Settings::default()).is_err());
}

#[test]
fn unordered_or_non_finite_grids_are_refused() {
    let s = Settings::default();
    assert!(analyse([2.0, 1.0, 4.0], [1.0, 2.0, 3.0], &s).is_err());
    assert!(analyse([1.0, 1.0, 4.0], [1.0, 2.0, 3.0], &s).is_err());
    assert!(analyse([0.0, 1.0, 4.0], [1.0, 2.0, 3.0], &s).is_err());
    assert!(analyse([1.0, 2.0, 4.0], [1.0, f64::NAN, 3.0], &s).is_err());
}
