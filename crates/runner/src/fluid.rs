//! What a run needs from a fluid backend beyond the coupling itself ([`RunFluid`]): its clock,
//! the patch averages the observer samples (inlet pressure and velocity) and writing a time.
//!
//! The native solver ([`crate::native::NativeFluid`]) and grainPisoFoam over MPI (feature
//! `mpi`, [`crate::backend`]) implement it.

use couple::{CouplingStep, FluidSide, SideError};
use foam::PolyMesh;
use std::path::Path;

/// A fluid side that a run can observe and write.
pub trait RunFluid: FluidSide {
    /// The fluid's simulated time, s.
    fn time(&self) -> f64;
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
    /// A line on what the backend's exchange cost (external solvers), for the run's log.
    fn report(&self) -> Option<String> {
        None
    }
    /// Ends the fluid's run (stops a solver process); a no-op for in-process solvers.
    fn finish(&mut self) -> Result<(), SideError> {
        Ok(())
    }
}
