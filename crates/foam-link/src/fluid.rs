//! [`OpenFoamFluid`]: grainPisoFoam spawned over MPI as a [`couple::FluidSide`].

use crate::case_setup::{self, control_delta_t, launch_script_with, pid_path, Decomposition};
use crate::handshake;
use crate::protocol::{
    check_fields, check_heat_source, pack_fields, pack_heat_source, tag, Command, FieldsIn,
    GlobalState, HELD_WORDS_PER_CELL, PATCH_WORDS,
};
use crate::ranks::RankMap;
use crate::sparse::SolverCells;
use crate::transport::Transport;
use crate::watch::{Watch, Watched};
use crate::LinkError;
use couple::{ExchangeFields, FluidSide, FluidState, SideError};
use foam::{Case, PolyMesh};
use mesh::v3::V3;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::cell::{RefCell, RefMut};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::Instant;

/// The flow through one boundary patch after the last advance.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchFlow {
    /// Patch name (as in `constant/polyMesh/boundary`).
    pub name: String,
    /// Area-weighted mean kinematic pressure Σ p|S| / Σ |S|, m²/s² (× ρ for Pa).
    pub mean_p: f64,
    /// Patch area Σ |S|, m².
    pub area: f64,
    /// Total flux Σ φ = Σ (ε U)_f · S, m³/s (negative into the domain).
    pub flux: f64,
    /// With heat on: Σ φ T_b over the patch's faces, K m³/s (the same φ; `t_flux / flux` is
    /// the flux-weighted, mixing-cup temperature of the patch); `None` without heat.
    pub t_flux: Option<f64>,
}

/// How [`OpenFoamFluid::spawn_with`] starts the solver.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpawnOptions {
    /// Solve cfdemSolverPisoScalar's temperature equation (issue 27): the solver reads `0/T`
    /// (required), `0/Tsource` and `0/alphat` (optional) and `Pr` (and `Prt` with a turbulence
    /// model) from `constant/transportProperties`, needs a `T` solver in `system/fvSolution`,
    /// takes Tsource (K/s) with each exchange ([`ExchangeFields::heat_source`]) and returns T
    /// ([`FluidState::temperature`]). Off: the case runs exactly as without this option.
    pub heat: bool,
    /// CFDEM's Ksl form ([`couple::ksl`]) in the sparse exchange of several coupler ranks
    /// ([`OpenFoamFluid::spawn_ranked_with`]): the ranks' sums carry Σ w F, Σ w and Σ w v per
    /// cell and the solver ranks form Ksl and Us as CFDEM does. `None`: the conserving form,
    /// and every message exactly as without this option. (With one coupler rank the coupler
    /// forms Ksl itself and this stays `None`.)
    pub cfdem_ksl: Option<couple::ksl::CfdemKsl>,
    /// The replies carry the vorticity ∇ × U (1/s) per cell, for `MeiLift` and `SaffmanLift`
    /// ([`FluidState::vorticity`]; the launch line sets `FOAMGRAIN_VORTICITY=1`). One coupler
    /// rank only (the sparse exchange does not carry it). Off: every message as without it.
    pub vorticity: bool,
    /// The replies carry DU/Dt = ∂U/∂t + ∇·(φU) (m/s²) per cell, for `virtualMassForce` with
    /// `splitUrelCalculation` ([`FluidState::ddt_u`]; `FOAMGRAIN_DDT_U=1`). One coupler rank
    /// only. Off: every message as without it.
    pub ddt_u: bool,
}

/// What the exchange with the solver cost so far (coupler side, all ranks together).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExchangeStats {
    /// Coupling intervals advanced.
    pub intervals: u64,
    /// Payload bytes sent to the solver (commands and fields).
    pub bytes_sent: u64,
    /// Payload bytes received (fluid states).
    pub bytes_received: u64,
    /// Seconds packing the fields per rank (gather by the rank maps).
    pub pack_seconds: f64,
    /// Seconds in sends and receives proper (copying, matching, scattering into the global
    /// arrays), without the time spent waiting for the solver.
    pub transfer_seconds: f64,
    /// Seconds waiting for the solver (its PISO steps, mostly).
    pub wait_seconds: f64,
}

