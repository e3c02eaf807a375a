//! Typed errors of the mesh crate.

use foam::{Label, TopologyError};

/// Why geometry or a locator could not be built for a mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// The polyMesh failed [`foam::PolyMesh::check`].
    #[error("invalid mesh topology: {0}")]
    Topology(#[from] TopologyError),
    /// A point coordinate is NaN or infinite.
    #[error("point {point} has a non-finite coordinate {coords:?}")]
    NonFinitePoint {
        /// Point index.
        point: Label,
        /// Its coordinates, m.
        coords: [f64; 3],
    },
    /// A cell's volume (OpenFOAM's pyramid sum) is negative: the cell is inverted, e.g. its faces
    /// point inwards or the mesh was mirrored without flipping faces.
    #[error("cell {cell} is inverted: volume {volume:e} m³ is negative")]
    InvertedCell {
        /// Cell index.
        cell: Label,
        /// Its volume, m³.
        volume: f64,
    },
    /// A cell's volume is zero (|V| ≤ 1e-300 m³, OpenFOAM's `VSMALL`) or not finite.
    #[error("cell {cell} is degenerate: volume {volume:e} m³")]
    DegenerateCell {
        /// Cell index.
        cell: Label,
        /// Its volume, m³.
        volume: f64,
    },
    /// Geometry and mesh given together do not belong to each other.
    #[error("geometry has {geometry} cells and {geometry_faces} faces but the mesh has {mesh} cells and {mesh_faces} faces")]
    GeometryMismatch {
        /// Cells in the geometry.
        geometry: usize,
        /// Faces in the geometry.
        geometry_faces: usize,
        /// Cells in the mesh.
        mesh: usize,
        /// Faces in the mesh.
        mesh_faces: usize,
    },
    /// A patch entry the [`crate::cyclic`] pairs cannot use (type, `neighbourPatch`,
    /// `transform`, `separationVector`, non-matching faces).
    #[error("{}: `{key}`: {msg}", file.display())]
    Patch {
        /// The file holding the patch ([`crate::cyclic::BOUNDARY_FILE`], relative to the case).
        file: std::path::PathBuf,
        /// `patch.keyword`.
        key: String,
        /// What is wrong.
        msg: String,
    },
}
