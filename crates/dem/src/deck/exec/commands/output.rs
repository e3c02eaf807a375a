//! Output commands: `log`, `print`, `thermo`, `thermo_log`, `thermo_style`, `thermo_modify`,
//! `compute`, `uncompute`, `dump`, `dump_modify`, `undump`, `write_data`, `write_restart`.

use liggghts_deck::Command;

use crate::atom_value::AtomValue;
use crate::deck::data_file;
use crate::deck::restart;
use crate::deck::values::Values;
use crate::dump::DumpOutput;

use super::super::args::{int, word};
use super::super::{DeckEvent, Failure, Session};

pub(super) fn log(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let file = word(w, 1, "log file")?;
    let append = match (w.get(2).map(String::as_str), w.get(3).map(String::as_str)) {
        (None, _) => false,
        (Some("append"), Some("yes")) => true,
        (Some("append"), Some("no")) => false,
        _ => return Err("usage: log FILE|none [append yes|no]".into()),
    };
    let path = (file != "none").then(|| session.path(file));
    (session.observer)(DeckEvent::Log { path, append });
    Ok(())
}

pub(super) fn print(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    // quoted text keeps its variables until now, as LIGGGHTS's `print` does
    let text = w[1..].join(" ");
    let line = match &session.sim {
        Some(sim) => Values {
            sim,
            registry: &session.registry,
            vars: &session.vars,
            cpu: 0.0,
            norm: session.thermo.norm(),
        }
        .substitute(&text)?,
        None => session.vars.substitute(&text, &|r| {
            Err(format!("`{r}` is known only once the simulation exists"))
        })?,
    };
    (session.observer)(DeckEvent::Output(line));
    Ok(())
}

pub(super) fn thermo(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    session.thermo.set_every(&c.words)?;
    Ok(())
}

pub(super) fn thermo_log(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    session.warn(
        c.line,
        vec![format!(
            "thermo_log {}: the thermo lines go to the screen and log.liggghts only",
            c.words.get(1).map_or("", String::as_str)
        )],
    );
    Ok(())
}

pub(super) fn thermo_style(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let warnings = session.thermo.set_style(&c.words)?;
    session.warn(c.line, warnings);
    Ok(())
}

pub(super) fn thermo_modify(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let warnings = session.thermo.modify(&c.words)?;
    session.warn(c.line, warnings);
    if let Some(s) = &mut session.sim {
        s.set_lost_policy(session.thermo.lost());
    }
    Ok(())
}

pub(super) fn compute(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    session.registry.define_compute(&c.words)?;
    Ok(())
}

pub(super) fn uncompute(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    session
        .registry
        .remove_compute(word(&c.words, 1, "compute id")?)?;
    Ok(())
}

pub(super) fn dump(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let id = word(w, 1, "dump id")?;
    let style = word(w, 3, "style")?;
    if style == "stl" {
        session.pending.stl_dumps.push(id.to_string());
        let message = format!(
            "dump {id} stl writes the meshes of `fix mesh/surface`: the native DEM writes nothing"
        );
        session.warn(session.line, vec![message]);
        return Ok(());
    }
    if word(w, 2, "group")? != "all" || !matches!(style, "custom" | "custom/vtk") {
        return Err("only `dump ID all custom|custom/vtk N FILE columns…` is supported".into());
    }
    let every = int(w, 4, "dump interval")?;
    let file = session.path(word(w, 5, "file name")?);
    let temperature = session.registry.temperature_fixes();
    let heat_column = w[6..]
        .iter()
        .find(|c| AtomValue::parse_in(c, &temperature).is_some_and(AtomValue::needs_heat));
    if let (Some(c), false) = (heat_column, session.registry.has_heat()) {
        return Err(format!(
            "dump column `{c}` needs a heat fix defined before the dump (`fix ID all heat/gran \
             initial_temperature T0` or `couple/cfd/convection`)"
        )
        .into());
    }
    let d = match style {
        "custom" => DumpOutput::new_in(id, every, file, w[6..].to_vec(), &temperature)?,
        _ => DumpOutput::new_vtk(id, every, file, w[6..].to_vec(), &temperature)?,
    };
    match &mut session.sim {
        Some(s) => s.add_dump(d),
        None => session.pending.dumps.push(d),
    }
    Ok(())
}

pub(super) fn dump_modify(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let id = word(w, 1, "dump id")?;
    let d = match &mut session.sim {
        Some(s) => s.dump_mut(id),
        None => session.pending.dumps.iter_mut().find(|d| d.name == id),
    }
    .ok_or_else(|| format!("no dump `{id}`"))?;
    let mut k = 2;
    while k < w.len() {
        match w[k].as_str() {
            "sort" => {
                match word(w, k + 1, "sort")? {
                    "id" => d.sort_by_id = true,
                    "off" => d.sort_by_id = false,
                    o => return Err(format!("dump_modify sort `{o}` (id or off)").into()),
                }
                k += 2;
            }
            // values are always written at full precision; a label is not written
            "format" => k = w.len(),
            "label" => k += 2,
            o => return Err(format!("dump_modify `{o}` is not supported").into()),
        }
    }
    Ok(())
}

pub(super) fn undump(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let id = word(w, 1, "dump id")?;
    let stl = session.pending.stl_dumps.iter().position(|d| d == id);
    let found = match &mut session.sim {
        _ if stl.is_some() => {
            session.pending.stl_dumps.retain(|d| d != id);
            true
        }
        Some(s) => s.remove_dump(id),
        None => {
            let n = session.pending.dumps.len();
            session.pending.dumps.retain(|d| d.name != id);
            n != session.pending.dumps.len()
        }
    };
    if !found {
        return Err(format!("no dump `{id}`").into());
    }
    Ok(())
}

pub(super) fn write_data(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    if w.len() != 2 {
        return Err("only `write_data FILE` is supported".into());
    }
    let path = session.path(&w[1]);
    let s = session.sim_mut()?;
    let b = *s.sim_box();
    let bounds = b.dump_bounds(&s.particles.x);
    data_file::write_data(
        &path,
        &s.particles,
        s.materials().ntypes(),
        bounds.lo.into(),
        bounds.hi.into(),
        s.step(),
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

pub(super) fn write_restart(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    if w.len() != 2 {
        return Err("only `write_restart FILE` is supported (no region)".into());
    }
    let workdir = session.workdir.clone();
    let s = session.sim_mut()?;
    let (_, warnings) = restart::write(s, &w[1], &workdir)?;
    session.warn(c.line, warnings);
    Ok(())
}
