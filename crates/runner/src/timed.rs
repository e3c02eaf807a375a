//! A coupling side that measures the wall-clock time spent in its `advance`, so a run can
//! report how a coupling step splits between the DEM, the fluid and the coupler itself. For a
//! fluid whose advance is started and finished apart ([`RunFluid::start_advance`]) the clock
//! counts the start and the wait in the finish: the time the run spends on the fluid, not the
//! time the fluid computes.

use crate::fluid::RunFluid;
use couple::{ExchangeFields, FluidSide, FluidState, ParticleSide, ParticleState, SideError};
use foam::PolyMesh;
use mesh::v3::V3;
use std::time::Instant;

/// Wraps a side; `seconds` accumulates the time spent in `advance`.
pub struct Timed<S> {
    /// The wrapped side.
    pub inner: S,
    /// Wall-clock seconds spent in `advance` so far.
    pub seconds: f64,
}

impl<S> Timed<S> {
    /// Wraps `inner` with a zero clock.
    pub fn new(inner: S) -> Timed<S> {
        Timed {
            inner,
            seconds: 0.0,
        }
    }
}

impl<P: ParticleSide> ParticleSide for Timed<P> {
    fn advance(&mut self, steps: u64) -> Result<(), SideError> {
        let t = Instant::now();
        let r = self.inner.advance(steps);
        self.seconds += t.elapsed().as_secs_f64();
        r
    }
    fn time_step(&self) -> f64 {
        self.inner.time_step()
    }
    fn time(&self) -> f64 {
        self.inner.time()
    }
    fn state(&self) -> ParticleState<'_> {
        self.inner.state()
    }
    fn set_forces(&mut self, f_ext: &[V3], beta: &[f64], u_f: &[V3]) -> Result<(), SideError> {
        self.inner.set_forces(f_ext, beta, u_f)
    }
    fn set_heat_flux(&mut self, q: &[f64]) -> Result<(), SideError> {
        self.inner.set_heat_flux(q)
    }
    fn command(&mut self, command: &str) -> Result<(), SideError> {
        self.inner.command(command)
    }
    fn held_bytes(&self) -> Option<usize> {
        self.inner.held_bytes()
    }
}

impl<F: FluidSide> FluidSide for Timed<F> {
    fn mesh(&self) -> &PolyMesh {
        self.inner.mesh()
    }
    fn set_exchange(&mut self, fields: &ExchangeFields<'_>) -> Result<(), SideError> {
        self.inner.set_exchange(fields)
    }
    fn advance(&mut self, dt: f64) -> Result<(), SideError> {
        let t = Instant::now();
        let r = self.inner.advance(dt);
        self.seconds += t.elapsed().as_secs_f64();
        r
    }
    fn state(&self) -> FluidState<'_> {
        self.inner.state()
    }
    fn held_bytes(&self) -> Option<usize> {
        self.inner.held_bytes()
    }
}

impl<F: RunFluid> Timed<F> {
    /// [`RunFluid::start_advance`], timed.
    pub fn start_advance(&mut self, dt: f64) -> Result<(), SideError> {
        let t = Instant::now();
        let r = self.inner.start_advance(dt);
        self.seconds += t.elapsed().as_secs_f64();
        r
    }

    /// [`RunFluid::finish_advance`], timed.
    pub fn finish_advance(&mut self) -> Result<(), SideError> {
        let t = Instant::now();
        let r = self.inner.finish_advance();
        self.seconds += t.elapsed().as_secs_f64();
        r
    }
}
