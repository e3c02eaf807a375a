//! The `foamgrain` binary end to end on committed fixtures (real OpenFOAM and LIGGGHTS output).

use std::path::Path;
use std::process::{Command, Output};
use testkit::fixture;

fn foamgrain(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foamgrain"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn ok(args: &[&str], dir: &Path) -> String {
    let o = foamgrain(args, dir);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn info_json_matches_checkmesh() {
    let case = fixture("foam/cavity");
    let out = ok(
        &["info", "--case", case.to_str().unwrap(), "--json"],
        Path::new("."),
    );
    let v: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    // checkMesh on this case: points 60, faces 98, internal 46, cells 24, volume 0.0001.
    assert_eq!(v["cells"], 24);
    assert_eq!(v["faces"], 98);
    assert_eq!(v["internal_faces"], 46);
    assert_eq!(v["points"], 60);
    assert!((v["total_volume"].as_f64().unwrap() - 1e-4).abs() < 1e-18);
    assert_eq!(v["patches"][2]["type"], "empty");
    assert_eq!(v["processors"], 2);
    assert_eq!(v["axis_aligned_hex_grid"], serde_json::Value::Null); // the block is skewed
}

#[test]
fn convert_writes_vtk_files() {
    let dir = tempfile::tempdir().unwrap();
    let case = fixture("foam/cavity");
    ok(
        &[
            "convert",
            "case",
            "--case",
            case.to_str().unwrap(),
            "-o",
            "c.vtu",
            "--fields",
            "V,U",
        ],
        dir.path(),
    );
    let vtu = std::fs::read_to_string(dir.path().join("c.vtu")).unwrap();
    assert!(
        vtu.contains("NumberOfCells=\"24\"")
            && vtu.contains("Name=\"V\"")
            && vtu.contains("Name=\"U\"")
    );
    assert!(!vtu.contains("Name=\"p\""));
    let bin = fixture("liggghts/settle.bin");
    let cols = "id,type,x,y,z,vx,vy,vz,omegax,omegay,omegaz,radius,mass";
    let out = ok(
        &[
            "convert",
            "dump",
            "--dump",
            bin.to_str().unwrap(),
            "--columns",
            cols,
            "--all",
            "-o",
            "s",
        ],
        dir.path(),
    );
    assert!(out.contains("wrote 2 snapshots"), "{out}");
    let pvd = std::fs::read_to_string(dir.path().join("s/settle.pvd")).unwrap();
    assert!(pvd.contains("settle_3000.vtp") && pvd.contains("settle_6000.vtp"));
    let vtp = std::fs::read_to_string(dir.path().join("s/settle_6000.vtp")).unwrap();
    assert!(vtp.contains("NumberOfPoints=\"200\"") && vtp.contains("Name=\"omega\""));
}

#[test]
fn bad_input_fails_with_a_message_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let o = foamgrain(&["info", "--case", "no/such/case"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("no/such/case") && e.contains("does not exist"),
        "{e}"
    );
    let bin = fixture("liggghts/settle.bin");
    let o = foamgrain(
        &["convert", "dump", "--dump", bin.to_str().unwrap()],
        dir.path(),
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("settle.bin") && e.contains("13 columns but 9 column names"),
        "{e}"
    );
    let o = foamgrain(
        &[
            "convert",
            "dump",
            "--dump",
            bin.to_str().unwrap(),
            "--snapshot",
            "x",
        ],
        dir.path(),
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("--snapshot must be"));
    let o = foamgrain(
        &[
            "convert",
            "case",
            "--case",
            fixture("foam/cavity").to_str().unwrap(),
            "--time",
            "7",
        ],
        dir.path(),
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("no time directory `7`"));
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "failures write nothing"
    );
}

#[test]
fn every_command_has_help() {
    for args in [
        vec!["--help"],
        vec!["info", "--help"],
        vec!["convert", "--help"],
        vec!["convert", "dump", "--help"],
        vec!["convert", "case", "--help"],
    ] {
        let out = ok(&args, Path::new("."));
        assert!(out.contains("Usage: foamgrain"), "{args:?}");
    }
}
