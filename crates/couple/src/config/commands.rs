//! CFDEM's `constant/liggghtsCommands`: LIGGGHTS commands the coupler issues during a run.
//!
//! `liggghtsCommandModels ( … )` lists the models ([`super::registry::LIGGGHTS_COMMANDS`]):
//! * `runLiggghts`: LIGGGHTS runs `couplingInterval` steps per coupling step — what foamgrain
//!   always does (`runLiggghtsProps { preNo …; }` is accepted);
//! * `writeLiggghts`: `write_restart PATH/NAME` at the fluid's write times (`writeLastOnly on`:
//!   at the last coupling step only). `path` (default `../DEM`, relative to the OpenFOAM case)
//!   and `writeName` (default `liggghts.restartCFDEM`) make the file name; without
//!   `overwrite on` the time (`%f`, C's six decimals) is appended, one file per write time.
//!   `writeEvery N` writes at every N-th write time. CFDEM-PFM's older name `writeLast` is read
//!   as `writeLastOnly`;
//! * `execute`: a command assembled from `command ( … )` with CFDEM's tokens (`dot` `.`,
//!   `dotdot` `..`, `slash` `/`, `noBlanks`/`blanks` to glue or separate the words, `timeStamp`
//!   to append the time, `number`/`label` from `scalars`/`labels`, `$couplingInterval`), run
//!   once at the first coupling step (`runFirst`), at the last (`runLast`), every coupling step
//!   (`runEveryCouplingStep`), at every write time (`runEveryWriteStep`), or every
//!   `timeInterval` coupling steps from `startTime` to `endTime` (s). The k-th `execute` of the
//!   list reads `executeProps<k>` (k from 0), as CFDEM does.
//!
//! * `readLiggghtsData`: `read_data <filePath>_<n> add` (`filePath` words glued, with the
//!   `dot`/`dotdot`/`slash` tokens), n counting from `startIndex` at each run, on `execute`'s
//!   schedule switches (`readLiggghtsDataProps<k>`);
//! * `setDEMGravity`: `fix gravity all gravity |g| vector gx/|g| gy/|g| gz/|g|` (C's `%f`) with
//!   g from the case's `constant/g`, or `unfix gravity` with `unfix on`; run every
//!   `timeInterval` coupling steps from `startTime` to `endTime` (CFDEM reads no other
//!   schedule for it) (`setDEMGravityProps<k>`).
//!
//! A missing file means `runLiggghts` alone.

use super::registry::LIGGGHTS_COMMANDS;
use super::{Built, Given, Reader, Setup};
use crate::error::CoupleError;
use foam::{Dict, Item, Value};
use std::path::Path;

/// When a command runs.
#[derive(Clone, Debug, PartialEq)]
pub enum Schedule {
    /// At the first coupling step.
    First,
    /// At the last coupling step.
    Last,
    /// After every coupling step.
    EveryCouplingStep,
    /// At every `every`-th write time of the fluid.
    EveryWriteTime {
        /// Write times between runs (1: each).
        every: u64,
    },
    /// Every `interval` coupling steps from the step holding `start` to the one holding `end`
    /// (times in s from the start of the run, as CFDEM counts them).
    Interval {
        /// First time, s.
        start: f64,
        /// Last time, s.
        end: f64,
        /// Coupling steps between runs (≥ 1).
        interval: u64,
    },
}

/// One command and its schedule.
#[derive(Clone, Debug, PartialEq)]
pub struct ScheduledCommand {
    /// The LIGGGHTS command (with the time appended at run time when `time_stamp`).
    pub command: String,
    /// Append the current time (`%f`) to the command when it runs.
    pub time_stamp: bool,
    /// When it runs.
    pub schedule: Schedule,
    /// `readLiggghtsData`: the command gets `_<n> add` appended, n counting the runs from
    /// this start index ([`ScheduledCommand::due_after`]).
    pub numbered_from: Option<u64>,
}

/// Where a run stands after a coupling step, for [`ScheduledCommand::due`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moment {
    /// The coupling step just done (1-based).
    pub step: u64,
    /// Coupling steps in the run.
    pub steps: u64,
    /// Simulated time, s.
    pub time: f64,
    /// Time since the run's start, s.
    pub elapsed: f64,
    /// Coupling interval, s.
    pub dt_c: f64,
    /// Whether the fluid writes at this step.
    pub write: bool,
    /// Write times so far, this one included.
    pub writes: u64,
}

