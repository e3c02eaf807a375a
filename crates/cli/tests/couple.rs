//! `foamgrain couple` and `foamgrain timestep` end to end.
//! * couple: the committed LIGGGHTS dump `settle.txt` (2 snapshots, 200 spheres) on a grid
//!   around its box with a uniform frozen U: the written Ksl/Us/f/voidfraction per dump time
//!   integrate to the summed particle quantities of the written `particleForces` dump (to
//!   round-off), and the reported momentum balances;
//! * timestep: the Ergun reference case against hand-computed Rayleigh and Stokes times.

use approx::assert_abs_diff_eq;
use dem_io::{read_snapshot, ReadOptions, Selection};
use foam::{default_boundary, FieldValues, Format, VolField};
use mesh::build::uniform_box;
use mesh::MeshGeometry;
use std::f64::consts::PI;
use std::path::Path;
use std::process::{Command, Output};
use testkit::fixture;

fn foamgrain(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foamgrain"))
        .args(args)
        .output()
        .unwrap()
}

const COUPLING: &str = r#"FoamFile { version 2.0; format ascii; class dictionary; object couplingProperties; }
modelType "B";
couplingInterval 3000;
voidFractionModel exact;
locateModel engine;
forceModels ( DiFeliceDrag Archimedes );
momCoupleModels ( implicitCouple );
DiFeliceDragProps { interpolation true; implForceDEM true; }
"#;

fn make_case(dir: &Path, u: [f64; 3]) -> foam::PolyMesh {
    let mesh = uniform_box([-0.012, -0.012, 0.0], [0.012, 0.012, 0.03], [6, 6, 8]);
    foam::write_poly_mesh(&dir.join("constant/polyMesh"), &mesh, Format::Ascii).unwrap();
    std::fs::write(dir.join("constant/couplingProperties"), COUPLING).unwrap();
    std::fs::write(
        dir.join("constant/transportProperties"),
        "FoamFile { version 2.0; format ascii; class dictionary; object transportProperties; }\n\
         nu 1e-5;\nrho 10;\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("constant/g"),
        "FoamFile { version 2.0; format ascii; class uniformDimensionedVectorField; object g; }\n\
         dimensions [0 1 -2 0 0 0 0];\nvalue (0 0 -9.81);\n",
    )
    .unwrap();
    std::fs::create_dir_all(dir.join("0")).unwrap();
    let n = mesh.n_cells;
    let b = default_boundary(&mesh.boundary, "zeroGradient", None);
    VolField::new(
        "U",
        "0",
        [0, 1, -1, 0, 0, 0, 0],
        FieldValues::Vector(vec![u; n]),
        b.clone(),
    )
    .write(&dir.join("0/U"), Format::Ascii)
    .unwrap();
    VolField::new(
        "p",
        "0",
        [0, 2, -2, 0, 0, 0, 0],
        FieldValues::Scalar(vec![0.0; n]),
        b,
    )
    .write(&dir.join("0/p"), Format::Ascii)
    .unwrap();
    mesh
}

fn scalar(path: &Path, n: usize) -> Vec<f64> {
    match VolField::read(path).unwrap().internal(n).unwrap() {
        FieldValues::Scalar(v) => v,
        _ => panic!("{}", path.display()),
    }
}

fn vector(path: &Path, n: usize) -> Vec<[f64; 3]> {
    match VolField::read(path).unwrap().internal(n).unwrap() {
        FieldValues::Vector(v) => v,
        _ => panic!("{}", path.display()),
    }
}

