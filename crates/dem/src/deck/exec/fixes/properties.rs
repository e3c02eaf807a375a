//! Fixes that define materials and particles: `property/global`, `particletemplate/sphere`,
//! `particledistribution/discrete[/numberbased]`.

use crate::insert::{Distribution, SphereTemplate};

use super::super::args::{int, num, word};
use super::super::{Failure, Res, Session};
use super::Fix;

pub(super) fn property_global(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    let name = word(w, 4, "property name")?.to_string();
    // the thermal properties are read by the heat fixes, at any time (LIGGGHTS reads them at
    // every run's set-up); the others make the materials
    let thermal = matches!(name.as_str(), "thermalConductivity" | "thermalCapacity");
    if !thermal {
        session.before_run("material properties")?;
    }
    let pstyle = word(w, 5, "property style")?.to_string();
    let vals: Vec<f64> = match pstyle.as_str() {
        "peratomtype" | "scalar" | "vector" => {
            (6..w.len()).map(|k| num(w, k, &name)).collect::<Res<_>>()?
        }
        "peratomtypepair" => {
            let n = int(w, 6, "number of types")? as usize;
            let v: Vec<f64> = (7..w.len()).map(|k| num(w, k, &name)).collect::<Res<_>>()?;
            if v.len() != n * n {
                return Err(format!(
                    "{name}: peratomtypepair {n} needs {} values, {} given",
                    n * n,
                    v.len()
                )
                .into());
            }
            v
        }
        o => return Err(format!("property style `{o}` is not supported").into()),
    };
    session.pending.prop_style.insert(name.clone(), pstyle);
    session.pending.props.insert(name, vals);
    if let (true, Some(s)) = (thermal, &mut session.sim) {
        super::heat::refresh(s, &session.pending.props, &session.pending.prop_style)?;
    }
    Ok(())
}

pub(super) fn particletemplate_sphere(
    session: &mut Session<'_>,
    fix: Fix<'_>,
) -> Result<(), Failure> {
    let w = fix.words;
    let id = fix.id;
    int(w, 4, "seed")?;
    let mut t = SphereTemplate {
        name: id.clone(),
        atom_type: 0,
        density: 0.0,
        radius: 0.0,
    };
    let mut k = 5;
    while k < w.len() {
        let constant = |k: usize, what: &str| -> Res<f64> {
            if word(w, k + 1, what)? != "constant" {
                return Err(format!(
                    "{what}: only `constant` values are supported, not `{}`",
                    w[k + 1]
                ));
            }
            num(w, k + 2, what)
        };
        match w[k].as_str() {
            "atom_type" => {
                t.atom_type = int(w, k + 1, "atom_type")? as u32;
                k += 2;
            }
            "density" => {
                t.density = constant(k, "density")?;
                k += 3;
            }
            "radius" => {
                // LIGGGHTS-PFM: the parcels' radius is CG × the written one
                t.radius = session.coarse_grained() * constant(k, "radius")?;
                k += 3;
            }
            o => return Err(format!("particletemplate keyword `{o}` is not supported").into()),
        }
    }
    let nt = session.ntypes()?;
    if t.atom_type == 0 || t.atom_type as usize > nt {
        return Err(format!("atom_type {} outside 1..={nt}", t.atom_type).into());
    }
    if t.density <= 0.0 || t.radius <= 0.0 {
        return Err("density and radius must be given and > 0".into());
    }
    session.templates.insert(id, t);
    Ok(())
}

pub(super) fn particledistribution_discrete(
    session: &mut Session<'_>,
    fix: Fix<'_>,
) -> Result<(), Failure> {
    let w = fix.words;
    let id = fix.id;
    let style = fix.style;
    int(w, 4, "seed")?;
    let n = int(w, 5, "number of templates")? as usize;
    if n == 0 || w.len() != 6 + 2 * n {
        return Err(format!("{n} templates need {} arguments", 2 * n).into());
    }
    let mut parts = Vec::new();
    for k in 0..n {
        let name = &w[6 + 2 * k];
        let t = session
            .templates
            .get(name)
            .ok_or_else(|| format!("no particletemplate `{name}`"))?;
        let wt = num(w, 7 + 2 * k, "weight")?;
        if wt < 0.0 {
            return Err("weights must be ≥ 0".into());
        }
        if parts
            .iter()
            .any(|(p, _): &(SphereTemplate, f64)| &p.name == name)
        {
            return Err(format!("template `{name}` used twice").into());
        }
        parts.push((t.clone(), wt));
    }
    if parts.iter().map(|p| p.1).sum::<f64>() <= 0.0 {
        return Err("weights sum to 0".into());
    }
    let mass_based = !style.ends_with("numberbased");
    session
        .dists
        .insert(id.clone(), Distribution::new(&id, parts, mass_based));
    Ok(())
}
