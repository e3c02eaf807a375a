//! Mesh geometry and point location on an OpenFOAM polyMesh.
//!
//! This crate owns the *geometry* of the mesh held by [`foam::PolyMesh`]:
//! * [`MeshGeometry`]: face centres and area vectors, cell centres and volumes, the estimated
//!   cell centres (pyramid apexes), the bounding box — **computed exactly as OpenFOAM v1912
//!   computes them** (`primitiveMeshFaceCentresAndAreas.C`, `primitiveMeshCellCentresAndVols.C`),
//!   in the same operation order, so they agree with OpenFOAM's own `writeCellVolumes` /
//!   `writeCellCentres` output to the last bit on x86-64;
//! * [`TetDecomposition`]: the tetrahedra (apex cEst, base triangles of each face fan) that sum
//!   to those volumes and tile the mesh — the decomposition the voidage engine reuses for exact
//!   sphere ∩ cell volumes;
//! * [`Locator`]: which cell holds a point, consistent with the tet decomposition and one
//!   documented tie rule ([`tets`] module), with an axis-aligned-grid fast path ([`AxisGrid`]),
//!   a bin index, a tet walk seeded by a previous cell, tests on the face planes that settle
//!   most queries without the exact tet predicates, points near a located centre
//!   ([`Locator::locate_near`]), and parallel batch queries;
//! * [`nearest`]: nearest points on triangles and faces (point–face distances);
//! * [`cyclic`]: translational `cyclic` patch pairs and their separations;
//! * [`part`]: a rank's part of a mesh, the cells around a box with their whole-mesh labels;
//! * [`build`]: programmatic meshes (graded Cartesian grids, single cells, affine maps).
//!
//! Invariant: geometry exactly as OpenFOAM computes it; no I/O (reading meshes is the `foam`
//! crate's job). Units are SI: m, m², m³. Invalid input gives a typed [`MeshError`], never a
//! panic, for any mesh that passes [`foam::PolyMesh::check`].

pub mod build;
pub mod cyclic;
mod error;
mod exact;
pub mod geometry;
pub mod locate;
pub mod nearest;
pub mod part;
pub mod tets;
/// The 3-vector type, from the leaf crate `v3` (so `mesh::v3::V3` is `v3::V3`).
pub use ::v3;

pub use error::MeshError;
pub use geometry::{face_centre_and_area, Aabb, MeshGeometry};
pub use locate::{AxisGrid, Locator, LocatorOptions};
pub use tets::{tet_volume, Tet, TetDecomposition, TetId};
