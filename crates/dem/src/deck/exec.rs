//! Executes a [`Deck`] on a [`Simulation`], command by command, as LIGGGHTS would.
//!
//! Supported (anything else is an error naming file, line and command):
//! - set-up: `atom_style granular`, `atom_modify map array|hash`, `units si|cgs`, `boundary`
//!   (`f`, `m`, `s`, `p`: [`crate::periodic`]), `newton`, `communicate`/`comm_modify`,
//!   `processors`, `region ID block|cylinder … [units box] [side in]`, `create_box N REGION`,
//!   `read_data FILE`, `read_restart FILE` (LIGGGHTS 3.8 restart files, `*` = the latest step;
//!   [`restart`](super::restart)), `create_atoms T single x y z [units box]`, `set group all diameter D
//!   density ρ`, `velocity all set vx vy vz`, `neighbor SKIN bin`, `neigh_modify`
//!   (`delay every check one page contact_distance_factor`), `soft_particles yes`,
//!   `hard_particles yes`, `timestep DT`, `delete_atoms region R [compress yes|no]`;
//! - contacts: `pair_style gran model hertz tangential history [cohesion sjkr]
//!   [rolling_friction cdt|epsd2] [tangential_damping on|off] [limitForce on|off]`,
//!   `pair_coeff * *`;
//! - fixes (group `all`): `property/global`, `gravity G vector x y z`, `wall/gran model … primitive
//!   type T xplane|yplane|zplane P | xcylinder|ycylinder|zcylinder R C1 C2` or `… mesh n_meshes N
//!   meshes ID…` ([`crate::mesh_wall`]), `mesh/surface[/stress] file F.stl type T …`
//!   ([`mesh_surface`](super::mesh_surface)),
//!   `particletemplate/sphere`, `particledistribution/discrete[/numberbased]`, `insert/pack`
//!   (`insert_every once`), `insert/rate/region` and `insert/stream` ([`crate::insert_rate`],
//!   [`crate::insert_stream`]; arguments of all in
//!   [`insertion`](super::insertion)), `nve/sphere`, `check/timestep/gran`, `couple/cfd`,
//!   `couple/cfd/force`, `couple/cfd/force/implicit` (recorded: the deck is coupled; their
//!   vector `f_ID[1..3]` is the total coupling force), `print` ([`print`](super::print));
//!   `unfix` of gravity, prints, walls and pending insertions;
//! - output: `dump ID all custom|custom/vtk N FILE cols…` (`dump ID all stl …` warns and
//!   writes nothing) (columns of [`crate::atom_value`]),
//!   `dump_modify ID sort id|label L|format …`, `undump`, `write_data FILE`, `write_restart
//!   FILE` (`*` = the step; directories are made); `thermo`, `thermo_style`, `thermo_modify`
//!   ([`thermo`](super::thermo): LIGGGHTS-style thermo lines, reported as
//!   [`DeckEvent::Output`]; `lost error|warn|ignore` as [`crate::outflow`] says); `compute` (`erotate/sphere`, `com`, `reduce`; other styles are
//!   accepted, [`values`](super::values)), `uncompute`; `print TEXT` (its variables evaluated
//!   when it runs); `log FILE|none [append yes]` ([`DeckEvent::Log`]); `compute_modify` and
//!   `echo` are accepted and have no effect;
//! - `run N [upto] [pre yes|no] [post yes|no]`, reported as [`DeckEvent`]s: the run's span,
//!   progress, thermo rows and LIGGGHTS's `Loop time of …` line.
//!
//! Relative file names are resolved against the working directory given to
//! [`Simulation::from_deck`] (LIGGGHTS resolves them against its current directory).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use dem_io::Boundary;
use mesh::v3::V3;

use crate::contact::{ContactModel, RollingModel};
use crate::deck::data_file;
use crate::deck::insertion;
use crate::deck::mesh_surface;
use crate::deck::print::FixPrint;
use crate::deck::restart;
use crate::deck::thermo::{RunColumns, Thermo};
use crate::deck::values::{Registry, Values};
use crate::dump::DumpOutput;
use crate::error::DemError;
use crate::insert::{Distribution, InsertPack, SphereTemplate};
use crate::insert_rate::InsertRate;
use crate::material::{MaterialInput, Materials};
use crate::mesh_wall::{MeshSurface, MeshWall};
use crate::particles::NewParticle;
use crate::region::Region;
use crate::sim::{SimBox, SimConfig, Simulation};
use crate::walls::{Wall, WallShape};
use closures::timestep::{
    hertz_contact_time_with, rayleigh_time_step, HERTZ_DURATION_CONSTANT_ROUNDED,
};
use liggghts_deck::{Command, Deck, Variables};

type Res<T> = Result<T, String>;

/// Set-up collected before the simulation exists (it is created at the first `run`,
/// `write_data` or at the end of the deck).
#[derive(Default)]
struct Pending {
    boundary: Option<[[Boundary; 2]; 3]>,
    sim_box: Option<(SimBox, usize)>,
    particles: Vec<NewParticle>,
    skin: Option<f64>,
    props: HashMap<String, Vec<f64>>,
    prop_style: HashMap<String, String>,
    pair_model: Option<ContactModel>,
    pair_coeff: bool,
    dt: Option<f64>,
    gravity: Option<(String, V3)>,
    walls: Vec<Wall>,
    mesh_walls: Vec<MeshWall>,
    inserts: Vec<InsertPack>,
    rate_inserts: Vec<InsertRate>,
    dumps: Vec<DumpOutput>,
    soft: bool,
    hard: bool,
    /// `units cgs` (default si).
    cgs: bool,
    /// What `read_restart` read beyond box and particles, applied when the simulation is built.
    restart: Option<restart::Loaded>,
    /// Ids of `dump … stl` outputs (they write `fix mesh/surface` meshes; accepted with a
    /// warning, writing nothing), so that `undump` finds them.
    stl_dumps: Vec<String>,
}

/// What executing a deck reports as it goes, for a front end (`foamgrain dem` prints the
/// output lines and draws a progress bar from the rest).
#[derive(Debug, Clone, PartialEq)]
pub enum DeckEvent {
    /// A `run` command (deck line `line`) starts at step `from` and will end at step `to`,
    /// with time step `dt` (s).
    RunStart {
        /// 1-based deck line of the `run` command.
        line: usize,
        /// The step the run starts from.
        from: u64,
        /// The step it ends at.
        to: u64,
        /// The time step (s).
        dt: f64,
    },
    /// The run reached `step` (simulated time `time`, s).
    Progress {
        /// The current step.
        step: u64,
        /// The simulated time (s).
        time: f64,
    },
    /// A line of LIGGGHTS-style screen output: a thermo header or row, or the loop time.
    Output(String),
    /// `log FILE [append yes]` (`path` resolved against the working directory) or `log none`
    /// (`path` `None`): the front end sends the output lines there from now on.
    Log {
        /// The new log file, or none.
        path: Option<PathBuf>,
        /// Append to it instead of truncating it.
        append: bool,
    },
    /// Something accepted that does not act as the deck may expect (deck line `line`).
    Warning {
        /// 1-based deck line.
        line: usize,
        /// What.
        message: String,
    },
}

/// How many progress reports a run gives at most (each costs one `Simulation::run` call).
const PROGRESS_REPORTS: u64 = 200;

