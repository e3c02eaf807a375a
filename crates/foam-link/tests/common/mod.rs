//! The porous cavity driven three ways — through the link, by grainPisoFoam's `prescribed`
//! source from files, by the native `fv` solver — with the same exchange fields.
//!
//! Case: `foam-solver-tests`' cavity (16 × 16 skewed cells, lid 1 m/s, ν 0.01 m²/s,
//! deltaT 5 ms) with a porous block 0.03 < x < 0.09 m, y < 0.05 m: Ksl = 2000 kg/(m³ s),
//! Us = (0.05, 0, 0) m/s, f = (0, −500, 0) N/m³ (as the solver's parallel test). Two coupling
//! intervals of 5 steps (pressure solved to 1e-12 in every corrector): in the first, ε goes from 1 to 0.6 in the block (blended linearly
//! per step), in the second it stays at 0.6.

#![allow(dead_code)]

use foam::FieldValues;
use foam_solver_tests::TestCase;
use mesh::v3::V3;

/// PISO steps per coupling interval.
pub const STEPS: usize = 5;
/// Coupling intervals.
pub const INTERVALS: usize = 2;
/// controlDict deltaT of the cavity, s.
pub const DT: f64 = 0.005;
/// The time after both intervals, as OpenFOAM names it.
pub const END: &str = "0.05";

/// The exchange fields per cell.
pub struct Fields {
    pub eps_block: Vec<f64>,
    pub ksl: Vec<f64>,
    pub us: Vec<V3>,
    pub f: Vec<V3>,
}

/// The meshed cavity and its exchange fields.
pub fn porous_cavity() -> (TestCase, Fields) {
    let case = TestCase::new("cavity");
    // Every pressure solve to 1e-12 (the template's first corrector stops at relTol 0.01,
    // where serial and processor-local DIC iterates differ by ~1e-4 in p after 10 steps).
    case.edit("system/fvSolution", "relTol 0.01;", "relTol 0;");
    let porous = case.cavity_porous_block();
    let pick = |a: f64, b: f64| porous.iter().map(|&p| if p { a } else { b }).collect();
    let vpick = |a: V3| {
        porous
            .iter()
            .map(|&p| if p { a } else { V3::zeros() })
            .collect()
    };
    let fields = Fields {
        eps_block: pick(0.6, 1.0),
        ksl: pick(2000.0, 0.0),
        us: vpick(V3::new(0.05, 0.0, 0.0)),
        f: vpick(V3::new(0.0, -500.0, 0.0)),
    };
    (case, fields)
}

/// ε at the start and end of interval `i` (0-based).
pub fn interval_voidage(fields: &Fields, i: usize) -> (Vec<f64>, Vec<f64>) {
    let ones = vec![1.0; fields.eps_block.len()];
    if i == 0 {
        (ones, fields.eps_block.clone())
    } else {
        (fields.eps_block.clone(), fields.eps_block.clone())
    }
}

/// ε at global step `k` (1-based) as the blending gives it.
pub fn step_voidage(fields: &Fields, k: usize) -> Vec<f64> {
    let (old, new) = interval_voidage(fields, (k - 1) / STEPS);
    let w = ((k - 1) % STEPS + 1) as f64 / STEPS as f64;
    old.iter().zip(&new).map(|(a, b)| a + w * (b - a)).collect()
}

/// OpenFOAM's name of step k's time (timePrecision 6).
pub fn time_name(k: usize) -> String {
    let t = (k as f64 * DT * 1e6).round() / 1e6;
    format!("{t}")
}

/// Runs grainPisoFoam with the `prescribed` source on a copy of `case`: Ksl, Us, f in `0/`,
/// each step's blended ε in its time directory; returns U and p at [`END`].
pub fn run_prescribed(
    case: &TestCase,
    fields: &Fields,
    solver: &std::path::Path,
) -> (Vec<V3>, Vec<f64>) {
    let run = case.duplicate();
    run.set_field("Ksl", FieldValues::Scalar(fields.ksl.clone()));
    run.set_field("Us", FieldValues::Vector(mesh::v3::to_arrays(&fields.us)));
    run.set_field("f", FieldValues::Vector(mesh::v3::to_arrays(&fields.f)));
    run.edit(
        "system/controlDict",
        "endTime         0.2;",
        "endTime         0.05;",
    );
    run.edit(
        "system/controlDict",
        "writeInterval   40;",
        "writeInterval   10;",
    );
    run.edit(
        "constant/couplingProperties",
        "couplingSource  frozen;",
        "couplingSource  prescribed;",
    );
    let template = run.dir.join("0/voidfraction");
    for k in 1..=STEPS * INTERVALS {
        let mut eps = foam::VolField::read(&template).unwrap();
        eps.set_internal(FieldValues::Scalar(step_voidage(fields, k)))
            .unwrap();
        let dir = run.dir.join(time_name(k));
        eps.write(&dir.join("voidfraction"), foam::Format::Ascii)
            .unwrap();
    }
    let log = run.run(solver);
    assert!(log.contains("prescribed coupling fields read"), "{log}");
    (
        mesh::v3::from_arrays(&run.vectors(END, "U")),
        run.scalars(END, "p"),
    )
}

