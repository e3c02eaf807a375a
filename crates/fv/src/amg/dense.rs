//! The coarsest level's exact solve: dense LU factors with partial pivoting (Golub & Van Loan,
//! *Matrix Computations*, 4th ed., Alg. 3.4.1), the coarsest level having at most a few tens of
//! rows.

use super::Csr;

/// Dense LU factors with partial pivoting of the coarsest matrix.
#[derive(Clone, Debug)]
pub(super) struct DenseLu {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
}

impl DenseLu {
    /// The factors of `a` (its off-diagonal entries and diagonal summed into a dense matrix).
    pub(super) fn new(a: &Csr) -> DenseLu {
        let n = a.n();
        let mut lu = vec![0.0; n * n];
        for i in 0..n {
            lu[i * n + i] = a.diag[i];
            for k in a.row(i) {
                lu[i * n + a.col[k] as usize] += a.val[k];
            }
        }
        let mut piv: Vec<usize> = (0..n).collect();
        for c in 0..n {
            let p = (c..n)
                .max_by(|&x, &y| lu[x * n + c].abs().total_cmp(&lu[y * n + c].abs()))
                .unwrap_or(c);
            if p != c {
                for j in 0..n {
                    lu.swap(c * n + j, p * n + j);
                }
                piv.swap(c, p);
            }
            let d = lu[c * n + c];
            if d == 0.0 {
                continue;
            }
            for i in c + 1..n {
                let f = lu[i * n + c] / d;
                lu[i * n + c] = f;
                for j in c + 1..n {
                    lu[i * n + j] -= f * lu[c * n + j];
                }
            }
        }
        DenseLu { n, lu, piv }
    }

    /// x = A⁻¹ b (a zero pivot, a singular coarse matrix, leaves that unknown at 0).
    pub(super) fn solve(&self, b: &[f64], x: &mut [f64]) {
        let n = self.n;
        for i in 0..n {
            let mut s = b[self.piv[i]];
            for j in 0..i {
                s -= self.lu[i * n + j] * x[j];
            }
            x[i] = s;
        }
        for i in (0..n).rev() {
            let mut s = x[i];
            for j in i + 1..n {
                s -= self.lu[i * n + j] * x[j];
            }
            let d = self.lu[i * n + i];
            x[i] = if d == 0.0 { 0.0 } else { s / d };
        }
    }
}
