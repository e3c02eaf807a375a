//! The arguments of LIGGGHTS's insertion fixes (`fix ID all insert/pack|insert/rate/region|
//! insert/stream seed S distributiontemplate D …`): the keywords they share are read once
//! here, the fix-specific ones by the caller.

use std::collections::HashMap;
use std::sync::Arc;

use mesh::v3::V3;

use crate::insert::{Distribution, InsertPack, InsertTarget};
use crate::insert_rate::{InsertRate, Rate, Source, Total};
use crate::insert_stream::{Extrude, Stream};
use crate::mesh_wall::MeshSurface;
use crate::region::Region;

type Res<T> = Result<T, String>;

/// `insert_every`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Every {
    Once,
    Steps(u64),
}

/// What the insertion fixes share.
struct Common {
    seed: Option<u64>,
    distribution: Option<Distribution>,
    velocity: V3,
    omega: V3,
    region: Option<Region>,
    all_in: bool,
    overlap_check: bool,
    max_attempt: u32,
    every: Option<Every>,
    start: Option<u64>,
}

/// The deck's particle distributions and regions by id.
pub(crate) struct Known<'a> {
    /// `particledistribution/discrete` fixes.
    pub dists: &'a HashMap<String, Distribution>,
    /// Regions.
    pub regions: &'a HashMap<String, Region>,
    /// `fix mesh/surface` surfaces.
    pub surfaces: &'a HashMap<String, Arc<MeshSurface>>,
}

fn value<'w>(w: &'w [String], k: usize, what: &str) -> Res<&'w str> {
    w.get(k)
        .map(String::as_str)
        .ok_or_else(|| format!("missing the value of `{what}`"))
}

fn number(w: &[String], k: usize, what: &str) -> Res<f64> {
    let s = value(w, k, what)?;
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("{what}: `{s}` is not a number"))
}

fn count(w: &[String], k: usize, what: &str) -> Res<u64> {
    let v = number(w, k, what)?;
    if v < 0.0 || v.fract() != 0.0 {
        return Err(format!("{what}: `{}` is not a non-negative integer", w[k]));
    }
    Ok(v as u64)
}

fn yes_no(w: &[String], k: usize, what: &str) -> Res<bool> {
    match value(w, k, what)? {
        "yes" => Ok(true),
        "no" => Ok(false),
        o => Err(format!("{what}: `{o}` (yes/no expected)")),
    }
}

/// Reads `w[4..]`; a keyword this does not know goes to `extra(keyword index)`, which returns
/// the index after it, or `None` if it does not know it either (an error naming `style`).
fn common(
    style: &str,
    w: &[String],
    known: &Known<'_>,
    mut extra: impl FnMut(usize) -> Res<Option<usize>>,
) -> Res<Common> {
    let mut c = Common {
        seed: None,
        distribution: None,
        velocity: V3::zeros(),
        omega: V3::zeros(),
        region: None,
        all_in: false,
        overlap_check: true,
        max_attempt: 50,
        every: None,
        start: None,
    };
    let mut k = 4;
    while k < w.len() {
        let key = w[k].as_str();
        k = match key {
            "seed" => {
                c.seed = Some(count(w, k + 1, key)?);
                k + 2
            }
            "distributiontemplate" => {
                let d = value(w, k + 1, key)?;
                let dist = known.dists.get(d).cloned();
                c.distribution =
                    Some(dist.ok_or_else(|| format!("no particledistribution `{d}`"))?);
                k + 2
            }
            "vel" | "omega" => {
                if value(w, k + 1, key)? != "constant" {
                    return Err(format!("{key}: only `constant` is supported"));
                }
                let v = V3::new(
                    number(w, k + 2, key)?,
                    number(w, k + 3, key)?,
                    number(w, k + 4, key)?,
                );
                match key {
                    "vel" => c.velocity = v,
                    _ => c.omega = v,
                }
                k + 5
            }
            "insert_every" => {
                c.every = Some(match value(w, k + 1, key)? {
                    "once" => Every::Once,
                    _ => Every::Steps(count(w, k + 1, key)?),
                });
                k + 2
            }
            "start" => {
                c.start = Some(count(w, k + 1, key)?);
                k + 2
            }
            "overlapcheck" => {
                c.overlap_check = yes_no(w, k + 1, key)?;
                k + 2
            }
            "all_in" => {
                c.all_in = yes_no(w, k + 1, key)?;
                k + 2
            }
            "maxattempt" => {
                c.max_attempt = count(w, k + 1, key)? as u32;
                k + 2
            }
            "region" => {
                let id = value(w, k + 1, key)?;
                let r = known.regions.get(id).copied();
                c.region = Some(r.ok_or_else(|| format!("no region `{id}`"))?);
                k + 2
            }
            _ => extra(k)?.ok_or_else(|| format!("{style} keyword `{key}` is not supported"))?,
        };
    }
    Ok(c)
}

