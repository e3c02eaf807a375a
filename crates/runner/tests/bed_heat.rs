//! PFM's bed heat models in a run's plan (issue 28), on `openfoam-cases/packed-bed-heating`
//! with one model added to its `couplingProperties`: with the native fluid the plan hands the
//! fluid's temperature equation the bed conductivity (Zehner & Schlünder's A = k_s/λ with the
//! case's λ = 0.026 W/(m K): k_s = 2.6 gives A = 100); with grainPisoFoam the plan refuses `thermCondModel` and
//! `wallHeatTransferYagi` by name while it is read, before anything is spawned.

use runner::plan::{FluidBackend, RunOptions, RunPlan};
use std::path::{Path, PathBuf};

fn case_with(extra: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let src = testkit::repo_root().join("openfoam-cases/packed-bed-heating");
    let dst = dir.path().join("packed-bed-heating");
    testkit::copy_inputs(&src, &dst);
    let cp = dst.join("CFD/constant/couplingProperties");
    let mut s = std::fs::read_to_string(&cp).unwrap();
    s.push_str(extra);
    std::fs::write(&cp, s).unwrap();
    (dir, dst)
}

fn plan(case: &Path, fluid: FluidBackend) -> Result<RunPlan, String> {
    let opts = RunOptions {
        fluid,
        ..RunOptions::default()
    };
    RunPlan::read(case, &opts).map_err(|e| e.to_string())
}

/// The error of reading the plan of `case` for grainPisoFoam.
fn refusal(case: &Path) -> String {
    match plan(case, FluidBackend::OpenFoam) {
        Ok(_) => panic!("the plan was read"),
        Err(e) => e,
    }
}

#[test]
fn the_native_fluid_gets_the_bed_conductivity() {
    let (_tmp, case) = case_with(
        "\nthermCondModel ZehnerSchluenderThermCond;\n\
         ZehnerSchluenderThermCondProps { thermalConductivities ( 2.6 ); }\n",
    );
    let p = plan(&case, FluidBackend::Native).unwrap();
    match p.fluid.temperature.unwrap().bed {
        Some(fv::temperature::BedConduction::ZehnerSchluender { ks_over_kf }) => {
            assert!((ks_over_kf - 100.0).abs() < 1e-12, "{ks_over_kf}")
        }
        other => panic!("{other:?}"),
    }
    let (_tmp, plain) = case_with("");
    assert_eq!(
        plan(&plain, FluidBackend::Native)
            .unwrap()
            .fluid
            .temperature
            .unwrap()
            .bed,
        None
    );
}

#[test]
fn grain_piso_foam_refuses_them_by_name_before_spawning() {
    let (_tmp, case) = case_with("\nthermCondModel SyamlalThermCond;\nSyamlalThermCondProps { }\n");
    let e = refusal(&case);
    assert!(
        e.contains("thermCondModel SyamlalThermCond") && e.contains("native fluid only"),
        "{e}"
    );
    assert!(e.contains("couplingProperties"), "{e}");
    let (_tmp, case) = case_with(
        "\nenergyModels ( wallHeatTransferYagi );\n\
         wallHeatTransferYagiProps { wallTempName \"Twall\"; voidfractionMax 0.9; implicit false; }\n",
    );
    let e = refusal(&case);
    assert!(
        e.contains("energyModels wallHeatTransferYagi") && e.contains("native fluid only"),
        "{e}"
    );
    assert!(plan(&case, FluidBackend::Native).is_ok());
}
