//! Set-up commands: `atom_style`, `atom_modify`, `units`, `boundary`, `region`, `create_box`,
//! `read_data`, `read_restart`, `neighbor`, `neigh_modify`, `soft_particles`,
//! `hard_particles`, `timestep`, `pair_style`, `pair_coeff`.

use dem_io::Boundary;
use liggghts_deck::Command;
use mesh::v3::V3;

use crate::deck::data_file;
use crate::deck::restart;
use crate::region::Region;
use crate::sim::SimBox;

use super::super::args::{contact_model, int, num, word, yes_no};
use super::super::{Failure, Res, Session};

pub(super) fn atom_style(_: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    if word(w, 1, "style")? != "granular" || w.len() > 2 {
        return Err("only `atom_style granular` is supported".into());
    }
    Ok(())
}

pub(super) fn atom_modify(_: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    // `map array|hash` (particles by tag: always so here) and `sort N binsize`
    // (LIGGGHTS's memory reordering; the native DEM's neighbour lists sort anyway)
    let mut k = 1;
    while k < w.len() {
        match (w[k].as_str(), w.get(k + 1).map(String::as_str)) {
            ("map", Some("array" | "hash")) => k += 2,
            ("sort", Some(_)) if w.len() > k + 2 => {
                int(w, k + 1, "sort interval")?;
                num(w, k + 2, "sort bin size")?;
                k += 3
            }
            _ => {
                return Err("only `atom_modify map array|hash [sort N BINSIZE]` is \
                            supported"
                    .into())
            }
        }
    }
    Ok(())
}

pub(super) fn units(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    // granular physics is the same in any consistent unit system: cgs (cm, g, s,
    // dyn) only moves LIGGGHTS's bounds on Young's modulus
    session.pending.cgs = match word(w, 1, "units")? {
        "si" => false,
        "cgs" => true,
        other => return Err(format!("`units {other}` is not supported (si, cgs)").into()),
    };
    Ok(())
}

pub(super) fn boundary(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    session.before_run("boundary")?;
    if session.pending.sim_box.is_some() {
        return Err("boundary after the box is defined".into());
    }
    let mut b = [[Boundary::Fixed; 2]; 3];
    for k in 0..3 {
        let s = word(w, k + 1, "boundary")?.as_bytes();
        let (lo, hi) = match s.len() {
            1 => (s[0], s[0]),
            2 => (s[0], s[1]),
            _ => return Err(format!("bad boundary `{}`", w[k + 1]).into()),
        };
        for (f, ch) in [(0, lo), (1, hi)] {
            b[k][f] = match Boundary::from_letter(ch) {
                Some(x) => x,
                None => return Err(format!("bad boundary `{}`", w[k + 1]).into()),
            };
        }
    }
    for (k, [lo, hi]) in b.iter().enumerate() {
        if (*lo == Boundary::Periodic) != (*hi == Boundary::Periodic) {
            return Err(format!(
                "boundary `{}`: both faces of an axis must be periodic or neither",
                w[k + 1]
            )
            .into());
        }
    }
    session.pending.boundary = Some(b);
    Ok(())
}

pub(super) fn region(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let (id, r) = parse_region(&c.words)?;
    session.regions.insert(id, r);
    Ok(())
}

/// What LAMMPS's region `block` puts for a bound `INF` (its `BIG`, m).
const REGION_BIG: f64 = 1e20;

fn parse_region(w: &[String]) -> Res<(String, Region)> {
    let id = word(w, 1, "region id")?.to_string();
    let style = word(w, 2, "region style")?;
    let (reg, mut k) = match style {
        "block" => {
            // `INF` (LAMMPS's ±BIG = 1e20): unbounded on that side
            let v: Vec<f64> = (3..9)
                .map(|k| match w.get(k).map(String::as_str) {
                    Some("INF" | "-INF") if k % 2 == 1 => Ok(-REGION_BIG),
                    Some("INF") => Ok(REGION_BIG),
                    _ => num(w, k, "block bound"),
                })
                .collect::<Res<_>>()?;
            if v[0] >= v[1] || v[2] >= v[3] || v[4] >= v[5] {
                return Err("block bounds must satisfy lo < hi".into());
            }
            (
                Region::Block {
                    lo: V3::new(v[0], v[2], v[4]),
                    hi: V3::new(v[1], v[3], v[5]),
                },
                9,
            )
        }
        "cylinder" => {
            let axis = match word(w, 3, "cylinder axis")? {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                o => return Err(format!("cylinder axis `{o}` (x, y or z)")),
            };
            let c1 = num(w, 4, "c1")?;
            let c2 = num(w, 5, "c2")?;
            let radius = num(w, 6, "radius")?;
            let lo = num(w, 7, "lo")?;
            let hi = num(w, 8, "hi")?;
            if radius <= 0.0 || lo >= hi {
                return Err("cylinder needs radius > 0 and lo < hi".into());
            }
            (
                Region::Cylinder {
                    axis,
                    centre: [c1, c2],
                    radius,
                    lo,
                    hi,
                },
                9,
            )
        }
        o => {
            return Err(format!(
                "region style `{o}` is not supported (block, cylinder)"
            ))
        }
    };
    while k < w.len() {
        match (w[k].as_str(), w.get(k + 1).map(String::as_str)) {
            ("units", Some("box")) | ("side", Some("in")) => k += 2,
            ("units", Some(u)) => {
                return Err(format!("region units `{u}` is not supported (units box)"))
            }
            (o, v) => {
                return Err(format!(
                    "region keyword `{o} {}` is not supported",
                    v.unwrap_or("")
                ))
            }
        }
    }
    Ok((id, reg))
}

