//! A test case in a temporary directory: copy a template, mesh it, set fields, run, read.

use foam::{Case, FieldValues, Format, PolyMesh, VolField};
use mesh::MeshGeometry;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A case copied from `cases/<template>` into its own temporary directory and meshed.
pub struct TestCase {
    _tmp: tempfile::TempDir,
    /// The case directory.
    pub dir: PathBuf,
}

fn template_dir(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
}

impl TestCase {
    /// Copies the template `name` and runs `blockMesh` on it.
    pub fn new(name: &str) -> TestCase {
        let case = TestCase::template(name);
        case.block_mesh();
        case
    }

    /// Copies the template `name` without meshing it (edit `system/blockMeshDict`, then call
    /// [`TestCase::block_mesh`]).
    pub fn template(name: &str) -> TestCase {
        TestCase::copy_of(&template_dir(name))
    }

    /// Runs `blockMesh`.
    pub fn block_mesh(&self) {
        self.run_tool("blockMesh", &[]);
    }

    /// A copy of `dir` (e.g. a meshed case about to be run a second way).
    pub fn copy_of(dir: &Path) -> TestCase {
        TestCase::copied_with(dir, testkit::copy_dir)
    }

    /// A copy of the inputs of `dir` (what git tracks: a reference case without the outputs a
    /// user's run left in it).
    pub fn inputs_of(dir: &Path) -> TestCase {
        TestCase::copied_with(dir, testkit::copy_inputs)
    }

    fn copied_with(dir: &Path, copy: fn(&Path, &Path)) -> TestCase {
        let tmp = tempfile::tempdir().expect("temporary directory");
        let dir_out = tmp.path().join("case");
        copy(dir, &dir_out);
        TestCase {
            _tmp: tmp,
            dir: dir_out,
        }
    }

    /// An independent copy of this case as it is now.
    pub fn duplicate(&self) -> TestCase {
        TestCase::copy_of(&self.dir)
    }

    /// The mesh and its geometry (cell centres and volumes as OpenFOAM computes them).
    pub fn mesh(&self) -> (PolyMesh, MeshGeometry) {
        let case = Case::open(&self.dir).expect("case");
        let mesh = case.read_mesh().expect("polyMesh");
        let geometry = MeshGeometry::new(&mesh).expect("mesh geometry");
        (mesh, geometry)
    }

    /// Replaces the cell values of `0/<name>` (its boundary conditions stay as written).
    pub fn set_field(&self, name: &str, values: FieldValues) {
        let path = self.dir.join("0").join(name);
        let mut field = VolField::read(&path).expect("field file");
        field
            .set_internal(values)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        field.write(&path, Format::Ascii).expect("write field");
    }

    /// Replaces `from` by `to` in the file `rel` of the case; `from` must occur.
    pub fn edit(&self, rel: &str, from: &str, to: &str) {
        let path = self.dir.join(rel);
        let text = std::fs::read_to_string(&path).expect("case file");
        assert!(text.contains(from), "{}: no `{from}`", path.display());
        std::fs::write(&path, text.replace(from, to)).expect("write case file");
    }

    /// Runs an OpenFOAM program (`WM_PROJECT_DIR` set) on the case; returns its stdout.
    pub fn run_tool(&self, program: &str, args: &[&str]) -> String {
        let mut c = testkit::openfoam(program);
        c.arg("-case").arg(&self.dir).args(args);
        testkit::run_ok(c, &self.dir)
    }

    /// Runs `program` (e.g. the grainPisoFoam path) serially and returns its log.
    pub fn run(&self, program: &Path) -> String {
        self.run_tool(program.to_str().expect("UTF-8 path"), &[])
    }

    /// Runs `program` and returns whether it succeeded and its stdout + stderr (for tests of
    /// the solver's error messages).
    pub fn try_run(&self, program: &Path) -> (bool, String) {
        let out = testkit::openfoam(program.to_str().expect("UTF-8 path"))
            .arg("-case")
            .arg(&self.dir)
            .current_dir(&self.dir)
            .env("FOAM_ABORT", "0")
            .output()
            .expect("run solver");
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        (out.status.success(), text)
    }

    /// `decomposePar`, `mpirun -np <ranks> program -parallel`, `reconstructPar`; returns the
    /// solver's log. Runs as root are allowed and ranks may oversubscribe the cores.
    pub fn run_parallel(&self, program: &Path, ranks: usize) -> String {
        self.run_tool("decomposePar", &["-force"]);
        let mut c: Command = testkit::openfoam("mpirun");
        c.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
            .env("OMPI_MCA_mpi_yield_when_idle", "1")
            .args(["--oversubscribe", "-np", &ranks.to_string()])
            .arg(program)
            .arg("-parallel")
            .arg("-case")
            .arg(&self.dir);
        let log = testkit::run_ok(c, &self.dir);
        self.run_tool("reconstructPar", &["-latestTime"]);
        log
    }

    /// The cell values of `<time>/<name>`.
    pub fn cell_values(&self, time: &str, name: &str) -> FieldValues {
        let path = self.dir.join(time).join(name);
        let field = VolField::read(&path).unwrap_or_else(|e| panic!("{e}"));
        let n = self.mesh().0.n_cells;
        field
            .internal(n)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    /// The cavity's porous block, 0.03 < x < 0.09 m and y < 0.05 m, per cell (the `simple`
    /// 2 × 1 × 1 decomposition splits the cells at x ≈ 0.06 m, through the block). Checks that
    /// the block is neither empty nor the whole mesh.
    pub fn cavity_porous_block(&self) -> Vec<bool> {
        let (_, g) = self.mesh();
        let porous: Vec<bool> = g
            .cell_centres
            .iter()
            .map(|c| c[0] > 0.03 && c[0] < 0.09 && c[1] < 0.05)
            .collect();
        assert!(porous.iter().any(|&b| b) && !porous.iter().all(|&b| b));
        porous
    }

    /// Cell values of a scalar field.
    pub fn scalars(&self, time: &str, name: &str) -> Vec<f64> {
        match self.cell_values(time, name) {
            FieldValues::Scalar(v) => v,
            FieldValues::Vector(_) => panic!("{time}/{name} is a vector field"),
        }
    }

    /// Cell values of a vector field.
    pub fn vectors(&self, time: &str, name: &str) -> Vec<[f64; 3]> {
        match self.cell_values(time, name) {
            FieldValues::Vector(v) => v,
            FieldValues::Scalar(_) => panic!("{time}/{name} is a scalar field"),
        }
    }
}

/// max |a − b| over all components.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "different numbers of values");
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The components of vectors as one slice-friendly list.
pub fn flatten(v: &[[f64; 3]]) -> Vec<f64> {
    v.iter().flatten().copied().collect()
}

/// max |x| over all values.
pub fn max_abs(a: &[f64]) -> f64 {
    a.iter().map(|x| x.abs()).fold(0.0, f64::max)
}
