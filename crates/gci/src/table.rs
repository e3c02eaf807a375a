//! A grid-refinement table: one row per grid with its cell count (or cell size h), optionally the
//! domain measure, and one or more values. Read from CSV text or from command-line lists; every
//! error names the file (or argument) and the line (or item).
//!
//! CSV layout: a header line naming the columns, then one row per grid, comma separated.
//! Blank lines and lines starting with `#` are skipped.
//! - exactly one of `cells` (cell count N) or `h` (representative cell size, any length unit);
//! - optionally `volume`, `area` or `length`: the domain measure in eqs. (1)–(2) (default 1,
//!   which gives relative sizes and the same ratios when all grids cover one domain);
//! - one or more value columns, each a quantity φ analysed on its own.

use crate::error::{GciError, Location};
use crate::size::{representative_size, Dim};
use crate::study::Grid;

/// What the size column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SizeKind {
    /// Cell counts N; h follows from eq. (1)/(2).
    Cells,
    /// Representative cell sizes h given directly.
    H,
}

/// One grid's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Where it was read.
    pub at: Location,
    /// The cell count or cell size.
    pub size: f64,
    /// The domain measure (volume, area or length), 1 when not given.
    pub measure: f64,
    /// One value per quantity.
    pub values: Vec<f64>,
}

/// The rows of a study, checked: ≥ 3 rows, sizes and measures > 0, finite values, no two rows
/// with the same cell size.
#[derive(Debug, Clone, PartialEq)]
pub struct GridTable {
    /// The file name or argument the rows came from.
    pub source: String,
    /// What the size column holds.
    pub size_kind: SizeKind,
    /// The quantities' names, in column order.
    pub quantities: Vec<String>,
    /// The rows in input order.
    pub rows: Vec<Row>,
}

const SIZE_COLUMNS: [&str; 2] = ["cells", "h"];
const MEASURE_COLUMNS: [&str; 3] = ["volume", "area", "length"];

fn number(text: &str, at: &Location, column: &str) -> Result<f64, GciError> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(GciError::NotANumber {
            at: at.clone(),
            column: column.to_string(),
            text: text.to_string(),
        }),
    }
}

fn positive(value: f64, at: &Location, column: &str) -> Result<f64, GciError> {
    if value > 0.0 {
        Ok(value)
    } else {
        Err(GciError::NotPositive {
            at: at.clone(),
            column: column.to_string(),
            value,
        })
    }
}

/// The roles of the header's columns.
struct Columns {
    size: usize,
    size_kind: SizeKind,
    measure: Option<usize>,
    values: Vec<usize>,
}

fn columns(names: &[String], at: &Location, header: &str) -> Result<Columns, GciError> {
    let bad = |problem: String| GciError::Header {
        at: at.clone(),
        problem,
        header: header.to_string(),
    };
    for (i, name) in names.iter().enumerate() {
        if name.is_empty() {
            return Err(bad(format!("column {} has no name", i + 1)));
        }
        if names[..i].contains(name) {
            return Err(bad(format!("column `{name}` appears twice")));
        }
    }
    let find = |set: &[&str]| -> Vec<usize> {
        (0..names.len())
            .filter(|&i| set.contains(&names[i].as_str()))
            .collect()
    };
    let sizes = find(&SIZE_COLUMNS);
    let size = match sizes.as_slice() {
        [i] => *i,
        [] => return Err(bad("no `cells` or `h` column".into())),
        _ => return Err(bad("both `cells` and `h`: give one".into())),
    };
    let measures = find(&MEASURE_COLUMNS);
    if measures.len() > 1 {
        return Err(bad("more than one of `volume`, `area`, `length`".into()));
    }
    let measure = measures.first().copied();
    let values: Vec<usize> = (0..names.len())
        .filter(|&i| i != size && Some(i) != measure)
        .collect();
    if values.is_empty() {
        return Err(bad("no value column (e.g. `cells,value`)".into()));
    }
    let size_kind = if names[size] == "cells" {
        SizeKind::Cells
    } else {
        SizeKind::H
    };
    if size_kind == SizeKind::H && measure.is_some() {
        return Err(bad(
            "a domain measure goes with `cells`, not with `h`".into()
        ));
    }
    Ok(Columns {
        size,
        size_kind,
        measure,
        values,
    })
}