pub(super) fn create_box(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    session.before_run("the box")?;
    if session.pending.sim_box.is_some() {
        return Err("create_box after the box is defined".into());
    }
    let n = int(w, 1, "number of atom types")? as usize;
    if n == 0 {
        return Err("create_box needs at least one atom type".into());
    }
    let r = session.region_ref(word(w, 2, "region id")?)?;
    let (lo, hi) = r.bounds();
    let boundary = session.boundary()?;
    session.pending.sim_box = Some((SimBox { lo, hi, boundary }, n));
    Ok(())
}

pub(super) fn read_data(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    session.before_run("read_data")?;
    if session.pending.sim_box.is_some() {
        return Err("read_data after the box is defined".into());
    }
    if w.len() != 2 {
        return Err("only `read_data FILE` (no keywords) is supported".into());
    }
    let d = data_file::read_data(&session.path(&w[1]))?;
    let boundary = session.boundary()?;
    session.pending.sim_box = Some((
        SimBox {
            lo: d.lo,
            hi: d.hi,
            boundary,
        },
        d.ntypes,
    ));
    session.pending.particles.extend(d.particles);
    Ok(())
}

/// `read_restart FILE`: the box, boundary, types, particles and step of a LIGGGHTS restart
/// file; its contact histories are applied when the simulation is built.
pub(super) fn read_restart(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    if session.sim.is_some() || session.pending.sim_box.is_some() {
        return Err("read_restart after the box is defined".into());
    }
    if w.len() != 2 {
        return Err("only `read_restart FILE` is supported".into());
    }
    let path = restart::input_name(&session.path(&w[1]))?;
    let (mut loaded, mut warnings) = restart::read(&path)?;
    if session
        .pending
        .boundary
        .is_some_and(|b| b != loaded.sim_box.boundary)
    {
        warnings.push(
            "the restart file has other boundary settings than `boundary`: using the \
             file's (as LIGGGHTS does)"
                .into(),
        );
    }
    session.pending.boundary = Some(loaded.sim_box.boundary);
    session.pending.sim_box = Some((loaded.sim_box, loaded.ntypes));
    session.pending.particles = std::mem::take(&mut loaded.particles);
    session.pending.restart = Some(loaded);
    session.warn(c.line, warnings);
    Ok(())
}

pub(super) fn neighbor(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    session.before_run("neighbor")?;
    if word(w, 2, "style")? != "bin" {
        return Err("only `neighbor SKIN bin` is supported".into());
    }
    let s = num(w, 1, "skin")?;
    if s < 0.0 {
        return Err("skin must be ≥ 0".into());
    }
    // LIGGGHTS-PFM scales the skin with the parcels
    session.pending.skin = Some(session.coarse_grained() * s);
    Ok(())
}

pub(super) fn neigh_modify(_: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    let mut k = 1;
    while k < w.len() {
        match w[k].as_str() {
            // `binsize` sets LIGGGHTS's bins; the native DEM sizes its linked
            // cells from the largest contact distance
            "delay" | "every" | "one" | "page" | "contact_distance_factor" | "binsize" => k += 2,
            "check" => {
                yes_no(w, k + 1, "check")?;
                k += 2
            }
            o => return Err(format!("neigh_modify `{o}` is not supported").into()),
        }
    }
    Ok(())
}

pub(super) fn soft_particles(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    session.pending.soft = yes_no(&c.words, 1, "soft_particles")?;
    Ok(())
}

pub(super) fn hard_particles(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    session.pending.hard = yes_no(&c.words, 1, "hard_particles")?;
    Ok(())
}

pub(super) fn timestep(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let dt = num(&c.words, 1, "time step")?;
    match &mut session.sim {
        Some(s) => s.set_dt(dt)?,
        None if dt > 0.0 => session.pending.dt = Some(dt),
        None => return Err("time step must be > 0".into()),
    }
    Ok(())
}

pub(super) fn pair_style(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    session.before_run("pair_style")?;
    if word(w, 1, "style")? != "gran" {
        return Err("only `pair_style gran …` is supported".into());
    }
    let (m, k) = contact_model(w, 2)?;
    if k != w.len() {
        return Err(format!("unexpected `{}` in pair_style", w[k]).into());
    }
    session.coarse_graining_contact(&m)?;
    session.pending.pair_model = Some(m);
    Ok(())
}

pub(super) fn pair_coeff(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    let w = &c.words;
    if w.len() != 3 || w[1] != "*" || w[2] != "*" {
        return Err("only `pair_coeff * *` is supported".into());
    }
    session.pending.pair_coeff = true;
    Ok(())
}