#[test]
fn couple_replays_settle_dump() {
    let dir = tempfile::tempdir().unwrap();
    let u = [0.0, 0.0, 0.05];
    let mesh = make_case(dir.path(), u);
    let dumps = dir.path().join("dump*.txt");
    std::fs::copy(fixture("liggghts/settle.txt"), dir.path().join("dump1.txt")).unwrap();
    let o = foamgrain(&[
        "couple",
        "--case",
        dir.path().to_str().unwrap(),
        "--dumps",
        dumps.to_str().unwrap(),
        "--dem-dt",
        "1e-5",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2, "{out}");
    let vols = MeshGeometry::new(&mesh).unwrap().cell_volumes;
    let n = mesh.n_cells;
    for (line, (time, step)) in lines.iter().zip([("0.03", 3000u64), ("0.06", 6000)]) {
        let r: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(r["time"], time);
        assert_eq!(r["timestep"], step);
        let t = dir.path().join(time);
        let eps = scalar(&t.join("voidfraction"), n);
        let ksl = scalar(&t.join("Ksl"), n);
        let us = vector(&t.join("Us"), n);
        let f = vector(&t.join("f"), n);
        assert!(f.iter().all(|x| *x == [0.0; 3]));
        // The particles, independently from the input dump, and their forces as written.
        let snap = read_snapshot(
            fixture("liggghts/settle.txt"),
            &ReadOptions::default(),
            Selection::Timestep(step),
        )
        .unwrap();
        let p = snap.particles().unwrap();
        let forces = read_snapshot(
            t.join("particleForces"),
            &ReadOptions::default(),
            Selection::Last,
        )
        .unwrap();
        assert_eq!(forces.require("id").unwrap().len(), 200);
        let beta = forces.require("beta").unwrap();
        let solid: f64 = p.radius.iter().map(|r| 4.0 / 3.0 * PI * r * r * r).sum();
        let deposited: f64 = eps.iter().zip(&vols).map(|(e, v)| (1.0 - e) * v).sum();
        let outside = r["outside_volume"].as_f64().unwrap();
        assert!((deposited + outside - solid).abs() < 1e-12 * solid);
        let sum_beta: f64 = beta.iter().sum();
        let int_ksl: f64 = ksl.iter().zip(&vols).map(|(k, v)| k * v).sum();
        assert!(
            approx::abs_diff_eq!(int_ksl, sum_beta, epsilon = 1e-12 * sum_beta),
            "{int_ksl} vs {sum_beta}"
        );
        for a in 0..3 {
            let bv: f64 = beta.iter().zip(&p.velocity).map(|(b, v)| b * v[a]).sum();
            let cells: f64 = (0..n).map(|c| ksl[c] * vols[c] * us[c][a]).sum();
            assert!(
                approx::abs_diff_eq!(cells, bv, epsilon = 1e-12 * sum_beta),
                "Σ Ksl Us V vs Σ β v"
            );
            let pm = r["particle_momentum"][a].as_f64().unwrap();
            let cm = r["cell_momentum"][a].as_f64().unwrap();
            assert_abs_diff_eq!(pm, cm, epsilon = 1e-12 * sum_beta * 0.1);
        }
        // The total fluid force on the particles: drag β (U − v) in the uniform flow plus
        // Archimedes' ρ V g upwards (model B, no other force).
        let buoyancy = 10.0 * 9.81 * solid;
        let drag_z: f64 = beta
            .iter()
            .zip(&p.velocity)
            .map(|(b, v)| b * (u[2] - v[2]))
            .sum();
        let total_z = r["total_fluid_force"][2].as_f64().unwrap();
        assert!(
            (total_z - drag_z - buoyancy).abs() < 1e-9 * (drag_z.abs() + buoyancy),
            "{total_z} vs drag {drag_z} + buoyancy {buoyancy}"
        );
    }
}

#[test]
fn couple_errors_name_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    make_case(dir.path(), [0.0; 3]);
    let c = dir.path().to_str().unwrap();
    let o = foamgrain(&[
        "couple",
        "--case",
        c,
        "--dumps",
        "/nonexistent/dump*",
        "--dem-dt",
        "1e-5",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent"));
    std::fs::write(
        dir.path().join("constant/couplingProperties"),
        COUPLING.replace("locateModel engine;", "fancy 1;"),
    )
    .unwrap();
    let dump = fixture("liggghts/settle.txt");
    let o = foamgrain(&[
        "couple",
        "--case",
        c,
        "--dumps",
        dump.to_str().unwrap(),
        "--dem-dt",
        "1e-5",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && e.contains("fancy") && e.contains("couplingProperties"),
        "{e}"
    );
}

#[test]
fn timestep_of_the_ergun_case() {
    let case = testkit::repo_root().join("openfoam-cases/ergun/CFD");
    let o = foamgrain(&["timestep", "--case", case.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout).unwrap();
    let value = |name: &str| -> f64 {
        let line = out.lines().find(|l| l.starts_with(name)).unwrap();
        line[name.len()..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    // Rayleigh (seed 002 eq. 10): r = 0.5 mm, ρ_p = 2000, E = 5 MPa, ν = 0.45.
    let shear: f64 = 5e6 / (2.0 * 1.45);
    let rayleigh = PI * 5e-4 * (2000.0 / shear).sqrt() / (0.1631 * 0.45 + 0.8766);
    assert_abs_diff_eq!(
        value("Rayleigh time step"),
        rayleigh,
        epsilon = 1e-6 * rayleigh
    );
    // Stokes: ρ_p d²/(18 ρ ν) with ρ = 10, ν = 1.5e-4.
    let stokes = 2000.0 * 1e-6 / (18.0 * 10.0 * 1.5e-4);
    assert_abs_diff_eq!(
        value("Stokes relaxation time"),
        stokes,
        epsilon = 1e-6 * stokes
    );
    assert_abs_diff_eq!(value("coupling time"), 50.0 * 1e-5, epsilon = 1e-12);
    assert!(
        out.contains("warning: DEM step 1e-5 s resolves the Hertz contact time"),
        "{out}"
    );
}

/// The conveyor's case (material values behind `${cor}`-style variables) with a written `phi`
/// of the same flux q on every face: every cell of this all-hexahedral mesh has 6 faces, so
/// OpenFOAM's Courant number is 3 q Δt / V_c per cell — largest in the smallest cell — and its
/// mean 3 q Δt N / Σ V.
#[test]
fn timestep_reports_the_courant_number_of_a_written_phi() {
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_inputs(
        &testkit::repo_root().join("openfoam-cases/pneumatic-conveying"),
        dir.path(),
    );
    let cfd = dir.path().join("CFD");
    let q = 2e-6; // m³/s
    let patches = ["inlet", "outlet", "walls"];
    let mut phi = String::from(
        "FoamFile { version 2.0; format ascii; class surfaceScalarField; object phi; }\n\
         dimensions [0 3 -1 0 0 0 0];\ninternalField uniform 2e-06;\nboundaryField\n{\n",
    );
    let boundary = std::fs::read_to_string(cfd.join("constant/polyMesh/boundary")).unwrap();
    for p in patches {
        assert!(boundary.contains(p), "no patch {p}");
        phi.push_str(&format!(
            "    {p} {{ type calculated; value uniform 2e-06; }}\n"
        ));
    }
    phi.push_str("}\n");
    std::fs::create_dir_all(cfd.join("0.01")).unwrap();
    std::fs::write(cfd.join("0.01/phi"), phi).unwrap();
    let o = foamgrain(&["timestep", "--case", cfd.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout).unwrap();
    let line = out
        .lines()
        .find(|l| l.starts_with("fluid Courant number"))
        .unwrap();
    let w: Vec<&str> = line.split_whitespace().collect();
    let (mean, max): (f64, f64) = (w[4].parse().unwrap(), w[6].parse().unwrap());
    let m = foam::Case::open(&cfd).unwrap().read_mesh().unwrap();
    let g = MeshGeometry::new(&m).unwrap();
    let dt = 2e-5;
    let v_min = g.cell_volumes.iter().copied().fold(f64::INFINITY, f64::min);
    let v_sum: f64 = g.cell_volumes.iter().sum();
    // printed with 7 significant digits
    assert_abs_diff_eq!(max, 3.0 * q * dt / v_min, epsilon = 1e-6 * max);
    let n = g.cell_volumes.len() as f64;
    assert_abs_diff_eq!(mean, 3.0 * q * dt * n / v_sum, epsilon = 1e-6 * mean);
    assert!(line.contains("phi of time 0.01"), "{line}");
    // the deck's `coefficientRestitution … ${cor}` is read through `variable cor index 0.5`
    assert!(out.contains("Rayleigh time step"), "{out}");
    // 0/U is at rest (uniform (0 0 0)): no speed for the CFL row, which is unknown, not 0
    let cfl = out.lines().find(|l| l.starts_with("CFL")).unwrap();
    assert!(cfl.ends_with("(unknown)"), "{cfl}");
}

#[test]
fn archimedes_without_gravity_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    make_case(dir.path(), [0.0; 3]);
    std::fs::remove_file(dir.path().join("constant/g")).unwrap();
    std::fs::copy(fixture("liggghts/settle.txt"), dir.path().join("dump1.txt")).unwrap();
    let o = foamgrain(&[
        "couple",
        "--case",
        dir.path().to_str().unwrap(),
        "--dumps",
        dir.path().join("dump*.txt").to_str().unwrap(),
        "--dem-dt",
        "1e-5",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "succeeded without gravity");
    assert!(e.contains("constant/g") && e.contains("Archimedes"), "{e}");
}
