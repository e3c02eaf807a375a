//! Native fluid solver speed on the lid-driven cavity at Re 100 (the icoFoam tutorial's
//! settings: PCG/DIC 1e-6 for p with relTol 0.05 and 0 in the final corrector, smoothSolver/
//! symGaussSeidel 1e-5 for U, 2 PISO correctors) on a uniform N×N×1 mesh (N = 100: 10,000 cells,
//! Δt for a Courant number 0.5):
//!
//! * `advance`: one PISO step after 5 warm-up steps;
//! * `pcg_dic`: the pressure equation of that mesh (Laplacian, one Dirichlet wall) from a zero
//!   guess to 1e-6;
//! * `symmetric_gauss_seidel`: one momentum-like solve (diffusion + Δt term) to 1e-5.
//!
//! Run: `cargo bench -p fv`. `bench_vs_pisofoam` (an example) compares with pisoFoam itself.

use fv::ldu::Ldu;
use fv::linsolve::{self, Preconditioner, Smoother, SmootherKind, SolverControls};
use fv::FvGeometry;
use std::path::{Path, PathBuf};

const N: usize = 100;

fn main() {
    divan::main();
}

fn cavity_mesh(n: usize) -> foam::PolyMesh {
    let mut m = mesh::build::uniform_box([0.0; 3], [0.1, 0.1, 0.01], [n, n, 1]);
    for p in &mut m.boundary {
        if p.name.starts_with('z') {
            p.patch_type = "empty".into();
        }
    }
    m
}

/// The cavity case with an N×N mesh in a fresh directory (kept alive by the returned guard).
fn cavity_case(n: usize) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().to_path_buf();
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/fv/cavity-re100");
    for sub in ["system", "constant"] {
        std::fs::create_dir_all(case.join(sub)).unwrap();
    }
    for f in [
        "system/fvSchemes",
        "system/fvSolution",
        "constant/transportProperties",
    ] {
        std::fs::copy(fixture.join(f), case.join(f)).unwrap();
    }
    let dt = 0.5 * 0.1 / n as f64;
    let cd = std::fs::read_to_string(fixture.join("system/controlDict"))
        .unwrap()
        .replace("deltaT          0.005;", &format!("deltaT {dt};"));
    std::fs::write(case.join("system/controlDict"), cd).unwrap();
    std::fs::create_dir_all(case.join("constant/polyMesh")).unwrap();
    foam::write_poly_mesh(
        &case.join("constant/polyMesh"),
        &cavity_mesh(n),
        foam::Format::Binary,
    )
    .unwrap();
    std::fs::create_dir_all(case.join("0")).unwrap();
    let field = |class: &str, name: &str, dims: &str, internal: &str, walls: &str, lid: &str| {
        format!(
            "FoamFile {{ version 2.0; format ascii; class {class}; object {name}; }}\n\
             dimensions {dims};\ninternalField uniform {internal};\nboundaryField\n{{\n\
             xMin {{ {walls} }}\nxMax {{ {walls} }}\nyMin {{ {walls} }}\nyMax {{ {lid} }}\n\
             zMin {{ type empty; }}\nzMax {{ type empty; }}\n}}\n"
        )
    };
    let u = field(
        "volVectorField",
        "U",
        "[0 1 -1 0 0 0 0]",
        "(0 0 0)",
        "type noSlip;",
        "type fixedValue; value uniform (1 0 0);",
    );
    let zg = "type zeroGradient;";
    let p = field("volScalarField", "p", "[0 2 -2 0 0 0 0]", "0", zg, zg);
    std::fs::write(case.join("0/U"), u).unwrap();
    std::fs::write(case.join("0/p"), p).unwrap();
    (dir, case)
}

#[divan::bench(sample_count = 20)]
fn advance(bencher: divan::Bencher) {
    let (_guard, case) = cavity_case(N);
    let mut fluid = fv::Fluid::from_case(&case).unwrap();
    let dt = fluid.settings.delta_t;
    for _ in 0..5 {
        fluid.advance(dt).unwrap();
    }
    bencher.bench_local(|| fluid.advance(dt).unwrap());
}

/// The pressure Laplacian of the 2-D mesh with p fixed on the yMax wall, and a smooth source.
fn pressure_system() -> (FvGeometry, Ldu, Vec<f64>) {
    let g = FvGeometry::new(&cavity_mesh(N)).unwrap();
    let mut a = Ldu::zeros(&g);
    for f in 0..g.n_internal {
        let c = g.mag_sf[f] * g.delta_coeff[f];
        a.upper[f] = -c;
        a.lower[f] = -c;
        a.diag[g.owner[f] as usize] += c;
        a.diag[g.neighbour[f] as usize] += c;
    }
    let lid = g.patch_index("yMax").unwrap();
    for f in g.patches[lid].faces.clone() {
        a.diag[g.owner[f] as usize] += g.mag_sf[f] * g.delta_coeff[f];
    }
    let b = g.c.iter().map(|c| (40.0 * c[0]).sin() * g.v[0]).collect();
    (g, a, b)
}

#[divan::bench(sample_count = 20)]
fn pcg_dic(bencher: divan::Bencher) {
    let (g, a, b) = pressure_system();
    let c = SolverControls::default();
    bencher.bench_local(|| {
        let mut x = vec![0.0; g.n_cells];
        linsolve::pcg(&a, &g, &b, &mut x, Preconditioner::Dic, &c, "p").unwrap()
    });
}

#[divan::bench(sample_count = 20)]
fn symmetric_gauss_seidel(bencher: divan::Bencher) {
    let (g, mut a, b) = pressure_system();
    // A momentum-like matrix: ν times the Laplacian plus V/Δt (ν = 1e-3 m²/s, Δt = 5e-4 s).
    let (nu, dt) = (1e-3, 5e-4);
    for x in a.upper.iter_mut().chain(a.lower.iter_mut()) {
        *x *= nu;
    }
    for (d, v) in a.diag.iter_mut().zip(&g.v) {
        *d = *d * nu + v / dt;
    }
    let c = SolverControls {
        tolerance: 1e-5,
        ..SolverControls::default()
    };
    let sm = Smoother {
        kind: SmootherKind::SymGaussSeidel,
        sweeps: 1,
        hybrid: false,
    };
    bencher.bench_local(|| {
        let mut x = vec![0.0; g.n_cells];
        linsolve::smooth(&a, &g, &b, &mut x, sm, &c, "U").unwrap()
    });
}
