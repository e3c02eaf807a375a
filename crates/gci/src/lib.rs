//! The Grid Convergence Index of a grid-refinement study, after Celik, Ghia, Roache, Freitas,
//! Coleman & Raad (2008), "Procedure for estimation and reporting of uncertainty due to
//! discretization in CFD applications", J. Fluids Eng. 130, 078001 (equation numbers below are
//! that paper's).
//!
//! Owns: the representative cell size h ([`size`], eqs. 1–2), the convergence classification and
//! the apparent order p by fixed-point iteration ([`order`], eqs. 3a–3c), the per-triplet
//! estimates — extrapolated value, approximate and extrapolated relative errors, GCI_fine
//! ([`triplet`], eqs. 4–7) — successive triplets of three or more grids ([`study`]), and the
//! reading of a `(cells or h, value…)` table from CSV text with errors naming the file and line
//! ([`table`]). No physics and no file system: callers hand over text or numbers.
//!
//! Start with [`table::GridTable::parse_csv`] (or [`table::GridTable::from_lists`]), then
//! [`table::GridTable::grids`] for one quantity and [`study::analyse_study`]; each
//! [`triplet::Triplet`] carries its [`order::Behaviour`] and either an
//! [`triplet::Estimate`] or the [`order::Undefined`] reason why p has no meaning (divergence,
//! a zero change between two grids). Undefined quantities are never numbers: no NaN reaches a
//! caller.

pub mod error;
pub mod order;
pub mod size;
pub mod study;
pub mod table;
pub mod triplet;

pub use error::{GciError, Location};
pub use order::{apparent_order, classify, Behaviour, Method, Order, Undefined};
pub use size::{representative_size, Dim};
pub use study::{analyse_study, Grid};
pub use table::{GridTable, SizeKind};
pub use triplet::{analyse, Estimate, Outcome, Pair, RelativeErrors, Settings, Triplet, Warning};
