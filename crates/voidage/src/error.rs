//! Typed errors of the voidage crate.

use crate::method::{Method, UnknownMethod};
use mesh::v3::V3;

/// What is wrong with one particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParticleProblem {
    /// A position coordinate is NaN or infinite.
    NonFinitePosition(V3),
    /// The radius is negative or NaN, or so large that its volume overflows.
    BadRadius(f64),
}

impl std::fmt::Display for ParticleProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParticleProblem::NonFinitePosition(p) => {
                write!(f, "non-finite position ({}, {}, {})", p[0], p[1], p[2])
            }
            ParticleProblem::BadRadius(r) => {
                write!(
                    f,
                    "radius {r} is not a non-negative length with a finite volume"
                )
            }
        }
    }
}

/// Why a voidage computation could not be done.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VoidageError {
    /// The mesh geometry or locator could not be built.
    #[error(transparent)]
    Mesh(#[from] mesh::MeshError),
    /// A particle has a bad position or radius (the first one found, by index).
    #[error("particle {index}{}: {problem}", id.map(|i| format!(" (id {i})")).unwrap_or_default())]
    InvalidParticle {
        /// 0-based index in the input arrays.
        index: usize,
        /// The particle's id, when ids were given.
        id: Option<u64>,
        /// What is wrong.
        problem: ParticleProblem,
    },
    /// Input arrays of different lengths.
    #[error("{what}: expected {expected} values, found {found}")]
    LengthMismatch {
        /// Which array.
        what: &'static str,
        /// Its expected length.
        expected: usize,
        /// Its length.
        found: usize,
    },
    /// `alpha_min` outside [0, 1) or not finite.
    #[error("alpha_min must lie in [0, 1), got {0}")]
    BadAlphaMin(f64),
    /// An unknown method name.
    #[error(transparent)]
    UnknownMethod(#[from] UnknownMethod),
    /// The method is not defined on this mesh (`trilinear` on a graded or unstructured mesh).
    #[error("voidage method `{method}` needs {requirement}; {problem}")]
    UnsupportedMesh {
        /// The method.
        method: Method,
        /// What the method needs of a mesh.
        requirement: &'static str,
        /// What this mesh lacks.
        problem: String,
    },
}
