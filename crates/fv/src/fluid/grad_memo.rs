//! ∇U kept from the end of one step for the next step's momentum matrix.
//!
//! pisoFoam's k-ε model takes ∇U of the corrected velocity at the end of a step, and the next
//! step's momentum matrix takes ∇U again (for the `limitedLinearV` limiter and the stress's
//! explicit part) of the same velocity unless something changed it in between (a boundary
//! condition evaluated at the new time, a coupling that sets U). [`GradMemo`] keeps the
//! gradient with the cell and boundary values it was computed from and hands it out only when
//! the velocity is still those values bit for bit, so the result is the gradient computed
//! again, without computing it (on the 48³ cavity about 3 ms of a 140 ms step on 2 threads).
//! Its bits comparison, [`same_values`] for scalars, also serves the step's kept ε at faces
//! (`Fluid::eps_faces_kept`).

use crate::fvc::{self, Tensor};
use crate::geometry::{FvGeometry, V3};
use std::borrow::Cow;

/// A gradient of the velocity and the values it is the gradient of.
#[derive(Clone, Debug, Default)]
pub(super) struct GradMemo {
    u: Vec<V3>,
    u_b: Vec<V3>,
    grad: Vec<Tensor>,
}

/// True when `a` and `b` hold the same bits.
fn same_bits(a: &[V3], b: &[V3]) -> bool {
    same_by(a, b, |x, y| {
        (0..3).all(|k| x[k].to_bits() == y[k].to_bits())
    })
}

/// True when `a` and `b` hold the same bits (of the same length).
pub(super) fn same_values(a: &[f64], b: &[f64]) -> bool {
    same_by(a, b, |x, y| x.to_bits() == y.to_bits())
}

/// `a` and `b` of the same length and `eq` for each pair (in blocks on the team).
fn same_by<T: Sync>(a: &[T], b: &[T], eq: impl Fn(&T, &T) -> bool + Sync) -> bool {
    a.len() == b.len()
        && crate::reduce::all_blocks(a.len(), true, |r| {
            a[r.clone()].iter().zip(&b[r]).all(|(x, y)| eq(x, y))
        })
}

impl GradMemo {
    /// ∇U (Gauss linear, [`fvc::grad_vector`]) of cells `u` and boundary faces `u_b`, kept.
    pub(super) fn compute(g: &FvGeometry, u: &[V3], u_b: &[V3]) -> GradMemo {
        let mut keep = GradMemo {
            u: Vec::new(),
            u_b: Vec::new(),
            grad: fvc::grad_vector(g, u, u_b),
        };
        crate::gather::over(0..u.len())
            .map(|c| u[c])
            .collect_into(&mut keep.u);
        keep.u_b.extend_from_slice(u_b);
        keep
    }

    /// The gradient.
    pub(super) fn grad(&self) -> &[Tensor] {
        &self.grad
    }

    /// ∇U of `u`, `u_b`: the kept gradient when `memo` was computed from these values, else
    /// computed.
    pub(super) fn of<'m>(
        memo: Option<&'m GradMemo>,
        g: &FvGeometry,
        u: &[V3],
        u_b: &[V3],
    ) -> Cow<'m, [Tensor]> {
        match memo {
            Some(m) if same_bits(&m.u_b, u_b) && same_bits(&m.u, u) => Cow::Borrowed(&m.grad),
            _ => Cow::Owned(fvc::grad_vector(g, u, u_b)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kept_gradient_serves_only_the_velocity_it_was_computed_from() {
        let m = mesh::build::uniform_box([0.0; 3], [1.0, 0.8, 0.6], [4, 3, 2]);
        let g = FvGeometry::new(&m).unwrap();
        let u: Vec<V3> = (0..g.n_cells)
            .map(|c| V3::new(g.c[c][0] * g.c[c][1], 0.5 * g.c[c][2], -g.c[c][0]))
            .collect();
        let u_b = vec![V3::new(1.0, 0.0, 0.0); g.n_boundary()];
        let memo = GradMemo::compute(&g, &u, &u_b);
        assert_eq!(memo.grad(), &fvc::grad_vector(&g, &u, &u_b)[..]);
        assert!(matches!(
            GradMemo::of(Some(&memo), &g, &u, &u_b),
            Cow::Borrowed(_)
        ));
        // One cell changed, a boundary value changed, a zero's sign changed: computed again.
        let mut u2 = u.clone();
        u2[5][1] += 1e-12;
        let mut u_b2 = u_b.clone();
        u_b2[0][2] = -0.0;
        for (uu, ub) in [(&u2, &u_b), (&u, &u_b2)] {
            let got = GradMemo::of(Some(&memo), &g, uu, ub);
            assert!(matches!(got, Cow::Owned(_)));
            assert_eq!(&got[..], &fvc::grad_vector(&g, uu, ub)[..]);
        }
        assert!(matches!(GradMemo::of(None, &g, &u, &u_b), Cow::Owned(_)));
    }
}
