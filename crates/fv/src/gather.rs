//! Cell loops of the assembly, in parallel without changing a bit.
//!
//! OpenFOAM assembles by face loops that scatter into the two cells of each face
//! (`diag[owner] += …; diag[neighbour] += …` for every face in increasing order). A cell's
//! value is then the sum of its faces' terms in increasing face order, owner side before
//! neighbour side for a face that has the cell on both (a cyclic face coupling a cell with
//! itself). [`face_sums`] gathers exactly those terms in exactly that order for each cell
//! from its face list ([`FvGeometry::faces_of`], sorted by face), so the result is the
//! scatter's bit for bit on any mesh — face order, not the upper-triangular order of the
//! matrices' rows, decides it — and each cell is computed on its own, so the cells run in
//! parallel. [`cells`] is the parallel map of a loop whose iterations are independent.
//! Both run sequentially below [`PAR_MIN`] cells, where handing work to the pool costs more
//! than it saves.

use crate::geometry::FvGeometry;
use crate::ldu::PAR_MIN;

/// For every cell `c`: `init(c)`, then `add(acc, f, owner)` for each of its faces `f` in
/// increasing face order (`owner`: `c` is the face's owner; boundary faces of `empty`
/// patches are not among a cell's faces). The same bits as the face loop
/// `for f in faces { acc[owner[f]] = add(acc[owner[f]], f, true); if internal,
/// acc[neighbour[f]] = add(acc[neighbour[f]], f, false) }` over the internal faces and then the
/// non-empty boundary faces (see the module doc).
pub fn face_sums<T, I, A>(g: &FvGeometry, init: I, add: A) -> Vec<T>
where
    T: Send,
    I: Fn(usize) -> T + Sync,
    A: Fn(T, usize, bool) -> T + Sync,
{
    let one = |c: usize| {
        let mut acc = init(c);
        let mut last = usize::MAX;
        for &f in g.faces_of(c) {
            let f = f as usize;
            // A face listed twice couples the cell with itself: owner side first.
            let owner = g.owner[f] as usize == c && f != last;
            acc = add(acc, f, owner);
            last = f;
        }
        acc
    };
    cells(g.n_cells, one)
}

/// `(0..n).map(f)`, in parallel over cells when `n` ≥ [`PAR_MIN`] (each value computed on its
/// own, so the same bits either way).
pub fn cells<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    if n >= PAR_MIN {
        crate::team::collect(n, crate::reduce::BLOCK, f)
    } else {
        (0..n).map(f).collect()
    }
}

/// A range of indices to map on the team ([`over`]).
pub struct Over(std::ops::Range<usize>);

/// The loop `range.map(f)` on the team when the range has ≥ [`PAR_MIN`] indices, else in
/// order (each value computed on its own: the same values either way):
/// `over(0..n).map(f).collect()`.
pub fn over(range: std::ops::Range<usize>) -> Over {
    Over(range)
}

impl Over {
    /// Each index `i` of the range to `f(i)`.
    pub fn map<T, F: Fn(usize) -> T + Sync>(self, f: F) -> Mapped<F> {
        Mapped { range: self.0, f }
    }
}

/// [`Over::map`]'s loop, run by [`Mapped::collect`], [`Mapped::collect_into`] or
/// [`Mapped::unzip`].
pub struct Mapped<F> {
    range: std::ops::Range<usize>,
    f: F,
}

impl<F> Mapped<F> {
    /// The values in index order.
    pub fn collect<T: Send>(self) -> Vec<T>
    where
        F: Fn(usize) -> T + Sync,
    {
        let mut v = Vec::new();
        self.collect_into(&mut v);
        v
    }

    /// The values appended to `out` in index order.
    pub fn collect_into<T: Send>(self, out: &mut Vec<T>)
    where
        F: Fn(usize) -> T + Sync,
    {
        let Mapped { range, f } = self;
        let lo = range.start;
        if range.len() < PAR_MIN {
            out.extend(range.map(f));
        } else {
            crate::team::collect_into(out, range.len(), crate::reduce::BLOCK, |i| f(lo + i));
        }
    }

