//! ADR 0004's particle force, `F = F_ext + β (u_f − v)` every DEM step until the next
//! exchange, as the per-particle fields of LIGGGHTS's coupling fixes.
//!
//! What LIGGGHTS 3.8.0 applies each step (read in `fix_cfd_coupling_force_implicit.cpp` and
//! `fix_cfd_coupling_force.cpp`, `post_force`, i.e. after the drift, with the half-step
//! velocity v of velocity Verlet — the same v the native DEM uses):
//! - `couple/cfd/force/implicit`: `f += Ksl·(uf − v) + dragforce` (without Crank–Nicolson,
//!   which [`crate::deck`] refuses), with `Ksl` a per-particle scalar (kg/s), `uf` and
//!   `dragforce` per-particle vectors pulled from the coupler. So `Ksl = β`, `uf = u_f`,
//!   `dragforce = F_ext` reproduce ADR 0004 exactly.
//! - `couple/cfd/force`: `f += dragforce` only. The implicit part can then only be frozen at
//!   the exchange: `dragforce = F_ext + β (u_f − v_exchange)` (CFDEM's explicit coupling); the
//!   difference to ADR 0004 grows like β·Δt_couple/m. The side reports which of the two a deck
//!   uses ([`crate::ForceMode`]).
//!
//! Timing: runs after the first are `run N pre no post no`, so the first half kick of an
//! interval still uses the force of the previous interval's last step; new forces act from
//! the first force evaluation on (the native DEM does the same: `set_coupling` keeps its stored
//! forces). Tested in `tests/link_explicit.rs` to 1e-12. After a `write_restart` (CFDEM's
//! `writeLiggghts`) the next run is a plain `run N` again: a run restarted from that file
//! begins with LIGGGHTS's setup, which computes the forces with the exchange's new fields, and
//! the run that wrote it does the same, so the two continue alike (`cli/tests/dying_rank.rs`).

use mesh::v3::V3;

use crate::error::LiggghtsError;

/// How a deck's force fix takes ADR 0004's force.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForceMode {
    /// `couple/cfd/force/implicit`: β(u_f − v) with the current v every step (exact).
    Implicit,
    /// `couple/cfd/force`: β(u_f − v) frozen at the exchange velocity.
    FrozenAtExchange,
}

/// The pulled fields in the coupler's particle order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ForceFields {
    /// `dragforce` (N).
    pub dragforce: Vec<V3>,
    /// `Ksl` (kg/s per particle; empty for [`ForceMode::FrozenAtExchange`]).
    pub ksl: Vec<f64>,
    /// `uf` (m/s; empty for [`ForceMode::FrozenAtExchange`]).
    pub uf: Vec<V3>,
}

/// Maps (F_ext, β, u_f) of the particles `ids` moving at `v` onto the fields of `mode`,
/// checking lengths, finiteness and β ≥ 0 (errors name the particle by tag).
pub fn force_fields(
    mode: ForceMode,
    ids: &[u64],
    v: &[V3],
    f_ext: &[V3],
    beta: &[f64],
    u_f: &[V3],
    out: &mut ForceFields,
) -> Result<(), LiggghtsError> {
    let n = ids.len();
    for (what, len) in [
        ("explicit forces", f_ext.len()),
        ("drag coefficients", beta.len()),
        ("fluid velocities", u_f.len()),
        ("particle velocities", v.len()),
    ] {
        if len != n {
            return Err(LiggghtsError::Length {
                what,
                expected: n,
                found: len,
            });
        }
    }
    if let Some(i) = (0..n).find(|&i| {
        !(f_ext[i].iter().chain(&u_f[i]).all(|c| c.is_finite())
            && beta[i].is_finite()
            && beta[i] >= 0.0)
    }) {
        return Err(LiggghtsError::Particle {
            tag: ids[i],
            message: format!(
                "F_ext {:?}, β {}, u_f {:?} (finite values and β ≥ 0 needed)",
                f_ext[i], beta[i], u_f[i]
            ),
        });
    }
    out.dragforce.clear();
    out.ksl.clear();
    out.uf.clear();
    match mode {
        ForceMode::Implicit => {
            out.dragforce.extend_from_slice(f_ext);
            out.ksl.extend_from_slice(beta);
            out.uf.extend_from_slice(u_f);
        }
        ForceMode::FrozenAtExchange => {
            out.dragforce.extend((0..n).map(|i| {
                let (f, b, u, w) = (f_ext[i], beta[i], u_f[i], v[i]);
                f + b * (u - w)
            }));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn implicit_passes_the_pair_and_explicit_freezes_it() {
        let ids = [4, 9];
        let v = [V3::new(1.0, 0.0, -2.0), V3::zeros()];
        let f = [V3::new(0.5, 0.0, 0.0), V3::new(0.0, 0.0, -1.0)];
        let beta = [2.0, 0.0];
        let uf = [V3::new(0.0, 3.0, 0.0), V3::new(7.0, 7.0, 7.0)];
        let mut out = ForceFields::default();
        force_fields(ForceMode::Implicit, &ids, &v, &f, &beta, &uf, &mut out).unwrap();
        assert_eq!(out.dragforce, f);
        assert_eq!(out.ksl, beta);
        assert_eq!(out.uf, uf);
        force_fields(
            ForceMode::FrozenAtExchange,
            &ids,
            &v,
            &f,
            &beta,
            &uf,
            &mut out,
        )
        .unwrap();
        // F_ext + β(u_f − v), by hand
        assert_eq!(
            out.dragforce,
            [V3::new(0.5 - 2.0, 6.0, 4.0), V3::new(0.0, 0.0, -1.0)]
        );
        assert!(out.ksl.is_empty() && out.uf.is_empty());
    }

    #[test]
    fn bad_values_name_the_tag() {
        let mut out = ForceFields::default();
        let e = force_fields(
            ForceMode::Implicit,
            &[3, 8],
            &[V3::zeros(); 2],
            &[V3::zeros(); 2],
            &[1.0, -1.0],
            &[V3::zeros(); 2],
            &mut out,
        )
        .unwrap_err();
        assert!(e.to_string().starts_with("particle 8:"), "{e}");
        let e = force_fields(
            ForceMode::Implicit,
            &[3],
            &[V3::zeros()],
            &[V3::zeros()],
            &[],
            &[V3::zeros()],
            &mut out,
        )
        .unwrap_err();
        assert!(matches!(e, LiggghtsError::Length { .. }), "{e}");
    }
}
