//! [`OpenFoamFluid`]: grainPisoFoam spawned over MPI as a [`couple::FluidSide`].

use crate::case_setup::{self, control_delta_t, launch_script, pid_path, Decomposition};
use crate::protocol::{
    self, check_fields, pack_fields, tag, Command, FieldsIn, GlobalState, Hello,
};
use crate::ranks::RankMap;
use crate::transport::Transport;
use crate::LinkError;
use couple::{ExchangeFields, FluidSide, FluidState, SideError};
use foam::{Case, PolyMesh};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};
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
    transport: Transport,
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
        if world.size() != 1 {
            return Err(LinkError::Parameter(format!(
                "the coupler's communicator has {} processes; foam-link drives grainPisoFoam \
                 from one",
                world.size()
            )));
        }
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

        let script = launch_script(solver, &case, np, &case_setup::wm_project_dir());
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
        let transport = Transport::new(inter, case.clone(), np);
        let mut fluid = OpenFoamFluid {
            transport,
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

    fn protocol_error(&mut self, rank: usize, message: String) -> LinkError {
        self.transport.mark_broken();
        LinkError::Protocol {
            rank,
            log: self.transport.log(rank),
            message,
        }
    }

    fn handshake(&mut self) -> Result<(), LinkError> {
        let np = self.transport.ranks();
        let mesh_patches: Vec<String> = self.mesh.boundary.iter().map(|p| p.name.clone()).collect();
        let mut cells = Vec::with_capacity(np);
        let mut start_states = Vec::with_capacity(np);
        for rank in 0..np {
            let words: Vec<i32> = self.transport.receive(rank, tag::HELLO, "the handshake")?;
            let hello = Hello::parse(&words).map_err(|m| self.protocol_error(rank, m))?;
            if hello.rank != rank {
                let m = format!("says it is rank {}", hello.rank);
                return Err(self.protocol_error(rank, m));
            }
            self.transport.set_pid(rank, hello.pid)?;
            let local: Vec<i32> = self.transport.receive(rank, tag::CELLS, "the cell map")?;
            if local.len() != hello.n_cells {
                let m = format!(
                    "{} cells announced, {} in its map",
                    hello.n_cells,
                    local.len()
                );
                return Err(self.protocol_error(rank, m));
            }
            let Ok(local) = local
                .into_iter()
                .map(u32::try_from)
                .collect::<Result<Vec<u32>, _>>()
            else {
                return Err(self.protocol_error(rank, "a negative cell in its map".into()));
            };
            cells.push(local);
            let names: Vec<u8> = self
                .transport
                .receive(rank, tag::PATCHES, "the patch names")?;
            let names =
                protocol::parse_patch_names(&names).map_err(|m| self.protocol_error(rank, m))?;
            if names != mesh_patches {
                let m =
                    format!("patches {names:?}; constant/polyMesh/boundary has {mesh_patches:?}");
                return Err(self.protocol_error(rank, m));
            }
            let times: Vec<f64> = self.transport.receive(rank, tag::TIMES, "the start time")?;
            if times.len() != 2 {
                return Err(self.protocol_error(rank, format!("{} time values", times.len())));
            }
            let state: Vec<f64> = self
                .transport
                .receive(rank, tag::STATE, "the start fields")?;
            start_states.push(state);
        }
        self.map = RankMap::new(self.mesh.n_cells, cells)
            .map_err(|(rank, m)| self.protocol_error(rank, m))?;
        self.patch_names = mesh_patches;
        self.state = GlobalState::new(self.mesh.n_cells, self.patch_names.len());
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
        (0..self.ranks()).map(|r| self.transport.log(r)).collect()
    }

    /// The solver's process ids (from the handshakes).
    pub fn pids(&self) -> Vec<u32> {
        self.transport.pids().into_iter().flatten().collect()
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
        self.patch_names
            .iter()
            .zip(&self.state.patch_sums)
            .map(|(name, s)| PatchFlow {
                name: name.clone(),
                mean_p: if s[1] > 0.0 { s[0] / s[1] } else { 0.0 },
                area: s[1],
                flux: s[2],
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
        s.wait_seconds = self.transport.wait_seconds;
        s
    }

    /// Writes every field now through OpenFOAM (runTime.writeNow(); in `processorN/` when
    /// decomposed). Time directories at controlDict's write times are written anyway.
    pub fn write(&mut self) -> Result<(), LinkError> {
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
            self.transport.send(rank, &words, tag::COMMAND, waiting)?;
        }
        for rank in 0..self.ranks() {
            let t: Vec<f64> = self.transport.receive(rank, tag::DONE, waiting)?;
            if t.len() != 1 {
                return Err(self.protocol_error(rank, format!("{} values in an ack", t.len())));
            }
        }
        Ok(())
    }

    /// Takes the exchange fields of the next interval (global cell order).
    pub fn set_fields(&mut self, fields: &FieldsIn<'_>) -> Result<(), LinkError> {
        check_fields(&self.map, fields)?;
        let t = Instant::now();
        for rank in 0..self.ranks() {
            pack_fields(self.map.cells_of(rank), fields, &mut self.packed[rank]);
        }
        self.stats.pack_seconds += t.elapsed().as_secs_f64();
        self.has_fields = true;
        Ok(())
    }

    /// Advances one coupling interval of `dt` seconds: `round(dt / deltaT)` (at least 1)
    /// steps of equal length, ε blended linearly from the interval's old to its new field.
    pub fn advance_interval(&mut self, dt: f64) -> Result<(), LinkError> {
        if self.stopped {
            return Err(LinkError::Parameter(
                "advance after the solver was stopped".into(),
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
        let command = Command::Advance {
            steps,
            step_length: dt / steps as f64,
            first: self.stats.intervals == 0,
        };
        let wait_before = self.transport.wait_seconds;
        let t = Instant::now();
        let words = command.words();
        let packed = std::mem::take(&mut self.packed);
        let sent = (0..self.ranks()).try_for_each(|rank| {
            self.transport
                .send(rank, &words, tag::COMMAND, "the command to arrive")?;
            self.transport
                .send(rank, &packed[rank], tag::FIELDS, "the fields to arrive")
        });
        self.packed = packed;
        sent?;
        self.stats.bytes_sent += (8
            * (words.len() * self.ranks() + self.packed.iter().map(Vec::len).sum::<usize>()))
            as u64;
        self.state.clear_sums();
        let mut time = self.state.time;
        for rank in 0..self.ranks() {
            let msg: Vec<f64> = self
                .transport
                .receive(rank, tag::STATE, "the fluid state")?;
            self.stats.bytes_received += 8 * msg.len() as u64;
            let cells = self.map.cells_of(rank);
            time = match self.state.scatter(cells, &msg) {
                Ok(t) => t,
                Err(m) => return Err(self.protocol_error(rank, m)),
            };
        }
        self.state.time = time;
        self.stats.intervals += 1;
        let waited = self.transport.wait_seconds - wait_before;
        self.stats.transfer_seconds += t.elapsed().as_secs_f64() - waited;
        Ok(())
    }
}

impl Drop for OpenFoamFluid {
    fn drop(&mut self) {
        if !self.transport.is_broken() {
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
        self.set_fields(&FieldsIn {
            eps_old: fields.voidage_old,
            eps_new: fields.voidage_new,
            ksl: &fields.exchange.ksl,
            us: &fields.exchange.us,
            f: &fields.exchange.f,
        })?;
        Ok(())
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.advance_interval(dt)?;
        Ok(())
    }

    fn state(&self) -> FluidState<'_> {
        FluidState {
            u: &self.state.u,
            p: &self.state.p,
            grad_p: &self.state.grad_p,
            div_tau: &self.state.div_tau,
        }
    }
}