/// A deck being executed, and the simulation it made: what LIGGGHTS's instance is to CFDEM.
/// [`Session::execute`] runs a deck's commands; afterwards [`Session::advance`] continues the
/// runs (a coupled run's DEM intervals, with the deck's thermo output, `fix print`s and dumps)
/// and [`Session::command_text`] runs more commands (CFDEM's `liggghtsCommands`).
pub struct Session<'a> {
    workdir: PathBuf,
    observer: Box<dyn FnMut(DeckEvent) + 'a>,
    thermo: Thermo,
    registry: Registry,
    /// The variables as of the command being executed.
    vars: Variables,
    prints: Vec<FixPrint>,
    regions: HashMap<String, Region>,
    /// `fix mesh/surface` surfaces by fix id.
    surfaces: HashMap<String, std::sync::Arc<MeshSurface>>,
    templates: HashMap<String, SphereTemplate>,
    dists: HashMap<String, Distribution>,
    pending: Pending,
    sim: Option<Simulation>,
    nve: bool,
    checks: Vec<(f64, f64)>,
    gravity_fix: Option<String>,
    /// Deck line of the command being executed (for warnings raised while building).
    line: usize,
    /// Warnings of building the simulation, reported with the command that caused it.
    build_warnings: Vec<String>,
    /// The thermo columns of [`Session::advance`], set at its first call.
    continuation: Option<(RunColumns, std::time::Instant)>,
}

impl Simulation {
    /// Executes every command of `deck` (including its `run`s) with relative paths resolved
    /// against `workdir`, and returns the simulation ready for more [`Simulation::run`] calls.
    pub fn from_deck(deck: &Deck, workdir: &Path) -> Result<Simulation, DemError> {
        Simulation::from_deck_observed(deck, workdir, &mut |_| {})
    }

    /// [`Simulation::from_deck`], reporting runs, progress, thermo output and warnings to
    /// `observer` as they happen. The physics does not depend on the observer.
    pub fn from_deck_observed(
        deck: &Deck,
        workdir: &Path,
        observer: &mut dyn FnMut(DeckEvent),
    ) -> Result<Simulation, DemError> {
        let mut session = Session::new(workdir, observer);
        session.execute(deck)?;
        session.into_simulation()
    }
}

impl<'a> Session<'a> {
    /// A session whose relative file names resolve against `workdir`, reporting to `observer`.
    pub fn new(workdir: &Path, observer: impl FnMut(DeckEvent) + 'a) -> Session<'a> {
        Session {
            workdir: workdir.to_path_buf(),
            observer: Box::new(observer),
            thermo: Thermo::default(),
            registry: Registry::default(),
            vars: Variables::default(),
            prints: Vec::new(),
            regions: HashMap::new(),
            surfaces: HashMap::new(),
            templates: HashMap::new(),
            dists: HashMap::new(),
            pending: Pending::default(),
            sim: None,
            nve: false,
            checks: Vec::new(),
            gravity_fix: None,
            line: 0,
            build_warnings: Vec::new(),
            continuation: None,
        }
    }

    /// Executes every command of `deck` in order (errors name the deck line).
    pub fn execute(&mut self, deck: &Deck) -> Result<(), DemError> {
        for c in &deck.commands {
            self.vars = deck.variables_at(c.line);
            self.execute_one(deck, c)?;
        }
        self.vars = deck.variables_at(usize::MAX);
        Ok(())
    }

    /// Executes `text` (one or more deck lines, e.g. a `liggghtsCommands` entry) with the
    /// variables the session has; `file` names it in errors.
    pub fn command_text(&mut self, text: &str, file: &Path) -> Result<(), DemError> {
        let deck =
            Deck::parse_with(text, file, &self.vars).map_err(|e| DemError::Setup(e.to_string()))?;
        self.execute(&deck)
    }

    fn execute_one(&mut self, deck: &Deck, c: &Command) -> Result<(), DemError> {
        let err = |message: String| DemError::Deck {
            at: deck.location(c),
            message,
        };
        self.command(c).map_err(|e| match e {
            Failure::Msg(m) => err(m),
            Failure::Dem(d) => match d {
                DemError::Deck { .. } => d,
                other => err(other.to_string()),
            },
        })
    }

    /// The simulation, built from the set-up if no command needed it yet.
    pub fn simulation(&mut self) -> Result<&mut Simulation, DemError> {
        self.sim_mut().map_err(|e| match e {
            Failure::Msg(m) => DemError::Setup(m),
            Failure::Dem(d) => d,
        })
    }

    /// The simulation if it exists.
    pub fn sim(&self) -> Option<&Simulation> {
        self.sim.as_ref()
    }

    /// Ends the session, returning the simulation (built now if no command needed it).
    pub fn into_simulation(mut self) -> Result<Simulation, DemError> {
        match self.sim.take() {
            Some(s) => Ok(s),
            None => {
                let s = self.build().map_err(|e| match e {
                    Failure::Msg(m) => DemError::Setup(m),
                    Failure::Dem(d) => d,
                })?;
                let warnings = std::mem::take(&mut self.build_warnings);
                self.warn(self.line, warnings);
                Ok(s)
            }
        }
    }

    /// Continues the runs by `steps` steps, as CFDEM's `run N` between two exchanges: thermo
    /// rows at the `thermo` interval (the header once, at the first call), `fix print`s and
    /// dumps when due. The state does not depend on how the steps are split into calls.
    pub fn advance(&mut self, steps: u64) -> Result<(), DemError> {
        let fail = |e: Failure| match e {
            Failure::Msg(m) => DemError::Setup(m),
            Failure::Dem(d) => d,
        };
        if self.continuation.is_none() {
            let (columns, warnings) = self
                .thermo
                .for_run(&self.registry, &self.vars)
                .map_err(DemError::Setup)?;
            self.warn(self.line, warnings);
            self.sim_mut().map_err(fail)?.run(0)?;
            let header = columns.header();
            (self.observer)(DeckEvent::Output(header));
            let started = std::time::Instant::now();
            let first = self.row(&columns, 0.0).map_err(DemError::Setup)?;
            (self.observer)(DeckEvent::Output(first));
            self.continuation = Some((columns, started));
        }
        let (columns, started) = self.continuation.take().expect("set above");
        let from = self.sim_mut().map_err(fail)?.step();
        let result = self.steps(from, from + steps, &columns, started, false);
        self.continuation = Some((columns, started));
        result.map_err(fail)
    }
}

enum Failure {
    Msg(String),
    Dem(DemError),
}

impl From<String> for Failure {
    fn from(s: String) -> Self {
        Failure::Msg(s)
    }
}

impl From<&str> for Failure {
    fn from(s: &str) -> Self {
        Failure::Msg(s.to_string())
    }
}

impl From<DemError> for Failure {
    fn from(e: DemError) -> Self {
        Failure::Dem(e)
    }
}

fn num(w: &[String], k: usize, what: &str) -> Res<f64> {
    let s = w
        .get(k)
        .ok_or_else(|| format!("missing {what} (argument {k})"))?;
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("{what}: `{s}` is not a number"))
}

fn int(w: &[String], k: usize, what: &str) -> Res<u64> {
    let v = num(w, k, what)?;
    if v < 0.0 || v.fract() != 0.0 {
        return Err(format!("{what}: `{}` is not a non-negative integer", w[k]));
    }
    Ok(v as u64)
}

fn word<'w>(w: &'w [String], k: usize, what: &str) -> Res<&'w str> {
    w.get(k)
        .map(String::as_str)
        .ok_or_else(|| format!("missing {what}"))
}

fn yes_no(w: &[String], k: usize, what: &str) -> Res<bool> {
    match word(w, k, what)? {
        "yes" | "on" => Ok(true),
        "no" | "off" => Ok(false),
        o => Err(format!("{what}: `{o}` (yes/no expected)")),
    }
}

