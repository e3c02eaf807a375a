//! `forceModels`: the drag law, the other fluid forces, and CFDEM's auxiliary entries of the
//! same list (`noDrag`, which removes forces; `fieldStore`, `particleCellVolume`,
//! `volWeightedAverage`, which observe the fields — see [`super::monitors`]).
//!
//! Which names exist and what each does is the table [`super::registry::FORCES`] (plus the drag
//! laws of [`super::registry::DRAG_LAWS`], closures' list); this file holds the constructors
//! of the forces (the observers' are in [`super::monitors`]).

use super::registry::{DRAG_LAWS, FORCES};
use super::{Built, DragSettings, Given, LiftSettings, NoDrag, Reader, Setup, VirtualMassSettings};
use crate::error::CoupleError;
use crate::interpolate::Interpolation;
use closures::{DragClosure, DragLaw, Parcel, DEFAULT_VOIDAGE_FLOOR};
use foam::Dict;

/// Props keys of a drag law that act, by law.
pub(super) fn drag_keys(law: DragLaw) -> Vec<&'static str> {
    let mut known = vec![
        "interpolation",
        "implForceDEM",
        "treatForceExplicit",
        "treatForceDEM",
        "verbose",
        "scale",
        "scaleDrag",
    ];
    if matches!(law, DragLaw::Gidaspow { .. }) {
        known.extend(["switchingVoidfraction", "phi"]);
    }
    known
}

/// Props keys of drag laws that CFDEM reads but that change nothing here, with why.
const DRAG_KEYS_WITHOUT_EFFECT: [(&str, &str); 3] = [
    (
        "rhoParticle",
        "the particle densities come from the DEM (CFDEM-PFM's BeetstraDrag does not read it either)",
    ),
    (
        "implForceDEMaccumulated",
        "foamgrain's implicit DEM drag is applied every DEM step already",
    ),
    (
        "implDEM_",
        "CFDEM-PFM reads no key of that name (its switch is implForceDEM; PFM's ErgunTestCG \
         writes it)",
    ),
];

/// Reads `forceModels`: a drag law of [`DRAG_LAWS`] through [`drag`], every other name
/// through [`FORCES`].
pub(super) fn read_forces(
    r: &mut Reader<'_>,
    top: &Dict,
    setup: &mut Setup,
) -> Result<(), CoupleError> {
    let key = FORCES.key;
    for name in &r.word_list(top, key)? {
        // every listed model's Props must be a dictionary, whatever the model's support
        r.props(top, name)?;
        let given = Given { key, name, top };
        if let Some(&(_, law)) = DRAG_LAWS.iter().find(|(n, _)| n == name) {
            drag(r, &given, law, setup)?;
        } else if FORCES.support(name).is_none() {
            let mut valid: Vec<&str> = DRAG_LAWS.iter().map(|(n, _)| *n).collect();
            let others = FORCES.valid_names();
            valid.push(&others);
            return Err(r.err(
                key,
                format!("unknown force model `{name}`; valid: {}", valid.join(", ")),
            ));
        } else {
            r.apply(&FORCES, &given, setup)?;
        }
    }
    Ok(())
}

/// CFDEM-PFM's `scale` (the parcels' coarse-graining factor, ≥ 1; 1 leaves it to the DEM's
/// `coarsegraining`, as PFM's `scaleDia_ > 1` test does) and `scaleDrag` (> 0) of a drag law's
/// Props ([`closures::Parcel`]).
fn parcel(r: &Reader<'_>, props: &Dict, dict: &str) -> Result<Parcel, CoupleError> {
    let factor = |key: &str| -> Result<f64, CoupleError> {
        match props.contains(key) {
            true => r.number(props, key, &format!("{dict}/{key}")),
            false => Ok(1.0),
        }
    };
    let (cg, scale_drag) = (factor("scale")?, factor("scaleDrag")?);
    Parcel::new(cg, scale_drag).map_err(|e| {
        let key = if cg >= 1.0 { "scaleDrag" } else { "scale" };
        r.err(&format!("{dict}/{key}"), e.to_string())
    })
}

