//! The coupled LIGGGHTS deck (`DEM/in.liggghts_run`): what it declares for the coupling, the
//! checks that must pass before LIGGGHTS sees it, and the copies the backends run.
//!
//! Any LIGGGHTS error ends the whole process (it calls `exit`), so what can be checked is
//! checked here first, each failure naming the deck line:
//! - exactly one `fix ID GROUP couple/cfd [couple_every N] mpi|file PREFIX`, and one
//!   `fix … couple/cfd/force` or `couple/cfd/force/implicit` *after* it (the other order
//!   segfaults LIGGGHTS 3.8.0);
//! - `atom_modify map array` (or `map hash`): the coupling addresses particles by tag;
//! - no `transfer_torque no` (segfaults; the torques simply stay zero), no Crank–Nicolson or
//!   added-mass options (they change the force law of ADR 0004);
//! - trailing `run` commands are skipped (the coupler issues its own runs) and reported; a `run`
//!   after `couple/cfd` that is followed by other commands cannot be replaced and is an error;
//! - `include`, `jump`, `label` and `next` are refused (the checks could not see through them);
//! - `coarsegraining` (LIGGGHTS-PFM's) is refused: Debian's LIGGGHTS has no coarse graining;
//! - files named by `read_data` and `read_restart` exist in the working directory;
//! - a `processors Px Py Pz` grid matches the ranks LIGGGHTS gets ([`CouplingDeck::check_ranks`]).
//!
//! Lines are read with the deck language's reader ([`liggghts_deck`]: `&` continuations,
//! comments, quotes, `-var` values and `variable` substitution).

use std::ops::Range;
use std::path::{Path, PathBuf};

use liggghts_deck::{CfdFix, CoupleFix, Deck};

use crate::error::LiggghtsError;

pub use liggghts_deck::{DataCoupling, DeckFile, ForceFix, ForceLawOption, Processors};

/// A `run` command the coupler skips.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkippedRun {
    /// 1-based deck line.
    pub line: usize,
    /// The command as LIGGGHTS would run it (variables substituted).
    pub command: String,
}

/// A coupled deck, checked.
#[derive(Debug, Clone)]
pub struct CouplingDeck {
    /// The deck file.
    pub file: PathBuf,
    /// Its text.
    source: String,
    /// `couple/cfd`'s 1-based line, fix id and group.
    pub couple_line: usize,
    couple_id: String,
    couple_group: String,
    /// `couple_every N` when given (LIGGGHTS ignores it with `mpi`: the caller decides).
    pub couple_every: Option<u64>,
    /// `mpi` or `file PREFIX`.
    pub data_coupling: DataCoupling,
    /// The force fix.
    pub force: ForceFix,
    /// The trailing `run` commands, skipped.
    pub skipped_runs: Vec<SkippedRun>,
    /// `timestep` when given as a number (s).
    pub time_step: Option<f64>,
    read_data: Vec<DeckFile>,
    dump_files: Vec<DeckFile>,
    /// `processors Px Py Pz`.
    pub processors: Option<Processors>,
    /// The line of `fix … couple/cfd/convection T0 …`, when the deck exchanges heat: LIGGGHTS
    /// then pushes each particle's `Temp` and pulls its `convectiveHeatFlux` (W).
    pub convection: Option<usize>,
}

impl CouplingDeck {
    /// Reads and checks a deck; `vars` are the `-var NAME VALUE` pairs LIGGGHTS will get.
    pub fn read(path: &Path, vars: &[(String, String)]) -> Result<CouplingDeck, LiggghtsError> {
        let source =
            std::fs::read_to_string(path).map_err(|e| LiggghtsError::io(path.to_path_buf(), e))?;
        CouplingDeck::parse(&source, path, vars)
    }

