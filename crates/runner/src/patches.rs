//! The velocity inlet and the pressure outlet of a case without `validationDict`, found as a
//! CFD user reads them off the start fields, whatever the patches are called:
//! * the inlet is the one patch where `U` is prescribed (`fixedValue` with a non-zero value,
//!   `uniformFixedValue`, `flowRateInletVelocity`, `timeVaryingUniformFixedValue`,
//!   `surfaceNormalFixedValue`, CFDEM's `uniformFixedValueVoidfraction`) and `p` is not;
//! * the outlet is the one patch where `p` is prescribed (`fixedValue`, `totalPressure`,
//!   `uniformFixedValue`, `fixedMean`).
//!
//! Patches of mesh type `wall`, `empty`, `symmetry`, `symmetryPlane`, `wedge`, `cyclic`,
//! `cyclicAMI` and `processor` are never either. When no patch or more than one qualifies, the
//! run records no Δp (or no inlet velocity) and says why once, rather than guessing.

use foam::{Dict, Item, PolyMesh, Value};
use std::path::Path;

/// U boundary types that prescribe an inflow.
const INFLOW_TYPES: [&str; 6] = [
    "fixedValue",
    "uniformFixedValue",
    "uniformFixedValueVoidfraction",
    "flowRateInletVelocity",
    "timeVaryingUniformFixedValue",
    "surfaceNormalFixedValue",
];

/// p boundary types that prescribe the pressure.
const PRESSURE_TYPES: [&str; 4] = [
    "fixedValue",
    "totalPressure",
    "uniformFixedValue",
    "fixedMean",
];

/// Mesh patch types that are neither inlet nor outlet.
const CLOSED_TYPES: [&str; 8] = [
    "wall",
    "empty",
    "symmetry",
    "symmetryPlane",
    "wedge",
    "cyclic",
    "cyclicAMI",
    "processor",
];

/// What was found: the patch names and a note on each that is missing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlowPatches {
    /// The velocity inlet.
    pub inlet: Option<String>,
    /// The pressure outlet.
    pub outlet: Option<String>,
    /// Why an inlet or outlet is missing, one sentence each.
    pub notes: Vec<String>,
}

/// The boundary condition of `patch` in a field's `boundaryField` (OpenFOAM's lookup: the
/// exact name, else the last matching pattern).
fn patch_bc<'a>(boundary: &'a Dict, patch: &str, groups: &[String]) -> Option<&'a Dict> {
    match boundary.resolve(patch, groups).map(|e| &e.value) {
        Some(Value::Dict(d)) => Some(d),
        _ => None,
    }
}

fn bc_type(bc: &Dict) -> Option<&str> {
    bc.get("type").and_then(|v| match v {
        Value::Stream(s) => s.first().and_then(Item::as_word),
        _ => None,
    })
}

/// True when the `value` of a `fixedValue` U is `uniform (0 0 0)` (a no-slip wall).
fn zero_velocity(bc: &Dict) -> bool {
    match bc.get("value") {
        Some(Value::Stream(s)) => match s.as_slice() {
            [Item::Word(u), v] if u == "uniform" => {
                v.as_vector().is_some_and(|v| v.iter().all(|&x| x == 0.0))
            }
            _ => false,
        },
        _ => false,
    }
}