/// An `insert/pack` fix: inserting once (at the start of the next run), or every K steps on
/// the schedule of the rate insertions ([`crate::insert_rate`], [`Rate::Fill`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PackFix {
    /// `insert_every once` (or `0`, which LIGGGHTS reads as `once`).
    Once(InsertPack),
    /// `insert_every K`, K ≥ 1.
    Every(InsertRate),
}

/// `fix ID all insert/pack seed S distributiontemplate D insert_every once|K [start s]
/// particles_in_region N | volumefraction_region φ | mass_in_region M region R [all_in yes|no]
/// [overlapcheck yes|no] [vel constant …] [omega constant …] [maxattempt n] [ntry_mc n]`
/// (`w`: the command's words). `start` only with `insert_every K`.
pub(crate) fn insert_pack(id: &str, w: &[String], known: &Known<'_>) -> Res<PackFix> {
    let mut target = None;
    let c = common("insert/pack", w, known, |k| {
        let key = w[k].as_str();
        let t = match key {
            "particles_in_region" => InsertTarget::ParticlesInRegion(count(w, k + 1, key)?),
            "volumefraction_region" => InsertTarget::VolumeFraction(number(w, k + 1, key)?),
            "mass_in_region" => InsertTarget::MassInRegion(number(w, k + 1, key)?),
            // the Monte-Carlo tries for the region's volume: the native regions know theirs
            "ntry_mc" if count(w, k + 1, key)? < 1000 => {
                return Err("insert/pack: ntry_mc must be ≥ 1000 (as LIGGGHTS)".into())
            }
            "ntry_mc" => return Ok(Some(k + 2)),
            _ => return Ok(None),
        };
        if target.is_some() {
            return Err("insert/pack: give exactly one of particles_in_region, \
                        volumefraction_region and mass_in_region"
                .into());
        }
        target = Some(t);
        Ok(Some(k + 2))
    })?;
    let every = match c.every {
        Some(Every::Once | Every::Steps(0)) => None,
        Some(Every::Steps(k)) => Some(k),
        None => return Err("insert/pack needs `insert_every once` or `insert_every K`".into()),
    };
    let target = target
        .ok_or("insert/pack needs particles_in_region, volumefraction_region or mass_in_region")?;
    if let Some(k) = every {
        let region = c.region.ok_or("insert/pack needs `region`")?;
        let rk = RateKeys {
            total: Some(Total::Unlimited),
            rate: Some(Rate::Fill(target)),
        };
        let spec = rate_spec(id, "insert/pack", c, rk, Source::Region(region), k)?;
        return Ok(PackFix::Every(spec));
    }
    if c.start.is_some() {
        return Err("insert/pack: `start` is supported with `insert_every K` only".into());
    }
    Ok(PackFix::Once(InsertPack {
        name: id.to_string(),
        seed: c.seed.ok_or("insert/pack needs `seed`")?,
        distribution: c
            .distribution
            .ok_or("insert/pack needs `distributiontemplate`")?,
        velocity: c.velocity,
        omega: c.omega,
        region: c.region.ok_or("insert/pack needs `region`")?,
        target,
        all_in: c.all_in,
        overlap_check: c.overlap_check,
        max_attempt: c.max_attempt,
    }))
}

/// `fix ID all insert/rate/region seed S distributiontemplate D [nparticles N|INF | mass
/// M|INF] particlerate r | massrate m insert_every K [start s] [overlapcheck yes|no] [all_in
/// yes|no] [vel constant …] [omega constant …] region R [ntry_mc n] [maxattempt n]`
/// ([`crate::insert_rate`]).
pub(crate) fn insert_rate(id: &str, w: &[String], known: &Known<'_>) -> Res<InsertRate> {
    let style = "insert/rate/region";
    let mut rk = RateKeys::default();
    let c = common(style, w, known, |k| rk.read(style, w, k))?;
    let every = match c.every {
        Some(Every::Steps(n)) if n >= 1 => n,
        Some(_) => return Err(format!("{style}: `insert_every` must be a step count ≥ 1")),
        None => return Err(format!("{style} needs `insert_every`")),
    };
    let region = c.region.ok_or("insert/rate/region needs `region`")?;
    rate_spec(id, style, c, rk, Source::Region(region), every)
}

/// The total and the rate of a rate insertion (`nparticles`/`mass`, `particlerate`/
/// `massrate`), and `ntry_mc`, which the native volumes do not need.
#[derive(Default)]
struct RateKeys {
    total: Option<Total>,
    rate: Option<Rate>,
}

