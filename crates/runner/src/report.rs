//! What a run tells its front end: [`Event`]s as it goes and the [`RunReport`] at the end.

use crate::sample::Sample;
use crate::validation::Check;

/// What a run reports as it goes.
#[derive(Clone, Debug)]
pub enum Event {
    /// A log line.
    Message(String),
    /// The coupled loop starts: `steps` coupling steps follow (setting up, stage 1 and
    /// reading the case are done; a front end's estimate of the time left starts here).
    LoopStarted {
        /// Coupling steps to run.
        steps: u64,
    },
    /// Progress after a coupling step.
    Step {
        /// Simulated time, s.
        time: f64,
        /// End time, s.
        end: f64,
        /// Steps done.
        step: u64,
        /// Steps in total.
        steps: u64,
        /// The step's integrals.
        sample: Box<Sample>,
    },
}

/// The outcome of a run.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// This process's rank in an `mpirun -np N` run (0 alone); only rank 0's report holds
    /// the samples and checks.
    pub rank: usize,
    /// Coupling steps done.
    pub steps: u64,
    /// Simulated time reached, s.
    pub time: f64,
    /// True when a stop request ended the run early.
    pub stopped: bool,
    /// Particles at the start of the coupled stage (over all ranks).
    pub particles: usize,
    /// Particles at its end (over all ranks).
    pub particles_at_end: usize,
    /// What entered and left during the coupled stage ([`couple::population`]).
    pub population: couple::PopulationChange,
    /// Fluid cells.
    pub cells: usize,
    /// Wall-clock seconds of stage 1 (packing; 0 when skipped).
    pub init_seconds: f64,
    /// Wall-clock seconds of the coupled loop (stage 2).
    pub loop_seconds: f64,
    /// Of which in the DEM's advance.
    pub dem_seconds: f64,
    /// Of which in the fluid's advance.
    pub fluid_seconds: f64,
    /// Of which in output writing.
    pub output_seconds: f64,
    /// The checks (empty without validationDict or when stopped early).
    pub checks: Vec<Check>,
    /// The samples of every step.
    pub samples: Vec<Sample>,
}

impl RunReport {
    /// Wall-clock seconds of the coupler itself (locate, voidage, forces, exchange):
    /// the loop minus DEM, fluid and output.
    pub fn coupling_seconds(&self) -> f64 {
        (self.loop_seconds - self.dem_seconds - self.fluid_seconds - self.output_seconds).max(0.0)
    }
}
