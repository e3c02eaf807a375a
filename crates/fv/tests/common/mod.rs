//! Writes small OpenFOAM cases for the solver tests: a generated hex mesh, `0/U`, `0/p` with
//! per-patch conditions given as dictionary text, and the system/constant dictionaries.

pub mod compare;

use foam::PolyMesh;
use std::fmt::Write;
use std::path::Path;

/// One patch: the name of a `mesh::build::hex_grid` patch (`xMin`, …), its polyMesh type and
/// the U and p boundaryField entries (the text inside the braces).
pub struct PatchSpec<'a> {
    pub name: &'a str,
    pub patch_type: &'a str,
    pub u: &'a str,
    pub p: &'a str,
}

/// Case parameters.
pub struct CaseSpec<'a> {
    pub nu: f64,
    pub rho: f64,
    pub delta_t: f64,
    pub end_time: f64,
    pub ddt: &'a str,
    pub div: &'a str,
    pub n_correctors: usize,
    pub u_internal: [f64; 3],
}

fn header(class: &str, location: &str, object: &str) -> String {
    format!(
        "FoamFile\n{{\n    version 2.0;\n    format ascii;\n    class {class};\n    location \"{location}\";\n    object {object};\n}}\n"
    )
}

/// Writes the case into `dir`.
pub fn write_case(dir: &Path, mut mesh: PolyMesh, patches: &[PatchSpec<'_>], spec: &CaseSpec<'_>) {
    for p in &mut mesh.boundary {
        let s = patches
            .iter()
            .find(|s| s.name == p.name)
            .unwrap_or_else(|| panic!("no spec for patch {}", p.name));
        p.patch_type = s.patch_type.into();
    }
    std::fs::create_dir_all(dir.join("constant/polyMesh")).unwrap();
    std::fs::create_dir_all(dir.join("system")).unwrap();
    std::fs::create_dir_all(dir.join("0")).unwrap();
    foam::write_poly_mesh(&dir.join("constant/polyMesh"), &mesh, foam::Format::Ascii).unwrap();
    let mut u = header("volVectorField", "0", "U");
    let [a, b, c] = spec.u_internal;
    write!(
        u,
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform ({a} {b} {c});\nboundaryField\n{{\n"
    )
    .unwrap();
    let mut p = header("volScalarField", "0", "p");
    p.push_str("dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\nboundaryField\n{\n");
    for s in patches {
        writeln!(u, "    {} {{ {} }}", s.name, s.u).unwrap();
        writeln!(p, "    {} {{ {} }}", s.name, s.p).unwrap();
    }
    u.push_str("}\n");
    p.push_str("}\n");
    std::fs::write(dir.join("0/U"), u).unwrap();
    std::fs::write(dir.join("0/p"), p).unwrap();
    let tp = format!(
        "{}transportModel Newtonian;\nnu {};\nrho {};\n",
        header("dictionary", "constant", "transportProperties"),
        spec.nu,
        spec.rho
    );
    std::fs::write(dir.join("constant/transportProperties"), tp).unwrap();
    let cd = format!(
        "{}application foamgrain;\nstartFrom startTime;\nstartTime 0;\nstopAt endTime;\nendTime {};\ndeltaT {};\nwriteControl timeStep;\nwriteInterval 100000;\nwriteFormat ascii;\n",
        header("dictionary", "system", "controlDict"),
        spec.end_time,
        spec.delta_t
    );
    std::fs::write(dir.join("system/controlDict"), cd).unwrap();
    let sch = format!(
        "{}ddtSchemes {{ default {}; }}\ngradSchemes {{ default Gauss linear; }}\ndivSchemes {{ default none; div(phi,U) {}; }}\nlaplacianSchemes {{ default Gauss linear corrected; }}\ninterpolationSchemes {{ default linear; }}\nsnGradSchemes {{ default corrected; }}\n",
        header("dictionary", "system", "fvSchemes"),
        spec.ddt,
        spec.div
    );
    std::fs::write(dir.join("system/fvSchemes"), sch).unwrap();
    let sol = format!(
        "{}solvers\n{{\n    p {{ solver PCG; preconditioner DIC; tolerance 1e-12; relTol 0; }}\n    U {{ solver PBiCGStab; preconditioner DILU; tolerance 1e-12; relTol 0; }}\n}}\nPISO {{ nCorrectors {}; nNonOrthogonalCorrectors 0; pRefCell 0; pRefValue 0; }}\n",
        header("dictionary", "system", "fvSolution"),
        spec.n_correctors
    );
    std::fs::write(dir.join("system/fvSolution"), sol).unwrap();
}
