//! The spread of the voidage field inside the bed: the volume-weighted mean and standard
//! deviation of ε over the cells that lie wholly inside the bed (Volk et al. 2018, seed 001,
//! relate the growth of this spread at small cells to the solution error).
//!
//! mean = Σ V_c ε_c / Σ V_c, std = √(Σ V_c (ε_c − mean)² / Σ V_c) (population form: the cells
//! are the whole field, not a sample). On uniform grids this is the plain mean and standard
//! deviation of the cell values.

use serde::Serialize;

/// Mean and standard deviation of ε over a set of cells.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Spread {
    /// Volume-weighted mean ε.
    pub mean: f64,
    /// Volume-weighted standard deviation of ε.
    pub std: f64,
    /// Number of cells.
    pub cells: usize,
}

/// The spread of `eps` over `cells` with volumes `volumes` (module docs); `None` without
/// cells or with a zero total volume.
pub fn voidage_spread(eps: &[f64], volumes: &[f64], cells: &[usize]) -> Option<Spread> {
    let v: f64 = cells.iter().map(|&c| volumes[c]).sum();
    if cells.is_empty() || v.is_nan() || v <= 0.0 {
        return None;
    }
    let mean = cells.iter().map(|&c| volumes[c] * eps[c]).sum::<f64>() / v;
    let var = cells
        .iter()
        .map(|&c| volumes[c] * (eps[c] - mean).powi(2))
        .sum::<f64>()
        / v;
    Some(Spread {
        mean,
        std: var.sqrt(),
        cells: cells.len(),
    })
}

/// The cells of a tensor-product grid (numbered `i + nx (j + ny k)`, as blockMesh and
/// [`mesh::build::hex_grid`]) whose layer k lies wholly inside `[z0, z1]` along the third axis,
/// given the layer planes `zs` (nz + 1 values). A tolerance of 1e-9 of the layer height lets a
/// plane that coincides with the bed floor count as inside.
pub fn cells_in_layers(n: [usize; 3], zs: &[f64], z0: f64, z1: f64) -> Vec<usize> {
    let per_layer = n[0] * n[1];
    let mut out = Vec::new();
    for k in 0..n[2] {
        let (lo, hi) = (zs[k], zs[k + 1]);
        let tol = 1e-9 * (hi - lo);
        if lo >= z0 - tol && hi <= z1 + tol {
            out.extend(k * per_layer..(k + 1) * per_layer);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_by_hand() {
        // Volumes 1, 1, 2, 4 with ε 0.4, 0.5, 0.3, 0.6 (and a fifth cell left out):
        // mean = (0.4 + 0.5 + 0.6 + 2.4)/8 = 0.4875;
        // Σ V (ε − mean)² = 0.00765625 + 0.00015625 + 2·0.03515625 + 4·0.01265625 = 0.12875,
        // variance 0.12875/8 = 0.01609375, std = 0.1268611...
        let eps = [0.4, 0.5, 0.3, 0.6, 0.99];
        let vol = [1.0, 1.0, 2.0, 4.0, 100.0];
        let s = voidage_spread(&eps, &vol, &[0, 1, 2, 3]).unwrap();
        assert!((s.mean - 0.4875).abs() < 1e-15);
        assert!((s.std - 0.01609375f64.sqrt()).abs() < 1e-15);
        assert!((s.std - 0.126_861_1).abs() < 1e-7);
        assert_eq!(s.cells, 4);
        assert!(voidage_spread(&eps, &vol, &[]).is_none());
    }

    #[test]
    fn layers_inside_the_bed() {
        // 2 × 1 cells per layer, layers at 0, 1, 2, 3, 4: bed [1, 3.5] holds layers 1 and 2.
        let zs = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(cells_in_layers([2, 1, 4], &zs, 1.0, 3.5), vec![2, 3, 4, 5]);
        assert!(cells_in_layers([2, 1, 4], &zs, 0.5, 0.9).is_empty());
    }
}
