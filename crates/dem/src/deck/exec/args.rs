//! Reading a command's words: numbers, non-negative integers, words, `yes`/`no`, and the
//! contact model keywords that `pair_style gran` and `fix wall/gran` share.

use crate::contact::{ContactModel, RollingModel};

use super::Res;

pub(super) fn num(w: &[String], k: usize, what: &str) -> Res<f64> {
    let s = w
        .get(k)
        .ok_or_else(|| format!("missing {what} (argument {k})"))?;
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("{what}: `{s}` is not a number"))
}

pub(super) fn int(w: &[String], k: usize, what: &str) -> Res<u64> {
    let v = num(w, k, what)?;
    if v < 0.0 || v.fract() != 0.0 {
        return Err(format!("{what}: `{}` is not a non-negative integer", w[k]));
    }
    Ok(v as u64)
}

pub(super) fn word<'w>(w: &'w [String], k: usize, what: &str) -> Res<&'w str> {
    w.get(k)
        .map(String::as_str)
        .ok_or_else(|| format!("missing {what}"))
}

pub(super) fn yes_no(w: &[String], k: usize, what: &str) -> Res<bool> {
    match word(w, k, what)? {
        "yes" | "on" => Ok(true),
        "no" | "off" => Ok(false),
        o => Err(format!("{what}: `{o}` (yes/no expected)")),
    }
}

/// Parses `model hertz tangential history [cohesion sjkr] [rolling_friction cdt|epsd2]
/// [surface default] [tangential_damping on|off] [limitForce on|off]` from `w[k..]`; returns
/// the model and the index after it.
pub(super) fn contact_model(w: &[String], mut k: usize) -> Res<(ContactModel, usize)> {
    let mut m = ContactModel::default();
    let mut normal = false;
    let mut tangential = false;
    while k < w.len() {
        let arg = || word(w, k + 1, &format!("value after `{}`", w[k]));
        match w[k].as_str() {
            "model" => {
                match arg()? {
                    "hertz" => normal = true,
                    o => return Err(format!("normal model `{o}` is not supported (hertz)")),
                }
                k += 2;
            }
            "tangential" => {
                match arg()? {
                    "history" => tangential = true,
                    o => return Err(format!("tangential model `{o}` is not supported (history)")),
                }
                k += 2;
            }
            "cohesion" => {
                match arg()? {
                    "sjkr" => m.cohesion = true,
                    "off" => {}
                    o => return Err(format!("cohesion model `{o}` is not supported (sjkr)")),
                }
                k += 2;
            }
            "rolling_friction" => {
                m.rolling = match arg()? {
                    "cdt" => Some(RollingModel::Cdt),
                    "epsd2" => Some(RollingModel::Epsd2),
                    "off" => None,
                    o => {
                        return Err(format!(
                            "rolling friction model `{o}` is not supported (cdt, epsd2)"
                        ))
                    }
                };
                k += 2;
            }
            "surface" => {
                if arg()? != "default" {
                    return Err(format!("surface model `{}` is not supported", w[k + 1]));
                }
                k += 2;
            }
            "tangential_damping" => {
                m.no_tangential_damping = !yes_no(w, k + 1, "tangential_damping")?;
                k += 2;
            }
            "limitForce" => {
                m.limit_force = yes_no(w, k + 1, "limitForce")?;
                k += 2;
            }
            _ => break,
        }
    }
    if !normal || !tangential {
        return Err("`model hertz tangential history` is required".into());
    }
    Ok((m, k))
}
