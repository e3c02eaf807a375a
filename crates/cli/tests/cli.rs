//! The `foamgrain` binary end to end on committed fixtures (real OpenFOAM and LIGGGHTS output).

use approx::assert_abs_diff_eq;
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
    assert_abs_diff_eq!(v["total_volume"].as_f64().unwrap(), 1e-4, epsilon = 1e-18);
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

/// Output into a pipe whose reader is gone (`foamgrain info … | head` after head exits) ends the
/// process by SIGPIPE, as it ends `cat`, not by a panic.
#[test]
fn a_closed_pipe_ends_the_output_without_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let case = fixture("foam/cavity");
    let o = Command::new(env!("CARGO_BIN_EXE_foamgrain"))
        .args(["info", "--case", case.to_str().unwrap()])
        .stdout(writer)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(
        o.status.signal(),
        Some(libc::SIGPIPE),
        "{:?}: {stderr}",
        o.status
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

#[test]
fn dem_runs_a_liggghts_deck_as_liggghts_would() {
    // The small pour of the DEM fixtures, in a directory of its own (paths in the deck are
    // relative to the current directory, as with `liggghts -in`).
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        testkit::liggghts_input("pour.in"),
        dir.path().join("in.pour"),
    )
    .unwrap();
    let out = ok(
        &[
            "dem", "-in", "in.pour", "-var", "np", "60", "-var", "w", "0.003", "-var", "nsteps",
            "400", "-var", "zmax", "0.01",
        ],
        dir.path(),
    );
    // LIGGGHTS's thermo: a header per run and rows at the first and last step of each run
    // (`run 1`, then `run 400`); the deck's `thermo 2000` has no multiple in between.
    let rows: Vec<Vec<&str>> = out
        .lines()
        .filter(|l| {
            l.split_whitespace()
                .next()
                .is_some_and(|w| w.parse::<u64>().is_ok())
        })
        .map(|l| l.split_whitespace().collect())
        .collect();
    let steps: Vec<&str> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(steps, ["0", "1", "1", "401"], "{out}");
    assert!(rows.iter().all(|r| r[1] == "60" && r.len() == 4), "{out}");
    assert_eq!(
        out.lines()
            .filter(|l| l.trim_start().starts_with("Step"))
            .count(),
        2
    );
    assert!(out.contains("Loop time of "), "{out}");
    // its dumps (every nsteps/4 = 100 steps) and the log file
    for s in [100, 200, 300, 400] {
        assert!(
            dir.path().join(format!("post/pour_{s}.txt")).is_file(),
            "{s}"
        );
    }
    let log = std::fs::read_to_string(dir.path().join("log.liggghts")).unwrap();
    assert!(
        log.contains("Loop time of ") && log.contains("KinEng"),
        "{log}"
    );

    // A bad deck: the error names the file and the line, nothing panics.
    std::fs::write(
        dir.path().join("in.bad"),
        "atom_style granular\nfix p all pour 100 1 1\n",
    )
    .unwrap();
    let o = foamgrain(&["dem", "in.bad", "-log", "none"], dir.path());
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("in.bad:2:") && e.contains("pour"), "{e}");
    // A missing deck is named, its OS error said once.
    let o = foamgrain(&["dem", "in.missing"], dir.path());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && e.contains("in.missing"), "{e}");
    assert_eq!(e.matches("No such file").count(), 1, "{e}");
    // An unknown LIGGGHTS option is refused with the supported ones.
    let o = foamgrain(&["dem", "in.pour", "-sf", "gpu"], dir.path());
    assert!(String::from_utf8_lossy(&o.stderr).contains("-in, -var"));
}
