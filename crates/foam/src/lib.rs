//! OpenFOAM file I/O for foamgrain.
//!
//! This crate owns everything that touches OpenFOAM's files: the FoamFile tokenizer and
//! dictionary parser (ASCII and binary lists), the polyMesh data model and its readers/writers,
//! volScalarField/volVectorField read-modify-write, and the layout of a case (time directories,
//! `constant/`, `system/`, `processorN/`).
//!
//! Architecture invariant: no geometry and no physics here — only data as OpenFOAM stores it.
//! Every error names the file and the line (ASCII) or byte offset (binary) where it was found.

pub mod poly_mesh;

pub use poly_mesh::{FaceList, Label, Patch, PolyMesh, TopologyError};