impl ScheduledCommand {
    /// The command to run at `now`, or `None` when it does not run then.
    pub fn due(&self, now: Moment) -> Option<String> {
        let run = match self.schedule {
            Schedule::First => now.step == 1,
            Schedule::Last => now.step == now.steps,
            Schedule::EveryCouplingStep => true,
            Schedule::EveryWriteTime { every } => {
                now.write && (now.writes - 1).is_multiple_of(every)
            }
            Schedule::Interval {
                start,
                end,
                interval,
            } => {
                // CFDEM: the coupling steps holding start and end, then every `interval`
                let first = ((start + 1e-12) / now.dt_c).floor() as u64;
                let last = ((end + 1e-12) / now.dt_c).floor() as u64;
                let k = ((now.elapsed + 1e-9 * now.dt_c) / now.dt_c).floor() as u64;
                k >= first && k <= last && (k - first).is_multiple_of(interval)
            }
        };
        run.then(|| match self.time_stamp {
            true => format!("{}{:.6}", self.command, now.time),
            false => self.command.clone(),
        })
    }
}

impl ScheduledCommand {
    /// [`ScheduledCommand::due`] for a command that has run `runs` times before: a numbered
    /// command (`readLiggghtsData`) reads file number start + runs, as CFDEM's
    /// `readLiggghtsData::command` appends `_%d` of its counter and ` add`.
    pub fn due_after(&self, now: Moment, runs: u64) -> Option<String> {
        let command = self.due(now)?;
        Some(match self.numbered_from {
            Some(start) => format!("{command}_{} add", start + runs),
            None => command,
        })
    }

    /// Whether [`ScheduledCommand::due`] can run the command at coupling step `step` of
    /// `steps` (write time or not: `write`) whatever the simulated time: false only when the
    /// schedule alone rules it out. A run that must know the fluid's time before it calls
    /// `due` (the runner, which lets the fluid's advance run during the next DEM interval)
    /// waits for the fluid at every step where this is true. `Interval` depends on the time,
    /// so it may be due at any step.
    pub fn may_be_due(&self, step: u64, steps: u64, write: bool) -> bool {
        match self.schedule {
            Schedule::First => step == 1,
            Schedule::Last => step == steps,
            Schedule::EveryCouplingStep | Schedule::Interval { .. } => true,
            Schedule::EveryWriteTime { .. } => write,
        }
    }
}

/// The content of `liggghtsCommands`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct LiggghtsCommands {
    /// The commands, in the file's order.
    pub commands: Vec<ScheduledCommand>,
    /// Accepted settings without effect, one sentence each.
    pub warnings: Vec<String>,
}

impl LiggghtsCommands {
    /// Reads `constant/liggghtsCommands` of the OpenFOAM case `case` (none: no commands).
    pub fn read_case(case: &Path) -> Result<LiggghtsCommands, CoupleError> {
        let file = case.join("constant").join("liggghtsCommands");
        if !file.is_file() {
            return Ok(LiggghtsCommands::default());
        }
        let body = foam::parse_file(&file)?.body;
        LiggghtsCommands::from_dict(&body, &file)
    }

    /// The commands of `top`, the body of the file `file`.
    pub fn from_dict(top: &Dict, file: &Path) -> Result<LiggghtsCommands, CoupleError> {
        let mut r = Reader::new(file);
        let key = LIGGGHTS_COMMANDS.key;
        let mut setup = Setup::default();
        for (position, name) in r.word_list(top, key)?.into_iter().enumerate() {
            setup.position = position;
            r.apply(
                &LIGGGHTS_COMMANDS,
                &Given {
                    key,
                    name: &name,
                    top,
                },
                &mut setup,
            )?;
        }
        Ok(LiggghtsCommands {
            commands: setup.commands,
            warnings: r.warnings,
        })
    }
}

