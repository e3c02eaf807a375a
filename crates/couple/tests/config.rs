//! couplingProperties: the lead's CFDEM-layout reference cases read into the expected typed
//! configuration; every bad or unsupported entry is an error naming the file and the key.

use closures::model::ModelType;
use closures::DragLaw;
use couple::config::{read_gravity, read_transport};
use couple::{CouplingConfig, Interpolation};
use mesh::v3::V3;
use std::path::Path;
use voidage::Method;

#[test]
fn ergun_case() {
    let case = testkit::repo_root().join("openfoam-cases/ergun/CFD");
    let c = CouplingConfig::read_case(&case).unwrap();
    assert_eq!(c.model, ModelType::A);
    assert_eq!(c.coupling_interval, 50);
    assert_eq!(c.voidage.method, Method::Divided);
    assert_eq!(c.voidage.alpha_min, Some(0.3));
    let drag = c.forces.drag.unwrap();
    assert_eq!(drag.closure.law, DragLaw::GIDASPOW);
    assert_eq!(drag.interpolation, Interpolation::Smooth);
    assert!(drag.implicit_dem && !drag.explicit_fluid && !drag.dem_only);
    assert_eq!(c.forces.grad_p, Some(Interpolation::Smooth));
    assert_eq!(c.forces.viscous, Some(Interpolation::Smooth));
    assert!(c.forces.archimedes);
    assert!(c.momentum.implicit && !c.momentum.explicit);
    assert_eq!(c.data_exchange, "twoWayMPI");
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    assert_eq!(read_transport(&case).unwrap(), (10.0, 1.5e-4));
    assert_eq!(read_gravity(&case).unwrap(), Some(V3::new(0.0, 0.0, -9.81)));
}

#[test]
fn settling_case() {
    let case = testkit::repo_root().join("openfoam-cases/settling/CFD");
    let c = CouplingConfig::read_case(&case).unwrap();
    assert_eq!(c.model, ModelType::B);
    assert_eq!(c.coupling_interval, 100);
    assert_eq!(c.voidage.alpha_min, Some(0.1));
    let drag = c.forces.drag.unwrap();
    assert_eq!(drag.closure.law, DragLaw::DiFelice);
    assert_eq!(drag.interpolation, Interpolation::Cell);
    assert!(!drag.implicit_dem);
    assert_eq!(c.forces.grad_p, None);
    assert!(c.forces.archimedes);
}

const BASE: &str = r#"
FoamFile { version 2.0; format ascii; class dictionary; object couplingProperties; }
modelType "B";
couplingInterval 10;
voidFractionModel exact;
locateModel engine;
forceModels ( GidaspowDrag Archimedes );
momCoupleModels ( implicitCouple );
GidaspowDragProps { switchingVoidfraction 0.7; interpolation true; }
"#;

fn read(text: &str) -> Result<CouplingConfig, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("couplingProperties");
    std::fs::write(&path, text).unwrap();
    CouplingConfig::read(&path).map_err(|e| e.to_string())
}

#[test]
fn cfdem_sphericity_of_one_is_accepted() {
    let c = read(&BASE.replace("interpolation true;", "interpolation true; phi 1;")).unwrap();
    assert_eq!(
        c.forces.drag.unwrap().closure.law,
        DragLaw::Gidaspow {
            switch_voidage: 0.7
        }
    );
}

#[test]
fn our_extensions_and_gidaspow_switch() {
    let c = read(BASE).unwrap();
    assert_eq!(c.voidage.method, Method::Exact);
    assert_eq!(c.voidage.alpha_min, None);
    assert_eq!(
        c.forces.drag.unwrap().closure.law,
        DragLaw::Gidaspow {
            switch_voidage: 0.7
        }
    );
}

#[test]
fn cfdem_trilinear_with_its_alpha_min() {
    let text = BASE.replace(
        "voidFractionModel exact;",
        "voidFractionModel trilinear; trilinearProps { alphaMin 0.3; }",
    );
    let c = read(&text).unwrap();
    assert_eq!(c.voidage.method, Method::Trilinear);
    assert_eq!(c.voidage.alpha_min, Some(0.3));
}

/// `text` with `from` replaced by `to` must fail with a message holding every `expect`.
fn fails(from: &str, to: &str, expect: &[&str]) {
    assert!(BASE.contains(from), "{from}");
    let e = read(&BASE.replace(from, to)).unwrap_err();
    assert!(e.contains("couplingProperties"), "file not named: {e}");
    for x in expect {
        assert!(e.contains(x), "`{x}` missing in: {e}");
    }
}

