//! Full tier: grainPisoFoam on 2 ranks of its own with more cells on a rank than Open MPI sends
//! eagerly gets through the handshake (`foam-link`'s handshake module).
//!
//! Each solver rank sends the coupler its cell map (4 bytes per cell) in its handshake; over
//! the TCP BTL that carries the spawn's intercommunicator a message above 64 KiB is sent only
//! once the coupler posts its receive. When the coupler took rank 0's whole handshake and start
//! fields before any message of rank 1, rank 1 waited for its cell map to be taken, rank 0
//! waited for rank 1 in OpenFOAM's `globalMeshData` gather (before the start fields) and the
//! coupler for rank 0's start fields: on 2 solver ranks the run hung at 40,000 and 64,000
//! cells and not at 25,600 (docs/scaling.md). Here the settling case's box is meshed with
//! 20 × 100 × 20 = 40,000 cells (20,000 on each rank: an 80,000-byte map) and run for
//! [`STEPS`] coupling steps as users launch it (`mpirun -np 1 foamgrain run CASE --fluid
//! openfoam --dem liggghts --np 2`). A run that has not ended within [`BOUND`] fails the test
//! (its processes are killed; the run takes about 7 s, the bound is wide for a loaded
//! machine): it must end, having advanced the fluid, and written the end time's U on each
//! solver rank's piece (more than 16,384 cells each) with a finite value for every cell.
//!
//! Needs the cargo features `mpi` and `liggghts`, Open MPI, LIGGGHTS, OpenFOAM's blockMesh and
//! grainPisoFoam (`openfoam-cases/solver/build.sh`).

#![cfg(all(feature = "mpi", feature = "liggghts"))]

use foam::{FieldValues, VolField};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;

/// The mesh: 20 × 100 × 20 cells over the settling case's 0.01 × 0.05 × 0.01 m box.
const CELLS: [usize; 3] = [20, 100, 20];
/// Coupling steps run (1 ms each: the case's `couple_every 100` DEM steps of 10 µs).
const STEPS: usize = 2;
/// How long the run may take (it took about 10 s with the handshake fixed).
const BOUND: Duration = Duration::from_secs(180);

/// The settling case in `dir`, meshed with [`CELLS`] by blockMesh, to [`STEPS`] ms.
fn fine_settling(dir: &Path) -> PathBuf {
    let case = dir.join("settling-fine");
    testkit::copy_inputs(&testkit::repo_root().join("openfoam-cases/settling"), &case);
    let cfd = case.join("CFD");
    let edit = |file: &str, from: &str, to: &str| {
        let path = cfd.join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(from), "{file} has no `{from}`");
        std::fs::write(&path, text.replace(from, to)).unwrap();
    };
    let [x, y, z] = CELLS;
    edit(
        "system/blockMeshDict",
        "(4 20 4) simpleGrading",
        &format!("({x} {y} {z}) simpleGrading"),
    );
    let end = format!("{}", STEPS as f64 * 1e-3);
    edit(
        "system/controlDict",
        "endTime         0.2;",
        &format!("endTime         {end};"),
    );
    edit(
        "system/controlDict",
        "writeInterval   0.05;",
        &format!("writeInterval   {end};"),
    );
    std::fs::remove_dir_all(cfd.join("constant/polyMesh")).unwrap();
    let mesh = common::cosim_env(Command::new("blockMesh").current_dir(&cfd))
        .output()
        .unwrap();
    assert!(
        mesh.status.success(),
        "blockMesh failed:\n{}",
        String::from_utf8_lossy(&mesh.stdout)
    );
    case
}

/// The pids of the processes whose command line names `case` (the coupler, the solver ranks
/// and the shells that started them).
fn pids_naming(case: &Path) -> Vec<i32> {
    let key = case.to_string_lossy().into_owned();
    let me = std::process::id() as i32;
    std::fs::read_dir("/proc")
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let pid: i32 = e.file_name().to_str()?.parse().ok()?;
            let cmd = std::fs::read(e.path().join("cmdline")).ok()?;
            (pid != me && String::from_utf8_lossy(&cmd).contains(&key)).then_some(pid)
        })
        .collect()
}

#[test]
fn two_solver_ranks_above_the_eager_limit_get_through_the_handshake() {
    if !common::cosim_ready(&["mpirun", "liggghts", "blockMesh"]) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let case = fine_settling(tmp.path());
    let log_path = tmp.path().join("run.log");
    let log = std::fs::File::create(&log_path).unwrap();
    let mut child = common::cosim_env(
        Command::new("mpirun")
            .args([
                "--oversubscribe",
                "-np",
                "1",
                env!("CARGO_BIN_EXE_foamgrain"),
                "run",
            ])
            .arg(&case)
            .args(["--fluid", "openfoam", "--dem", "liggghts", "--np", "2"]),
    )
    .stdout(Stdio::from(log.try_clone().unwrap()))
    .stderr(Stdio::from(log))
    .spawn()
    .unwrap();
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > BOUND {
            let left = pids_naming(&case);
            for pid in &left {
                unsafe { libc::kill(*pid, libc::SIGKILL) };
            }
            let _ = child.kill();
            let _ = child.wait();
            let text = std::fs::read_to_string(&log_path).unwrap_or_default();
            panic!("the run did not end within {BOUND:?} (processes {left:?} killed):\n{text}");
        }
        std::thread::sleep(Duration::from_millis(200));
    };
    let text = std::fs::read_to_string(&log_path).unwrap();
    eprintln!("the run took {:.1} s", started.elapsed().as_secs_f64());
    // the settling case's seed comparisons are for its own mesh and end time (exit 2 when they
    // fail); an error must not happen
    assert!(
        status.success() || status.code() == Some(2),
        "the run failed ({status}):\n{text}"
    );
    let n: usize = CELLS.iter().product();
    assert!(
        text.contains(&format!("{STEPS} coupling steps to"))
            && text.contains(&format!("{n} cells;")),
        "not {STEPS} coupling steps on {n} cells:\n{text}"
    );
    // the fields stay decomposed: each piece holds more cells than fit in an eager message
    // of its cell map, and its U at the end time has a value for each
    let whole = foam::Case::open(case.join("CFD")).unwrap();
    let pieces = foam::decomposed::pieces(&whole, n).unwrap();
    assert_eq!(pieces.len(), 2, "processor pieces");
    for piece in &pieces {
        let local = piece.mesh.n_cells;
        assert!(4 * local > 65536, "piece {}: {local} cells", piece.rank);
        let path = piece
            .case
            .root()
            .join(format!("{}", STEPS as f64 * 1e-3))
            .join("U");
        let field = VolField::read(&path).unwrap();
        match field.internal(local).unwrap() {
            FieldValues::Vector(u) => assert!(u.iter().flatten().all(|x| x.is_finite())),
            _ => panic!("{}: not a vector field", path.display()),
        }
    }
    assert!(
        pids_naming(&case).is_empty(),
        "processes left after the run"
    );
}
