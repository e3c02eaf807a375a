//! couplingProperties with heat transfer: CFDEM-PUBLIC's packedBedTemp (its dictionary text,
//! copied below) and CFDEM-PFM's `heatTransferGunn` read into [`HeatSettings`]; every bad or
//! unsupported heat entry is an error naming the file and the key; cases without heat have none.

use closures::heat::{Nusselt, ReynoldsVelocity};
use couple::config::{
    BedConductivity, HeatModel, HeatSettings, InterGrainSettings, MaxSource, WallHeatSettings,
};
use couple::{CouplingConfig, Interpolation};

/// The keys and values of CFDEMcoupling-PUBLIC's `tutorials/cfdemSolverPisoScalar/
/// packedBedTemp/CFD/constant/couplingProperties` (its comments left out).
const PACKED_BED_TEMP: &str = r#"
FoamFile
{
    version         2.0;
    format          ascii;
    class           dictionary;
    object          couplingProperties;
}
modelType B;
couplingInterval 500;
voidFractionModel divided;
locateModel engine;
meshMotionModel noMeshMotion;
IOModel basicIO;
probeModel off;
dataExchangeModel twoWayMPI;
averagingModel dense;
clockModel off;
smoothingModel off;
forceModels
(
    KochHillDrag
    LaEuScalarTemp
    Archimedes
);
momCoupleModels
(
    implicitCouple
);
turbulenceModelType turbulenceProperties;
LaEuScalarTempProps
{
    tempFieldName "T";
    partTempName "Temp";
    partHeatFluxName "convectiveHeatFlux";
    lambda 0.0256;
    Cp 1007;
}
implicitCoupleProps
{
}
KochHillDragProps
{
}
DiFeliceDragProps
{
}
ArchimedesProps
{
}
gradPForceProps
{
}
viscForceProps
{
    interpolation true;
}
oneWayVTKProps
{
    couplingFilename "vtk_out%4.4d.vtk";
    maxNumberOfParticles 30000;
}
twoWayMPIProps
{
    maxNumberOfParticles 10000;
    liggghtsPath "../DEM/in.liggghts_run";
}
centreProps
{
}
dividedProps
{
    alphaMin 0.4;
}
engineProps
{
    treeSearch true;
}
"#;

/// Reads `text` as `constant/couplingProperties` of a case whose `transportProperties` is
/// `transport`.
fn read_with(text: &str, transport: &str) -> Result<CouplingConfig, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("couplingProperties");
    std::fs::write(&path, text).unwrap();
    std::fs::write(dir.path().join("transportProperties"), transport).unwrap();
    CouplingConfig::read(&path).map_err(|e| e.to_string())
}

fn read(text: &str) -> Result<CouplingConfig, String> {
    read_with(text, "nu [0 2 -1 0 0 0 0] 1.5e-3;\n")
}

/// `PACKED_BED_TEMP` with `from` replaced by `to`, which must fail with all of `expect`.
fn fails(from: &str, to: &str, expect: &[&str]) {
    assert!(PACKED_BED_TEMP.contains(from), "{from}");
    let e = read(&PACKED_BED_TEMP.replace(from, to)).unwrap_err();
    assert!(e.contains("couplingProperties"), "{e}");
    for x in expect {
        assert!(e.contains(x), "`{x}` not in: {e}");
    }
}

#[test]
fn packed_bed_temp_reads_its_heat_settings() {
    let c = read(PACKED_BED_TEMP).unwrap();
    assert_eq!(
        c.heat,
        Some(HeatSettings {
            model: HeatModel::LaEuScalarTemp,
            nusselt: Nusselt::LiMason,
            reynolds: ReynoldsVelocity::Interstitial,
            voidage_floor: 0.0,
            nusselt_scale: 1.0,
            lambda: 0.0256,
            cp: 1007.0,
            prandtl: None,
            max_source: None,
            interpolation: Interpolation::Cell,
        })
    );
    assert!(c.forces.drag.is_some() && c.forces.archimedes);
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
}

