//! The heat fixes: `heat/gran` (= `heat/gran/conduction`) and `couple/cfd/convection`
//! ([`crate::heat`]). Either creates the heat state (LIGGGHTS's transport equation
//! `heattransfer`) with its T₀; the capacities (`thermalCapacity`) and conductivities
//! (`thermalConductivity`) are the `property/global` values defined when the fix is, or
//! redefined later.

use std::collections::HashMap;

use crate::heat::{conduction, Conduction, ContactArea};
use crate::sim::Simulation;

use super::super::args::{num, word, yes_no};
use super::super::{Failure, Res, Session};
use super::Fix;

/// A heat fix as the deck defines it, applied to the simulation when it exists.
#[derive(Debug, Clone, PartialEq)]
pub(in crate::deck::exec) enum HeatFix {
    /// `heat/gran initial_temperature T0 [contact_area …] [area_correction yes|no]`.
    Conduction {
        /// T₀ (K) as written.
        t0: f64,
        /// `contact_area`.
        area: ContactArea,
        /// `area_correction yes`.
        correction: bool,
    },
    /// `couple/cfd/convection T0 T`.
    Convection {
        /// T₀ (K) as written.
        t0: f64,
    },
}

/// `fix ID all heat/gran initial_temperature T0 [contact_area overlap|projection|constant A]
/// [area_correction yes|no] [store_contact_data no]` (LIGGGHTS's keywords; others refused).
pub(super) fn heat_gran(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    session.coarse_graining_check(fix.style)?;
    if word(w, 4, "`initial_temperature`")? != "initial_temperature" {
        return Err(format!("{}: expecting keyword `initial_temperature`", fix.style).into());
    }
    let t0 = num(w, 5, "initial_temperature")?;
    let mut area = ContactArea::Overlap;
    let mut correction = false;
    let mut k = 6;
    while k < w.len() {
        match w[k].as_str() {
            "contact_area" => {
                let (a, used) = contact_area(w, k + 1)?;
                area = a;
                k += 1 + used;
            }
            "area_correction" => {
                correction = yes_no(w, k + 1, "area_correction")?;
                k += 2;
            }
            "store_contact_data" => {
                if yes_no(w, k + 1, "store_contact_data")? {
                    return Err("heat/gran store_contact_data yes is not supported by the \
                                native DEM (its per-atom contact data are not computed)"
                        .into());
                }
                k += 2;
            }
            o => {
                return Err(format!(
                    "{} keyword `{o}` is not supported (initial_temperature, contact_area, \
                     area_correction, store_contact_data no)",
                    fix.style
                )
                .into())
            }
        }
    }
    if correction && area != ContactArea::Overlap {
        return Err("can use 'area_correction' only for 'contact_area = overlap'".into());
    }
    if session.registry.has_heat_fix() {
        return Err("cannot have more than one fix of style heat/gran".into());
    }
    session.registry.add_heat_fix(&fix.id);
    session.define_heat(HeatFix::Conduction {
        t0,
        area,
        correction,
    })
}

/// The words of `contact_area overlap|projection|constant A` from `w[k]` on (the mode), as
/// `heat/gran` and `wall/gran` read them: the area model and how many words it took.
pub(super) fn contact_area(w: &[String], k: usize) -> Res<(ContactArea, usize)> {
    Ok(match word(w, k, "contact_area mode")? {
        "overlap" => (ContactArea::Overlap, 1),
        "projection" => (ContactArea::Projection, 1),
        "constant" => {
            let a = num(w, k + 1, "contact_area constant")?;
            if a <= 0.0 {
                return Err("'contact_area constant' value must be > 0".into());
            }
            (ContactArea::Constant(a), 2)
        }
        o => {
            return Err(format!(
                "contact_area `{o}`: expecting overlap, projection or constant"
            ))
        }
    })
}

/// `fix ID all couple/cfd/convection T0 T`: the coupler's convective heat flows
/// ([`Simulation::set_convective_heat_flux`]) are added to the particles' heat flows.
pub(super) fn couple_cfd_convection(
    session: &mut Session<'_>,
    fix: Fix<'_>,
) -> Result<(), Failure> {
    let w = fix.words;
    if word(w, 4, "`T0`")? != "T0" {
        return Err("couple/cfd/convection: expecting keyword `T0`".into());
    }
    let t0 = num(w, 5, "T0")?;
    if t0 < 0.0 {
        return Err("couple/cfd/convection: T0 must be >= 0".into());
    }
    if let Some(o) = w.get(6) {
        return Err(format!("couple/cfd/convection: unexpected argument `{o}`").into());
    }
    if !session.registry.has_cfd_fix() {
        return Err("couple/cfd/convection needs a fix of style couple/cfd defined first".into());
    }
    if session
        .pending
        .heat
        .iter()
        .any(|h| matches!(h, HeatFix::Convection { .. }))
        || session
            .sim
            .as_ref()
            .and_then(|s| s.heat())
            .is_some_and(|h| h.convection)
    {
        return Err("more than one fix of style couple/cfd/convection is not allowed".into());
    }
    session.registry.add_convection_fix();
    session.define_heat(HeatFix::Convection { t0 })
}