#[test]
fn errors_name_file_and_key() {
    fails(
        "modelType \"B\";",
        "modelType \"C\";",
        &["modelType", "A, B, Bfull"],
    );
    fails(
        "couplingInterval 10;",
        "couplingInterval 0;",
        &["couplingInterval"],
    );
    fails("couplingInterval 10;", "", &["couplingInterval", "missing"]);
    fails(
        "voidFractionModel exact;",
        "voidFractionModel bigParticle;",
        &["voidFractionModel", "not supported", "cube or exact"],
    );
    fails(
        "voidFractionModel exact;",
        "voidFractionModel fuzzy;",
        &["voidFractionModel", "fuzzy", "divided"],
    );
    fails(
        "Archimedes );",
        "Archimedes FancyForce );",
        &["forceModels", "FancyForce", "KochHillDrag", "gradPForce"],
    );
    fails(
        "Archimedes );",
        "MeiLift );",
        &["forceModels", "MeiLift", "not supported"],
    );
    fails(
        "interpolation true;",
        "interpolation true; velFieldName \"Ufluid\";",
        &["GidaspowDragProps/velFieldName", "Ufluid"],
    );
    fails(
        "interpolation true;",
        "interpolation true; scaleDrag 2;",
        &["GidaspowDragProps/scaleDrag", "unknown"],
    );
    fails(
        "switchingVoidfraction 0.7;",
        "switchingVoidfraction 1.7;",
        &["GidaspowDragProps", "switchingVoidfraction"],
    );
    fails(
        "switchingVoidfraction 0.7;",
        "switchingVoidfraction 0.7; phi 0.8;",
        &["GidaspowDragProps/phi", "0.8", "spheres"],
    );
    fails(
        "locateModel engine;",
        "smoothingModel constDiffSmoothing;",
        &["smoothingModel"],
    );
    fails(
        "locateModel engine;",
        "fancyKey 3;",
        &["fancyKey", "unknown"],
    );
    fails(
        "voidFractionModel exact;",
        "voidFractionModel divided; dividedProps { scaleUpVol 1.2; }",
        &["dividedProps/scaleUpVol", "1.2"],
    );
    fails(
        "voidFractionModel exact;",
        "voidFractionModel centre; centreProps { alphaMin 1.5; }",
        &["centreProps/alphaMin"],
    );
    fails(
        "momCoupleModels ( implicitCouple );",
        "momCoupleModels ( fancyCouple );",
        &["momCoupleModels", "fancyCouple"],
    );
}

#[test]
fn harmless_settings_warn() {
    let c = read(&BASE.replace(
        "locateModel engine;",
        "averagingModel dilute; IOModel basicIO;",
    ))
    .unwrap();
    assert_eq!(c.warnings.len(), 1);
    assert!(c.warnings[0].contains("averagingModel dilute"));
}

#[test]
fn missing_file_is_named() {
    let e = CouplingConfig::read(Path::new("/nonexistent/couplingProperties"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/couplingProperties"), "{e}");
}

/// CFDEM's tutorials give Props under OpenFOAM pattern keys and name the coupled deck there.
#[test]
fn pattern_props_and_the_named_deck() {
    let text = format!(
        "{BASE}dataExchangeModel twoWayMPI;\n\
         \"(twoWayMPIProps|M2MProps)\" {{ liggghtsPath \"../DEM/in.liggghts_resume\"; }}\n\
         \"(engineProps|turboEngineProps)\" {{ treeSearch true; }}\n"
    );
    let c = read(&text).unwrap();
    assert_eq!(c.data_exchange, "twoWayMPI");
    assert_eq!(
        c.liggghts_path.as_deref(),
        Some(std::path::Path::new("../DEM/in.liggghts_resume"))
    );
    // a pattern Props applies to the drag law it matches: its keys are checked
    let bad = text.replace(
        "GidaspowDragProps { switchingVoidfraction 0.7; interpolation true; }",
        "\"(GidaspowDrag|KochHillDrag)Props\" { interpolation true; bogus 1; }",
    );
    let e = read(&bad).unwrap_err();
    assert!(e.contains("GidaspowDragProps/bogus"), "{e}");
    // an exact key wins over a pattern
    let both = text.replace(
        "dataExchangeModel twoWayMPI;",
        "dataExchangeModel twoWayMPI;\ntwoWayMPIProps { liggghtsPath \"../DEM/in.exact\"; }",
    );
    assert_eq!(
        read(&both).unwrap().liggghts_path.as_deref(),
        Some(std::path::Path::new("../DEM/in.exact"))
    );
    // without a liggghtsPath the default deck applies
    assert_eq!(read(BASE).unwrap().liggghts_path, None);
}
