//! LIGGGHTS-PFM's `coarsegraining CG [model_check error|warn]` (its `src/coarsegraining.cpp`,
//! `doc/coarsegraining.txt`): every particle is a parcel standing for CG³ particles of radius
//! r/CG. The command must come before the box, `neighbor` and every fix. Then, as PFM does:
//! * the radii of `particletemplate/sphere … radius constant R` and of `set … diameter D`
//!   are CG·R and CG·D ([`Session::coarse_grained`]);
//! * the neighbour skin is CG × the written one;
//! * the Hertz–Mindlin contact (pair and walls) is unchanged: its stiffness and damping come
//!   from E, ν, e and the parcel's own radius and mass, which PFM's table calls "inherently
//!   compatible" — the restitution coefficient of a parcel's collision is the real particle's
//!   and its contact time is CG × the real one (Hertz: t_c ∝ (m*²/(R* E*² v))^{1/5} ∝ R at the
//!   same density and speed);
//! * the models PFM marks as not consistent with coarse graining — cohesion `sjkr`, rolling
//!   friction `cdt` and `epsd2`, `heat/gran[/conduction]`, `create_atoms` — are an error, or
//!   with `model_check warn` a warning, and run unscaled ([`Session::coarse_graining_check`]).
//!
//! The factor itself is read by `liggghts_deck::CoarseGraining::parse`, the coupler's reader too.

use liggghts_deck::{CoarseGraining, Command, ModelCheck};

use super::{Failure, Res, Session};

/// `coarsegraining CG [model_check error|warn]`.
pub(super) fn coarsegraining(session: &mut Session<'_>, c: &Command) -> Result<(), Failure> {
    session.before_run("coarsegraining")?;
    if session.pending.sim_box.is_some() || session.pending.skin.is_some() {
        return Err(
            "coarsegraining must come first in the deck: before the box (create_box, \
                    read_data, read_restart) and `neighbor` (LIGGGHTS-PFM's rule)"
                .into(),
        );
    }
    if session.fixes_defined > 0 {
        return Err("coarsegraining must come before any `fix` (LIGGGHTS-PFM's rule)".into());
    }
    session.coarse_graining = Some(CoarseGraining::parse(c)?);
    Ok(())
}

impl Session<'_> {
    /// The coarse-graining factor CG (1 without `coarsegraining`).
    pub(super) fn coarse_grained(&self) -> f64 {
        self.coarse_graining.map_or(1.0, |c| c.factor)
    }

    /// A model PFM does not scale consistently with coarse graining (`what`, PFM's name for it):
    /// with CG > 1 an error, or with `model_check warn` a warning (the model runs unscaled).
    pub(super) fn coarse_graining_check(&mut self, what: &str) -> Res<()> {
        let Some(cg) = self.coarse_graining.filter(|c| c.factor > 1.0) else {
            return Ok(());
        };
        let message = format!(
            "{what} does not yield consistent results with coarse-graining (coarsegraining {} \
             at line {})",
            cg.factor, cg.line
        );
        match cg.model_check {
            ModelCheck::Error => Err(format!(
                "{message}; `coarsegraining CG model_check warn` runs it unscaled"
            )),
            ModelCheck::Warn => {
                let line = self.line;
                self.warn(line, vec![format!("{message}: it runs unscaled")]);
                Ok(())
            }
        }
    }

    /// [`Session::coarse_graining_check`] of a contact model's cohesion and rolling friction.
    pub(super) fn coarse_graining_contact(
        &mut self,
        model: &crate::contact::ContactModel,
    ) -> Res<()> {
        use crate::contact::RollingModel;
        if model.cohesion {
            self.coarse_graining_check("cohesion model sjkr")?;
        }
        match model.rolling {
            Some(RollingModel::Cdt) => self.coarse_graining_check("rolling model cdt"),
            Some(RollingModel::Epsd2) => self.coarse_graining_check("rolling model epsd2"),
            None => Ok(()),
        }
    }
}
