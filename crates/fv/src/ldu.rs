//! The sparse matrix of a finite-volume equation in OpenFOAM's LDU layout: one diagonal
//! coefficient per cell, one upper (owner row, neighbour column) and one lower (neighbour row,
//! owner column) coefficient per internal face — the layout the equations are assembled in —
//! and its row-wise copy ([`RowMatrix`]) that the linear solvers iterate over.
//!
//! The row form keeps, for each cell, first the faces it is the neighbour of (the strictly
//! lower part, columns below the row since owner < neighbour) and then the faces it owns (the
//! upper part), each in increasing face order. On a mesh in OpenFOAM's upper-triangular face
//! order this is the order in which OpenFOAM's face loops accumulate into a cell, so a row sum
//! here has the same terms in the same order (bit-identical results); the products gather per
//! row, so they run in parallel without atomics, and the triangular sweeps keep the running
//! value in a register instead of scattering it through memory.

// Row loops index several arrays by the same row or entry, as the equations do.
#![allow(clippy::needless_range_loop)]

use crate::geometry::FvGeometry;

/// Rows at least this long are multiplied in parallel: below it, handing work to rayon's pool
/// (a wake-up and a context switch per operation) costs more than it saves.
pub const PAR_MIN: usize = 50_000;

/// Row-wise (CSR) addressing of the LDU matrix of a mesh, computed once per mesh.
///
/// The faces of cyclic pairs (faces `n_plain..` of the internal faces, see
/// [`crate::FvGeometry`]) are the matrix's *interfaces*, as OpenFOAM keeps coupled patches
/// apart from the triangular face loops: their entries come last in each row
/// (`end[c]..start[c + 1]`), the matrix products include them, and the incomplete
/// factorisations and Gauss–Seidel sweeps treat them as v1912 treats `cyclic` interfaces (left
/// out of DIC/DILU, explicit with the values of the sweep's start in Gauss–Seidel).
#[derive(Clone, Debug, PartialEq)]
pub struct RowAddressing {
    /// Start of each row's entries (length `n_cells + 1`).
    pub start: Vec<u32>,
    /// First upper entry of each row: entries `start[c]..mid[c]` are the faces with `c` as
    /// neighbour (column: the owner), `mid[c]..end[c]` the faces `c` owns (column: the
    /// neighbour), each in increasing face order.
    pub mid: Vec<u32>,
    /// End of each row's triangular entries: `end[c]..start[c + 1]` are its interface entries
    /// (cyclic pair faces with `c` on either side, in face order; column: the other cell).
    pub end: Vec<u32>,
    /// Per entry: true when its coefficient is the face's `lower` one (row = the face's
    /// neighbour), false for `upper` (row = owner); a face coupling a cell with itself has
    /// one entry of each.
    pub is_lower: Vec<bool>,
    /// Column (the other cell) of each entry.
    pub col: Vec<u32>,
    /// Internal face of each entry.
    pub face: Vec<u32>,
    /// The multi-threaded Gauss–Seidel schedule of these rows, made at its first use
    /// ([`RowAddressing::pipeline`]).
    pipeline: PipelineCache,
}

/// A lazily made [`crate::sweep::Schedule`]: not part of the addressing's value (a clone starts
/// empty, equality ignores it).
#[derive(Default)]
struct PipelineCache(std::sync::OnceLock<Option<crate::sweep::Schedule>>);

impl Clone for PipelineCache {
    fn clone(&self) -> Self {
        PipelineCache::default()
    }
}

impl PartialEq for PipelineCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for PipelineCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PipelineCache")
    }
}

impl RowAddressing {
    /// The addressing of the internal faces of a mesh of `n_cells`: faces `0..n_plain` with
    /// `owner[f] < neighbour[f]`, the rest interfaces (any two cells).
    pub fn new(n_cells: usize, owner: &[u32], neighbour: &[u32], n_plain: usize) -> Self {
        let mut n_lower = vec![0u32; n_cells];
        let mut n_upper = vec![0u32; n_cells];
        let mut n_iface = vec![0u32; n_cells];
        for (f, (&o, &n)) in owner.iter().zip(neighbour).enumerate() {
            if f < n_plain {
                n_upper[o as usize] += 1;
                n_lower[n as usize] += 1;
            } else {
                n_iface[o as usize] += 1;
                n_iface[n as usize] += 1;
            }
        }
        let mut start = vec![0u32; n_cells + 1];
        let mut mid = vec![0u32; n_cells];
        let mut end = vec![0u32; n_cells];
        for c in 0..n_cells {
            mid[c] = start[c] + n_lower[c];
            end[c] = mid[c] + n_upper[c];
            start[c + 1] = end[c] + n_iface[c];
        }
        let total = start[n_cells] as usize;
        let mut col = vec![0u32; total];
        let mut face = vec![0u32; total];
        let mut is_lower = vec![false; total];
        let mut next_lower: Vec<u32> = start[..n_cells].to_vec();
        let mut next_upper = mid.clone();
        let mut next_iface = end.clone();
        let mut put = |slot: &mut u32, c: u32, f: usize, lower: bool| {
            let k = *slot as usize;
            *slot += 1;
            col[k] = c;
            face[k] = f as u32;
            is_lower[k] = lower;
        };
        for (f, (&o, &n)) in owner.iter().zip(neighbour).enumerate() {
            if f < n_plain {
                put(&mut next_lower[n as usize], o, f, true);
                put(&mut next_upper[o as usize], n, f, false);
            } else {
                // Both sides of an interface face go into the interface part.
                put(&mut next_iface[n as usize], o, f, true);
                put(&mut next_iface[o as usize], n, f, false);
            }
        }
        RowAddressing {
            start,
            mid,
            end,
            is_lower,
            col,
            face,
            pipeline: PipelineCache::default(),
        }
    }

