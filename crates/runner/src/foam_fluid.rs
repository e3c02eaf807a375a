//! grainPisoFoam over MPI (`foam-link`) as a [`RunFluid`] (feature `mpi`).
//!
//! The solver writes its own time directories (U, p, voidfraction, Ksl, Us, f: it holds the
//! exchange fields as its own fields); a run's write asks it to write now, in `processorN/`
//! when decomposed, and [`RunFluid::finish`] stops it and reconstructs. An advance can be
//! started and finished apart ([`RunFluid::start_advance`]): the solver's ranks compute while
//! the run advances the particles.

use crate::fluid::{HeldExchange, RunFluid};
use couple::{CouplingStep, ExchangeFields, FluidSide, FluidState, SideError};
use foam::PolyMesh;
use foam_link::OpenFoamFluid;
use std::path::Path;

/// The spawned solver; `None` once finished.
pub struct FoamFluid {
    inner: Option<OpenFoamFluid>,
    mesh: PolyMesh,
}

impl FoamFluid {
    /// Wraps a spawned solver; the coupler works on the solver's mesh.
    pub fn new(inner: OpenFoamFluid) -> FoamFluid {
        let mesh = inner.mesh().clone();
        FoamFluid::on_mesh(inner, mesh)
    }

    /// Wraps a spawned solver whose coupler works on `mesh`: coupler rank 0's part of the
    /// mesh when the solver's ranks exchange straight with the coupler's
    /// ([`crate::mesh_part::foam_on_part`]; the solver's replies to rank 0 are then the patch
    /// sums, or the whole fields in the whole mesh's cell order).
    pub fn on_mesh(inner: OpenFoamFluid, mesh: PolyMesh) -> FoamFluid {
        FoamFluid {
            inner: Some(inner),
            mesh,
        }
    }

    fn solver(&self) -> &OpenFoamFluid {
        self.inner
            .as_ref()
            .expect("the run loop uses the solver only before finish")
    }

    fn solver_mut(&mut self) -> Result<&mut OpenFoamFluid, SideError> {
        self.inner
            .as_mut()
            .ok_or_else(|| "grainPisoFoam has already been stopped".into())
    }
}

impl FluidSide for FoamFluid {
    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError> {
        self.solver_mut()?.set_exchange(fields)
    }

    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        self.solver_mut()?.advance(dt)
    }

    fn state(&self) -> FluidState<'_> {
        self.solver().state()
    }

    /// The coupler's copy of the mesh it holds (the solver's mesh, or rank 0's first part).
    fn held_bytes(&self) -> Option<usize> {
        use foam::heap::HeapBytes as _;
        Some(self.mesh.heap_bytes())
    }
}

impl RunFluid for FoamFluid {
    fn time(&self) -> f64 {
        self.inner.as_ref().map_or(0.0, OpenFoamFluid::time)
    }

    fn patch_pressure(&self, name: &str) -> Option<f64> {
        self.inner.as_ref()?.patch(name).map(|p| p.mean_p)
    }

    fn inflow_velocity(&self, name: &str) -> Option<f64> {
        let p = self.inner.as_ref()?.patch(name)?;
        (p.area > 0.0).then(|| -p.flux / p.area)
    }

    fn write_time(
        &mut self,
        _cfd: &Path,
        _mesh: &PolyMesh,
        _step: &CouplingStep,
    ) -> Result<String, SideError> {
        let solver = self.solver_mut()?;
        solver.write()?;
        // grainPisoFoam's time sums Δt (0.010000000000000005 after 20 steps of 5e-4 s); the
        // directory it wrote is OpenFOAM's name of that time, `0.01`.
        Ok(couple::output::time_name(solver.time()))
    }

    fn start_advance(&mut self, dt: f64) -> Result<(), SideError> {
        Ok(self.solver_mut()?.start_interval(dt)?)
    }

    fn finish_advance(&mut self) -> Result<(), SideError> {
        Ok(self.solver_mut()?.finish_interval()?)
    }

    fn runs_apart(&self) -> bool {
        true
    }

    fn report(&self) -> Option<String> {
        let s = self.inner.as_ref()?.stats();
        let n = s.intervals.max(1) as f64;
        Some(format!(
            "grainPisoFoam exchange: {} intervals, {:.1} kB sent and {:.1} kB received per \
             interval; per interval {:.2} ms packing, {:.2} ms transfer, {:.1} ms waiting for \
             the solver",
            s.intervals,
            s.bytes_sent as f64 / n / 1e3,
            s.bytes_received as f64 / n / 1e3,
            1e3 * s.pack_seconds / n,
            1e3 * s.transfer_seconds / n,
            1e3 * s.wait_seconds / n,
        ))
    }

    fn want_held(&mut self) {
        if let Some(s) = self.inner.as_mut() {
            s.set_whole(s.is_sparse());
        }
    }

    fn held_exchange(&self) -> Option<HeldExchange<'_>> {
        let h = self.inner.as_ref()?.held_fields()?;
        Some(HeldExchange {
            eps: &h.eps,
            ksl: &h.ksl,
            us: &h.us,
            f: &h.f,
        })
    }

    fn watch(&mut self, cells: &[usize], cfl: bool) -> Result<bool, SideError> {
        let solver = self.solver_mut()?;
        if !solver.is_sparse() || solver.is_whole() {
            return Ok(false);
        }
        solver.watch(cells, cfl)?;
        Ok(true)
    }

    fn watched(&self) -> Option<crate::fluid::Watched<'_>> {
        let w = self.inner.as_ref()?.watched()?;
        Some(crate::fluid::Watched {
            u: &w.u,
            u_by_size: w.u_by_size,
        })
    }

    fn finish(&mut self) -> Result<(), SideError> {
        match self.inner.take() {
            Some(s) => Ok(s.finish()?),
            None => Ok(()),
        }
    }
}
