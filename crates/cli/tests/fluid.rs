//! `foamgrain fluid CASE`: the native fluid alone on plain OpenFOAM cases.
//!
//! * Fast tier: the icoFoam cavity fixture (`tests/fixtures/fv/cavity-re10`, Debian's icoFoam
//!   v1912 output) through the command: its U at t = 0.5 equals icoFoam's to round-off (as
//!   `fv`'s own test of `Fluid::run`, here through the CLI's wiring); `purgeWrite` keeps the
//!   last N directories; an unsupported function object or application is refused by name.
//! * Full tier: OpenFOAM's own `incompressible/pisoFoam/RAS/cavity` as Debian ships it
//!   (`openfoam-examples`), run unchanged by pisoFoam and by `foamgrain fluid`: every written
//!   time's U, p, k, epsilon and nut agree to 2e-4 of the field's largest magnitude.
//!   The case's solvers stop at tolerance 1e-6 (p, GAMG, relTol 0.1 before the final
//!   corrector) and 1e-5 (U, k, ε), and `fv`'s GAMG is a different multigrid from OpenFOAM's
//!   (the same answer to the tolerance, not the same iterates), so the fields differ at the
//!   level of the tolerances, not of round-off. Measured: at t = 0.5 s U 3.0e-5, p 6.3e-5,
//!   k 1.3e-5, ε 1.3e-5, nut 1.1e-5; at t = 10 s U 5.2e-6, p 7.4e-6, k 1.1e-6, ε 3.4e-6, nut
//!   3.5e-5. The U, k and ε iteration counts over the run were pisoFoam's exactly (6529, 5088);
//!   p took 14674 against pisoFoam's 11416.
//! * Full tier: OpenFOAM's own `incompressible/icoFoam/elbow` (a Fluent mesh of triangles and
//!   quadrilaterals, converted by `fluentMeshToFoam`; non-orthogonal, two non-orthogonal
//!   correctors, p by PCG/DIC, U by smoothSolver) run by icoFoam and by `foamgrain fluid`: the
//!   same iterations in every solve (measured: all 1200 p solves and 400 U solves equal, 24372 p
//!   iterations each), and every written time's U and p equal to the case's `writePrecision 6`
//!   (measured: at most 2.0e-6 of the largest magnitude, at t = 1).

use std::path::Path;
use std::process::{Command, Output};
use testkit::{copy_dir, fixture, openfoam, run_ok, tool};

fn foamgrain_fluid(case: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foamgrain"))
        .arg("fluid")
        .arg(case)
        .args(extra)
        .output()
        .unwrap()
}

/// The internal field of a volField file, as flat components (`n` cells).
fn internal(path: &Path, n: usize) -> Vec<f64> {
    let f = foam::VolField::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match f.internal(n).unwrap() {
        foam::FieldValues::Scalar(v) => v,
        foam::FieldValues::Vector(v) => v.into_iter().flatten().collect(),
    }
}

