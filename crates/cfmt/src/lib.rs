//! Numbers as C's `printf` writes them, which LIGGGHTS's and OpenFOAM's text files use:
//!
//! * `%.Pg` ([`format_g`]) rounds to P significant digits, then uses scientific notation when
//!   the decimal exponent X of the rounded value is < −4 or ≥ P, fixed notation with P − 1 − X
//!   decimals otherwise, and drops trailing zeros (and a trailing point). LAMMPS and LIGGGHTS
//!   substitute equal-style variables as `%.15g` and print thermo columns as `%14.8g`;
//!   OpenFOAM names time directories with its `general` format, a `%g`.
//! * `%.De` ([`format_e`]): one digit, the point and D decimals, then the exponent; OpenFOAM's
//!   `scientific` streams (function-object files) write this.
//!
//! The exponent has a sign and at least two digits (`1e-05`, `2.5e+20`), as glibc prints it.

/// `v` as C's `printf("%.{precision}g", v)` (precision 0 counts as 1).
pub fn format_g(v: f64, precision: usize) -> String {
    let p = precision.max(1);
    if v.is_nan() {
        return if v.is_sign_negative() { "-nan" } else { "nan" }.into();
    }
    if v.is_infinite() {
        return if v < 0.0 { "-inf" } else { "inf" }.into();
    }
    if v == 0.0 {
        return if v.is_sign_negative() { "-0" } else { "0" }.into();
    }
    // The exponent after rounding to p significant digits (9.9999999 → 1e+01 at p = 8).
    let sci = format!("{:.*e}", p - 1, v);
    let (mantissa, exp) = sci.split_once('e').expect("`{:e}` has an exponent");
    let exp: i32 = exp.parse().expect("`{:e}` exponent is an integer");
    if exp < -4 || exp >= p as i32 {
        c_exponent(trim_zeros(mantissa), exp)
    } else {
        let decimals = (p as i32 - 1 - exp) as usize;
        trim_zeros(&format!("{v:.decimals$}")).to_owned()
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// `v` as C's `printf("%.{digits}e", v)` (`-4.081169e-04`).
pub fn format_e(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return format_g(v, 1);
    }
    let s = format!("{v:.digits$e}");
    let (mantissa, exp) = s.split_once('e').expect("`{:e}` has an exponent");
    let exp: i32 = exp.parse().expect("`{:e}` exponent is an integer");
    c_exponent(mantissa, exp)
}

/// `mantissa` and a signed exponent of at least two digits, as glibc writes them.
fn c_exponent(mantissa: &str, exp: i32) -> String {
    format!(
        "{mantissa}e{}{:02}",
        if exp < 0 { '-' } else { '+' },
        exp.abs()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scientific_as_c_writes_it() {
        // glibc's printf("%.6e") / ("%.3e")
        assert_eq!(format_e(-4.081169e-4, 6), "-4.081169e-04");
        assert_eq!(format_e(0.01, 6), "1.000000e-02");
        assert_eq!(format_e(0.0, 6), "0.000000e+00");
        assert_eq!(format_e(1.5e123, 3), "1.500e+123");
    }

    #[test]
    fn matches_c_printf() {
        // Expected strings are what glibc's printf("%.15g") / ("%.8g") prints.
        for (v, p, want) in [
            (5.0, 15, "5"),
            (1e-5, 15, "1e-05"),
            (0.1 + 0.2, 15, "0.3"),
            (-2.5e20, 15, "-2.5e+20"),
            (12345.678, 15, "12345.678"),
            (0.0001, 15, "0.0001"),
            (0.00001234, 8, "1.234e-05"),
            (99999999.5, 8, "1e+08"),
            (9.99999999, 8, "10"),
            (1.6783027e-06, 8, "1.6783027e-06"),
            (0.00067464093, 8, "0.00067464093"),
            (26.281027, 8, "26.281027"),
            (1e15, 15, "1e+15"),
            (123456789012345.0, 15, "123456789012345"),
            (-0.0, 8, "-0"),
            (1.0 / 3.0, 8, "0.33333333"),
        ] {
            assert_eq!(format_g(v, p), want, "{v} at %.{p}g");
        }
    }
}
