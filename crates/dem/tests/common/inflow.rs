//! Thermo rows `step atoms inserted mass` of the insertion decks (`outflow.in`, `stream.in`)
//! and their comparison with LIGGGHTS's rows and a closed-form expected count.

/// A thermo row: step, atoms, inserted number, inserted mass (kg).
pub type Row = (u64, u64, u64, f64);

/// The rows of a LIGGGHTS log or of the native output lines (lines of four numbers).
pub fn rows<'a>(lines: impl Iterator<Item = &'a str>) -> Vec<Row> {
    lines
        .filter_map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            if w.len() != 4 {
                return None;
            }
            Some((
                w[0].parse().ok()?,
                w[1].parse().ok()?,
                w[2].parse().ok()?,
                w[3].parse().ok()?,
            ))
        })
        .collect()
}

/// Compares the native rows with LIGGGHTS's: same steps, inserted number and mass (to 1e-8
/// relative) on every row, the same atoms before step `first_exit`, and both atom counts within
/// 5 σ + 3 of `expected(step)` = (mean, binomial variance) (the 3 for LIGGGHTS removing lost
/// atoms only when it re-neighbours). Returns Σ atoms over the rows: native, LIGGGHTS, expected.
pub fn compare(
    ours: &[Row],
    theirs: &[Row],
    first_exit: u64,
    expected: impl Fn(u64) -> (f64, f64),
) -> (f64, f64, f64) {
    assert_eq!(ours.len(), theirs.len());
    let (mut area_ours, mut area_theirs, mut area_expected) = (0.0, 0.0, 0.0);
    for (a, b) in ours.iter().zip(theirs) {
        assert_eq!(a.0, b.0, "thermo steps");
        assert_eq!(a.2, b.2, "inserted at step {}", a.0);
        assert!(
            (a.3 - b.3).abs() <= 1e-8 * b.3,
            "mass at step {}: {a:?} {b:?}",
            a.0
        );
        if a.0 < first_exit {
            assert_eq!(a.1, b.1, "atoms at step {}", a.0);
        }
        let (mean, var) = expected(a.0);
        let tol = 5.0 * var.sqrt() + 3.0;
        for (who, n) in [("native", a.1), ("LIGGGHTS", b.1)] {
            assert!(
                (n as f64 - mean).abs() <= tol,
                "{who}: {n} atoms at step {}, expected {mean:.1} ± {:.1}",
                a.0,
                var.sqrt()
            );
        }
        area_ours += a.1 as f64;
        area_theirs += b.1 as f64;
        area_expected += mean;
    }
    (area_ours, area_theirs, area_expected)
}
