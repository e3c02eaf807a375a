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

/// CFDEM-PUBLIC's drag models clamp the interpolated ε (`interpolation true`) before β:
/// Koch–Hill to [0.4, 1], Di Felice to [0.3, 1], Gidaspow to [0.1, 1]; the cell value
/// (`interpolation false`) keeps the voidage model's floor 0.1.
#[test]
fn cfdem_drag_clamps_the_interpolated_voidage() {
    let with = |law: &str, interp: &str| {
        let text = BASE
            .replace("GidaspowDrag Archimedes", &format!("{law} Archimedes"))
            .replace(
                "GidaspowDragProps { switchingVoidfraction 0.7; interpolation true; }",
                &format!("{law}Props {{ interpolation {interp}; }}"),
            );
        read(&text).unwrap().forces.drag.unwrap().closure
    };
    let kh = with("KochHillDrag", "true");
    assert_eq!(kh.voidage_floor, 0.4);
    assert_eq!(with("KochHillDrag", "false").voidage_floor, 0.1);
    assert_eq!(with("DiFeliceDrag", "true").voidage_floor, 0.3);
    assert_eq!(with("GidaspowDrag", "true").voidage_floor, 0.1);
    // Hand-computed with CFDEM-PUBLIC's KochHillDrag.C at its clamp ε = 0.4 (an interpolated
    // 0.3 is raised to it): d = 1 mm, ν = 1.5e-4 m²/s, ρ = 10 kg/m³, |u − v| = 0.01 m/s.
    // φ = 0.6 ≥ 0.4, so F0 = 10 φ/ε³ = 93.75; Rep = d ε |u − v|/ν = 0.02666…;
    // F3 = 0.0673 + 0.212 φ + 0.0232/ε⁵ = 2.460125; F = ε (F0 + ½ F3 Rep) = 37.513120666…;
    // betaP = 18 ν ρ/d² ε F = 405141.7032 kg/(m³ s); β = (π/6) d³ betaP = 2.12131699739e-4 kg/s.
    let x = closures::DragInput::new(0.3, 1e-3, 0.01, 10.0, 1.5e-4 * 10.0);
    let beta = kh.beta(&x);
    assert!(
        (beta / 2.121_316_997_393_3e-4 - 1.0).abs() < 1e-12,
        "β = {beta}"
    );
}