/// grainPisoFoam on `np` ranks, driven over MPI (see the crate documentation).
pub struct OpenFoamFluid {
    /// Shared with this rank's [`SolverCells`] in a sparse run.
    transport: Rc<RefCell<Transport>>,
    case: PathBuf,
    mesh: PolyMesh,
    map: RankMap,
    patch_names: Vec<String>,
    delta_t: f64,
    state: GlobalState,
    packed: Vec<Vec<f64>>,
    has_fields: bool,
    decomposition: Option<Decomposition>,
    stats: ExchangeStats,
    stopped: bool,
    /// The exchange fields come from the coupler ranks' sparse exchange
    /// ([`OpenFoamFluid::spawn_ranked`]), not from [`OpenFoamFluid::set_fields`].
    sparse: bool,
    /// In a sparse run: ask for the whole state and the held fields after each advance.
    whole: bool,
    /// In a sparse run with `whole`: ε, Ksl, Us and f the solver held in the last advance.
    held: Option<HeldFields>,
    /// An advance that has been started and whose reply has not been received yet
    /// ([`OpenFoamFluid::start_interval`]).
    pending: Option<Pending>,
    /// The solver solves the temperature equation ([`SpawnOptions::heat`]).
    heat: bool,
    /// The solver ranks form CFDEM's Ksl in the sparse exchange ([`SpawnOptions::cfdem_ksl`]).
    cfdem_ksl: bool,
    /// The replies carry ∇ × U and DU/Dt ([`SpawnOptions::vorticity`], `ddt_u`).
    vorticity: bool,
    ddt_u: bool,
    /// In a sparse run with heat: the last advance replied the patch sums only, so the cells'
    /// T is that of an earlier reply ([`OpenFoamFluid::temperature`] then says `None`).
    stale_temperature: bool,
    /// In a sparse run: the cells whose U the patch replies carry ([`OpenFoamFluid::watch`]).
    watch: Option<Watch>,
}

/// What [`OpenFoamFluid::finish_interval`] needs of the advance it completes.
#[derive(Clone, Copy, Debug)]
struct Pending {
    /// The reply's tag: [`tag::STATE`], [`tag::PATCH_STATE`] or [`tag::WHOLE_STATE`].
    reply: i32,
}

/// The exchange fields the solver held in an advance of a sparse run (global cell order, ADR
/// 0004 units).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HeldFields {
    /// ε at the end of the interval.
    pub eps: Vec<f64>,
    /// Ksl, kg/(m³ s).
    pub ksl: Vec<f64>,
    /// Us, m/s.
    pub us: Vec<V3>,
    /// f, N/m³.
    pub f: Vec<V3>,
}

impl OpenFoamFluid {
    /// Starts `solver` (grainPisoFoam, built by `openfoam-cases/solver/build.sh`) on `case`
    /// with `np` ranks: decomposes the case when `np > 1` ([`case_setup::decompose`]),
    /// `MPI_Comm_spawn`s the ranks from `world` (which must have one process, the coupler)
    /// and reads their handshakes. MPI must be initialised by the caller, after
    /// [`crate::prepare_environment`].
    pub fn spawn(
        world: &SimpleCommunicator,
        case: &Path,
        np: usize,
        solver: &Path,
    ) -> Result<OpenFoamFluid, LinkError> {
        OpenFoamFluid::spawn_with(world, case, np, solver, SpawnOptions::default())
    }

    /// As [`OpenFoamFluid::spawn`], with `options` (heat: [`SpawnOptions::heat`]).
    pub fn spawn_with(
        world: &SimpleCommunicator,
        case: &Path,
        np: usize,
        solver: &Path,
        options: SpawnOptions,
    ) -> Result<OpenFoamFluid, LinkError> {
        if world.size() != 1 {
            return Err(LinkError::Parameter(format!(
                "the coupler's communicator has {} processes; foam-link drives grainPisoFoam \
                 from one (OpenFoamFluid::spawn_ranked drives it from several)",
                world.size()
            )));
        }
        if options.cfdem_ksl.is_some() {
            return Err(LinkError::Parameter(
                "SpawnOptions::cfdem_ksl is for the sparse exchange (spawn_ranked_with); with \
                 one coupler rank the coupler forms CFDEM's Ksl itself"
                    .into(),
            ));
        }
        let fluid = OpenFoamFluid::spawn_from_root(world, case, np, solver, options)?;
        Ok(fluid)
    }

    /// As [`OpenFoamFluid::spawn`], collectively from every rank of `world` (the coupler's
    /// ranks, `mpirun -np N foamgrain`): rank 0 prepares the case, spawns the solver (the
    /// other ranks join the collective spawn), reads the handshakes and sends the others the
    /// cell map and the solver's pids. Every rank gets its [`SolverCells`], the straight link
    /// to the solver ranks owning the cells ([`crate::sparse`]); rank 0 also gets the fluid,
    /// which from then on takes its exchange fields from the ranks' sparse exchange.
    /// `case`, `np` and `solver` matter on rank 0 only.
    pub fn spawn_ranked(
        world: &SimpleCommunicator,
        case: &Path,
        np: usize,
        solver: &Path,
    ) -> Result<(Option<OpenFoamFluid>, SolverCells), LinkError> {
        OpenFoamFluid::spawn_ranked_with(world, case, np, solver, SpawnOptions::default())
    }

