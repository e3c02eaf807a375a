//! Executes a [`Deck`] on a [`Simulation`], command by command, as LIGGGHTS would.
//!
//! Supported (anything else is an error naming file, line and command):
//! - set-up: `atom_style granular`, `atom_modify map array|hash`, `units si|cgs`, `boundary`
//!   (`f`, `m`, `s`, `p`: [`crate::periodic`]), `newton`, `communicate`/`comm_modify`,
//!   `processors`, `region ID block|cylinder … [units box] [side in]`, `create_box N REGION`,
//!   `read_data FILE`, `read_restart FILE` (LIGGGHTS 3.8 restart files, `*` = the latest step;
//!   `restart`), `create_atoms T single x y z [units box]`, `set group all diameter D
//!   density ρ`, `set group all|region R property/atom Temp|heatFlux|convectiveHeatFlux V`
//!   ([`crate::heat`]; block regions may have `INF` bounds), `velocity all set vx vy vz`, `neighbor SKIN bin`, `neigh_modify`
//!   (`delay every check one page contact_distance_factor`), `soft_particles yes`,
//!   `hard_particles yes`, `timestep DT`, `delete_atoms region R [compress yes|no]`;
//! - contacts: `pair_style gran model hertz tangential history [cohesion sjkr]
//!   [rolling_friction cdt|epsd2] [tangential_damping on|off] [limitForce on|off]`,
//!   `pair_coeff * *`;
//! - fixes (group `all`): `property/global`, `gravity G vector x y z`, `wall/gran model … primitive
//!   type T xplane|yplane|zplane P | xcylinder|ycylinder|zcylinder R C1 C2 [temperature T]
//!   [contact_area …]` or `… mesh n_meshes N
//!   meshes ID…` ([`crate::mesh_wall`]), `mesh/surface[/stress] file F.stl type T …`
//!   ([`mesh_surface`](super::mesh_surface)),
//!   `particletemplate/sphere`, `particledistribution/discrete[/numberbased]`, `insert/pack`
//!   (`insert_every once` or `K`), `insert/rate/region` and `insert/stream`
//!   ([`crate::insert_rate`], [`crate::insert_stream`]; arguments of all in
//!   `insertion`), `nve/sphere`, `check/timestep/gran`, `couple/cfd`,
//!   `couple/cfd/force`, `couple/cfd/force/implicit` (recorded: the deck is coupled; their
//!   vector `f_ID[1..3]` is the total coupling force), `heat/gran[/conduction]
//!   initial_temperature T0 [contact_area overlap|projection|constant A] [area_correction
//!   yes|no]` and `couple/cfd/convection T0 T` ([`crate::heat`]; `f_ID` of heat/gran is Σ m c T,
//!   `f_ID[0]` in dumps its temperatures), `print` ([`print`](super::print));
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
//!   progress, thermo rows and LIGGGHTS's `Loop time of …` line; a run of steps needs `fix
//!   nve/sphere`, a `run 0` does not (CFDEM's coupled decks set up with one before defining it).
//!
//! Relative file names are resolved against the working directory given to
//! [`Simulation::from_deck`] (LIGGGHTS resolves them against its current directory).
//!
//! A command is looked up by name in one table (`commands`), a fix style in another
//! (`fixes`), as LIGGGHTS's style registry does: a row names the command or style (and its
//! aliases) and its handler, in a module of its family; this module holds the [`Session`],
//! the dispatch and what the handlers share (building the simulation, running the steps).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use dem_io::Boundary;
use mesh::v3::V3;

use crate::contact::ContactModel;
use crate::deck::insertion;
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
use crate::walls::Wall;
use commands::Action;
use liggghts_deck::{Command, Deck, Variables};

mod args;
mod coarse_graining;
mod commands;
mod fixes;

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
    /// The heat fixes defined before the simulation was built (applied in order when it is).
    heat: Vec<fixes::heat::HeatFix>,
    /// The primitive walls with a temperature (handed to the heat state when it exists).
    wall_heat: Vec<crate::heat::WallHeat>,
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
    /// Temperatures and heat flows (by particle id) of the last `read_restart`, taken up by the
    /// first heat fix (LIGGGHTS's `Temp` and `heatFlux` restart blocks).
    restart_heat: Option<HashMap<u64, (f64, Option<f64>)>>,
    /// `coarsegraining` ([`coarse_graining`]), if given.
    coarse_graining: Option<liggghts_deck::CoarseGraining>,
    /// How many `fix` commands were executed (`coarsegraining` must come before any).
    fixes_defined: usize,
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
            restart_heat: None,
            coarse_graining: None,
            fixes_defined: 0,
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
            self.sim_mut().map_err(fail)?;
            self.drop_restart_heat();
            self.check_wall_heat().map_err(DemError::Setup)?;
            self.sim_mut().map_err(fail)?.run(0)?;
            let header = columns.header();
            (self.observer)(DeckEvent::Output(header));
            let started = std::time::Instant::now();
            let first = self.row(&columns, 0.0).map_err(DemError::Setup)?;
            (self.observer)(DeckEvent::Output(first));
            self.continuation = Some((columns, started));
        }
        if steps > 0 {
            self.require_integration().map_err(DemError::Setup)?;
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

    /// A run of steps needs `fix nve/sphere` (a `run 0` does not: CFDEM's coupled decks set up
    /// with `run 0` before they define it).
    fn require_integration(&self) -> Res<()> {
        match self.nve {
            true => Ok(()),
            false => Err("no time integration: `fix ID all nve/sphere` is required".into()),
        }
    }

    fn before_run(&self, what: &str) -> Res<()> {
        if self.sim.is_some() {
            return Err(format!(
                "{what} cannot be changed after the first run (restart the deck)"
            ));
        }
        Ok(())
    }

    /// Executes one command: the handler of its row in the command table.
    fn command(&mut self, c: &Command) -> Result<(), Failure> {
        self.line = c.line;
        let name = c.words[0].as_str();
        match commands::find(name).map(|row| row.action) {
            Some(Action::Run(handler)) => handler(self, c),
            Some(Action::Ignored) => Ok(()),
            None => Err(format!("command `{name}` is not supported by the native DEM").into()),
        }
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

    fn warn(&mut self, line: usize, messages: Vec<String>) {
        for message in messages {
            (self.observer)(DeckEvent::Warning { line, message });
        }
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
        if let Some(mut r) = p.restart.take() {
            if let Some(h) = r.heat.take() {
                self.restart_heat = Some(h);
            }
            let coupled = self.registry.has_force_fix();
            self.build_warnings.extend(r.apply(&mut sim, coupled)?);
        }
        for h in std::mem::take(&mut p.heat) {
            fixes::heat::apply(&mut sim, &p.props, &p.prop_style, &h)?;
            for w in &p.wall_heat {
                sim.set_wall_heat(w.clone());
            }
        }
        if sim.heat().is_some() {
            if let Some(saved) = self.restart_heat.take() {
                sim.set_heat_by_id(&saved)?;
            }
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
