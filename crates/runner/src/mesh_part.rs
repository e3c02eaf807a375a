//! The part of the mesh a coupler rank holds ([`couple::part`]): the cells around its
//! particles, cut from the case's polyMesh, read from disk for each cut (the whole mesh is
//! held only while a part is cut, then dropped).
//!
//! Ranks other than 0 hold a part with a stand-in fluid ([`stand_in_on_part`]). With
//! grainPisoFoam on several coupler ranks rank 0 holds a part too ([`foam_on_part`]): its
//! first part is cut from the whole mesh the solver's spawn read, after rank 0 has taken from
//! it what it observes of the whole mesh ([`crate::whole`]). With the native fluid on several
//! ranks rank 0's coupler holds a part as well ([`native_on_part`]): the fluid holds the whole
//! mesh and fields, and the coupler sums the ranks' cells into whole-length fields with the
//! whole mesh's cell volumes only ([`couple::Coupler::set_root_volumes`]). A mesh with
//! `cyclic` patches is not cut ([`mesh::part`]): every rank then holds it whole, as before.

use crate::error::RunError;
use crate::fluid::StandInFluid;
use couple::part::{PartSource, Parted};
use couple::SideError;
use foam::PolyMesh;
use mesh::part::MeshPart;
use mesh::v3::V3;
use mesh::Aabb;
use std::path::PathBuf;

/// The case's polyMesh on disk as the source of a rank's parts; the first part from a whole
/// mesh already read, when there is one.
struct CaseMesh {
    cfd: PathBuf,
    first: Option<PolyMesh>,
}

impl PartSource for CaseMesh {
    fn cut(&mut self, region: &Aabb) -> Result<Option<MeshPart>, SideError> {
        let whole = match self.first.take() {
            Some(whole) => whole,
            None => foam::Case::open(&self.cfd)
                .and_then(|c| c.read_mesh())
                .map_err(|e| {
                    SideError::from(format!("reading the mesh to cut this rank's part: {e}"))
                })?,
        };
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
        first: None,
    });
    match Parted::first(source, position, radius).map_err(RunError::Fluid)? {
        Some((mesh, parted)) => Ok((StandInFluid::on_mesh(plan, mesh), Some(parted))),
        None => Ok((StandInFluid::open(plan)?, None)),
    }
}

/// Coupler rank 0 with grainPisoFoam on several ranks (`inner`, a sparse run): the fluid on
/// rank 0's part of the mesh around its particles at `position` (radii `radius`), what its
/// coupler keeps of the part, and what rank 0 keeps of the whole mesh and observes on it
/// ([`crate::whole`], for a run starting at the solver's time with coupling interval `dt_c`
/// s). The whole mesh the spawn read is summarised, cut and dropped. A mesh that cannot be cut
/// (cyclic patches, or a part that would be the whole mesh) stays whole, as before (`None`s).
#[cfg(feature = "mpi")]
pub(crate) fn foam_on_part(
    plan: &crate::plan::RunPlan,
    mut inner: foam_link::OpenFoamFluid,
    position: &[V3],
    radius: &[f64],
    dt_c: f64,
) -> Result<PartedFoam, RunError> {
    use crate::foam_fluid::FoamFluid;
    let Some(whole) = inner.take_mesh() else {
        return Ok((FoamFluid::new(inner), None, None));
    };
    if whole
        .boundary
        .iter()
        .any(|p| p.patch_type.contains("cyclic"))
    {
        return Ok((FoamFluid::on_mesh(inner, whole), None, None));
    }
    let summary = crate::whole::WholeMesh::of(plan, &whole, inner.time(), dt_c)?;
    let source = Box::new(CaseMesh {
        cfd: plan.layout.cfd.clone(),
        first: Some(whole),
    });
    match Parted::first(source, position, radius).map_err(RunError::Fluid)? {
        Some((mesh, parted)) => Ok((FoamFluid::on_mesh(inner, mesh), Some(parted), Some(summary))),
        None => {
            let whole = foam::Case::open(&plan.layout.cfd)?.read_mesh()?;
            Ok((FoamFluid::on_mesh(inner, whole), None, None))
        }
    }
}

/// Coupler rank 0 with the native fluid on several coupler ranks: the mesh of its coupler's
/// part around its particles `at` (centres, radii), the part, and what it keeps of the fluid's
/// whole mesh `whole` and observes on it ([`crate::whole`], for a run starting at `start` s
/// with coupling interval `dt_c` s). A mesh that cannot be cut (cyclic patches, or a part that
/// would be the whole mesh) gives `None`s: the coupler holds the whole mesh, as before.
#[cfg(feature = "liggghts")]
pub(crate) fn native_on_part(
    plan: &crate::plan::RunPlan,
    whole: &PolyMesh,
    at: (&[V3], &[f64]),
    start: f64,
    dt_c: f64,
) -> Result<PartedNative, RunError> {
    if whole
        .boundary
        .iter()
        .any(|p| p.patch_type.contains("cyclic"))
    {
        return Ok((None, None, None));
    }
    let summary = crate::whole::WholeMesh::of(plan, whole, start, dt_c)?;
    let source = Box::new(CaseMesh {
        cfd: plan.layout.cfd.clone(),
        first: Some(whole.clone()),
    });
    match Parted::first(source, at.0, at.1).map_err(RunError::Fluid)? {
        Some((mesh, parted)) => Ok((Some(mesh), Some(parted), Some(summary))),
        None => Ok((None, None, None)),
    }
}

/// What [`native_on_part`] gives: the coupler's mesh, the part and the whole mesh's summary.
#[cfg(feature = "liggghts")]
pub(crate) type PartedNative = (
    Option<PolyMesh>,
    Option<Parted>,
    Option<(crate::whole::WholeMesh, crate::whole::Observed)>,
);

/// What [`foam_on_part`] gives: the fluid side, the part and the whole mesh's summary.
#[cfg(feature = "mpi")]
pub(crate) type PartedFoam = (
    crate::foam_fluid::FoamFluid,
    Option<Parted>,
    Option<(crate::whole::WholeMesh, crate::whole::Observed)>,
);