    /// As [`OpenFoamFluid::spawn_ranked`], with `options`, which must be the same on every
    /// rank. With `options.heat` the sparse exchange carries T and the ranks' Tsource shares
    /// ([`crate::protocol`]); rank 0's fluid has T after an advance with
    /// [`OpenFoamFluid::set_whole`] (and the patches' Σ φ T_b after every advance).
    pub fn spawn_ranked_with(
        world: &SimpleCommunicator,
        case: &Path,
        np: usize,
        solver: &Path,
        options: SpawnOptions,
    ) -> Result<(Option<OpenFoamFluid>, SolverCells), LinkError> {
        if options.vorticity || options.ddt_u {
            return Err(LinkError::Parameter(
                "SpawnOptions::vorticity and ddt_u are for one coupler rank (spawn_with): the \
                 sparse exchange of several coupler ranks does not carry ∇ × U or DU/Dt"
                    .into(),
            ));
        }
        let root = world.process_at_rank(0);
        if world.rank() == 0 {
            let mut fluid = OpenFoamFluid::spawn_from_root(world, case, np, solver, options)?;
            fluid.sparse = true;
            let mut words = share_words(&fluid.map, &fluid.tp().pids());
            let mut len = [words.len() as u64];
            root.broadcast_into(&mut len[..]);
            root.broadcast_into(&mut words[..]);
            let cells = SolverCells::new(0, fluid.transport.clone(), fluid.map.clone(), options);
            return Ok((Some(fluid), cells));
        }
        // The program and count matter at the root only; Open MPI sizes its error codes by
        // the count on every rank.
        let inter = root
            .spawn(&std::process::Command::new("/bin/true"), np.max(1) as i32)
            .map_err(|e| LinkError::Spawn {
                solver: solver.to_owned(),
                ranks: np,
                message: format!("{e:?}"),
            })?;
        let mut len = [0u64];
        root.broadcast_into(&mut len[..]);
        let mut words = vec![0i64; len[0] as usize];
        root.broadcast_into(&mut words[..]);
        let (map, pids) = unshare_words(&words)?;
        let mut transport = Transport::new(inter, case.to_owned(), map.ranks());
        for (rank, pid) in pids.into_iter().enumerate() {
            transport.set_pid(rank, pid)?;
        }
        let rank = world.rank() as usize;
        Ok((
            None,
            SolverCells::new(rank, Rc::new(RefCell::new(transport)), map, options),
        ))
    }

    /// [`OpenFoamFluid::spawn`] on the root (rank 0) of `world`, whose other ranks (if any)
    /// call the collective spawn themselves.
    fn spawn_from_root(
        world: &SimpleCommunicator,
        case: &Path,
        np: usize,
        solver: &Path,
        options: SpawnOptions,
    ) -> Result<OpenFoamFluid, LinkError> {
        let heat = options.heat;
        if np == 0 {
            return Err(LinkError::Parameter(
                "grainPisoFoam needs at least 1 rank".into(),
            ));
        }
        if !solver.is_file() {
            return Err(LinkError::Parameter(format!(
                "{}: no such solver (build it with openfoam-cases/solver/build.sh)",
                solver.display()
            )));
        }
        let case = std::fs::canonicalize(case).map_err(|e| LinkError::io(case, e))?;
        let foam_case = Case::open(&case)?;
        let mesh = foam_case.read_mesh()?;
        let delta_t = control_delta_t(&foam_case)?;
        let decomposition = if np > 1 {
            Some(case_setup::decompose(&foam_case, &mesh, np)?)
        } else {
            None
        };
        for rank in 0..np {
            let path = pid_path(&case, rank);
            match std::fs::remove_file(&path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(LinkError::io(path, e))
                }
                _ => {}
            }
        }