/// CFDEM's models floor ε at alphaMin 0.1 when their Props leave it out (CFDEM-PUBLIC's
/// default for every voidFractionModel); foamgrain's own have no default floor.
#[test]
fn cfdem_models_default_to_alpha_min_0_1() {
    for (model, expect) in [
        ("divided", Some(0.1)),
        ("centre", Some(0.1)),
        ("trilinear", Some(0.1)),
        ("cube", None),
        ("exact", None),
    ] {
        let text = BASE.replace(
            "voidFractionModel exact;",
            &format!("voidFractionModel {model}; {model}Props {{ }}"),
        );
        assert_eq!(read(&text).unwrap().voidage.alpha_min, expect, "{model}");
    }
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
        "voidFractionModel IBVoidFraction;",
        &["voidFractionModel", "not supported", "use exact"],
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
        "ShirgaonkarIB );",
        &["forceModels", "ShirgaonkarIB", "not supported"],
    );
    fails(
        "interpolation true;",
        "interpolation true; velFieldName \"Ufluid\";",
        &["GidaspowDragProps/velFieldName", "Ufluid"],
    );
    fails(
        "interpolation true;",
        // (scaleDrag was this example until coarse graining made it a key that acts)
        "interpolation true; dragScale 2;",
        &["GidaspowDragProps/dragScale", "unknown"],
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
        "smoothingModel localPSizeDiffSmoothing;",
        &["localPSizeDiffSmoothingProps/dSmoothingLength", "missing"],
    );
    fails(
        "locateModel engine;",
        "smoothingModel constDiffSmoothing;",
        &["constDiffSmoothingProps/smoothingLength", "missing"],
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

/// The vocabulary of CFDEM's tutorials beyond the forces (our own text using the same
/// constructs): auxiliary force models, clock, IO, flags, Props keys without effect.
const CFDEM_VOCABULARY: &str = r#"
FoamFile { version 2.0; format ascii; class dictionary; object couplingProperties; }
debug false;
solveFlow off;
useDDTvoidfraction b;
syncMode false;
modelType "A";
couplingInterval 20;
voidFractionModel divided;
locateModel engine;
meshMotionModel noMeshMotion;
regionModel allRegion;
IOModel basicIO;
probeModel off;
dataExchangeModel twoWayMPI;
averagingModel dense;
clockModel standardClock;
smoothingModel off;
forceModels ( BeetstraDrag gradPForce Archimedes fieldStore particleCellVolume volWeightedAverage noDrag );
momCoupleModels ( implicitCouple );
turbulenceModelType turbulenceProperties;
BeetstraDragProps { velFieldName "U"; rhoParticle 1500.; interpolation true; }
fieldStoreProps { scalarFieldNames ( ); vectorFieldNames ( "U" ); }
particleCellVolumeProps { upperThreshold 0.999; lowerThreshold 0.; verbose true; writeToFile true; }
volWeightedAverageProps { scalarFieldNames ( voidfraction ddtVoidfraction ); vectorFieldNames ( ); upperThreshold 2; lowerThreshold 0; useVolumeFraction true; }
noDragProps { noDEMForce true; }
"#;

#[test]
fn cfdem_auxiliary_models_and_flags() {
    let c = read(CFDEM_VOCABULARY).unwrap();
    assert!(!c.solve_flow);
    assert!(c.ddt_voidage);
    assert!(c.monitors.clock && c.monitors.basic_io);
    let fs = c.monitors.field_store.as_ref().unwrap();
    assert!(fs.scalar_fields.is_empty());
    assert_eq!(fs.vector_fields, ["U"]);
    let pcv = c.monitors.particle_cell_volume.as_ref().unwrap();
    assert_eq!((pcv.lower, pcv.upper), (0.0, 0.999));
    assert!(pcv.verbose && pcv.write_to_file);
    let vwa = c.monitors.vol_weighted_average.as_ref().unwrap();
    assert_eq!(vwa.scalar_fields, ["voidfraction", "ddtVoidfraction"]);
    assert!(vwa.use_volume_fraction && !vwa.verbose && !vwa.write_to_file);
    assert_eq!((vwa.lower, vwa.upper, vwa.start_time), (0.0, 2.0, 0.0));
    let nd = c.forces.no_drag.unwrap();
    assert!(nd.no_dem_force && !nd.keep_cfd_force);
    assert_eq!(c.forces.drag.unwrap().closure.law, DragLaw::Beetstra);
    // rhoParticle is read by no drag law: accepted with one warning naming it
    assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
    assert!(c.warnings[0].contains("BeetstraDragProps/rhoParticle"));

    // CFDEM's defaults: particleCellVolume's thresholds, solveFlow on, clock off
    let plain = CFDEM_VOCABULARY
        .replace("upperThreshold 0.999; lowerThreshold 0.; ", "")
        .replace("solveFlow off;", "")
        .replace("clockModel standardClock;", "clockModel off;")
        .replace("useDDTvoidfraction b;", "useDDTvoidfraction off;");
    let c = read(&plain).unwrap();
    let pcv = c.monitors.particle_cell_volume.unwrap();
    assert_eq!((pcv.lower, pcv.upper), (-0.01, 1.01));
    assert!(c.solve_flow && !c.monitors.clock && !c.ddt_voidage);

    // CFDEM-PFM's settlingTestMPI smoothing
    assert_eq!(c.smoothing, None);
    let smooth = CFDEM_VOCABULARY.replace(
        "smoothingModel off;",
        "smoothingModel constDiffSmoothing;\nconstDiffSmoothingProps { lowerLimit 0.0; \
         upperLimit 1e99; smoothingLength 3e-4; verbose; }",
    );
    assert_eq!(
        read(&smooth).unwrap().smoothing,
        Some(couple::smoothing::SmoothingModel::ConstDiff(
            couple::smoothing::SmoothingSettings {
                length: 3e-4,
                lower: 0.0,
                upper: 1e99
            }
        ))
    );

    // CFDEM-PFM's voidfractionTest: the key alone switches ∂ε/∂t on
    let bare = CFDEM_VOCABULARY.replace("useDDTvoidfraction b;", "useDDTvoidfraction;");
    assert!(read(&bare).unwrap().ddt_voidage);
}

#[test]
fn cfdem_vocabulary_errors_name_the_key() {
    let fails = |from: &str, to: &str, expect: &[&str]| {
        assert!(CFDEM_VOCABULARY.contains(from), "{from}");
        let e = read(&CFDEM_VOCABULARY.replace(from, to)).unwrap_err();
        for x in expect {
            assert!(e.contains(x), "`{x}` missing in: {e}");
        }
    };
    fails(
        "vectorFieldNames ( \"U\" )",
        "vectorFieldNames ( \"Uf\" )",
        &["fieldStoreProps/vectorFieldNames", "Uf", "Us"],
    );
    fails(
        "volWeightedAverage noDrag )",
        "noDrag volWeightedAverage viscForce )",
        &["forceModels", "viscForce", "after `noDrag`"],
    );
    fails(
        "useDDTvoidfraction b;",
        "useDDTvoidfraction a;",
        &["useDDTvoidfraction", "`a`", "off"],
    );
    fails(
        "clockModel standardClock;",
        "clockModel fancyClock;",
        &["clockModel", "fancyClock", "standardClock"],
    );
    fails(
        "IOModel basicIO;",
        "IOModel rawIO;",
        &["IOModel", "rawIO", "basicIO"],
    );
    fails(
        "noDEMForce true;",
        "noDEMForce true; bogus 1;",
        &["noDragProps/bogus"],
    );
    fails(
        "upperThreshold 2; lowerThreshold 0;",
        "upperThreshold 2;",
        &["volWeightedAverageProps/lowerThreshold"],
    );
    fails(
        "Archimedes fieldStore",
        "Archimedes RongDrag fieldStore",
        &["RongDrag", "not supported"],
    );
    fails("debug false;", "debug maybe;", &["debug", "switch"]);
}

#[test]
fn cfdem_flags_that_do_nothing_here_warn() {
    let c = read(
        &CFDEM_VOCABULARY
            .replace("debug false;", "debug true;")
            .replace("averagingModel dense;", "averagingModel dilute;"),
    )
    .unwrap();
    assert_eq!(c.warnings.len(), 3, "{:?}", c.warnings);
    assert!(c.warnings.iter().any(|w| w.contains("debug on")));
    assert!(c
        .warnings
        .iter()
        .any(|w| w.contains("averagingModel dilute")));
}

/// `probeModel particleProbe` acts (issue 28): its `particleProbeProps` as CFDEM's
/// voidfractionTest writes them, where a switch is on when its key is present
/// (`particleProbe.C`: `propsDict_.found(…)`); `particleIDsToSample` is required as there;
/// `probeDebug` warns that the models' internal scalars are not written.
#[test]
fn particle_probe_reads_cfdems_props() {
    let props = "particleProbeProps { particleIDsToSample (0 0); verboseToFile; printEvery 2; \
                 sampleAll; probeDebug; includePosition; writePrecision 4; }\n";
    let c =
        read(&(CFDEM_VOCABULARY.replace("probeModel off;", "probeModel particleProbe;") + props))
            .unwrap();
    let p = c.monitors.particle_probe.as_ref().unwrap();
    assert_eq!(p.ids, [0, 0]);
    assert!(p.verbose_to_file && p.sample_all && p.include_position && p.debug);
    assert_eq!(
        (p.print_every, p.print_only_at, p.write_precision),
        (2, None, 4)
    );
    assert!(
        c.warnings.iter().any(|w| w.contains("probeDebug")),
        "{:?}",
        c.warnings
    );
    let e = read(&CFDEM_VOCABULARY.replace("probeModel off;", "probeModel particleProbe;"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("particleProbeProps/particleIDsToSample"), "{e}");
}

/// CFDEM keeps the fluid density in the field `0/rho`; transportProperties' `rho` wins.
#[test]
fn density_from_the_rho_field() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path();
    std::fs::create_dir_all(case.join("constant")).unwrap();
    std::fs::create_dir_all(case.join("0")).unwrap();
    let header = "FoamFile { version 2.0; format ascii; class dictionary; object x; }\n";
    std::fs::write(
        case.join("constant/transportProperties"),
        format!("{header}transportModel Newtonian;\nnu [0 2 -1 0 0 0 0] 1.488e-05;\n"),
    )
    .unwrap();
    let e = read_transport(case).unwrap_err().to_string();
    assert!(e.contains("rho") && e.contains("0/rho"), "{e}");
    let rho_field = |internal: &str| {
        std::fs::write(
            case.join("0/rho"),
            format!(
                "{header}dimensions [1 -3 0 0 0 0 0];\ninternalField {internal};\n\
                 boundaryField {{ wall {{ type zeroGradient; }} }}\n"
            ),
        )
        .unwrap();
    };
    rho_field("uniform 1.13");
    assert_eq!(read_transport(case).unwrap(), (1.13, 1.488e-5));
    rho_field("nonuniform List<scalar> 3(2.5 2.5 2.5)");
    assert_eq!(read_transport(case).unwrap(), (2.5, 1.488e-5));
    rho_field("nonuniform List<scalar> 3(2.5 2.5 2.6)");
    let e = read_transport(case).unwrap_err().to_string();
    assert!(e.contains("0/rho") && e.contains("varies"), "{e}");
    rho_field("uniform -1");
    let e = read_transport(case).unwrap_err().to_string();
    assert!(e.contains("internalField") && e.contains("positive"), "{e}");
    std::fs::write(
        case.join("constant/transportProperties"),
        format!("{header}nu 1e-5;\nrho rho [1 -3 0 0 0 0 0] 7;\n"),
    )
    .unwrap();
    assert_eq!(read_transport(case).unwrap(), (7.0, 1e-5));
}

/// `implicitCoupleProps/KslForm` selects CFDEM's Ksl form with its `KslLimit`, `minAlphaP`
/// and `averagingModel`; the conserving form is the default; unknown words are errors naming
/// the file and key.
#[test]
fn ksl_form_is_selected_in_implicit_couple_props() {
    use couple::ksl::{CfdemKsl, KslForm, UsAveraging};
    assert_eq!(read(BASE).unwrap().momentum.ksl_form(), KslForm::Conserving);
    let props = "implicitCoupleProps { KslForm CFDEM; KslLimit 1e4; minAlphaP 0.001; }\n";
    let c = read(&format!("{BASE}{props}averagingModel dilute;\n")).unwrap();
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    assert_eq!(
        c.momentum.ksl_form(),
        KslForm::Cfdem(CfdemKsl {
            limit: 1e4,
            max_voidage: 0.999,
            averaging: UsAveraging::Dilute,
        })
    );
    let c = read(&format!("{BASE}implicitCoupleProps {{ KslForm CFDEM; }}\n")).unwrap();
    assert_eq!(c.momentum.ksl_form(), KslForm::Cfdem(CfdemKsl::default()));
    let c = read(&format!(
        "{BASE}implicitCoupleProps {{ KslForm conserving; }}\n"
    ))
    .unwrap();
    assert_eq!(c.momentum.ksl_form(), KslForm::Conserving);
    let e = read(&format!("{BASE}implicitCoupleProps {{ KslForm cfdem; }}\n")).unwrap_err();
    for x in [
        "couplingProperties",
        "implicitCoupleProps/KslForm",
        "conserving, CFDEM",
    ] {
        assert!(e.contains(x), "`{x}` missing in: {e}");
    }
    let e = read(&format!("{BASE}implicitCoupleProps {{ minAlphaP 2; }}\n")).unwrap_err();
    assert!(e.contains("implicitCoupleProps/minAlphaP"), "{e}");
}

/// virtualMassForce, MeiLift and SaffmanLift: CFDEM's keys read, foamgrain's limits named.
#[test]
fn added_mass_and_lift_keys() {
    let with = |props: &str| {
        BASE.replace(
            "Archimedes );",
            &format!("Archimedes virtualMassForce MeiLift SaffmanLift );\n{props}"),
        )
    };
    let c = read(&with(
        "virtualMassForceProps { velFieldName \"U\"; phiFieldName \"phi\"; \
         splitUrelCalculation true; Cadd 0.4; treatForceDEM true; }\n\
         MeiLiftProps { useSecondOrderTerms; interpolation true; verbose false; }\n",
    ))
    .unwrap();
    let vm = c.forces.virtual_mass.unwrap();
    assert!(vm.split && vm.dem_only && vm.c_add == 0.4);
    assert!(c.forces.mei_lift.unwrap().second_order);
    assert!(!c.forces.saffman_lift.unwrap().second_order);
    assert!(c.forces.needs_vorticity() && c.forces.needs_ddt_u());
    // defaults: CFDEM-PFM's unsplit form, Cadd 0.5
    let c = read(&with("")).unwrap();
    let vm = c.forces.virtual_mass.unwrap();
    assert!(!vm.split && !vm.dem_only && vm.c_add == 0.5 && !c.forces.needs_ddt_u());
    for (props, expect) in [
        (
            "virtualMassForceProps { Ccc 1; }",
            "virtualMassForceProps/Ccc",
        ),
        (
            "virtualMassForceProps { useFelderhof true; }",
            "useFelderhof",
        ),
        (
            "virtualMassForceProps { treatForceExplicit false; }",
            "treatForceExplicit",
        ),
        (
            "MeiLiftProps { useSecondOrderTerms false; }",
            "remove the key",
        ),
        ("MeiLiftProps { useSpinInduced true; }", "spin"),
        (
            "SaffmanLiftProps { velFieldName \"V\"; }",
            "SaffmanLiftProps/velFieldName",
        ),
    ] {
        let e = read(&with(props)).unwrap_err();
        assert!(
            e.contains("couplingProperties") && e.contains(expect),
            "{e}"
        );
    }
}

/// CFDEM-PFM's `scale` in a drag law's Props: the parcel of diameter d is CG³ particles of
/// d/CG. Hand-computed with PFM's KochHillDrag.C (β = V_s·betaP with betaP at ds/scale, V_s
/// the parcel's volume): the particle of `cfdem_drag_clamps_the_interpolated_voidage` (d = 1 mm,
/// β = 2.12131699739e-4 kg/s) as a parcel of 2 mm with scale 2 has β = 8 × that; `scaleDrag 3`
/// triples it. `implDEM_` (ErgunTestCG's) is a warning: PFM reads no such key.
#[test]
fn pfm_scale_makes_the_drag_a_parcels() {
    let with = |props: &str| {
        let text = BASE
            .replace("GidaspowDrag Archimedes", "KochHillDrag Archimedes")
            .replace(
                "GidaspowDragProps { switchingVoidfraction 0.7; interpolation true; }",
                &format!("KochHillDragProps {{ interpolation true; {props} }}"),
            );
        read(&text)
    };
    let x = closures::DragInput::new(0.3, 2e-3, 0.01, 10.0, 1.5e-4 * 10.0);
    let c = with("scale 2;").unwrap();
    let beta = c.forces.drag.unwrap().closure.beta(&x);
    assert!(
        (beta / (8.0 * 2.121_316_997_393_3e-4) - 1.0).abs() < 1e-12,
        "β = {beta}"
    );
    let c = with("scale 2; scaleDrag 3; implDEM_;").unwrap();
    let beta = c.forces.drag.unwrap().closure.beta(&x);
    assert!(
        (beta / (24.0 * 2.121_316_997_393_3e-4) - 1.0).abs() < 1e-12,
        "β = {beta}"
    );
    assert!(
        c.warnings.iter().any(|w| w.contains("implDEM_")),
        "{:?}",
        c.warnings
    );
    let e = with("scale 0.5;").unwrap_err();
    assert!(
        e.contains("KochHillDragProps/scale") && e.contains("≥ 1"),
        "{e}"
    );
    let e = with("scaleDrag -1;").unwrap_err();
    assert!(e.contains("KochHillDragProps/scaleDrag"), "{e}");
}
