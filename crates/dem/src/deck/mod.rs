//! The native DEM's side of a LIGGGHTS deck: the commands that [`liggghts_deck`] reads are
//! executed here ([`exec`], [`Simulation::from_deck`](crate::Simulation::from_deck)), with
//! LIGGGHTS's screen output ([`thermo`]), its data files ([`data_file`]) and restart files
//! ([`restart`]); `fix mesh/surface` is read by [`mesh_surface`].

pub mod data_file;
pub mod exec;
pub(crate) mod insertion;
pub mod mesh_surface;
pub mod print;
pub mod restart;
pub mod thermo;
pub mod values;

/// Opens an output file as LIGGGHTS's `log FILE [append yes]` and `fix print … file|append F`
/// do: truncated, or appended to (created either way).
pub fn open_output(path: &std::path::Path, append: bool) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new()
        .create(true)
        .write(true)
        .append(append)
        .truncate(!append)
        .open(path)
}
