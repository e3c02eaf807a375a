//! grainPisoFoam (Debian's OpenFOAM v1912, `openfoam-cases/solver`) as the fluid side of a
//! coupling, over MPI.
//!
//! With the cargo feature `mpi` (needs `openmpi-bin libopenmpi-dev libclang-dev` to build),
//! `OpenFoamFluid` spawns the solver on `np` ranks with `MPI_Comm_spawn`, learns from each
//! rank's handshake which cells it holds (its `cellProcAddressing`; the identity serially) and
//! implements [`couple::FluidSide`]: each coupling interval it sends every rank ε_old, ε_new,
//! Ksl, Us and f of *its* cells only and gets back U, p, ∇p and ∇·τ of those cells plus the
//! per-patch sums (mean p and flux of each boundary patch). Without the feature the crate
//! holds the parts that need no MPI (message layout, rank maps, case preparation), tested in
//! the fast tier.
//!
//! # Using it (the runner's `--fluid openfoam`)
//!
//! ```ignore
//! foam_link::prepare_environment();              // before MPI is initialised
//! let universe = mpi::initialize().unwrap();    // once per process (LIGGGHTS shares it)
//! let mut fluid = foam_link::OpenFoamFluid::spawn(
//!     &universe.world(), Path::new("CASE/CFD"), 2, Path::new(solver_path))?;
//! // As any FluidSide: fluid.set_exchange(&fields)?; fluid.advance(interval)?; fluid.state()
//! let inlet = fluid.patch("inlet").unwrap();    // mean p (m²/s², × ρ for Pa), flux (m³/s)
//! let t = fluid.time();
//! fluid.write()?;                               // write all fields now (optional)
//! fluid.finish()?;                              // stop; reconstructPar when np > 1
//! drop(universe);                               // MPI_Finalize after the fluid is gone
//! ```
//!
//! * **Solver binary**: the `grainPisoFoam=` path printed by `openfoam-cases/solver/build.sh`
//!   (`~/.cache/foamgrain/bin/grainPisoFoam` by default).
//! * **Case**: an OpenFOAM case for grainPisoFoam (`0/{U,p,voidfraction,Ksl,Us,f}`,
//!   `constant/couplingProperties` with `modelType`, `transportProperties` with `nu`, `rho`).
//!   The `couplingSource` entry is ignored: a spawned solver always uses the `mpi` source.
//!   `controlDict`'s `deltaT` sets the PISO step; its `endTime` is ignored (the coupler
//!   decides when to stop); time directories are written at its write times by OpenFOAM.
//! * **np > 1**: `spawn` runs `decomposePar -force`. If `system/decomposeParDict` is missing,
//!   it **writes one** (`simple`, `np` slabs along the mesh's longest axis — Debian's OpenFOAM
//!   has no scotch/metis); an existing one must have `numberOfSubdomains np`. `finish`
//!   reconstructs the written times (`reconstructPar -time` those new in `processor0/`); a run that ends by error
//!   stays decomposed in `processor*/`.
//! * **Time stepping**: an interval Δt_c is `round(Δt_c/deltaT)` (≥ 1) steps of Δt_c/N; at
//!   step k, ε = ε_old + (k/N)(ε_new − ε_old); Ksl, Us, f are held; on the first interval ε's
//!   old time is ε_old — all as the native fluid (`runner::native::NativeFluid`) does.
//! * **Heat** (issue 27): `OpenFoamFluid::spawn_with` with `SpawnOptions { heat: true }`
//!   makes the solver solve cfdemSolverPisoScalar's temperature equation (the case needs
//!   `0/T`, `Pr`, `div(phi,T)` and a `T` solver); every exchange then needs
//!   `ExchangeFields::heat_source` (Tsource, K/s; `OpenFoamFluid::set_fields_with_heat`)
//!   and the state carries `FluidState::temperature` (T, K) and each `PatchFlow` its
//!   `t_flux` (Σ φ T_b, K m³/s; `t_flux / flux` is the patch's mixing-cup temperature).
//!   Without heat nothing changes.
//!   Over the sparse exchange (`OpenFoamFluid::spawn_ranked_with` with heat) each coupler
//!   rank gets T of its touched cells and gives its share of Tsource (`SolverCells`,
//!   [`protocol`]); rank 0's fluid has T only after an advance with
//!   `OpenFoamFluid::set_whole` (`None` otherwise), and the patches' `t_flux` always.
//! * **Logs**: each rank writes `CASE/log.grainPisoFoam` (serial) or
//!   `CASE/log.grainPisoFoam.<rank>`.
//!
//! # Failures
//!
//! Nothing waits blindly: sends and receives poll (`MPI_Isend`/`MPI_Test`, `MPI_Improbe`) and
//! check every 50 ms that the solver pids are alive. An OpenFOAM FatalError while linked is
//! sent to the coupler ([`LinkError::SolverError`] with OpenFOAM's message and the rank's
//! log); a rank that vanishes (killed, SIGFPE on a NaN, a segfault) gives
//! [`LinkError::SolverDied`] with its pid, its log and the log's last lines. The coupler
//! survives both; the other ranks are then ended and the intercommunicator abandoned (a
//! disconnect would wait for the dead rank). Exchange fields are checked before they are sent
//! ([`LinkError::Value`] names the field and the cell: a NaN would otherwise kill the solver
//! through OpenFOAM's floating-point trap).
//!
//! # Environment
//!
//! [`prepare_environment`] sets, where unset, `OMPI_ALLOW_RUN_AS_ROOT(_CONFIRM)=1` (CI runs
//! as root), `OMPI_MCA_rmaps_base_oversubscribe=1` (spawning needs free slots; the machine
//! has 2 cores), `OMPI_MCA_mpi_yield_when_idle=1` (waiting ranks yield the cores) and
//! `WM_PROJECT_DIR`. Open MPI reads them when MPI starts, so call it first.
//!
//! Modules: [`protocol`] (the messages; `mpiCouplingSource.H` is the solver's half),
//! [`ranks`] (the decomposition maps), [`case_setup`] (decomposePar/reconstructPar, logs, the
//! launch line), [`alive`] (pid checks), `transport`, `handshake` and `fluid` (feature `mpi`).

