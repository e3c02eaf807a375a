//! What a read deck declares that other crates need before or around running it: the typed
//! accessors that every crate uses instead of interpreting commands itself — the DEM time step,
//! the files the deck reads and writes, the `processors` grid, CFDEM's coupling fixes
//! (`couple/cfd`, `couple/cfd/force[/implicit]`, and `couple/cfd/convection`, which makes the
//! DEM take a convective heat flow per particle), LIGGGHTS-PFM's `coarsegraining` factor and the
//! material values the time-step advice reads.
//!
//! Executing a command stays the executor's business (`dem`), and the checks LIGGGHTS needs
//! before it sees a coupled deck stay `liggghts`'s; what a command *says* is read here, once.
//! Every accessor reads the words as [`Deck::parse`] left them (variables substituted, `&`
//! continuations joined), and an ill-formed argument is a [`DeckError::Syntax`] naming the file
//! and line.

use crate::{Command, Deck, DeckError};

/// A file a command names, as written (relative paths are the caller's to resolve: LIGGGHTS
/// resolves them against its working directory).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeckFile {
    /// 1-based line of the command.
    pub line: usize,
    /// The command ([`Command::label`]: `read_data`, `dump`, `fix print`, …).
    pub command: String,
    /// The path as the deck writes it (a `*` in a restart name stands for a step).
    pub path: String,
}

/// `processors Px Py Pz`: the LIGGGHTS rank grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Processors {
    /// 1-based line of the command.
    pub line: usize,
    /// Ranks along x, y, z (`None` for `*`: LIGGGHTS chooses).
    pub grid: [Option<usize>; 3],
}

/// How `couple/cfd` exchanges data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DataCoupling {
    /// `mpi`: through library calls (in-process).
    Mpi,
    /// `file PREFIX`: through files named PREFIX + property + `0`/`1`.
    File(String),
}

/// `fix ID GROUP couple/cfd [couple_every|every N] mpi|file PREFIX`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CoupleFix {
    /// 1-based line.
    pub line: usize,
    /// The fix id.
    pub id: String,
    /// The fix group.
    pub group: String,
    /// `couple_every N` when given (LIGGGHTS ignores it with `mpi`: the coupler decides).
    pub couple_every: Option<u64>,
    /// `mpi` or `file PREFIX`.
    pub data: DataCoupling,
}

/// An option of the force fix that changes the particle force law, or switches off what
/// LIGGGHTS 3.8.0 needs (the `liggghts` crate refuses these; see [`ForceFix::law_options`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ForceLawOption {
    /// `transfer_torque no`.
    NoTorque,
    /// `CrankNicolson …` or `CAddRhoFluid …` (the word).
    Law(String),
}

/// `fix ID GROUP couple/cfd/force[/implicit] [options]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ForceFix {
    /// 1-based line.
    pub line: usize,
    /// `couple/cfd/force/implicit` (applies Ksl·(uf − v) + dragforce every step) rather than
    /// `couple/cfd/force` (applies dragforce only).
    pub implicit: bool,
    /// `transfer_density yes`.
    pub transfer_density: bool,
    /// `transfer_type yes`.
    pub transfer_type: bool,
    /// Options other than transfer_density/transfer_type/transfer_torque and the force-law
    /// ones (they add exchange files).
    pub other_options: bool,
    /// The force-law options in the order written.
    pub law_options: Vec<ForceLawOption>,
    /// The command's words.
    pub words: Vec<String>,
}

/// One of CFDEM's coupling fixes, in deck order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CfdFix {
    /// `couple/cfd`.
    Couple(CoupleFix),
    /// `couple/cfd/force` or `couple/cfd/force/implicit`.
    Force(ForceFix),
}

/// `fix ID GROUP couple/cfd/convection T0 T`: the DEM takes a convective heat flow per particle
/// from the CFD side (and hands it the particle temperatures, `Temp`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvectionFix {
    /// 1-based deck line.
    pub line: usize,
    /// `T0` (K): the initial temperature when this fix creates the heat equation.
    pub t0: f64,
}

/// What `fix couple/cfd` and `fix couple/cfd/force[/implicit]` declare together.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoupledDeck {
    /// `couple_every N`: DEM steps per coupling exchange (1 when not given).
    pub couple_every: u64,
    /// Whether the force fix is `couple/cfd/force/implicit` (else `couple/cfd/force`, or none).
    pub implicit: bool,
    /// Whether a force fix follows `couple/cfd`.
    pub has_force_fix: bool,
}

