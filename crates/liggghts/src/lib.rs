//! LIGGGHTS 3.8.0 (Debian's `liggghts` and `libliggghts-dev`) as a particle side of the
//! coupler ([`couple::ParticleSide`]), three ways:
//!
//! - **In-process** (cargo feature `link`, off by default): `LiggghtsDem` links
//!   libliggghts and drives it through its library interface on an MPI communicator the caller
//!   owns — the fast path. MPI is initialised once by the caller (e.g. `mpi::initialize()`),
//!   because the runner also spawns OpenFOAM through the same MPI universe:
//!   ```ignore
//!   let universe = mpi::initialize().unwrap();
//!   let mut dem = liggghts::LiggghtsDem::open(&universe.world(), "DEM/in.liggghts_run".as_ref(),
//!                                             "DEM".as_ref(), &[])?;
//!   for r in dem.skipped_runs() { eprintln!("skipped line {}: {}", r.line, r.command); }
//!   dem.advance(50)?;                       // `run 50` (then `run 50 pre no post no`)
//!   let s = dem.state();                    // ids (tags, increasing), x, v, radius, density
//!   dem.set_forces(&f_ext, &beta, &u_f)?;   // → dragforce, Ksl, uf (F = F_ext + β(u_f − v))
//!   ```
//!   With several ranks each calls every method together; each rank's state holds only the
//!   particles its LIGGGHTS rank owns, and its forces go to those particles only.
//! - **File coupling** (always compiled): [`FileDem`] runs the `liggghts` binary as a child
//!   process on a rewritten copy of the deck and exchanges through files (LIGGGHTS's
//!   `couple/cfd … file` handshake). About 10 s per exchange by LIGGGHTS's design; for users
//!   who cannot link the library.
//! - **Stage 1**: [`run_deck`] runs an init deck with the binary in the DEM directory and
//!   reports a failure with the tail of its log.
//!
//! # Map
//! - [`deck`]: the checks a coupled deck must pass before LIGGGHTS sees it (any LIGGGHTS error
//!   ends the process), the trailing `run`s skipped, the copies the backends run.
//! - [`forces`]: ADR 0004's `F = F_ext + β (u_f − v)` as LIGGGHTS's `dragforce`, `Ksl`, `uf`.
//! - [`particles`]: the owned, tag-ordered state buffers.
//! - [`file`](mod@file): [`FileDem`]; [`program`]: [`run_deck`] and the binary's command line.
//! - `inproc` and `ffi` (feature `link`): `LiggghtsDem` and the hand-written declarations.
//!
//! # Units and conventions
//! SI (`units si` decks), ADR 0004. The DEM time is `step × dt` as for the native DEM.
//!
//! # Invariants
//! The state is ordered by tag on every rank and backend; in-process, a rank's state is the
//! particles its LIGGGHTS rank owns and nothing else; what a side hands to LIGGGHTS never
//! contains a non-finite value or a negative β (errors name the particle by tag); a LIGGGHTS
//! child that stops is an error carrying its log's tail, never a hang.

pub mod deck;
pub mod error;
pub mod file;
pub mod forces;
pub mod particles;
pub mod program;

#[cfg(feature = "link")]
mod ffi;
#[cfg(feature = "link")]
mod inproc;

pub use deck::{CouplingDeck, DataCoupling, SkippedRun};
pub use error::LiggghtsError;
pub use file::{FileDem, FileOptions, Rewritten};
pub use forces::ForceMode;
#[cfg(feature = "link")]
pub use inproc::LiggghtsDem;
pub use particles::Particles;
pub use program::{run_deck, ProgramRun, LIGGGHTS_PROGRAM};
