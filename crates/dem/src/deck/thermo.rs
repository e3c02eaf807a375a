//! `thermo`, `thermo_style` and `thermo_modify`: the screen output of a run, printed as LIGGGHTS
//! 3.8.0 prints it (header `%8s`/`%14s`, rows `%8d` for integers and `%14.8g` for floats, one
//! blank after each column).
//!
//! LIGGGHTS prints a row at the first step of every `run`, at every step that is a multiple of
//! the `thermo N` interval (N = 0: none), and at the last step. The default style (`one`) is
//! `step atoms ke cpu`, as LIGGGHTS 3.8's granular decks print it.
//!
//! A column is a keyword, `c_ID[i]`, `f_ID[i]` or `v_name`, evaluated by [`Values`] (which lists
//! what is computed). What foamgrain does not compute is accepted with a warning and its column
//! is left blank: a value that is not computed is never printed as a number. The header of
//! `c_`/`f_`/`v_` columns drops the prefix, as LIGGGHTS 3.8 prints it.

use liggghts_deck::expr::Ref;
use liggghts_deck::format::{thermo_float, thermo_int};
use liggghts_deck::Variables;

use crate::deck::values::{Registry, Support, Values, KEYWORDS};
use crate::outflow::LostPolicy;

type Res<T> = Result<T, String>;

/// The reference a thermo column names.
fn column_ref(word: &str) -> Res<Ref<'_>> {
    let (kind, rest) = match word.get(..2) {
        Some(p @ ("c_" | "f_" | "v_")) => (p, &word[2..]),
        _ => return Ok(Ref::Keyword(word)),
    };
    let (id, index) = match rest.split_once('[') {
        Some((id, i)) => {
            let i = i
                .strip_suffix(']')
                .and_then(|i| i.parse::<usize>().ok())
                .filter(|&i| i >= 1)
                .ok_or_else(|| format!("thermo column `{word}`: bad index"))?;
            (id, Some(i))
        }
        None => (rest, None),
    };
    if id.is_empty() {
        return Err(format!("thermo column `{word}`: no id"));
    }
    Ok(match (kind, index) {
        ("c_", i) => Ref::Compute(id, i),
        ("f_", i) => Ref::Fix(id, i),
        ("v_", None) => Ref::Variable(id),
        _ => {
            return Err(format!(
                "thermo column `{word}`: vector variables are not supported"
            ))
        }
    })
}

/// The thermo settings of a deck.
#[derive(Debug, Clone)]
pub struct Thermo {
    every: u64,
    columns: Vec<String>,
    norm: bool,
    lost: LostPolicy,
}

impl Default for Thermo {
    fn default() -> Self {
        Thermo {
            every: 0,
            columns: ["step", "atoms", "ke", "cpu"].map(String::from).to_vec(),
            norm: false,
            lost: LostPolicy::default(),
        }
    }
}

/// The columns of one run, checked against the computes and variables defined by then.
#[derive(Debug, Clone)]
pub struct RunColumns {
    /// (word, computed) per column.
    columns: Vec<(String, bool)>,
    norm: bool,
}

impl Thermo {
    /// The `thermo N` interval (0: first and last step of a run only).
    pub fn every(&self) -> u64 {
        self.every
    }

    /// `thermo_modify norm yes`.
    pub fn norm(&self) -> bool {
        self.norm
    }

    /// `thermo N`.
    pub fn set_every(&mut self, w: &[String]) -> Res<()> {
        match w {
            [_, n] => {
                self.every = n
                    .parse()
                    .map_err(|_| format!("thermo interval `{n}` is not a whole number"))?;
                Ok(())
            }
            _ => Err("usage: thermo N".into()),
        }
    }

