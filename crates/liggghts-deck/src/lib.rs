//! The LIGGGHTS 3.8 input-deck language, read into commands with every variable substituted —
//! the one reader that the native DEM (`dem`, which executes the commands) and the LIGGGHTS
//! backend (`liggghts`, which checks a coupled deck before LIGGGHTS sees it) share.
//!
//! Reading handles `&` continuations, `#` comments, quotes ([`lines`]), and `variable NAME
//! index|string|equal|delete …` with `$x`, `${name}` and `$(formula)` substitution ([`expr`]
//! evaluates formulas; equal-style values are formatted `%.15g`, `$(formula)` `%.20g`, as LAMMPS does, [`format`](mod@format));
//! values given on the command line (`-var NAME VALUE`) take precedence over `index`
//! definitions. What a command means is not this crate's business: it returns the words, and
//! `declared`'s typed accessors read what the commands declare that other crates need before
//! running the deck (time step, files, `processors`, the CFD coupling fixes, materials).
//!
//! ```
//! let deck = liggghts_deck::Deck::parse(
//!     "variable n index 10\nvariable h equal 0.5*${n}\nrun ${n} # steps\nprint $(v_h+1)",
//!     std::path::Path::new("in.demo"),
//!     &[("n".into(), "4".into())],
//! )?;
//! assert_eq!(deck.commands[0].words, ["run", "4"]);
//! assert_eq!(deck.commands[1].words, ["print", "3"]);
//! # Ok::<(), liggghts_deck::DeckError>(())
//! ```
//!
//! *Invariant:* every error names the file and the 1-based line of the command.

mod declared;
pub mod expr;
pub mod format;
pub mod lines;

pub use declared::{
    CfdFix, CoarseGraining, ConvectionFix, CoupleFix, CoupledDeck, DataCoupling, DeckFile,
    ForceFix, ForceLawOption, Materials, ModelCheck, Processors,
};

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use format::format_g;

/// Where in a deck a command was read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeckLocation {
    /// The deck file.
    pub file: PathBuf,
    /// 1-based line of the command's first line.
    pub line: usize,
    /// The command word (`fix`, `region`, …) and, for fixes, the style (`fix wall/gran`).
    pub command: String,
}

impl std::fmt::Display for DeckLocation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}: `{}`",
            self.file.display(),
            self.line,
            self.command
        )
    }
}

/// A deck that cannot be read: the file is missing, or a line does not parse (quotes,
/// variables, formulas).
#[derive(Debug, thiserror::Error)]
pub enum DeckError {
    /// A line is malformed.
    #[error("{at}: {message}")]
    Syntax {
        /// Where.
        at: DeckLocation,
        /// What is wrong.
        message: String,
    },
    /// The deck file cannot be read.
    #[error("cannot read deck {file}: {error}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The OS error (in the message, not a `source`: front ends print the chain).
        error: std::io::Error,
    },
}

/// One command: its line and its words after substitution.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Command {
    /// 1-based line of the command's first physical line.
    pub line: usize,
    /// Words (the command name first).
    pub words: Vec<String>,
}

impl Command {
    /// `fix STYLE` for fixes, the command word otherwise.
    pub fn label(&self) -> String {
        match (self.words.first().map(String::as_str), self.words.get(3)) {
            (Some("fix"), Some(style)) => format!("fix {style}"),
            (Some(w), _) => w.to_string(),
            _ => String::new(),
        }
    }
}

/// A read deck.
#[derive(Debug, Clone, PartialEq)]
pub struct Deck {
    /// The file (for messages); relative paths inside the deck are not resolved against it.
    pub file: PathBuf,
    /// The commands in order, `variable` lines already applied.
    pub commands: Vec<Command>,
    /// The variables before the first line (the command line's, or those a deck read with
    /// [`Deck::parse_with`] started from).
    initial: Variables,
    /// Every `variable` command with its line, in order (what [`Deck::variables_at`] replays).
    definitions: Vec<(usize, Vec<String>)>,
}