/// A `property/global … peratomtype` value list of `ntypes` values, by name.
fn per_type(
    props: &HashMap<String, Vec<f64>>,
    style: &HashMap<String, String>,
    name: &str,
    ntypes: usize,
) -> Res<Vec<f64>> {
    let v = props
        .get(name)
        .filter(|_| style.get(name).map(String::as_str) == Some("peratomtype"))
        .ok_or_else(|| {
            format!("missing `fix … property/global {name} peratomtype …` (the heat fixes need it)")
        })?;
    if v.len() != ntypes {
        return Err(format!(
            "property {name} has {} values, {ntypes} needed for {ntypes} atom types",
            v.len()
        ));
    }
    Ok(v.clone())
}

/// Applies a heat fix to the simulation with the properties defined so far.
pub(in crate::deck::exec) fn apply(
    sim: &mut Simulation,
    props: &HashMap<String, Vec<f64>>,
    style: &HashMap<String, String>,
    fix: &HeatFix,
) -> Result<(), Failure> {
    let ntypes = sim.materials().ntypes();
    let capacity = per_type(props, style, "thermalCapacity", ntypes)?;
    match fix {
        HeatFix::Conduction {
            t0,
            area,
            correction,
        } => {
            let conductivity = per_type(props, style, "thermalConductivity", ntypes)?;
            let deltan_ratio = match correction {
                false => None,
                true => Some(conduction::deltan_ratio(
                    &per_type(props, style, "youngsModulus", ntypes)?,
                    &per_type(props, style, "youngsModulusOriginal", ntypes)?,
                    &per_type(props, style, "poissonsRatio", ntypes)?,
                )),
            };
            let h = sim.enable_heat(*t0, capacity)?;
            h.convection_first = h.convection;
            sim.set_conduction(Conduction {
                conductivity,
                area: *area,
                deltan_ratio,
            })?;
        }
        HeatFix::Convection { t0 } => {
            sim.enable_heat(*t0, capacity)?.convection = true;
        }
    }
    Ok(())
}

/// Re-reads the thermal properties into an existing heat state (a `property/global`
/// `thermalCapacity` or `thermalConductivity` redefined after the heat fixes).
pub(in crate::deck::exec) fn refresh(
    sim: &mut Simulation,
    props: &HashMap<String, Vec<f64>>,
    style: &HashMap<String, String>,
) -> Result<(), Failure> {
    let Some(h) = sim.heat() else {
        return Ok(());
    };
    let ntypes = sim.materials().ntypes();
    let mut conduction = h.conduction.clone();
    let (t0, capacity) = (h.t0, per_type(props, style, "thermalCapacity", ntypes)?);
    sim.enable_heat(t0, capacity)?;
    if let Some(c) = &mut conduction {
        c.conductivity = per_type(props, style, "thermalConductivity", ntypes)?;
        sim.set_conduction(c.clone())?;
    }
    Ok(())
}

impl Session<'_> {
    /// At a run's start: LIGGGHTS hands a restart file's per-atom data only to fixes defined
    /// before the first run, so temperatures no heat fix took up by now are dropped (reported).
    pub(in crate::deck::exec) fn drop_restart_heat(&mut self) {
        if self.restart_heat.take().is_some() {
            let message = "the restart file's temperatures (Temp, heatFlux) are dropped: no heat \
                           fix (heat/gran, couple/cfd/convection) was defined before the first \
                           run (LIGGGHTS drops them too; a heat fix defined later starts at its \
                           initial temperature)"
                .to_string();
            self.warn(self.line, vec![message]);
        }
    }

    /// At a run's start: what the native heat model cannot do as LIGGGHTS would (walls with a
    /// temperature need `heat/gran`'s conductivities and no `area_correction`) is refused.
    pub(in crate::deck::exec) fn check_wall_heat(&self) -> Res<()> {
        let Some(h) = self.sim.as_ref().and_then(|s| s.heat()) else {
            return match self.pending.wall_heat.first() {
                // LIGGGHTS stops too: the wall looks for the particles' `Temp` property
                Some(w) => Err(format!(
                    "wall {} has a temperature but no heat fix defines the particles' Temp \
                     (`fix ID all heat/gran initial_temperature T0`)",
                    w.wall
                )),
                None => Ok(()),
            };
        };
        let Some(w) = h.walls.first() else {
            return Ok(());
        };
        match &h.conduction {
            None => Err(format!(
                "wall {} has a temperature: the native DEM conducts with walls only with \
                 `fix heat/gran` (its thermalConductivity)",
                w.wall
            )),
            Some(c) if c.deltan_ratio.is_some() => Err(format!(
                "wall {} has a temperature: heat/gran area_correction with walls is not \
                 implemented by the native DEM",
                w.wall
            )),
            Some(_) => Ok(()),
        }
    }

    /// Applies a heat fix now if the simulation exists, else when it is built; the first
    /// one applied takes up the temperatures a restart file carried.
    fn define_heat(&mut self, fix: HeatFix) -> Result<(), Failure> {
        match &mut self.sim {
            Some(s) => {
                apply(s, &self.pending.props, &self.pending.prop_style, &fix)?;
                for w in &self.pending.wall_heat {
                    s.set_wall_heat(w.clone());
                }
                if let Some(saved) = self.restart_heat.take() {
                    s.set_heat_by_id(&saved)?;
                }
            }
            None => self.pending.heat.push(fix),
        }
        Ok(())
    }
}