/// noDrag removes the forces of the models listed before it (CFDEM's order); foamgrain
/// applies it to all of them, so a force listed after it is refused rather than misread.
fn not_after_no_drag(r: &Reader<'_>, g: &Given<'_>, s: &Setup) -> Result<(), CoupleError> {
    match s.forces.no_drag {
        Some(_) => Err(force_after_no_drag(r, g.name, "noDrag")),
        None => Ok(()),
    }
}

/// The interpolation of a fluid force (`gradPForce`, `viscForce`) from its Props.
fn fluid_force(r: &Reader<'_>, g: &Given<'_>, s: &Setup) -> Result<Interpolation, CoupleError> {
    not_after_no_drag(r, g, s)?;
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &["interpolation", "verbose", "treatForceExplicit"],
    )?;
    r.interpolation(props, dict)
}

/// `gradPForce`: −V_p ∇p.
pub(super) fn grad_p(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    s.forces.grad_p = Some(fluid_force(r, g, s)?);
    Ok(())
}

/// `viscForce`: V_p ∇·τ.
pub(super) fn viscous(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    s.forces.viscous = Some(fluid_force(r, g, s)?);
    Ok(())
}

/// `Archimedes`: −ρ V_p g.
pub(super) fn archimedes(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    not_after_no_drag(r, g, s)?;
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &["verbose", "treatForceDEM"])?;
    s.forces.archimedes = true;
    Ok(())
}

/// `noDrag`: `noDEMForce`, `keepCFDForce` ([`NoDrag`]).
pub(super) fn no_drag(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &["noDEMForce", "keepCFDForce", "verbose"])?;
    let flag = |key: &str| r.opt_switch(props, key, &format!("{dict}/{key}"));
    s.forces.no_drag = Some(NoDrag {
        no_dem_force: flag("noDEMForce")?.unwrap_or(false),
        keep_cfd_force: flag("keepCFDForce")?.unwrap_or(false),
    });
    Ok(())
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

/// The constructor of every drag law ([`DRAG_LAWS`]): `law`'s Props (the keys of
/// [`drag_keys`] and [`DRAG_KEYS_WITHOUT_EFFECT`]) into [`DragSettings`].
pub(super) fn drag(
    r: &mut Reader<'_>,
    g: &Given<'_>,
    law: DragLaw,
    s: &mut Setup,
) -> Result<(), CoupleError> {
    drag_with(r, g, law, s, &[])
}

/// `KochHillRWDrag` (CFDEM-PFM): `KochHillDrag` with a random-walk turbulent fluctuation
/// ([`crate::random_walk`]); its Props are the drag's and `cl` (C_L, > 0, default 0.15),
/// `rhoP` (kg/m³, > 0; default each particle's density), `randomTauE` (a key that switches on
/// when present, as PFM reads it); PFM's `velFieldName`, `voidfractionFieldName`,
/// `granVelFieldName` are the standard names.
pub(super) fn koch_hill_rw(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    use crate::random_walk::RandomWalkSettings;
    drag_with(r, g, DragLaw::KochHill, s, &["cl", "rhoP", "randomTauE"])?;
    let (props, dict) = &g.props(r)?;
    let positive = |key: &str| -> Result<Option<f64>, CoupleError> {
        if !props.contains(key) {
            return Ok(None);
        }
        let path = format!("{dict}/{key}");
        match r.number(props, key, &path)? {
            x if x.is_finite() && x > 0.0 => Ok(Some(x)),
            x => Err(r.err(&path, format!("{x} is not positive"))),
        }
    };
    let d = RandomWalkSettings::default();
    s.forces.random_walk = Some(RandomWalkSettings {
        cl: positive("cl")?.unwrap_or(d.cl),
        rho_p: positive("rhoP")?,
        random_tau_e: props.contains("randomTauE"),
        seed: d.seed,
    });
    Ok(())
}

