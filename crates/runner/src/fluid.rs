//! What a run needs from a fluid backend beyond the coupling itself ([`RunFluid`]): its clock,
//! the patch averages the observer samples (inlet pressure and velocity) and writing a time.
//!
//! The native solver ([`crate::native::NativeFluid`]) and grainPisoFoam over MPI (feature
//! `mpi`, [`crate::backend`]) implement it.

use couple::{CouplingStep, FluidSide, SideError};
use foam::PolyMesh;
use mesh::v3::V3;
use std::path::Path;

/// A fluid side that a run can observe and write.
pub trait RunFluid: FluidSide {
    /// The fluid's simulated time, s.
    fn time(&self) -> f64;
    /// The coupler now holds `n_cells` cells (a new part of the mesh, [`couple::part`]): a
    /// side whose fields stand in on the coupler's cells grows them to match.
    fn cells_held(&mut self, _n_cells: usize) {}
    /// Area-weighted mean kinematic pressure p/ρ (m²/s²) over patch `name`; `None` without
    /// the patch.
    fn patch_pressure(&self, name: &str) -> Option<f64>;
    /// Mean velocity into the domain through patch `name`: −Σ φ_f / Σ |S_f| (m/s, positive
    /// for inflow); `None` without the patch.
    fn inflow_velocity(&self, name: &str) -> Option<f64>;
    /// Writes the current time (fluid fields and, where the backend does not write them
    /// itself, the coupling step's exchange fields) into the case `cfd`; returns the time
    /// directory's name.
    fn write_time(
        &mut self,
        cfd: &Path,
        mesh: &PolyMesh,
        step: &CouplingStep,
    ) -> Result<String, SideError>;
    /// Starts advancing by `dt` seconds (one coupling interval), with the exchange fields last
    /// set. A fluid that runs in processes of its own ([`RunFluid::runs_apart`]) returns
    /// while it computes, so the run can advance the particles meanwhile; until
    /// [`RunFluid::finish_advance`] its state, time and patch values are those before the
    /// advance. The default advances at once.
    fn start_advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.advance(dt)
    }
    /// Waits for the advance [`RunFluid::start_advance`] started (a no-op when it is done).
    fn finish_advance(&mut self) -> Result<(), SideError> {
        Ok(())
    }
    /// True when [`RunFluid::start_advance`] returns before the fluid has advanced: the fluid
    /// computes on cores of its own while this process goes on. False for in-process solvers
    /// (the native fluid computes on the cores the DEM's threads use).
    fn runs_apart(&self) -> bool {
        false
    }
    /// A line on what the backend's exchange cost (external solvers), for the run's log.
    fn report(&self) -> Option<String> {
        None
    }
    /// Ends the fluid's run (stops a solver process); a no-op for in-process solvers.
    fn finish(&mut self) -> Result<(), SideError> {
        Ok(())
    }
    /// Asks for the whole exchange fields after each advance when the coupler ranks exchange
    /// straight with the solver's ranks (no coupler rank holds them then; monitors need
    /// them). A no-op where the coupler holds them.
    fn want_held(&mut self) {}
    /// With [`RunFluid::want_held`] in such a run: ε, Ksl, Us and f of the last advance
    /// (global cell order), which the run puts into its step for the monitors.
    fn held_exchange(&self) -> Option<HeldExchange<'_>> {
        None
    }
    /// When this rank's [`FluidSide::state`] is not the current fluid on the whole mesh
    /// (coupler rank 0 in grainPisoFoam's sparse exchange, without [`RunFluid::want_held`]:
    /// the solver ranks reply with the patch sums only): asks the fluid for U of the whole
    /// mesh's `cells` and, with `cfl`, for max |U|/∛V over its cells, after each advance
    /// ([`RunFluid::watched`]). `Ok(false)`: the state is current, read it instead.
    fn watch(&mut self, cells: &[usize], cfl: bool) -> Result<bool, SideError> {
        let _ = (cells, cfl);
        Ok(false)
    }
    /// After [`RunFluid::watch`] said `true`: its values of the last advance.
    fn watched(&self) -> Option<Watched<'_>> {
        None
    }
    /// The faces of patch `name` (area vectors out of the domain), for the native
    /// `surfaceFieldValue` ([`crate::surface_values`]); `None` without the patch or where the
    /// backend runs OpenFOAM's own function objects (grainPisoFoam).
    fn patch_faces(&self, name: &str) -> Option<PatchFaces> {
        let _ = name;
        None
    }
    /// The values of `field` on the faces of patch `name`, in [`RunFluid::patch_faces`]' order:
    /// `phi` (m³/s, out of the domain), the kinematic pressure `p` (m²/s²) or `U` (m/s); `None`
    /// for another field or where [`RunFluid::patch_faces`] is `None`.
    fn patch_field(&self, name: &str, field: &str) -> Option<FaceField> {
        let _ = (name, field);
        None
    }
}

