//! The subset of a LIGGGHTS 3.8 input deck that foamgrain's reference cases use, read into
//! commands (variables substituted) and executed on a [`Simulation`](crate::Simulation) by
//! [`Simulation::from_deck`](crate::Simulation::from_deck).
//!
//! Reading handles `&` continuations, `#` comments, quotes, and `variable NAME index|string|
//! equal …` with `$x`, `${name}` and `$(formula)` substitution (equal-style values are
//! formatted with 15 significant digits, as LAMMPS does); values given on the command line
//! (`-var NAME VALUE`) take precedence over `index` definitions. The supported commands are
//! listed in [`exec`]; any other command is an error naming the file, line and command.

pub mod data_file;
pub mod exec;
pub mod expr;
pub mod lines;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::error::{DeckLocation, DemError};

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
}

/// What `fix couple/cfd` and `fix couple/cfd/force[/implicit]` declare.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoupledDeck {
    /// `couple_every N`: DEM steps per coupling exchange.
    pub couple_every: u64,
    /// Whether the force fix is `couple/cfd/force/implicit` (else `couple/cfd/force`, or none).
    pub implicit: bool,
    /// Whether a force fix is present at all.
    pub has_force_fix: bool,
}

#[derive(Debug, Clone)]
enum Var {
    Text(String),
    Equal(String),
}

impl Deck {
    /// Reads a deck file.
    pub fn read(path: impl AsRef<Path>) -> Result<Deck, DemError> {
        Deck::read_with_vars(path, &[])
    }

    /// Reads a deck with command-line variables (`-var NAME VALUE`).
    pub fn read_with_vars(
        path: impl AsRef<Path>,
        vars: &[(String, String)],
    ) -> Result<Deck, DemError> {
        let path = path.as_ref();
        let src = std::fs::read_to_string(path).map_err(|source| DemError::DeckIo {
            file: path.to_path_buf(),
            source,
        })?;
        Deck::parse(&src, path, vars)
    }

    /// Parses deck text; `file` names it in errors.
    pub fn parse(src: &str, file: &Path, vars: &[(String, String)]) -> Result<Deck, DemError> {
        let mut table: HashMap<String, Var> = vars
            .iter()
            .map(|(k, v)| (k.clone(), Var::Text(v.clone())))
            .collect();
        let mut commands = Vec::new();
        for l in lines::logical_lines(src) {
            let err = |command: &str, message: String| DemError::Deck {
                at: DeckLocation {
                    file: file.to_path_buf(),
                    line: l.line,
                    command: command.to_string(),
                },
                message,
            };
            let text = substitute(&l.text, &table).map_err(|m| err("", m))?;
            let words = lines::split_words(lines::strip_comment(&text)).map_err(|m| err("", m))?;
            if words.is_empty() {
                continue;
            }
            if words[0] == "variable" {
                define(&words, &mut table).map_err(|m| err("variable", m))?;
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
        })
    }

    /// The location of `c` for messages.
    pub fn location(&self, c: &Command) -> DeckLocation {
        DeckLocation {
            file: self.file.clone(),
            line: c.line,
            command: c.label(),
        }
    }

    /// Whether and how the deck is coupled to a CFD solver (`fix couple/cfd …`).
    pub fn coupling(&self) -> Option<CoupledDeck> {
        let mut out: Option<CoupledDeck> = None;
        for c in &self.commands {
            if c.words.first().map(String::as_str) != Some("fix") {
                continue;
            }
            match c.words.get(3).map(String::as_str) {
                Some("couple/cfd") => {
                    let every = c
                        .words
                        .iter()
                        .position(|w| w == "couple_every")
                        .and_then(|k| c.words.get(k + 1))
                        .and_then(|w| w.parse().ok())
                        .unwrap_or(1);
                    out = Some(CoupledDeck {
                        couple_every: every,
                        implicit: false,
                        has_force_fix: false,
                    });
                }
                Some(s @ ("couple/cfd/force" | "couple/cfd/force/implicit")) => {
                    if let Some(o) = out.as_mut() {
                        o.has_force_fix = true;
                        o.implicit = s.ends_with("implicit");
                    }
                }
                _ => {}
            }
        }
        out
    }
}

fn lookup(name: &str, table: &HashMap<String, Var>, depth: usize) -> Result<String, String> {
    if depth > 32 {
        return Err(format!("variable `{name}` refers to itself"));
    }
    match table.get(name) {
        Some(Var::Text(t)) => Ok(t.clone()),
        Some(Var::Equal(f)) => {
            let v = eval_formula(f, table, depth)?;
            Ok(format_g15(v))
        }
        None => Err(format!("variable `{name}` is not defined")),
    }
}

fn eval_formula(f: &str, table: &HashMap<String, Var>, depth: usize) -> Result<f64, String> {
    expr::evaluate(f, &|n| {
        let t = lookup(n, table, depth + 1)?;
        t.trim()
            .parse::<f64>()
            .map_err(|_| format!("variable `{n}` = `{t}` is not a number"))
    })
}

/// `%.15g`, the format LAMMPS substitutes equal-style values with.
fn format_g15(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let exp = v.abs().log10().floor() as i32;
    if !(-4..15).contains(&exp) {
        let s = format!("{:.14e}", v);
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = m.trim_end_matches('0').trim_end_matches('.');
        let e: i32 = e.parse().unwrap_or(0);
        return format!("{m}e{}{:02}", if e < 0 { '-' } else { '+' }, e.abs());
    }
    let decimals = (14 - exp).max(0) as usize;
    let s = format!("{:.*}", decimals, v);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Replaces `$x`, `${name}` and `$(formula)` outside quotes.
fn substitute(s: &str, table: &HashMap<String, Var>) -> Result<String, String> {
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
                    format_g15(eval_formula(&name, table, 0)?)
                } else {
                    lookup(&name, table, 0)?
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
    fn g15_format() {
        assert_eq!(format_g15(5.0), "5");
        assert_eq!(format_g15(1e-5), "1e-05");
        assert_eq!(format_g15(0.1 + 0.2), "0.3");
        assert_eq!(format_g15(-2.5e20), "-2.5e+20");
        assert_eq!(format_g15(12345.678), "12345.678");
    }
}
