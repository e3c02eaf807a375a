//! Voidage (void fraction) of spherical particles on OpenFOAM meshes.
//!
//! # Kernels (pure functions, SI units: m, m³)
//! * [`sphere_box_volume`], [`corner_volume`], [`sphere_grid_volumes`]: exact ball ∩
//!   axis-aligned box in closed form, and all boxes of a grid around a particle from shared
//!   corner values ([`sphere_box`] module docs);
//! * [`sphere_tet_volume`], [`sphere_polyhedron_volume`], [`triangle_flux`]: exact ball ∩
//!   tetrahedron / triangulated polyhedron by the divergence theorem ([`sphere_poly`]);
//! * [`cube_fraction`], [`khawaja_correction`], [`correct_and_renormalise`]: the circumscribing
//!   cube and Khawaja et al.'s (2012) corrected cube ([`cube`]);
//! * [`divided_offsets`]: CFDEM's 29 "divided" marker points ([`divided`]);
//! * [`trilinear_weights`], [`cfdem_lower_corner`]: CFDEM's trilinear weights over the 8 cell
//!   centres around a particle and its choice of their lower corner ([`trilinear`]);
//! * [`box_polygon_flux`], [`box_tet_volume`]: exact axis-aligned box ∩ polyhedron /
//!   tetrahedron from face terms ([`clip`]).
//!
//! # Models on a mesh
//! [`VoidageMesh`] prepares an OpenFOAM [`foam::PolyMesh`] (geometry, [`mesh::Locator`],
//! indexes) and deposits the volume of N particles ([`ParticleSet`]) into per-cell solid volume
//! with a [`Method`] — `centre`, `divided`, `trilinear` (uniform axis-aligned grids only),
//! `cube`, `corrected-cube`, `exact` or CFDEM's `bigParticle` — in parallel,
//! with every particle's volume either in a cell or counted outside the mesh ([`Deposit`]);
//! [`VoidageMesh::voidage`] turns it into ε = 1 − solid / cell volume ([`Voidage`]), optionally
//! clipped from below with the clipped volume reported. See the [`engine`] module docs for how
//! each method works on axis-aligned grids and on general meshes.
//!
//! ```
//! use voidage::{Method, ParticleSet, VoidageMesh};
//! let mesh = mesh::build::uniform_box([0.0; 3], [3e-3; 3], [3, 3, 3]);
//! let vm = VoidageMesh::new(&mesh)?;
//! let pos = [mesh::v3::V3::new(1.5e-3, 1.5e-3, 1.0e-3)];
//! let rad = [0.5e-3];
//! let dep = vm.deposit(Method::Exact, &ParticleSet::new(&pos, &rad))?;
//! assert!(dep.conservation_error() < 1e-12);
//! let eps = vm.voidage(&dep, None)?;
//! assert!(eps.epsilon.iter().all(|&e| e <= 1.0));
//! # Ok::<(), voidage::VoidageError>(())
//! ```

// `!(x > 0.0)` is used on purpose: it is also true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod clip;
pub mod cube;
pub mod divided;
pub mod engine;
mod error;
mod label_map;
pub mod memo;
mod method;
pub mod sphere_box;
pub mod sphere_poly;
pub mod trilinear;
mod vec3;

pub use clip::{box_polygon_flux, box_tet_volume, ClipScratch};
pub use engine::{
    voidage_field, CellShares, Deposit, MeshOptions, ParticleSet, Voidage, VoidageMesh,
};
pub use error::{ParticleProblem, VoidageError};
pub use memo::{DividedMemo, MEMO_CELLS};
pub use method::{Method, UnknownMethod};

pub use cube::{
    correct_and_renormalise, cube_axis_fraction, cube_fraction, khawaja_correction,
    KHAWAJA_COEFFICIENTS,
};
pub use divided::{
    divided_directions, divided_offsets, divided_radii, divided_shell_bounds, DIVIDED_MARKERS,
};
pub use sphere_box::{
    ball_volume, cap_volume, corner_volume, sphere_box_volume, sphere_grid_volumes, GridScratch,
};
pub use sphere_poly::{sphere_polyhedron_volume, sphere_tet_volume, triangle_flux, TET_FACES};
pub use trilinear::{cfdem_lower_corner, trilinear_weights, TRILINEAR_REQUIREMENT};
