//! The part of the mesh a coupler rank other than 0 holds ([`couple::part`]): the cells around
//! its particles, cut from the case's polyMesh, read from disk for each cut (the whole mesh is
//! held only while a part is cut, then dropped).
//!
//! Rank 0 keeps the whole mesh: it holds the native fluid, or, with grainPisoFoam, observes
//! the patches and writes the run's outputs. A mesh with `cyclic` patches is not cut
//! ([`mesh::part`]): every rank then holds it whole, as before.

use crate::error::RunError;
use crate::fluid::StandInFluid;
use couple::part::{PartSource, Parted};
use couple::SideError;
use mesh::part::MeshPart;
use mesh::v3::V3;
use mesh::Aabb;
use std::path::PathBuf;

/// The case's polyMesh on disk as the source of a rank's parts.
struct CaseMesh {
    cfd: PathBuf,
}

impl PartSource for CaseMesh {
    fn cut(&mut self, region: &Aabb) -> Result<Option<MeshPart>, SideError> {
        let whole = foam::Case::open(&self.cfd)
            .and_then(|c| c.read_mesh())
            .map_err(|e| {
                SideError::from(format!("reading the mesh to cut this rank's part: {e}"))
            })?;
        Ok(MeshPart::around(&whole, region))
    }
}

/// The stand-in fluid of a coupler rank other than 0 on the part of the mesh around the
/// particles at `position` (radii `radius`), and what its coupler keeps of the part; the whole
/// mesh (and `None`) when the mesh cannot be cut.
pub(crate) fn stand_in_on_part(
    plan: &crate::plan::RunPlan,
    position: &[V3],
    radius: &[f64],
) -> Result<(StandInFluid, Option<Parted>), RunError> {
    let source = Box::new(CaseMesh {
        cfd: plan.layout.cfd.clone(),
    });
    match Parted::first(source, position, radius).map_err(RunError::Fluid)? {
        Some((mesh, parted)) => Ok((StandInFluid::on_mesh(plan, mesh), Some(parted))),
        None => Ok((StandInFluid::open(plan)?, None)),
    }
}