/// Finds the inlet and outlet of the OpenFOAM case `cfd` from its fields `U` and `p` in the
/// time directory `start`; a field that cannot be read gives a note, not an error (the fluid
/// solver reports its own errors).
pub fn find(cfd: &Path, start: &str, mesh: &PolyMesh) -> FlowPatches {
    let read = |name: &str| -> Option<Dict> {
        let path = cfd.join(start).join(name);
        let body = foam::parse_file(&path).ok()?.body;
        match body.get("boundaryField") {
            Some(Value::Dict(d)) => Some(d.clone()),
            _ => None,
        }
    };
    let mut found = FlowPatches::default();
    let (Some(u), Some(p)) = (read("U"), read("p")) else {
        found.notes.push(format!(
            "{start}/U or {start}/p unreadable: no inlet or outlet found"
        ));
        return found;
    };
    let mut inlets = Vec::new();
    let mut outlets = Vec::new();
    for patch in &mesh.boundary {
        if CLOSED_TYPES.contains(&patch.patch_type.as_str()) {
            continue;
        }
        // OpenFOAM matches a patch's type as a group name too (`wall { … }`)
        let groups = std::slice::from_ref(&patch.patch_type);
        let ubc = patch_bc(&u, &patch.name, groups);
        let pbc = patch_bc(&p, &patch.name, groups);
        let u_type = ubc.and_then(bc_type).unwrap_or("");
        let p_type = pbc.and_then(bc_type).unwrap_or("");
        let p_fixed = PRESSURE_TYPES.contains(&p_type);
        let u_inflow = INFLOW_TYPES.contains(&u_type)
            && !(u_type == "fixedValue" && ubc.is_some_and(zero_velocity));
        if u_inflow && !p_fixed {
            inlets.push(patch.name.clone());
        } else if p_fixed && !u_inflow {
            outlets.push(patch.name.clone());
        }
    }
    let pick = |v: Vec<String>, what: &str, notes: &mut Vec<String>| match v.len() {
        1 => v.into_iter().next(),
        0 => {
            notes.push(format!("no {what} patch found in {start}/U and {start}/p"));
            None
        }
        _ => {
            notes.push(format!(
                "{} {what} patches ({}): name them in validationDict to measure Δp",
                v.len(),
                v.join(", ")
            ));
            None
        }
    };
    found.inlet = pick(inlets, "velocity-inlet", &mut found.notes);
    found.outlet = pick(outlets, "pressure-outlet", &mut found.notes);
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(u: &str, p: &str) -> (tempfile::TempDir, PolyMesh) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("0")).unwrap();
        let header = "FoamFile { version 2.0; format ascii; class volVectorField; object x; }\n";
        for (name, bf) in [("U", u), ("p", p)] {
            std::fs::write(
                dir.path().join("0").join(name),
                format!("{header}internalField uniform 0;\nboundaryField\n{{\n{bf}\n}}\n"),
            )
            .unwrap();
        }
        let mesh = mesh::build::uniform_box([0.0; 3], [1.0; 3], [1, 1, 2]);
        (dir, mesh)
    }

    #[test]
    fn inlet_and_outlet_from_the_boundary_conditions() {
        // CFDEM's Ergun tutorial's constructs: a ramped inlet by a table, walls by a pattern
        let u = r#"
            zMin { type uniformFixedValue; uniformValue table ((0 (0 0 0.002)) (0.1 (0 0 0.02))); }
            zMax { type zeroGradient; }
            "(x|y).*" { type fixedValue; value uniform (0 0 0); }"#;
        let p = r#"
            zMax { type fixedValue; value uniform 0; }
            ".*" { type zeroGradient; }"#;
        let (dir, mesh) = case(u, p);
        let found = find(dir.path(), "0", &mesh);
        assert_eq!(found.inlet.as_deref(), Some("zMin"));
        assert_eq!(found.outlet.as_deref(), Some("zMax"));
        assert!(found.notes.is_empty(), "{:?}", found.notes);

        // two velocity inlets: none is guessed, and the note names both
        let (dir, mesh) = case(
            &u.replace(
                "\"(x|y).*\" { type fixedValue; value uniform (0 0 0); }",
                "xMin { type fixedValue; value uniform (1 0 0); } \"(xMax|y).*\" { type slip; }",
            ),
            p,
        );
        let found = find(dir.path(), "0", &mesh);
        assert_eq!(found.inlet, None);
        assert_eq!(found.outlet.as_deref(), Some("zMax"));
        assert!(
            found.notes[0].contains("xMin") && found.notes[0].contains("zMin"),
            "{:?}",
            found.notes
        );

        // no fields: notes, no guess
        let found = find(dir.path(), "5", &mesh);
        assert_eq!((found.inlet, found.outlet), (None, None));
        assert_eq!(found.notes.len(), 1);
    }
}
