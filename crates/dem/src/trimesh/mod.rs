//! Triangulated surfaces (`fix mesh/surface`): STL files ([`stl`]), the surface with its
//! topology and closest-point test ([`surface::TriMesh`]), and a grid that finds the triangles
//! near a point ([`bins::TriBins`]). The mesh walls that make particles meet them are in
//! [`crate::mesh_wall`]; `fix insert/stream` (an insertion face) can build on the same type.

pub mod bins;
pub mod stl;
pub mod surface;

pub use bins::TriBins;
pub use surface::{Feature, MeshOptions, Transform, TriContact, TriMesh};
