//! `foamgrain dem DECK [-var NAME VALUE]…`: a LIGGGHTS deck on the native DEM, run as
//! `liggghts -in DECK` runs it — relative paths against the current directory, thermo lines on
//! the screen and in `log.liggghts`, dumps and `write_data` files where the deck says.

use anyhow::{bail, Context};
use clap::Args;
use indicatif::ProgressBar;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `foamgrain dem`.
#[derive(Args, Debug)]
pub struct DemArgs {
    /// The deck and LIGGGHTS's own options, as `liggghts` takes them: `DECK` or `-in DECK`,
    /// `-var NAME VALUE` (or `-v`; repeatable), `-log FILE|none` (default `log.liggghts`),
    /// `-screen none|FILE` (default: this terminal); and `--threads N`, the native DEM's worker
    /// threads (default: all cores; results are deterministic for a given count).
    #[arg(
        value_name = "DECK [-var NAME VALUE]… [-log FILE] [-screen FILE] [--threads N]",
        required = true,
        allow_hyphen_values = true,
        trailing_var_arg = true
    )]
    pub words: Vec<String>,
}

/// What `liggghts`-style options ask for.
#[derive(Debug, PartialEq)]
struct Options {
    deck: PathBuf,
    vars: Vec<(String, String)>,
    log: Option<PathBuf>,
    screen: Screen,
    threads: Option<usize>,
}

#[derive(Debug, PartialEq)]
enum Screen {
    Terminal,
    None,
    File(PathBuf),
}

fn parse_options(words: &[String]) -> anyhow::Result<Options> {
    let mut deck = None;
    let mut vars = Vec::new();
    let mut log = Some(PathBuf::from("log.liggghts"));
    let mut screen = Screen::Terminal;
    let mut threads = None;
    let mut k = 0;
    let value = |k: usize, flag: &str| -> anyhow::Result<&String> {
        words
            .get(k)
            .with_context(|| format!("{flag} needs a value"))
    };
    while k < words.len() {
        let w = words[k].as_str();
        match w {
            "-in" | "-i" => {
                if deck.is_some() {
                    bail!("two decks given (a DECK and `-in`)");
                }
                deck = Some(PathBuf::from(value(k + 1, w)?));
                k += 2;
            }
            "-var" | "-v" => {
                let name = value(k + 1, w)?.clone();
                let v = value(k + 2, &format!("{w} {name}"))?.clone();
                k += 3;
                if words.get(k).is_some_and(|x| !x.starts_with('-')) {
                    bail!(
                        "{w} {name}: several values (an index variable looping over values) \
                         are not supported; give one value"
                    );
                }
                vars.push((name, v));
            }
            "-log" | "-l" => {
                let f = value(k + 1, w)?;
                log = (f != "none").then(|| PathBuf::from(f));
                k += 2;
            }
            "-screen" | "-sc" => {
                let f = value(k + 1, w)?;
                screen = if f == "none" {
                    Screen::None
                } else {
                    Screen::File(PathBuf::from(f))
                };
                k += 2;
            }
            "--threads" => {
                let n = value(k + 1, w)?;
                threads = Some(
                    n.parse()
                        .with_context(|| format!("--threads `{n}` is not a whole number"))?,
                );
                k += 2;
            }
            _ if w.starts_with('-') => bail!(
                "LIGGGHTS option `{w}` is not supported by foamgrain dem \
                 (supported: -in, -var/-v, -log, -screen, --threads)"
            ),
            _ if k == 0 => {
                deck = Some(PathBuf::from(w));
                k += 1;
            }
            _ => bail!(
                "unexpected `{w}` (the deck comes first: foamgrain dem DECK [-var NAME VALUE]…)"
            ),
        }
    }
    Ok(Options {
        deck: deck.context("no deck given (foamgrain dem DECK or -in DECK)")?,
        vars,
        log,
        screen,
        threads,
    })
}

/// Where the screen and log lines go.
struct Output {
    screen: Option<Box<dyn Write>>,
    log: Option<std::io::BufWriter<std::fs::File>>,
    bar: Option<ProgressBar>,
}

impl Output {
    fn set_log(&mut self, path: Option<&Path>, append: bool) -> std::io::Result<()> {
        if let Some(mut old) = self.log.take() {
            old.flush()?;
        }
        if let Some(p) = path {
            let f = dem::deck::open_output(p, append)
                .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", p.display())))?;
            self.log = Some(std::io::BufWriter::new(f));
        }
        Ok(())
    }

    fn line(&mut self, text: &str) -> std::io::Result<()> {
        if let Some(log) = &mut self.log {
            writeln!(log, "{text}")?;
        }
        match (&self.bar, &mut self.screen) {
            (Some(b), Some(_)) => b.println(text),
            (None, Some(s)) => writeln!(s, "{text}")?,
            (_, None) => {}
        }
        Ok(())
    }
}

