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
//!   may move before the part is cut again (each cut reads the mesh from disk).
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
}

/// The safe box and the region to cut for particles at `position` with radii `radius` (module
/// docs); `None` without particles.
pub fn region_for(position: &[V3], radius: &[f64], reach_factor: f64) -> Option<(Aabb, Aabb)> {
    if position.is_empty() {
        return None;
    }
    let mut b = Aabb::EMPTY;
    for &x in position {
        b.include(x);
    }
    let r_max = radius.iter().copied().fold(0.0, f64::max);
    let e = b.extent();
    let slack = 4.0 * r_max + 0.1 * e.max();
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
            region_for(position, radius, 1.0).unwrap_or((Aabb::EMPTY, Aabb::EMPTY));
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

    /// A new part for the particles at `position`, with the reach doubled first when `wider`;
    /// returns its mesh.
    pub fn recut(
        &mut self,
        position: &[V3],
        radius: &[f64],
        wider: bool,
    ) -> Result<PolyMesh, CoupleError> {
        if wider {
            self.reach_factor *= 2.0;
        }
        let (safe, region) =
            region_for(position, radius, self.reach_factor).unwrap_or((Aabb::EMPTY, Aabb::EMPTY));
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
        let (safe, region) = region_for(&pos, &[0.01, 0.02], 1.0).unwrap();
        // slack 4 × 0.02 + 0.1 × 1.0 = 0.18, reach 1.5 × 0.02 = 0.03
        assert!((safe.min - V3::repeat(-0.18)).norm() < 1e-15);
        assert!((region.max - V3::new(1.21, 0.71, 0.41)).norm() < 1e-15);
        assert!(region_for(&[], &[], 1.0).is_none());
    }
}