    /// Parses and checks deck text; `file` names it in errors.
    pub fn parse(
        source: &str,
        file: &Path,
        vars: &[(String, String)],
    ) -> Result<CouplingDeck, LiggghtsError> {
        let deck = liggghts_deck::Deck::parse(source, file, vars)?;
        let err = |line: usize, message: String| LiggghtsError::Deck {
            file: file.to_path_buf(),
            line,
            message,
        };
        refuse_hidden_commands(&deck).map_err(|(l, m)| err(l, m))?;
        refuse_coarse_graining(&deck)?.map_or(Ok(()), |(l, m)| Err(err(l, m)))?;
        let (couple, force) = coupling_fixes(deck.cfd_fixes()?).map_err(|(l, m)| err(l, m))?;
        let map = deck
            .named("atom_modify")
            .filter_map(|c| {
                let k = c.words.iter().position(|x| x == "map")?;
                Some(matches!(
                    c.words.get(k + 1).map(String::as_str),
                    Some("array" | "hash")
                ))
            })
            .last()
            .unwrap_or(false);
        if !map {
            return Err(err(
                0,
                "no `atom_modify map array`: the coupling addresses particles by tag and \
                 LIGGGHTS stops without an atom map"
                    .into(),
            ));
        }
        let skipped_runs = trailing_runs(&deck, couple.line).map_err(|(l, m)| err(l, m))?;
        let convection = convection_fix(&deck, deck.convection()?).map_err(|(l, m)| err(l, m))?;
        Ok(CouplingDeck {
            file: file.to_path_buf(),
            source: source.to_string(),
            couple_line: couple.line,
            couple_id: couple.id,
            couple_group: couple.group,
            couple_every: couple.couple_every,
            data_coupling: couple.data,
            force,
            skipped_runs,
            time_step: deck.time_step(),
            read_data: deck.read_files(),
            dump_files: deck
                .written_files()
                .into_iter()
                .filter(|f| f.command == "dump" || f.command == "fix print")
                .collect(),
            processors: deck.processors()?,
            convection,
        })
    }

    /// Checks that the deck's `processors` grid can run on `ranks` LIGGGHTS ranks (the product
    /// of its numbers equals `ranks`, or divides it when a `*` lets LIGGGHTS choose the rest);
    /// LIGGGHTS would stop the whole process otherwise.
    pub fn check_ranks(&self, ranks: usize) -> Result<(), LiggghtsError> {
        let Some(Processors { line, grid }) = self.processors else {
            return Ok(());
        };
        let fixed: usize = grid.iter().flatten().product();
        let free = grid.iter().any(Option::is_none);
        let fits = if free {
            ranks.is_multiple_of(fixed)
        } else {
            fixed == ranks
        };
        if fits {
            return Ok(());
        }
        let shown: Vec<String> = grid
            .iter()
            .map(|g| g.map_or("*".into(), |n| n.to_string()))
            .collect();
        Err(LiggghtsError::Deck {
            file: self.file.clone(),
            line,
            message: format!(
                "`processors {}` asks for {}{fixed} LIGGGHTS ranks, but LIGGGHTS runs on {ranks} \
                 here (foamgrain runs LIGGGHTS on its own MPI ranks: launch \
                 `mpirun -np {fixed} foamgrain run CASE --dem liggghts`, or run this deck on the \
                 native DEM, `--dem native`, which ignores `processors` and uses threads, or \
                 change the line to `processors * * *`)",
                shown.join(" "),
                if free { "a multiple of " } else { "" },
            ),
        })
    }

    /// Checks that the files the deck reads (`read_data`, `read_restart`) exist under
    /// `workdir`, the directory LIGGGHTS will run in, and makes the folders its dumps and `fix
    /// print` files go to (LIGGGHTS would stop without them; CFDEM's run scripts make `post/`).
    pub fn check_inputs(&self, workdir: &Path) -> Result<(), LiggghtsError> {
        if !workdir.is_dir() {
            return Err(LiggghtsError::Parameter(format!(
                "working directory {} does not exist",
                workdir.display()
            )));
        }
        for DeckFile { line, path: f, .. } in &self.read_data {
            if !workdir.join(f).is_file() {
                return Err(LiggghtsError::Deck {
                    file: self.file.clone(),
                    line: *line,
                    message: format!(
                        "{} does not exist (relative to the working directory {}; \
                         does stage 1 have to run first?)",
                        f,
                        workdir.display()
                    ),
                });
            }
        }
        for DeckFile { line, path: f, .. } in &self.dump_files {
            let Some(parent) = workdir.join(f).parent().map(Path::to_path_buf) else {
                continue;
            };
            std::fs::create_dir_all(&parent).map_err(|e| LiggghtsError::Deck {
                file: self.file.clone(),
                line: *line,
                message: format!("cannot make the folder {} for {f}: {e}", parent.display()),
            })?;
        }
        Ok(())
    }

