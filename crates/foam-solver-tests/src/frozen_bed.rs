//! The Ergun case (`openfoam-cases/ergun/CFD`) with frozen coupling fields: the inlet held at
//! 0.002 m/s, ε, Ksl, Us, f (and U, p when given) from a time directory of a coupled run, and
//! the Darcy drop of those fields ([`crate::darcy`]) as the reference for the steady Δp.

use crate::darcy::{self, Bed, DarcyDrop};
use crate::TestCase;
use foam::VolField;
use std::path::{Path, PathBuf};

/// Fluid density of the Ergun case (kg/m³).
pub const RHO: f64 = 10.0;
/// Superficial inlet velocity held (m/s).
pub const U_IN: f64 = 0.002;
/// The case's time step (s).
pub const DT: f64 = 5e-4;
/// Axial cell layers of the Ergun mesh.
pub const LAYERS: usize = 20;

/// The committed fields of the Ergun bed at t = 0.02 s (`fixtures/ergun-bed/README.md`).
pub fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/ergun-bed")
}

/// The Ergun case on frozen fields, set up to run `steps` steps and write 4 times.
pub struct FrozenBed {
    /// The case (temporary directory).
    pub case: TestCase,
    /// ε per cell.
    pub eps: Vec<f64>,
    /// Ksl per cell (kg/(m³ s)).
    pub ksl: Vec<f64>,
    /// Us per cell (m/s).
    pub us: Vec<[f64; 3]>,
    /// f per cell (N/m³).
    pub f: Vec<[f64; 3]>,
    /// Rows and columns of the bed.
    pub bed: Bed,
    /// End time (s).
    pub end: f64,
    /// Time step (s).
    pub dt: f64,
}

impl FrozenBed {
    /// Copies the Ergun case and sets the fields of `fields` (`voidfraction Ksl Us f` needed,
    /// `U p` used when present) as its start fields; `steps` steps of the case's [`DT`].
    pub fn new(fields: &Path, steps: usize) -> FrozenBed {
        Self::with_time_step(fields, steps, DT)
    }

    /// As [`Self::new`] with the time step `dt` (s) in `system/controlDict`.
    pub fn with_time_step(fields: &Path, steps: usize, dt: f64) -> FrozenBed {
        let case = TestCase::inputs_of(&testkit::repo_root().join("openfoam-cases/ergun/CFD"));
        let n = case.mesh().0.n_cells;
        hold_inlet(&case);
        for name in ["U", "p", "voidfraction", "Ksl", "Us", "f"] {
            let path = fields.join(name);
            if !path.exists() && (name == "U" || name == "p") {
                continue;
            }
            let values = VolField::read(&path)
                .unwrap_or_else(|e| panic!("{e}"))
                .internal(n)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            case.set_field(name, values);
        }
        let end = steps as f64 * dt;
        case.edit(
            "system/controlDict",
            "endTime         0.2;",
            &format!("endTime {end};"),
        );
        case.edit(
            "system/controlDict",
            "deltaT          0.0005;",
            &format!("deltaT {dt};"),
        );
        case.edit(
            "system/controlDict",
            "writeInterval   0.02;",
            &format!("writeInterval {};", end / 4.0),
        );
        let eps = case.scalars("0", "voidfraction");
        let ksl = case.scalars("0", "Ksl");
        let us = case.vectors("0", "Us");
        let f = case.vectors("0", "f");
        let bed = Bed::new(&case.mesh().1, &eps, &ksl, &us, RHO, LAYERS);
        FrozenBed {
            case,
            eps,
            ksl,
            us,
            f,
            bed,
            end,
            dt,
        }
    }

    /// The Darcy drops of the frozen fields at the held inlet velocity (kinematic, m²/s²).
    pub fn reference(&self) -> DarcyDrop {
        self.bed.bounds(U_IN)
    }

    /// The four write times (directory names).
    pub fn write_times(&self) -> Vec<String> {
        (1..=4)
            .map(|q| format!("{}", (self.end * q as f64 / 4.0 * 1e9).round() / 1e9))
            .collect()
    }

    /// Runs `solver` (grainPisoFoam) on the case; Δp (Pa, inlet mean − outlet) at each write
    /// time and the last p field.
    pub fn run_grain_piso_foam(&self, solver: &Path) -> (Vec<f64>, Vec<f64>) {
        self.case.run(solver);
        let (mesh, geo) = self.case.mesh();
        let inlet = mesh
            .boundary
            .iter()
            .find(|p| p.name == "inlet")
            .expect("inlet patch");
        let mut history = Vec::new();
        let mut last = Vec::new();
        for time in self.write_times() {
            let p = self.case.dir.join(&time).join("p");
            let pb = darcy::patch_values(&p, "inlet", inlet.n_faces)
                .expect("the inlet's face pressures");
            history.push(RHO * darcy::area_mean(&geo.face_areas[inlet.faces()], &pb));
            last = self.case.scalars(&time, "p");
        }
        (history, last)
    }
}

/// Replaces the inlet's velocity table of the Ergun case by its first value, 0.002 m/s.
fn hold_inlet(case: &TestCase) {
    let path = case.dir.join("0/U");
    let text = std::fs::read_to_string(&path).expect("0/U");
    let start = text
        .find("type            uniformFixedValue;")
        .expect("inlet table");
    let tail = "value           uniform (0 0 0.002);";
    let end = text[start..].find(tail).expect("inlet value") + start + tail.len();
    let held = format!("type fixedValue; value uniform (0 0 {U_IN});");
    std::fs::write(&path, format!("{}{held}{}", &text[..start], &text[end..])).expect("write 0/U");
}