/// Material and particle values for the time-step advice (each `None` was not declared).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Materials {
    /// `timestep`, s.
    pub timestep: Option<f64>,
    /// `youngsModulus peratomtype` (first type), Pa.
    pub young: Option<f64>,
    /// `poissonsRatio peratomtype` (first type).
    pub poisson: Option<f64>,
    /// `coefficientRestitution peratomtypepair n` (first value).
    pub restitution: Option<f64>,
    /// `particletemplate/sphere … density constant` or `set … density`, kg/m³.
    pub density: Option<f64>,
    /// `particletemplate/sphere … radius constant`, or half of `set … diameter`, m.
    pub radius: Option<f64>,
    /// `thermalCapacity peratomtype` (first type), J/(kg K): the particles' c_p of `fix
    /// heat/gran` (checks of heat-transfer cases).
    pub thermal_capacity: Option<f64>,
    /// `thermalConductivity peratomtype` (first type), W/(m K).
    pub thermal_conductivity: Option<f64>,
}

/// What LIGGGHTS-PFM does with a model that coarse graining does not scale consistently
/// (`coarsegraining CG model_check error|warn`; its `doc/coarsegraining.txt`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelCheck {
    /// Such a model is an error (PFM's default).
    Error,
    /// Such a model is a warning; it runs unscaled.
    Warn,
}

/// `coarsegraining CG [model_check error|warn]` (LIGGGHTS-PFM, not Debian's LIGGGHTS 3.8.0):
/// each particle is a parcel standing for CG³ particles of radius r/CG. PFM multiplies the
/// radii of `particletemplate/sphere … radius constant` and of `set … diameter`, and the
/// neighbour skin and bin size, by CG; CFDEM-PFM's drag laws evaluate a particle of diameter
/// d/CG and multiply its drag by CG³.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoarseGraining {
    /// 1-based line of the command.
    pub line: usize,
    /// The factor CG ≥ 1 (dimensionless).
    pub factor: f64,
    /// `model_check` (default `error`).
    pub model_check: ModelCheck,
}

impl CoarseGraining {
    /// The arguments of a `coarsegraining` command, with LIGGGHTS-PFM's checks
    /// (`src/coarsegraining.cpp`): a number ≥ 1, then only `model_check error|warn`. The
    /// error is the message without the location ([`Deck::coarse_graining`] adds it).
    pub fn parse(c: &Command) -> Result<CoarseGraining, String> {
        let w = &c.words;
        let factor = w
            .get(1)
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|x| x.is_finite())
            .ok_or("coarsegraining: expected the factor CG (a number)")?;
        if factor < 1.0 {
            return Err(format!(
                "coarsegraining {factor}: the factor must be ≥ 1 (LIGGGHTS-PFM: cg > 1 expected)"
            ));
        }
        let mut model_check = ModelCheck::Error;
        let mut k = 2;
        while k < w.len() {
            model_check = match (w[k].as_str(), w.get(k + 1).map(String::as_str)) {
                ("model_check", Some("error")) => ModelCheck::Error,
                ("model_check", Some("warn")) => ModelCheck::Warn,
                ("model_check", _) => {
                    return Err(
                        "coarsegraining: expected `error` or `warn` after `model_check`".into(),
                    )
                }
                (other, _) => {
                    return Err(format!(
                        "coarsegraining: unknown keyword `{other}` (model_check)"
                    ))
                }
            };
            k += 2;
        }
        Ok(CoarseGraining {
            line: c.line,
            factor,
            model_check,
        })
    }
}

impl Materials {
    /// Values of `other` where this one has none.
    pub fn or(self, other: Materials) -> Materials {
        Materials {
            timestep: self.timestep.or(other.timestep),
            young: self.young.or(other.young),
            poisson: self.poisson.or(other.poisson),
            restitution: self.restitution.or(other.restitution),
            density: self.density.or(other.density),
            radius: self.radius.or(other.radius),
            thermal_capacity: self.thermal_capacity.or(other.thermal_capacity),
            thermal_conductivity: self.thermal_conductivity.or(other.thermal_conductivity),
        }
    }
}