/// max |a − b| / max |b| over the internal field `name` at time `t`.
fn rel_diff(ours: &Path, theirs: &Path, t: &str, name: &str) -> f64 {
    let n = foam::case::Case::open(theirs)
        .unwrap()
        .read_mesh()
        .unwrap()
        .n_cells;
    let a = internal(&ours.join(t).join(name), n);
    let b = internal(&theirs.join(t).join(name), n);
    assert_eq!(a.len(), b.len(), "{t}/{name}: sizes");
    let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

#[test]
fn icofoam_cavity_through_the_command_matches_icofoam() {
    let dir = tempfile::tempdir().unwrap();
    copy_dir(&fixture("fv/cavity-re10"), dir.path());
    std::fs::remove_dir_all(dir.path().join("0.5")).unwrap();
    let out = foamgrain_fluid(dir.path(), &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let e = rel_diff(dir.path(), &fixture("fv/cavity-re10"), "0.5", "U");
    assert!(e < 1e-12, "U differs from icoFoam's by {e:e}");
}

#[test]
fn purge_write_keeps_the_last_directories() {
    let dir = tempfile::tempdir().unwrap();
    copy_dir(&fixture("fv/cavity-re10"), dir.path());
    std::fs::remove_dir_all(dir.path().join("0.5")).unwrap();
    let cd = dir.path().join("system/controlDict");
    let text = std::fs::read_to_string(&cd).unwrap();
    let text = text
        .replace("writeInterval   100;", "writeInterval   20;")
        .replace("purgeWrite      0;", "purgeWrite      2;");
    std::fs::write(&cd, text).unwrap();
    let out = foamgrain_fluid(dir.path(), &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut times: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.parse::<f64>().is_ok())
        .collect();
    times.sort_by(|a, b| a.parse::<f64>().unwrap().total_cmp(&b.parse().unwrap()));
    // writes at steps 20, 40, …, 100 (t = 0.1 … 0.5); the start time is not purged
    assert_eq!(times, ["0", "0.4", "0.5"]);
}

/// A `probes` function object: the value at a point is the one of the cell holding it in the
/// written field (the cavity's 20 × 20 cells of 5 mm: (52.5, 52.5) mm is the centre of cell
/// 10 + 20·10 = 210), a point outside the mesh is skipped with a warning.
#[test]
fn probes_sample_the_cell_holding_the_point() {
    let dir = tempfile::tempdir().unwrap();
    copy_dir(&fixture("fv/cavity-re10"), dir.path());
    std::fs::remove_dir_all(dir.path().join("0.5")).unwrap();
    let cd = dir.path().join("system/controlDict");
    let text = std::fs::read_to_string(&cd).unwrap();
    let probes = "functions { probes { type probes; fields (p); \
                  probeLocations ((0.0525 0.0525 0.005) (0.5 0.5 0.005)); } }";
    std::fs::write(&cd, format!("{text}\n{probes}\n")).unwrap();
    let out = foamgrain_fluid(dir.path(), &[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("0.5 0.5 0.005"),
        "no warning for the point outside: {err}"
    );
    let samples = std::fs::read_to_string(dir.path().join("postProcessing/probes/0/p")).unwrap();
    let last = samples.lines().last().unwrap();
    let cols: Vec<f64> = last
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect();
    assert_eq!(cols.len(), 2, "{last}");
    let p = internal(&dir.path().join("0.5/p"), 400);
    assert!(
        (cols[0] - 0.5).abs() < 1e-12 && (cols[1] - p[210]).abs() <= 1e-5 * p[210].abs(),
        "{last} against p[210] = {}",
        p[210]
    );
}

#[test]
fn unsupported_function_objects_and_applications_are_refused_by_name() {
    let cases = [
        (
            "functions { drag { type forces; patches (movingWall); } }",
            "functions/drag: function object type `forces`",
        ),
        ("application simpleFoam;", "application `simpleFoam`"),
    ];
    for (extra, expected) in cases {
        let dir = tempfile::tempdir().unwrap();
        copy_dir(&fixture("fv/cavity-re10"), dir.path());
        let cd = dir.path().join("system/controlDict");
        let text = std::fs::read_to_string(&cd)
            .unwrap()
            .replace("application     icoFoam;", "");
        std::fs::write(&cd, format!("{text}\n{extra}\n")).unwrap();
        let out = foamgrain_fluid(dir.path(), &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains(expected), "{err}");
        assert!(err.contains("system/controlDict"), "{err}");
    }
}

/// An `openfoam-examples` case run both ways: copied to `ours` and `theirs`, each meshed by
/// `mesh`, OpenFOAM's `solver` run in `theirs` and `foamgrain fluid` (with `extra`, and it must
/// succeed) in `ours`.
struct BothWays {
    _root: tempfile::TempDir,
    ours: std::path::PathBuf,
    theirs: std::path::PathBuf,
    /// OpenFOAM's standard output.
    their_log: String,
    /// foamgrain's standard output.
    our_log: String,
}

fn run_both_ways(example: &str, solver: &str, mesh: impl Fn(&Path), extra: &[&str]) -> BothWays {
    assert!(
        Path::new(example).is_dir(),
        "{example} is missing: install openfoam-examples (docker/build-and-run.sh packages)"
    );
    let root = tempfile::tempdir().unwrap();
    let (ours, theirs) = (root.path().join("ours"), root.path().join(solver));
    for d in [&ours, &theirs] {
        copy_dir(Path::new(example), d);
        mesh(d);
    }
    let their_log = run_ok(openfoam(solver), &theirs);
    let out = foamgrain_fluid(&ours, extra);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    BothWays {
        _root: root,
        ours,
        theirs,
        their_log,
        our_log: String::from_utf8_lossy(&out.stdout).into_owned(),
    }
}

/// Where Debian's `openfoam-examples` puts the RAS cavity.
const RAS_CAVITY: &str =
    "/usr/share/doc/openfoam-examples/examples/incompressible/pisoFoam/RAS/cavity";

#[test]
fn openfoams_ras_cavity_example_gives_pisofoams_fields() {
    if !tool("pisoFoam") {
        return;
    }
    let run = run_both_ways(
        RAS_CAVITY,
        "pisoFoam",
        |d| {
            run_ok(openfoam("blockMesh"), d);
        },
        &[],
    );
    let (ours, theirs) = (&run.ours, &run.theirs);
    let mut compared = 0;
    for t in ["0.5", "1", "5", "10"] {
        for name in ["U", "p", "k", "epsilon", "nut"] {
            let e = rel_diff(ours, theirs, t, name);
            assert!(e < 2e-4, "t = {t}: {name} differs from pisoFoam's by {e:e}");
            compared += 1;
        }
    }
    assert_eq!(compared, 20);
}

/// Where Debian's `openfoam-examples` puts icoFoam's elbow.
const ELBOW: &str = "/usr/share/doc/openfoam-examples/examples/incompressible/icoFoam/elbow";

/// The `No Iterations` of every solve of `field` in a log, in order (icoFoam's `Solving for p,
/// …` lines or `foamgrain fluid --log`'s `p: …` lines).
fn iterations(log: &str, field: &str) -> Vec<u32> {
    log.lines()
        .filter(|l| {
            l.contains(&format!("Solving for {field},")) || l.starts_with(&format!("{field}: "))
        })
        .map(|l| {
            let n = l.rsplit("No Iterations").next().unwrap_or("");
            n.trim()
                .parse()
                .unwrap_or_else(|_| panic!("no count in `{l}`"))
        })
        .collect()
}

#[test]
fn openfoams_elbow_example_gives_icofoams_iterations_and_fields() {
    if !tool("icoFoam") {
        return;
    }
    let run = run_both_ways(
        ELBOW,
        "icoFoam",
        |d| {
            // Debian's package compresses the mesh file (its documentation is gzipped); the
            // case's Allrun reads it as elbow.msh.
            if d.join("elbow.msh.gz").is_file() {
                let mut gunzip = Command::new("gunzip");
                gunzip.arg("elbow.msh.gz");
                run_ok(gunzip, d);
            }
            let mut convert = openfoam("fluentMeshToFoam");
            convert.arg("elbow.msh");
            run_ok(convert, d);
        },
        &["--log"],
    );
    let (ours, theirs) = (&run.ours, &run.theirs);
    for field in ["Ux", "Uy", "p"] {
        let (a, b) = (
            iterations(&run.our_log, field),
            iterations(&run.their_log, field),
        );
        assert!(!b.is_empty(), "no {field} solves in icoFoam's log");
        assert_eq!(a, b, "{field}: iterations per solve differ from icoFoam's");
    }
    for t in ["1", "2", "5", "10"] {
        for name in ["U", "p"] {
            let e = rel_diff(ours, theirs, t, name);
            // writePrecision 6: a value's last digit is 5e-7 of it.
            assert!(e < 5e-6, "t = {t}: {name} differs from icoFoam's by {e:e}");
        }
    }
}
