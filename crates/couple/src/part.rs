//! A coupler rank on its part of the mesh ([`mesh::part`]): the cells around its particles,
//! cut again when the particles leave them.
//!
//! On N coupler ranks ([`crate::ranks`]) a rank other than 0 reads only the cells its
//! particles touch: its coupler runs on a [`MeshPart`] of the mesh (the part's own cell labels
//! everywhere inside the coupler), and the labels it gives the other ranks
//! ([`crate::Ranks::sum_to_root`]) or the fluid's owners ([`crate::ranks::CellOwners`]) are
//! the whole mesh's ([`Parted::global`]). The part's cells are kept in whole-mesh order, so a
//! sorted list of touched cells stays sorted once mapped, and the exchange is the same as with
//! the whole mesh.
//!
//! **The region.** A part is cut around the box of the rank's particle centres grown by
//! `slack + reach`:
//! * `reach` = 1.5 × the largest radius: how far from its centre a particle's volume (the
//!   spheres of `exact`, the markers of `divided`, which lie within the radius) or its centre
//!   cell reaches;
//! * `slack` = 2 × the largest diameter + 10 % of the box's largest side: how far the particles
//!   may move before the part is cut again (each cut reads the mesh from disk); from the second
//!   cut on, at least the *floor* [`Parted::recut`] gives it: the typical width of the last
//!   part's cells ([`cell_width`]) and the distance the fastest particle travels in
//!   [`TRAVEL_STEPS`] coupling steps. A part is made of whole cells, so a slack below a cell's
//!   width saves at most one layer of cells, while a lone particle (a box of one centre: the
//!   10 % is nothing) would leave a slack of 4 radii within a few steps and have the whole mesh
//!   read again each time (the settling sphere on 2 ranks: 75 cuts in 200 coupling steps).
//!
//! [`MeshPart::around`] adds one layer of cells beyond those meeting the region, so a particle
//! whose centre stays within the *safe box* (the particles' box grown by `slack`) touches no
//! edge cell. Before each placement the coupler checks that every centre is in the safe box
//! ([`Parted::holds`]); after it, that no touched cell is an edge cell ([`Parted::edge`]): a
//! method reaching further than `reach` (a scaled-up volume) would. Either failing cuts a new
//! part (with `reach` doubled after an edge touch) and places again; what was kept per
//! particle by cell (the search hints, `divided`'s markers) is dropped with the old part. The
//! run is the same as with the whole mesh: every touched cell is an inner cell of the part,
//! whose geometry is the whole mesh's bit for bit ([`mesh::part`]).
//!
//! A particle whose centre is inside the safe box but in no cell is outside the whole mesh
//! (every cell meeting the box is in the part), and is counted as outside as on one rank.

use crate::error::{CoupleError, SideError};
use crate::sides::ParticleState;
use foam::{Label, PolyMesh};
use mesh::part::MeshPart;
use mesh::v3::V3;
use mesh::Aabb;
use voidage::CellShares;

/// Where a rank's parts come from: the whole mesh, read (from disk) each time a part is cut.
pub trait PartSource: Send {
    /// The part of the whole mesh around `region` ([`MeshPart::around`]); `None` when the
    /// mesh cannot be cut (cyclic patches) or the part would be the whole mesh.
    fn cut(&mut self, region: &Aabb) -> Result<Option<MeshPart>, SideError>;
}

/// What a coupler on a part keeps of it (module docs).
pub struct Parted {
    source: Box<dyn PartSource>,
    /// The whole mesh's label of each of the part's cells (increasing).
    pub global: Vec<Label>,
    /// Whether each of the part's cells has a cut face.
    pub edge: Vec<bool>,
    /// The box the particle centres must stay in.
    safe: Aabb,
    /// Multiplies the reach after a touched edge cell.
    reach_factor: f64,
    /// Parts cut so far (the first included).
    pub cuts: u64,
    /// The typical width of the current part's cells ([`cell_width`]), m: the next cut's slack
    /// is at least this.
    width: f64,
}

/// Coupling steps the fastest particle of an exchange may travel within the slack of the part
/// cut then ([`Parted::recut`]): a cut reads the whole mesh, so this bounds the cuts a fast
/// particle causes to about one per 20 coupling steps, at the cost of a slack of 20 steps'
/// travel (for a bed moving at 0.01 m/s with Δt_c = 5e-4 s, 0.1 mm).
pub const TRAVEL_STEPS: f64 = 20.0;