#[test]
fn la_eu_scalar_temp_options() {
    let props = "    lambda 0.0256;\n    Cp 1007;\n";
    let more = "    lambda 0.0256;\n    Cp 1007;\n    NuCorrelation Gunn;\n    maxSource 5;\n    \
                interpolation true;\n    compressible false;\n    verbose true;\n";
    let c = read(&PACKED_BED_TEMP.replace(props, more)).unwrap();
    let h = c.heat.unwrap();
    assert_eq!(h.nusselt, Nusselt::Gunn);
    assert_eq!(h.max_source, Some(MaxSource::KelvinPerSecond(5.0)));
    assert_eq!(h.interpolation, Interpolation::Smooth);
    let deen = read(&PACKED_BED_TEMP.replace(props, &format!("{props}NuCorrelation Deen;\n")));
    assert_eq!(deen.unwrap().heat.unwrap().nusselt, Nusselt::Deen);
}

#[test]
fn la_eu_scalar_temp_errors_name_the_key() {
    let p = "LaEuScalarTempProps/";
    fails(
        "    lambda 0.0256;\n",
        "",
        &[&format!("{p}lambda"), "missing"],
    );
    fails("    Cp 1007;\n", "", &[&format!("{p}Cp"), "missing"]);
    fails("Cp 1007;", "Cp 0;", &[&format!("{p}Cp"), "not > 0"]);
    fails(
        "lambda 0.0256;",
        "lambda -1;",
        &[&format!("{p}lambda"), "not > 0"],
    );
    fails(
        "Cp 1007;",
        "Cp 1007; compressible true;",
        &[&format!("{p}compressible"), "incompressible"],
    );
    fails(
        "Cp 1007;",
        "Cp 1007; NuCorrelation RanzMarshall;",
        &[
            &format!("{p}NuCorrelation"),
            "RanzMarshall",
            "LiMason, Deen, Gunn",
        ],
    );
    fails(
        "Cp 1007;",
        "Cp 1007; lamda 0.03;",
        &[&format!("{p}lamda"), "unknown"],
    );
    fails(
        "tempFieldName \"T\";",
        "tempFieldName \"Tgas\";",
        &[&format!("{p}tempFieldName"), "`T`"],
    );
    fails(
        "    tempFieldName \"T\";\n",
        "",
        &[&format!("{p}tempFieldName"), "missing"],
    );
    fails(
        "Cp 1007;",
        "Cp 1007; maxSource 0;",
        &[&format!("{p}maxSource"), "not > 0"],
    );
    fails(
        "    LaEuScalarTemp\n",
        "    LaEuScalarTemp\n    LaEuScalarTemp\n",
        &["second heat transfer model"],
    );
    fails(
        "    LaEuScalarTemp\n",
        "    scalarGeneralExchange\n",
        &["scalarGeneralExchangeProps/tempFieldName", "missing"],
    );
}

#[test]
fn cases_without_heat_have_none() {
    let text = PACKED_BED_TEMP.replace("    LaEuScalarTemp\n", "");
    let c = read(&text).unwrap();
    assert_eq!(c.heat, None);
}

/// CFDEM-PFM's heatTransferGunn (as in its `cfdemSolverRhoPimple/ErgunTestMPI`, with
/// `implicit false`, which foamgrain requires) and `kf`, `Cp` in `transportProperties`.
const GUNN: &str = r#"
modelType "A";
couplingInterval 25;
voidFractionModel divided;
regionModel allRegion;
forceModels ( GidaspowDrag );
energyModels ( heatTransferGunn );
chemistryModels ( off );
thermCondModel SyamlalThermCond;
momCoupleModels ( implicitCouple );
heatTransferGunnProps
{
    partTempName "Temp";
    partHeatFluxName "convectiveHeatFlux";
    interpolation true;
    implicit false;
    maxSource 1e5;
    NusseltScalingFactor 1.5;
}
SyamlalThermCondProps { }
"#;

const GUNN_TRANSPORT: &str = "transportModel Newtonian;\nnu [0 2 -1 0 0 0 0] 1.5e-5;\n\
                              kf [1 1 -3 -1 0 0 0] 0.0256;\nCp [0 2 -2 -1 0 0 0] 1007;\n";

