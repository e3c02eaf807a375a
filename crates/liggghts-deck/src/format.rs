//! C's `%.Pg`, the number format LAMMPS and LIGGGHTS print with: equal-style variables are
//! substituted as `%.15g` (`$(formula)` as `%.20g`), thermo columns are `%14.8g` (see [`thermo_float`]) and integers
//! `%8d`.
//!
//! `%.Pg` rounds to P significant digits, then uses scientific notation when the decimal
//! exponent X of the rounded value is < −4 or ≥ P, fixed notation with P − 1 − X decimals
//! otherwise, and drops trailing zeros (and a trailing point). The exponent has a sign and at
//! least two digits (`1e-05`, `2.5e+20`), as glibc prints it.

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
        let m = trim_zeros(mantissa);
        format!("{m}e{}{:02}", if exp < 0 { '-' } else { '+' }, exp.abs())
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

/// A floating-point thermo column as LIGGGHTS 3.8 prints it: `%14.8g`.
pub fn thermo_float(v: f64) -> String {
    format!("{:>14}", format_g(v, 8))
}

/// An integer thermo column (`Step`, `Atoms`) as LIGGGHTS 3.8 prints it: `%8d`.
pub fn thermo_int(v: u64) -> String {
    format!("{v:>8}")
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn thermo_columns_line_up_as_liggghts_prints_them() {
        // A row of LIGGGHTS 3.8.0's log (tests/fixtures/dem/pour_liggghts.log):
        // "       1     3000  0.00067464093    0.005550462 "
        let row = format!(
            "{} {} {} {} ",
            thermo_int(1),
            thermo_int(3000),
            thermo_float(0.00067464093),
            thermo_float(0.005550462)
        );
        assert_eq!(row, "       1     3000  0.00067464093    0.005550462 ");
    }
}