impl Deck {
    /// The commands named `name` (`fix` styles: [`Deck::fixes`]), in order.
    pub fn named<'d>(&'d self, name: &'d str) -> impl Iterator<Item = &'d Command> + 'd {
        self.commands
            .iter()
            .filter(move |c| c.words.first().map(String::as_str) == Some(name))
    }

    /// The `fix ID GROUP STYLE …` commands of style `style`, in order.
    pub fn fixes<'d>(&'d self, style: &'d str) -> impl Iterator<Item = &'d Command> + 'd {
        self.named("fix")
            .filter(move |c| c.words.get(3).map(String::as_str) == Some(style))
    }

    /// `timestep DT` (s): the last one with a numeric value, the step LIGGGHTS runs with once
    /// the deck is read.
    pub fn time_step(&self) -> Option<f64> {
        self.named("timestep")
            .filter_map(|c| c.words.get(1)?.parse::<f64>().ok())
            .last()
    }

    /// The files the deck reads particles from: `read_data FILE` and `read_restart FILE`, in
    /// order (the first is the one a coupled deck starts from).
    pub fn read_files(&self) -> Vec<DeckFile> {
        self.commands
            .iter()
            .filter(|c| {
                matches!(
                    c.words.first().map(String::as_str),
                    Some("read_data" | "read_restart")
                )
            })
            .filter_map(|c| file_of(c, 1))
            .collect()
    }

    /// The files the deck's outputs go to: `dump ID GROUP STYLE N FILE`, `fix ID GROUP print N
    /// TEXT file|append FILE`, `write_data`, `write_restart` and `write_dump`'s files, in order.
    pub fn written_files(&self) -> Vec<DeckFile> {
        self.commands.iter().filter_map(written_file).collect()
    }

    /// `processors Px Py Pz`, the last one.
    pub fn processors(&self) -> Result<Option<Processors>, DeckError> {
        let mut out = None;
        for c in self.named("processors") {
            let mut grid = [None; 3];
            for (k, g) in grid.iter_mut().enumerate() {
                let word = c.words.get(k + 1).map(String::as_str).unwrap_or("");
                *g = match word {
                    "*" => None,
                    n => match n.parse::<usize>() {
                        Ok(n) if n >= 1 => Some(n),
                        _ => {
                            return Err(self.syntax(
                                c,
                                format!("processors: `{word}` is not a rank count ≥ 1 or `*`"),
                            ))
                        }
                    },
                };
            }
            out = Some(Processors { line: c.line, grid });
        }
        Ok(out)
    }

    /// CFDEM's coupling fixes in deck order, each read whole (an ill-formed one is an error
    /// naming its line).
    pub fn cfd_fixes(&self) -> Result<Vec<CfdFix>, DeckError> {
        let mut out = Vec::new();
        for c in self.named("fix") {
            match c.words.get(3).map(String::as_str) {
                Some("couple/cfd") => {
                    let f = couple_fix(c).map_err(|m| self.syntax(c, m))?;
                    out.push(CfdFix::Couple(f));
                }
                Some("couple/cfd/force" | "couple/cfd/force/implicit") => {
                    let f = force_fix(c).map_err(|m| self.syntax(c, m))?;
                    out.push(CfdFix::Force(f));
                }
                _ => {}
            }
        }
        Ok(out)
    }

    /// The deck's `couple/cfd/convection` fix, if any (the last one): the CFD side then
    /// exchanges heat with the particles. An ill-formed one is an error naming its line.
    pub fn convection(&self) -> Result<Option<ConvectionFix>, DeckError> {
        let mut out = None;
        for c in self.named("fix") {
            if c.words.get(3).map(String::as_str) != Some("couple/cfd/convection") {
                continue;
            }
            let t0 = match (c.words.get(4).map(String::as_str), c.words.get(5)) {
                (Some("T0"), Some(v)) => v.parse::<f64>().ok().filter(|t| *t >= 0.0),
                _ => None,
            };
            let t0 = t0.ok_or_else(|| {
                self.syntax(
                    c,
                    "couple/cfd/convection: expected `T0 T` with T ≥ 0".into(),
                )
            })?;
            out = Some(ConvectionFix { line: c.line, t0 });
        }
        Ok(out)
    }

    /// Whether and how the deck is coupled to a CFD solver: the last `couple/cfd` and the
    /// force fix after it (`None`: not coupled).
    pub fn coupling(&self) -> Result<Option<CoupledDeck>, DeckError> {
        let mut out: Option<CoupledDeck> = None;
        for f in self.cfd_fixes()? {
            match f {
                CfdFix::Couple(c) => {
                    out = Some(CoupledDeck {
                        couple_every: c.couple_every.unwrap_or(1),
                        implicit: false,
                        has_force_fix: false,
                    })
                }
                CfdFix::Force(f) => {
                    if let Some(o) = out.as_mut() {
                        o.has_force_fix = true;
                        o.implicit = f.implicit;
                    }
                }
            }
        }
        Ok(out)
    }

    /// The deck's `coarsegraining` command (the last one), `None` without one: the one
    /// reader of the factor ([`CoarseGraining::parse`]), for the coupler's drag and for the
    /// checks of a deck Debian's LIGGGHTS would run. An ill-formed one is an error naming its
    /// line.
    pub fn coarse_graining(&self) -> Result<Option<CoarseGraining>, DeckError> {
        let mut out = None;
        for c in self.named("coarsegraining") {
            out = Some(CoarseGraining::parse(c).map_err(|m| self.syntax(c, m))?);
        }
        Ok(out)
    }

    /// The material values for the time-step advice (later commands override earlier ones).
    /// Radii are the particles' as the deck makes them: with `coarsegraining CG` the parcels'
    /// (CG × the written radius, as LIGGGHTS-PFM scales them).
    pub fn materials(&self) -> Materials {
        let mut s = Materials {
            timestep: self.time_step(),
            ..Materials::default()
        };
        for c in &self.commands {
            let w = &c.words;
            let after = |key: &str, skip: usize| -> Option<f64> {
                let i = w.iter().position(|t| t == key)?;
                w.get(i + 1 + skip)?.parse::<f64>().ok()
            };
            match w[0].as_str() {
                "fix" => {
                    if let Some(v) = after("youngsModulus", 1) {
                        s.young = Some(v);
                    }
                    if let Some(v) = after("poissonsRatio", 1) {
                        s.poisson = Some(v);
                    }
                    if let Some(v) = after("coefficientRestitution", 2) {
                        s.restitution = Some(v);
                    }
                    if let Some(v) = after("thermalCapacity", 1) {
                        s.thermal_capacity = Some(v);
                    }
                    if let Some(v) = after("thermalConductivity", 1) {
                        s.thermal_conductivity = Some(v);
                    }
                    if w.get(3).map(String::as_str) == Some("particletemplate/sphere") {
                        if let Some(v) = after("density", 1) {
                            s.density = Some(v);
                        }
                        if let Some(v) = after("radius", 1) {
                            s.radius = Some(v);
                        }
                    }
                }
                "set" => {
                    if let Some(v) = after("density", 0) {
                        s.density = Some(v);
                    }
                    if let Some(v) = after("diameter", 0) {
                        s.radius = Some(0.5 * v);
                    }
                }
                _ => {}
            }
        }
        if let Ok(Some(cg)) = self.coarse_graining() {
            s.radius = s.radius.map(|r| r * cg.factor);
        }
        s
    }

    fn syntax(&self, c: &Command, message: String) -> DeckError {
        DeckError::Syntax {
            at: self.location(c),
            message,
        }
    }
}