#[test]
fn heat_transfer_gunn_reads_pfm_props_and_transport() {
    let c = read_with(GUNN, GUNN_TRANSPORT).unwrap();
    assert_eq!(
        c.heat,
        Some(HeatSettings {
            model: HeatModel::HeatTransferGunn,
            nusselt: Nusselt::GunnPfm,
            reynolds: ReynoldsVelocity::Superficial,
            voidage_floor: 0.01,
            nusselt_scale: 1.5,
            lambda: 0.0256,
            cp: 1007.0,
            prandtl: None,
            max_source: Some(MaxSource::WattPerCubicMetre(1e5)),
            interpolation: Interpolation::Smooth,
        })
    );
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    assert_eq!(c.bed_conduction, Some(BedConductivity::Syamlal));
}

/// PFM's `thermCondModel`s act (the fluid's bed conductivity): `ZehnerSchluenderThermCond`
/// reads its one k_s; several particle types, a missing or non-positive k_s and another
/// `partKsFieldName` are errors naming the key; `noTherm` and no key leave the fluid's own.
#[test]
fn therm_cond_models_are_read() {
    let zs = GUNN.replace(
        "thermCondModel SyamlalThermCond;",
        "thermCondModel ZehnerSchluenderThermCond;\n\
         ZehnerSchluenderThermCondProps { thermalConductivities ( 2.5 ); }",
    );
    let c = read_with(&zs, GUNN_TRANSPORT).unwrap();
    assert_eq!(
        c.bed_conduction,
        Some(BedConductivity::ZehnerSchluender { ks: 2.5 })
    );
    for (from, to, expect) in [
        ("( 2.5 )", "( 2.5 1.0 )", "2 particle types"),
        ("( 2.5 )", "( 0 )", "not a positive conductivity"),
        ("thermalConductivities ( 2.5 );", "", "missing"),
        (
            "( 2.5 );",
            "( 2.5 ); partKsFieldName ks;",
            "partKsFieldName",
        ),
    ] {
        let e = read_with(&zs.replace(from, to), GUNN_TRANSPORT).unwrap_err();
        assert!(e.contains("ZehnerSchluenderThermCondProps/"), "{e}");
        assert!(e.contains(expect), "`{expect}` not in {e}");
    }
    let none = GUNN.replace("SyamlalThermCond;", "noTherm;");
    assert_eq!(
        read_with(&none, GUNN_TRANSPORT).unwrap().bed_conduction,
        None
    );
    let without = GUNN.replace("thermCondModel SyamlalThermCond;", "");
    assert_eq!(
        read_with(&without, GUNN_TRANSPORT).unwrap().bed_conduction,
        None
    );
}

/// PFM's heatTransferRanzMarshall: heatTransferGunn's Props and checks with Ranz & Marshall's
/// Nusselt law; `NusseltConstParameter` other than 0.6 is an error naming the key.
#[test]
fn heat_transfer_ranz_marshall_reads_pfm_props() {
    let text = GUNN
        .replace("heatTransferGunn", "heatTransferRanzMarshall")
        .replace("maxSource 1e5;", "NusseltConstParameter 0.6;");
    let c = read_with(&text, GUNN_TRANSPORT).unwrap();
    let h = c.heat.unwrap();
    assert_eq!(h.model, HeatModel::HeatTransferRanzMarshall);
    assert_eq!(h.nusselt, Nusselt::RanzMarshall);
    assert_eq!(h.reynolds, ReynoldsVelocity::Superficial);
    assert_eq!((h.voidage_floor, h.nusselt_scale), (0.01, 1.5));
    let e = read_with(
        &text.replace("NusseltConstParameter 0.6;", "NusseltConstParameter 1.2;"),
        GUNN_TRANSPORT,
    )
    .unwrap_err();
    assert!(
        e.contains("heatTransferRanzMarshallProps/NusseltConstParameter"),
        "{e}"
    );
    let e = read_with(&text.replace("implicit false;", ""), GUNN_TRANSPORT).unwrap_err();
    assert!(e.contains("heatTransferRanzMarshall is implicit"), "{e}");
}

