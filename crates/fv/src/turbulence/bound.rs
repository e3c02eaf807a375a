//! Keeping k and ε positive after a solve, as OpenFOAM v1912's `bound(field, min)` does: when
//! the smallest cell or boundary value is below `min`, every cell at or below zero takes the
//! area-weighted average of its faces' values of max(x, min) (the faces linearly interpolated,
//! boundary faces their own values), and then every value at least `min`. Cells with a positive
//! value below `min` are just raised to `min`.

use crate::fvc::{self, Field};
use crate::geometry::FvGeometry;

/// Bounds the cell values `x` and boundary values `x_b` (one per boundary face; `empty` faces
/// ignored) from below by `min` (same unit as x). Returns true when anything changed.
pub fn bound(g: &FvGeometry, x: &mut [f64], x_b: &mut [f64], min: f64) -> bool {
    let live_b = |b: usize| !g.boundary_empty[b];
    let lowest = x
        .iter()
        .copied()
        .chain((0..x_b.len()).filter(|&b| live_b(b)).map(|b| x_b[b]))
        .fold(f64::INFINITY, f64::min);
    if lowest >= min {
        return false;
    }
    let xm: Vec<f64> = x.iter().map(|&v| v.max(min)).collect();
    let xmb: Vec<f64> = x_b.iter().map(|&v| v.max(min)).collect();
    let faces = fvc::interpolate(g, Field::new(&xm, &xmb));
    let mut sum = vec![0.0; g.n_cells];
    let mut area = vec![0.0; g.n_cells];
    for c in 0..g.n_cells {
        for &f in g.faces_of(c) {
            let f = f as usize;
            sum[c] += g.mag_sf[f] * faces[f];
            area[c] += g.mag_sf[f];
        }
    }
    for c in 0..g.n_cells {
        let avg = sum[c] / area[c];
        let pos0 = if -x[c] >= 0.0 { 1.0 } else { 0.0 };
        x[c] = x[c].max(avg * pos0).max(min);
    }
    for v in x_b.iter_mut() {
        *v = v.max(min);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_negative_cell_takes_its_neighbours_average_and_small_ones_the_minimum() {
        let mesh = mesh::build::hex_grid(&[0.0, 1.0, 2.0, 3.0], &[0.0, 1.0], &[0.0, 1.0]);
        let g = FvGeometry::new(&mesh).unwrap();
        let mut x = vec![2.0, -1.0, 1e-20];
        let mut xb = vec![2.0; g.n_boundary()];
        // Boundary faces of the middle cell carry its value in a real field.
        for f in g.n_internal..g.n_faces() {
            let o = g.owner[f] as usize;
            xb[f - g.n_internal] = x[o];
        }
        assert!(bound(&g, &mut x, &mut xb, 1e-10));
        // Middle cell: faces x = 2 (left), interpolated ½(2 + 1e-10)… here (2 + 1e-10)/2 and
        // (1e-10 + 1e-10)/2 to the right, and its four side faces at max(−1, 1e-10).
        let left = 0.5 * (2.0 + 1e-10);
        let right = 1e-10;
        let expect = (left + right + 4.0 * 1e-10) / 6.0;
        assert!((x[1] - expect).abs() < 1e-15, "{}", x[1]);
        assert_eq!(x[2], 1e-10);
        assert_eq!(x[0], 2.0);
    }
}
