//! The representative cell size of a grid, Celik et al. (2008) eqs. (1)–(2).

use serde::Serialize;

/// The number of space dimensions a grid resolves (the root taken in eqs. 1–2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(into = "u8")]
pub enum Dim {
    /// h = L/N.
    One,
    /// h = (A/N)^(1/2), eq. (2).
    Two,
    /// h = (V/N)^(1/3), eq. (1).
    Three,
}

impl Dim {
    /// The dimension from its number (1, 2 or 3).
    pub fn from_number(d: u8) -> Option<Dim> {
        match d {
            1 => Some(Dim::One),
            2 => Some(Dim::Two),
            3 => Some(Dim::Three),
            _ => None,
        }
    }

    /// 1, 2 or 3.
    pub fn number(self) -> u8 {
        match self {
            Dim::One => 1,
            Dim::Two => 2,
            Dim::Three => 3,
        }
    }
}

impl From<Dim> for u8 {
    fn from(d: Dim) -> u8 {
        d.number()
    }
}

/// Representative cell size h = (measure/N)^(1/d): Celik et al. (2008) eq. (1) in 3-D
/// (measure = total volume ΣΔV_i, m³ → h in m), eq. (2) in 2-D (measure = total area ΣΔA_i, m²).
/// With `measure = 1` h is relative (unit-free), which leaves every refinement ratio unchanged
/// when all grids cover the same domain. Exact up to one `powf` rounding (≈1 ulp).
pub fn representative_size(measure: f64, cells: f64, dim: Dim) -> f64 {
    match dim {
        Dim::One => measure / cells,
        Dim::Two => (measure / cells).sqrt(),
        Dim::Three => (measure / cells).cbrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn celik_two_dimensional_ratios() {
        // Celik et al. (2008) Table 1: N = 18000, 8000, 4500 in 2-D gives r21 = 1.5, r32 = 1.333.
        let h: Vec<f64> = [18000.0, 8000.0, 4500.0]
            .iter()
            .map(|&n| representative_size(76.0, n, Dim::Two))
            .collect();
        assert!((h[1] / h[0] - 1.5).abs() < 1e-15);
        assert!((h[2] / h[1] - 4.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn cube_of_eight_cells() {
        // A unit cube cut into 2×2×2 cells has cells of edge 0.5 m.
        assert_eq!(representative_size(1.0, 8.0, Dim::Three), 0.5);
        assert_eq!(representative_size(2.0, 8.0, Dim::One), 0.25);
    }
}
