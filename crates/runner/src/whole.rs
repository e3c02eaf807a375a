//! What the run observes of the whole mesh ([`Observed`]: the column's floor and
//! cross-section, the inlet and outlet, the outlet's cells, a conveyor's air cells, a heating
//! case's and a fluidised bed's bins), and what coupler rank 0 keeps of the whole mesh when it
//! holds only a part of it ([`WholeMesh`]).
//!
//! Every rank computes [`Observed`] from the mesh it holds and rank 0's values are the run's
//! (broadcast by the run loop: a part sees only its own points). With grainPisoFoam on several
//! coupler ranks rank 0 holds a part too ([`crate::mesh_part::foam_on_part`]): it computes
//! [`Observed`] and [`WholeMesh`] once from the whole mesh the solver's spawn read, then drops
//! that mesh. With the native fluid on several ranks
//! ([`crate::mesh_part::native_on_part`]) it computes them from the fluid's mesh, and its
//! coupler forms ε with [`WholeMesh`]'s cell volumes. Both are light: per cell only the volumes (8 B, for the monitors and
//! `checkCouplingInterval`) and a heating case's bins; per face of the outlet its cell and area.

#[cfg(any(feature = "mpi", feature = "liggghts"))]
use crate::error::RunError;
use crate::layout::ValidationSpec;
use crate::outputs::Column;
use crate::plan::RunPlan;
use foam::PolyMesh;
use mesh::geometry::MeshGeometry;
use mesh::v3::{unit, V3};

/// The observer's inputs taken from a mesh (module docs).
pub(crate) struct Observed {
    /// The column along the flow: axis, floor and cross-section.
    pub(crate) column: Column,
    pub(crate) inlet: Option<String>,
    pub(crate) outlet: Option<String>,
    /// The log lines of finding the inlet and outlet (without a validationDict).
    pub(crate) notes: Vec<String>,
    /// The outlet patch's cells and face areas (m²).
    pub(crate) outlet_cells: Vec<(usize, f64)>,
    /// A full conveyor's cells whose air velocity is sampled.
    pub(crate) air_cells: Option<crate::branch::AirCells>,
    /// A packed-bed heating case's bins (this rank's floor: rank 0's is agreed later).
    pub(crate) heating: Option<crate::heating_run::Profiler>,
    /// A fluidised bed's slabs (likewise).
    pub(crate) slabs: Option<crate::slab_profile::Profiler>,
}

/// The column's axis: the validationDict's, else against gravity (z without gravity).
fn axis(plan: &RunPlan) -> V3 {
    match &plan.layout.validation {
        Some(ValidationSpec::ErgunPackedBed { axis, .. }) => *axis,
        Some(ValidationSpec::PackedBedHeating(c)) => c.axis,
        _ => unit(-plan.settings.physics.gravity).unwrap_or(V3::z()),
    }
}