fn sub_dict<'d>(r: &Reader<'_>, top: &'d Dict, key: &str) -> Result<Option<&'d Dict>, CoupleError> {
    match top.get(key) {
        None => Ok(None),
        Some(Value::Dict(d)) => Ok(Some(d)),
        Some(Value::Stream(_)) => Err(r.err(key, "expected a dictionary")),
    }
}

/// `writeLiggghts`: `write_restart` at the write times, from `writeLiggghtsProps`.
pub(super) fn write_liggghts(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let dict = "writeLiggghtsProps";
    let empty = Dict::new();
    let props = sub_dict(r, g.top, dict)?.unwrap_or(&empty);
    r.check_props(
        props,
        dict,
        &[
            "path",
            "writeName",
            "overwrite",
            "writeLastOnly",
            "writeLast",
            "writeEvery",
            "verbose",
        ],
    )?;
    let path = match props.contains("path") {
        true => r.word(props, "path", &format!("{dict}/path"))?,
        false => "../DEM",
    };
    let name = match props.contains("writeName") {
        true => r.word(props, "writeName", &format!("{dict}/writeName"))?,
        false => "liggghts.restartCFDEM",
    };
    let flag = |key: &str| r.opt_switch(props, key, &format!("{dict}/{key}"));
    let last_only = match (flag("writeLastOnly")?, flag("writeLast")?) {
        (Some(x), _) | (None, Some(x)) => x,
        (None, None) => false,
    };
    let overwrite = flag("overwrite")?.unwrap_or(false);
    let every = match props.contains("writeEvery") {
        true => {
            let key = format!("{dict}/writeEvery");
            let n = props
                .label("writeEvery")
                .map_err(|e| r.err(&key, e.to_string()))?;
            if n < 1 {
                return Err(r.err(&key, format!("{n} is not ≥ 1")));
            }
            n as u64
        }
        false => 1,
    };
    let mut command = format!("write_restart {path}/{name}");
    if !overwrite {
        command.push('_');
    }
    s.commands.push(ScheduledCommand {
        command,
        time_stamp: !overwrite,
        schedule: match last_only {
            true => Schedule::Last,
            false => Schedule::EveryWriteTime { every },
        },
        numbered_from: None,
    });
    Ok(())
}

/// `execute` at position i of the list (from 0, counting every model) reads
/// `executeProps<i>`, as CFDEM-PUBLIC's `execute.C` (constructed with the model's index in
/// `cfdemCloud`'s loop over the list): `( runLiggghts execute )` reads `executeProps1`.
pub(super) fn execute(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let dict = &format!("executeProps{}", s.position);
    let Some(props) = sub_dict(r, g.top, dict)? else {
        return Err(r.err(
            dict,
            "missing: an `execute` at position i of liggghtsCommandModels (from 0, counting \
             every model) reads executeProps<i>",
        ));
    };
    r.check_props(
        props,
        dict,
        &[
            "command",
            "scalars",
            "labels",
            "runFirst",
            "runLast",
            "runEveryCouplingStep",
            "runEveryWriteStep",
            "startTime",
            "endTime",
            "timeInterval",
            "verbose",
        ],
    )?;
    let words = r.word_list_at(props, "command", &format!("{dict}/command"))?;
    let numbers = |key: &str| -> Result<Vec<f64>, CoupleError> {
        match props.get(key) {
            None => Ok(Vec::new()),
            Some(Value::Stream(s)) => match s.as_slice() {
                [item] | [Item::Label(_), item] => item
                    .as_f64_list()
                    .ok_or_else(|| r.err(&format!("{dict}/{key}"), "expected a list of numbers")),
                _ => Err(r.err(&format!("{dict}/{key}"), "expected a list of numbers")),
            },
            Some(Value::Dict(_)) => Err(r.err(&format!("{dict}/{key}"), "expected a list")),
        }
    };
    let (scalars, labels) = (numbers("scalars")?, numbers("labels")?);
    let (command, time_stamp) =
        assemble(&words, &scalars, &labels).map_err(|m| r.err(&format!("{dict}/command"), m))?;
    let schedule = time_mode(r, props, dict)?;
    s.commands.push(ScheduledCommand {
        command,
        time_stamp,
        schedule,
        numbered_from: None,
    });
    Ok(())
}

