//! Time integration and body forces: `nve/sphere`, `gravity`, `check/timestep/gran` (checked
//! when a run starts).

use mesh::v3::V3;

use super::super::args::{int, num, word};
use super::super::{Failure, Session};
use super::Fix;

pub(super) fn nve_sphere(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    if w.len() != 4 {
        return Err("`nve/sphere` options are not supported".into());
    }
    session.nve = true;
    Ok(())
}

pub(super) fn gravity(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    let id = fix.id;
    let g = num(w, 4, "magnitude")?;
    if word(w, 5, "`vector`")? != "vector" || w.len() != 9 {
        return Err("only `gravity G vector x y z` is supported".into());
    }
    let d = [num(w, 6, "x")?, num(w, 7, "y")?, num(w, 8, "z")?];
    let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if m == 0.0 {
        return Err("gravity direction is zero".into());
    }
    let gv = V3::new(g * d[0] / m, g * d[1] / m, g * d[2] / m);
    session.gravity_fix = Some(id.clone());
    match &mut session.sim {
        Some(s) => s.set_gravity(gv),
        None => session.pending.gravity = Some((id, gv)),
    }
    Ok(())
}

pub(super) fn check_timestep_gran(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    int(w, 4, "check interval")?;
    let fr = num(w, 5, "fraction of the Rayleigh time")?;
    let fh = num(w, 6, "fraction of the Hertz time")?;
    session.checks.push((fr, fh));
    Ok(())
}
