//! The coupler between a particle side (DEM) and a fluid side (CFD).
//!
//! Start with [`Coupler`] ([`step`] module docs give the order of one coupling step) on a
//! [`ParticleSide`] and a [`FluidSide`] ([`sides`]); the configuration comes from a CFDEM-style
//! `constant/couplingProperties` ([`CouplingConfig`]).
//!
//! Modules, one concept each:
//! * [`config`]: `couplingProperties` → typed configuration (CFDEM names mapped onto ours);
//! * [`interpolate`]: fluid cell fields at particles (cell value or share-weighted);
//! * [`forces`]: per-particle fluid forces (closures' laws, model A/B/Bfull) and their split
//!   between the DEM (F_ext, β, u_f) and the fluid; [`forces::couplings_and_exchange`] runs
//!   the force loop and the exchange as one pipeline;
//! * [`exchange`](mod@exchange): Ksl, Us, f per cell with the voidage kernel's shares (ADR 0004);
//! * [`ksl`]: which Ksl the fluid gets: foamgrain's conserving form or CFDEM's
//!   |Σ F| / (V |U − Us|) (`implicitCoupleProps/KslForm`);
//! * [`heat`]: the convective heat per particle (Nusselt laws of closures) and the fluid's
//!   `Tsource` with the same shares, and the heat account;
//! * [`blend`]: linear time blending of ε and Us over a coupling interval;
//! * [`sides`]: the two traits and the data they exchange; [`memory`]: in-memory test doubles;
//! * [`replay`]: a particle side replaying LIGGGHTS dumps (one-way coupling);
//! * [`frozen`]: a fluid side holding U and p read from a case time directory;
//! * [`random_walk`]: `KochHillRWDrag`'s turbulent fluctuation (eddy-interaction model in the
//!   fluid's k–ε fields);
//! * [`population`]: the particles that entered and left between exchanges (by tag);
//! * [`ranks`]: the coupler on several ranks, each with the particles its DEM rank owns;
//! * [`timestep`]: DEM/CFD time-step and coupling-interval advice; [`interval_check`]: CFDEM's
//!   `checkCouplingInterval` during a run;
//! * [`monitor`]: the values of CFDEM's observing models (`particleCellVolume`,
//!   `volWeightedAverage`, `fieldTimeAverage`, `particleVolume`, `totalMomentumExchange`);
//!   [`probe`]: each force model's force on a particle (`particleProbe`); [`output`]: cell
//!   fields into time directories.
//!
//! Invariant: what the particles receive equals what the fluid loses — Σ_c V_c Ksl_c (U_c −
//! Us_c) = Σ_p β_p (u_f − v_p) with the smooth interpolation and Σ_c V_c f_c = −Σ_p F_p, to
//! round-off — and anything outside the mesh is counted, never dropped silently. SI units,
//! kinematic pressure (ADR 0004). Results do not depend on the number of threads: every sum
//! over particles runs in particle order (`tests/parallel.rs` checks 1 to 8 threads bit for
//! bit).
//!
//! Speed (`cargo bench -p couple`, 10⁶ particles on 10⁵ cells): the force loop is parallel over
//! particles and the exchange sums run alongside it; a loop over steps should hand each
//! finished step back ([`Coupler::recycle`], done by [`Coupler::run`]), or the ~200 MB of
//! per-particle buffers are page-faulted in anew every step, which costs the kernel about as
//! much time as the forces themselves.

// Loops over the three vector components index several arrays at once on purpose.
#![allow(clippy::needless_range_loop)]

pub mod bed_heat;
pub mod blend;
pub mod config;
pub mod error;
pub mod exchange;
pub mod forces;
pub mod frozen;
pub mod heat;
pub mod held;
pub mod inter_grain;
pub mod interpolate;
pub mod interval_check;
pub mod ksl;
pub mod memory;
pub mod monitor;
pub mod output;
pub mod parcels;
pub mod part;
pub mod periodic;
pub mod population;
pub mod probe;
pub mod random_walk;
pub mod ranks;
pub mod replay;
mod side_checks;
pub mod sides;
pub mod smoothing;
pub mod step;
pub mod timestep;
pub mod wall_heat;

pub use config::{CouplingConfig, HeatSettings};
pub use error::{CoupleError, SideError};
pub use exchange::{exchange, Exchange, Outside};
pub use forces::{ParticleCoupling, Physics};
pub use heat::{HeatAccount, HeatStep};
pub use held::HeldBytes;
pub use interpolate::{Interpolation, Placement};
pub use population::PopulationChange;
pub use ranks::{Ranks, Serial};
pub use sides::{ExchangeFields, FluidSide, FluidState, ParticleSide, ParticleState, Turbulence};
pub use step::{Coupler, CouplerSettings, CouplingStep};