/// The typical width of `mesh`'s cells (m): the median over its cells of the largest side of
/// the cell's bounding box (0 without cells). The median, so that a few long cells of a graded
/// mesh do not set it.
pub fn cell_width(mesh: &PolyMesh) -> f64 {
    let mut w: Vec<f64> = mesh::part::cell_bounds(mesh)
        .iter()
        .map(|b| b.extent().max())
        .collect();
    if w.is_empty() {
        return 0.0;
    }
    let mid = w.len() / 2;
    *w.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The safe box and the region to cut for particles at `position` with radii `radius`, with a
/// slack of at least `floor` m (module docs); `None` without particles.
pub fn region_for(
    position: &[V3],
    radius: &[f64],
    floor: f64,
    reach_factor: f64,
) -> Option<(Aabb, Aabb)> {
    if position.is_empty() {
        return None;
    }
    let mut b = Aabb::EMPTY;
    for &x in position {
        b.include(x);
    }
    let r_max = radius.iter().copied().fold(0.0, f64::max);
    let e = b.extent();
    let slack = (4.0 * r_max + 0.1 * e.max()).max(floor);
    let reach = 1.5 * r_max * reach_factor;
    let grow = |b: &Aabb, d: f64| Aabb {
        min: b.min - V3::repeat(d),
        max: b.max + V3::repeat(d),
    };
    let safe = grow(&b, slack);
    Some((safe, grow(&safe, reach)))
}

impl Parted {
    /// The first part's mesh for the particles at `position`, and what the coupler keeps of the
    /// part; `None` when the source gives none (the coupler then keeps the whole mesh).
    pub fn first(
        mut source: Box<dyn PartSource>,
        position: &[V3],
        radius: &[f64],
    ) -> Result<Option<(PolyMesh, Parted)>, SideError> {
        let (safe, region) =
            region_for(position, radius, 0.0, 1.0).unwrap_or((Aabb::EMPTY, Aabb::EMPTY));
        let Some(MeshPart {
            mesh, global, edge, ..
        }) = source.cut(&region)?
        else {
            return Ok(None);
        };
        let parted = Parted {
            source,
            global,
            edge,
            safe,
            reach_factor: 1.0,
            cuts: 1,
            width: cell_width(&mesh),
        };
        Ok(Some((mesh, parted)))
    }

    /// Whether every centre of `position` is in the safe box.
    pub fn holds(&self, position: &[V3]) -> bool {
        position.iter().all(|&x| self.safe.contains(x))
    }

    /// Whether any cell the particles touch (their `shares`' cells and `centre` cells) is an
    /// edge cell.
    pub fn touches_edge(&self, shares: &CellShares, centre: &[Option<Label>]) -> bool {
        let edge = |c: &Label| self.edge[*c as usize];
        shares.cells.iter().any(edge) || centre.iter().flatten().any(edge)
    }

    /// A new part for `particles`, with the reach doubled first when `wider`; returns its mesh.
    /// The slack is at least the current part's [`cell_width`] and the distance the fastest
    /// particle travels in [`TRAVEL_STEPS`] coupling intervals of `dt_c` s (none without it).
    pub fn recut(
        &mut self,
        particles: &ParticleState<'_>,
        dt_c: Option<f64>,
        wider: bool,
    ) -> Result<PolyMesh, CoupleError> {
        if wider {
            self.reach_factor *= 2.0;
        }
        let v_max = particles
            .velocity
            .iter()
            .map(|v| v.norm())
            .fold(0.0, f64::max);
        let floor = self.width.max(TRAVEL_STEPS * v_max * dt_c.unwrap_or(0.0));
        let (position, radius) = (particles.position, particles.radius);
        let (safe, region) = region_for(position, radius, floor, self.reach_factor)
            .unwrap_or((Aabb::EMPTY, Aabb::EMPTY));
        let part = self
            .source
            .cut(&region)
            .map_err(crate::side_checks::fluid_err)?
            .ok_or_else(|| {
                CoupleError::Parameter(
                    "the mesh can no longer be cut into a part around this rank's particles".into(),
                )
            })?;
        self.global = part.global;
        self.edge = part.edge;
        self.safe = safe;
        self.cuts += 1;
        self.width = cell_width(&part.mesh);
        Ok(part.mesh)
    }

    /// The whole mesh's labels of the part's cells `cells`.
    pub fn to_global(&self, cells: &[Label]) -> Vec<Label> {
        cells.iter().map(|&c| self.global[c as usize]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_region_grows_the_particles_box_by_slack_then_reach() {
        let pos = [V3::new(0.0, 0.0, 0.0), V3::new(1.0, 0.5, 0.2)];
        let (safe, region) = region_for(&pos, &[0.01, 0.02], 0.1, 1.0).unwrap();
        // slack 4 × 0.02 + 0.1 × 1.0 = 0.18 (above the floor 0.1), reach 1.5 × 0.02 = 0.03
        assert!((safe.min - V3::repeat(-0.18)).norm() < 1e-15);
        assert!((region.max - V3::new(1.21, 0.71, 0.41)).norm() < 1e-15);
        assert!(region_for(&[], &[], 0.0, 1.0).is_none());
    }

    #[test]
    fn a_lone_particle_gets_the_floor_as_its_slack() {
        // one centre: a box of no extent, slack 4 × 0.001 = 0.004 below the floor 0.05
        let (safe, region) = region_for(&[V3::new(0.5, 0.5, 0.5)], &[0.001], 0.05, 2.0).unwrap();
        assert!((safe.min - V3::repeat(0.45)).norm() < 1e-15);
        // reach 1.5 × 0.001 × 2
        assert!((region.max - V3::repeat(0.553)).norm() < 1e-15);
    }

    #[test]
    fn the_cell_width_is_the_median_cell_s_largest_side() {
        // 3 × 2 × 1 cells of 0.1 × 0.2 × 0.05 m, and one column stretched to 0.7 m along x:
        // sides per cell (0.2, 0.2, 0.7 | 0.2, 0.2, 0.7), median (upper of the middle pair) 0.2
        let mesh = mesh::build::hex_grid(&[0.0, 0.1, 0.2, 0.9], &[0.0, 0.2, 0.4], &[0.0, 0.05]);
        assert!((cell_width(&mesh) - 0.2).abs() < 1e-15);
        let one = mesh::build::hex_grid(&[0.0, 0.3], &[0.0, 0.1], &[0.0, 0.2]);
        assert!((cell_width(&one) - 0.3).abs() < 1e-15);
    }
}
