//! The particles' conduction as a continuum: CFDEM-PFM's `heatTransferInterGrain`
//! (`energyModel/heatTransferInterGrain`, explicit, without radiation).
//!
//! PFM's model is not contact conduction between touching particles (foamgrain's DEM does that
//! with `fix heat/gran`): per cell c, with the particle temperature field T_p (the cells'
//! share-weighted mean particle temperature, PFM's `partTemp`, zeroGradient on the boundary),
//! the solid fraction α_c = 1 − ε_c and the particles' conductivity k_s (`thermalConductivities`):
//! * k_eff,c = ½ (3 α_c − 1) k_s for α_c ≥ 0.334, else 0 (PFM's effective-medium form of
//!   Qian et al.), capped at `kMax` when given;
//! * Q_c = ∇·(k_eff ∇T_p) (W/m³), the Gauss-linear Laplacian without non-orthogonal correction:
//!   per internal face f between P and N, k_f |S_f| (T_p,N − T_p,P) / (n̂_f·d_PN) into P, with
//!   k_f the linear interpolate of k_eff — taken as 0 where either cell has k_eff = 0
//!   (foamgrain's one departure: PFM's linear interpolate lets a bed cell conduct to an empty
//!   cell, whose T_p is 0 K, and the heat that reaches cells without particles is lost; here
//!   no heat leaves the particles);
//! * particle p receives q_p = Σ_c v_pc/(Σ_p' v_p'c) Q_c V_c (W), v_pc its volume share in c:
//!   for a particle wholly inside c this is PFM's V_p Q_c / (1 − ε_c), and Σ_p q_p = Σ_c Q_c
//!   V_c = 0 to round-off (the boundary is insulated), counted as
//!   [`crate::HeatAccount::between_particles`].
//!
//! The conduction is added to each particle's heat flux handed to the DEM (with the fluid's
//! convective part; LIGGGHTS-PFM keeps it apart as `conductiveHeatFlux`).

use crate::error::CoupleError;
use crate::interpolate::Placement;
use foam::PolyMesh;

/// PFM's lower solid fraction of the effective-medium form.
const ALPHA_MIN: f64 = 0.334;

/// k_eff = ½ (3 α − 1) k_s for the solid fraction α ≥ 0.334, else 0 (W/(m·K)).
pub fn effective_conductivity(alpha: f64, ks: f64) -> f64 {
    match alpha < ALPHA_MIN {
        true => 0.0,
        false => 0.5 * (3.0 * alpha - 1.0) * ks,
    }
}

/// One internal face: owner, neighbour, |S_f|/(n̂·d) (m).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Face {
    owner: usize,
    neighbour: usize,
    coefficient: f64,
}

/// The model on a mesh (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct InterGrain {
    faces: Vec<Face>,
    /// The particles' conductivity k_s, W/(m·K).
    pub ks: f64,
    /// `kMax`, W/(m·K), if given.
    pub k_max: Option<f64>,
}

impl InterGrain {
    /// The model with conductivity `ks` (> 0) and cap `k_max` on the internal faces of `mesh`.
    pub fn new(mesh: &PolyMesh, ks: f64, k_max: Option<f64>) -> Result<InterGrain, CoupleError> {
        let g = mesh::geometry::MeshGeometry::compute(mesh)
            .map_err(|e| CoupleError::Parameter(format!("heatTransferInterGrain: {e}")))?;
        let faces = (0..mesh.neighbour.len())
            .map(|f| {
                let (o, n) = (mesh.owner[f] as usize, mesh.neighbour[f] as usize);
                let s = g.face_areas[f];
                let d = g.cell_centres[n] - g.cell_centres[o];
                Face {
                    owner: o,
                    neighbour: n,
                    coefficient: s.norm() * s.norm() / s.dot(&d),
                }
            })
            .collect();
        Ok(InterGrain { faces, ks, k_max })
    }

    /// Q_c V_c per cell (W) for the particle temperatures `t_p` (K) and the solid fractions
    /// `alpha` per cell.
    pub fn cell_heat(&self, t_p: &[f64], alpha: &[f64]) -> Vec<f64> {
        let k: Vec<f64> = alpha
            .iter()
            .map(|&a| {
                let k = effective_conductivity(a, self.ks);
                self.k_max.map_or(k, |m| k.min(m))
            })
            .collect();
        let mut q = vec![0.0; alpha.len()];
        for f in &self.faces {
            let (ko, kn) = (k[f.owner], k[f.neighbour]);
            if ko > 0.0 && kn > 0.0 {
                let flow = 0.5 * (ko + kn) * f.coefficient * (t_p[f.neighbour] - t_p[f.owner]);
                q[f.owner] += flow;
                q[f.neighbour] -= flow;
            }
        }
        q
    }

    /// Each particle's conduction q_p (W) and their sum, for the particles `placement` and
    /// temperatures `temperature` (K) in cells of voidage `eps` (module docs).
    pub fn particle_heat(
        &self,
        placement: &Placement,
        temperature: &[f64],
        eps: &[f64],
    ) -> (Vec<f64>, f64) {
        let n_cells = eps.len();
        let (mut wt, mut w, mut v) = (vec![0.0; n_cells], vec![0.0; n_cells], vec![0.0; n_cells]);
        for (i, t) in temperature.iter().enumerate() {
            placement.for_each_weight(i, |c, s| {
                wt[c as usize] += s * t;
                w[c as usize] += s;
            });
            let (cells, vols) = placement.shares.of(i);
            for (&c, &vol) in cells.iter().zip(vols) {
                v[c as usize] += vol;
            }
        }
        let t_p: Vec<f64> = wt
            .iter()
            .zip(&w)
            .map(|(&a, &b)| if b > 0.0 { a / b } else { 0.0 })
            .collect();
        let alpha: Vec<f64> = eps.iter().map(|e| 1.0 - e).collect();
        let cell = self.cell_heat(&t_p, &alpha);
        let q: Vec<f64> = (0..temperature.len())
            .map(|i| {
                let (cells, vols) = placement.shares.of(i);
                cells
                    .iter()
                    .zip(vols)
                    .map(|(&c, &vol)| match v[c as usize] > 0.0 {
                        true => vol / v[c as usize] * cell[c as usize],
                        false => 0.0,
                    })
                    .sum()
            })
            .collect();
        let total = q.iter().sum();
        (q, total)
    }

    /// Adds the conduction to the heat step `h` (its particles' `q`) and counts its sum.
    pub fn add_to(
        &self,
        h: &mut crate::HeatStep,
        placement: &Placement,
        temperature: &[f64],
        eps: &[f64],
    ) -> Result<(), CoupleError> {
        let (q, total) = self.particle_heat(placement, temperature, eps);
        if let Some(i) = q.iter().position(|x| !x.is_finite()) {
            return Err(CoupleError::Parameter(format!(
                "heatTransferInterGrain: the conduction into particle {i} is {}",
                q[i]
            )));
        }
        for (a, b) in h.q.iter_mut().zip(&q) {
            *a += b;
        }
        h.account.between_particles = total;
        Ok(())
    }
}