/// Runs the command.
pub fn run(a: &DemArgs) -> anyhow::Result<()> {
    let opts = parse_options(&a.words)?;
    crate::args::set_threads(opts.threads, "--threads")?;
    let deck = liggghts_deck::Deck::read_with_vars(&opts.deck, &opts.vars)?;
    let log = match &opts.log {
        Some(p) => Some(std::io::BufWriter::new(
            std::fs::File::create(p).with_context(|| format!("creating log {}", p.display()))?,
        )),
        None => None,
    };
    let screen: Option<Box<dyn Write>> = match &opts.screen {
        Screen::Terminal => Some(Box::new(std::io::stdout())),
        Screen::None => None,
        Screen::File(p) => Some(Box::new(std::io::BufWriter::new(
            std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?,
        ))),
    };
    let bar = match opts.screen {
        Screen::Terminal => crate::args::progress_bar(
            1,
            "{spinner} [{elapsed_precise}] {bar:30} step {pos}/{len} {msg} (ETA {eta})",
        ),
        _ => None,
    };
    let mut out = Output { screen, log, bar };
    out.line(&format!(
        "foamgrain dem {} (native DEM, {} threads): {}",
        env!("CARGO_PKG_VERSION"),
        rayon::current_num_threads(),
        opts.deck.display()
    ))?;
    let started = Instant::now();
    let mut io_error = None;
    let (mut run_from, mut end_time) = (0, 0.0);
    let mut on_event = |e: dem::deck::exec::DeckEvent| {
        use dem::deck::exec::DeckEvent;
        let written = match e {
            DeckEvent::RunStart { from, to, dt, .. } => {
                run_from = from;
                end_time = to as f64 * dt;
                if let Some(b) = &out.bar {
                    b.reset();
                    b.set_length(to - from);
                }
                Ok(())
            }
            DeckEvent::Progress { step, time } => {
                if let Some(b) = &out.bar {
                    b.set_position(step - run_from);
                    b.set_message(format!("t = {time:.6} / {end_time:.6} s"));
                }
                Ok(())
            }
            DeckEvent::Output(line) => out.line(&line),
            // `log FILE` in the deck moves the log, as in LIGGGHTS
            DeckEvent::Log { path, append } => out.set_log(path.as_deref(), append),
            DeckEvent::Warning { line, message } => out.line(&format!(
                "WARNING: {}:{line}: {message}",
                opts.deck.display()
            )),
        };
        if let Err(e) = written {
            io_error.get_or_insert(e);
        }
    };
    let result = dem::Simulation::from_deck_observed(&deck, Path::new("."), &mut on_event);
    if let Some(b) = &out.bar {
        b.finish_and_clear();
    }
    let sim = result?;
    if let Some(e) = io_error {
        return Err(e).context("writing the screen or log output");
    }
    for w in sim.warnings() {
        out.line(&format!("WARNING: {w}"))?;
    }
    out.line(&format!(
        "foamgrain dem: {} particles at step {} (t = {} s), {} lost through the box faces; \
         {:.2} s wall time",
        sim.particles.len(),
        sim.step(),
        liggghts_deck::format::format_g(sim.time(), 8),
        sim.lost(),
        started.elapsed().as_secs_f64()
    ))?;
    if let Some(log) = &mut out.log {
        log.flush().context("writing the log")?;
    }
    if let Some(s) = &mut out.screen {
        s.flush().context("writing the screen output")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_owned).collect()
    }

    #[test]
    fn liggghts_options() {
        let o = parse_options(&words("-in in.pour -var np 300 -v w -0.004 -log none")).unwrap();
        assert_eq!(o.deck, PathBuf::from("in.pour"));
        assert_eq!(
            o.vars,
            [
                ("np".to_string(), "300".to_string()),
                ("w".to_string(), "-0.004".to_string())
            ]
        );
        assert_eq!(o.log, None);
        assert_eq!(o.screen, Screen::Terminal);
        assert_eq!(o.threads, None);
        let o = parse_options(&words("in.pour -screen none --threads 2")).unwrap();
        assert_eq!(o.threads, Some(2));
        assert_eq!(o.log, Some(PathBuf::from("log.liggghts")));
        assert_eq!(o.screen, Screen::None);
        for (bad, says) in [
            ("-var np", "needs a value"),
            ("in.a in.b", "unexpected `in.b`"),
            ("in.a -in in.b", "two decks"),
            ("-var n 1 2 3 in.x", "several values"),
            ("in.a -sf gpu", "`-sf`"),
            ("-log x.log", "no deck"),
            ("in.a --threads two", "whole number"),
        ] {
            let e = parse_options(&words(bad)).unwrap_err().to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }
}