    /// The deck with its trailing `run` commands turned into comments (same line numbers, so
    /// LIGGGHTS's messages point at the original lines).
    pub fn without_runs(&self) -> String {
        let lines: Vec<&str> = self.source.lines().collect();
        let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        for r in &self.skipped_runs {
            for k in physical_span(&lines, r.line) {
                out[k] = format!(
                    "# foamgrain: skipped, the coupler runs the steps: {}",
                    lines[k]
                );
            }
        }
        out.join("\n") + "\n"
    }

    /// The deck for file coupling (see [`crate::file`]): `couple/cfd` rewritten to
    /// `file PREFIX` with a block before it that gives every particle its tag as a per-atom
    /// property `fgTag` and dumps the initial state to `init_dump`; the force fix with
    /// `transfer_density yes transfer_property name fgTag type scalar-atom` appended; the
    /// trailing runs replaced by one `run total_steps`.
    pub fn for_file_coupling(
        &self,
        prefix: &str,
        init_dump: &str,
        total_steps: u64,
    ) -> Result<String, LiggghtsError> {
        let every = self.couple_every.ok_or_else(|| LiggghtsError::Deck {
            file: self.file.clone(),
            line: self.couple_line,
            message: "file coupling needs `couple_every N` on the couple/cfd line".into(),
        })?;
        if self.force.other_options || self.force.transfer_type {
            return Err(LiggghtsError::Deck {
                file: self.file.clone(),
                line: self.force.line,
                message: "file coupling supports only transfer_density on the force fix (other \
                          options add exchange files it does not handle)"
                    .into(),
            });
        }
        let lines: Vec<&str> = self.source.lines().collect();
        let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        let couple_span = physical_span(&lines, self.couple_line);
        let (id, group) = (&self.couple_id, &self.couple_group);
        let block = [
            "# foamgrain file coupling: each particle's tag as a per-atom property (the files"
                .to_string(),
            "# are in local order), and the initial state".to_string(),
            format!("fix {TAG_FIX} all property/atom {TAG_PROPERTY} scalar no no no 0"),
            format!("variable {TAG_FIX}V atom id"),
            "run 0".to_string(),
            format!("set group all property/atom {TAG_PROPERTY} v_{TAG_FIX}V"),
            format!("dump {TAG_FIX}Dump all custom 1 {init_dump} id type x y z vx vy vz radius density"),
            "dump_modify fgTagDump format \"%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\"".to_string(),
            "run 0".to_string(),
            format!("undump {TAG_FIX}Dump"),
            format!("fix {id} {group} couple/cfd couple_every {every} file {prefix}"),
        ];
        replace_span(&mut out, couple_span, block.join("\n"));
        let force_span = physical_span(&lines, self.force.line);
        let mut force = self.force.words.join(" ");
        if !self.force.transfer_density {
            force.push_str(" transfer_density yes");
        }
        force.push_str(&format!(
            " transfer_property name {TAG_PROPERTY} type scalar-atom"
        ));
        replace_span(&mut out, force_span, force);
        for r in &self.skipped_runs {
            let span = physical_span(&lines, r.line);
            let text = format!(
                "# foamgrain: replaced by the run at the end: {}",
                lines[span.clone()].join(" ")
            );
            replace_span(&mut out, span, text);
        }
        out.push(format!("run {total_steps}"));
        Ok(out.join("\n") + "\n")
    }
}

/// The per-atom property that carries tags in file coupling, and the id of its fix.
pub(crate) const TAG_PROPERTY: &str = "fgTag";
const TAG_FIX: &str = "fgTag";

/// Replaces the physical lines `span` by `text` (the first keeps it, the others become empty).
fn replace_span(out: &mut [String], span: Range<usize>, text: String) {
    let mut first = true;
    for k in span {
        out[k] = if first { text.clone() } else { String::new() };
        first = false;
    }
}

/// The 0-based physical lines of the logical line that starts on 1-based `line` (`&` at the end
/// of a line continues it).
fn physical_span(lines: &[&str], line: usize) -> Range<usize> {
    let start = line - 1;
    let mut end = start;
    while end < lines.len() && lines[end].trim_end().ends_with('&') {
        end += 1;
    }
    start..(end + 1).min(lines.len())
}

