//! `fix ID all print N "TEXT" [file F | append F] [screen yes|no] [title T]`: every N steps
//! (at the multiples of N after a run starts, as LAMMPS's `fix print`), TEXT with its variables
//! substituted at that moment ([`Values::substitute`]) goes to the file (one line each, after
//! the title line, `# Fix print output for fix ID` by default; flushed at once) and, with
//! `screen yes` (the default), to the screen.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::deck::values::Values;

type Res<T> = Result<T, String>;

/// One `fix print`.
#[derive(Debug)]
pub struct FixPrint {
    /// The fix id.
    pub id: String,
    /// Print every this many steps.
    pub every: u64,
    text: String,
    screen: bool,
    file: Option<(PathBuf, BufWriter<File>)>,
}

impl FixPrint {
    /// Parses `fix ID GROUP print N TEXT …` (`w` are the command's words, TEXT without its
    /// quotes) and opens the file, relative names against `workdir` (its folder is made).
    pub fn new(w: &[String], workdir: &Path) -> Res<FixPrint> {
        let id = w.get(1).ok_or("fix print: no id")?.clone();
        let every: u64 = w
            .get(4)
            .and_then(|n| n.parse().ok())
            .filter(|&n| n > 0)
            .ok_or("fix print: the interval N must be a whole number ≥ 1")?;
        let text = w.get(5).ok_or("fix print: no text")?.clone();
        let mut screen = true;
        let mut title = format!("# Fix print output for fix {id}");
        let mut target: Option<(String, bool)> = None;
        let mut k = 6;
        while k < w.len() {
            let value = w
                .get(k + 1)
                .ok_or_else(|| format!("fix print {}: no value", w[k]))?;
            match w[k].as_str() {
                "file" => target = Some((value.clone(), false)),
                "append" => target = Some((value.clone(), true)),
                "screen" => {
                    screen = match value.as_str() {
                        "yes" => true,
                        "no" => false,
                        o => return Err(format!("fix print screen `{o}` (yes/no expected)")),
                    }
                }
                "title" => title = value.clone(),
                o => return Err(format!("fix print keyword `{o}` is not supported")),
            }
            k += 2;
        }
        let file = match target {
            None => None,
            Some((name, append)) => {
                let path = workdir.join(&name);
                let err =
                    |e: std::io::Error| format!("fix print: cannot open {}: {e}", path.display());
                if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                    std::fs::create_dir_all(dir).map_err(err)?;
                }
                let f = crate::deck::open_output(&path, append).map_err(err)?;
                let mut f = BufWriter::new(f);
                if !append {
                    writeln!(f, "{title}")
                        .and_then(|_| f.flush())
                        .map_err(err)?;
                }
                Some((path, f))
            }
        };
        Ok(FixPrint {
            id,
            every,
            text,
            screen,
            file,
        })
    }

    /// The next step after `step` at which it prints.
    pub fn next_after(&self, step: u64) -> u64 {
        (step / self.every + 1) * self.every
    }

    /// Prints if `step` is one of its steps; returns the line for the screen, if any.
    pub fn at_step(&mut self, step: u64, values: &Values) -> Res<Option<String>> {
        if !step.is_multiple_of(self.every) {
            return Ok(None);
        }
        let line = values
            .substitute(&self.text)
            .map_err(|e| format!("fix print {}: {e}", self.id))?;
        if let Some((path, f)) = &mut self.file {
            writeln!(f, "{line}").and_then(|_| f.flush()).map_err(|e| {
                format!(
                    "fix print {}: cannot write {}: {e}",
                    self.id,
                    path.display()
                )
            })?;
        }
        Ok(self.screen.then_some(line))
    }
}
