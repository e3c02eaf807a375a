//! The sparse matrix of a finite-volume equation in OpenFOAM's LDU layout: one diagonal
//! coefficient per cell, one upper (owner row, neighbour column) and one lower (neighbour row,
//! owner column) coefficient per internal face. Products gather over each cell's faces, so they
//! run in parallel without atomics.

use crate::geometry::FvGeometry;
use rayon::prelude::*;

/// A square matrix with the sparsity of the mesh's cell–face graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Ldu {
    /// Diagonal, one per cell.
    pub diag: Vec<f64>,
    /// Coefficient of the neighbour's value in the owner's row, one per internal face.
    pub upper: Vec<f64>,
    /// Coefficient of the owner's value in the neighbour's row, one per internal face.
    pub lower: Vec<f64>,
}

impl Ldu {
    /// The zero matrix for `g`.
    pub fn zeros(g: &FvGeometry) -> Self {
        Ldu {
            diag: vec![0.0; g.n_cells],
            upper: vec![0.0; g.n_internal],
            lower: vec![0.0; g.n_internal],
        }
    }

    /// True when `upper == lower` (bitwise equal coefficients).
    pub fn is_symmetric(&self) -> bool {
        self.upper == self.lower
    }

    /// Σ of the off-diagonal coefficients of row `c` times `x` of the other cells.
    #[inline]
    pub fn off_row(&self, g: &FvGeometry, c: usize, x: &[f64]) -> f64 {
        let mut s = 0.0;
        for &f in g.faces_of(c) {
            let f = f as usize;
            if f >= g.n_internal {
                continue;
            }
            if g.owner[f] as usize == c {
                s += self.upper[f] * x[g.neighbour[f] as usize];
            } else {
                s += self.lower[f] * x[g.owner[f] as usize];
            }
        }
        s
    }

    /// `y = A x` (parallel over cells on large meshes).
    pub fn mul(&self, g: &FvGeometry, x: &[f64], y: &mut [f64]) {
        let row = |(c, yc): (usize, &mut f64)| *yc = self.diag[c] * x[c] + self.off_row(g, c, x);
        if y.len() < crate::linsolve::PAR_MIN {
            // OpenFOAM's face loop: no branches, contiguous coefficient arrays.
            for c in 0..y.len() {
                y[c] = self.diag[c] * x[c];
            }
            for f in 0..self.upper.len() {
                let (o, n) = (g.owner[f] as usize, g.neighbour[f] as usize);
                y[o] += self.upper[f] * x[n];
                y[n] += self.lower[f] * x[o];
            }
        } else {
            y.par_iter_mut().enumerate().for_each(row);
        }
    }
}
