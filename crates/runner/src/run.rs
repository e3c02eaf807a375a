//! `foamgrain run`: a coupled case on any pair of backends, one way through:
//! read ([`RunPlan`]) → stage 1, the packed bed (`crate::stage1`) → pair the backends
//! (`crate::backend::run_pair`) → the coupled loop (`crate::run_loop`) → outputs and checks.
//!
//! 1. Stage 1 (packing): when the coupled deck starts from a file (`read_data FILE`, or CFDEM's
//!    `read_restart FILE`) that does not exist and `DEM/in.liggghts_init` does, the init deck
//!    is run first (natively, or with the liggghts binary for the LIGGGHTS backends); it writes
//!    that file.
//! 2. Stage 2: the coupled deck builds the DEM, `CFD/` the fluid, `couplingProperties` the
//!    coupler; `(endTime − startTime) / (couplingInterval · dt_DEM)` coupling steps follow.
//! 3. After every step the integral quantities ([`crate::sample::Sample`]) are recorded; at the
//!    case's write times the fluid (U, p), the exchange fields (voidfraction, Ksl, Us, f) and the
//!    particles (`CASE/postProcessing/particles/*.vtp` + `.pvd`) are written, and the CSV
//!    (`postProcessing/integrals.csv`) is rewritten.
//! 4. A stop request (Ctrl-C) ends the loop after the current step; that step's time is then
//!    written completely.
//! 5. The case's `validationDict` decides the checks ([`crate::checks`]); they go to
//!    `postProcessing/validation.json` with PNG plots.

pub use crate::error::RunError;
pub use crate::plan::{RunOptions, RunPlan};
pub use crate::report::{Event, RunReport};

use crate::backend::Launch;
use crate::run_loop::LoopContext;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// Runs the case at `case` (CFDEM layout) natively. `stop` is polled after every coupling step;
/// `events` receives log lines and progress.
pub fn run(
    case: &Path,
    opts: &RunOptions,
    stop: &AtomicBool,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    let launch = Launch::init(opts.fluid, opts.dem)?;
    // On N ranks only rank 0 speaks (the others' log lines would repeat it N times), and an
    // error on any rank ends every rank with its cause (no rank waits for a dead one).
    let mut quiet = |_: Event| {};
    let events: &mut dyn FnMut(Event) = if launch.rank() > 0 {
        &mut quiet
    } else {
        events
    };
    let result = run_launched(case, opts, stop, &launch, events);
    if launch.size() > 1 {
        return result.map_err(|e| launch.fail_together(e));
    }
    result
}

/// [`run`] in the process layout `launch`.
fn run_launched(
    case: &Path,
    opts: &RunOptions,
    stop: &AtomicBool,
    launch: &Launch,
    events: &mut dyn FnMut(Event),
) -> Result<RunReport, RunError> {
    // what a run killed during a write left (crate::journal), before the case is read
    let recovered = match launch.rank() {
        0 => crate::journal::recover(&case.join("CFD")),
        _ => Ok(Vec::new()),
    };
    if !launch.all_ok(recovered.is_ok()) {
        return Err(recovered.err().unwrap_or_else(|| {
            RunError::Backend("rank 0 could not recover the case's last write".into())
        }));
    }
    for line in recovered? {
        events(Event::Message(line));
    }
    let plan = RunPlan::read(case, opts)?;
    if plan.fluid.start_time > 0.0 {
        if let Some((file, _)) = plan.start_file() {
            crate::journal::check_start(&plan.layout.cfd, plan.fluid.start_time, &file)?;
        }
    }
    for w in &plan.warnings {
        events(Event::Message(format!("warning: {w}")));
    }
    let init_seconds = crate::stage1::pack(&plan, opts, launch, events)?;
    if plan.fluid.start_time > 0.0 {
        // a restart: each side starts from what its own input names
        let dem_start = plan.start_file().map_or_else(
            || "the state its deck builds".to_owned(),
            |(f, _)| f.display().to_string(),
        );
        events(Event::Message(format!(
            "restart: the fluid starts at t = {} s from {} (system/controlDict), the particles \
             from {dem_start} ({})",
            plan.fluid.start_time,
            plan.layout
                .cfd
                .join(couple::output::time_name(plan.fluid.start_time))
                .display(),
            plan.layout.run_deck.display(),
        )));
    }
    let ctx = LoopContext {
        plan: &plan,
        opts,
        stop,
        init_seconds,
        ranks: None,
        owners: None,
        part: None,
        part_mesh: None,
        whole: None,
    };
    crate::backend::run_pair(ctx, opts.fluid, opts.dem, launch, events)
}