/// CFDEM's `checkTimeMode` and `checkTimeSettings` (`liggghtsCommandModel.C`): the switches
/// `runFirst`, `runLast`, `runEveryCouplingStep`, `runEveryWriteStep` in this order, each read
/// only when the ones before are off, else every `timeInterval` coupling steps from
/// `startTime` to `endTime`.
fn time_mode(r: &Reader<'_>, props: &Dict, dict: &str) -> Result<Schedule, CoupleError> {
    let flag =
        |key: &str| -> Result<bool, CoupleError> { r.switch(props, key, &format!("{dict}/{key}")) };
    Ok(if flag("runFirst")? {
        Schedule::First
    } else if flag("runLast")? {
        Schedule::Last
    } else if flag("runEveryCouplingStep")? {
        Schedule::EveryCouplingStep
    } else if flag("runEveryWriteStep")? {
        Schedule::EveryWriteTime { every: 1 }
    } else {
        interval(r, props, dict)?
    })
}

/// `checkTimeSettings`' "every n steps": `timeInterval` coupling steps (≥ 1) from `startTime`
/// to `endTime`.
fn interval(r: &Reader<'_>, props: &Dict, dict: &str) -> Result<Schedule, CoupleError> {
    let num = |key: &str| r.number(props, key, &format!("{dict}/{key}"));
    let interval = num("timeInterval")?;
    if interval.is_nan() || interval < 1.0 {
        return Err(r.err(
            &format!("{dict}/timeInterval"),
            format!("{interval} is not ≥ 1 (coupling steps between runs)"),
        ));
    }
    Ok(Schedule::Interval {
        start: num("startTime")?,
        end: num("endTime")?,
        interval: interval.floor() as u64,
    })
}

/// The Props of the k-th model of the list, `<name>Props<k>` (CFDEM's numbering, as
/// [`execute`]'s).
fn numbered_props<'d>(
    r: &Reader<'_>,
    g: &Given<'d>,
    s: &Setup,
) -> Result<(&'d Dict, String), CoupleError> {
    let dict = format!("{}Props{}", g.name, s.position);
    match sub_dict(r, g.top, &dict)? {
        Some(props) => Ok((props, dict)),
        None => Err(r.err(
            &dict,
            format!(
                "missing: a `{}` at position i of liggghtsCommandModels (from 0, counting \
                 every model) reads {}Props<i>",
                g.name, g.name
            ),
        )),
    }
}

/// `readLiggghtsData`: `read_data <path>_<n> add`, n from `startIndex` (CFDEM-PUBLIC's
/// `readLiggghtsData.C`).
pub(super) fn read_liggghts_data(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = numbered_props(r, g, s)?;
    let dict = &dict;
    r.check_props(
        props,
        dict,
        &[
            "startIndex",
            "filePath",
            "exactTiming",
            "verbose",
            "runFirst",
            "runLast",
            "runEveryCouplingStep",
            "runEveryWriteStep",
            "startTime",
            "endTime",
            "timeInterval",
        ],
    )?;
    let key = format!("{dict}/startIndex");
    let start = r.number(props, "startIndex", &key)?;
    if start < 0.0 || start.fract() != 0.0 {
        return Err(r.err(&key, format!("{start} is not a whole number ≥ 0")));
    }
    let mut path = String::new();
    for w in r.word_list_at(props, "filePath", &format!("{dict}/filePath"))? {
        path.push_str(match w.as_str() {
            "dot" => ".",
            "dotdot" => "..",
            "slash" => "/",
            other => other,
        });
    }
    let schedule = time_mode(r, props, dict)?;
    s.commands.push(ScheduledCommand {
        command: format!("read_data {path}"),
        time_stamp: false,
        schedule,
        numbered_from: Some(start as u64),
    });
    Ok(())
}