impl GridTable {
    /// Reads CSV `text`; `source` (the file name) appears in every error with the line.
    pub fn parse_csv(text: &str, source: &str) -> Result<GridTable, GciError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (header_line, header) = lines.next().ok_or_else(|| GciError::Empty {
            input: source.to_string(),
        })?;
        let at = |line| Location {
            source: source.to_string(),
            line,
        };
        let names: Vec<String> = header
            .split(',')
            .map(|n| n.trim().to_ascii_lowercase())
            .collect();
        let cols = columns(&names, &at(header_line), header)?;
        let mut rows = Vec::new();
        for (line, text) in lines {
            let here = at(line);
            let fields: Vec<&str> = text.split(',').map(str::trim).collect();
            if fields.len() != names.len() {
                return Err(GciError::FieldCount {
                    at: here,
                    expected: names.len(),
                    found: fields.len(),
                });
            }
            let read = |i: usize| number(fields[i], &here, &names[i]);
            let size = positive(read(cols.size)?, &here, &names[cols.size])?;
            let measure = match cols.measure {
                Some(i) => positive(read(i)?, &here, &names[i])?,
                None => 1.0,
            };
            let values = cols
                .values
                .iter()
                .map(|&i| read(i))
                .collect::<Result<_, _>>()?;
            rows.push(Row {
                at: here,
                size,
                measure,
                values,
            });
        }
        let table = GridTable {
            source: source.to_string(),
            size_kind: cols.size_kind,
            quantities: cols.values.iter().map(|&i| names[i].clone()).collect(),
            rows,
        };
        table.check()
    }

    /// A one-quantity table from command-line lists: `sizes` (cell counts or h, from the
    /// argument named `sizes_arg`) and `values` (from `values_arg`); errors name the argument
    /// and the item's position.
    pub fn from_lists(
        size_kind: SizeKind,
        sizes: &[f64],
        sizes_arg: &str,
        values: &[f64],
        values_arg: &str,
    ) -> Result<GridTable, GciError> {
        if sizes.len() != values.len() {
            return Err(GciError::ListLengths {
                sizes: sizes_arg.to_string(),
                n_sizes: sizes.len(),
                values: values_arg.to_string(),
                n_values: values.len(),
            });
        }
        let mut rows = Vec::with_capacity(sizes.len());
        for (i, (&size, &value)) in sizes.iter().zip(values).enumerate() {
            let at = |source: &str| Location {
                source: source.to_string(),
                line: i + 1,
            };
            if !size.is_finite() {
                return Err(GciError::NotANumber {
                    at: at(sizes_arg),
                    column: sizes_arg.to_string(),
                    text: size.to_string(),
                });
            }
            positive(size, &at(sizes_arg), sizes_arg)?;
            let value = number(&value.to_string(), &at(values_arg), values_arg)?;
            rows.push(Row {
                at: at(sizes_arg),
                size,
                measure: 1.0,
                values: vec![value],
            });
        }
        let table = GridTable {
            source: sizes_arg.to_string(),
            size_kind,
            quantities: vec!["value".to_string()],
            rows,
        };
        table.check()
    }

    /// At least three rows, no two with the same cell size (same h for any dimension: equal
    /// measure/N or equal h).
    fn check(self) -> Result<GridTable, GciError> {
        if self.rows.len() < 3 {
            return Err(GciError::TooFewGrids {
                input: self.source.clone(),
                found: self.rows.len(),
                last_line: self.rows.last().map_or(0, |r| r.at.line),
            });
        }
        for (i, row) in self.rows.iter().enumerate() {
            let key = self.size_key(row);
            if let Some(first) = self.rows[..i].iter().find(|r| self.size_key(r) == key) {
                return Err(GciError::DuplicateSize {
                    at: row.at.clone(),
                    first: first.at.clone(),
                });
            }
        }
        Ok(self)
    }

    /// A number that is equal for two rows exactly when their cell sizes are.
    fn size_key(&self, row: &Row) -> f64 {
        match self.size_kind {
            SizeKind::Cells => row.measure / row.size,
            SizeKind::H => row.size,
        }
    }

    /// The representative cell size of `row` in `dim` dimensions (eq. 1 or 2 for cell counts;
    /// the given h otherwise).
    pub fn h(&self, row: &Row, dim: Dim) -> f64 {
        match self.size_kind {
            SizeKind::Cells => representative_size(row.measure, row.size, dim),
            SizeKind::H => row.size,
        }
    }

    /// The grids of quantity number `quantity` (index into [`GridTable::quantities`]), in row
    /// order.
    pub fn grids(&self, quantity: usize, dim: Dim) -> Vec<Grid> {
        self.rows
            .iter()
            .map(|row| Grid {
                h: self.h(row, dim),
                value: row.values[quantity],
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        GridTable::parse_csv(text, "g.csv").unwrap_err().to_string()
    }

    #[test]
    fn reads_cells_measure_and_two_quantities() {
        let t = GridTable::parse_csv(
            "# study\ncells, area, drag, dp\n\n18000,76,6.063,1\n8000,76,5.972,2\r\n4500,76,5.863,3\n",
            "g.csv",
        )
        .unwrap();
        assert_eq!(t.size_kind, SizeKind::Cells);
        assert_eq!(t.quantities, ["drag", "dp"]);
        assert_eq!(t.rows.len(), 3);
        assert_eq!(t.rows[2].at.line, 6);
        assert_eq!(t.rows[1].values, [5.972, 2.0]);
        let g = t.grids(0, Dim::Two);
        assert!((g[1].h / g[0].h - 1.5).abs() < 1e-15);
        assert_eq!(g[2].value, 5.863);
    }

    #[test]
    fn errors_name_file_and_line() {
        assert_eq!(
            err("size,value\n1,2\n"),
            "g.csv:1: no `cells` or `h` column (header: `size,value`)"
        );
        assert_eq!(
            err("cells\n1\n2\n3\n"),
            "g.csv:1: no value column (e.g. `cells,value`) (header: `cells`)"
        );
        assert_eq!(
            err("h,value\n0.1,1\n0.2,x\n0.3,1\n"),
            "g.csv:3: column `value`: `x` is not a finite number"
        );
        assert_eq!(
            err("h,value\n0.1,1\n0.2,NaN\n0.3,1\n"),
            "g.csv:3: column `value`: `NaN` is not a finite number"
        );
        assert_eq!(
            err("h,value\n0.1,1\n0.2\n0.3,1\n"),
            "g.csv:3: 1 fields, the header has 2"
        );
        assert_eq!(
            err("cells,value\n100,1\n-5,1\n20,1\n"),
            "g.csv:3: column `cells` = -5 must be > 0"
        );
        assert_eq!(
            err("cells,value\n100,1\n\n50,2\n"),
            "g.csv: 2 grid(s) (last at line 4); the GCI needs at least 3"
        );
        assert_eq!(
            err("cells,value\n100,1\n50,2\n100,3\n"),
            "g.csv:4: the same cell size as g.csv:2 (two grids of one size give no refinement ratio)"
        );
        assert_eq!(
            err("cells,value,value\n1,2,3\n"),
            "g.csv:1: column `value` appears twice (header: `cells,value,value`)"
        );
        assert!(err("# only a comment\n\n").contains("empty table"));
    }

    #[test]
    fn same_count_on_a_different_domain_is_a_different_size() {
        let t = GridTable::parse_csv("cells,volume,v\n100,1,1\n100,2,2\n100,4,3\n", "g.csv");
        assert!(t.is_ok());
    }

    #[test]
    fn command_line_lists_are_checked_like_rows() {
        let e = GridTable::from_lists(
            SizeKind::Cells,
            &[1e4, 2e3],
            "--cells",
            &[1.0, 2.0],
            "--values",
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "--cells: 2 grid(s) (last at line 2); the GCI needs at least 3"
        );
        let e = GridTable::from_lists(SizeKind::H, &[0.1, 0.2], "--sizes", &[1.0], "--values")
            .unwrap_err();
        assert_eq!(e.to_string(), "--sizes has 2 item(s) but --values has 1");
        let e = GridTable::from_lists(
            SizeKind::H,
            &[0.1, 0.2, 0.1],
            "--sizes",
            &[1.0, 2.0, 3.0],
            "--values",
        )
        .unwrap_err();
        assert!(e
            .to_string()
            .starts_with("--sizes:3: the same cell size as --sizes:1"));
    }
}