        let wm = case_setup::wm_project_dir();
        let script = case_setup::with_field_requests(
            &launch_script_with(solver, &case, np, &wm, heat, options.cfdem_ksl),
            options.vorticity,
            options.ddt_u,
        );
        let mut command = std::process::Command::new("/bin/sh");
        command.arg("-c").arg(script);
        let inter = world
            .process_at_rank(0)
            .spawn(&command, np as i32)
            .map_err(|e| LinkError::Spawn {
                solver: solver.to_owned(),
                ranks: np,
                message: format!("{e:?}"),
            })?;
        let transport = Rc::new(RefCell::new(Transport::new(inter, case.clone(), np)));
        let mut fluid = OpenFoamFluid {
            transport,
            sparse: false,
            whole: false,
            held: None,
            pending: None,
            heat,
            cfdem_ksl: options.cfdem_ksl.is_some(),
            vorticity: options.vorticity,
            ddt_u: options.ddt_u,
            stale_temperature: false,
            watch: None,
            case,
            map: RankMap::serial(0),
            patch_names: Vec::new(),
            delta_t,
            state: GlobalState::default(),
            packed: vec![Vec::new(); np],
            has_fields: false,
            decomposition,
            stats: ExchangeStats::default(),
            stopped: false,
            mesh,
        };
        fluid.handshake()?;
        Ok(fluid)
    }

    fn tp(&self) -> RefMut<'_, Transport> {
        self.transport.borrow_mut()
    }

    fn protocol_error(&mut self, rank: usize, message: String) -> LinkError {
        self.tp().mark_broken();
        LinkError::Protocol {
            rank,
            log: self.tp().log(rank),
            message,
        }
    }

    /// Every rank's handshake and start fields (module `handshake`: taken as they arrive).
    fn handshake(&mut self) -> Result<(), LinkError> {
        let mesh_patches: Vec<String> = self.mesh.boundary.iter().map(|p| p.name.clone()).collect();
        let asked = handshake::Asked {
            heat: self.heat,
            cfdem_ksl: self.cfdem_ksl,
            vorticity: self.vorticity,
            ddt_u: self.ddt_u,
        };
        let starts = handshake::receive_all(&mut self.tp(), &asked, &mesh_patches)?;
        let (cells, start_states): (Vec<Vec<u32>>, Vec<Vec<f64>>) =
            starts.into_iter().map(|s| (s.cells, s.state)).unzip();
        self.map = RankMap::new(self.mesh.n_cells, cells)
            .map_err(|(rank, m)| self.protocol_error(rank, m))?;
        self.patch_names = mesh_patches;
        self.state = GlobalState::with_fields(
            self.mesh.n_cells,
            self.patch_names.len(),
            self.heat,
            self.vorticity,
            self.ddt_u,
        );
        for (rank, msg) in start_states.iter().enumerate() {
            match self.state.scatter(self.map.cells_of(rank), msg) {
                Ok(t) => self.state.time = t,
                Err(m) => return Err(self.protocol_error(rank, m)),
            }
        }
        Ok(())
    }

    /// The OpenFOAM case (absolute path).
    pub fn case(&self) -> &Path {
        &self.case
    }

    /// Solver ranks.
    pub fn ranks(&self) -> usize {
        self.map.ranks()
    }

    /// Which cells live on which rank.
    pub fn rank_map(&self) -> &RankMap {
        &self.map
    }

    /// What `spawn` did to decompose the case (`None` serially).
    pub fn decomposition(&self) -> Option<&Decomposition> {
        self.decomposition.as_ref()
    }

    /// The log of each rank (`CASE/log.grainPisoFoam[.rank]`).
    pub fn logs(&self) -> Vec<PathBuf> {
        (0..self.ranks()).map(|r| self.tp().log(r)).collect()
    }

    /// The solver's process ids (from the handshakes).
    pub fn pids(&self) -> Vec<u32> {
        self.tp().pids().into_iter().flatten().collect()
    }

    /// True when the solver solves the temperature equation ([`SpawnOptions::heat`]).
    pub fn heat(&self) -> bool {
        self.heat
    }

    /// T per global cell (K) after the last advance (the start field before the first);
    /// `None` without heat, and in a sparse run after an advance without
    /// [`OpenFoamFluid::set_whole`] (the solver replied its patch sums only: the cells' T here
    /// would be an earlier one; the coupler ranks get T of their cells in the sparse exchange).
    pub fn temperature(&self) -> Option<&[f64]> {
        if self.stale_temperature {
            return None;
        }
        self.state.temperature.as_deref()
    }

    /// The solver's simulated time, s.
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// `deltaT` of `system/controlDict`, s (a coupling interval is advanced in steps of about
    /// this length).
    pub fn delta_t(&self) -> f64 {
        self.delta_t
    }

    /// Per boundary patch (in the boundary file's order): mean p and total flux after the last
    /// advance (zeros before the first).
    pub fn patches(&self) -> Vec<PatchFlow> {
        let t_flux = self.state.patch_t_flux.as_deref();
        self.patch_names
            .iter()
            .zip(&self.state.patch_sums)
            .enumerate()
            .map(|(j, (name, s))| PatchFlow {
                name: name.clone(),
                mean_p: if s[1] > 0.0 { s[0] / s[1] } else { 0.0 },
                area: s[1],
                flux: s[2],
                t_flux: t_flux.map(|t| t[j]),
            })
            .collect()
    }

    /// The flow through the patch `name`; `None` when the mesh has no such patch.
    pub fn patch(&self, name: &str) -> Option<PatchFlow> {
        self.patches().into_iter().find(|p| p.name == name)
    }

    /// What the exchange has cost so far.
    pub fn stats(&self) -> ExchangeStats {
        let mut s = self.stats;
        s.wait_seconds = self.tp().wait_seconds;
        s
    }

    /// Writes every field now through OpenFOAM (runTime.writeNow(); in `processorN/` when
    /// decomposed). Time directories at controlDict's write times are written anyway.
    pub fn write(&mut self) -> Result<(), LinkError> {
        if self.pending.is_some() {
            return Err(LinkError::Parameter(
                "write while an advance is under way (finish_interval first)".into(),
            ));
        }
        self.command_all(Command::Write, "the write to finish")
    }

    /// Stops the solver (it leaves its time loop and exits) and, when decomposed,
    /// reconstructs the time directories it wrote ([`case_setup::reconstruct`]).
    pub fn finish(mut self) -> Result<(), LinkError> {
        self.stop()?;
        if self.ranks() > 1 {
            case_setup::reconstruct(&self.case)?;
        }
        Ok(())
    }

    fn stop(&mut self) -> Result<(), LinkError> {
        if self.stopped {
            return Ok(());
        }
        // an advance under way replies first: the solver reads the stop command after it
        self.finish_interval()?;
        self.stopped = true;
        self.command_all(Command::Stop, "the solver to stop")?;
        for rank in 0..self.ranks() {
            let _ = std::fs::remove_file(pid_path(&self.case, rank));
        }
        Ok(())
    }

    fn command_all(&mut self, command: Command, waiting: &'static str) -> Result<(), LinkError> {
        let words = command.words();
        for rank in 0..self.ranks() {
            self.tp().send(rank, &words, tag::COMMAND, waiting)?;
        }
        for rank in 0..self.ranks() {
            let t: Vec<f64> = self.tp().receive(rank, tag::DONE, waiting)?;
            if t.len() != 1 {
                return Err(self.protocol_error(rank, format!("{} values in an ack", t.len())));
            }
        }
        Ok(())
    }

    /// Takes the exchange fields of the next interval (global cell order).
    /// In a sparse run ([`OpenFoamFluid::spawn_ranked`]) the fields are ignored: the coupler
    /// ranks have given the solver theirs ([`SolverCells`]). With heat on this is an error:
    /// use [`OpenFoamFluid::set_fields_with_heat`].
    pub fn set_fields(&mut self, fields: &FieldsIn<'_>) -> Result<(), LinkError> {
        self.set_fields_with_heat(fields, None)
    }

    /// As [`OpenFoamFluid::set_fields`], with the heat source Tsource (K/s per global cell,
    /// held over the interval): required when the fluid was spawned with
    /// [`SpawnOptions::heat`], refused otherwise.
    pub fn set_fields_with_heat(
        &mut self,
        fields: &FieldsIn<'_>,
        heat_source: Option<&[f64]>,
    ) -> Result<(), LinkError> {
        match (self.heat, heat_source) {
            (true, None) => {
                return Err(LinkError::Parameter(
                    "the fluid solves heat (SpawnOptions::heat): the exchange needs Tsource \
                     (ExchangeFields::heat_source)"
                        .into(),
                ))
            }
            (false, Some(_)) => {
                return Err(LinkError::Parameter(
                    "a heat source (Tsource) for a fluid spawned without heat \
                     (SpawnOptions::heat is off)"
                        .into(),
                ))
            }
            _ => {}
        }
        if self.sparse {
            self.has_fields = true;
            return Ok(());
        }
        check_fields(&self.map, fields)?;
        if let Some(ts) = heat_source {
            check_heat_source(&self.map, ts)?;
        }
        let t = Instant::now();
        for rank in 0..self.ranks() {
            pack_fields(self.map.cells_of(rank), fields, &mut self.packed[rank]);
            if let Some(ts) = heat_source {
                pack_heat_source(self.map.cells_of(rank), ts, &mut self.packed[rank]);
            }
        }
        self.stats.pack_seconds += t.elapsed().as_secs_f64();
        self.has_fields = true;
        Ok(())
    }

    /// Advances one coupling interval of `dt` seconds: `round(dt / deltaT)` (at least 1)
    /// steps of equal length, ε blended linearly from the interval's old to its new field
    /// ([`OpenFoamFluid::start_interval`] and [`OpenFoamFluid::finish_interval`]).
    pub fn advance_interval(&mut self, dt: f64) -> Result<(), LinkError> {
        self.start_interval(dt)?;
        self.finish_interval()
    }

    /// True between [`OpenFoamFluid::start_interval`] and [`OpenFoamFluid::finish_interval`].
    pub fn is_advancing(&self) -> bool {
        self.pending.is_some()
    }

    /// Starts advancing one coupling interval (as [`OpenFoamFluid::advance_interval`]): sends
    /// the command and the exchange fields and returns while the solver computes. Until
    /// [`OpenFoamFluid::finish_interval`], the state, time and patch sums are those before the
    /// advance; the solver's replies wait in MPI meanwhile (a solver that dies is found by
    /// `finish_interval`).
    pub fn start_interval(&mut self, dt: f64) -> Result<(), LinkError> {
        if self.stopped {
            return Err(LinkError::Parameter(
                "advance after the solver was stopped".into(),
            ));
        }
        if self.pending.is_some() {
            return Err(LinkError::Parameter(
                "advance while the last one is under way (finish_interval first)".into(),
            ));
        }
        if !self.has_fields {
            return Err(LinkError::Parameter(
                "advance before the exchange fields were set (set_exchange)".into(),
            ));
        }
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(LinkError::Parameter(format!("coupling interval {dt} s")));
        }
        let steps = (dt / self.delta_t).round().max(1.0) as u64;
        let first = self.stats.intervals == 0;
        let step_length = dt / steps as f64;
        let t = Instant::now();
        let reply = if self.sparse {
            self.start_held(steps, step_length, first)?
        } else {
            let words = Command::Advance {
                steps,
                step_length,
                first,
            }
            .words();
            let packed = std::mem::take(&mut self.packed);
            let sent = (0..self.ranks()).try_for_each(|rank| {
                self.tp()
                    .send(rank, &words, tag::COMMAND, "the command to arrive")?;
                self.tp()
                    .send(rank, &packed[rank], tag::FIELDS, "the fields to arrive")
            });
            self.packed = packed;
            sent?;
            self.stats.bytes_sent += (8
                * (words.len() * self.ranks() + self.packed.iter().map(Vec::len).sum::<usize>()))
                as u64;
            tag::STATE
        };
        self.stats.transfer_seconds += t.elapsed().as_secs_f64();
        self.pending = Some(Pending { reply });
        Ok(())
    }

    /// Completes the advance [`OpenFoamFluid::start_interval`] started: receives every
    /// rank's reply (the state, or in a sparse run the patch sums and, with `whole`, the
    /// whole state and held fields). A no-op when no advance is under way.
    pub fn finish_interval(&mut self) -> Result<(), LinkError> {
        let Some(Pending { reply }) = self.pending.take() else {
            return Ok(());
        };
        let wait_before = self.tp().wait_seconds;
        let t = Instant::now();
        self.state.clear_sums();
        if let Some(w) = self.watch.as_mut() {
            w.clear();
        }
        let mut time = self.state.time;
        let n_patches = self.patch_names.len();
        for rank in 0..self.ranks() {
            let msg: Vec<f64> = self.tp().receive(rank, reply, "the fluid state")?;
            self.stats.bytes_received += 8 * msg.len() as u64;
            let got = if reply == tag::STATE {
                self.state.scatter(self.map.cells_of(rank), &msg)
            } else if reply == tag::WHOLE_STATE {
                let cells = self.map.cells_of(rank).to_vec();
                let n = cells.len();
                let h = self.state.heat_words();
                let split = (1 + self.state.cell_words() * n + (PATCH_WORDS + h) * n_patches)
                    .min(msg.len());
                let (state, held) = msg.split_at(split);
                let held_fields = self.held.as_mut().expect("allocated by start_held");
                scatter_held(&cells, held, held_fields)
                    .and_then(|()| self.state.scatter(&cells, state))
            } else {
                self.patch_reply(rank, &msg)
            };
            time = match got {
                Ok(t) => t,
                Err(m) => return Err(self.protocol_error(rank, m)),
            };
        }
        self.state.time = time;
        self.stale_temperature = reply == tag::PATCH_STATE;
        self.stats.intervals += 1;
        let waited = self.tp().wait_seconds - wait_before;
        self.stats.transfer_seconds += t.elapsed().as_secs_f64() - waited;
        Ok(())
    }
}

