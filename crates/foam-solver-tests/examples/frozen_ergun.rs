//! The Ergun bed with frozen coupling fields: grainPisoFoam and the native solver (`fv`, with
//! and without `harmonic_faces`) run to steady state on the same ε, Ksl, Us, f, and their
//! pressure drops are compared with the Darcy drop of those fields
//! (`foam_solver_tests::darcy`).
//!
//! ```sh
//! cargo run -p foam-solver-tests --example frozen_ergun -- [FIELDS_DIR] [STEPS]
//! ```
//!
//! FIELDS_DIR is a time directory of a coupled Ergun run (default `/tmp/erg-full/CFD/0.02`)
//! holding `U p voidfraction Ksl Us f` on the mesh of `openfoam-cases/ergun/CFD`; STEPS (default
//! 80) steps of the case's Δt = 5e-4 s are run with the inlet held at 0.002 m/s. grainPisoFoam
//! runs only when OpenFOAM is installed.

use foam::VolField;
use foam_solver_tests::darcy::{self, Bed};
use foam_solver_tests::{grain_piso_foam, TestCase};
use std::path::PathBuf;

const RHO: f64 = 10.0;
const U_IN: f64 = 0.002;
const DT: f64 = 5e-4;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let src = PathBuf::from(
        args.first()
            .map(String::as_str)
            .unwrap_or("/tmp/erg-full/CFD/0.02"),
    );
    let steps: usize = args.get(1).map_or(80, |s| s.parse().expect("STEPS"));

    let case = TestCase::copy_of(&testkit::repo_root().join("openfoam-cases/ergun/CFD"));
    let n = case.mesh().0.n_cells;
    hold_inlet(&case);
    for name in ["U", "p", "voidfraction", "Ksl", "Us", "f"] {
        let path = src.join(name);
        let values = VolField::read(&path)
            .unwrap_or_else(|e| panic!("{e}"))
            .internal(n)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        case.set_field(name, values);
    }
    let end = steps as f64 * DT;
    case.edit(
        "system/controlDict",
        "endTime         0.2;",
        &format!("endTime {end};"),
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
    let (_, geo) = case.mesh();
    let bed = Bed::new(&geo, &eps, &ksl, &us, RHO, 20);
    let reference = bed.bounds(U_IN);
    println!(
        "Darcy drop of the frozen fields (Pa): uniform flux {:.4}, rows as parallel cells {:.4}, \
         columns without cross-flow {:.4}; max|Us| = {:.2e} m/s",
        RHO * reference.uniform_flux,
        RHO * reference.lower,
        RHO * reference.upper,
        us.iter()
            .map(|v| v.iter().map(|x| x * x).sum::<f64>().sqrt())
            .fold(0.0, f64::max),
    );
    println!(
        "per-row uniform-flux drop (Pa): {:?}",
        bed.row_drops(U_IN, RHO)
    );

    for harmonic in [false, true] {
        let run = case.duplicate();
        let mut fluid = fv::Fluid::from_case(&run.dir).expect("native solver reads the case");
        fluid.harmonic_faces = harmonic;
        fluid.set_voidage(&eps, &eps).unwrap();
        fluid.set_exchange(&ksl, &us).unwrap();
        fluid.set_force(&f).unwrap();
        let mut history = Vec::new();
        for step in 1..=steps {
            fluid.advance(DT).unwrap();
            if step % (steps / 4).max(1) == 0 {
                let g = fluid.geometry();
                let inlet = &g.patches[g.patch_index("inlet").expect("inlet patch")];
                let pb = &fluid.p_boundary()[inlet.boundary_range(g.n_internal)];
                history.push(inlet_drop(&g.sf[inlet.faces.clone()], pb));
            }
        }
        let dp = *history.last().unwrap();
        println!(
            "native harmonic_faces={harmonic}: Δp = {dp:.4} Pa ({:+.2} % of uniform flux), \
             history {history:.4?}",
            100.0 * (dp / (RHO * reference.uniform_flux) - 1.0)
        );
        println!(
            "  row means ρp: {:.3?}",
            bed.row_means(fluid.p())
                .iter()
                .map(|x| RHO * x)
                .collect::<Vec<_>>()
        );
    }

    if let Some(solver) = grain_piso_foam() {
        case.run(&solver);
        let (mesh, geo) = case.mesh();
        let inlet = mesh
            .boundary
            .iter()
            .find(|p| p.name == "inlet")
            .expect("inlet patch");
        let mut history = Vec::new();
        let mut last = Vec::new();
        for q in 1..=4 {
            let time = format!("{}", (end * q as f64 / 4.0 * 1e9).round() / 1e9);
            let pb = darcy::patch_values(&case.dir.join(&time).join("p"), "inlet", inlet.n_faces)
                .expect("the inlet's face pressures");
            history.push(inlet_drop(&geo.face_areas[inlet.faces()], &pb));
            last = case.scalars(&time, "p");
        }
        let dp = *history.last().unwrap();
        println!(
            "grainPisoFoam: Δp = {dp:.4} Pa ({:+.2} % of uniform flux), history {history:.4?}",
            100.0 * (dp / (RHO * reference.uniform_flux) - 1.0)
        );
        println!(
            "  row means ρp: {:.3?}",
            bed.row_means(&last)
                .iter()
                .map(|x| RHO * x)
                .collect::<Vec<_>>()
        );
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

/// ρ × the area mean of the inlet's face pressures (the outlet is at p = 0), in Pa.
fn inlet_drop(areas: &[[f64; 3]], p_inlet: &[f64]) -> f64 {
    RHO * darcy::area_mean(areas, p_inlet)
}