/// The faces of one patch.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchFaces {
    /// Area vectors S_f (m²), out of the domain on this side.
    pub sf: Vec<V3>,
    /// Their magnitudes |S_f| (m²).
    pub mag_sf: Vec<f64>,
}

/// A field's values on the faces of a patch.
#[derive(Clone, Debug, PartialEq)]
pub enum FaceField {
    /// One number per face.
    Scalar(Vec<f64>),
    /// One vector per face.
    Vector(Vec<V3>),
}

/// What [`RunFluid::watch`] asked for.
#[derive(Clone, Copy, Debug)]
pub struct Watched<'a> {
    /// U of the watched cells (m/s), in the order they were named.
    pub u: &'a [V3],
    /// max |U|/∛V over the fluid's cells (1/s), when asked for.
    pub u_by_size: Option<f64>,
}

/// Whole exchange fields held by an external solver (ADR 0004 units).
pub struct HeldExchange<'a> {
    /// ε at the end of the interval.
    pub eps: &'a [f64],
    /// Ksl, kg/(m³ s).
    pub ksl: &'a [f64],
    /// Us, m/s.
    pub us: &'a [mesh::v3::V3],
    /// f, N/m³.
    pub f: &'a [mesh::v3::V3],
}

/// The fluid side of a coupler rank other than 0 in an N-rank run ([`couple::ranks`]): rank 0
/// holds the fluid and sends each rank the cells it needs, so this side only has the mesh (for
/// locating particles), the clock, and zero fields of the mesh's size that the coupler never
/// reads. It writes nothing and observes no patch.
pub struct StandInFluid {
    mesh: PolyMesh,
    time: f64,
    u: Vec<mesh::v3::V3>,
    p: Vec<f64>,
}

impl StandInFluid {
    /// The mesh of the run's OpenFOAM case and its start time (`system/controlDict`, read
    /// once into the plan).
    pub fn open(plan: &crate::plan::RunPlan) -> Result<StandInFluid, crate::error::RunError> {
        let mesh = foam::Case::open(&plan.layout.cfd)?.read_mesh()?;
        Ok(StandInFluid::on_mesh(plan, mesh))
    }

    /// The stand-in on `mesh` (a part of the case's mesh, [`couple::part`]).
    pub fn on_mesh(plan: &crate::plan::RunPlan, mesh: PolyMesh) -> StandInFluid {
        let n = mesh.n_cells;
        StandInFluid {
            mesh,
            time: plan.fluid.start_time,
            u: vec![mesh::v3::V3::zeros(); n],
            p: vec![0.0; n],
        }
    }
}

impl FluidSide for StandInFluid {
    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn set_exchange(&mut self, _fields: &couple::ExchangeFields<'_>) -> Result<(), SideError> {
        Ok(())
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.time += dt;
        Ok(())
    }

    fn state(&self) -> couple::FluidState<'_> {
        couple::FluidState {
            vorticity: None,
            ddt_u: None,
            turbulence: None,
            temperature: None,
            u: &self.u,
            p: &self.p,
            grad_p: &self.u,
            div_tau: &self.u,
        }
    }

    /// Its mesh (the first part's, or the whole mesh) and its zero fields.
    fn held_bytes(&self) -> Option<usize> {
        use foam::heap::{flat, HeapBytes as _};
        Some(self.mesh.heap_bytes() + flat(&self.u) + flat(&self.p))
    }
}

impl RunFluid for StandInFluid {
    fn time(&self) -> f64 {
        self.time
    }

    fn cells_held(&mut self, n_cells: usize) {
        // grown, never shrunk: what the run observed on the first part keeps its cells
        if n_cells > self.u.len() {
            self.u.resize(n_cells, mesh::v3::V3::zeros());
            self.p.resize(n_cells, 0.0);
        }
    }

    fn patch_pressure(&self, _name: &str) -> Option<f64> {
        None
    }

    fn inflow_velocity(&self, _name: &str) -> Option<f64> {
        None
    }

    fn write_time(
        &mut self,
        _cfd: &Path,
        _mesh: &PolyMesh,
        _step: &CouplingStep,
    ) -> Result<String, SideError> {
        Ok(couple::output::time_name(self.time))
    }
}