/// What the observer measures on `mesh` (of geometry `geometry`) for a run starting at `start`
/// s with coupling interval `dt_c` s: the inlet and outlet are the validationDict's, else the
/// ones the start fields' boundary conditions make inlet and outlet.
pub(crate) fn observed(
    plan: &RunPlan,
    mesh: &PolyMesh,
    geometry: &MeshGeometry,
    start: f64,
    dt_c: f64,
) -> Observed {
    let spec = &plan.layout.validation;
    let axis = axis(plan);
    let volume: f64 = geometry.cell_volumes.iter().sum();
    let mut notes = Vec::new();
    let (inlet, outlet) = match spec {
        Some(
            ValidationSpec::ErgunPackedBed { inlet, outlet, .. }
            | ValidationSpec::FluidisedBed { inlet, outlet, .. },
        ) => (Some(inlet.clone()), Some(outlet.clone())),
        Some(ValidationSpec::PneumaticConveying(c)) => {
            (Some(c.inlet.clone()), Some(c.outlet.clone()))
        }
        Some(ValidationSpec::PackedBedHeating(c)) => {
            (Some(c.inlet.clone()), Some(c.outlet.clone()))
        }
        _ => {
            let start = couple::output::time_name(start);
            let found = crate::patches::find(&plan.layout.cfd, &start, mesh);
            notes.extend(found.notes.iter().map(|n| format!("monitoring: {n}")));
            if let (Some(i), Some(o)) = (&found.inlet, &found.outlet) {
                notes.push(format!(
                    "monitoring: Δp between the inlet `{i}` and the outlet `{o}`"
                ));
            }
            (found.inlet, found.outlet)
        }
    };
    let outlet_cells = outlet
        .as_deref()
        .and_then(|name| mesh.boundary.iter().find(|p| p.name == name))
        .map(|patch| {
            let areas = &geometry.face_areas;
            patch
                .faces()
                .map(|f| (mesh.owner[f] as usize, areas[f].norm()))
                .collect()
        })
        .unwrap_or_default();
    let column = Column::of(mesh, volume, axis);
    let air_cells = match spec {
        Some(ValidationSpec::PneumaticConveying(c)) => c.branch.as_ref().map(|b| {
            crate::branch::AirCells::select(
                b,
                c.tube_from,
                axis,
                &geometry.cell_centres,
                &geometry.cell_volumes,
            )
        }),
        _ => None,
    };
    let heating = match spec {
        Some(ValidationSpec::PackedBedHeating(c)) => Some(crate::heating_run::Profiler::new(
            c,
            geometry,
            mesh,
            column.floor,
            dt_c,
        )),
        _ => None,
    };
    let slabs = match spec {
        Some(ValidationSpec::FluidisedBed {
            profiles: Some(p), ..
        }) => Some(crate::slab_profile::Profiler::new(
            p,
            &mesh.points,
            column.axis,
            column.floor,
            column.area,
        )),
        _ => None,
    };
    Observed {
        column,
        inlet,
        outlet,
        notes,
        outlet_cells,
        air_cells,
        heating,
        slabs,
    }
}

/// What coupler rank 0 keeps of the whole mesh while its coupler holds a part (module docs).
pub(crate) struct WholeMesh {
    /// The whole mesh's cell count and patches, without points, faces or owners: what writing
    /// a cell field of the whole mesh needs (the monitors' fields, whose values the solver
    /// sends whole).
    pub(crate) shell: PolyMesh,
    /// The whole mesh's cell volumes (m³), as the coupler's geometry computes them.
    pub(crate) cell_volumes: Vec<f64>,
}

impl WholeMesh {
    /// The summary of `mesh` and what the observer measures on it (for a run starting at
    /// `start` s with coupling interval `dt_c` s); the geometry is computed here and dropped.
    /// (Only a run on several coupler ranks, `mpi` or `liggghts`, cuts rank 0's part.)
    #[cfg(any(feature = "mpi", feature = "liggghts"))]
    pub(crate) fn of(
        plan: &RunPlan,
        mesh: &PolyMesh,
        start: f64,
        dt_c: f64,
    ) -> Result<(WholeMesh, Observed), RunError> {
        let geometry = MeshGeometry::new(mesh)
            .map_err(|e| RunError::Backend(format!("the whole mesh's geometry: {e}")))?;
        let observed = observed(plan, mesh, &geometry, start, dt_c);
        let shell = PolyMesh {
            points: Vec::new(),
            faces: foam::FaceList::new(),
            owner: Vec::new(),
            neighbour: Vec::new(),
            boundary: mesh.boundary.clone(),
            n_cells: mesh.n_cells,
        };
        let whole = WholeMesh {
            shell,
            cell_volumes: geometry.cell_volumes,
        };
        Ok((whole, observed))
    }

    /// The bytes its arrays hold.
    pub(crate) fn held_bytes(&self) -> usize {
        foam::heap::flat(&self.cell_volumes)
    }
}