/// Parses `model hertz tangential history [cohesion sjkr] [rolling_friction cdt|epsd2]
/// [surface default] [tangential_damping on|off] [limitForce on|off]` from `w[k..]`; returns
/// the model and the index after it.
fn contact_model(w: &[String], mut k: usize) -> Res<(ContactModel, usize)> {
    let mut m = ContactModel::default();
    let mut normal = false;
    let mut tangential = false;
    while k < w.len() {
        let arg = || word(w, k + 1, &format!("value after `{}`", w[k]));
        match w[k].as_str() {
            "model" => {
                match arg()? {
                    "hertz" => normal = true,
                    o => return Err(format!("normal model `{o}` is not supported (hertz)")),
                }
                k += 2;
            }
            "tangential" => {
                match arg()? {
                    "history" => tangential = true,
                    o => return Err(format!("tangential model `{o}` is not supported (history)")),
                }
                k += 2;
            }
            "cohesion" => {
                match arg()? {
                    "sjkr" => m.cohesion = true,
                    "off" => {}
                    o => return Err(format!("cohesion model `{o}` is not supported (sjkr)")),
                }
                k += 2;
            }
            "rolling_friction" => {
                m.rolling = match arg()? {
                    "cdt" => Some(RollingModel::Cdt),
                    "epsd2" => Some(RollingModel::Epsd2),
                    "off" => None,
                    o => {
                        return Err(format!(
                            "rolling friction model `{o}` is not supported (cdt, epsd2)"
                        ))
                    }
                };
                k += 2;
            }
            "surface" => {
                if arg()? != "default" {
                    return Err(format!("surface model `{}` is not supported", w[k + 1]));
                }
                k += 2;
            }
            "tangential_damping" => {
                m.no_tangential_damping = !yes_no(w, k + 1, "tangential_damping")?;
                k += 2;
            }
            "limitForce" => {
                m.limit_force = yes_no(w, k + 1, "limitForce")?;
                k += 2;
            }
            _ => break,
        }
    }
    if !normal || !tangential {
        return Err("`model hertz tangential history` is required".into());
    }
    Ok((m, k))
}

fn region(w: &[String]) -> Res<(String, Region)> {
    let id = word(w, 1, "region id")?.to_string();
    let style = word(w, 2, "region style")?;
    let (reg, mut k) = match style {
        "block" => {
            let v: Vec<f64> = (3..9)
                .map(|k| num(w, k, "block bound"))
                .collect::<Res<_>>()?;
            if v[0] >= v[1] || v[2] >= v[3] || v[4] >= v[5] {
                return Err("block bounds must satisfy lo < hi".into());
            }
            (
                Region::Block {
                    lo: V3::new(v[0], v[2], v[4]),
                    hi: V3::new(v[1], v[3], v[5]),
                },
                9,
            )
        }
        "cylinder" => {
            let axis = match word(w, 3, "cylinder axis")? {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                o => return Err(format!("cylinder axis `{o}` (x, y or z)")),
            };
            let c1 = num(w, 4, "c1")?;
            let c2 = num(w, 5, "c2")?;
            let radius = num(w, 6, "radius")?;
            let lo = num(w, 7, "lo")?;
            let hi = num(w, 8, "hi")?;
            if radius <= 0.0 || lo >= hi {
                return Err("cylinder needs radius > 0 and lo < hi".into());
            }
            (
                Region::Cylinder {
                    axis,
                    centre: [c1, c2],
                    radius,
                    lo,
                    hi,
                },
                9,
            )
        }
        o => {
            return Err(format!(
                "region style `{o}` is not supported (block, cylinder)"
            ))
        }
    };
    while k < w.len() {
        match (w[k].as_str(), w.get(k + 1).map(String::as_str)) {
            ("units", Some("box")) | ("side", Some("in")) => k += 2,
            ("units", Some(u)) => {
                return Err(format!("region units `{u}` is not supported (units box)"))
            }
            (o, v) => {
                return Err(format!(
                    "region keyword `{o} {}` is not supported",
                    v.unwrap_or("")
                ))
            }
        }
    }
    Ok((id, reg))
}