    /// The pairs' first and second values, each in index order.
    pub fn unzip<A: Send, B: Send>(self) -> (Vec<A>, Vec<B>)
    where
        F: Fn(usize) -> (A, B) + Sync,
    {
        let Mapped { range, f } = self;
        let (lo, n) = (range.start, range.len());
        if n < PAR_MIN {
            return range.map(f).unzip();
        }
        crate::team::collect_unzip(n, crate::reduce::BLOCK, |i| f(lo + i))
    }
}

/// `f(i, &mut v[i])` for every element, in parallel when `v` has ≥ [`PAR_MIN`] elements.
pub fn each_mut<T: Send>(v: &mut [T], f: impl Fn(usize, &mut T) + Sync) {
    if v.len() >= PAR_MIN {
        crate::team::each_mut(v, crate::reduce::BLOCK, f);
    } else {
        v.iter_mut().enumerate().for_each(|(i, x)| f(i, x));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The face loop `face_sums` stands for, written as OpenFOAM writes it.
    fn scatter(g: &FvGeometry, v: &[f64]) -> Vec<f64> {
        let mut acc: Vec<f64> = (0..g.n_cells).map(|c| 0.1 * c as f64).collect();
        for f in 0..g.n_internal {
            acc[g.owner[f] as usize] += v[f];
            acc[g.neighbour[f] as usize] -= 0.5 * v[f];
        }
        for f in g.n_internal..g.n_faces() {
            if !g.boundary_empty[f - g.n_internal] {
                acc[g.owner[f] as usize] += v[f];
            }
        }
        acc
    }

    fn gathered(g: &FvGeometry, v: &[f64]) -> Vec<f64> {
        face_sums(
            g,
            |c| 0.1 * c as f64,
            |a, f, own| if own { a + v[f] } else { a - 0.5 * v[f] },
        )
    }

    #[test]
    fn a_gather_gives_the_face_loops_bits_on_any_face_order_and_thread_count() {
        // 3-D so that a cell has six faces, ≥ PAR_MIN cells so that the cells run in
        // parallel; values of very different magnitudes so that a different summation order
        // would show in the last bits.
        let m = mesh::build::uniform_box([0.0; 3], [1.0, 0.7, 0.4], [40, 40, 32]);
        let g = FvGeometry::new(&m).unwrap();
        assert!(g.n_cells >= PAR_MIN);
        let v: Vec<f64> = (0..g.n_faces())
            .map(|f| ((f * 37 % 101) as f64).exp2().sin() * 10f64.powi((f % 13) as i32 - 6))
            .collect();
        let expect = scatter(&g, &v);
        assert_eq!(gathered(&g, &v), expect);
        // The same on a pool of 1 and 3 threads, and with the faces' neighbours out of
        // OpenFOAM's upper-triangular order (the owner/neighbour of every other face
        // swapped, the face list rebuilt): the gather follows the face order, not the rows.
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| gathered(&g, &v)), expect);
        }
        let mut h = g.clone();
        for f in (0..h.n_internal).step_by(2) {
            let (o, n) = (h.owner[f], h.neighbour[f]);
            h.owner[f] = n;
            h.neighbour[f] = o;
        }
        assert_eq!(gathered(&h, &v), scatter(&h, &v));
        // A sum that differs from the face loop's only by its order differs in the bits
        // here, so the test can tell the orders apart.
        let reversed: Vec<f64> = (0..g.n_cells)
            .map(|c| {
                g.faces_of(c).iter().rev().fold(0.1 * c as f64, |a, &f| {
                    let f = f as usize;
                    if g.owner[f] as usize == c {
                        a + v[f]
                    } else {
                        a - 0.5 * v[f]
                    }
                })
            })
            .collect();
        assert_ne!(reversed, expect);
    }
}