impl OpenFoamFluid {
    /// In a sparse run: after each advance, also fetch the whole fluid state and the fields
    /// the solver held ([`OpenFoamFluid::held_fields`]): for monitors that need whole fields
    /// on rank 0, at the cost of a mesh-sized reply.
    pub fn set_whole(&mut self, whole: bool) {
        self.whole = whole;
    }

    /// In a sparse run with [`OpenFoamFluid::set_whole`]: ε, Ksl, Us and f of the last
    /// advance (global cell order).
    pub fn held_fields(&self) -> Option<&HeldFields> {
        self.held.as_ref()
    }

    /// True when the exchange fields come from the coupler ranks' sparse exchange.
    pub fn is_sparse(&self) -> bool {
        self.sparse
    }

    /// True in a sparse run whose replies carry the whole state ([`OpenFoamFluid::set_whole`]).
    pub fn is_whole(&self) -> bool {
        self.whole
    }

    /// In a sparse run without [`OpenFoamFluid::set_whole`], where only the patch sums come
    /// back after an advance and [`FluidSide::state`] keeps the start fields: asks every
    /// solver rank for U of the global `cells` now and after each advance, and with `cfl` for
    /// max |U|/∛V over its cells ([`OpenFoamFluid::watched`]; the protocol's watch). The
    /// bytes scale with `cells`, not with the mesh. Replaces an earlier watch; refused in a
    /// dense or whole run (the state is current there), while an advance is under way, and
    /// for a cell outside the mesh.
    pub fn watch(&mut self, cells: &[usize], cfl: bool) -> Result<(), LinkError> {
        if !self.sparse || self.whole {
            return Err(LinkError::Parameter(
                "watch is for the sparse exchange without whole replies: there the state \
                 after an advance carries every cell"
                    .into(),
            ));
        }
        if self.pending.is_some() || self.stopped {
            return Err(LinkError::Parameter(
                "watch while an advance is under way or after the solver was stopped".into(),
            ));
        }
        let np = self.ranks();
        let mut groups = vec![Vec::new(); np];
        let mut local: Vec<Vec<i32>> = vec![Vec::new(); np];
        for (k, &c) in cells.iter().enumerate() {
            if c >= self.map.n_cells() {
                return Err(LinkError::Parameter(format!(
                    "watch: cell {c} of a mesh of {} cells",
                    self.map.n_cells()
                )));
            }
            let (s, l) = self.map.locate(c);
            groups[s].push(k);
            local[s].push(l as i32);
        }
        let words = Command::Watch { cfl }.words();
        for (rank, cells) in local.iter().enumerate() {
            self.tp()
                .send(rank, &words, tag::COMMAND, "the watch to arrive")?;
            self.tp()
                .send(rank, cells, tag::WATCH_CELLS, "the watched cells to arrive")?;
        }
        self.stats.bytes_sent += (8 * words.len() * np + 4 * cells.len()) as u64;
        let mut watch = Watch::new(groups, cells.len(), cfl);
        for rank in 0..np {
            let msg: Vec<f64> =
                self.tp()
                    .receive(rank, tag::WATCHED, "the watched cells' fluid")?;
            self.stats.bytes_received += 8 * msg.len() as u64;
            if let Err(m) = watch.take(rank, &msg) {
                return Err(self.protocol_error(rank, m));
            }
        }
        self.watch = Some(watch);
        Ok(())
    }

