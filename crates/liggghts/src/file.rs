//! File coupling: the `liggghts` binary as a child process, exchanging through files — for
//! users who cannot link libliggghts. **Slow by design**: LIGGGHTS 3.8.0 checks for the
//! coupler's files with `sleep(10)` between looks, so each exchange costs about 10 s whatever
//! the number of particles; serial only; values it writes have 6 significant digits (C++
//! stream default), so positions and velocities come with a relative rounding of 5e-7.
//!
//! # What runs
//! [`FileDem::open`] writes `<deck>.file-coupling` next to the deck in the working directory,
//! a copy of the deck ([`CouplingDeck::for_file_coupling`]) in which
//! - the `fix … couple/cfd … mpi` line becomes `… file PREFIX` with PREFIX
//!   `<workdir>/couple-files/` (reported by [`FileDem::rewritten`] with the original line);
//! - a block before it stores each particle's tag in a per-atom property `fgTag` (LIGGGHTS
//!   writes the exchange files in its local order, which changes as it sorts its atoms, and
//!   its own `transfer_id` writes integers as doubles) and dumps the initial state with full
//!   precision (`couple-files/init.dump`, what [`FileDem::state`] shows before any exchange);
//! - the force fix gets `transfer_density yes transfer_property name fgTag type scalar-atom`;
//! - the trailing `run` commands become one `run total_steps`.
//!
//! # The handshake (LIGGGHTS's `cfd_datacoupling_file.cpp`)
//! Every `couple_every` steps LIGGGHTS writes each pushed property to `PREFIX<name>0` and
//! renames it to `PREFIX<name>1` (`x`, `v`, `radius`, `omega`, `density`, `fgTag`); from the
//! second exchange on it first waits until the coupler has renamed the previous `…1` back to
//! `…0`. Then, for each pulled property (`dragforce`, `hdtorque` and with the implicit fix `Ksl`,
//! `uf`, `KslRotation`, `KslExtra`, `ex`), it waits for `PREFIX<name>0`, reads it and renames it
//! to `…1`. Files hold the row count then one row per particle (`x y z` or one value).
//! The coupler here reads all pushed files and renames them to `…0`, and writes each pulled
//! file as `<name>.tmp` renamed to `<name>0` (so LIGGGHTS never reads half a file), `dragforce`
//! last (the one LIGGGHTS waits on first). While waiting it polls the child: a LIGGGHTS that
//! exits or crashes is an error with the tail of its log, never a hang.
//! No particle may be inserted during the coupled run (LIGGGHTS's file coupling refuses it).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use couple::{ParticleSide, ParticleState, SideError};
use mesh::v3::V3;

use crate::deck::{CouplingDeck, DataCoupling};
use crate::error::LiggghtsError;
use crate::forces::{force_fields, ForceFields, ForceMode};
use crate::particles::Particles;
use crate::program::{self, absolute};

/// Options of [`FileDem::open`].
#[derive(Debug, Clone)]
pub struct FileOptions {
    /// DEM steps of the whole coupled run (the `run` the copy of the deck ends with).
    pub total_steps: u64,
    /// How often the coupler looks for LIGGGHTS's files.
    pub poll: Duration,
    /// Longest wait for one exchange before giving up (LIGGGHTS itself needs ~10 s).
    pub timeout: Duration,
}

impl FileOptions {
    /// `total_steps` with a 20 ms poll and a 10-minute timeout.
    pub fn new(total_steps: u64) -> FileOptions {
        FileOptions {
            total_steps,
            poll: Duration::from_millis(20),
            timeout: Duration::from_secs(600),
        }
    }
}

/// The deck line that was rewritten for file coupling.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rewritten {
    /// The original deck.
    pub deck: PathBuf,
    /// 1-based line of its `fix … couple/cfd`.
    pub line: usize,
    /// The copy LIGGGHTS runs.
    pub copy: PathBuf,
    /// The exchange-file prefix written into it.
    pub prefix: String,
}

/// Names of the properties LIGGGHTS pushes (with the options the copy sets).
const PUSHED: [&str; 6] = ["x", "v", "radius", "omega", "density", "fgTag"];
/// Pulled vector properties that stay zero.
const ZERO_VECTORS_IMPLICIT: [&str; 4] = ["hdtorque", "KslRotation", "KslExtra", "ex"];