fn file_of(c: &Command, k: usize) -> Option<DeckFile> {
    Some(DeckFile {
        line: c.line,
        command: c.label(),
        path: c.words.get(k)?.clone(),
    })
}

fn written_file(c: &Command) -> Option<DeckFile> {
    let w = &c.words;
    match w[0].as_str() {
        "dump" => file_of(c, 5),
        "write_data" | "write_restart" => file_of(c, 1),
        // `write_dump GROUP STYLE FILE …`
        "write_dump" => file_of(c, 3),
        // `fix ID group print N TEXT file|append F`
        "fix" if w.get(3).map(String::as_str) == Some("print") => {
            let k = w
                .iter()
                .skip(6)
                .position(|x| x == "file" || x == "append")?;
            file_of(c, 6 + k + 1)
        }
        _ => None,
    }
}

/// `fix ID GROUP couple/cfd [couple_every|every N] mpi|file PREFIX`.
fn couple_fix(c: &Command) -> Result<CoupleFix, String> {
    let w = &c.words;
    let mut k = 4;
    let mut every = None;
    if matches!(w.get(k).map(String::as_str), Some("couple_every" | "every")) {
        let n = w
            .get(k + 1)
            .and_then(|s| s.parse::<u64>().ok())
            .filter(|&n| n > 0)
            .ok_or("couple_every needs a positive whole number")?;
        every = Some(n);
        k += 2;
    }
    let data = match w.get(k).map(String::as_str) {
        Some("mpi") => DataCoupling::Mpi,
        Some("file") => {
            DataCoupling::File(w.get(k + 1).cloned().ok_or("`file` needs a path prefix")?)
        }
        other => {
            return Err(format!(
                "couple/cfd: expected `mpi` or `file PREFIX`, found {}",
                other.map_or("nothing".to_string(), |s| format!("`{s}`"))
            ))
        }
    };
    Ok(CoupleFix {
        line: c.line,
        id: w[1].clone(),
        group: w[2].clone(),
        couple_every: every,
        data,
    })
}

