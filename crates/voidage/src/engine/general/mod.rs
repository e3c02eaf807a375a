//! `exact`, `cube` and `corrected-cube` on general meshes (any polyhedral cells; module docs
//! of [`crate::engine`]): the candidate cells (`candidates`), each cell's face planes and the
//! tests of a body against a cell (`cells`), the face terms (`faces`), and the two methods
//! (`exact`, `cube`).

mod candidates;
mod cells;
mod cube;
mod exact;
mod faces;

pub(super) use candidates::CellBins;
pub(super) use cells::CellPlane;