/// LIGGGHTS through files (module docs).
pub struct FileDem {
    child: Option<Child>,
    command: String,
    log: PathBuf,
    screen: PathBuf,
    dir: PathBuf,
    rewritten: Rewritten,
    options: FileOptions,
    mode: ForceMode,
    every: u64,
    dt: f64,
    start_step: u64,
    steps: u64,
    particles: Particles,
    /// Local row of each particle of `particles` at the last exchange.
    row_of: Vec<usize>,
    /// The fields last set, in the order of `field_ids`.
    fields: ForceFields,
    field_ids: Vec<u64>,
    forces_set: bool,
    exchanges: u64,
}

impl FileDem {
    /// Starts `liggghts` on the file-coupling copy of `deck` in `workdir` with `-var` values
    /// `vars`, and reads the initial particles. The deck is checked first
    /// ([`crate::deck`]); it must give `timestep` as a number and `couple_every`.
    pub fn open(
        deck: &Path,
        workdir: &Path,
        vars: &[(String, String)],
        options: FileOptions,
    ) -> Result<FileDem, LiggghtsError> {
        let d = CouplingDeck::read(deck, vars)?;
        if let Some(line) = d.convection {
            return Err(LiggghtsError::Deck {
                file: deck.to_path_buf(),
                line,
                message: "`couple/cfd/convection`: heat is exchanged with LIGGGHTS in-process \
                          only (`--dem liggghts` with the `liggghts` feature) or with the native \
                          DEM, not through files"
                    .into(),
            });
        }
        d.check_inputs(workdir)?;
        // the binary runs serially
        d.check_ranks(1)?;
        let workdir = absolute(workdir)?;
        let every = d.couple_every.ok_or_else(|| LiggghtsError::Deck {
            file: deck.to_path_buf(),
            line: d.couple_line,
            message: "file coupling needs `couple_every N` on the couple/cfd line".into(),
        })?;
        let dt = d.time_step.ok_or_else(|| LiggghtsError::Deck {
            file: deck.to_path_buf(),
            line: 0,
            message: "file coupling needs `timestep` given as a number".into(),
        })?;
        if options.total_steps == 0 || !options.total_steps.is_multiple_of(every) {
            return Err(LiggghtsError::Parameter(format!(
                "total_steps {} must be a positive multiple of couple_every {every}",
                options.total_steps
            )));
        }
        let dir = workdir.join("couple-files");
        if dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(|e| LiggghtsError::io(&dir, e))?;
        }
        std::fs::create_dir_all(&dir).map_err(|e| LiggghtsError::io(&dir, e))?;
        let prefix = format!("{}/", dir.display());
        if prefix.chars().any(char::is_whitespace) {
            return Err(LiggghtsError::Parameter(format!(
                "the exchange directory {} contains blanks, which LIGGGHTS cannot take",
                dir.display()
            )));
        }
        let init_dump = dir.join("init.dump");
        let text = d.for_file_coupling(
            &prefix,
            &init_dump.display().to_string(),
            options.total_steps,
        )?;
        let name = deck
            .file_name()
            .map_or("deck".into(), |n| n.to_string_lossy().into_owned());
        let copy = workdir.join(format!("{name}.file-coupling"));
        std::fs::write(&copy, text).map_err(|e| LiggghtsError::io(&copy, e))?;
        let log = workdir.join("log.file-coupling");
        let screen = workdir.join("screen.file-coupling");
        let mut c = program::command(&copy, vars, &log, &screen);
        c.current_dir(&workdir)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        let command = program::describe(&c);
        let child = c.spawn().map_err(|e| LiggghtsError::Program {
            program: command.clone(),
            what: format!("could not be started ({e}; is Debian's `liggghts` package installed?)"),
            log: log.clone(),
            tail: String::new(),
        })?;
        let mode = if d.force.implicit {
            ForceMode::Implicit
        } else {
            ForceMode::FrozenAtExchange
        };
        let mut side = FileDem {
            child: Some(child),
            command,
            log,
            screen,
            dir,
            rewritten: Rewritten {
                deck: deck.to_path_buf(),
                line: d.couple_line,
                copy,
                prefix,
            },
            options,
            mode,
            every,
            dt,
            start_step: 0,
            steps: 0,
            particles: Particles::default(),
            row_of: Vec::new(),
            fields: ForceFields::default(),
            field_ids: Vec::new(),
            forces_set: false,
            exchanges: 0,
        };
        side.read_initial(&init_dump)?;
        debug_assert!(matches!(
            d.data_coupling,
            DataCoupling::Mpi | DataCoupling::File(_)
        ));
        Ok(side)
    }

    /// Which line of which deck was rewritten, and the copy that runs.
    pub fn rewritten(&self) -> &Rewritten {
        &self.rewritten
    }

    /// How the deck's force fix takes the force.
    pub fn force_mode(&self) -> ForceMode {
        self.mode
    }

    /// Exchanges done.
    pub fn exchanges(&self) -> u64 {
        self.exchanges
    }

    /// After the last exchange of `total_steps`: waits for LIGGGHTS to finish its run and
    /// checks its exit status (a run stopped earlier is ended).
    pub fn finish(mut self) -> Result<(), LiggghtsError> {
        if self.steps < self.options.total_steps || !self.forces_set {
            self.kill();
            return Ok(());
        }
        let start = Instant::now();
        loop {
            if let Some(status) = self.try_wait()? {
                self.child = None;
                if !status.success() {
                    return Err(self.failed(status));
                }
                return Ok(());
            }
            if start.elapsed() > self.options.timeout {
                self.kill();
                return Err(self.timeout("its end"));
            }
            std::thread::sleep(self.options.poll);
        }
    }

    fn kill(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }

    fn try_wait(&mut self) -> Result<Option<std::process::ExitStatus>, LiggghtsError> {
        match self.child.as_mut() {
            Some(c) => c
                .try_wait()
                .map_err(|e| LiggghtsError::io(PathBuf::from(&self.command), e)),
            None => Err(LiggghtsError::Parameter(
                "LIGGGHTS has already ended".into(),
            )),
        }
    }

    fn failed(&self, status: std::process::ExitStatus) -> LiggghtsError {
        let mut c = Command::new(program::LIGGGHTS_PROGRAM);
        c.arg(&self.rewritten.copy);
        program::program_failed(&c, status, &self.log, &self.screen)
    }

    fn timeout(&self, what: &str) -> LiggghtsError {
        LiggghtsError::Program {
            program: self.command.clone(),
            what: format!(
                "did not reach {what} within {:.0} s",
                self.options.timeout.as_secs_f64()
            ),
            log: self.log.clone(),
            tail: program::log_tail(&self.log, program::TAIL_LINES),
        }
    }

    /// Waits until `ready()` holds, polling the child.
    fn wait_for(
        &mut self,
        what: &str,
        mut ready: impl FnMut() -> bool,
    ) -> Result<(), LiggghtsError> {
        let start = Instant::now();
        loop {
            if ready() {
                return Ok(());
            }
            if let Some(status) = self.try_wait()? {
                self.child = None;
                return Err(self.failed(status));
            }
            if start.elapsed() > self.options.timeout {
                return Err(self.timeout(what));
            }
            std::thread::sleep(self.options.poll);
        }
    }

    /// The initial state from the dump the copy writes before coupling starts.
    fn read_initial(&mut self, dump: &Path) -> Result<(), LiggghtsError> {
        // complete when it ends with a newline and parses with all its rows
        let mut snap = None;
        self.wait_for("the initial dump", || {
            let ends = std::fs::read(dump).is_ok_and(|b| b.ends_with(b"\n"));
            if ends {
                snap = dem_io_snapshot(dump).ok();
            }
            snap.is_some()
        })?;
        let (step, p) = snap.expect("waited for");
        self.start_step = step;
        let density = p.density.clone().ok_or_else(|| LiggghtsError::Exchange {
            file: dump.to_path_buf(),
            line: 9,
            message: "no density column".into(),
        })?;
        let mut idx: Vec<usize> = (0..p.len()).collect();
        idx.sort_by_key(|&i| p.id[i]);
        self.particles.clear();
        for &i in &idx {
            self.particles.push(
                p.id[i],
                p.position[i],
                p.velocity[i],
                p.radius[i],
                density[i],
            );
        }
        Ok(())
    }

    fn path(&self, name: &str, suffix: &str) -> PathBuf {
        self.dir.join(format!("{name}{suffix}"))
    }

    /// One exchange: waits for LIGGGHTS's files, reads them into the state, hands them back.
    fn receive(&mut self) -> Result<(), LiggghtsError> {
        let paths: Vec<PathBuf> = PUSHED.iter().map(|n| self.path(n, "1")).collect();
        let step = self.start_step + self.steps + self.every;
        self.wait_for(&format!("the exchange at step {step}"), || {
            paths.iter().all(|p| p.is_file())
        })?;
        let x = read_rows::<3>(&paths[0])?;
        let v = read_rows::<3>(&paths[1])?;
        let r = read_rows::<1>(&paths[2])?;
        let rho = read_rows::<1>(&paths[4])?;
        let tag = read_rows::<1>(&paths[5])?;
        let n = x.len();
        for (p, rows) in [
            (&paths[1], v.len()),
            (&paths[2], r.len()),
            (&paths[4], rho.len()),
            (&paths[5], tag.len()),
        ] {
            if rows != n {
                return Err(LiggghtsError::Exchange {
                    file: p.clone(),
                    line: 1,
                    message: format!("{rows} rows, but {} has {n}", paths[0].display()),
                });
            }
        }
        let mut tags = Vec::with_capacity(n);
        for (k, t) in tag.iter().enumerate() {
            let t = t[0];
            if !((1.0..1e6).contains(&t) && t.fract() == 0.0) {
                return Err(LiggghtsError::Exchange {
                    file: paths[5].clone(),
                    line: k + 2,
                    message: format!(
                        "tag {t}: file coupling needs tags 1..999999 set before the coupling \
                         starts (no insertion during the coupled run; LIGGGHTS writes 6 digits)"
                    ),
                });
            }
            tags.push(t as u64);
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&k| tags[k]);
        self.particles.clear();
        for &k in &order {
            self.particles.push(tags[k], x[k], v[k], r[k][0], rho[k][0]);
        }
        self.row_of = order;
        for name in PUSHED {
            let (from, to) = (self.path(name, "1"), self.path(name, "0"));
            std::fs::rename(&from, &to).map_err(|e| LiggghtsError::io(&from, e))?;
        }
        self.steps += self.every;
        self.exchanges += 1;
        Ok(())
    }

    /// Writes the pulled files for the particles of the last exchange (in LIGGGHTS's local
    /// order), with the fields last set (zero for particles without).
    fn send(&mut self) -> Result<(), LiggghtsError> {
        let n = self.particles.len();
        let mut index = std::collections::HashMap::with_capacity(self.field_ids.len());
        for (k, &id) in self.field_ids.iter().enumerate() {
            index.insert(id, k);
        }
        // local row → index into the fields
        let mut at_row: Vec<Option<usize>> = vec![None; n];
        for (s, &row) in self.row_of.iter().enumerate() {
            at_row[row] = index.get(&self.particles.ids[s]).copied();
        }
        let vec_rows = |f: &dyn Fn(usize) -> V3| -> String {
            let mut s = format!("{n}\n");
            for r in &at_row {
                let v = r.map_or(V3::zeros(), f);
                s.push_str(&format!("{:e} {:e} {:e}\n", v[0], v[1], v[2]));
            }
            s
        };
        let zero = vec_rows(&|_| V3::zeros());
        let mut files: Vec<(&str, String)> = vec![("hdtorque", zero.clone())];
        if self.mode == ForceMode::Implicit {
            let mut ksl = format!("{n}\n");
            for r in &at_row {
                ksl.push_str(&format!("{:e}\n", r.map_or(0.0, |k| self.fields.ksl[k])));
            }
            files.push(("Ksl", ksl));
            files.push(("uf", vec_rows(&|k| self.fields.uf[k])));
            for name in &ZERO_VECTORS_IMPLICIT[1..] {
                files.push((name, zero.clone()));
            }
        }
        files.push(("dragforce", vec_rows(&|k| self.fields.dragforce[k])));
        for (name, text) in files {
            let tmp = self.path(name, ".tmp");
            std::fs::write(&tmp, text).map_err(|e| LiggghtsError::io(&tmp, e))?;
            let to = self.path(name, "0");
            std::fs::rename(&tmp, &to).map_err(|e| LiggghtsError::io(&to, e))?;
        }
        Ok(())
    }
}

