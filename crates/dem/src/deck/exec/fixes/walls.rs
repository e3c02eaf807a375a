//! Walls: `wall/gran` (primitive planes and cylinders, or meshes) and `mesh/surface[/stress]`,
//! the meshes' surfaces.

use crate::contact::ContactModel;
use crate::deck::mesh_surface;
use crate::heat::{ContactArea, WallHeat};
use crate::mesh_wall::{MeshSurface, MeshWall};
use crate::walls::{Wall, WallShape};

use super::super::args::{contact_model, int, num, word};
use super::super::{Failure, Res, Session};
use super::Fix;

pub(super) fn wall_gran(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    let id = fix.id;
    let (model, mut k) = contact_model(w, 4)?;
    session.coarse_graining_contact(&model)?;
    if word(w, k, "`primitive` or `mesh`")? == "mesh" {
        let wall = mesh_wall(session, &id, model, &w[k + 1..])?;
        match &mut session.sim {
            Some(s) => s.add_mesh_wall(wall)?,
            None => session.pending.mesh_walls.push(wall),
        }
        return Ok(());
    }
    if w[k] != "primitive" {
        return Err("walls are `primitive type T xplane|…` or `mesh n_meshes N meshes ID…`".into());
    }
    if word(w, k + 1, "`type`")? != "type" {
        return Err("`primitive` must be followed by `type T`".into());
    }
    let t = int(w, k + 2, "wall material type")? as u32;
    let shape_name = word(w, k + 3, "wall style")?;
    k += 4;
    let shape = match shape_name {
        "xplane" | "yplane" | "zplane" => {
            let axis = (shape_name.as_bytes()[0] - b'x') as usize;
            let position = num(w, k, "plane position")?;
            k += 1;
            WallShape::Plane { axis, position }
        }
        "xcylinder" | "ycylinder" | "zcylinder" => {
            let axis = (shape_name.as_bytes()[0] - b'x') as usize;
            let radius = num(w, k, "cylinder radius")?;
            let centre = [num(w, k + 1, "centre")?, num(w, k + 2, "centre")?];
            if radius <= 0.0 {
                return Err("cylinder radius must be > 0".into());
            }
            k += 3;
            WallShape::Cylinder {
                axis,
                radius,
                centre,
            }
        }
        o => return Err(format!("primitive wall `{o}` is not supported").into()),
    };
    let heat = wall_heat(&id, &w[k..])?;
    let wall = Wall {
        name: id,
        shape,
        material_type: t,
        model,
    };
    match &mut session.sim {
        Some(s) => s.add_wall(wall)?,
        None => session.pending.walls.push(wall),
    }
    if let Some(h) = heat {
        session.pending.wall_heat.retain(|x| x.wall != h.wall);
        session.pending.wall_heat.push(h.clone());
        if let Some(s) = &mut session.sim {
            s.set_wall_heat(h);
        }
    }
    Ok(())
}

/// `[temperature T] [contact_area overlap|projection|constant A]` after a primitive wall's
/// shape: its heat settings when it has a temperature ≥ 0 ([`crate::heat::walls`]).
fn wall_heat(id: &str, w: &[String]) -> Res<Option<WallHeat>> {
    let mut temperature = None;
    let mut area = ContactArea::Overlap;
    let mut k = 0;
    while k < w.len() {
        match w[k].as_str() {
            "temperature" => {
                temperature = Some(num(w, k + 1, "wall temperature")?);
                k += 2;
            }
            "contact_area" => {
                let (a, used) = super::heat::contact_area(w, k + 1)?;
                area = a;
                k += 1 + used;
            }
            o => return Err(format!("unsupported wall keyword `{o}`")),
        }
    }
    // LIGGGHTS: a negative temperature (its default, -1) is no heat transfer
    Ok(temperature
        .filter(|t| *t >= 0.0)
        .map(|temperature| WallHeat {
            wall: id.to_string(),
            temperature,
            area,
        }))
}

pub(super) fn mesh_surface(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    let id = fix.id;
    let parsed = mesh_surface::parse(w, &session.workdir, session.ntypes()?)?;
    session.warn(session.line, parsed.warnings);
    if parsed.surface.stress {
        session.registry.add_mesh_stress_fix(&id);
    }
    session.surfaces.insert(id, parsed.surface);
    Ok(())
}

/// The mesh wall of `wall/gran … mesh n_meshes N meshes ID…` (`rest` = the words after
/// `mesh`).
fn mesh_wall(
    session: &Session<'_>,
    id: &str,
    model: ContactModel,
    rest: &[String],
) -> Res<MeshWall> {
    if word(rest, 0, "`n_meshes`")? != "n_meshes" {
        return Err("expected `mesh n_meshes N meshes ID…`".into());
    }
    let n = int(rest, 1, "n_meshes")? as usize;
    if n == 0 || word(rest, 2, "`meshes`")? != "meshes" {
        return Err("expected `n_meshes N meshes ID…` with N ≥ 1".into());
    }
    if rest.len() != 3 + n {
        return Err(match rest.len() < 3 + n {
            true => format!(
                "n_meshes {n} but {} mesh ids follow `meshes`",
                rest.len() - 3
            ),
            false => format!("unsupported wall keyword `{}`", rest[3 + n]),
        });
    }
    let mut surfaces = Vec::with_capacity(n);
    for m in &rest[3..] {
        let s = session.surfaces.get(m).ok_or_else(|| {
            format!("mesh `{m}` is not a `fix mesh/surface` defined before this line")
        })?;
        if surfaces
            .iter()
            .any(|x: &std::sync::Arc<MeshSurface>| x.mesh.name() == m)
        {
            return Err(format!("mesh `{m}` listed twice"));
        }
        surfaces.push(s.clone());
    }
    Ok(MeshWall::new(id, surfaces, model))
}