#[test]
fn heat_transfer_gunn_errors_name_the_key() {
    let fail = |text: &str, transport: &str, expect: &[&str]| {
        let e = read_with(text, transport).unwrap_err();
        for x in expect {
            assert!(e.contains(x), "`{x}` not in: {e}");
        }
    };
    let p = "heatTransferGunnProps/";
    fail(
        &GUNN.replace("    implicit false;\n", ""),
        GUNN_TRANSPORT,
        &[&format!("{p}implicit"), "implicit false"],
    );
    fail(
        &GUNN.replace("implicit false;", "implicit false; initPartTemp true;"),
        GUNN_TRANSPORT,
        &[&format!("{p}initPartTemp")],
    );
    fail(
        &GUNN.replace("implicit false;", "implicit false; scaleNuCellsName bed;"),
        GUNN_TRANSPORT,
        &[&format!("{p}scaleNuCellsName"), "`all`"],
    );
    fail(
        GUNN,
        &GUNN_TRANSPORT.replace("kf [1 1 -3 -1 0 0 0] 0.0256;\n", ""),
        &["transportProperties", "`kf`", "missing"],
    );
    fail(
        GUNN,
        &GUNN_TRANSPORT.replace("1007", "-3"),
        &["transportProperties", "`Cp`"],
    );
    fail(
        &GUNN.replace("( off )", "( species )"),
        GUNN_TRANSPORT,
        &["chemistryModels", "species", "not supported"],
    );
    fail(
        &GUNN.replace("heatTransferGunn )", "heatTransferGunn reactionHeat )"),
        GUNN_TRANSPORT,
        &[
            "energyModels",
            "reactionHeat",
            "not supported",
            "fix couple/cfd/chemistry",
        ],
    );
}

/// CFDEM-PUBLIC's `tutorials/cfdemSolverPisoSTM/packedBedTemp` `scalarGeneralExchangeProps`,
/// with its species lists emptied (foamgrain couples temperature only).
const STM: &str = r#"
modelType B;
couplingInterval 500;
voidFractionModel divided;
forceModels ( KochHillDrag scalarGeneralExchange Archimedes );
momCoupleModels ( implicitCouple );
scalarGeneralExchangeProps
{
    tempFieldName           "T";
    partTempName            "Temp";
    partHeatFluxName        "convectiveHeatFlux";
    lambda                  0.0256;
    Prandtl                 70.097;
    useLiMason              true;
    partSpeciesNames ( );
    partSpeciesFluxNames ( );
    partSpeciesTransCoeffNames ( );
    partSpeciesFluidNames ( );
    DMolecular ( );
}
"#;

/// The tutorial's `scalarTransportProperties` with the temperature only.
const STM_SCALARS: &str = "scalarTransportModel generalManual;\ngeneralManualProps\n{\n    \
                           ScT 0.7;\n    PrT 0.7;\n    cpVolumetric 1196;\n    \
                           eulerianFields\n    (\n        T\n    );\n}\n";

/// Reads `text` as `constant/couplingProperties` of a case with ρ 1.196 and `scalars` as
/// `constant/scalarTransportProperties`.
fn read_stm(text: &str, scalars: &str) -> Result<CouplingConfig, String> {
    let dir = tempfile::tempdir().unwrap();
    let constant = dir.path().join("constant");
    std::fs::create_dir(&constant).unwrap();
    std::fs::write(constant.join("couplingProperties"), text).unwrap();
    std::fs::write(
        constant.join("transportProperties"),
        "nu 1.5e-3;\nrho 1.196;\n",
    )
    .unwrap();
    std::fs::write(constant.join("scalarTransportProperties"), scalars).unwrap();
    CouplingConfig::read(&constant.join("couplingProperties")).map_err(|e| e.to_string())
}

#[test]
fn scalar_general_exchange_reads_its_temperature_part() {
    let h = read_stm(STM, STM_SCALARS).unwrap().heat.unwrap();
    assert_eq!(h.model, HeatModel::ScalarGeneralExchange);
    assert_eq!(h.nusselt, Nusselt::LiMasonCubeRoot);
    assert_eq!(h.reynolds, ReynoldsVelocity::Superficial);
    assert_eq!((h.lambda, h.prandtl), (0.0256, Some(70.097)));
    // ρ c_p is the given cpVolumetric
    assert!((h.cp * 1.196 - 1196.0).abs() < 1e-12 * 1196.0, "{}", h.cp);
    let deen = read_stm(
        &STM.replace("useLiMason              true;", ""),
        STM_SCALARS,
    );
    assert_eq!(deen.unwrap().heat.unwrap().nusselt, Nusselt::Deen);
}