/// `setDEMGravity`: the fluid case's gravity `constant/g` set in the DEM as CFDEM-PUBLIC's
/// `setDEMGravity.C` does, `fix gravity all gravity |g| vector ĝ` (C's `%f`), or `unfix
/// gravity` with `unfix on`.
pub(super) fn set_dem_gravity(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = numbered_props(r, g, s)?;
    let dict = &dict;
    r.check_props(
        props,
        dict,
        &[
            "unfix",
            "exactTiming",
            "verbose",
            "startTime",
            "endTime",
            "timeInterval",
        ],
    )?;
    let unfix = r
        .opt_switch(props, "unfix", &format!("{dict}/unfix"))?
        .unwrap_or(false);
    let command = if unfix {
        "unfix gravity".to_owned()
    } else {
        let case = r
            .file
            .parent()
            .and_then(Path::parent)
            .unwrap_or(Path::new("."));
        let gravity = super::transport::read_gravity(case)?
            .filter(|g| g.norm() > 0.0)
            .ok_or_else(|| {
                r.err(
                    dict,
                    format!(
                        "setDEMGravity sets the fluid's gravity in the DEM: {} is missing or zero",
                        case.join("constant").join("g").display()
                    ),
                )
            })?;
        let n = gravity.norm();
        let d = gravity / n;
        let words: Vec<String> = "fix gravity all gravity number vector number number number"
            .split(' ')
            .map(str::to_owned)
            .collect();
        assemble(&words, &[n, d.x, d.y, d.z], &[])
            .map_err(|m| r.err(dict, m))?
            .0
    };
    s.commands.push(ScheduledCommand {
        command,
        time_stamp: false,
        schedule: interval(r, props, dict)?,
        numbered_from: None,
    });
    Ok(())
}

