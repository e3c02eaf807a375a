//! `forceModels`: the drag law, the other fluid forces, and CFDEM's auxiliary entries of the
//! same list (`noDrag`, which removes forces; `fieldStore`, `particleCellVolume`,
//! `volWeightedAverage`, which observe the fields — see [`super::monitors`]).
//!
//! Which names exist and what each does is the table [`super::registry::FORCES`] (plus the drag
//! laws of [`closures::DRAG_LAW_NAMES`]).

use super::monitors::{self, Monitors};
use super::registry::{Support, FORCES};
use super::{DragSettings, Forces, NoDrag, Reader};
use crate::error::CoupleError;
use crate::interpolate::Interpolation;
use closures::{DragClosure, DragLaw, DEFAULT_VOIDAGE_FLOOR, DRAG_LAW_NAMES};
use foam::Dict;

/// Props keys of a drag law that act, by law.
fn drag_keys(law: DragLaw) -> Vec<&'static str> {
    let mut known = vec![
        "interpolation",
        "implForceDEM",
        "treatForceExplicit",
        "treatForceDEM",
        "verbose",
    ];
    if matches!(law, DragLaw::Gidaspow { .. }) {
        known.extend(["switchingVoidfraction", "phi"]);
    }
    known
}

/// Props keys of drag laws that CFDEM reads but that change nothing here, with why.
const DRAG_KEYS_WITHOUT_EFFECT: [(&str, &str); 2] = [
    (
        "rhoParticle",
        "the particle densities come from the DEM (CFDEM-PFM's BeetstraDrag does not read it either)",
    ),
    (
        "implForceDEMaccumulated",
        "foamgrain's implicit DEM drag is applied every DEM step already",
    ),
];

/// Reads `forceModels` and their Props into the forces and the monitors they declare.
pub(super) fn read_forces(
    r: &mut Reader<'_>,
    top: &Dict,
    monitors: &mut Monitors,
) -> Result<Forces, CoupleError> {
    let names = r.word_list(top, "forceModels")?;
    let mut forces = Forces::default();
    // noDrag removes the forces of the models listed before it (CFDEM's order); foamgrain
    // applies it to all of them, so a force listed after it is refused rather than misread.
    let mut after_no_drag: Option<&str> = None;
    for name in &names {
        let dict = format!("{name}Props");
        let props = r.props(top, name)?;
        if let Ok(law) = DragLaw::from_name(name) {
            if forces.drag.is_some() {
                return Err(r.err("forceModels", format!("a second drag law `{name}`")));
            }
            if let Some(nd) = after_no_drag {
                return Err(force_after_no_drag(r, name, nd));
            }
            forces.drag = Some(read_drag(r, law, &props, &dict)?);
            continue;
        }
        match FORCES.support(name) {
            Some(Support::Refuse(instead)) => {
                return Err(r.err(
                    "forceModels",
                    format!("`{name}` is not supported ({instead})"),
                ))
            }
            None => {
                let mut valid: Vec<&str> = DRAG_LAW_NAMES.iter().map(|(n, _)| *n).collect();
                let others = FORCES.valid_names();
                valid.push(&others);
                return Err(r.err(
                    "forceModels",
                    format!("unknown force model `{name}`; valid: {}", valid.join(", ")),
                ));
            }
            Some(_) => {}
        }
        match name.as_str() {
            "gradPForce" | "viscForce" => {
                if let Some(nd) = after_no_drag {
                    return Err(force_after_no_drag(r, name, nd));
                }
                r.check_props(
                    &props,
                    &dict,
                    &["interpolation", "verbose", "treatForceExplicit"],
                )?;
                let interp = r.interpolation(&props, &dict)?;
                if name == "gradPForce" {
                    forces.grad_p = Some(interp);
                } else {
                    forces.viscous = Some(interp);
                }
            }
            "Archimedes" => {
                if let Some(nd) = after_no_drag {
                    return Err(force_after_no_drag(r, name, nd));
                }
                r.check_props(&props, &dict, &["verbose", "treatForceDEM"])?;
                forces.archimedes = true;
            }
            "noDrag" => {
                r.check_props(&props, &dict, &["noDEMForce", "keepCFDForce", "verbose"])?;
                let flag = |key: &str| r.opt_switch(&props, key, &format!("{dict}/{key}"));
                forces.no_drag = Some(NoDrag {
                    no_dem_force: flag("noDEMForce")?.unwrap_or(false),
                    keep_cfd_force: flag("keepCFDForce")?.unwrap_or(false),
                });
                after_no_drag = Some("noDrag");
            }
            "fieldStore" => monitors.field_store = Some(monitors::field_store(r, &props, &dict)?),
            "particleCellVolume" => {
                monitors.particle_cell_volume =
                    Some(monitors::particle_cell_volume(r, &props, &dict)?)
            }
            "volWeightedAverage" => {
                monitors.vol_weighted_average =
                    Some(monitors::vol_weighted_average(r, &props, &dict)?)
            }
            _ => unreachable!("every acting name of FORCES is matched above"),
        }
    }
    Ok(forces)
}

fn force_after_no_drag(r: &Reader<'_>, name: &str, no_drag: &str) -> CoupleError {
    r.err(
        "forceModels",
        format!(
            "`{name}` is listed after `{no_drag}`: foamgrain's noDrag removes every force \
             model's force, so list it last"
        ),
    )
}

fn read_drag(
    r: &mut Reader<'_>,
    law: DragLaw,
    props: &Dict,
    dict: &str,
) -> Result<DragSettings, CoupleError> {
    let mut known = drag_keys(law);
    known.extend(DRAG_KEYS_WITHOUT_EFFECT.iter().map(|(k, _)| *k));
    r.check_props(props, dict, &known)?;
    for (key, why) in DRAG_KEYS_WITHOUT_EFFECT {
        if props.contains(key) {
            r.warn(format!("{dict}/{key} has no effect: {why}"));
        }
    }
    if props.contains("phi") {
        // CFDEM's GidaspowDragProps carry the sphericity `phi`; spheres have 1, and
        // only spheres are supported.
        let key = format!("{dict}/phi");
        let phi = r.number(props, "phi", &key)?;
        if phi != 1.0 {
            return Err(r.err(
                &key,
                format!("sphericity {phi}: only spheres (phi 1) are supported"),
            ));
        }
    }
    let mut law = law;
    if props.contains("switchingVoidfraction") {
        let key = format!("{dict}/switchingVoidfraction");
        law = DragLaw::Gidaspow {
            switch_voidage: r.number(props, "switchingVoidfraction", &key)?,
        };
    }
    let interpolation = r.interpolation(props, dict)?;
    // With `interpolation true` CFDEM clamps the interpolated ε per law (0.4 for Koch–Hill).
    let floor = match interpolation {
        Interpolation::Smooth => law.cfdem_interpolated_floor(),
        Interpolation::Cell => DEFAULT_VOIDAGE_FLOOR,
    };
    let closure = DragClosure::new(law, floor).map_err(|e| r.err(dict, e.to_string()))?;
    let flag = |key: &str| -> Result<bool, CoupleError> {
        Ok(r.opt_switch(props, key, &format!("{dict}/{key}"))?
            .unwrap_or(false))
    };
    Ok(DragSettings {
        closure,
        interpolation,
        implicit_dem: flag("implForceDEM")?,
        explicit_fluid: flag("treatForceExplicit")?,
        dem_only: flag("treatForceDEM")?,
    })
}