    /// What [`OpenFoamFluid::watch`] asked for, after the last advance (before the first:
    /// at the watch); `None` without a watch, and while the replies carry the whole state
    /// ([`OpenFoamFluid::set_whole`]: read [`FluidSide::state`] then).
    pub fn watched(&self) -> Option<&Watched> {
        match self.whole {
            true => None,
            false => self.watch.as_ref().map(|w| &w.values),
        }
    }

    /// One rank's [`tag::PATCH_STATE`] reply: the patch sums, then the watch block when
    /// watching; returns the rank's time.
    fn patch_reply(&mut self, rank: usize, msg: &[f64]) -> Result<f64, String> {
        let per_patch = PATCH_WORDS + self.state.heat_words();
        let sums = (1 + per_patch * self.patch_names.len()).min(msg.len());
        let (sums, block) = msg.split_at(sums);
        let time = self.state.add_patch_sums(sums)?;
        match self.watch.as_mut() {
            Some(w) => w.take(rank, block)?,
            None if !block.is_empty() => {
                return Err(format!(
                    "patch reply with {} values after the sums, and no watch",
                    block.len()
                ))
            }
            None => {}
        }
        Ok(time)
    }

    /// In a sparse run ([`OpenFoamFluid::spawn_ranked`]): hands the caller the whole mesh read
    /// at the spawn, so that coupler rank 0 can cut its part of it and summarise what it
    /// observes without holding it twice. The exchange does not read the mesh after the
    /// handshake (the cell map has the cell count); this fluid's [`FluidSide::mesh`] is then a
    /// mesh without points, faces or cells. `None` in a dense run (one coupler rank, whose
    /// exchange fields are the mesh's) and once taken.
    pub fn take_mesh(&mut self) -> Option<PolyMesh> {
        if !self.sparse || self.mesh.n_cells == 0 {
            return None;
        }
        let none = PolyMesh {
            points: Vec::new(),
            faces: foam::FaceList::new(),
            owner: Vec::new(),
            neighbour: Vec::new(),
            boundary: Vec::new(),
            n_cells: 0,
        };
        Some(std::mem::replace(&mut self.mesh, none))
    }