/// [`drag`] accepting also the keys `extra` (read by the caller).
fn drag_with(
    r: &mut Reader<'_>,
    g: &Given<'_>,
    law: DragLaw,
    s: &mut Setup,
    extra: &[&str],
) -> Result<(), CoupleError> {
    let name = g.name;
    if s.forces.drag.is_some() {
        return Err(r.err(g.key, format!("a second drag law `{name}`")));
    }
    not_after_no_drag(r, g, s)?;
    let (props, dict) = &g.props(r)?;
    let mut known = drag_keys(law);
    known.extend(DRAG_KEYS_WITHOUT_EFFECT.iter().map(|(k, _)| *k));
    known.extend_from_slice(extra);
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
    let closure = DragClosure::new(law, floor)
        .map_err(|e| r.err(dict, e.to_string()))?
        .with_parcel(parcel(r, props, dict)?);
    let flag = |key: &str| -> Result<bool, CoupleError> {
        Ok(r.opt_switch(props, key, &format!("{dict}/{key}"))?
            .unwrap_or(false))
    };
    s.forces.drag = Some(DragSettings {
        closure,
        interpolation,
        implicit_dem: flag("implForceDEM")?,
        explicit_fluid: flag("treatForceExplicit")?,
        dem_only: flag("treatForceDEM")?,
    });
    Ok(())
}

/// Props keys the added-mass and lift models accept without effect: CFDEM's probe switch and
/// interpolation-type names (foamgrain's `interpolation true` is its own smooth rule, the same
/// for every field).
const KEYS_WITHOUT_EFFECT: [&str; 5] = [
    "suppressProbe",
    "UInterpolationType",
    "DDtUInterpolationType",
    "vorticityInterpolationType",
    "UrelOldName",
];

/// A switch that must keep the value `expected` in foamgrain, `why` saying why otherwise.
fn fixed_switch(
    r: &Reader<'_>,
    props: &Dict,
    dict: &str,
    key: &str,
    expected: bool,
    why: &str,
) -> Result<(), CoupleError> {
    let path = format!("{dict}/{key}");
    match r.opt_switch(props, key, &path)? {
        Some(v) if v != expected => Err(r.err(&path, format!("`{v}` is not supported: {why}"))),
        _ => Ok(()),
    }
}

/// `treatForceExplicit`: foamgrain applies added mass and lift explicitly (CFDEM's default
/// for them); `false` would fold them into Ksl along the slip velocity.
fn explicit_only(r: &Reader<'_>, props: &Dict, dict: &str) -> Result<(), CoupleError> {
    fixed_switch(
        r,
        props,
        dict,
        "treatForceExplicit",
        true,
        "foamgrain applies this force explicitly (CFDEM's default), its reaction in f",
    )
}

/// `virtualMassForce` (CFDEM-PUBLIC's keys and CFDEM-PFM's): `Cadd` (default 0.5),
/// `splitUrelCalculation` (default false, CFDEM-PFM's unsplit form; CFDEM-PUBLIC stops on
/// false), `interpolation`, `treatForceDEM`, `treatForceExplicit` (true only), `verbose`, the
/// field names `velFieldName`, `phiFieldName`, `voidfractionFieldName`,
/// `granVelFieldName`/`UsFieldName` (standard names only), PFM's `useUs` and `useFelderhof`
/// (false only), `smoothingModel` (`off` only), and [`KEYS_WITHOUT_EFFECT`].
pub(super) fn virtual_mass(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    not_after_no_drag(r, g, s)?;
    let (props, dict) = &g.props(r)?;
    let mut known = vec![
        "Cadd",
        "splitUrelCalculation",
        "interpolation",
        "treatForceDEM",
        "treatForceExplicit",
        "verbose",
        "useUs",
        "useFelderhof",
        "smoothingModel",
    ];
    known.extend(KEYS_WITHOUT_EFFECT);
    r.check_props(props, dict, &known)?;
    explicit_only(r, props, dict)?;
    for key in ["useUs", "useFelderhof"] {
        fixed_switch(
            r,
            props,
            dict,
            key,
            false,
            "CFDEM-PFM's variant is not implemented",
        )?;
    }
    if let Some(w) = r.opt_word(props, "smoothingModel", &format!("{dict}/smoothingModel"))? {
        if w != "off" && w != "noSmoothing" {
            return Err(r.err(
                &format!("{dict}/smoothingModel"),
                format!("`{w}`: the DU/Dt field is not smoothed in foamgrain (use off)"),
            ));
        }
    }
    let c_add = match props.contains("Cadd") {
        true => {
            let key = format!("{dict}/Cadd");
            let c = r.number(props, "Cadd", &key)?;
            if c < 0.0 {
                return Err(r.err(&key, format!("{c} is not ≥ 0")));
            }
            c
        }
        false => closures::forces::SPHERE_VIRTUAL_MASS_COEFFICIENT,
    };
    let flag = |key: &str| -> Result<bool, CoupleError> {
        Ok(r.opt_switch(props, key, &format!("{dict}/{key}"))?
            .unwrap_or(false))
    };
    s.forces.virtual_mass = Some(VirtualMassSettings {
        c_add,
        split: flag("splitUrelCalculation")?,
        interpolation: r.interpolation(props, dict)?,
        dem_only: flag("treatForceDEM")?,
    });
    Ok(())
}

