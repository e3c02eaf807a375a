//! `foamgrain gci` end to end on the fixtures in `tests/fixtures/gci`: Celik et al. (2008)
//! Table 1 through the CLI, successive triplets with a divergent one, command-line lists, and
//! bad tables whose errors name the file and line.

use approx::assert_abs_diff_eq;
use std::process::{Command, Output};
use testkit::fixture;

fn foamgrain(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foamgrain"))
        .args(args)
        .output()
        .unwrap()
}

fn ok(args: &[&str]) -> (String, String) {
    let o = foamgrain(args);
    let stderr = String::from_utf8(o.stderr).unwrap();
    assert!(o.status.success(), "{args:?}: {stderr}");
    (String::from_utf8(o.stdout).unwrap(), stderr)
}

fn gci_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["gci", "--json"];
    all.extend_from_slice(args);
    let (out, _) = ok(&all);
    assert!(!out.contains("NaN") && !out.contains("null"), "{out}");
    serde_json::from_str(&out).unwrap()
}

fn path(name: &str) -> String {
    fixture(&format!("gci/{name}"))
        .to_str()
        .unwrap()
        .to_string()
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// `x` printed with `decimals` decimals equals `table`.
fn rounds_to(x: f64, decimals: i32, table: f64) -> bool {
    let s = 10f64.powi(decimals);
    ((x * s).round() - table * s).abs() < 0.5
}

#[test]
fn celik_table_1_first_column_through_the_cli() {
    // Table 1: r21 = 1.5, r32 = 1.333, p = 1.53, φ_ext = 6.1685, e_a = 1.5 %, e_ext = 1.7 %,
    // GCI_fine = 2.2 %.
    let v = gci_json(&[&path("celik_reattachment.csv"), "--dim", "2"]);
    assert_eq!(v["dim"], 2);
    let q = &v["quantities"][0];
    assert_eq!(q["name"], "reattachment");
    assert_eq!(q["grids"][0]["line"], 4);
    let t = &q["triplets"][0];
    assert_eq!(t["behaviour"], "monotonic_convergence");
    assert_eq!(t["lines"], serde_json::json!([4, 5, 6]));
    assert!(rounds_to(f(&t["r21"]), 3, 1.5) && rounds_to(f(&t["r32"]), 3, 1.333));
    let e = &t["outcome"]["estimate"];
    assert!(rounds_to(f(&e["p"]), 2, 1.53), "{e}");
    assert!(rounds_to(f(&e["phi_ext21"]), 4, 6.1685), "{e}");
    let r = &e["relative"];
    assert!(rounds_to(100.0 * f(&r["e_a21"]), 1, 1.5), "{r}");
    assert!(rounds_to(100.0 * f(&r["e_ext21"]), 1, 1.7), "{r}");
    assert!(rounds_to(100.0 * f(&r["gci_fine21"]), 1, 2.2), "{r}");

    let (text, _) = ok(&["gci", &path("celik_reattachment.csv"), "--dim", "2"]);
    assert!(text.contains("monotonic convergence"), "{text}");
    assert!(text.contains("GCI_fine^21   2.17499 %"), "{text}");
    assert!(text.contains("φ_ext^21      6.16850"), "{text}");
}

#[test]
fn celik_table_1_velocity_columns_with_shuffled_rows() {
    // Table 1: y = 0.0526: p = 0.75, φ_ext = 10.8801 (monotonic); y = 0.652: p = 1.51,
    // φ_ext = 6.0269 (oscillatory). Both with r21 = 2.0, r32 = 2.143.
    let v = gci_json(&[&path("celik_axial_velocity.csv"), "--dim", "2"]);
    let expect = [
        ("u_y0.0526", "monotonic_convergence", 0.75, 10.8801),
        ("u_y0.652", "oscillatory_convergence", 1.51, 6.0269),
    ];
    for (q, (name, behaviour, p, ext)) in expect.iter().enumerate() {
        let quantity = &v["quantities"][q];
        assert_eq!(quantity["name"], *name);
        let t = &quantity["triplets"][0];
        assert_eq!(t["behaviour"], *behaviour);
        // Fine to coarse: 18000 cells (line 6), 4500 (line 7), 980 (line 5).
        assert_eq!(t["lines"], serde_json::json!([6, 7, 5]));
        assert!(rounds_to(f(&t["r21"]), 3, 2.0) && rounds_to(f(&t["r32"]), 3, 2.143));
        let e = &t["outcome"]["estimate"];
        assert!(rounds_to(f(&e["p"]), 2, *p), "{name}: {e}");
        assert!(rounds_to(f(&e["phi_ext21"]), 4, *ext), "{name}: {e}");
    }
    let (text, _) = ok(&["gci", &path("celik_axial_velocity.csv"), "--dim", "2"]);
    assert!(text.contains("note: oscillatory convergence"), "{text}");
}

#[test]
fn successive_triplets_report_divergence_instead_of_numbers() {
    let v = gci_json(&[&path("four_grids.csv")]);
    let ts = v["quantities"][0]["triplets"].as_array().unwrap();
    assert_eq!(ts.len(), 2);
    // φ = 2 + 0.5 h² on h = 0.1, 0.2, 0.4: p = 2, φ_ext = 2 (inputs rounded to 3 decimals).
    let e = &ts[0]["outcome"]["estimate"];
    assert!(approx::abs_diff_eq!(f(&e["p"]), 2.0, epsilon = 1e-9), "{e}");
    assert!(
        approx::abs_diff_eq!(f(&e["phi_ext21"]), 2.0, epsilon = 1e-9),
        "{e}"
    );
    assert_eq!(ts[1]["behaviour"], "oscillatory_divergence");
    assert_eq!(ts[1]["outcome"]["undefined"], "oscillatory_divergence");
    assert!(ts[1]["outcome"].get("estimate").is_none());

    let (text, _) = ok(&["gci", &path("four_grids.csv")]);
    assert!(text.contains("triplet 2 of 2 (lines 6, 7, 8)"), "{text}");
    assert!(
        text.contains("p undefined: oscillatory divergence"),
        "{text}"
    );
    let second = text.split("triplet 2 of 2").nth(1).unwrap();
    assert!(
        !second.contains("GCI") && !second.contains("NaN"),
        "{second}"
    );
}

#[test]
fn command_line_lists_safety_factor_and_small_ratio_warning() {
    let list = [
        "--cells",
        "18000,8000,4500",
        "--values",
        "6.063,5.972,5.863",
        "--dim",
        "2",
    ];
    let base = gci_json(&list);
    let three = gci_json(&[&list[..], &["--safety", "3"]].concat());
    let gci = |v: &serde_json::Value| {
        f(&v["quantities"][0]["triplets"][0]["outcome"]["estimate"]["relative"]["gci_fine21"])
    };
    assert!(rounds_to(100.0 * gci(&base), 1, 2.2));
    assert_abs_diff_eq!(gci(&three) / gci(&base), 3.0 / 1.25, epsilon = 1e-12);

    let (_, stderr) = ok(&[
        "gci",
        "--sizes",
        "1,1.2,2",
        "--values",
        "-1.01,-1.0144,-1.04",
    ]);
    assert!(
        stderr.contains("r21 = 1.20000 < 1.3"),
        "expected a small-ratio warning: {stderr}"
    );
}

fn fails(args: &[&str], expected: &str) {
    let o = foamgrain(args);
    let stderr = String::from_utf8(o.stderr).unwrap();
    assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(
        stderr.contains(expected),
        "{args:?}: expected `{expected}` in: {stderr}"
    );
}

#[test]
fn bad_tables_name_file_and_line() {
    let cases = [
        ("missing_column.csv", ":1: no `cells` or `h` column"),
        ("non_numeric.csv", ":3: 3 fields, the header has 2"),
        (
            "not_a_number.csv",
            ":3: column `value`: `about 6` is not a finite number",
        ),
        (
            "too_few.csv",
            "too_few.csv: 2 grid(s) (last at line 4); the GCI needs at least 3",
        ),
        ("duplicate_size.csv", ":4: the same cell size as"),
    ];
    for (name, expected) in cases {
        let file = path(name);
        fails(
            &["gci", &file],
            &format!("{file}{}", expected.trim_start_matches(name)),
        );
    }
    fails(
        &["gci", &path("duplicate_size.csv")],
        &format!("the same cell size as {}:2", path("duplicate_size.csv")),
    );
    fails(&["gci", "no/such/file.csv"], "cannot read no/such/file.csv");
    fails(
        &["gci", &path("celik_reattachment.csv"), "--safety", "0"],
        "setting `safety factor` = 0 is invalid",
    );
    fails(
        &["gci", "--cells", "100,50", "--values", "1,2,3"],
        "--cells has 2 item(s) but --values has 3",
    );
}
