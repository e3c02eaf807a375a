//! CFDEM's `GaussVoidFraction` (CFDEMcoupling-PUBLIC `voidFractionModel/GaussVoidFraction`),
//! with its weights normalised: the particle volume V is spread over the cells whose centre
//! lies within 3σ of the particle centre (σ = r, the particle radius; reached from the
//! centre's cell through internal faces, as `bigParticle`'s cells are, and the centre's cell
//! itself) in proportion to a Gaussian of the distance d_c from the particle centre to the
//! cell centre times the cell volume,
//!
//!   V_c = V · g(d_c) V_cell,c / Σ_k g(d_k) V_cell,k,   g(d) = e^(−d²/(2σ²)).
//!
//! CFDEM's own code multiplies the volume by (2/(π r²))^(3/2) e^(−d²/(2r²)) V_cell, eight times
//! the normalised Gaussian (2π r²)^(−3/2) e^(−d²/(2r²)), and does not normalise, so its shares
//! add up to about 8 V (CFDEM stops on the model: "does not yet work properly"). foamgrain
//! normalises by the sum over the cells actually reached, so each particle's volume is
//! conserved exactly (to round-off) whatever the mesh, and the distribution is the Gaussian
//! CFDEM intends, truncated at 3σ and sampled at the cell centres: on a mesh fine against σ
//! its second moment Σ V_c d_c² / V tends to the truncated Gaussian's, 3σ²·(I₄/I₂)/3 with
//! I_n = ∫₀³ tⁿ e^(−t²/2) dt (`tests/gauss.rs`). A particle much smaller than the cells puts
//! its whole volume into its centre's cell (centre's rule). A particle whose centre is outside
//! the mesh is counted outside. Not continuous: a share jumps when a cell centre crosses the
//! 3σ sphere (by g(3σ) = e^(−4.5) ≈ 1.1 % of the peak weight).

use super::{Ball, Scratch, VoidageMesh};
use foam::Label;

/// The kernel's reach in standard deviations (CFDEM's `buildLabelHashSet(3 r, …)`).
pub const GAUSS_REACH: f64 = 3.0;

impl VoidageMesh {
    /// Pushes the shares of one particle by the normalised Gaussian rule (module docs) and
    /// returns its volume outside the mesh.
    pub(super) fn gauss(&self, b: Ball, s: &mut Scratch, out: &mut Vec<(Label, f64)>) -> f64 {
        let sigma = b.r;
        if !self.cells_within(b, GAUSS_REACH * sigma, s) {
            return b.v;
        }
        let centres = &self.geom.cell_centres;
        let volumes = &self.geom.cell_volumes;
        let start = out.len();
        let mut total = 0.0;
        for &c in &s.candidates {
            let d2 = (centres[c as usize] - b.c).norm_squared();
            let w = (-d2 / (2.0 * sigma * sigma)).exp() * volumes[c as usize];
            total += w;
            out.push((c, w));
        }
        if !(total > 0.0) {
            // every weight underflowed (a particle far from every reached cell centre): the
            // centre's cell holds it
            out.truncate(start);
            out.push((s.candidates[0], b.v));
            return 0.0;
        }
        for share in &mut out[start..] {
            share.1 *= b.v / total;
        }
        0.0
    }
}