/// The keys both lift models read: `velFieldName` (standard name only), `interpolation`,
/// `treatForceExplicit` (true only), `verbose`, [`KEYS_WITHOUT_EFFECT`], and `extra`.
fn lift(
    r: &Reader<'_>,
    g: &Given<'_>,
    s: &Setup,
    extra: &[&str],
) -> Result<(Dict, String), CoupleError> {
    not_after_no_drag(r, g, s)?;
    let (props, dict) = g.props(r)?;
    let mut known = vec!["interpolation", "treatForceExplicit", "verbose"];
    known.extend(KEYS_WITHOUT_EFFECT);
    known.extend(extra);
    r.check_props(&props, &dict, &known)?;
    explicit_only(r, &props, &dict)?;
    Ok((props, dict))
}

/// `MeiLift`: CFDEM-PUBLIC's keys (`useSecondOrderTerms`, which CFDEM switches on by the key
/// alone — here the key alone or `true`; `false` is an error, since CFDEM would switch the
/// terms on —, `scalarViscosity` false only) and CFDEM-PFM's (`useShearInduced` true only,
/// `useSpinInduced` and `combineShearSpin` false only: foamgrain's particle sides give no spin),
/// with the keys of [`lift`].
pub(super) fn mei_lift(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let extra = [
        "useSecondOrderTerms",
        "scalarViscosity",
        "useShearInduced",
        "useSpinInduced",
        "combineShearSpin",
    ];
    let (props, dict) = &lift(r, g, s, &extra)?;
    fixed_switch(
        r,
        props,
        dict,
        "scalarViscosity",
        false,
        "the fluid's ν is used",
    )?;
    fixed_switch(
        r,
        props,
        dict,
        "useShearInduced",
        true,
        "it is the lift MeiLift computes",
    )?;
    let spin = "the particles' spin is not exchanged (CFDEM-PFM's getParticleAngVels)";
    fixed_switch(r, props, dict, "useSpinInduced", false, spin)?;
    fixed_switch(r, props, dict, "combineShearSpin", false, spin)?;
    let second_order = match props.stream("useSecondOrderTerms") {
        Err(_) => false,
        Ok([]) => true,
        Ok(_) => {
            let key = format!("{dict}/useSecondOrderTerms");
            if !r.switch(props, "useSecondOrderTerms", &key)? {
                return Err(r.err(
                    &key,
                    "`false`: CFDEM switches the second-order terms on whenever the key is \
                     present; remove the key to leave them off",
                ));
            }
            true
        }
    };
    s.forces.mei_lift = Some(LiftSettings {
        interpolation: r.interpolation(props, dict)?,
        second_order,
        dem_only: false,
    });
    Ok(())
}

/// `SaffmanLift` (in neither CFDEM-PUBLIC nor CFDEM-PFM: Saffman's 1965 lift, with the 1968
/// erratum's coefficient), with the keys of [`lift`] and `treatForceDEM`.
pub(super) fn saffman_lift(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &lift(r, g, s, &["treatForceDEM"])?;
    let key = format!("{dict}/treatForceDEM");
    s.forces.saffman_lift = Some(LiftSettings {
        interpolation: r.interpolation(props, dict)?,
        second_order: false,
        dem_only: r.opt_switch(props, "treatForceDEM", &key)?.unwrap_or(false),
    });
    Ok(())
}
