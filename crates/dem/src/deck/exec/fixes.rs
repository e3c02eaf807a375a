//! The fix styles the native DEM has: `fix ID all STYLE …` looks its style up in one table,
//! a row per style (its LIGGGHTS name and aliases, and the handler); the handlers are in a
//! module per family — [`properties`] (materials, particle templates and distributions),
//! [`walls`] (primitive and mesh walls, mesh surfaces), [`insert`] (insertion),
//! [`integration`] (time integration, gravity, time-step checks), [`coupling`] (CFD coupling)
//! , [`heat`] (`heat/gran`, `couple/cfd/convection`) and [`output`] (`print`). Adding a fix style is one row here and one handler. `unfix` is
//! here too.

use liggghts_deck::Command;
use mesh::v3::V3;

use super::args::word;
use super::{Failure, Session};

mod coupling;
pub(super) mod heat;
mod insert;
mod integration;
mod output;
mod properties;
mod walls;

/// A `fix ID all STYLE …` command, as its style's handler gets it.
struct Fix<'w> {
    /// The fix id.
    id: String,
    /// The style (one of its row's names).
    style: &'w str,
    /// The command's words (`fix` first).
    words: &'w [String],
}

/// What defines a fix of a style.
type Handler = fn(&mut Session<'_>, Fix<'_>) -> Result<(), Failure>;

/// A fix style: its LIGGGHTS name and aliases, and the handler that defines such a fix.
struct FixStyle {
    /// The names that select it.
    names: &'static [&'static str],
    /// Defines the fix.
    handler: Handler,
}

/// Every fix style the native DEM knows.
static FIXES: &[FixStyle] = &[
    row(&["property/global"], properties::property_global),
    row(&["gravity"], integration::gravity),
    row(&["wall/gran"], walls::wall_gran),
    row(
        &["mesh/surface", "mesh/surface/stress"],
        walls::mesh_surface,
    ),
    row(
        &["particletemplate/sphere"],
        properties::particletemplate_sphere,
    ),
    row(
        &[
            "particledistribution/discrete",
            "particledistribution/discrete/numberbased",
        ],
        properties::particledistribution_discrete,
    ),
    row(&["insert/pack"], insert::insert_pack),
    row(
        &["insert/rate/region", "insert/stream"],
        insert::insert_rate,
    ),
    row(&["nve/sphere"], integration::nve_sphere),
    row(&["check/timestep/gran"], integration::check_timestep_gran),
    row(&["couple/cfd"], coupling::couple_cfd),
    row(
        &["couple/cfd/force", "couple/cfd/force/implicit"],
        coupling::couple_cfd_force,
    ),
    row(&["print"], output::print),
    row(&["heat/gran", "heat/gran/conduction"], heat::heat_gran),
    row(&["couple/cfd/convection"], heat::couple_cfd_convection),
];

/// A row of [`FIXES`].
const fn row(names: &'static [&'static str], handler: Handler) -> FixStyle {
    FixStyle { names, handler }
}

/// `fix ID all STYLE …`: the handler of STYLE's row defines it.
pub(super) fn fix(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let id = word(w, 1, "fix id")?.to_string();
    if word(w, 2, "group")? != "all" {
        return Err("only the group `all` is supported".into());
    }
    let style = word(w, 3, "fix style")?;
    let Some(row) = FIXES.iter().find(|f| f.names.contains(&style)) else {
        return Err(format!("fix style `{style}` is not supported by the native DEM").into());
    };
    session.fixes_defined += 1;
    (row.handler)(
        session,
        Fix {
            id,
            style,
            words: w,
        },
    )
}

pub(super) fn unfix(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let id = word(&c.words, 1, "fix id")?;
    let prints = session.prints.len();
    session.prints.retain(|p| p.id != id);
    if prints != session.prints.len() {
        return Ok(());
    }
    if session.gravity_fix.as_deref() == Some(id) {
        session.gravity_fix = None;
        match &mut session.sim {
            Some(s) => s.set_gravity(V3::zeros()),
            None => session.pending.gravity = None,
        }
        return Ok(());
    }
    let p = &mut session.pending;
    match &mut session.sim {
        Some(s) => {
            if s.remove_insertion(id) {
                return Ok(());
            }
        }
        None => {
            let n = p.walls.len() + p.mesh_walls.len() + p.inserts.len() + p.rate_inserts.len();
            p.walls.retain(|x| x.name != id);
            p.mesh_walls.retain(|x| x.name != id);
            p.inserts.retain(|x| x.name != id);
            p.rate_inserts.retain(|x| x.name != id);
            if n != p.walls.len() + p.mesh_walls.len() + p.inserts.len() + p.rate_inserts.len() {
                return Ok(());
            }
        }
    }
    Err(format!("unfix `{id}`: only gravity, print, insertions, and walls before the first run, can be removed").into())
}