/// `coarsegraining` (LIGGGHTS-PFM's command, `Deck::coarse_graining`) is refused: Debian's
/// LIGGGHTS 3.8.0 has no coarse graining and would stop at it. `Some((line, message))` when
/// the deck has one; an ill-formed one is the deck's syntax error.
pub fn refuse_coarse_graining(
    deck: &Deck,
) -> Result<Option<(usize, String)>, liggghts_deck::DeckError> {
    Ok(deck.coarse_graining()?.map(|cg| {
        (
            cg.line,
            format!(
                "`coarsegraining {}` is LIGGGHTS-PFM's command: Debian's LIGGGHTS 3.8.0 has no \
                 coarse graining (it would stop here). Run this deck on the native DEM \
                 (`--dem native`), which scales the parcels as LIGGGHTS-PFM does",
                cg.factor
            ),
        )
    }))
}

/// `include`, `jump`, `label` and `next` are refused: the checks could not see through them.
fn refuse_hidden_commands(deck: &Deck) -> Result<(), (usize, String)> {
    for c in &deck.commands {
        if matches!(c.words[0].as_str(), "include" | "jump" | "label" | "next") {
            return Err((
                c.line,
                format!(
                    "`{}` is not supported in a coupled deck (the checks that must pass before \
                     LIGGGHTS runs could not see through it): inline the commands",
                    c.words[0]
                ),
            ));
        }
    }
    Ok(())
}

/// Exactly one `couple/cfd` and one force fix after it, with the options LIGGGHTS 3.8.0
/// survives.
/// The line of the deck's `fix … couple/cfd/convection T0 …` (`Deck::convection`, which reads
/// it whole; LIGGGHTS 3.8 allows one, and it needs `fix heat/gran`, which holds the
/// per-particle `Temp` and `heatFlux`; without it LIGGGHTS adds a `transportequation/scalar`
/// of its own, which we refuse: the particles' heat conduction would then silently be off).
fn convection_fix(
    deck: &liggghts_deck::Deck,
    fix: Option<liggghts_deck::ConvectionFix>,
) -> Result<Option<usize>, (usize, String)> {
    let Some(fix) = fix else {
        return Ok(None);
    };
    let line = fix.line;
    if let Some(first) = deck
        .fixes("couple/cfd/convection")
        .map(|c| c.line)
        .find(|&l| l != line)
    {
        return Err((
            line,
            format!("a second `fix … couple/cfd/convection` (the first is on line {first})"),
        ));
    }
    if deck.fixes("heat/gran").next().is_none() {
        return Err((
            line,
            "`couple/cfd/convection` without `fix ID all heat/gran initial_temperature T0`: the \
             particles would have no temperature equation (CFDEM's packedBedTemp declares both, \
             with `fix property/global thermalConductivity` and `thermalCapacity`)"
                .into(),
        ));
    }
    Ok(Some(line))
}

fn coupling_fixes(fixes: Vec<CfdFix>) -> Result<(CoupleFix, ForceFix), (usize, String)> {
    let mut couple: Option<CoupleFix> = None;
    let mut force: Option<ForceFix> = None;
    for f in fixes {
        match f {
            CfdFix::Couple(c) => {
                if let Some(first) = &couple {
                    return Err((
                        c.line,
                        format!(
                            "a second `fix … couple/cfd` (the first is on line {})",
                            first.line
                        ),
                    ));
                }
                couple = Some(c);
            }
            CfdFix::Force(f) => {
                if couple.is_none() {
                    return Err((
                        f.line,
                        format!(
                            "`fix … {}` before `fix … couple/cfd`: LIGGGHTS 3.8.0 segfaults in \
                             this order; define couple/cfd first",
                            f.words[3]
                        ),
                    ));
                }
                if let Some(first) = &force {
                    return Err((
                        f.line,
                        format!(
                            "a second coupling force fix (the first is on line {})",
                            first.line
                        ),
                    ));
                }
                if let Some(o) = f.law_options.first() {
                    return Err((f.line, law_refusal(o)));
                }
                force = Some(f);
            }
        }
    }
    let Some(couple) = couple else {
        return Err((
            0,
            "no `fix ID all couple/cfd couple_every N mpi`: the deck is not coupled to a CFD \
             solver"
                .into(),
        ));
    };
    let Some(force) = force else {
        return Err((
            0,
            "no `fix ID all couple/cfd/force/implicit` (or `couple/cfd/force`) after \
             `couple/cfd`: the particles would receive no fluid force"
                .into(),
        ));
    };
    Ok((couple, force))
}

/// Why LIGGGHTS cannot be given a force fix option.
fn law_refusal(o: &ForceLawOption) -> String {
    match o {
        ForceLawOption::NoTorque => "`transfer_torque no` segfaults LIGGGHTS 3.8.0; leave it out \
                                     (the hydrodynamic torques stay zero)"
            .into(),
        ForceLawOption::Law(word) => format!(
            "`{word}` changes the particle force law; foamgrain applies F = F_ext + β(u_f − v) \
             each step (ADR 0004): remove it"
        ),
    }
}