/// The options of `fix … couple/cfd/force[/implicit]`.
fn force_fix(c: &Command) -> Result<ForceFix, String> {
    let w = &c.words;
    let mut f = ForceFix {
        line: c.line,
        implicit: w[3].ends_with("implicit"),
        transfer_density: false,
        transfer_type: false,
        other_options: false,
        law_options: Vec::new(),
        words: w.clone(),
    };
    let yes = |k: usize| -> Result<bool, String> {
        match w.get(k).map(String::as_str) {
            Some("yes") => Ok(true),
            Some("no") => Ok(false),
            _ => Err(format!("`{}` needs yes or no", w[k - 1])),
        }
    };
    let mut k = 4;
    while k < w.len() {
        match w[k].as_str() {
            "transfer_torque" => {
                if !yes(k + 1)? {
                    f.law_options.push(ForceLawOption::NoTorque);
                }
                k += 2;
            }
            "transfer_density" => {
                f.transfer_density = yes(k + 1)?;
                k += 2;
            }
            "transfer_type" => {
                f.transfer_type = yes(k + 1)?;
                k += 2;
            }
            "CrankNicolson" | "CAddRhoFluid" => {
                f.law_options.push(ForceLawOption::Law(w[k].clone()));
                k += 1;
            }
            _ => {
                f.other_options = true;
                k += 1;
            }
        }
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn deck(src: &str) -> Deck {
        Deck::parse(src, Path::new("in.t"), &[]).unwrap()
    }

    /// `&` continuations and variables reach every accessor (the old scanner of the time-step
    /// advice read physical lines and missed both).
    #[test]
    fn accessors_see_continuations_and_variables() {
        let d = deck(
            "variable dt index 5e-6\nvariable e equal 5.e6\nvariable f equal 2*v_e\n\
             timestep ${dt}\nfix m1 all property/global youngsModulus &\n  peratomtype $e\n\
             fix m2 all property/global poissonsRatio peratomtype ${f}\n\
             fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5\n\
             fix pts all particletemplate/sphere 1 atom_type 1 density constant 1500 &\n\
             radius constant 0.00025\nprocessors 2 * 1\nread_data post/packed.data\n\
             dump d all custom 100 post/dump*.run id x\n\
             fix p all print 10 \"$x\" file post/p.txt screen no\nwrite_restart post/r.restart\n\
             write_dump all custom post/final.dump id\n",
        );
        let m = d.materials();
        assert_eq!(m.timestep, Some(5e-6));
        assert_eq!(m.young, Some(5e6));
        // LIGGGHTS substitutes ${f} = 2*v_e before the command sees it
        assert_eq!(m.poisson, Some(1e7));
        assert_eq!(m.restitution, Some(0.5));
        assert_eq!((m.density, m.radius), (Some(1500.0), Some(0.00025)));
        assert_eq!(
            d.processors().unwrap(),
            Some(Processors {
                line: 11,
                grid: [Some(2), None, Some(1)]
            })
        );
        let read: Vec<_> = d
            .read_files()
            .into_iter()
            .map(|f| (f.line, f.path))
            .collect();
        assert_eq!(read, [(12, "post/packed.data".to_string())]);
        let written: Vec<_> = d.written_files().into_iter().map(|f| f.path).collect();
        assert_eq!(
            written,
            [
                "post/dump*.run",
                "post/p.txt",
                "post/r.restart",
                "post/final.dump"
            ]
        );
    }

    #[test]
    fn the_last_timestep_is_the_one_run() {
        assert_eq!(
            deck("timestep 1e-5\ntimestep 2e-5\n").time_step(),
            Some(2e-5)
        );
        assert_eq!(deck("run 1\n").time_step(), None);
    }

    #[test]
    fn coupling_fixes_are_read_whole_with_their_lines() {
        let d = deck(
            "fix cfd all couple/cfd couple_every 50 mpi\n\
             fix f all couple/cfd/force/implicit transfer_density yes CrankNicolson 0.5\n",
        );
        let fixes = d.cfd_fixes().unwrap();
        let CfdFix::Couple(c) = &fixes[0] else {
            panic!("{fixes:?}")
        };
        assert_eq!(
            (c.line, c.couple_every, &c.data),
            (1, Some(50), &DataCoupling::Mpi)
        );
        let CfdFix::Force(f) = &fixes[1] else {
            panic!("{fixes:?}")
        };
        assert!(f.implicit && f.transfer_density && f.other_options);
        assert_eq!(f.law_options, [ForceLawOption::Law("CrankNicolson".into())]);
        let c = d.coupling().unwrap().unwrap();
        assert_eq!(
            (c.couple_every, c.implicit, c.has_force_fix),
            (50, true, true)
        );
        assert_eq!(deck("run 1\n").coupling().unwrap(), None);
        let e = deck("\nfix cfd all couple/cfd couple_every 0 mpi\n")
            .coupling()
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("in.t:2:") && e.contains("positive"), "{e}");
        let e = deck("fix f all couple/cfd/force transfer_density maybe\n")
            .cfd_fixes()
            .unwrap_err()
            .to_string();
        assert!(e.contains("yes or no"), "{e}");
    }

    #[test]
    fn convection_fix_is_read_with_its_t0() {
        let d = deck(
            "fix cfd all couple/cfd couple_every 100 mpi\n\
             fix c3 all couple/cfd/convection T0 600\n",
        );
        assert_eq!(
            d.convection().unwrap(),
            Some(ConvectionFix { line: 2, t0: 600.0 })
        );
        assert_eq!(deck("run 1\n").convection().unwrap(), None);
        let e = deck("fix c3 all couple/cfd/convection 600\n")
            .convection()
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("in.t:1:") && e.contains("T0"), "{e}");
    }

    #[test]
    fn a_bad_processors_grid_names_its_line() {
        let e = deck("\n\nprocessors 0 1 1\n")
            .processors()
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("in.t:3:") && e.contains("rank count"), "{e}");
    }

    /// ErgunTestCG's way of writing it: the factor through an `equal` variable; the parcels'
    /// radius in the time-step advice is CG × the written one.
    #[test]
    fn coarse_graining_is_read_once_with_pfms_checks() {
        let d = deck(
            "variable cg equal 2\natom_style granular\ncoarsegraining ${cg}\n\
             fix pts all particletemplate/sphere 1 atom_type 1 density constant 7000 &\n\
             radius constant 0.00025\n",
        );
        let cg = d.coarse_graining().unwrap().unwrap();
        assert_eq!(
            (cg.line, cg.factor, cg.model_check),
            (3, 2.0, ModelCheck::Error)
        );
        assert_eq!(d.materials().radius, Some(0.0005));
        let warn = deck("coarsegraining 3 model_check warn\n");
        let cg = warn.coarse_graining().unwrap().unwrap();
        assert_eq!((cg.factor, cg.model_check), (3.0, ModelCheck::Warn));
        assert_eq!(deck("run 1\n").coarse_graining().unwrap(), None);
        for (src, says) in [
            ("x\ncoarsegraining 0.5\n", "must be ≥ 1"),
            ("x\ncoarsegraining\n", "expected the factor"),
            (
                "x\ncoarsegraining 2 model_check maybe\n",
                "`error` or `warn`",
            ),
            ("x\ncoarsegraining 2 skin 3\n", "unknown keyword `skin`"),
        ] {
            let e = deck(src).coarse_graining().unwrap_err().to_string();
            assert!(e.starts_with("in.t:2:") && e.contains(says), "{e}");
        }
    }
}