/// CFDEM's command assembly from words and tokens; returns the command and whether the time
/// is to be appended.
fn assemble(words: &[String], scalars: &[f64], labels: &[f64]) -> Result<(String, bool), String> {
    let mut out = String::new();
    let mut blank = true;
    let mut time_stamp = false;
    let (mut n, mut l) = (0, 0);
    for w in words {
        let add =
            match w.as_str() {
                "dot" => ".".to_owned(),
                "dotdot" => "..".to_owned(),
                "slash" => "/".to_owned(),
                "noBlanks" => {
                    blank = false;
                    String::new()
                }
                "blanks" => {
                    blank = true;
                    String::new()
                }
                "timeStamp" => {
                    time_stamp = true;
                    String::new()
                }
                "number" => {
                    let x = scalars.get(n).ok_or_else(|| {
                        format!("`number` #{} but only {} scalars", n + 1, scalars.len())
                    })?;
                    n += 1;
                    format!("{x:.6}")
                }
                "label" => {
                    let x = labels.get(l).ok_or_else(|| {
                        format!("`label` #{} but only {} labels", l + 1, labels.len())
                    })?;
                    l += 1;
                    format!("{}", *x as i64)
                }
                "$couplingInterval" => return Err(
                    "`$couplingInterval` in an execute command is not supported: write the number"
                        .into(),
                ),
                other => other.to_owned(),
            };
        out.push_str(&add);
        if blank {
            out.push(' ');
        }
    }
    Ok((out.trim_end().to_owned(), time_stamp))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<LiggghtsCommands, String> {
        let d = foam::parse_bytes(text.as_bytes(), Path::new("liggghtsCommands"))
            .map_err(|e| e.to_string())?
            .body;
        LiggghtsCommands::from_dict(&d, Path::new("liggghtsCommands")).map_err(|e| e.to_string())
    }

    #[test]
    fn may_be_due_holds_wherever_due_runs() {
        // `due` is the reference: whenever it runs a command, `may_be_due` must have said it
        // might (for any simulated time); and it rules steps out where the schedule does.
        let schedules = [
            Schedule::First,
            Schedule::Last,
            Schedule::EveryCouplingStep,
            Schedule::EveryWriteTime { every: 2 },
            Schedule::Interval {
                start: 0.003,
                end: 0.02,
                interval: 3,
            },
        ];
        let (dt_c, steps) = (1e-3, 30);
        for schedule in schedules {
            let c = ScheduledCommand {
                command: "write_restart r".into(),
                time_stamp: true,
                schedule: schedule.clone(),
                numbered_from: None,
            };
            let mut ruled_out = 0;
            for step in 1..=steps {
                let write = step % 4 == 0;
                for time in [step as f64 * dt_c, (step as f64 - 0.5) * dt_c] {
                    let now = Moment {
                        step,
                        steps,
                        time,
                        elapsed: time,
                        dt_c,
                        write,
                        writes: step / 4,
                    };
                    if c.due(now).is_some() {
                        assert!(c.may_be_due(step, steps, write), "{schedule:?} at {step}");
                    }
                }
                ruled_out += u64::from(!c.may_be_due(step, steps, write));
            }
            let expected = match schedule {
                Schedule::First | Schedule::Last => steps - 1,
                Schedule::EveryWriteTime { .. } => steps - steps / 4,
                _ => 0,
            };
            assert_eq!(ruled_out, expected, "{schedule:?}");
        }
    }

    #[test]
    fn tokens_assemble_as_cfdem_does() {
        let w: Vec<String> = "write_restart noBlanks dotdot slash DEM slash post slash restart \
                              slash liggghts dot restartRare_ timeStamp"
            .split_whitespace()
            .map(str::to_owned)
            .collect();
        let (c, ts) = assemble(&w, &[], &[]).unwrap();
        assert_eq!(c, "write_restart ../DEM/post/restart/liggghts.restartRare_");
        assert!(ts);
        let w: Vec<String> = ["fix", "grav", "all", "gravity", "number", "vector", "label"]
            .map(str::to_owned)
            .to_vec();
        assert_eq!(
            assemble(&w, &[9.81], &[3.0]).unwrap().0,
            "fix grav all gravity 9.810000 vector 3"
        );
        assert!(assemble(&w, &[], &[]).unwrap_err().contains("number"));
    }

    #[test]
    fn write_and_execute_schedules() {
        let c = read(
            "liggghtsCommandModels ( runLiggghts writeLiggghts execute );\n\
             runLiggghtsProps { preNo false; }\n\
             writeLiggghtsProps { path \"../DEM/post/restart\"; overwrite off; writeLastOnly off; }\n\
             executeProps2 { startTime 0.04; endTime 100; timeInterval 40; \
               command ( write_restart noBlanks dotdot slash DEM slash r_ timeStamp ); \
               runFirst off; runLast off; runEveryCouplingStep off; runEveryWriteStep off; }\n",
        )
        .unwrap();
        assert_eq!(c.commands.len(), 2);
        let w = &c.commands[0];
        assert_eq!(
            w.command,
            "write_restart ../DEM/post/restart/liggghts.restartCFDEM_"
        );
        assert_eq!(w.schedule, Schedule::EveryWriteTime { every: 1 });
        let at = |step: u64, steps: u64, dt_c: f64, write: bool, writes: u64| Moment {
            step,
            steps,
            time: step as f64 * dt_c,
            elapsed: step as f64 * dt_c,
            dt_c,
            write,
            writes,
        };
        // written at a write time only, with C's %f time stamp
        assert_eq!(w.due(at(3, 10, 5e-4, false, 0)), None);
        assert_eq!(
            w.due(at(4, 10, 5e-4, true, 1)).as_deref(),
            Some("write_restart ../DEM/post/restart/liggghts.restartCFDEM_0.002000")
        );
        // every 40 coupling steps of 5e-4 s from t = 0.04 s (step 80)
        let e = &c.commands[1];
        let every = |k: u64| e.due(at(k, 1000, 5e-4, false, 0));
        assert_eq!(every(79), None);
        assert_eq!(
            every(80).as_deref(),
            Some("write_restart ../DEM/r_0.040000")
        );
        assert_eq!(every(100), None);
        assert!(every(120).is_some());
        // CFDEM-PFM's `writeLast`, overwrite on: one file, at the last step
        let p = read(
            "liggghtsCommandModels ( runLiggghts writeLiggghts );\n\
             writeLiggghtsProps { writeLast on; writeName \"post/restart/liggghts.restartCFDEM\"; overwrite on; }\n",
        )
        .unwrap();
        let w = &p.commands[0];
        assert_eq!(w.schedule, Schedule::Last);
        assert_eq!(
            w.due(at(10, 10, 0.01, true, 3)).as_deref(),
            Some("write_restart ../DEM/post/restart/liggghts.restartCFDEM")
        );
        assert_eq!(w.due(at(9, 10, 0.01, true, 2)), None);
    }

    #[test]
    fn errors_name_the_key() {
        let e = read("liggghtsCommandModels ( runLiggghts fancyCommand );").unwrap_err();
        assert!(
            e.contains("liggghtsCommandModels") && e.contains("fancyCommand"),
            "{e}"
        );
        assert!(e.contains("writeLiggghts"), "{e}");
        let e = read("liggghtsCommandModels ( execute );").unwrap_err();
        assert!(e.contains("executeProps0"), "{e}");
        // the index counts every model, as CFDEM's (packedBedTemp: runLiggghts, execute)
        let e =
            read("liggghtsCommandModels ( runLiggghts execute );\nexecuteProps0 {}").unwrap_err();
        assert!(e.contains("executeProps1"), "{e}");
        let e = read(
            "liggghtsCommandModels ( writeLiggghts );\nwriteLiggghtsProps { overwrite on; bogus 1; }",
        )
        .unwrap_err();
        assert!(e.contains("writeLiggghtsProps/bogus"), "{e}");
    }

    /// CFDEM-PUBLIC's `readLiggghtsData.C`: the command is `"read_data " + filePath` with
    /// `sprintf(h, "_%d", insertionNr_)` and `" add"` appended, the counter starting at
    /// `startIndex` and counting each run.
    #[test]
    fn read_liggghts_data_numbers_its_files() {
        let c = read(
            "liggghtsCommandModels ( runLiggghts readLiggghtsData );\n\
             readLiggghtsDataProps1 { startIndex 3; filePath ( dotdot slash DEM slash data dot \
             in ); runFirst off; runLast off; runEveryCouplingStep on; exactTiming; }\n",
        )
        .unwrap();
        let d = &c.commands[0];
        let now = Moment {
            step: 1,
            steps: 5,
            time: 0.1,
            elapsed: 0.1,
            dt_c: 0.1,
            write: false,
            writes: 0,
        };
        assert_eq!(
            d.due_after(now, 0).as_deref(),
            Some("read_data ../DEM/data.in_3 add")
        );
        assert_eq!(
            d.due_after(now, 2).as_deref(),
            Some("read_data ../DEM/data.in_5 add")
        );
        let e = read("liggghtsCommandModels ( readLiggghtsData );\nreadLiggghtsDataProps0 { }")
            .unwrap_err();
        assert!(e.contains("readLiggghtsDataProps0/startIndex"), "{e}");
    }

    /// CFDEM-PUBLIC's `setDEMGravity.C`: the words `fix gravity all gravity number vector
    /// number number number` with the scalars |g|, g/|g| (C's `%f`), g from the case's
    /// `constant/g`; `unfix gravity` with `unfix on`; the schedule is always `startTime`,
    /// `endTime`, `timeInterval`.
    #[test]
    fn set_dem_gravity_from_the_case() {
        let dir = tempfile::tempdir().unwrap();
        let constant = dir.path().join("constant");
        std::fs::create_dir(&constant).unwrap();
        std::fs::write(
            constant.join("liggghtsCommands"),
            "liggghtsCommandModels ( runLiggghts setDEMGravity setDEMGravity );\n\
             setDEMGravityProps1 { startTime 0; endTime 1; timeInterval 1; }\n\
             setDEMGravityProps2 { unfix on; startTime 0.5; endTime 0.5; timeInterval 1; }\n",
        )
        .unwrap();
        let e = LiggghtsCommands::read_case(dir.path())
            .unwrap_err()
            .to_string();
        assert!(e.contains("constant/g"), "{e}");
        std::fs::write(
            constant.join("g"),
            "dimensions [0 1 -2 0 0 0 0];\nvalue (3 0 -4);\n",
        )
        .unwrap();
        let c = LiggghtsCommands::read_case(dir.path()).unwrap();
        assert_eq!(
            c.commands[0].command,
            "fix gravity all gravity 5.000000 vector 0.600000 0.000000 -0.800000"
        );
        assert_eq!(
            c.commands[0].schedule,
            Schedule::Interval {
                start: 0.0,
                end: 1.0,
                interval: 1
            }
        );
        assert_eq!(c.commands[1].command, "unfix gravity");
    }
}