    /// The schedule on which Gauss–Seidel sweeps of these rows run on several threads with
    /// the sequential sweep's bits ([`crate::sweep`]); `None` below [`PAR_MIN`] rows or where
    /// the numbering leaves nothing to run side by side. Made once, at the first call.
    pub(crate) fn pipeline(&self) -> Option<&crate::sweep::Schedule> {
        self.pipeline
            .0
            .get_or_init(|| {
                (self.n_rows() >= PAR_MIN)
                    .then(|| crate::sweep::Schedule::new(self))
                    .flatten()
            })
            .as_ref()
    }

    /// True when row `c`'s entry `k` is an interface entry.
    #[inline]
    pub fn is_interface(&self, c: usize, k: usize) -> bool {
        k >= self.end[c] as usize
    }

    /// Number of rows.
    pub fn n_rows(&self) -> usize {
        self.mid.len()
    }

    /// The entries of row `c` (lower part, then upper part).
    #[inline]
    pub fn row(&self, c: usize) -> std::ops::Range<usize> {
        self.start[c] as usize..self.start[c + 1] as usize
    }
}

/// A square matrix with the sparsity of the mesh's cell–face graph, in LDU layout.
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
        let r = &g.rows;
        let mut s = 0.0;
        for k in r.row(c) {
            s += self.coef(r, k) * x[r.col[k] as usize];
        }
        s
    }

    /// The coefficient of entry `k` of the row addressing `r`.
    #[inline]
    pub fn coef(&self, r: &RowAddressing, k: usize) -> f64 {
        let f = r.face[k] as usize;
        if r.is_lower[k] {
            self.lower[f]
        } else {
            self.upper[f]
        }
    }

    /// `y = A x` (the same bits as [`RowMatrix::mul`]).
    pub fn mul(&self, g: &FvGeometry, x: &[f64], y: &mut [f64]) {
        RowMatrix::new(self, g).mul(x, y);
    }
}

/// An [`Ldu`] matrix copied into row order (see the module doc): what the solvers iterate over.
#[derive(Clone, Debug)]
pub struct RowMatrix<'a> {
    /// The row addressing of the mesh.
    pub rows: &'a RowAddressing,
    /// Diagonal, one per row.
    pub diag: &'a [f64],
    /// Off-diagonal coefficient of each entry of [`RowAddressing`] (borrowed by the views of
    /// [`RowMatrix::with_diag`]).
    pub coef: std::borrow::Cow<'a, [f64]>,
}

impl<'a> RowMatrix<'a> {
    /// The row form of `a` on the mesh of `g`.
    pub fn new(a: &'a Ldu, g: &'a FvGeometry) -> Self {
        let r = &g.rows;
        // Each entry on its own (in parallel on large meshes: the same values).
        let coef = if r.n_rows() < PAR_MIN {
            (0..r.col.len()).map(|k| a.coef(r, k)).collect()
        } else {
            crate::team::collect(r.col.len(), crate::reduce::BLOCK, |k| a.coef(r, k))
        };
        RowMatrix {
            rows: r,
            diag: &a.diag,
            coef: std::borrow::Cow::Owned(coef),
        }
    }

    /// The matrix with these off-diagonal coefficients and the diagonal `diag` (one per row):
    /// a component of a vector equation whose components differ in the diagonal only.
    pub fn with_diag<'b>(&'b self, diag: &'b [f64]) -> RowMatrix<'b> {
        assert_eq!(diag.len(), self.diag.len(), "one diagonal entry per row");
        RowMatrix {
            rows: self.rows,
            diag,
            coef: std::borrow::Cow::Borrowed(&self.coef),
        }
    }

    /// Row `c` of `A x`: d_c x_c + Σ a_ck x_k, the terms in row order.
    #[inline(always)]
    pub fn row_times(&self, c: usize, x: &[f64]) -> f64 {
        let (a, b) = (self.rows.start[c] as usize, self.rows.start[c + 1] as usize);
        let mut s = self.diag[c] * x[c];
        for (&j, &v) in self.rows.col[a..b].iter().zip(&self.coef[a..b]) {
            s += v * x[j as usize];
        }
        s
    }

    /// `y = A x` (parallel over rows on large meshes; the same bits either way).
    pub fn mul(&self, x: &[f64], y: &mut [f64]) {
        let parallel = y.len() >= PAR_MIN;
        crate::reduce::fill(y, parallel, |c, _| self.row_times(c, x));
    }

    /// `y = A x` and returns Σ x·y (summed in row order on small meshes, as
    /// [`crate::linsolve`]'s dot products are).
    pub fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        if y.len() < PAR_MIN {
            let mut d = 0.0;
            for (c, yc) in y.iter_mut().enumerate() {
                *yc = self.row_times(c, x);
                d += x[c] * *yc;
            }
            d
        } else {
            // One pass, the additions of `mul` then `linsolve::dot` (`reduce::dot_blocked`).
            let [d] = crate::reduce::fill_and_sum(y, true, |c| {
                let yc = self.row_times(c, x);
                (yc, [x[c] * yc])
            });
            d
        }
    }
}
