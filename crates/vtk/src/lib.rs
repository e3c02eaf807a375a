//! VTK writers (XML, and legacy for particles) for foamgrain's outputs, the files ParaView opens.
//!
//! This crate owns the translation of foamgrain's data into VTK's XML formats:
//! - particles as PolyData (`.vtp`, [`write_vtp`]): points, one `VTK_VERTEX` per particle so
//!   they show without a Glyph filter, and any named scalar, vector or integer point arrays;
//! - an OpenFOAM [`foam::PolyMesh`] with cell and point fields as an UnstructuredGrid (`.vtu`,
//!   [`write_vtu`]): hexahedra, tetrahedra and pyramids become VTK's own cell types with VTK's
//!   point order derived from the face topology; every other cell (prisms included, whose VTK
//!   orientation convention differs between VTK versions, and any cell whose shape is not
//!   matched exactly) becomes a `VTK_POLYHEDRON` ([`VtkCells`]);
//! - time series as ParaView collections (`.pvd`, [`write_pvd`]);
//! - particles as a legacy ASCII `.vtk` PolyData ([`write_legacy_vtk`]), what LIGGGHTS's `dump
//!   custom/vtk` writes for a `.vtk` name.
//!
//! Arrays are Float64 (coordinates and fields), Int64 (connectivity) or the integer type given,
//! stored inline as base64 binary (`header_type="UInt64"`, little-endian, the header holding
//! the byte count) or, with [`Encoding::Ascii`], as text for debugging.
//!
//! Polyhedra follow the VTK file-format specification
//! (<https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>, "UnstructuredGrid"
//! and the polyhedron cell): the cell's `connectivity` lists its distinct points; the `faces`
//! array holds, per polyhedron, the number of faces followed, for each face, by its number of
//! points and their (global) point ids, faces ordered so that their right-hand normal points out
//! of the cell; `faceoffsets` gives the end of each cell's face stream, `-1` for other cells.
//! OpenFOAM faces point out of their owner, so they are reversed in the neighbour's stream.
//!
//! Invariants: the writers are pure — they read their inputs and write one file, nothing else —
//! and never leave a half-written file: each file is written to a temporary in the same
//! directory, synced and renamed over the target. Inconsistent input (an array whose length is
//! not the number of points or cells, a mesh with out-of-range labels) is a typed [`VtkError`]
//! naming the output path, never a panic.
//!
//! ```
//! use vtk::{write_pvd, write_vtp, DataArray};
//! # let dir = tempfile::tempdir().unwrap();
//! let positions = [[0.0, 0.0, 0.0], [1e-3, 0.0, 2e-3]];
//! let radius = [5e-4, 4e-4];
//! let velocity = [[0.0, 0.0, -0.1], [0.0, 0.0, -0.2]];
//! let id = [1_i64, 2];
//! let file = dir.path().join("particles_0.vtp");
//! write_vtp(
//!     &file,
//!     &positions,
//!     &[
//!         DataArray::scalar("radius", &radius),
//!         DataArray::vector("v", &velocity),
//!         DataArray::int64("id", &id),
//!     ],
//! )?;
//! write_pvd(dir.path().join("particles.pvd"), &[(0.0, &file)])?;
//! # Ok::<(), vtk::VtkError>(())
//! ```

mod array;
mod cells;
mod error;
mod legacy;
mod pvd;
mod vtp;
mod vtu;
mod xml;

pub use array::{DataArray, Encoding, Values};
pub use cells::{CellType, VtkCells};
pub use error::VtkError;
pub use legacy::write_legacy_vtk;
pub use pvd::write_pvd;
pub use vtp::{write_vtp, write_vtp_with};
pub use vtu::{write_vtu, write_vtu_cells, write_vtu_with};
