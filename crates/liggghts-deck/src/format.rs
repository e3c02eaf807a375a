//! The number formats LAMMPS and LIGGGHTS print with: equal-style variables are substituted as
//! `%.15g` (`$(formula)` as `%.20g`), thermo columns are `%14.8g` (see [`thermo_float`]) and
//! integers `%8d`. C's `%g` itself is [`cfmt::format_g`].

pub use cfmt::format_g;

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