impl Session<'_> {
    fn path(&self, p: &str) -> PathBuf {
        self.workdir.join(p)
    }

    fn ntypes(&self) -> Res<usize> {
        if let Some(s) = &self.sim {
            return Ok(s.materials().ntypes());
        }
        self.pending
            .sim_box
            .as_ref()
            .map(|b| b.1)
            .ok_or_else(|| "needs the box first (create_box or read_data)".into())
    }

    fn before_run(&self, what: &str) -> Res<()> {
        if self.sim.is_some() {
            return Err(format!(
                "{what} cannot be changed after the first run (restart the deck)"
            ));
        }
        Ok(())
    }

    fn command(&mut self, c: &Command) -> Result<(), Failure> {
        let w = &c.words;
        self.line = c.line;
        match w[0].as_str() {
            "atom_style" => {
                if word(w, 1, "style")? != "granular" || w.len() > 2 {
                    return Err("only `atom_style granular` is supported".into());
                }
            }
            "atom_modify" => {
                // `map array|hash` (particles by tag: always so here) and `sort N binsize`
                // (LIGGGHTS's memory reordering; the native DEM's neighbour lists sort anyway)
                let mut k = 1;
                while k < w.len() {
                    match (w[k].as_str(), w.get(k + 1).map(String::as_str)) {
                        ("map", Some("array" | "hash")) => k += 2,
                        ("sort", Some(_)) if w.len() > k + 2 => {
                            int(w, k + 1, "sort interval")?;
                            num(w, k + 2, "sort bin size")?;
                            k += 3
                        }
                        _ => {
                            return Err("only `atom_modify map array|hash [sort N BINSIZE]` is \
                                        supported"
                                .into())
                        }
                    }
                }
            }
            "units" => {
                // granular physics is the same in any consistent unit system: cgs (cm, g, s,
                // dyn) only moves LIGGGHTS's bounds on Young's modulus
                self.pending.cgs = match word(w, 1, "units")? {
                    "si" => false,
                    "cgs" => true,
                    other => {
                        return Err(format!("`units {other}` is not supported (si, cgs)").into())
                    }
                };
            }
            "newton" | "communicate" | "comm_modify" | "processors" | "echo" | "compute_modify" => {
            }
            "log" => {
                let file = word(w, 1, "log file")?;
                let append = match (w.get(2).map(String::as_str), w.get(3).map(String::as_str)) {
                    (None, _) => false,
                    (Some("append"), Some("yes")) => true,
                    (Some("append"), Some("no")) => false,
                    _ => return Err("usage: log FILE|none [append yes|no]".into()),
                };
                let path = (file != "none").then(|| self.path(file));
                (self.observer)(DeckEvent::Log { path, append });
            }
            "print" => {
                // quoted text keeps its variables until now, as LIGGGHTS's `print` does
                let text = w[1..].join(" ");
                let line = match &self.sim {
                    Some(sim) => Values {
                        sim,
                        registry: &self.registry,
                        vars: &self.vars,
                        cpu: 0.0,
                        norm: self.thermo.norm(),
                    }
                    .substitute(&text)?,
                    None => self.vars.substitute(&text, &|r| {
                        Err(format!("`{r}` is known only once the simulation exists"))
                    })?,
                };
                (self.observer)(DeckEvent::Output(line));
            }
            "thermo" => self.thermo.set_every(w)?,
            "thermo_log" => self.warn(
                c.line,
                vec![format!(
                    "thermo_log {}: the thermo lines go to the screen and log.liggghts only",
                    w.get(1).map_or("", String::as_str)
                )],
            ),
            "thermo_style" => {
                let warnings = self.thermo.set_style(w)?;
                self.warn(c.line, warnings);
            }
            "thermo_modify" => {
                let warnings = self.thermo.modify(w)?;
                self.warn(c.line, warnings);
                if let Some(s) = &mut self.sim {
                    s.set_lost_policy(self.thermo.lost());
                }
            }
            "delete_atoms" => self.delete_atoms(w)?,
            "compute" => self.registry.define_compute(w)?,
            "uncompute" => self.registry.remove_compute(word(w, 1, "compute id")?)?,
            "boundary" => {
                self.before_run("boundary")?;
                if self.pending.sim_box.is_some() {
                    return Err("boundary after the box is defined".into());
                }
                let mut b = [[Boundary::Fixed; 2]; 3];
                for k in 0..3 {
                    let s = word(w, k + 1, "boundary")?.as_bytes();
                    let (lo, hi) = match s.len() {
                        1 => (s[0], s[0]),
                        2 => (s[0], s[1]),
                        _ => return Err(format!("bad boundary `{}`", w[k + 1]).into()),
                    };
                    for (f, ch) in [(0, lo), (1, hi)] {
                        b[k][f] = match Boundary::from_letter(ch) {
                            Some(x) => x,
                            None => return Err(format!("bad boundary `{}`", w[k + 1]).into()),
                        };
                    }
                }
                for (k, [lo, hi]) in b.iter().enumerate() {
                    if (*lo == Boundary::Periodic) != (*hi == Boundary::Periodic) {
                        return Err(format!(
                            "boundary `{}`: both faces of an axis must be periodic or neither",
                            w[k + 1]
                        )
                        .into());
                    }
                }
                self.pending.boundary = Some(b);
            }
            "region" => {
                let (id, r) = region(w)?;
                self.regions.insert(id, r);
            }
            "create_box" => {
                self.before_run("the box")?;
                if self.pending.sim_box.is_some() {
                    return Err("create_box after the box is defined".into());
                }
                let n = int(w, 1, "number of atom types")? as usize;
                if n == 0 {
                    return Err("create_box needs at least one atom type".into());
                }
                let r = self.region_ref(word(w, 2, "region id")?)?;
                let (lo, hi) = r.bounds();
                let boundary = self.boundary()?;
                self.pending.sim_box = Some((SimBox { lo, hi, boundary }, n));
            }
            "read_data" => {
                self.before_run("read_data")?;
                if self.pending.sim_box.is_some() {
                    return Err("read_data after the box is defined".into());
                }
                if w.len() != 2 {
                    return Err("only `read_data FILE` (no keywords) is supported".into());
                }
                let d = data_file::read_data(&self.path(&w[1]))?;
                let boundary = self.boundary()?;
                self.pending.sim_box = Some((
                    SimBox {
                        lo: d.lo,
                        hi: d.hi,
                        boundary,
                    },
                    d.ntypes,
                ));
                self.pending.particles.extend(d.particles);
            }
            "read_restart" => self.read_restart(c)?,
            "write_restart" => {
                if w.len() != 2 {
                    return Err("only `write_restart FILE` is supported (no region)".into());
                }
                let workdir = self.workdir.clone();
                let s = self.sim_mut()?;
                let (_, warnings) = restart::write(s, &w[1], &workdir)?;
                self.warn(c.line, warnings);
            }
            "create_atoms" => self.create_atoms(w)?,
            "set" => self.set(w)?,
            "velocity" => self.velocity(w)?,
            "neighbor" => {
                self.before_run("neighbor")?;
                if word(w, 2, "style")? != "bin" {
                    return Err("only `neighbor SKIN bin` is supported".into());
                }
                let s = num(w, 1, "skin")?;
                if s < 0.0 {
                    return Err("skin must be ≥ 0".into());
                }
                self.pending.skin = Some(s);
            }
            "neigh_modify" => {
                let mut k = 1;
                while k < w.len() {
                    match w[k].as_str() {
                        // `binsize` sets LIGGGHTS's bins; the native DEM sizes its linked
                        // cells from the largest contact distance
                        "delay"
                        | "every"
                        | "one"
                        | "page"
                        | "contact_distance_factor"
                        | "binsize" => k += 2,
                        "check" => {
                            yes_no(w, k + 1, "check")?;
                            k += 2
                        }
                        o => return Err(format!("neigh_modify `{o}` is not supported").into()),
                    }
                }
            }
            "soft_particles" => self.pending.soft = yes_no(w, 1, "soft_particles")?,
            "hard_particles" => self.pending.hard = yes_no(w, 1, "hard_particles")?,
            "timestep" => {
                let dt = num(w, 1, "time step")?;
                match &mut self.sim {
                    Some(s) => s.set_dt(dt)?,
                    None if dt > 0.0 => self.pending.dt = Some(dt),
                    None => return Err("time step must be > 0".into()),
                }
            }
            "pair_style" => {
                self.before_run("pair_style")?;
                if word(w, 1, "style")? != "gran" {
                    return Err("only `pair_style gran …` is supported".into());
                }
                let (m, k) = contact_model(w, 2)?;
                if k != w.len() {
                    return Err(format!("unexpected `{}` in pair_style", w[k]).into());
                }
                self.pending.pair_model = Some(m);
            }
            "pair_coeff" => {
                if w.len() != 3 || w[1] != "*" || w[2] != "*" {
                    return Err("only `pair_coeff * *` is supported".into());
                }
                self.pending.pair_coeff = true;
            }
            "fix" => self.fix(w)?,
            "unfix" => self.unfix(word(w, 1, "fix id")?)?,
            "dump" => self.dump(w)?,
            "dump_modify" => self.dump_modify(w)?,
            "undump" => {
                let id = word(w, 1, "dump id")?;
                let stl = self.pending.stl_dumps.iter().position(|d| d == id);
                let found = match &mut self.sim {
                    _ if stl.is_some() => {
                        self.pending.stl_dumps.retain(|d| d != id);
                        true
                    }
                    Some(s) => s.remove_dump(id),
                    None => {
                        let n = self.pending.dumps.len();
                        self.pending.dumps.retain(|d| d.name != id);
                        n != self.pending.dumps.len()
                    }
                };
                if !found {
                    return Err(format!("no dump `{id}`").into());
                }
            }
            "run" => self.run(c)?,
            "write_data" => {
                if w.len() != 2 {
                    return Err("only `write_data FILE` is supported".into());
                }
                let path = self.path(&w[1]);
                let s = self.sim_mut()?;
                let b = *s.sim_box();
                let bounds = b.dump_bounds(&s.particles.x);
                data_file::write_data(
                    &path,
                    &s.particles,
                    s.materials().ntypes(),
                    bounds.lo.into(),
                    bounds.hi.into(),
                    s.step(),
                )
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            }
            other => {
                return Err(format!("command `{other}` is not supported by the native DEM").into())
            }
        }
        Ok(())
    }

    fn boundary(&self) -> Res<[[Boundary; 2]; 3]> {
        self.pending
            .boundary
            .ok_or_else(|| "no `boundary` given (LIGGGHTS's default is `p p p`: state it)".into())
    }

    /// The distributions, regions and mesh surfaces defined so far.
    fn known(&self) -> insertion::Known<'_> {
        insertion::Known {
            dists: &self.dists,
            regions: &self.regions,
            surfaces: &self.surfaces,
        }
    }

    fn region_ref(&self, id: &str) -> Res<Region> {
        self.regions
            .get(id)
            .copied()
            .ok_or_else(|| format!("no region `{id}`"))
    }

    fn sim_mut(&mut self) -> Result<&mut Simulation, Failure> {
        if self.sim.is_none() {
            self.sim = Some(self.build()?);
            let warnings = std::mem::take(&mut self.build_warnings);
            self.warn(self.line, warnings);
        }
        Ok(self.sim.as_mut().expect("built above"))
    }

    /// `read_restart FILE`: the box, boundary, types, particles and step of a LIGGGHTS restart
    /// file; its contact histories are applied when the simulation is built.
    fn read_restart(&mut self, c: &Command) -> Result<(), Failure> {
        let w = &c.words;
        if self.sim.is_some() || self.pending.sim_box.is_some() {
            return Err("read_restart after the box is defined".into());
        }
        if w.len() != 2 {
            return Err("only `read_restart FILE` is supported".into());
        }
        let path = restart::input_name(&self.path(&w[1]))?;
        let (mut loaded, mut warnings) = restart::read(&path)?;
        if self
            .pending
            .boundary
            .is_some_and(|b| b != loaded.sim_box.boundary)
        {
            warnings.push(
                "the restart file has other boundary settings than `boundary`: using the \
                 file's (as LIGGGHTS does)"
                    .into(),
            );
        }
        self.pending.boundary = Some(loaded.sim_box.boundary);
        self.pending.sim_box = Some((loaded.sim_box, loaded.ntypes));
        self.pending.particles = std::mem::take(&mut loaded.particles);
        self.pending.restart = Some(loaded);
        self.warn(c.line, warnings);
        Ok(())
    }

    fn create_atoms(&mut self, w: &[String]) -> Result<(), Failure> {
        let t = int(w, 1, "atom type")? as u32;
        if word(w, 2, "style")? != "single" {
            return Err("only `create_atoms T single x y z [units box]` is supported".into());
        }
        let x = V3::new(num(w, 3, "x")?, num(w, 4, "y")?, num(w, 5, "z")?);
        match (
            w.get(6).map(String::as_str),
            w.get(7).map(String::as_str),
            w.len(),
        ) {
            (None, _, 6) | (Some("units"), Some("box"), 8) => {}
            _ => return Err("only `units box` may follow the position".into()),
        }
        // LAMMPS's granular defaults: diameter 1, density 1 (change them with `set`)
        let p = NewParticle {
            id: 0,
            atom_type: t,
            x,
            v: V3::zeros(),
            omega: V3::zeros(),
            radius: 0.5,
            density: 1.0,
        };
        let nt = self.ntypes()?;
        if t == 0 || t as usize > nt {
            return Err(format!("atom type {t} outside 1..={nt}").into());
        }
        match &mut self.sim {
            Some(s) => s.add_particles(&[p])?,
            None => {
                let next = self
                    .pending
                    .particles
                    .iter()
                    .map(|p| p.id)
                    .max()
                    .unwrap_or(0)
                    + 1;
                self.pending.particles.push(NewParticle { id: next, ..p });
            }
        }
        Ok(())
    }

    fn set(&mut self, w: &[String]) -> Result<(), Failure> {
        if word(w, 1, "set style")? != "group" || word(w, 2, "group")? != "all" {
            return Err("only `set group all …` is supported".into());
        }
        let mut radius = None;
        let mut density = None;
        let mut k = 3;
        while k < w.len() {
            match w[k].as_str() {
                "diameter" => radius = Some(0.5 * num(w, k + 1, "diameter")?),
                "density" => density = Some(num(w, k + 1, "density")?),
                o => return Err(format!("set keyword `{o}` is not supported").into()),
            }
            k += 2;
        }
        if radius.is_some_and(|r| r <= 0.0) || density.is_some_and(|d| d <= 0.0) {
            return Err("diameter and density must be > 0".into());
        }
        match &mut self.sim {
            Some(s) => {
                let p = &mut s.particles;
                for i in 0..p.len() {
                    if let Some(r) = radius {
                        p.radius[i] = r;
                    }
                    if let Some(d) = density {
                        p.density[i] = d;
                    }
                    p.mass[i] =
                        4.0 / 3.0 * std::f64::consts::PI * p.radius[i].powi(3) * p.density[i];
                }
                s.invalidate_forces();
            }
            None => {
                for p in &mut self.pending.particles {
                    if let Some(r) = radius {
                        p.radius = r;
                    }
                    if let Some(d) = density {
                        p.density = d;
                    }
                }
            }
        }
        Ok(())
    }

    /// `delete_atoms region R [compress yes|no]`: with `compress yes` (LIGGGHTS's default) the
    /// remaining particles get the ids 1…N in the order of their old ids (LIGGGHTS numbers
    /// them in its storage order, which this order is for a serial run without sorting).
    fn delete_atoms(&mut self, w: &[String]) -> Result<(), Failure> {
        if word(w, 1, "style")? != "region" {
            return Err("only `delete_atoms region ID [compress yes|no]` is supported".into());
        }
        let region = self.region_ref(word(w, 2, "region id")?)?;
        let mut compress = true;
        let mut k = 3;
        while k < w.len() {
            match w[k].as_str() {
                "compress" => compress = yes_no(w, k + 1, "compress")?,
                o => return Err(format!("delete_atoms keyword `{o}` is not supported").into()),
            }
            k += 2;
        }
        let s = self.sim_mut()?;
        s.delete_in_region(&region);
        if compress {
            s.compress_ids();
        }
        Ok(())
    }

    fn velocity(&mut self, w: &[String]) -> Result<(), Failure> {
        if word(w, 1, "group")? != "all" || word(w, 2, "style")? != "set" || w.len() != 6 {
            return Err("only `velocity all set vx vy vz` is supported".into());
        }
        let v = V3::new(num(w, 3, "vx")?, num(w, 4, "vy")?, num(w, 5, "vz")?);
        match &mut self.sim {
            Some(s) => {
                s.particles.v.iter_mut().for_each(|x| *x = v);
                s.invalidate_forces();
            }
            None => self.pending.particles.iter_mut().for_each(|p| p.v = v),
        }
        Ok(())
    }

    fn fix(&mut self, w: &[String]) -> Result<(), Failure> {
        let id = word(w, 1, "fix id")?.to_string();
        if word(w, 2, "group")? != "all" {
            return Err("only the group `all` is supported".into());
        }
        let style = word(w, 3, "fix style")?;
        match style {
            "property/global" => {
                self.before_run("material properties")?;
                let name = word(w, 4, "property name")?.to_string();
                let pstyle = word(w, 5, "property style")?.to_string();
                let vals: Vec<f64> = match pstyle.as_str() {
                    "peratomtype" | "scalar" | "vector" => {
                        (6..w.len()).map(|k| num(w, k, &name)).collect::<Res<_>>()?
                    }
                    "peratomtypepair" => {
                        let n = int(w, 6, "number of types")? as usize;
                        let v: Vec<f64> =
                            (7..w.len()).map(|k| num(w, k, &name)).collect::<Res<_>>()?;
                        if v.len() != n * n {
                            return Err(format!(
                                "{name}: peratomtypepair {n} needs {} values, {} given",
                                n * n,
                                v.len()
                            )
                            .into());
                        }
                        v
                    }
                    o => return Err(format!("property style `{o}` is not supported").into()),
                };
                self.pending.prop_style.insert(name.clone(), pstyle);
                self.pending.props.insert(name, vals);
            }
            "gravity" => {
                let g = num(w, 4, "magnitude")?;
                if word(w, 5, "`vector`")? != "vector" || w.len() != 9 {
                    return Err("only `gravity G vector x y z` is supported".into());
                }
                let d = [num(w, 6, "x")?, num(w, 7, "y")?, num(w, 8, "z")?];
                let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if m == 0.0 {
                    return Err("gravity direction is zero".into());
                }
                let gv = V3::new(g * d[0] / m, g * d[1] / m, g * d[2] / m);
                self.gravity_fix = Some(id.clone());
                match &mut self.sim {
                    Some(s) => s.set_gravity(gv),
                    None => self.pending.gravity = Some((id, gv)),
                }
            }
            "wall/gran" => {
                let (model, mut k) = contact_model(w, 4)?;
                if word(w, k, "`primitive` or `mesh`")? == "mesh" {
                    let wall = self.mesh_wall(&id, model, &w[k + 1..])?;
                    match &mut self.sim {
                        Some(s) => s.add_mesh_wall(wall)?,
                        None => self.pending.mesh_walls.push(wall),
                    }
                    return Ok(());
                }
                if w[k] != "primitive" {
                    return Err(
                        "walls are `primitive type T xplane|…` or `mesh n_meshes N meshes ID…`"
                            .into(),
                    );
                }
                if word(w, k + 1, "`type`")? != "type" {
                    return Err("`primitive` must be followed by `type T`".into());
                }
                let t = int(w, k + 2, "wall material type")? as u32;
                let shape_name = word(w, k + 3, "wall style")?;
                k += 4;
                let shape = match shape_name {
                    "xplane" | "yplane" | "zplane" => {
                        let axis = (shape_name.as_bytes()[0] - b'x') as usize;
                        let position = num(w, k, "plane position")?;
                        k += 1;
                        WallShape::Plane { axis, position }
                    }
                    "xcylinder" | "ycylinder" | "zcylinder" => {
                        let axis = (shape_name.as_bytes()[0] - b'x') as usize;
                        let radius = num(w, k, "cylinder radius")?;
                        let centre = [num(w, k + 1, "centre")?, num(w, k + 2, "centre")?];
                        if radius <= 0.0 {
                            return Err("cylinder radius must be > 0".into());
                        }
                        k += 3;
                        WallShape::Cylinder {
                            axis,
                            radius,
                            centre,
                        }
                    }
                    o => return Err(format!("primitive wall `{o}` is not supported").into()),
                };
                if k != w.len() {
                    return Err(format!("unsupported wall keyword `{}`", w[k]).into());
                }
                let wall = Wall {
                    name: id,
                    shape,
                    material_type: t,
                    model,
                };
                match &mut self.sim {
                    Some(s) => s.add_wall(wall)?,
                    None => self.pending.walls.push(wall),
                }
            }
            "mesh/surface" | "mesh/surface/stress" => {
                let parsed = mesh_surface::parse(w, &self.workdir, self.ntypes()?)?;
                self.warn(self.line, parsed.warnings);
                if parsed.surface.stress {
                    self.registry.add_mesh_stress_fix(&id);
                }
                self.surfaces.insert(id, parsed.surface);
            }
            "particletemplate/sphere" => {
                int(w, 4, "seed")?;
                let mut t = SphereTemplate {
                    name: id.clone(),
                    atom_type: 0,
                    density: 0.0,
                    radius: 0.0,
                };
                let mut k = 5;
                while k < w.len() {
                    let constant = |k: usize, what: &str| -> Res<f64> {
                        if word(w, k + 1, what)? != "constant" {
                            return Err(format!(
                                "{what}: only `constant` values are supported, not `{}`",
                                w[k + 1]
                            ));
                        }
                        num(w, k + 2, what)
                    };
                    match w[k].as_str() {
                        "atom_type" => {
                            t.atom_type = int(w, k + 1, "atom_type")? as u32;
                            k += 2;
                        }
                        "density" => {
                            t.density = constant(k, "density")?;
                            k += 3;
                        }
                        "radius" => {
                            t.radius = constant(k, "radius")?;
                            k += 3;
                        }
                        o => {
                            return Err(
                                format!("particletemplate keyword `{o}` is not supported").into()
                            )
                        }
                    }
                }
                let nt = self.ntypes()?;
                if t.atom_type == 0 || t.atom_type as usize > nt {
                    return Err(format!("atom_type {} outside 1..={nt}", t.atom_type).into());
                }
                if t.density <= 0.0 || t.radius <= 0.0 {
                    return Err("density and radius must be given and > 0".into());
                }
                self.templates.insert(id, t);
            }
            "particledistribution/discrete" | "particledistribution/discrete/numberbased" => {
                int(w, 4, "seed")?;
                let n = int(w, 5, "number of templates")? as usize;
                if n == 0 || w.len() != 6 + 2 * n {
                    return Err(format!("{n} templates need {} arguments", 2 * n).into());
                }
                let mut parts = Vec::new();
                for k in 0..n {
                    let name = &w[6 + 2 * k];
                    let t = self
                        .templates
                        .get(name)
                        .ok_or_else(|| format!("no particletemplate `{name}`"))?;
                    let wt = num(w, 7 + 2 * k, "weight")?;
                    if wt < 0.0 {
                        return Err("weights must be ≥ 0".into());
                    }
                    if parts
                        .iter()
                        .any(|(p, _): &(SphereTemplate, f64)| &p.name == name)
                    {
                        return Err(format!("template `{name}` used twice").into());
                    }
                    parts.push((t.clone(), wt));
                }
                if parts.iter().map(|p| p.1).sum::<f64>() <= 0.0 {
                    return Err("weights sum to 0".into());
                }
                let mass_based = !style.ends_with("numberbased");
                self.dists
                    .insert(id.clone(), Distribution::new(&id, parts, mass_based));
            }
            "insert/pack" => {
                let ins = insertion::insert_pack(&id, w, &self.known())?;
                match &mut self.sim {
                    Some(s) => s.add_insertion(ins),
                    None => self.pending.inserts.push(ins),
                }
            }
            "insert/rate/region" | "insert/stream" => {
                let ins = match style {
                    "insert/stream" => insertion::insert_stream(&id, w, &self.known())?,
                    _ => insertion::insert_rate(&id, w, &self.known())?,
                };
                self.registry.add_insert_fix(&id);
                match &mut self.sim {
                    Some(s) => s.add_rate_insertion(ins)?,
                    None => self.pending.rate_inserts.push(ins),
                }
            }
            "nve/sphere" => {
                if w.len() != 4 {
                    return Err("`nve/sphere` options are not supported".into());
                }
                self.nve = true;
            }
            "check/timestep/gran" => {
                int(w, 4, "check interval")?;
                let fr = num(w, 5, "fraction of the Rayleigh time")?;
                let fh = num(w, 6, "fraction of the Hertz time")?;
                self.checks.push((fr, fh));
            }
            "couple/cfd" => {
                let mut k = 4;
                while k < w.len() {
                    match w[k].as_str() {
                        "couple_every" => {
                            if int(w, k + 1, "couple_every")? == 0 {
                                return Err("couple_every must be ≥ 1".into());
                            }
                            k += 2;
                        }
                        "mpi" => k += 1,
                        "file" => k += 2,
                        o => {
                            return Err(format!("couple/cfd keyword `{o}` is not supported").into())
                        }
                    }
                }
            }
            "couple/cfd/force" | "couple/cfd/force/implicit" => self.registry.add_force_fix(&id),
            "print" => {
                let p = FixPrint::new(w, &self.workdir)?;
                self.prints.retain(|q| q.id != p.id);
                self.prints.push(p);
            }
            other => {
                return Err(
                    format!("fix style `{other}` is not supported by the native DEM").into(),
                )
            }
        }
        Ok(())
    }

    /// The mesh wall of `wall/gran … mesh n_meshes N meshes ID…` (`rest` = the words after
    /// `mesh`).
    fn mesh_wall(&self, id: &str, model: ContactModel, rest: &[String]) -> Res<MeshWall> {
        if word(rest, 0, "`n_meshes`")? != "n_meshes" {
            return Err("expected `mesh n_meshes N meshes ID…`".into());
        }
        let n = int(rest, 1, "n_meshes")? as usize;
        if n == 0 || word(rest, 2, "`meshes`")? != "meshes" {
            return Err("expected `n_meshes N meshes ID…` with N ≥ 1".into());
        }
        if rest.len() != 3 + n {
            return Err(match rest.len() < 3 + n {
                true => format!(
                    "n_meshes {n} but {} mesh ids follow `meshes`",
                    rest.len() - 3
                ),
                false => format!("unsupported wall keyword `{}`", rest[3 + n]),
            });
        }
        let mut surfaces = Vec::with_capacity(n);
        for m in &rest[3..] {
            let s = self.surfaces.get(m).ok_or_else(|| {
                format!("mesh `{m}` is not a `fix mesh/surface` defined before this line")
            })?;
            if surfaces
                .iter()
                .any(|x: &std::sync::Arc<MeshSurface>| x.mesh.name() == m)
            {
                return Err(format!("mesh `{m}` listed twice"));
            }
            surfaces.push(s.clone());
        }
        Ok(MeshWall::new(id, surfaces, model))
    }

    fn unfix(&mut self, id: &str) -> Result<(), Failure> {
        let prints = self.prints.len();
        self.prints.retain(|p| p.id != id);
        if prints != self.prints.len() {
            return Ok(());
        }
        if self.gravity_fix.as_deref() == Some(id) {
            self.gravity_fix = None;
            match &mut self.sim {
                Some(s) => s.set_gravity(V3::zeros()),
                None => self.pending.gravity = None,
            }
            return Ok(());
        }
        let p = &mut self.pending;
        match &mut self.sim {
            Some(s) => {
                if s.remove_insertion(id) {
                    return Ok(());
                }
            }
            None => {
                let n = p.walls.len() + p.mesh_walls.len() + p.inserts.len() + p.rate_inserts.len();
                p.walls.retain(|x| x.name != id);
                p.mesh_walls.retain(|x| x.name != id);
                p.inserts.retain(|x| x.name != id);
                p.rate_inserts.retain(|x| x.name != id);
                if n != p.walls.len() + p.mesh_walls.len() + p.inserts.len() + p.rate_inserts.len()
                {
                    return Ok(());
                }
            }
        }
        Err(format!("unfix `{id}`: only gravity, print, insertions, and walls before the first run, can be removed").into())
    }

    fn dump(&mut self, w: &[String]) -> Result<(), Failure> {
        let id = word(w, 1, "dump id")?;
        let style = word(w, 3, "style")?;
        if style == "stl" {
            self.pending.stl_dumps.push(id.to_string());
            let message = format!("dump {id} stl writes the meshes of `fix mesh/surface`: the native DEM writes nothing");
            self.warn(self.line, vec![message]);
            return Ok(());
        }
        if word(w, 2, "group")? != "all" || !matches!(style, "custom" | "custom/vtk") {
            return Err("only `dump ID all custom|custom/vtk N FILE columns…` is supported".into());
        }
        let every = int(w, 4, "dump interval")?;
        let file = self.path(word(w, 5, "file name")?);
        let d = match style {
            "custom" => DumpOutput::new(id, every, file, w[6..].to_vec())?,
            _ => DumpOutput::new_vtk(id, every, file, w[6..].to_vec())?,
        };
        match &mut self.sim {
            Some(s) => s.add_dump(d),
            None => self.pending.dumps.push(d),
        }
        Ok(())
    }

    fn dump_modify(&mut self, w: &[String]) -> Result<(), Failure> {
        let id = word(w, 1, "dump id")?;
        let d = match &mut self.sim {
            Some(s) => s.dump_mut(id),
            None => self.pending.dumps.iter_mut().find(|d| d.name == id),
        }
        .ok_or_else(|| format!("no dump `{id}`"))?;
        let mut k = 2;
        while k < w.len() {
            match w[k].as_str() {
                "sort" => {
                    match word(w, k + 1, "sort")? {
                        "id" => d.sort_by_id = true,
                        "off" => d.sort_by_id = false,
                        o => return Err(format!("dump_modify sort `{o}` (id or off)").into()),
                    }
                    k += 2;
                }
                // values are always written at full precision; a label is not written
                "format" => k = w.len(),
                "label" => k += 2,
                o => return Err(format!("dump_modify `{o}` is not supported").into()),
            }
        }
        Ok(())
    }

    fn warn(&mut self, line: usize, messages: Vec<String>) {
        for message in messages {
            (self.observer)(DeckEvent::Warning { line, message });
        }
    }

    /// `run N [upto] [pre …] [post …]`: advances in chunks that end at every thermo step and at
    /// most [`PROGRESS_REPORTS`] times per run (the state does not depend on the chunking:
    /// a chunk boundary only re-checks insertions and due dumps).
    fn run(&mut self, c: &Command) -> Result<(), Failure> {
        let w = &c.words;
        let n = int(w, 1, "number of steps")?;
        let mut upto = false;
        let mut k = 2;
        while k < w.len() {
            match w[k].as_str() {
                "upto" => {
                    upto = true;
                    k += 1;
                }
                "pre" | "post" => {
                    yes_no(w, k + 1, &w[k])?;
                    k += 2;
                }
                o => return Err(format!("run keyword `{o}` is not supported").into()),
            }
        }
        let (columns, warnings) = self.thermo.for_run(&self.registry, &self.vars)?;
        self.warn(c.line, warnings);
        let checks = self.checks.clone();
        let s = self.sim_mut()?;
        let steps = if upto {
            n.checked_sub(s.step())
                .ok_or_else(|| format!("run {n} upto: already at step {}", s.step()))?
        } else {
            n
        };
        let (from, to) = (s.step(), s.step() + steps);
        let started = std::time::Instant::now();
        s.run(0)?;
        for (fr, fh) in checks {
            check_timestep(s, fr, fh);
        }
        let dt = s.dt();
        (self.observer)(DeckEvent::RunStart {
            line: c.line,
            from,
            to,
            dt,
        });
        (self.observer)(DeckEvent::Output(columns.header()));
        let first = self.row(&columns, 0.0)?;
        (self.observer)(DeckEvent::Output(first));
        self.steps(from, to, &columns, started, true)?;
        let atoms = self.sim_mut()?.particles.len();
        (self.observer)(DeckEvent::Output(format!(
            "Loop time of {} on 1 procs ({} threads) for {steps} steps with {atoms} atoms",
            liggghts_deck::format::format_g(started.elapsed().as_secs_f64(), 6),
            rayon::current_num_threads()
        )));
        Ok(())
    }

    /// The thermo row now (`cpu`: wall seconds since the run began).
    fn row(&self, columns: &RunColumns, cpu: f64) -> Res<String> {
        let sim = self.sim.as_ref().ok_or("no simulation yet")?;
        columns.row(&Values {
            sim,
            registry: &self.registry,
            vars: &self.vars,
            cpu,
            norm: columns.norm(),
        })
    }

    /// Advances from step `from` to `to` in chunks that end at every thermo step, every `fix
    /// print` step and, with `progress`, at most [`PROGRESS_REPORTS`] times (the state does not
    /// depend on the chunking: a chunk boundary only re-checks insertions and due dumps).
    fn steps(
        &mut self,
        from: u64,
        to: u64,
        columns: &RunColumns,
        started: std::time::Instant,
        progress: bool,
    ) -> Result<(), Failure> {
        let every = self.thermo.every();
        let chunk = if progress {
            ((to - from) / PROGRESS_REPORTS).max(1)
        } else {
            to - from
        };
        let mut step = from;
        while step < to {
            let mut next = (step + chunk).min(to);
            if let Some(k) = step.checked_div(every) {
                next = next.min((k + 1) * every);
            }
            for p in &self.prints {
                next = next.min(p.next_after(step));
            }
            let s = self.sim_mut()?;
            s.run(next - step)?;
            step = next;
            let time = s.time();
            let thermo_due = (progress && step == to) || (every > 0 && step.is_multiple_of(every));
            let mut screen = Vec::new();
            if !self.prints.is_empty() {
                let sim = self.sim.as_ref().expect("built above");
                let values = Values {
                    sim,
                    registry: &self.registry,
                    vars: &self.vars,
                    cpu: started.elapsed().as_secs_f64(),
                    norm: columns.norm(),
                };
                for p in &mut self.prints {
                    screen.extend(p.at_step(step, &values)?);
                }
            }
            let row = if thermo_due {
                Some(self.row(columns, started.elapsed().as_secs_f64())?)
            } else {
                None
            };
            if progress {
                (self.observer)(DeckEvent::Progress { step, time });
            }
            for line in screen.into_iter().chain(row) {
                (self.observer)(DeckEvent::Output(line));
            }
        }
        Ok(())
    }

    /// Creates the simulation from the collected set-up.
    fn build(&mut self) -> Result<Simulation, Failure> {
        let p = &mut self.pending;
        let (sim_box, ntypes) = p
            .sim_box
            .ok_or("no box defined (create_box or read_data)")?;
        let model = match (p.pair_model, p.restart.as_ref().and_then(|r| r.pair)) {
            (Some(m), _) => {
                if !p.pair_coeff {
                    return Err("no `pair_coeff * *`".into());
                }
                m
            }
            (None, Some(g)) => {
                let r = p.restart.as_ref().expect("the pair came from it");
                if !(p.pair_coeff || r.pair_coeff) {
                    return Err("no `pair_coeff * *` (nor in the restart file)".into());
                }
                restart::contact_model(&g)?
            }
            (None, None) => return Err("no `pair_style gran …`".into()),
        };
        if !self.nve {
            return Err("no time integration: `fix ID all nve/sphere` is required".into());
        }
        let prop = |name: &str, style: &str, needed: bool| -> Res<Vec<f64>> {
            match (p.props.get(name), p.prop_style.get(name)) {
                (Some(v), Some(s)) if s == style => {
                    let want = if style == "peratomtype" {
                        ntypes
                    } else {
                        ntypes * ntypes
                    };
                    if v.len() != want {
                        return Err(format!(
                            "property {name} has {} values, {want} needed for {ntypes} atom types",
                            v.len()
                        ));
                    }
                    Ok(v.clone())
                }
                (Some(_), Some(s)) => Err(format!("property {name} must be {style}, not {s}")),
                _ if needed => Err(format!("missing `fix … property/global {name} {style} …`")),
                _ => Ok(Vec::new()),
            }
        };
        let wall_models = || {
            let mesh = p.mesh_walls.iter().map(|w| w.model);
            p.walls.iter().map(|w| w.model).chain(mesh)
        };
        let rolling = model.rolling.is_some() || wall_models().any(|m| m.rolling.is_some());
        let cohesion = model.cohesion || wall_models().any(|m| m.cohesion);
        let input = MaterialInput {
            youngs_modulus: prop("youngsModulus", "peratomtype", true)?,
            poissons_ratio: prop("poissonsRatio", "peratomtype", true)?,
            restitution: prop("coefficientRestitution", "peratomtypepair", true)?,
            friction: prop("coefficientFriction", "peratomtypepair", true)?,
            rolling_friction: prop("coefficientRollingFriction", "peratomtypepair", rolling)?,
            cohesion_energy_density: prop("cohesionEnergyDensity", "peratomtypepair", cohesion)?,
        };
        // LIGGGHTS's sanity bounds on E, in the deck's units (Pa, or dyn/cm² = 0.1 Pa for cgs)
        let (soft, hard, units) = match p.cgs {
            false => (5e6, 1e9, "SI"),
            true => (5e7, 1e10, "CGS"),
        };
        for (t, &e) in input.youngs_modulus.iter().enumerate() {
            if e < soft && !p.soft {
                return Err(format!(
                    "youngsModulus {e} of type {} < {soft:e} (LIGGGHTS's {units} limit; `soft_particles yes` overrides)",
                    t + 1
                )
                .into());
            }
            if e > hard && !p.hard {
                return Err(format!(
                    "youngsModulus {e} of type {} > {hard:e} (LIGGGHTS's {units} limit; `hard_particles yes` overrides)",
                    t + 1
                )
                .into());
            }
        }
        let materials = Materials::new(&input)?;
        let mut sim = Simulation::new(SimConfig {
            materials,
            pair_model: model,
            // LAMMPS's defaults for units si
            dt: p.dt.unwrap_or(1e-8),
            gravity: p.gravity.as_ref().map(|g| g.1).unwrap_or(V3::zeros()),
            skin: p.skin.unwrap_or(0.001),
            sim_box,
        })?;
        for wall in p.walls.drain(..) {
            sim.add_wall(wall)?;
        }
        for wall in p.mesh_walls.drain(..) {
            sim.add_mesh_wall(wall)?;
        }
        sim.add_particles(&p.particles)?;
        if let Some(r) = p.restart.take() {
            let coupled = self.registry.has_force_fix();
            self.build_warnings.extend(r.apply(&mut sim, coupled)?);
        }
        for ins in p.inserts.drain(..) {
            sim.add_insertion(ins);
        }
        for ins in p.rate_inserts.drain(..) {
            sim.add_rate_insertion(ins)?;
        }
        sim.set_lost_policy(self.thermo.lost());
        for d in p.dumps.drain(..) {
            sim.add_dump(d);
        }
        Ok(sim)
    }
}