    /// `thermo_style one|custom …`; returns warnings for keywords that are printed blank.
    pub fn set_style(&mut self, w: &[String]) -> Res<Vec<String>> {
        match w.get(1).map(String::as_str) {
            Some("one") if w.len() == 2 => {
                self.columns = Thermo::default().columns;
                Ok(Vec::new())
            }
            Some("custom") if w.len() > 2 => {
                for c in &w[2..] {
                    column_ref(c)?;
                }
                self.columns = w[2..].to_vec();
                Ok(self
                    .columns
                    .iter()
                    .filter(
                        |c| matches!(column_ref(c), Ok(Ref::Keyword(k)) if !KEYWORDS.contains(&k)),
                    )
                    .map(|k| {
                        format!(
                            "thermo keyword `{k}` is not computed by the native DEM: its column \
                             stays blank (computed: {}, c_ID, f_ID, v_name)",
                            KEYWORDS.join(" ")
                        )
                    })
                    .collect())
            }
            Some(s @ ("multi" | "custom")) => Err(if s == "custom" {
                "thermo_style custom needs at least one keyword".into()
            } else {
                "thermo_style multi is not supported (one, custom)".into()
            }),
            Some(s) => Err(format!("thermo_style `{s}` is not supported (one, custom)")),
            None => Err("usage: thermo_style one|custom KEYWORDS…".into()),
        }
    }

    /// `thermo_modify` keywords: `norm yes|no` and `lost error|warn|ignore` ([`Thermo::lost`])
    /// act; `lost/bond`, `flush`, `format`, `every`… are accepted and do nothing to the output;
    /// returns warnings for those that would change LIGGGHTS's output.
    pub fn modify(&mut self, w: &[String]) -> Res<Vec<String>> {
        let mut warnings = Vec::new();
        let mut k = 1;
        while k < w.len() {
            let value = w
                .get(k + 1)
                .ok_or_else(|| format!("thermo_modify {}: no value", w[k]))?;
            match w[k].as_str() {
                "norm" => {
                    self.norm = match value.as_str() {
                        "yes" => true,
                        "no" => false,
                        o => return Err(format!("thermo_modify norm `{o}` (yes/no expected)")),
                    }
                }
                "lost" => {
                    self.lost = LostPolicy::from_word(value).ok_or_else(|| {
                        format!("thermo_modify lost `{value}` (error, warn or ignore)")
                    })?
                }
                "lost/bond" | "flush" | "temp" | "press" | "line" => {}
                "format" => {
                    warnings.push(
                        "thermo_modify format is ignored: columns are printed as LIGGGHTS's \
                         default %8d / %14.8g"
                            .to_string(),
                    );
                    // `format int|float|line STRING` or `format N STRING`
                    k += 1;
                }
                o => warnings.push(format!("thermo_modify `{o}` is ignored")),
            }
            k += 2;
        }
        Ok(warnings)
    }

    /// What happens to particles leaving through a fixed face (`thermo_modify lost`).
    pub fn lost(&self) -> LostPolicy {
        self.lost
    }

    /// The columns for a run starting now: a compute or variable that does not exist is an
    /// error (as in LIGGGHTS), one foamgrain does not compute a warning and a blank.
    pub fn for_run(&self, registry: &Registry, vars: &Variables) -> Res<(RunColumns, Vec<String>)> {
        let mut warnings = Vec::new();
        let mut columns = Vec::with_capacity(self.columns.len());
        for c in &self.columns {
            let computed = match registry.check(column_ref(c)?, vars)? {
                Support::Yes => true,
                Support::Blank(why) => {
                    if !matches!(column_ref(c)?, Ref::Keyword(_)) {
                        warnings.push(format!("thermo column {c}: {why}; the column stays blank"));
                    }
                    false
                }
            };
            columns.push((c.clone(), computed));
        }
        Ok((
            RunColumns {
                columns,
                norm: self.norm,
            },
            warnings,
        ))
    }
}

/// LIGGGHTS's header for a column.
fn header(word: &str) -> String {
    match word {
        "step" => "Step".into(),
        "atoms" => "Atoms".into(),
        "ke" => "KinEng".into(),
        "cpu" => "CPU".into(),
        "time" => "Time".into(),
        "dt" => "Dt".into(),
        "vol" => "Volume".into(),
        w => match w.get(..2) {
            Some("c_" | "f_" | "v_") => w[2..].to_owned(),
            _ => w.to_owned(),
        },
    }
}

