//! The Courant number of a fluid step from the face fluxes, as OpenFOAM v1912's
//! `CourantNo.H` defines it (the line `Courant Number mean: … max: …` of pisoFoam's log):
//!
//! * per cell, Co_c = ½ Δt Σ_f |φ_f| / V_c, the sum over the cell's faces (m³/s), V_c its
//!   volume (m³), Δt the fluid step (s) — for a uniform flow through a hexahedron this is
//!   |U| Δt / Δx, the seed's eq. (7);
//! * the mean, ½ Δt Σ_c Σ_f |φ_f| / Σ_c V_c (the volume-weighted mean of Co_c).
//!
//! Which flux `φ` is passed decides what is measured: the native VANS fluid and grainPisoFoam
//! write the flux of the fluid velocity they convect with. Checked against the line pisoFoam
//! prints on `tests/fixtures/fv/channel-keps` (relative 1e-12, `tests/courant.rs`).

use crate::geometry::FvGeometry;

/// The Courant numbers of one step (dimensionless).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Courant {
    /// Volume-weighted mean over the cells.
    pub mean: f64,
    /// Largest cell value.
    pub max: f64,
    /// The cell holding `max`.
    pub max_cell: usize,
}

/// Σ_f |φ_f| of every cell (m³/s): each internal face (cyclic pairs included) counts for both
/// its cells, each boundary face for its owner; `empty` faces carry no flux.
pub fn sum_abs_flux(g: &FvGeometry, phi: &[f64]) -> Vec<f64> {
    assert!(phi.len() >= g.n_faces(), "one flux per face");
    // The face loop's additions in its order, per cell (crate::gather; an `empty` face's |φ|
    // is +0.0, which adds nothing to a sum of non-negative terms).
    crate::gather::face_sums(g, |_| 0.0, |s, f, _| s + phi[f].abs())
}

/// The Courant numbers of a step `dt` (s) with face fluxes `phi` (m³/s, one per solver face,
/// as [`crate::fields::read_phi`] returns them).
pub fn courant(g: &FvGeometry, phi: &[f64], dt: f64) -> Courant {
    let sum = sum_abs_flux(g, phi);
    let mut c = Courant {
        mean: 0.0,
        max: 0.0,
        max_cell: 0,
    };
    for (i, (s, v)) in sum.iter().zip(&g.v).enumerate() {
        let co = 0.5 * s / v * dt;
        if co > c.max {
            c.max = co;
            c.max_cell = i;
        }
    }
    c.mean = 0.5 * sum.iter().sum::<f64>() / g.v.iter().sum::<f64>() * dt;
    c
}