    /// [`OpenFoamFluid::start_interval`] of a sparse run: the solver advances with the fields
    /// of the last sparse exchange and replies with the patch sums (or everything, `whole`);
    /// returns the reply's tag.
    fn start_held(&mut self, steps: u64, step_length: f64, first: bool) -> Result<i32, LinkError> {
        let words = Command::AdvanceHeld {
            steps,
            step_length,
            first,
            whole: self.whole,
        }
        .words();
        for rank in 0..self.ranks() {
            self.tp()
                .send(rank, &words, tag::COMMAND, "the command to arrive")?;
        }
        self.stats.bytes_sent += (8 * words.len() * self.ranks()) as u64;
        if self.whole && self.held.is_none() {
            let n = self.map.n_cells();
            self.held = Some(HeldFields {
                eps: vec![1.0; n],
                ksl: vec![0.0; n],
                us: vec![V3::zeros(); n],
                f: vec![V3::zeros(); n],
            });
        }
        Ok(if self.whole {
            tag::WHOLE_STATE
        } else {
            tag::PATCH_STATE
        })
    }
}

/// Scatters the held fields of one rank's [`tag::WHOLE_STATE`] reply (after its state part):
/// ε, Ksl (n each), Us, f (3n each).
fn scatter_held(cells: &[u32], msg: &[f64], out: &mut HeldFields) -> Result<(), String> {
    let n = cells.len();
    if msg.len() != HELD_WORDS_PER_CELL * n {
        return Err(format!(
            "held fields of {} values, expected {} ({n} cells)",
            msg.len(),
            HELD_WORDS_PER_CELL * n
        ));
    }
    let (eps, rest) = msg.split_at(n);
    let (ksl, rest) = rest.split_at(n);
    let (us, f) = rest.split_at(3 * n);
    for (i, &c) in cells.iter().enumerate() {
        let c = c as usize;
        out.eps[c] = eps[i];
        out.ksl[c] = ksl[i];
        out.us[c] = V3::new(us[3 * i], us[3 * i + 1], us[3 * i + 2]);
        out.f[c] = V3::new(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
    }
    Ok(())
}

impl Drop for OpenFoamFluid {
    fn drop(&mut self) {
        if !self.tp().is_broken() {
            // Best effort: a solver left running would keep the MPI universe from finalising.
            let _ = self.stop();
        }
    }
}

impl FluidSide for OpenFoamFluid {
    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError> {
        self.set_fields_with_heat(
            &FieldsIn {
                eps_old: fields.voidage_old,
                eps_new: fields.voidage_new,
                ksl: &fields.exchange.ksl,
                us: &fields.exchange.us,
                f: &fields.exchange.f,
            },
            fields.heat_source,
        )?;
        Ok(())
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.advance_interval(dt)?;
        Ok(())
    }

    fn state(&self) -> FluidState<'_> {
        FluidState {
            vorticity: self.state.vorticity.as_deref(),
            ddt_u: self.state.ddt_u.as_deref(),
            turbulence: None,
            temperature: self.temperature(),
            u: &self.state.u,
            p: &self.state.p,
            grad_p: &self.state.grad_p,
            div_tau: &self.state.div_tau,
        }
    }
}