/// `fix check/timestep/gran`: warns when dt exceeds the given fractions of the smallest
/// Rayleigh time and of the Hertz time (LIGGGHTS's estimate: m* = m, R* = R/2, Y* of the type
/// with itself, v = twice the fastest particle).
fn check_timestep(s: &mut Simulation, frac_r: f64, frac_h: f64) {
    let p = &s.particles;
    let m = s.materials();
    let mut tr = f64::INFINITY;
    let mut th = f64::INFINITY;
    let vmax = p.v.iter().map(|v| (*v).norm()).fold(0.0, f64::max);
    for i in 0..p.len() {
        let t = p.atom_type[i] as usize;
        tr = tr.min(rayleigh_time_step(
            p.radius[i],
            p.density[i],
            m.youngs_modulus[t - 1],
            m.poissons_ratio[t - 1],
        ));
        if vmax > 0.0 {
            let y = m.pair(p.atom_type[i], p.atom_type[i]).y_eff;
            th = th.min(hertz_contact_time_with(
                HERTZ_DURATION_CONSTANT_ROUNDED,
                p.mass[i],
                0.5 * p.radius[i],
                y,
                2.0 * vmax,
            ));
        }
    }
    let dt = s.dt();
    if dt > frac_r * tr {
        // LIGGGHTS's words and digits, so the two logs compare
        let w = format!(
            "check/timestep/gran: time-step is {:.6} % of rayleigh time (dt = {dt} s, \
             Rayleigh time {tr:.6e} s)",
            100.0 * dt / tr
        );
        s.warn(w);
    }
    if dt > frac_h * th {
        let w = format!(
            "check/timestep/gran: time-step is {:.6} % of hertz time (dt = {dt} s, Hertz time \
             {th:.6e} s at twice the fastest speed)",
            100.0 * dt / th
        );
        s.warn(w);
    }
}