impl Drop for FileDem {
    fn drop(&mut self) {
        self.kill();
    }
}

/// Timestep and particles of the last snapshot of a dump.
fn dem_io_snapshot(path: &Path) -> Result<(u64, dem_io::Particles), LiggghtsError> {
    let snap = dem_io::read_snapshot(
        path,
        &dem_io::ReadOptions::default(),
        dem_io::Selection::Last,
    )
    .map_err(|e| LiggghtsError::Parameter(e.to_string()))?;
    let p = snap
        .particles()
        .map_err(|e| LiggghtsError::Parameter(e.to_string()))?;
    Ok((snap.timestep, p))
}

/// The rows of an exchange file: a count, then rows of `N` numbers.
fn read_rows<const N: usize>(path: &Path) -> Result<Vec<[f64; N]>, LiggghtsError> {
    let text = std::fs::read_to_string(path).map_err(|e| LiggghtsError::io(path, e))?;
    let bad = |line: usize, message: String| LiggghtsError::Exchange {
        file: path.to_path_buf(),
        line,
        message,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.starts_with('#'));
    let (l0, head) = lines.next().ok_or_else(|| bad(1, "empty file".into()))?;
    let n: usize = head
        .trim()
        .parse()
        .map_err(|_| bad(l0 + 1, format!("`{}` is not a row count", head.trim())))?;
    let mut rows = Vec::with_capacity(n.min(text.len()));
    for (k, line) in lines.take(n) {
        let mut row = [0.0; N];
        let mut words = line.split_whitespace();
        for c in row.iter_mut() {
            *c = words
                .next()
                .and_then(|w| w.parse().ok())
                .ok_or_else(|| bad(k + 1, format!("expected {N} numbers in `{line}`")))?;
        }
        rows.push(row);
    }
    if rows.len() != n {
        return Err(bad(
            l0 + 1,
            format!("{n} rows announced, {} present", rows.len()),
        ));
    }
    Ok(rows)
}