/// The variables defined at a point of a deck, for what is evaluated while the DEM runs
/// (`fix print` text, `v_name` thermo columns): equal-style formulas are evaluated when asked,
/// with the caller answering the names only a running simulation knows ([`expr::Ref`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Variables {
    table: HashMap<String, Var>,
}

/// The resolver used while a deck is read: only variables are known then.
fn reading(r: expr::Ref) -> Result<f64, String> {
    Err(format!(
        "`{r}` is known only while the simulation runs (use it in `fix print` or thermo_style, \
         not in an immediate $-substitution)"
    ))
}

impl Variables {
    /// The value of variable `name` as `${name}` substitutes it (equal-style: `%.15g`).
    pub fn value(
        &self,
        name: &str,
        resolve: &dyn Fn(expr::Ref) -> Result<f64, String>,
    ) -> Result<String, String> {
        lookup(name, &self.table, 0, resolve)
    }

    /// The value of variable `name` as a number (`v_name` in a formula or a thermo column).
    pub fn number(
        &self,
        name: &str,
        resolve: &dyn Fn(expr::Ref) -> Result<f64, String>,
    ) -> Result<f64, String> {
        number(name, &self.table, 0, resolve)
    }

    /// `text` with `$x`, `${name}` and `$(formula)` replaced outside quotes (what `fix print`
    /// does to its text every time it prints).
    pub fn substitute(
        &self,
        text: &str,
        resolve: &dyn Fn(expr::Ref) -> Result<f64, String>,
    ) -> Result<String, String> {
        substitute(text, &self.table, resolve)
    }