/// The native solver with the same blending (as `runner::native::NativeFluid`); U and p.
pub fn run_native(case: &TestCase, fields: &Fields) -> (Vec<V3>, Vec<f64>) {
    let mut fluid = fv::Fluid::from_case(&case.dir).expect("native solver reads the case");
    fluid.set_exchange(&fields.ksl, &fields.us).unwrap();
    fluid.set_force(&fields.f).unwrap();
    let mut last = interval_voidage(fields, 0).0;
    for k in 1..=STEPS * INTERVALS {
        let eps = step_voidage(fields, k);
        fluid.set_voidage(&eps, &last).unwrap();
        fluid.advance(DT).unwrap();
        last = eps;
    }
    (fluid.u().to_vec(), fluid.p().to_vec())
}

/// Drives `fluid` through the two intervals.
pub fn run_link(fluid: &mut foam_link::OpenFoamFluid, fields: &Fields) {
    for i in 0..INTERVALS {
        let (old, new) = interval_voidage(fields, i);
        fluid
            .set_fields(&foam_link::protocol::FieldsIn {
                eps_old: &old,
                eps_new: &new,
                ksl: &fields.ksl,
                us: &fields.us,
                f: &fields.f,
            })
            .unwrap();
        fluid.advance_interval(STEPS as f64 * DT).unwrap();
    }
    assert!(
        approx::abs_diff_eq!(fluid.time(), 0.05, epsilon = 1e-12),
        "time {}",
        fluid.time()
    );
}

/// max |a − b| / max |b| over all components.
pub fn rel_diff_v(a: &[V3], b: &[V3]) -> f64 {
    let fa: Vec<f64> = a.iter().flatten().copied().collect();
    let fb: Vec<f64> = b.iter().flatten().copied().collect();
    rel_diff(&fa, &fb)
}

/// max |a − b| / max |b|.
pub fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// Initialises MPI for this test process (once) after the environment the spawn needs.
pub fn universe() -> mpi::environment::Universe {
    foam_link::prepare_environment();
    mpi::initialize().expect("MPI initialises once per test process")
}

/// Whether the full-tier tools are here (skips with a note in the fast tier).
pub fn tools() -> Option<std::path::PathBuf> {
    let solver = foam_solver_tests::grain_piso_foam()?;
    if !(testkit::tool("mpirun") && testkit::tool("decomposePar")) {
        return None;
    }
    Some(solver)
}

/// The heat channel's exchange fields (`foam-solver-tests`' heat-channel case, used by
/// link_heat and link_sparse_heat): a porous block 40 mm < x < 60 mm at ε 0.6 with
/// Ksl = 500 kg/(m³ s), cooled by Tsource = −5 K/s; ε 1, Ksl 0 and Tsource 0 elsewhere; Us and
/// f zero. ε starts from 1 in the first interval.
pub struct HeatChannel {
    /// Cells of the block.
    pub block: Vec<bool>,
    pub eps: Vec<f64>,
    pub ksl: Vec<f64>,
    /// Tsource, K/s.
    pub tsource: Vec<f64>,
    zeros_v: Vec<V3>,
    ones: Vec<f64>,
}

impl HeatChannel {
    pub fn new(case: &TestCase) -> HeatChannel {
        let (_, g) = case.mesh();
        let block: Vec<bool> = g
            .cell_centres
            .iter()
            .map(|c| c[0] > 0.04 && c[0] < 0.06)
            .collect();
        let pick =
            |a: f64, b: f64| -> Vec<f64> { block.iter().map(|&x| if x { a } else { b }).collect() };
        let (eps, ksl, tsource) = (pick(0.6, 1.0), pick(500.0, 0.0), pick(-5.0, 0.0));
        let n = block.len();
        HeatChannel {
            block,
            eps,
            ksl,
            tsource,
            zeros_v: vec![V3::zeros(); n],
            ones: vec![1.0; n],
        }
    }

    /// The exchange fields of interval `i` (0 the first).
    pub fn fields(&self, i: usize) -> foam_link::protocol::FieldsIn<'_> {
        foam_link::protocol::FieldsIn {
            eps_old: if i == 0 { &self.ones } else { &self.eps },
            eps_new: &self.eps,
            ksl: &self.ksl,
            us: &self.zeros_v,
            f: &self.zeros_v,
        }
    }
}
