//! `run N [upto] [pre yes|no] [post yes|no]`: the deck's runs, reported as [`DeckEvent`]s,
//! with the time-step checks of `fix check/timestep/gran` at their start.

use closures::timestep::{
    hertz_contact_time_with, rayleigh_time_step, HERTZ_DURATION_CONSTANT_ROUNDED,
};
use liggghts_deck::Command;

use crate::sim::Simulation;

use super::super::args::{int, yes_no};
use super::super::{DeckEvent, Failure, Session};

/// `run N [upto] [pre …] [post …]`: advances in chunks that end at every thermo step and at
/// most [`PROGRESS_REPORTS`](super::super::PROGRESS_REPORTS) times per run (the state does not depend on the chunking:
/// a chunk boundary only re-checks insertions and due dumps).
pub(super) fn run(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let n = int(w, 1, "number of steps")?;
    let mut upto = false;
    let mut k = 2;
    while k < w.len() {
        match w[k].as_str() {
            "upto" => {
                upto = true;
                k += 1;
            }
            "pre" | "post" => {
                yes_no(w, k + 1, &w[k])?;
                k += 2;
            }
            o => return Err(format!("run keyword `{o}` is not supported").into()),
        }
    }
    let (columns, warnings) = session.thermo.for_run(&session.registry, &session.vars)?;
    session.warn(c.line, warnings);
    let checks = session.checks.clone();
    session.sim_mut()?;
    session.drop_restart_heat();
    session.check_wall_heat()?;
    let s = session.sim_mut()?;
    let steps = if upto {
        n.checked_sub(s.step())
            .ok_or_else(|| format!("run {n} upto: already at step {}", s.step()))?
    } else {
        n
    };
    let (from, to) = (s.step(), s.step() + steps);
    if steps > 0 {
        session.require_integration()?;
    }
    let s = session.sim_mut()?;
    let started = std::time::Instant::now();
    s.run(0)?;
    for (fr, fh) in checks {
        check_timestep(s, fr, fh);
    }
    let dt = s.dt();
    (session.observer)(DeckEvent::RunStart {
        line: c.line,
        from,
        to,
        dt,
    });
    (session.observer)(DeckEvent::Output(columns.header()));
    let first = session.row(&columns, 0.0)?;
    (session.observer)(DeckEvent::Output(first));
    session.steps(from, to, &columns, started, true)?;
    let atoms = session.sim_mut()?.particles.len();
    (session.observer)(DeckEvent::Output(format!(
        "Loop time of {} on 1 procs ({} threads) for {steps} steps with {atoms} atoms",
        liggghts_deck::format::format_g(started.elapsed().as_secs_f64(), 6),
        rayon::current_num_threads()
    )));
    Ok(())
}

/// `fix check/timestep/gran`: warns when dt exceeds the given fractions of the smallest
/// Rayleigh time and of the Hertz time (LIGGGHTS's estimate: m* = m, R* = R/2, Y* of the type
/// with itself, v = twice the fastest particle).
fn check_timestep(s: &mut Simulation, frac_r: f64, frac_h: f64) {
    let p = &s.particles;
    let m = s.materials();
    let mut tr = f64::INFINITY;
    let mut th = f64::INFINITY;
    let vmax = p.v.iter().map(|v| (*v).norm()).fold(0.0, f64::max);
    for i in 0..p.len() {
        let t = p.atom_type[i] as usize;
        tr = tr.min(rayleigh_time_step(
            p.radius[i],
            p.density[i],
            m.youngs_modulus[t - 1],
            m.poissons_ratio[t - 1],
        ));
        if vmax > 0.0 {
            let y = m.pair(p.atom_type[i], p.atom_type[i]).y_eff;
            th = th.min(hertz_contact_time_with(
                HERTZ_DURATION_CONSTANT_ROUNDED,
                p.mass[i],
                0.5 * p.radius[i],
                y,
                2.0 * vmax,
            ));
        }
    }
    let dt = s.dt();
    if dt > frac_r * tr {
        // LIGGGHTS's words and digits, so the two logs compare
        let w = format!(
            "check/timestep/gran: time-step is {:.6} % of rayleigh time (dt = {dt} s, \
             Rayleigh time {tr:.6e} s)",
            100.0 * dt / tr
        );
        s.warn(w);
    }
    if dt > frac_h * th {
        let w = format!(
            "check/timestep/gran: time-step is {:.6} % of hertz time (dt = {dt} s, Hertz time \
             {th:.6e} s at twice the fastest speed)",
            100.0 * dt / th
        );
        s.warn(w);
    }
}
