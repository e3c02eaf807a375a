//! `thermo`, `thermo_style`, `thermo_modify` and the `compute` styles a thermo column can name:
//! the screen output of a run, printed as LIGGGHTS 3.8.0 prints it (header `%8s`/`%14s`, rows
//! `%8d` for integers and `%14.8g` for floats, one blank after each column).
//!
//! LIGGGHTS prints a row at the first step of every `run`, at every step that is a multiple of
//! the `thermo N` interval (N = 0: none), and at the last step. The default style (`one`) is
//! `step atoms ke cpu`, as LIGGGHTS 3.8's granular decks print it.
//!
//! Columns: `step`, `atoms`, `ke` (Σ ½m|v|², J), `cpu` (wall seconds since the run began),
//! `time` (simulated s), `dt` (s), `vol` (box volume, m³, shrink-wrapped faces following the
//! particles), `c_ID` of `compute ID all erotate/sphere` (Σ ½I|ω|², J). Any other keyword or
//! compute is accepted with a warning and its column is left blank: a value that is not
//! computed is never printed as a number. `thermo_modify norm yes` divides the extensive
//! energies by the number of atoms (LIGGGHTS's default for `units si` is `norm no`).

use std::collections::HashMap;

use liggghts_deck::format::{thermo_float, thermo_int};

use crate::sim::Simulation;

type Res<T> = Result<T, String>;

/// A thermo column as the deck names it.
#[derive(Debug, Clone, PartialEq)]
enum Column {
    Step,
    Atoms,
    Ke,
    Cpu,
    Time,
    Dt,
    Vol,
    /// `c_ID` or `c_ID[k]`: a compute (its id, the keyword after `c_` for the header),
    /// resolved when a run starts (LIGGGHTS allows defining it later).
    Compute {
        id: String,
        label: String,
    },
    /// A keyword foamgrain does not compute: printed blank.
    Blank(String),
}

impl Column {
    fn parse(word: &str) -> Column {
        match word {
            "step" => Column::Step,
            "atoms" => Column::Atoms,
            "ke" => Column::Ke,
            "cpu" => Column::Cpu,
            "time" => Column::Time,
            "dt" => Column::Dt,
            "vol" => Column::Vol,
            w => match w.strip_prefix("c_") {
                Some(label) if !label.is_empty() => Column::Compute {
                    id: label.split('[').next().unwrap_or(label).to_owned(),
                    label: label.to_owned(),
                },
                _ => Column::Blank(w.to_owned()),
            },
        }
    }

    /// LIGGGHTS's header for the column.
    fn header(&self) -> String {
        match self {
            Column::Step => "Step".into(),
            Column::Atoms => "Atoms".into(),
            Column::Ke => "KinEng".into(),
            Column::Cpu => "CPU".into(),
            Column::Time => "Time".into(),
            Column::Dt => "Dt".into(),
            Column::Vol => "Volume".into(),
            Column::Compute { label, .. } => label.clone(),
            Column::Blank(w) => w.clone(),
        }
    }

    fn is_int(&self) -> bool {
        matches!(self, Column::Step | Column::Atoms)
    }
}

/// The compute styles a thermo column can print.
#[derive(Debug, Clone, PartialEq)]
pub enum ComputeStyle {
    /// `erotate/sphere`: rotational kinetic energy of the spheres (J).
    RotationalEnergy,
    /// Any other style: accepted (the deck may need it for something foamgrain ignores), but a
    /// thermo column naming it stays blank.
    Unsupported(String),
}

/// The thermo settings of a deck and the computes it defines.
#[derive(Debug, Clone)]
pub struct Thermo {
    every: u64,
    columns: Vec<Column>,
    norm: bool,
    computes: HashMap<String, ComputeStyle>,
}

impl Default for Thermo {
    fn default() -> Self {
        Thermo {
            every: 0,
            columns: vec![Column::Step, Column::Atoms, Column::Ke, Column::Cpu],
            norm: false,
            computes: HashMap::new(),
        }
    }
}

/// The columns of one run, resolved against the computes defined by then.
#[derive(Debug, Clone)]
pub struct RunColumns {
    columns: Vec<(Column, Option<ComputeStyle>)>,
    norm: bool,
}