fn is_int(word: &str) -> bool {
    matches!(word, "step" | "atoms")
}

impl RunColumns {
    /// Whether `thermo_modify norm yes` was in force when the run started.
    pub fn norm(&self) -> bool {
        self.norm
    }

    /// The header line.
    pub fn header(&self) -> String {
        let mut s = String::new();
        for (c, _) in &self.columns {
            let width = if is_int(c) { 8 } else { 14 };
            s.push_str(&format!("{:>width$} ", header(c)));
        }
        s
    }

    /// The row for the current state; an error when a value cannot be evaluated now (an atom
    /// tag that left, a variable that became text).
    pub fn row(&self, values: &Values) -> Res<String> {
        let mut s = String::new();
        for (c, computed) in &self.columns {
            let cell = if *computed {
                let v = values.resolve(column_ref(c)?)?;
                if is_int(c) {
                    thermo_int(v as u64)
                } else {
                    thermo_float(v)
                }
            } else {
                " ".repeat(if is_int(c) { 8 } else { 14 })
            };
            s.push_str(&cell);
            s.push(' ');
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_owned).collect()
    }

    #[test]
    fn header_as_liggghts_prints_it() {
        // LIGGGHTS 3.8.0 with `thermo_style custom step atoms ke c_rke cpu time dt vol`
        // (compute rke all erotate/sphere) prints this header.
        let mut t = Thermo::default();
        let mut reg = Registry::default();
        let vars = Variables::default();
        reg.define_compute(&words("compute rke all erotate/sphere"))
            .unwrap();
        let w = t
            .set_style(&words(
                "thermo_style custom step atoms ke c_rke cpu time dt vol",
            ))
            .unwrap();
        assert!(w.is_empty());
        let (cols, w) = t.for_run(&reg, &vars).unwrap();
        assert!(w.is_empty());
        assert_eq!(
            cols.header(),
            "    Step    Atoms         KinEng            rke            CPU           Time             Dt         Volume "
        );
        // the default style
        let (cols, _) = Thermo::default().for_run(&reg, &vars).unwrap();
        assert_eq!(
            cols.header(),
            "    Step    Atoms         KinEng            CPU "
        );
    }

    #[test]
    fn what_is_not_computed_is_blank_or_an_error() {
        let mut t = Thermo::default();
        let mut reg = Registry::default();
        let vars = Variables::default();
        let w = t
            .set_style(&words("thermo_style custom step press c_x"))
            .unwrap();
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("`press`"), "{w:?}");
        let e = t.for_run(&reg, &vars).unwrap_err();
        assert!(e.contains("no compute `x`"), "{e}");
        reg.define_compute(&words("compute x all pair/gran/local pos"))
            .unwrap();
        let (_, w) = t.for_run(&reg, &vars).unwrap();
        assert!(w[0].contains("pair/gran/local"), "{w:?}");
        // a vector compute needs an element; an undefined variable is an error
        reg.define_compute(&words("compute com all com")).unwrap();
        t.set_style(&words("thermo_style custom step c_com"))
            .unwrap();
        let e = t.for_run(&reg, &vars).unwrap_err();
        assert!(e.contains("name an element"), "{e}");
        t.set_style(&words("thermo_style custom c_com[3] f_cfd2[1] v_nope"))
            .unwrap();
        let e = t.for_run(&reg, &vars).unwrap_err();
        assert!(e.contains("`nope` is not defined"), "{e}");
        assert!(t.set_style(&words("thermo_style custom c_com[0]")).is_err());
        assert!(t.set_style(&words("thermo_style multi")).is_err());
        assert!(t.set_every(&words("thermo x")).is_err());
        assert!(t.modify(&words("thermo_modify norm maybe")).is_err());
        assert!(t
            .modify(&words("thermo_modify lost ignore norm no"))
            .unwrap()
            .is_empty());
    }
}