impl RateKeys {
    /// Reads the keyword at `w[k]` if it is one of these: the index after it.
    fn read(&mut self, style: &str, w: &[String], k: usize) -> Res<Option<usize>> {
        let key = w[k].as_str();
        let inf = value(w, k + 1, key)? == "INF";
        match key {
            "nparticles" | "mass" if self.total.is_some() => {
                return Err(format!("{style}: give one of `nparticles` and `mass`"))
            }
            "nparticles" if inf => self.total = Some(Total::Unlimited),
            "nparticles" => self.total = Some(Total::Particles(count(w, k + 1, key)?)),
            "mass" if inf => self.total = Some(Total::Unlimited),
            "mass" => self.total = Some(Total::Mass(number(w, k + 1, key)?)),
            "particlerate" | "massrate" if self.rate.is_some() => {
                return Err(format!(
                    "{style}: give one of `particlerate` and `massrate`"
                ))
            }
            "particlerate" => self.rate = Some(Rate::Particles(number(w, k + 1, key)?)),
            "massrate" => self.rate = Some(Rate::Mass(number(w, k + 1, key)?)),
            // the Monte-Carlo tries for the volume's share: the native volumes know theirs
            "ntry_mc" => {
                count(w, k + 1, key)?;
            }
            _ => return Ok(None),
        }
        Ok(Some(k + 2))
    }
}

/// The [`InsertRate`] of a rate insertion read by [`common`] and [`RateKeys`].
fn rate_spec(
    id: &str,
    style: &str,
    c: Common,
    rk: RateKeys,
    source: Source,
    every: u64,
) -> Res<InsertRate> {
    Ok(InsertRate {
        name: id.to_string(),
        seed: c.seed.ok_or(format!("{style} needs `seed`"))?,
        distribution: c
            .distribution
            .ok_or(format!("{style} needs `distributiontemplate`"))?,
        source,
        total: rk
            .total
            .ok_or(format!("{style} needs `nparticles` or `mass`"))?,
        rate: rk
            .rate
            .ok_or(format!("{style} needs `particlerate` or `massrate`"))?,
        every,
        start: c.start,
        velocity: c.velocity,
        omega: c.omega,
        all_in: c.all_in,
        overlap_check: c.overlap_check,
        max_attempt: c.max_attempt,
    })
}

/// `fix ID all insert/stream seed S distributiontemplate D [nparticles N|INF | mass M|INF]
/// particlerate r | massrate m [insert_every K [duration d] | extrude_length L] [start s]
/// [overlapcheck yes|no] vel constant vx vy vz [omega constant …] insertion_face F [ntry_mc n]
/// [maxattempt n] [parallel yes|no]` ([`crate::insert_stream`]). `all_in yes` needs
/// LIGGGHTS's `fix mesh/surface/planar`, which the native DEM does not read: refused.
pub(crate) fn insert_stream(id: &str, w: &[String], known: &Known<'_>) -> Res<InsertRate> {
    let style = "insert/stream";
    let mut rk = RateKeys::default();
    let (mut face, mut length, mut duration) = (None, None, None);
    let c = common(style, w, known, |k| {
        let key = w[k].as_str();
        match key {
            "insertion_face" => {
                let f = value(w, k + 1, key)?;
                let s = known.surfaces.get(f).ok_or_else(|| {
                    format!("insertion_face: no fix mesh/surface `{f}` (define it before)")
                })?;
                face = Some(s.clone());
            }
            "extrude_length" => {
                let l = number(w, k + 1, key)?;
                if l <= 0.0 {
                    return Err(format!("extrude_length {l} must be > 0"));
                }
                length = Some(l);
            }
            "duration" => {
                let d = count(w, k + 1, key)?;
                if d < 1 {
                    return Err("'duration' can not be < 1".into());
                }
                duration = Some(d);
            }
            // which ranks draw: one rank here
            "parallel" => {
                yes_no(w, k + 1, key)?;
            }
            _ => return rk.read(style, w, k),
        }
        Ok(Some(k + 2))
    })?;
    if c.region.is_some() {
        return Err(format!("{style} takes `insertion_face`, not `region`"));
    }
    if c.all_in {
        return Err(format!(
            "{style}: `all_in yes` needs LIGGGHTS's `fix mesh/surface/planar` face, which the \
             native DEM does not read"
        ));
    }
    let every = match c.every {
        Some(Every::Steps(n)) if n >= 1 => n,
        Some(_) => return Err(format!("{style}: `insert_every` must be a step count ≥ 1")),
        None => 0,
    };
    let extrude = match (length, duration, every) {
        (Some(_), _, k) if k > 0 => {
            return Err(format!(
                "{style}: give `insert_every` or `extrude_length`, not both (LIGGGHTS refuses \
                 both too)"
            ))
        }
        (Some(_), Some(_), _) => {
            return Err(format!(
                "{style}: give `extrude_length` or `duration`, not both (LIGGGHTS refuses both too)"
            ))
        }
        (Some(l), None, _) => Extrude::Length(l),
        (None, _, 0) => return Err(format!("{style} needs `insert_every` or `extrude_length`")),
        (None, d, _) => Extrude::Duration(d),
    };
    let face = face.ok_or(format!("{style} needs `insertion_face`"))?;
    let stream = Stream::new(&face.mesh, c.velocity, extrude, c.overlap_check)?;
    rate_spec(id, style, c, rk, Source::Stream(stream), every)
}