impl Thermo {
    /// The `thermo N` interval (0: first and last step of a run only).
    pub fn every(&self) -> u64 {
        self.every
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

    /// `thermo_style one|custom …`; returns warnings for what is printed blank.
    pub fn set_style(&mut self, w: &[String]) -> Res<Vec<String>> {
        match w.get(1).map(String::as_str) {
            Some("one") if w.len() == 2 => {
                self.columns = Thermo::default().columns;
                Ok(Vec::new())
            }
            Some("custom") if w.len() > 2 => {
                self.columns = w[2..].iter().map(|k| Column::parse(k)).collect();
                Ok(self
                    .columns
                    .iter()
                    .filter_map(|c| match c {
                        Column::Blank(k) => Some(format!(
                            "thermo keyword `{k}` is not computed by the native DEM: its column \
                             stays blank (computed: step atoms ke cpu time dt vol \
                             c_ID of erotate/sphere)"
                        )),
                        _ => None,
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

    /// `thermo_modify` keywords: `norm yes|no` acts; `lost ignore|warn|error`, `lost/bond`,
    /// `flush`, `format`, `every`… are accepted and do nothing to the output (particles that
    /// leave the box are removed and counted either way); returns warnings for those that would
    /// change LIGGGHTS's output.
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
                "lost" | "lost/bond" | "flush" | "temp" | "press" | "line" => {}
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

    /// `compute ID GROUP STYLE …`.
    pub fn define_compute(&mut self, w: &[String]) -> Res<()> {
        let (Some(id), Some(style)) = (w.get(1), w.get(3)) else {
            return Err("usage: compute ID GROUP STYLE …".into());
        };
        let style = match style.as_str() {
            "erotate/sphere" => ComputeStyle::RotationalEnergy,
            s => ComputeStyle::Unsupported(s.to_owned()),
        };
        self.computes.insert(id.clone(), style);
        Ok(())
    }

    /// `uncompute ID`.
    pub fn remove_compute(&mut self, id: &str) -> Res<()> {
        self.computes
            .remove(id)
            .map(|_| ())
            .ok_or_else(|| format!("uncompute: no compute `{id}`"))
    }

    /// The columns for a run starting now; a `c_ID` whose compute is missing is an error (as
    /// in LIGGGHTS), one of a style foamgrain does not compute gives a warning and a blank.
    pub fn for_run(&self) -> Res<(RunColumns, Vec<String>)> {
        let mut warnings = Vec::new();
        let mut columns = Vec::with_capacity(self.columns.len());
        for c in &self.columns {
            let style = match c {
                Column::Compute { id, label } => {
                    let style = self
                        .computes
                        .get(id)
                        .ok_or_else(|| format!("thermo column c_{label}: no compute `{id}`"))?;
                    let style = match style {
                        ComputeStyle::RotationalEnergy if label != id => ComputeStyle::Unsupported(
                            format!("erotate/sphere (a scalar) as {label}"),
                        ),
                        s => s.clone(),
                    };
                    if let ComputeStyle::Unsupported(s) = &style {
                        warnings.push(format!(
                            "thermo column c_{label}: compute style `{s}` is not computed by the \
                             native DEM; the column stays blank"
                        ));
                    }
                    Some(style)
                }
                _ => None,
            };
            columns.push((c.clone(), style));
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

impl RunColumns {
    /// The header line.
    pub fn header(&self) -> String {
        let mut s = String::new();
        for (c, _) in &self.columns {
            let width = if c.is_int() { 8 } else { 14 };
            s.push_str(&format!("{:>width$} ", c.header()));
        }
        s
    }

    /// The row for the simulation's current state; `cpu` is the wall time since the run
    /// started (s).
    pub fn row(&self, sim: &Simulation, cpu: f64) -> String {
        let atoms = sim.particles.len();
        let per = if self.norm && atoms > 0 {
            1.0 / atoms as f64
        } else {
            1.0
        };
        let mut s = String::new();
        for (c, style) in &self.columns {
            let cell = match (c, style) {
                (Column::Step, _) => thermo_int(sim.step()),
                (Column::Atoms, _) => thermo_int(atoms as u64),
                (Column::Ke, _) => thermo_float(sim.particles.translational_energy() * per),
                (Column::Cpu, _) => thermo_float(cpu),
                (Column::Time, _) => thermo_float(sim.time()),
                (Column::Dt, _) => thermo_float(sim.dt()),
                (Column::Vol, _) => {
                    let b = sim.sim_box().dump_bounds(&sim.particles.x);
                    thermo_float((0..3).map(|k| b.hi[k] - b.lo[k]).product())
                }
                (Column::Compute { .. }, Some(ComputeStyle::RotationalEnergy)) => {
                    thermo_float(sim.particles.rotational_energy() * per)
                }
                (Column::Compute { .. } | Column::Blank(_), _) => " ".repeat(14),
            };
            s.push_str(&cell);
            s.push(' ');
        }
        s
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
        t.define_compute(&words("compute rke all erotate/sphere"))
            .unwrap();
        let w = t
            .set_style(&words(
                "thermo_style custom step atoms ke c_rke cpu time dt vol",
            ))
            .unwrap();
        assert!(w.is_empty());
        let (cols, w) = t.for_run().unwrap();
        assert!(w.is_empty());
        assert_eq!(
            cols.header(),
            "    Step    Atoms         KinEng            rke            CPU           Time             Dt         Volume "
        );
        // the default style
        let (cols, _) = Thermo::default().for_run().unwrap();
        assert_eq!(
            cols.header(),
            "    Step    Atoms         KinEng            CPU "
        );
    }

    #[test]
    fn what_is_not_computed_is_blank_or_an_error() {
        let mut t = Thermo::default();
        let w = t
            .set_style(&words("thermo_style custom step press c_x"))
            .unwrap();
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("`press`"), "{w:?}");
        let e = t.for_run().unwrap_err();
        assert!(e.contains("no compute `x`"), "{e}");
        t.define_compute(&words("compute x all pair/gran/local pos"))
            .unwrap();
        let (_, w) = t.for_run().unwrap();
        assert!(w[0].contains("pair/gran/local"), "{w:?}");
        assert!(t.set_style(&words("thermo_style multi")).is_err());
        assert!(t.set_every(&words("thermo x")).is_err());
        assert!(t.modify(&words("thermo_modify norm maybe")).is_err());
        assert!(t
            .modify(&words("thermo_modify lost ignore norm no"))
            .unwrap()
            .is_empty());
    }
}
