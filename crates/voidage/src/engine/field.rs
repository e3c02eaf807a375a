//! The voidage field ε = 1 − solid / cell volume of a deposit, optionally clipped from below
//! ([`Voidage`], [`voidage_field`]).

use super::{Deposit, VoidageMesh};
use crate::error::VoidageError;

/// A voidage field ε = 1 − solid / cell volume, optionally clipped from below.
#[derive(Clone, Debug, PartialEq)]
pub struct Voidage {
    /// ε per cell (dimensionless).
    pub epsilon: Vec<f64>,
    /// The floor applied, if any.
    pub alpha_min: Option<f64>,
    /// Solid volume removed by clipping, m³: Σ (alpha_min − ε)·V over clipped cells.
    pub clipped_volume: f64,
    /// Number of clipped cells.
    pub clipped_cells: usize,
    /// Smallest ε before clipping (1 for no cells).
    pub min_epsilon: f64,
    /// Cells with ε < 0 before clipping (more solid than cell volume).
    pub negative_cells: usize,
}

impl VoidageMesh {
    /// The voidage ε = 1 − solid / cell volume of a deposit, clipped to `alpha_min` when given
    /// (which must lie in [0, 1)).
    pub fn voidage(
        &self,
        deposit: &Deposit,
        alpha_min: Option<f64>,
    ) -> Result<Voidage, VoidageError> {
        voidage_field(&deposit.solid, self.cell_volumes(), alpha_min)
    }
}

/// ε = 1 − solid / V per cell, clipped to `alpha_min` when given (module docs).
pub fn voidage_field(
    solid: &[f64],
    cell_volumes: &[f64],
    alpha_min: Option<f64>,
) -> Result<Voidage, VoidageError> {
    if let Some(a) = alpha_min {
        if !(a.is_finite() && (0.0..1.0).contains(&a)) {
            return Err(VoidageError::BadAlphaMin(a));
        }
    }
    if solid.len() != cell_volumes.len() {
        return Err(VoidageError::LengthMismatch {
            what: "solid volumes",
            expected: cell_volumes.len(),
            found: solid.len(),
        });
    }
    let mut res = Voidage {
        epsilon: Vec::with_capacity(solid.len()),
        alpha_min,
        clipped_volume: 0.0,
        clipped_cells: 0,
        min_epsilon: 1.0,
        negative_cells: 0,
    };
    for (&s, &vc) in solid.iter().zip(cell_volumes) {
        let mut e = 1.0 - s / vc;
        res.min_epsilon = res.min_epsilon.min(e);
        if e < 0.0 {
            res.negative_cells += 1;
        }
        if let Some(a) = alpha_min {
            if e < a {
                res.clipped_volume += (a - e) * vc;
                res.clipped_cells += 1;
                e = a;
            }
        }
        res.epsilon.push(e);
    }
    Ok(res)
}
