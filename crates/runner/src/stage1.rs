//! Stage 1, the packed bed: when the coupled deck starts from a file (`read_data FILE`, or
//! CFDEM's `read_restart FILE`) that does not exist (or `--repack`) and `DEM/in.liggghts_init`
//! does, the init deck runs first — natively, or with the liggghts binary for the LIGGGHTS
//! backends — and writes that file. On N ranks rank 0 packs alone; the others wait for it and
//! learn whether it failed.

use crate::backend::Launch;
use crate::error::{setup_err, RunError};
use crate::plan::{DemBackend, RunOptions, RunPlan};
use crate::report::Event;
use liggghts_deck::Deck;
use std::time::Instant;

/// Runs stage 1 where it is needed; returns its wall-clock seconds (0 when the pack exists).
pub(crate) fn pack(
    plan: &RunPlan,
    opts: &RunOptions,
    launch: &Launch,
    events: &mut dyn FnMut(Event),
) -> Result<f64, RunError> {
    let packed = if launch.rank() == 0 {
        pack_here(plan, opts, events)
    } else {
        Ok(0.0)
    };
    if !launch.all_ok(packed.is_ok()) && packed.is_ok() {
        return Err(RunError::Backend(
            "rank 0 failed in stage 1 (its error is above)".into(),
        ));
    }
    packed
}

/// Stage 1 in this process.
fn pack_here(
    plan: &RunPlan,
    opts: &RunOptions,
    events: &mut dyn FnMut(Event),
) -> Result<f64, RunError> {
    let layout = &plan.layout;
    let Some((data, exists)) = plan.start_file() else {
        return Ok(0.0);
    };
    if !opts.repack && exists {
        events(Event::Message(format!(
            "stage 1: using the existing {} (--repack to pack again)",
            data.display()
        )));
        return Ok(0.0);
    }
    let Some(init) = &layout.init_deck else {
        return Err(setup_err(
            &layout.run_deck,
            format!(
                "reads {} which does not exist, and there is no DEM/in.liggghts_init to make it",
                data.display()
            ),
        ));
    };
    let t = Instant::now();
    let packed = if opts.dem == DemBackend::Native {
        events(Event::Message(format!(
            "stage 1: running {} natively (writes {})",
            init.display(),
            data.display()
        )));
        let deck = Deck::read_with_vars(init, &opts.init_vars)?;
        let dem = crate::native::run_native_deck(&deck, &layout.dem, &mut |w| {
            events(Event::Message(format!("warning: {w}")))
        })?;
        format!("{} particles packed", dem.sim().particles.len())
    } else {
        events(Event::Message(format!(
            "stage 1: running {} with the liggghts binary (writes {})",
            init.display(),
            data.display()
        )));
        crate::backend::pack_with_liggghts(init, &layout.dem, &opts.init_vars)?;
        "packed by LIGGGHTS".to_owned()
    };
    let init_seconds = t.elapsed().as_secs_f64();
    if !plan.start_file().is_some_and(|(_, exists)| exists) {
        return Err(setup_err(
            init,
            format!(
                "ran, but did not write {} (needs `write_data` or `write_restart`)",
                data.display()
            ),
        ));
    }
    events(Event::Message(format!(
        "stage 1: {packed} in {init_seconds:.1} s"
    )));
    Ok(init_seconds)
}
