//! Fluid cell fields at particle positions.
//!
//! Two rules ([`Interpolation`]):
//! * `cell`: the value of the cell holding the particle's centre (CFDEM's default, no
//!   `interpolation` switch in a force model's Props). A particle whose centre lies outside the
//!   mesh but whose volume overlaps it (continuous voidage methods) takes the smooth value, so a
//!   particle that exchanges momentum always sees a fluid velocity;
//! * `smooth`: the average over the cells the voidage kernel put the particle's volume in,
//!   weighted by the renormalised shares w_pc = V_pc / Σ_c V_pc (ADR 0004). With it the implicit
//!   exchange conserves momentum exactly (ADR 0004, conservation bullet).
//!
//! A particle with no share in any cell (outside the mesh) gets `None`. Units are those of the
//! field. Both rules reproduce a uniform field exactly (weights sum to 1 up to round-off).

use crate::error::CoupleError;
use foam::Label;
use mesh::v3::V3;
use rayon::prelude::*;
use std::fmt;
use std::str::FromStr;
use voidage::CellShares;

/// How fluid fields are evaluated at particles (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Interpolation {
    /// The cell holding the centre.
    #[default]
    Cell,
    /// The share-weighted average over the particle's cells.
    Smooth,
}

impl Interpolation {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Cell => "cell",
            Interpolation::Smooth => "smooth",
        }
    }
}

impl fmt::Display for Interpolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Interpolation {
    type Err = CoupleError;
    fn from_str(s: &str) -> Result<Self, CoupleError> {
        match s {
            "cell" => Ok(Interpolation::Cell),
            "smooth" => Ok(Interpolation::Smooth),
            _ => Err(CoupleError::Unknown {
                what: "interpolation",
                name: s.into(),
                valid: "cell, smooth".into(),
            }),
        }
    }
}

/// Where the particles are: the cell of each centre (`None` outside) and the voidage shares.
#[derive(Clone, Debug)]
pub struct Placement {
    /// Cell holding each particle's centre, `None` outside the mesh.
    pub centre: Vec<Option<Label>>,
    /// The (cell, volume) shares of each particle.
    pub shares: CellShares,
}

impl Placement {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.centre.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.centre.is_empty()
    }

    /// True when particle `i` has volume in at least one cell.
    pub fn inside(&self, i: usize) -> bool {
        self.shares.offsets[i + 1] > self.shares.offsets[i]
    }

    /// Calls `f(cell, w)` for each renormalised share w_pc of particle `i` (Σ w = 1).
    #[inline]
    pub fn for_each_weight(&self, i: usize, mut f: impl FnMut(Label, f64)) {
        let (cells, vols) = self.shares.of(i);
        let total: f64 = vols.iter().sum();
        if total > 0.0 {
            let inv = 1.0 / total;
            for (&c, &v) in cells.iter().zip(vols) {
                f(c, v * inv);
            }
        }
    }

    /// The value of `field` at particle `i` by `rule`, `None` outside the mesh.
    #[inline]
    pub fn value_at<T: Lerp>(&self, field: &[T], i: usize, rule: Interpolation) -> Option<T> {
        if !self.inside(i) {
            return None;
        }
        if let (Interpolation::Cell, Some(c)) = (rule, self.centre[i]) {
            return Some(field[c as usize]);
        }
        let mut acc = T::zero();
        self.for_each_weight(i, |c, w| acc = acc.add_scaled(w, field[c as usize]));
        Some(acc)
    }

    /// The values of `field` at every particle (parallel).
    pub fn values<T: Lerp>(&self, field: &[T], rule: Interpolation) -> Vec<Option<T>> {
        (0..self.len())
            .into_par_iter()
            .map(|i| self.value_at(field, i, rule))
            .collect()
    }
}

/// Values that can be averaged: scalars and vectors.
pub trait Lerp: Copy + Send + Sync {
    /// The zero value.
    fn zero() -> Self;
    /// `self + w·x`.
    fn add_scaled(self, w: f64, x: Self) -> Self;
}

impl Lerp for f64 {
    #[inline]
    fn zero() -> Self {
        0.0
    }
    #[inline]
    fn add_scaled(self, w: f64, x: Self) -> Self {
        self + w * x
    }
}

impl Lerp for V3 {
    #[inline]
    fn zero() -> Self {
        V3::zeros()
    }
    #[inline]
    fn add_scaled(self, w: f64, x: Self) -> Self {
        self + w * x
    }
}