#[test]
fn scalar_general_exchange_refuses_species_and_implicit_coupling() {
    let fail = |text: &str, scalars: &str, expect: &[&str]| {
        let e = read_stm(text, scalars).unwrap_err();
        for x in expect {
            assert!(e.contains(x), "`{x}` not in: {e}");
        }
    };
    let p = "scalarGeneralExchangeProps/";
    // the tutorial's species C
    fail(
        &STM.replace("partSpeciesNames ( );", "partSpeciesNames ( speciesC );"),
        STM_SCALARS,
        &[
            &format!("{p}partSpeciesNames"),
            "species exchange is not implemented",
        ],
    );
    fail(
        STM,
        &STM_SCALARS.replace("        T\n", "        C\n        T\n"),
        &[
            "scalarTransportProperties",
            "eulerianFields",
            "temperature `T` only",
        ],
    );
    fail(
        &STM.replace("lambda ", "partHeatTransCoeffName \"hc\"; lambda "),
        STM_SCALARS,
        &[&format!("{p}partHeatTransCoeffName"), "implicit strategy"],
    );
    fail(
        &STM.replace("    Prandtl                 70.097;\n", ""),
        STM_SCALARS,
        &[&format!("{p}Prandtl"), "missing"],
    );
    fail(
        STM,
        &STM_SCALARS.replace("    cpVolumetric 1196;\n", ""),
        &["generalManualProps/cpVolumetric", "missing"],
    );
    fail(
        &STM.replace("lambda ", "useGeneralCorrelation true; lambda "),
        STM_SCALARS,
        &[&format!("{p}useGeneralCorrelation")],
    );
}

/// PFM's `wallHeatTransferYagi` and `heatTransferInterGrain` beside heatTransferGunn: their
/// Props read; each needs a heat transfer model, Yagi `implicit false`, InterGrain one k_s and
/// neither its implicit solve nor radiation (errors naming the key).
#[test]
fn wall_and_inter_grain_models_are_read() {
    let text = GUNN.replace(
        "energyModels ( heatTransferGunn );",
        "energyModels ( heatTransferGunn wallHeatTransferYagi heatTransferInterGrain );\n\
         wallHeatTransferYagiProps { wallTempName \"Twall\"; voidfractionMax 0.8; \
         implicit false; maxSource 1e6; }\n\
         heatTransferInterGrainProps { thermalConductivities ( 3 ); kMax 10; }",
    );
    let c = read_with(&text, GUNN_TRANSPORT).unwrap();
    assert_eq!(
        c.wall_heat,
        Some(WallHeatSettings {
            wall_temp_name: "Twall".into(),
            eps_max: 0.8,
            max_source: Some(1e6),
        })
    );
    assert_eq!(
        c.inter_grain,
        Some(InterGrainSettings {
            ks: 3.0,
            k_max: Some(10.0)
        })
    );
    for (from, to, expect) in [
        (
            "implicit false; maxSource",
            "maxSource",
            "wallHeatTransferYagiProps/implicit",
        ),
        (
            "voidfractionMax 0.8;",
            "",
            "wallHeatTransferYagiProps/voidfractionMax",
        ),
        (
            "kMax 10;",
            "implicit true;",
            "heatTransferInterGrainProps/implicit",
        ),
        (
            "kMax 10;",
            "radiativeHeatTransfer true;",
            "heatTransferInterGrainProps/radiativeHeatTransfer",
        ),
        (
            "( 3 )",
            "( 3 4 )",
            "heatTransferInterGrainProps/thermalConductivities",
        ),
        (
            "heatTransferGunn wallHeatTransferYagi",
            "wallHeatTransferYagi",
            "need a heat transfer model",
        ),
    ] {
        let e = read_with(&text.replace(from, to), GUNN_TRANSPORT).unwrap_err();
        assert!(e.contains(expect), "`{expect}` not in {e}");
    }
}
