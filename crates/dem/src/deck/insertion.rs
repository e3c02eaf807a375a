//! The arguments of LIGGGHTS's insertion fixes (`fix ID all insert/pack|insert/rate/region
//! seed S distributiontemplate D …`): the keywords they share are read once here, the
//! fix-specific ones by the caller.

use std::collections::HashMap;

use mesh::v3::V3;

use crate::insert::{Distribution, InsertPack, InsertTarget};
use crate::insert_rate::{InsertRate, Rate, Total};
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

/// `fix ID all insert/pack … insert_every once …` (`w`: the command's words).
pub(crate) fn insert_pack(id: &str, w: &[String], known: &Known<'_>) -> Res<InsertPack> {
    let mut target = None;
    let c = common("insert/pack", w, known, |k| {
        let key = w[k].as_str();
        target = Some(match key {
            "particles_in_region" => InsertTarget::ParticlesInRegion(count(w, k + 1, key)?),
            "volumefraction_region" => InsertTarget::VolumeFraction(number(w, k + 1, key)?),
            "mass_in_region" => InsertTarget::MassInRegion(number(w, k + 1, key)?),
            _ => return Ok(None),
        });
        Ok(Some(k + 2))
    })?;
    match c.every {
        Some(Every::Once) => {}
        Some(Every::Steps(_)) => {
            return Err("insert_every N of insert/pack is not supported (only `once`)".into())
        }
        None => return Err("insert/pack needs `insert_every once`".into()),
    }
    if c.start.is_some() {
        return Err("insert/pack: `start` is not supported".into());
    }
    Ok(InsertPack {
        name: id.to_string(),
        seed: c.seed.ok_or("insert/pack needs `seed`")?,
        distribution: c
            .distribution
            .ok_or("insert/pack needs `distributiontemplate`")?,
        velocity: c.velocity,
        omega: c.omega,
        region: c.region.ok_or("insert/pack needs `region`")?,
        target: target.ok_or(
            "insert/pack needs particles_in_region, volumefraction_region or mass_in_region",
        )?,
        all_in: c.all_in,
        overlap_check: c.overlap_check,
        max_attempt: c.max_attempt,
    })
}

/// `fix ID all insert/rate/region seed S distributiontemplate D [nparticles N|INF | mass
/// M|INF] particlerate r | massrate m insert_every K [start s] [overlapcheck yes|no] [all_in
/// yes|no] [vel constant …] [omega constant …] region R [ntry_mc n] [maxattempt n]`
/// ([`crate::insert_rate`]).
pub(crate) fn insert_rate(id: &str, w: &[String], known: &Known<'_>) -> Res<InsertRate> {
    let (mut total, mut rate) = (None, None);
    let c = common("insert/rate/region", w, known, |k| {
        let key = w[k].as_str();
        let inf = value(w, k + 1, key)? == "INF";
        match key {
            "nparticles" | "mass" if total.is_some() => {
                return Err("insert/rate/region: give one of `nparticles` and `mass`".into())
            }
            "nparticles" if inf => total = Some(Total::Unlimited),
            "nparticles" => total = Some(Total::Particles(count(w, k + 1, key)?)),
            "mass" if inf => total = Some(Total::Unlimited),
            "mass" => total = Some(Total::Mass(number(w, k + 1, key)?)),
            "particlerate" | "massrate" if rate.is_some() => {
                return Err("insert/rate/region: give one of `particlerate` and `massrate`".into())
            }
            "particlerate" => rate = Some(Rate::Particles(number(w, k + 1, key)?)),
            "massrate" => rate = Some(Rate::Mass(number(w, k + 1, key)?)),
            // the Monte-Carlo tries for the region's volume: the native regions know theirs
            "ntry_mc" => {
                count(w, k + 1, key)?;
            }
            _ => return Ok(None),
        }
        Ok(Some(k + 2))
    })?;
    let every = match c.every {
        Some(Every::Steps(n)) if n >= 1 => n,
        Some(_) => {
            return Err("insert/rate/region: `insert_every` must be a step count ≥ 1".into())
        }
        None => return Err("insert/rate/region needs `insert_every`".into()),
    };
    Ok(InsertRate {
        name: id.to_string(),
        seed: c.seed.ok_or("insert/rate/region needs `seed`")?,
        distribution: c
            .distribution
            .ok_or("insert/rate/region needs `distributiontemplate`")?,
        region: c.region.ok_or("insert/rate/region needs `region`")?,
        total: total.ok_or("insert/rate/region needs `nparticles` or `mass`")?,
        rate: rate.ok_or("insert/rate/region needs `particlerate` or `massrate`")?,
        every,
        start: c.start,
        velocity: c.velocity,
        omega: c.omega,
        all_in: c.all_in,
        overlap_check: c.overlap_check,
        max_attempt: c.max_attempt,
    })
}
