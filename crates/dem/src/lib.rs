//! Native discrete element method for spheres, parameterised like LIGGGHTS.
//!
//! Owns: particle state, velocity-Verlet integration, Hertz–Mindlin contacts with tangential
//! history (LIGGGHTS's parameterisation from E, ν, e, μ per type pair), cohesion and rolling
//! friction, plane and cylinder walls, STL mesh walls, linked-cell neighbour search, insertion, per-particle
//! coupling forces, and the subset of a LIGGGHTS input deck that drives it.
//!
//! # Map
//! - [`material`]: per-type E, ν and per-pair e, μ, μᵣ, k → Y*, G*, β.
//! - [`contact`]: `hertz`, `tangential` (history), `sjkr`, `rolling` (`cdt`, `epsd2`).
//! - [`trimesh`]: triangulated surfaces (STL files, topology, closest points, a grid);
//!   [`mesh_wall`]: `wall/gran … mesh` contacts with them.
//! - [`walls`], [`region`], [`insert`] (`insert/pack`), [`insert_rate`]
//!   (`insert/rate/region`, `insert/stream`'s counting), [`insert_stream`] (its extruded face
//!   and the carrying to it), [`outflow`] (lost and deleted particles), [`neighbor`] (linked cells, spatial
//!   order, pair list), [`pair_loop`] (pair forces and their per-particle sums).
//! - [`sim`]: [`Simulation`] — state, step, forces; [`coupling`]: F_ext + β(u_f − v);
//!   [`heat`]: particle temperatures (`heat/gran` conduction, `couple/cfd/convection`).
//! - [`atom_value`]: per-atom quantities by LIGGGHTS name (dump columns, `compute reduce`).
//! - [`deck`]: the LIGGGHTS input subset (restart files: [`deck::restart`]); [`dump`]:
//!   `dump custom` output via `dem-io`;
//!   [`from_dump`]: particles from a LIGGGHTS dump.
//! - `timestep`: Rayleigh and Hertz time criteria.
//!
//! # Example
//! ```no_run
//! let deck = liggghts_deck::Deck::read("DEM/in.liggghts")?;
//! let mut sim = dem::Simulation::from_deck(&deck, std::path::Path::new("."))?;
//! sim.run(1000)?;
//! println!("{} particles at t = {} s", sim.particles.len(), sim.time());
//! # Ok::<(), dem::DemError>(())
//! ```
//!
//! # Invariants
//! Results are bit-identical from run to run and for any number of rayon threads (pair forces
//! summed per particle in a fixed order, [`pair_loop`]). Bad input gives a [`DemError`] naming the deck line, property or
//! particle; nothing here panics on user input.

pub mod atom_value;
pub mod contact;
pub mod coupling;
pub mod deck;
pub mod dump;
pub mod error;
pub mod from_dump;
pub mod heat;
pub mod insert;
pub mod insert_rate;
pub mod insert_stream;
pub mod material;
pub mod mesh_wall;
pub mod neighbor;
pub mod outflow;
pub mod pair_loop;
pub mod particles;
pub mod periodic;
pub mod region;
pub mod sim;
pub mod trimesh;
pub mod walls;

pub use error::DemError;
pub use sim::{HalfStep, SimBox, SimConfig, Simulation};
