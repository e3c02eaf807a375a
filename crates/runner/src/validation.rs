//! The validation record of a run: `CASE/postProcessing/validation.json`, a list of checks
//! `{name, simulated, reference, unit, rel_error, tolerance, pass}`. Each reference is computed
//! by the code from the case's own parameters and measured bed, never typed in.

use serde::Serialize;
use std::path::Path;

/// One check of a simulated quantity against its reference.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Check {
    /// What is compared, e.g. "pressure drop at u = 0.002 m/s".
    pub name: String,
    /// The simulated value.
    pub simulated: f64,
    /// The reference value (closed form or ODE from the case's parameters).
    pub reference: f64,
    /// Unit of both values.
    pub unit: String,
    /// |simulated − reference| / |reference| (∞ for a zero reference and a non-zero value).
    pub rel_error: f64,
    /// Largest accepted `rel_error`.
    pub tolerance: f64,
    /// `rel_error <= tolerance` and both values finite.
    pub pass: bool,
}

impl Check {
    /// The check with `gap` (what the case's documentation traces a failure to: a
    /// validationDict's `…KnownGap`) added to its name when it fails.
    pub fn with_known_gap(mut self, gap: Option<&str>) -> Check {
        if let (false, Some(gap)) = (self.pass, gap) {
            self.name = format!("{} — known gap: {gap}", self.name);
        }
        self
    }

    /// A check with its relative error and verdict computed.
    pub fn new(name: &str, simulated: f64, reference: f64, unit: &str, tolerance: f64) -> Check {
        let diff = (simulated - reference).abs();
        let rel_error = if reference != 0.0 {
            diff / reference.abs()
        } else if diff == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        let pass = simulated.is_finite() && reference.is_finite() && rel_error <= tolerance;
        Check {
            name: name.to_owned(),
            simulated,
            reference,
            unit: unit.to_owned(),
            rel_error,
            tolerance,
            pass,
        }
    }

    /// A one-sided check: `simulated` must be at least `bound` (`reference`); its error is the
    /// shortfall relative to |bound| (0 when met), its tolerance 0.
    pub fn at_least(name: &str, simulated: f64, bound: f64, unit: &str) -> Check {
        let short = (bound - simulated).max(0.0);
        let rel_error = if bound != 0.0 {
            short / bound.abs()
        } else {
            short
        };
        Check {
            name: format!("{name} (at least)"),
            simulated,
            reference: bound,
            unit: unit.to_owned(),
            rel_error,
            tolerance: 0.0,
            pass: simulated.is_finite() && bound.is_finite() && simulated >= bound,
        }
    }
}

/// Writes the checks as pretty JSON (non-finite numbers become `null`), atomically.
pub fn write_json(path: &Path, checks: &[Check]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let text = serde_json::to_string_pretty(checks).map_err(std::io::Error::other)?;
    atomic_write::write_atomically(path, |w| {
        use std::io::Write;
        w.write_all(text.as_bytes())?;
        w.write_all(b"\n")
    })
}

/// A one-line-per-check table for logs: name, simulated, reference, error, verdict.
pub fn summary(checks: &[Check]) -> String {
    let mut s = String::new();
    for c in checks {
        s.push_str(&format!(
            "{:<4} {}: {:.6} {} vs reference {:.6} {} (error {:.2} %, tolerance {:.1} %)\n",
            if c.pass { "PASS" } else { "FAIL" },
            c.name,
            c.simulated,
            c.unit,
            c.reference,
            c.unit,
            100.0 * c.rel_error,
            100.0 * c.tolerance
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_error_and_verdict() {
        let c = Check::new("dp", 23.5, 23.0, "Pa", 0.05);
        assert!((c.rel_error - 0.5 / 23.0).abs() < 1e-15);
        assert!(c.pass);
        assert!(!Check::new("dp", 30.0, 23.0, "Pa", 0.05).pass);
        assert!(!Check::new("dp", f64::NAN, 23.0, "Pa", 0.05).pass);
        assert!(!Check::new("x", 1.0, 0.0, "m", 0.05).pass);
        assert!(Check::new("x", 0.0, 0.0, "m", 0.0).pass);
    }

    #[test]
    fn at_least_is_one_sided() {
        assert!(Check::at_least("n", 3.0, 1.0, "").pass);
        assert!(Check::at_least("n", 1.0, 1.0, "").pass);
        let c = Check::at_least("n", 0.0, 1.0, "");
        assert!(!c.pass);
        assert_eq!(c.rel_error, 1.0);
        assert!(!Check::at_least("n", f64::NAN, 1.0, "").pass);
    }

    #[test]
    fn json_has_the_documented_fields_and_null_for_non_finite() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("postProcessing/validation.json");
        let checks = [
            Check::new("a", 1.0, 1.0, "m", 0.01),
            Check::new("b", f64::NAN, 1.0, "m", 0.01),
        ];
        write_json(&path, &checks).unwrap();
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let a = &v[0];
        for key in [
            "name",
            "simulated",
            "reference",
            "unit",
            "rel_error",
            "tolerance",
            "pass",
        ] {
            assert!(a.get(key).is_some(), "missing {key}");
        }
        assert_eq!(a["pass"], true);
        assert!(v[1]["simulated"].is_null());
        assert_eq!(v[1]["pass"], false);
        assert!(summary(&checks).starts_with("PASS a:"));
    }
}