/// The trailing `run` commands, skipped; any other run after couple/cfd that takes steps is an
/// error (`run 0` and `run 0 upto`, CFDEM's way to set up dumps between commands, take none:
/// LIGGGHTS runs them as they are).
fn trailing_runs(deck: &Deck, couple_line: usize) -> Result<Vec<SkippedRun>, (usize, String)> {
    let mut first_trailing = deck.commands.len();
    while first_trailing > 0 && deck.commands[first_trailing - 1].words[0] == "run" {
        first_trailing -= 1;
    }
    if let Some(c) = deck.commands[..first_trailing].iter().find(|c| {
        c.words[0] == "run"
            && c.line > couple_line
            && c.words.get(1).map(String::as_str) != Some("0")
    }) {
        return Err((
            c.line,
            "a `run` after `fix … couple/cfd` followed by other commands: the coupler drives \
             the steps of a coupled deck and can only skip trailing runs"
                .into(),
        ));
    }
    Ok(deck.commands[first_trailing..]
        .iter()
        .map(|c| SkippedRun {
            line: c.line,
            command: c.words.join(" "),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deck(body: &str) -> Result<CouplingDeck, LiggghtsError> {
        CouplingDeck::parse(body, Path::new("in.t"), &[("n".into(), "7".into())])
    }

    const GOOD: &str = "atom_style granular\natom_modify map array\ntimestep 1e-5\n\
        fix cfd all couple/cfd couple_every 50 mpi\n\
        fix cfd2 all couple/cfd/force/implicit\nfix integr all nve/sphere\nrun 100\n\
        run ${n} &\n  upto\n";

    /// CFDEM's decks declare their LIGGGHTS grid (`processors 2 2 1`): refused before
    /// LIGGGHTS starts when the ranks do not match, naming the line and the ways out; a
    /// `read_restart` file must exist like a `read_data` file.
    #[test]
    fn processors_grid_and_restart_file_are_checked() {
        let d = deck(&GOOD.replace(
            "timestep 1e-5\n",
            "timestep 1e-5\nprocessors 2 2 1\nread_restart post/restart/liggghts.restart\n",
        ))
        .unwrap();
        assert_eq!(
            d.processors,
            Some(Processors {
                line: 4,
                grid: [Some(2), Some(2), Some(1)]
            })
        );
        d.check_ranks(4).unwrap();
        let e = d.check_ranks(1).unwrap_err().to_string();
        assert!(
            e.contains("in.t:4:")
                && e.contains("processors 2 2 1")
                && e.contains("4 LIGGGHTS ranks"),
            "{e}"
        );
        assert!(
            e.contains("--dem native") && e.contains("mpirun -np 4"),
            "{e}"
        );
        let dir = tempfile::tempdir().unwrap();
        let e = d.check_inputs(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("in.t:5:") && e.contains("liggghts.restart"),
            "{e}"
        );
        // `*` leaves the rest to LIGGGHTS
        let free = deck(&GOOD.replace("timestep 1e-5\n", "processors * 2 1\n")).unwrap();
        free.check_ranks(4).unwrap();
        assert!(free.check_ranks(3).is_err());
        assert!(deck(&GOOD.replace("timestep 1e-5\n", "processors 0 1 1\n")).is_err());
    }

    #[test]
    fn the_reference_case_decks_pass() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../openfoam-cases");
        let e = CouplingDeck::read(&root.join("ergun/DEM/in.liggghts_run"), &[]).unwrap();
        assert_eq!(e.couple_every, Some(50));
        assert!(e.force.implicit);
        assert_eq!(e.data_coupling, DataCoupling::Mpi);
        assert_eq!(e.time_step, Some(1e-5));
        let s = CouplingDeck::read(&root.join("settling/DEM/in.liggghts_run"), &[]).unwrap();
        assert_eq!(s.couple_every, Some(100));
        assert!(!s.force.implicit);
        let err = e.check_inputs(Path::new("/nonexistent")).unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
        // the dump's folder is made (LIGGGHTS would stop without it); one that cannot be made
        // is an error naming the deck line
        let dir = tempfile::tempdir().unwrap();
        s.check_inputs(dir.path()).unwrap();
        assert!(dir.path().join("post").is_dir());
        std::fs::remove_dir(dir.path().join("post")).unwrap();
        std::fs::write(dir.path().join("post"), "a file").unwrap();
        let err = s.check_inputs(dir.path()).unwrap_err().to_string();
        assert!(
            err.contains("in.liggghts_run:49:") && err.contains("post/dump*.run"),
            "{err}"
        );
    }

    #[test]
    fn trailing_runs_are_skipped_with_lines_kept() {
        let d = deck(GOOD).unwrap();
        assert_eq!(
            d.skipped_runs,
            [
                SkippedRun {
                    line: 7,
                    command: "run 100".into()
                },
                SkippedRun {
                    line: 8,
                    command: "run 7 upto".into()
                }
            ]
        );
        // CFDEM's settlingTestMPI: `run 0` before a dump, then `run 0 upto`: no steps, kept
        let mid = deck(&GOOD.replace(
            "run 100\n",
            "run 0\ndump d all custom 5 post/d id x\nrun 0 upto\n",
        ))
        .unwrap();
        assert_eq!(mid.skipped_runs.len(), 2, "{:?}", mid.skipped_runs);
        assert!(mid.without_runs().contains("\nrun 0\ndump d all"));
        let text = d.without_runs();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 9);
        assert!(lines[6].starts_with("# foamgrain: skipped"));
        assert!(lines[7].starts_with("# foamgrain: skipped"));
        assert!(lines[8].starts_with("# foamgrain: skipped"));
        assert_eq!(lines[5], "fix integr all nve/sphere");
    }

    #[test]
    fn what_liggghts_would_die_on_is_refused_with_its_line() {
        let cases = [
            (GOOD.replace("atom_modify map array\n", ""), 0, "atom_modify map array"),
            (
                "atom_modify map array\nfix cfd2 all couple/cfd/force\nfix cfd all couple/cfd mpi\n"
                    .to_string(),
                2,
                "segfaults",
            ),
            (GOOD.replace("implicit", "implicit transfer_torque no"), 5, "transfer_torque"),
            (GOOD.replace("implicit", "implicit CrankNicolson 0.5"), 5, "force law"),
            (GOOD.replace("fix integr", "run 5\nfix integr"), 6, "trailing"),
            (GOOD.replace("couple_every 50 mpi", "couple_every 50"), 4, "`mpi` or `file"),
            (GOOD.replace("fix cfd2 all couple/cfd/force/implicit\n", ""), 0, "no `fix ID all couple/cfd/force"),
            (GOOD.replace("fix cfd all couple/cfd couple_every 50 mpi\n", ""), 4, "before"),
            (format!("{GOOD}include more.in\n"), 10, "include"),
            (format!("{GOOD}fix c all couple/cfd mpi\n"), 10, "second"),
            // LIGGGHTS-PFM's command (ErgunTestCG): Debian's LIGGGHTS has no coarse graining
            (format!("coarsegraining 2\n{GOOD}"), 1, "Debian's LIGGGHTS 3.8.0 has no coarse"),
        ];
        for (src, line, what) in cases {
            let e = deck(&src).unwrap_err();
            let s = e.to_string();
            assert!(s.starts_with(&format!("in.t:{line}:")), "{s}");
            assert!(s.contains(what), "{s}");
        }
    }

    #[test]
    fn file_coupling_copy_rewrites_the_coupling_lines() {
        let d = deck(GOOD).unwrap();
        let text = d.for_file_coupling("/w/cpl/", "init.dump", 300).unwrap();
        assert!(
            text.contains("\nfix cfd all couple/cfd couple_every 50 file /w/cpl/\n"),
            "{text}"
        );
        assert!(text.contains(
            "fix cfd2 all couple/cfd/force/implicit transfer_density yes transfer_property name \
             fgTag type scalar-atom\n"
        ));
        assert!(text.contains("set group all property/atom fgTag v_fgTagV"));
        assert!(text.ends_with("run 300\n"), "{text}");
        assert!(!text.contains("\nrun 100"));
        // the couple/cfd line comes after the tag block and before the force fix
        let c = text.find("couple/cfd couple_every").unwrap();
        assert!(text.find("run 0").unwrap() < c && c < text.find("couple/cfd/force").unwrap());
        let no_every = deck(&GOOD.replace("couple_every 50 ", "")).unwrap();
        assert!(no_every.for_file_coupling("p", "d", 1).is_err());
    }
}