/// What rank 0 sends the other coupler ranks after the handshake: the cell count, the solver's
/// rank count and pids, and each solver rank's cells (global ids in its local order).
fn share_words(map: &RankMap, pids: &[Option<u32>]) -> Vec<i64> {
    let np = map.ranks();
    let mut w = vec![map.n_cells() as i64, np as i64];
    w.extend(pids.iter().map(|p| p.map_or(-1, i64::from)));
    w.extend((0..np).map(|r| map.cells_of(r).len() as i64));
    for r in 0..np {
        w.extend(map.cells_of(r).iter().map(|&c| i64::from(c)));
    }
    w
}

/// The inverse of [`share_words`].
fn unshare_words(w: &[i64]) -> Result<(RankMap, Vec<u32>), LinkError> {
    let bad = |what: &str| LinkError::Parameter(format!("the cell map from rank 0: {what}"));
    let (&n_cells, &np) = (
        w.first().ok_or(bad("empty"))?,
        w.get(1).ok_or(bad("short"))?,
    );
    let (n_cells, np) = (n_cells as usize, np as usize);
    let pids = w.get(2..2 + np).ok_or(bad("short"))?;
    let counts = w.get(2 + np..2 + 2 * np).ok_or(bad("short"))?;
    let mut at = 2 + 2 * np;
    let mut cells = Vec::with_capacity(np);
    for &k in counts {
        let k = k as usize;
        let part = w.get(at..at + k).ok_or(bad("short"))?;
        cells.push(part.iter().map(|&c| c as u32).collect());
        at += k;
    }
    let map = RankMap::new(n_cells, cells).map_err(|(r, m)| bad(&format!("rank {r}: {m}")))?;
    let pids = pids
        .iter()
        .map(|&p| u32::try_from(p).map_err(|_| bad("a pid is missing")))
        .collect::<Result<Vec<u32>, _>>()?;
    Ok((map, pids))
}