pub mod alive;
pub mod case_setup;
mod error;
pub mod protocol;
pub mod ranks;

#[cfg(feature = "mpi")]
mod fluid;
#[cfg(feature = "mpi")]
mod handshake;
#[cfg(feature = "mpi")]
pub mod sparse;
#[cfg(feature = "mpi")]
mod transport;
// read by the fluid (feature `mpi`); its parsing is tested without
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
mod watch;

pub use error::LinkError;
#[cfg(feature = "mpi")]
pub use fluid::{ExchangeStats, HeldFields, OpenFoamFluid, PatchFlow, SpawnOptions};
pub use ranks::RankMap;
#[cfg(feature = "mpi")]
pub use sparse::SolverCells;
pub use watch::Watched;

/// The environment variables Open MPI and Debian's OpenFOAM need for a spawned solver, as
/// (name, value); see the crate documentation.
pub fn mpi_environment() -> Vec<(&'static str, String)> {
    vec![
        ("OMPI_ALLOW_RUN_AS_ROOT", "1".into()),
        ("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1".into()),
        ("OMPI_MCA_rmaps_base_oversubscribe", "1".into()),
        ("OMPI_MCA_mpi_yield_when_idle", "1".into()),
        ("WM_PROJECT_DIR", case_setup::wm_project_dir()),
    ]
}

/// Sets the [`mpi_environment`] variables that are not set yet. Call it before MPI is
/// initialised and before other threads start (it changes the process environment).
pub fn prepare_environment() {
    for (name, value) in mpi_environment() {
        if std::env::var_os(name).is_none() {
            std::env::set_var(name, value);
        }
    }
}