    /// Whether `name` is defined.
    pub fn contains(&self, name: &str) -> bool {
        self.table.contains_key(name)
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Var {
    Text(String),
    Equal(String),
}

impl Deck {
    /// Reads a deck file.
    pub fn read(path: impl AsRef<Path>) -> Result<Deck, DeckError> {
        Deck::read_with_vars(path, &[])
    }

    /// Reads a deck with command-line variables (`-var NAME VALUE`).
    pub fn read_with_vars(
        path: impl AsRef<Path>,
        vars: &[(String, String)],
    ) -> Result<Deck, DeckError> {
        let path = path.as_ref();
        let src = std::fs::read_to_string(path).map_err(|error| DeckError::Io {
            file: path.to_path_buf(),
            error,
        })?;
        Deck::parse(&src, path, vars)
    }

    /// Parses deck text; `file` names it in errors.
    pub fn parse(src: &str, file: &Path, vars: &[(String, String)]) -> Result<Deck, DeckError> {
        let table: HashMap<String, Var> = vars
            .iter()
            .map(|(k, v)| (k.clone(), Var::Text(v.clone())))
            .collect();
        Deck::parse_with(src, file, &Variables { table })
    }

    /// Parses deck text that continues with the variables `vars` (commands given to a running
    /// simulation, e.g. CFDEM's `liggghtsCommands`, see the deck's [`Deck::variables_at`]).
    pub fn parse_with(src: &str, file: &Path, vars: &Variables) -> Result<Deck, DeckError> {
        let mut table = vars.table.clone();
        let mut definitions: Vec<(usize, Vec<String>)> = Vec::new();
        let mut commands = Vec::new();
        for l in lines::logical_lines(src) {
            let err = |command: &str, message: String| DeckError::Syntax {
                at: DeckLocation {
                    file: file.to_path_buf(),
                    line: l.line,
                    command: command.to_string(),
                },
                message,
            };
            let text = substitute(&l.text, &table, &reading).map_err(|m| err("", m))?;
            let words = lines::split_words(lines::strip_comment(&text)).map_err(|m| err("", m))?;
            if words.is_empty() {
                continue;
            }
            if words[0] == "variable" {
                define(&words, &mut table).map_err(|m| err("variable", m))?;
                definitions.push((l.line, words));
                continue;
            }
            commands.push(Command {
                line: l.line,
                words,
            });
        }
        Ok(Deck {
            file: file.to_path_buf(),
            commands,
            initial: vars.clone(),
            definitions,
        })
    }

    /// The variables as defined before deck line `line` (`usize::MAX`: at the end).
    pub fn variables_at(&self, line: usize) -> Variables {
        let mut table = self.initial.table.clone();
        for (_, words) in self.definitions.iter().filter(|(l, _)| *l < line) {
            // each definition was applied once already while reading: it cannot fail now
            let _ = define(words, &mut table);
        }
        Variables { table }
    }

    /// The location of `c` for messages.
    pub fn location(&self, c: &Command) -> DeckLocation {
        DeckLocation {
            file: self.file.clone(),
            line: c.line,
            command: c.label(),
        }
    }
}

type Resolve<'r> = &'r dyn Fn(expr::Ref) -> Result<f64, String>;

fn lookup(
    name: &str,
    table: &HashMap<String, Var>,
    depth: usize,
    resolve: Resolve,
) -> Result<String, String> {
    if depth > 32 {
        return Err(format!("variable `{name}` refers to itself"));
    }
    match table.get(name) {
        Some(Var::Text(t)) => Ok(t.clone()),
        Some(Var::Equal(f)) => {
            let v = eval_formula(f, table, depth, resolve)?;
            Ok(format_g(v, 15))
        }
        None => Err(format!("variable `{name}` is not defined")),
    }
}

fn number(
    name: &str,
    table: &HashMap<String, Var>,
    depth: usize,
    resolve: Resolve,
) -> Result<f64, String> {
    match table.get(name) {
        // no round trip through the %.15g text for a formula
        Some(Var::Equal(f)) if depth <= 32 => eval_formula(f, table, depth, resolve),
        _ => {
            let t = lookup(name, table, depth, resolve)?;
            t.trim()
                .parse::<f64>()
                .map_err(|_| format!("variable `{name}` = `{t}` is not a number"))
        }
    }
}

fn eval_formula(
    f: &str,
    table: &HashMap<String, Var>,
    depth: usize,
    resolve: Resolve,
) -> Result<f64, String> {
    expr::evaluate(f, &|r| match r {
        expr::Ref::Variable(n) => number(n, table, depth + 1, resolve),
        other => resolve(other),
    })
}

/// Replaces `$x`, `${name}` and `$(formula)` outside quotes.
fn substitute(s: &str, table: &HashMap<String, Var>, resolve: Resolve) -> Result<String, String> {
    let mut out = String::with_capacity(s.len());
    let chars: Vec<char> = s.chars().collect();
    let mut quote: Option<char> = None;
    let mut k = 0;
    while k < chars.len() {
        let c = chars[k];
        match quote {
            Some(q) if c == q => quote = None,
            None if c == '"' || c == '\'' => quote = Some(c),
            None if c == '#' => {
                out.extend(&chars[k..]);
                break;
            }
            None if c == '$' => {
                let (name, rest, immediate) = match chars.get(k + 1) {
                    Some('{') => {
                        let end = chars[k + 2..]
                            .iter()
                            .position(|&c| c == '}')
                            .ok_or("missing `}` after `${`")?;
                        (
                            chars[k + 2..k + 2 + end].iter().collect::<String>(),
                            k + 3 + end,
                            false,
                        )
                    }
                    Some('(') => {
                        let mut depth = 0;
                        let mut end = None;
                        for (j, &c) in chars.iter().enumerate().skip(k + 1) {
                            if c == '(' {
                                depth += 1;
                            } else if c == ')' {
                                depth -= 1;
                                if depth == 0 {
                                    end = Some(j);
                                    break;
                                }
                            }
                        }
                        let end = end.ok_or("missing `)` after `$(`")?;
                        (chars[k + 2..end].iter().collect(), end + 1, true)
                    }
                    Some(&c) => (c.to_string(), k + 2, false),
                    None => return Err("`$` at the end of a line".into()),
                };
                let value = if immediate {
                    format_g(eval_formula(&name, table, 0, resolve)?, 20)
                } else {
                    lookup(&name, table, 0, resolve)?
                };
                out.push_str(&value);
                k = rest;
                continue;
            }
            _ => {}
        }
        out.push(c);
        k += 1;
    }
    Ok(out)
}

/// Applies a `variable` command.
fn define(words: &[String], table: &mut HashMap<String, Var>) -> Result<(), String> {
    let (name, style) = match words {
        [_, n, s, ..] => (n.clone(), s.as_str()),
        [_, n] => return Err(format!("variable `{n}`: no style")),
        _ => return Err("no variable name".into()),
    };
    let args = &words[3..];
    match style {
        "index" | "string" | "getenv" if args.is_empty() => {
            Err(format!("variable `{name}`: no value"))
        }
        // an index variable already set (from the command line) keeps its value
        "index" => {
            table.entry(name).or_insert(Var::Text(args[0].clone()));
            Ok(())
        }
        "string" => {
            table.insert(name, Var::Text(args.join(" ")));
            Ok(())
        }
        "equal" => {
            if args.is_empty() {
                return Err(format!("variable `{name}`: no formula"));
            }
            table.insert(name, Var::Equal(args.join(" ")));
            Ok(())
        }
        "delete" => {
            table.remove(&name);
            Ok(())
        }
        other => Err(format!(
            "variable style `{other}` is not supported (index, string, equal, delete)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variables_and_substitution() {
        let src = "variable np index 10\nvariable r equal 0.5*${np}\nvariable s string a b\n\
                   run ${np} # $x\nx ${r} $(v_r*2) \"${s}\" ${s}\nvariable np index 99\ny ${np}";
        let d = Deck::parse(src, Path::new("t.in"), &[]).unwrap();
        assert_eq!(d.commands[0].words, ["run", "10"]);
        assert_eq!(d.commands[1].words, ["x", "5", "10", "${s}", "a", "b"]);
        assert_eq!(d.commands[2].words, ["y", "10"]);
        let d = Deck::parse(src, Path::new("t.in"), &[("np".into(), "4".into())]).unwrap();
        assert_eq!(d.commands[0].words, ["run", "4"]);
        let e = Deck::parse("a\nb ${nope}", Path::new("t.in"), &[]).unwrap_err();
        assert!(e.to_string().starts_with("t.in:2:"), "{e}");
        assert!(e.to_string().contains("nope"), "{e}");
    }

    #[test]
    fn runtime_variables_are_evaluated_when_asked() {
        // `fix print` keeps its quoted text; the variables it names are evaluated while the
        // simulation runs, with the running values of step, dt and the fix vectors.
        let src = "variable time equal step*dt\nvariable fx equal f_cfd2[1]\n\
                   variable n index 3\nfix p all print 10 \"${time} ${fx} $n\"\n\
                   variable n delete\nvariable n string late\nrun 1";
        let d = Deck::parse(src, Path::new("t.in"), &[("w".into(), "9".into())]).unwrap();
        assert_eq!(d.commands[0].words[5], "${time} ${fx} $n");
        let resolve = |r: expr::Ref| match r {
            expr::Ref::Keyword("step") => Ok(1000.0),
            expr::Ref::Keyword("dt") => Ok(1e-5),
            expr::Ref::Fix("cfd2", Some(1)) => Ok(-0.25),
            other => Err(format!("unknown {other}")),
        };
        let at_print = d.variables_at(d.commands[0].line);
        assert_eq!(
            at_print
                .substitute(&d.commands[0].words[5], &resolve)
                .unwrap(),
            "0.01 -0.25 3"
        );
        assert_eq!(at_print.number("time", &resolve).unwrap(), 1000.0 * 1e-5);
        assert_eq!(at_print.value("w", &resolve).unwrap(), "9");
        let at_end = d.variables_at(usize::MAX);
        assert_eq!(at_end.value("n", &resolve).unwrap(), "late");
        assert!(at_end
            .number("n", &resolve)
            .unwrap_err()
            .contains("not a number"));
        // while reading, a running value in an immediate substitution is an error
        let e = Deck::parse("variable t equal step\nrun ${t}", Path::new("t.in"), &[]).unwrap_err();
        assert!(
            e.to_string().contains("only while the simulation runs"),
            "{e}"
        );
    }
}
