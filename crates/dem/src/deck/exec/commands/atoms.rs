//! Commands that create and change particles: `create_atoms`, `set`, `velocity`,
//! `delete_atoms`.

use liggghts_deck::Command;
use mesh::v3::V3;

use crate::particles::NewParticle;
use crate::region::Region;

use super::super::args::{int, num, word, yes_no};
use super::super::{Failure, Session};

pub(super) fn create_atoms(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    session.coarse_graining_check("create_atoms")?;
    let t = int(w, 1, "atom type")? as u32;
    if word(w, 2, "style")? != "single" {
        return Err("only `create_atoms T single x y z [units box]` is supported".into());
    }
    let x = V3::new(num(w, 3, "x")?, num(w, 4, "y")?, num(w, 5, "z")?);
    match (
        w.get(6).map(String::as_str),
        w.get(7).map(String::as_str),
        w.len(),
    ) {
        (None, _, 6) | (Some("units"), Some("box"), 8) => {}
        _ => return Err("only `units box` may follow the position".into()),
    }
    // LAMMPS's granular defaults: diameter 1, density 1 (change them with `set`)
    let p = NewParticle {
        id: 0,
        atom_type: t,
        x,
        v: V3::zeros(),
        omega: V3::zeros(),
        radius: 0.5,
        density: 1.0,
    };
    let nt = session.ntypes()?;
    if t == 0 || t as usize > nt {
        return Err(format!("atom type {t} outside 1..={nt}").into());
    }
    match &mut session.sim {
        Some(s) => s.add_particles(&[p])?,
        None => {
            let next = session
                .pending
                .particles
                .iter()
                .map(|p| p.id)
                .max()
                .unwrap_or(0)
                + 1;
            session
                .pending
                .particles
                .push(NewParticle { id: next, ..p });
        }
    }
    Ok(())
}

/// `set group all diameter D density ρ`, `set group all|region R property/atom NAME V`.
pub(super) fn set(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let region = match (word(w, 1, "set style")?, word(w, 2, "group or region id")?) {
        ("group", "all") => None,
        ("region", id) => Some(session.region_ref(id)?),
        _ => return Err("only `set group all …` and `set region R …` are supported".into()),
    };
    if w.get(3).map(String::as_str) == Some("property/atom") {
        return set_property(session, region, w);
    }
    if region.is_some() {
        return Err("`set region R` supports `property/atom NAME VALUE` only".into());
    }
    let mut radius = None;
    let mut density = None;
    let mut k = 3;
    while k < w.len() {
        match w[k].as_str() {
            // LIGGGHTS-PFM: the parcels' diameter is CG × the written one
            "diameter" => {
                radius = Some(0.5 * session.coarse_grained() * num(w, k + 1, "diameter")?)
            }
            "density" => density = Some(num(w, k + 1, "density")?),
            o => return Err(format!("set keyword `{o}` is not supported").into()),
        }
        k += 2;
    }
    if radius.is_some_and(|r| r <= 0.0) || density.is_some_and(|d| d <= 0.0) {
        return Err("diameter and density must be > 0".into());
    }
    match &mut session.sim {
        Some(s) => {
            let p = &mut s.particles;
            for i in 0..p.len() {
                if let Some(r) = radius {
                    p.radius[i] = r;
                }
                if let Some(d) = density {
                    p.density[i] = d;
                }
                p.mass[i] = 4.0 / 3.0 * std::f64::consts::PI * p.radius[i].powi(3) * p.density[i];
            }
            s.invalidate_forces();
        }
        None => {
            for p in &mut session.pending.particles {
                if let Some(r) = radius {
                    p.radius = r;
                }
                if let Some(d) = density {
                    p.density = d;
                }
            }
        }
    }
    Ok(())
}

/// `set … property/atom NAME VALUE` (LIGGGHTS's `set` of a `fix property/atom`): the
/// particles of the group or region (centre in it, boundary included) get VALUE.
fn set_property(
    session: &mut Session<'_>,
    region: Option<Region>,
    w: &[String],
) -> Result<(), Failure> {
    let name = word(w, 4, "property/atom name")?.to_string();
    let value = num(w, 5, &name)?;
    if let Some(extra) = w.get(6) {
        return Err(format!(
            "set property/atom {name}: one value expected (a scalar property), `{extra}` follows"
        )
        .into());
    }
    let s = session.sim_mut()?;
    let select = |x: V3| region.as_ref().is_none_or(|r| r.contains(x));
    s.set_per_atom_where(&name, select, value)?;
    Ok(())
}

pub(super) fn velocity(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    if word(w, 1, "group")? != "all" || word(w, 2, "style")? != "set" || w.len() != 6 {
        return Err("only `velocity all set vx vy vz` is supported".into());
    }
    let v = V3::new(num(w, 3, "vx")?, num(w, 4, "vy")?, num(w, 5, "vz")?);
    match &mut session.sim {
        Some(s) => {
            s.particles.v.iter_mut().for_each(|x| *x = v);
            s.invalidate_forces();
        }
        None => session.pending.particles.iter_mut().for_each(|p| p.v = v),
    }
    Ok(())
}

/// `delete_atoms region R [compress yes|no]`: with `compress yes` (LIGGGHTS's default) the
/// remaining particles get the ids 1…N in the order of their old ids (LIGGGHTS numbers
/// them in its storage order, which this order is for a serial run without sorting).
pub(super) fn delete_atoms(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    if word(w, 1, "style")? != "region" {
        return Err("only `delete_atoms region ID [compress yes|no]` is supported".into());
    }
    let region = session.region_ref(word(w, 2, "region id")?)?;
    let mut compress = true;
    let mut k = 3;
    while k < w.len() {
        match w[k].as_str() {
            "compress" => compress = yes_no(w, k + 1, "compress")?,
            o => return Err(format!("delete_atoms keyword `{o}` is not supported").into()),
        }
        k += 2;
    }
    let s = session.sim_mut()?;
    s.delete_in_region(&region);
    if compress {
        s.compress_ids();
    }
    Ok(())
}
