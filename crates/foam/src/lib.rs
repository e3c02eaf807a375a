//! OpenFOAM file I/O for foamgrain.
//!
//! This crate owns everything that touches OpenFOAM's files: the FoamFile tokenizer and
//! dictionary parser (ASCII and binary lists), the polyMesh data model and its readers/writers,
//! volScalarField/volVectorField read-modify-write, and the layout of a case (time directories,
//! `constant/`, `system/`, `processorN/`).
//!
//! Architecture invariant: no geometry and no physics here — only data as OpenFOAM stores it.
//! Every error names the file and the line (ASCII) or byte offset (binary) where it was found.

pub mod heap;
pub mod poly_mesh;
pub mod poly_mesh_io;

pub use heap::HeapBytes;
pub use poly_mesh::{FaceList, Label, Patch, PolyMesh, TopologyError};
pub use poly_mesh_io::{read_poly_mesh, write_poly_mesh};

pub mod binary;
pub mod case;
pub mod decomposed;
pub mod dict;
pub mod error;
pub mod field;
mod lexer;
pub mod parser;
pub mod pattern;

pub use binary::Arch;
pub use case::{Case, TimeDir};
pub use dict::{Dict, Entry, Item, LookupError, Value};
pub use error::{FoamError, Location, Result};
pub use field::{default_boundary, FieldKind, FieldValues, VolField};
pub use parser::{parse_bytes, parse_file, read_header, FoamFile, Format, Header};
pub mod writer;
pub use writer::{write_atomic, write_dict_file, Writer};
