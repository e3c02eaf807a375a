//! Conduction between particles and primitive walls that have a temperature: LIGGGHTS 3.8's
//! `fix wall/gran … primitive … temperature T_w [contact_area …]` (`FixWallGran::addHeatFlux`).
//! A wall without `temperature` (or with T_w < 0, LIGGGHTS's "none") is adiabatic.
//!
//! For a particle of radius r touching the wall (centre distance d < r, overlap δ = r − d), the
//! heat flow into it is
//!
//!   Q = h_c (T_w − T),   h_c = 4 k k_w / (k + k_w) · √A   (W/K)
//!
//! with k, k_w the `thermalConductivity` of the particle's and the wall's material type
//! (h_c = 0 if |k| or |k_w| < 10⁻¹², the wall fix's `SMALL`) and the contact area, by the wall's
//! `contact_area`: `overlap` (default) A = π (r² − (r − δ)²), `projection` π r², `constant A`.
//! LIGGGHTS adds it while it computes the wall's forces, before the particle–particle
//! conduction (the walls are defined first in every deck that uses them).

use crate::heat::ContactArea;
use crate::particles::Particles;
use crate::walls::Wall;

/// |k| below which a wall contact does not conduct (W/(m K)): `SMALL` of `fix_wall_gran.cpp`.
const SMALL_WALL_CONDUCTIVITY: f64 = 1e-12;

/// A wall's heat settings: its temperature and contact area model.
#[derive(Debug, Clone, PartialEq)]
pub struct WallHeat {
    /// The wall fix's id ([`Wall::name`]).
    pub wall: String,
    /// T_w (K).
    pub temperature: f64,
    /// The wall's `contact_area`.
    pub area: ContactArea,
}

impl WallHeat {
    /// The contact area of a particle of radius `r` overlapping the wall by `delta` (m²).
    pub fn contact_area(&self, r: f64, delta: f64) -> f64 {
        match self.area {
            ContactArea::Overlap => {
                let rr = r - delta;
                (r * r - rr * rr) * std::f64::consts::PI
            }
            ContactArea::Projection => std::f64::consts::PI * r * r,
            ContactArea::Constant(a) => a,
        }
    }
}

/// Adds the heat flows of the walls in `heat` (those of `walls` with a temperature) to `flux`
/// (W), wall by wall in the order of `walls`; `k` is the conductivity per type.
pub fn add_wall_flux(
    heat: &[WallHeat],
    walls: &[Wall],
    k: &[f64],
    p: &Particles,
    temp: &[f64],
    flux: &mut [f64],
) {
    for wall in walls {
        let Some(h) = heat.iter().find(|h| h.wall == wall.name) else {
            continue;
        };
        let kw = k[wall.material_type as usize - 1];
        for i in 0..p.len() {
            let r = p.radius[i];
            if wall.shape.gap(p.x[i]) >= r {
                continue;
            }
            let Some((dist, _)) = wall.shape.distance(p.x[i]) else {
                continue;
            };
            let kp = k[p.atom_type[i] as usize - 1];
            let a = h.contact_area(r, r - dist);
            let hc = if kp.abs() < SMALL_WALL_CONDUCTIVITY || kw.abs() < SMALL_WALL_CONDUCTIVITY {
                0.
            } else {
                4. * kp * kw / (kp + kw) * a.sqrt()
            };
            flux[i] += (h.temperature - temp[i]) * hc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_area_is_the_cap_base() {
        // a sphere of radius 1 cut by a plane at distance 0.6 from its centre: base radius 0.8
        let h = WallHeat {
            wall: "w".into(),
            temperature: 300.0,
            area: ContactArea::Overlap,
        };
        let a = h.contact_area(1.0, 0.4);
        assert!((a - std::f64::consts::PI * 0.64).abs() < 1e-15);
    }
}