impl ParticleSide for FileDem {
    fn advance(&mut self, steps: u64) -> Result<(), SideError> {
        if !steps.is_multiple_of(self.every) {
            return Err(Box::new(LiggghtsError::Parameter(format!(
                "file coupling advances in whole exchanges: {steps} steps is not a multiple of \
                 couple_every {}",
                self.every
            ))));
        }
        if self.steps + steps > self.options.total_steps {
            return Err(Box::new(LiggghtsError::Parameter(format!(
                "{} steps done + {steps} exceed total_steps {}",
                self.steps, self.options.total_steps
            ))));
        }
        for k in 0..steps / self.every {
            if k > 0 {
                // an exchange inside the interval: the same forces again
                self.send()?;
            }
            self.receive()?;
        }
        Ok(())
    }

    fn time_step(&self) -> f64 {
        self.dt
    }

    fn time(&self) -> f64 {
        (self.start_step + self.steps) as f64 * self.dt
    }

    fn state(&self) -> ParticleState<'_> {
        self.particles.view()
    }

    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError> {
        let p = &self.particles;
        force_fields(
            self.mode,
            &p.ids,
            &p.velocity,
            f_ext,
            beta,
            u_f,
            &mut self.fields,
        )?;
        self.field_ids.clone_from(&p.ids);
        self.forces_set = true;
        if self.exchanges > 0 {
            self.send()?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exchange_files_parse_with_named_errors() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("x1");
        std::fs::write(&f, "2\n0.1 0.2 0.3 \n1e-3 -0 5\n").unwrap();
        assert_eq!(
            read_rows::<3>(&f).unwrap(),
            [[0.1, 0.2, 0.3], [1e-3, 0.0, 5.0]]
        );
        std::fs::write(&f, "3\n0.1 0.2 0.3\n1 2\n").unwrap();
        let e = read_rows::<3>(&f).unwrap_err().to_string();
        assert!(
            e.contains("x1:3:") && e.contains("expected 3 numbers"),
            "{e}"
        );
        std::fs::write(&f, "3\n1 2 3\n").unwrap();
        let e = read_rows::<3>(&f).unwrap_err().to_string();
        assert!(
            e.contains("x1:1:") && e.contains("3 rows announced, 1 present"),
            "{e}"
        );
    }
}
