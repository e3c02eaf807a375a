//! The native DEM's side of a LIGGGHTS deck: the commands that [`liggghts_deck`] reads are
//! executed here ([`exec`], [`Simulation::from_deck`](crate::Simulation::from_deck)), with
//! LIGGGHTS's screen output ([`thermo`]) and its data files ([`data_file`]).

pub mod data_file;
pub mod exec;
pub mod thermo;
