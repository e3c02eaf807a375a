//! Full tier: OpenFOAM itself integrates the voidfraction field that `foamgrain voidage` writes.
//! V_mesh − ∫ε dV (volFieldValue, operation volIntegrate, Debian's v1912 postProcess) must equal
//! the deposited solid volume foamgrain reports, for every method, on a blockMesh box that holds
//! a real LIGGGHTS dump.

use std::process::Command;
use testkit::{copy_dir, fixture, openfoam, run_ok, tool};

const FUNCTIONS: &str = r#"
functions
{
    solid
    {
        type            volFieldValue;
        libs            ("libfieldFunctionObjects.so");
        fields          (voidfraction);
        operation       volIntegrate;
        regionType      all;
        writeFields     false;
        log             true;
    }
}
"#;

#[test]
fn openfoam_integral_of_written_voidage_equals_deposited_volume() {
    if !tool("postProcess") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    copy_dir(&fixture("foam/cavity/system"), &dir.path().join("system"));
    std::fs::create_dir(dir.path().join("constant")).unwrap();
    std::fs::write(
        dir.path().join("system/blockMeshDict"),
        testkit::BOX_BLOCK_MESH,
    )
    .unwrap();
    let cd = dir.path().join("system/controlDict");
    let text = std::fs::read_to_string(&cd).unwrap() + FUNCTIONS;
    std::fs::write(&cd, text).unwrap();
    run_ok(openfoam("blockMesh"), dir.path());
    let dump = fixture("liggghts/settle.txt");
    let box_volume = 0.02 * 0.02 * 0.03;
    let methods = [
        "centre",
        "divided",
        "trilinear",
        "cube",
        "corrected-cube",
        "exact",
    ];
    for method in methods {
        let out = Command::new(env!("CARGO_BIN_EXE_foamgrain"))
            .args(["voidage", "--case", ".", "--dump", dump.to_str().unwrap()])
            .args(["--method", method, "--json"])
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stdout = String::from_utf8(out.stdout).unwrap();
        let v: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap()).unwrap();
        let deposited = v["deposited_volume"].as_f64().unwrap();
        let outside = v["outside_volume"].as_f64().unwrap();
        let particles = v["particle_volume"].as_f64().unwrap();
        assert!(
            approx::abs_diff_eq!(
                (deposited + outside),
                particles,
                epsilon = 1e-12 * particles
            ),
            "{method}: {v}"
        );
        let mut pp = openfoam("postProcess");
        pp.args(["-fields", "(voidfraction)", "-time", "0"]);
        let log = run_ok(pp, dir.path());
        let integral: f64 = log
            .lines()
            .find(|l| l.contains("volIntegrate"))
            .and_then(|l| l.split_whitespace().last())
            .unwrap_or_else(|| panic!("no volIntegrate line in:\n{log}"))
            .parse()
            .unwrap();
        let solid = box_volume - integral;
        // The subtraction V − ∫ε loses ~log10(V/deposited) ≈ 2 digits of the 17 written.
        let rel = (solid - deposited).abs() / deposited;
        assert!(
            rel < 1e-10,
            "{method}: OpenFOAM {solid:e} vs foamgrain {deposited:e} ({rel:e})"
        );
    }
}
