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
//! * [`divided_offsets`]: CFDEM's 29 "divided" marker points ([`divided`]).

// `!(x > 0.0)` is used on purpose: it is also true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod cube;
pub mod divided;
pub mod sphere_box;
pub mod sphere_poly;
mod vec3;

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
