//! The k–ε model with wall functions against Debian's pisoFoam v1912 (kEpsilon) on a plane
//! channel: the committed fixture `tests/fixtures/fv/channel-keps` (fast tier; its README says
//! how it was made), 100 steps of a developing turbulent channel flow at Re_τ ≈ 10³ with the
//! log-law wall functions active on both walls.
//!
//! With the same discretisation, the same linear solvers (PCG/DIC for p, PBiCGStab/DILU for U,
//! k and ε, all to 1e-12) and the same order of operations, the two solvers agree to round-off:
//! measured max |Δ|/max|·| after 100 steps U 2.9e-15, p 3.5e-13, k 1.7e-14, ε 2.4e-14,
//! νt 9.9e-15. The bound, 1e-10, leaves room for round-off growing over the steps and is far
//! below any modelling difference (e.g. leaving out the wall cells' G changes k by O(1) there).
//!
//! `Gauss linearUpwind grad(U)` is used for U rather than a TVD limiter: with
//! `limitedLinearV 1` the limiter switches on differences at round-off level in the nearly
//! uniform core, and the two solvers drift apart to 1e-7 in 20 steps (measured) though they
//! agree to 1e-16 after the first step.

mod common;

use common::compare::{rel, scalars, vectors};

#[test]
fn channel_matches_pisofoam_fixture() {
    let case = testkit::fixture("fv/channel-keps");
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&case, dir.path());
    let _ = std::fs::remove_dir_all(dir.path().join("5"));
    let mut fluid = fv::Fluid::from_case(dir.path()).unwrap();
    let steps = fluid.run().unwrap();
    assert_eq!(steps, 100);
    let n = fluid.geometry().n_cells;
    let ours = dir.path().join("5");
    let theirs = case.join("5");
    let du = rel(&vectors(&ours.join("U"), n), &vectors(&theirs.join("U"), n));
    let dp = rel(&scalars(&ours.join("p"), n), &scalars(&theirs.join("p"), n));
    let dk = rel(&scalars(&ours.join("k"), n), &scalars(&theirs.join("k"), n));
    let de = rel(
        &scalars(&ours.join("epsilon"), n),
        &scalars(&theirs.join("epsilon"), n),
    );
    let dn = rel(
        &scalars(&ours.join("nut"), n),
        &scalars(&theirs.join("nut"), n),
    );
    eprintln!("channel k-epsilon vs pisoFoam after {steps} steps: U {du:.3e}, p {dp:.3e}, k {dk:.3e}, epsilon {de:.3e}, nut {dn:.3e}");
    for (name, d) in [
        ("U", du),
        ("p", dp),
        ("k", dk),
        ("epsilon", de),
        ("nut", dn),
    ] {
        assert!(d < 1e-10, "{name}: {d}");
    }
}

/// The channel fixture's case with OpenFOAM's `CrankNicolson 0.9` for U, k and ε (each with
/// its own ddt0 field, Euler on the first step; `fv::ddt::CrankNicolsonDdt0`), and with the
/// pneumatic conveyor's combination (`CrankNicolson 0.9` for U, Euler for k and ε), natively
/// and with Debian's pisoFoam run here (full tier): round-off as with Euler, the same bound
/// 1e-10. Measured after 100 steps, the conveyor's combination: U 3.9e-15, p 8.2e-13, k 1.6e-14,
/// ε 2.2e-14, νt 9.8e-15 (the θ-scheme this replaced: U 3.6e-3, p 3.0e-2, k 1.6e-3, ε 1.5e-3,
/// νt 1.0e-3); all CrankNicolson: U 4.4e-15, p 3.1e-12, k 1.6e-14, ε 2.3e-14, νt 1.0e-14 (the
/// θ-scheme refused CrankNicolson for k and ε).
#[test]
fn channel_with_crank_nicolson_matches_pisofoam() {
    if !testkit::tool("pisoFoam") {
        return;
    }
    for ddt in [
        "default CrankNicolson 0.9; ddt(k) Euler; ddt(epsilon) Euler;",
        "default CrankNicolson 0.9;",
    ] {
        let d = channel_vs_pisofoam(ddt);
        eprintln!("channel k-epsilon, ddtSchemes {{ {ddt} }}, vs pisoFoam after 100 steps: {d:?}");
        for (name, d) in d {
            assert!(d < 1e-10, "{ddt} {name}: {d}");
        }
    }
}

/// The channel fixture with `ddtSchemes { ddt }`, natively and with pisoFoam: max|Δ|/max|·|
/// of U, p, k, ε and νt after 100 steps.
fn channel_vs_pisofoam(ddt: &str) -> Vec<(&'static str, f64)> {
    let case = testkit::fixture("fv/channel-keps");
    let root = tempfile::tempdir().unwrap();
    let (ours, theirs) = (root.path().join("fv"), root.path().join("pisoFoam"));
    testkit::copy_dir(&case, &theirs);
    let _ = std::fs::remove_dir_all(theirs.join("5"));
    let sch = theirs.join("system/fvSchemes");
    let text = std::fs::read_to_string(&sch).unwrap();
    assert!(text.contains("ddtSchemes { default Euler; }"));
    std::fs::write(
        &sch,
        text.replace(
            "ddtSchemes { default Euler; }",
            &format!("ddtSchemes {{ {ddt} }}"),
        ),
    )
    .unwrap();
    testkit::copy_dir(&theirs, &ours);
    testkit::run_ok(testkit::openfoam("pisoFoam"), &theirs);
    let mut fluid = fv::Fluid::from_case(&ours).unwrap();
    assert_eq!(fluid.run().unwrap(), 100);
    let n = fluid.geometry().n_cells;
    let (a, b) = (ours.join("5"), theirs.join("5"));
    ["U", "p", "k", "epsilon", "nut"]
        .into_iter()
        .map(|f| {
            let d = if f == "U" {
                rel(&vectors(&a.join(f), n), &vectors(&b.join(f), n))
            } else {
                rel(&scalars(&a.join(f), n), &scalars(&b.join(f), n))
            };
            (f, d)
        })
        .collect()
}

/// A closed box (slip walls, U = 0) holding uniform k0, ε0: the model reduces to
/// dk/dt = −ε, dε/dt = −C2 ε²/k, whose solution is
/// k = k0 (1 + (C2 − 1) ε0 t/k0)^(−1/(C2−1)), ε = ε0 (1 + (C2 − 1) ε0 t/k0)^(−C2/(C2−1))
/// (decay of homogeneous isotropic turbulence; e.g. Pope, Turbulent Flows, 2000, §10.4.1).
/// Returns the largest relative errors of k and ε over the run (`steps` steps to t = 2 k0/ε0)
/// against the closed form. Along the way every step is checked against the recurrence of
/// OpenFOAM's linearisation (ε solved first with the sink C2 ε/k of the old values, then k with
/// the sink ε_new/k_old, both implicit Euler):
/// ε' = ε/(1 + Δt C2 ε/k), k' = k/(1 + Δt ε'/k), to 1e-12.
fn decay_errors(steps: usize) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let xs: Vec<f64> = (0..=3).map(|i| i as f64 / 3.0).collect();
    let mesh = mesh::build::hex_grid(&xs, &xs, &xs);
    let slip = "type slip;";
    let zg = "type zeroGradient;";
    let names = ["xMin", "xMax", "yMin", "yMax", "zMin", "zMax"];
    let patches: Vec<common::PatchSpec<'_>> = names
        .iter()
        .map(|&name| common::PatchSpec {
            name,
            patch_type: "patch",
            u: slip,
            p: zg,
        })
        .collect();
    let (k0, eps0) = (1e-2, 1e-3);
    let end = 2.0 * k0 / eps0;
    let dt = end / steps as f64;
    let spec = common::CaseSpec {
        nu: 1e-5,
        rho: 1.0,
        delta_t: dt,
        end_time: end,
        ddt: "Euler",
        div: "Gauss linear",
        n_correctors: 2,
        u_internal: [0.0; 3],
    };
    common::write_case(dir.path(), mesh, &patches, &spec);
    let d = dir.path();
    let header = |class: &str, object: &str| {
        format!("FoamFile {{ version 2.0; format ascii; class {class}; object {object}; }}\n")
    };
    std::fs::write(
        d.join("constant/turbulenceProperties"),
        header("dictionary", "turbulenceProperties")
            + "simulationType RAS;\nRAS { RASModel kEpsilon; turbulence on; printCoeffs on; }\n",
    )
    .unwrap();
    for (name, dims, value) in [
        ("k", "[0 2 -2 0 0 0 0]", k0),
        ("epsilon", "[0 2 -3 0 0 0 0]", eps0),
        ("nut", "[0 2 -1 0 0 0 0]", 0.0),
    ] {
        std::fs::write(
            d.join("0").join(name),
            header("volScalarField", name)
                + &format!(
                    "dimensions {dims};\ninternalField uniform {value};\nboundaryField {{ \".*\" {{ type zeroGradient; }} }}\n"
                ),
        )
        .unwrap();
    }
    let sch = d.join("system/fvSchemes");
    let text = std::fs::read_to_string(&sch).unwrap().replace(
        "div(phi,U) Gauss linear;",
        "div(phi,U) Gauss linear; div(phi,k) bounded Gauss upwind; div(phi,epsilon) bounded Gauss upwind; div((nuEff*dev2(T(grad(U))))) Gauss linear;",
    );
    std::fs::write(&sch, text).unwrap();
    let sol = d.join("system/fvSolution");
    let text = std::fs::read_to_string(&sol).unwrap().replace(
        "solvers\n{\n",
        "solvers\n{\n    \"(k|epsilon)\" { solver PBiCGStab; preconditioner DILU; tolerance 1e-14; relTol 0; }\n",
    );
    std::fs::write(&sol, text).unwrap();

    let mut fluid = fv::Fluid::from_case(d).unwrap();
    let c2: f64 = 1.92;
    let (mut ek, mut ee) = (0.0f64, 0.0f64);
    let (mut k_rec, mut eps_rec) = (k0, eps0);
    for _ in 0..steps {
        fluid.advance(dt).unwrap();
        eps_rec /= 1.0 + dt * c2 * eps_rec / k_rec;
        k_rec /= 1.0 + dt * eps_rec / k_rec;
        let s = 1.0 + (c2 - 1.0) * eps0 * fluid.time() / k0;
        let k = k0 * s.powf(-1.0 / (c2 - 1.0));
        let eps = eps0 * s.powf(-c2 / (c2 - 1.0));
        let t = fluid.turbulence().unwrap();
        for (&kc, &ec) in t.k().iter().zip(t.epsilon()) {
            assert!(
                (kc / k_rec - 1.0).abs() < 1e-12,
                "k {kc} recurrence {k_rec}"
            );
            assert!(
                (ec / eps_rec - 1.0).abs() < 1e-12,
                "ε {ec} recurrence {eps_rec}"
            );
            ek = ek.max((kc / k - 1.0).abs());
            ee = ee.max((ec / eps - 1.0).abs());
        }
        // νt = Cμ k²/ε of the cells.
        for ((&n, &kc), &ec) in t.nut().iter().zip(t.k()).zip(t.epsilon()) {
            assert!((n / (0.09 * kc * kc / ec) - 1.0).abs() < 1e-14);
        }
    }
    (ek, ee)
}

/// Fast tier: the implicit Euler decay converges to the closed form at first order in Δt.
/// Measured (20, 40, 80 steps to t = 2 k0/ε0): max relative error of k 0.153, 0.081, 0.042
/// and of ε 0.115, 0.061, 0.032 (observed order 0.92–0.96, tending to 1).
#[test]
fn homogeneous_decay_converges_to_the_closed_form() {
    let e: Vec<(f64, f64)> = [20, 40, 80].iter().map(|&n| decay_errors(n)).collect();
    let order_k = [(e[0].0 / e[1].0).log2(), (e[1].0 / e[2].0).log2()];
    let order_e = [(e[0].1 / e[1].1).log2(), (e[1].1 / e[2].1).log2()];
    eprintln!("decay: errors (k, ε) {e:?}; order k {order_k:.3?}, ε {order_e:.3?}");
    assert!(e[2].0 < 0.045 && e[2].1 < 0.035, "{e:?}");
    for p in order_k.iter().chain(&order_e) {
        assert!((0.88..1.1).contains(p), "order {p}");
    }
}

/// What the native k–ε does not support is refused naming the file and key: each case edits
/// one entry of a copy of the channel fixture.
#[test]
fn unsupported_turbulence_settings_are_refused_naming_file_and_key() {
    let edits: &[(&str, &str, &str, &str)] = &[
        (
            "constant/turbulenceProperties",
            "RASModel kEpsilon;",
            "RASModel kOmegaSST;",
            "RAS.RASModel",
        ),
        (
            "constant/turbulenceProperties",
            "simulationType RAS;",
            "simulationType LES;",
            "simulationType",
        ),
        (
            "system/fvSchemes",
            "div(phi,k) bounded Gauss upwind;",
            "div(phi,k) bounded Gauss linearUpwind grad(k);",
            "divSchemes.div(phi,k)",
        ),
        (
            "system/fvSchemes",
            "ddtSchemes { default Euler; }",
            "ddtSchemes { default Euler; ddt(epsilon) backward; }",
            "ddtSchemes.ddt(epsilon)",
        ),
        (
            "system/fvSolution",
            "PISO {",
            "relaxationFactors { equations { k 0.7; } }\nPISO {",
            "relaxationFactors.equations.k",
        ),
        (
            "0/epsilon",
            "type epsilonWallFunction;",
            "type omegaWallFunction;",
            "boundaryField.walls.type",
        ),
        (
            "0/nut",
            "type nutkWallFunction;",
            "type nutUSpaldingWallFunction;",
            "boundaryField.walls.type",
        ),
        (
            "0/nut",
            "walls { type nutkWallFunction;",
            "walls { type zeroGradient;",
            "boundaryField.walls.type",
        ),
        (
            "0/k",
            "inlet { type fixedValue; value uniform 0.00375; }",
            "inlet { type kqRWallFunction; value uniform 0.00375; }",
            "boundaryField.inlet.type",
        ),
    ];
    for &(file, from, to, key) in edits {
        let dir = tempfile::tempdir().unwrap();
        testkit::copy_dir(&testkit::fixture("fv/channel-keps"), dir.path());
        let path = dir.path().join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(from), "{file}: `{from}` not found");
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        let Err(e) = fv::Fluid::from_case(dir.path()) else {
            panic!("{file}: `{to}` was accepted");
        };
        eprintln!("{e}");
        match &e {
            fv::FvError::Setting {
                file: f, key: k, ..
            } => {
                assert!(k == key, "{file}: key `{k}`, expected `{key}` ({e})");
                assert!(f.ends_with(file), "{e}");
            }
            other => panic!("{file}: {other}"),
        }
    }
}

/// The particles' viscous force (`Fluid::div_tau`, handed to the coupler) takes the molecular
/// ν, not ν + νt, also with k–ε on: CFDEM's `viscForce` forms ∇·τ from `turbulence.nu()`
/// (`forceSubModel::divTauField`), and grainPisoFoam sends ∇·(ν(∇U + ∇Uᵀ)) with the
/// `transportProperties` ν (`mpiCouplingSource.H`). Reference: the same divergence with a unit
/// viscosity, scaled by ν — to 1e-12 of the field's largest value — while νt exceeds ν
/// many times over in the channel after 10 steps (so ν + νt would miss it by that factor).
#[test]
fn particle_viscous_stress_takes_the_molecular_viscosity() {
    let case = testkit::fixture("fv/channel-keps");
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&case, dir.path());
    let mut fluid = fv::Fluid::from_case(dir.path()).unwrap();
    for _ in 0..10 {
        fluid.advance(fluid.settings.delta_t).unwrap();
    }
    let nu = fluid.settings.nu;
    let g = fluid.geometry();
    let (nu_eff, _) = fluid.nu_eff();
    let largest_nut = nu_eff.iter().fold(0.0f64, |m, &v| m.max(v)) - nu;
    assert!(largest_nut > 10.0 * nu, "νt {largest_nut} vs ν {nu}");
    let ones = (vec![1.0; g.n_cells], vec![1.0; g.n_boundary()]);
    let unit = fv::fvc::div_viscous_stress(
        g,
        fv::fvc::Field::new(&ones.0, &ones.1),
        fv::fvc::Field::new(fluid.u(), fluid.u_boundary()),
    );
    let div_tau = fluid.div_tau();
    let scale = div_tau.iter().map(|v| v.norm()).fold(0.0f64, f64::max);
    assert!(scale > 0.0);
    let worst = div_tau
        .iter()
        .zip(&unit)
        .map(|(d, u)| (d - nu * u).norm())
        .fold(0.0f64, f64::max);
    assert!(worst <= 1e-12 * scale, "{worst} of {scale}");
}

/// The channel fixture turned into a square-ish duct (x ∈ [0, 10] streamwise, y ∈ [0, 2],
/// z ∈ [0, 1]) with one `wall` patch on all four sides, graded differently in y and z so that
/// the corner cells lie nearer one wall than the other; `steps` steps of Δt 0.05 s.
fn write_duct(dir: &std::path::Path, steps: usize) {
    testkit::copy_dir(&testkit::fixture("fv/channel-keps"), dir);
    for d in ["5", "constant/polyMesh"] {
        std::fs::remove_dir_all(dir.join(d)).unwrap();
    }
    std::fs::write(
        dir.join("system/blockMeshDict"),
        "FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }
scale 1;
vertices
(
    (0 0 0) (10 0 0) (10 2 0) (0 2 0)
    (0 0 1) (10 0 1) (10 2 1) (0 2 1)
);
blocks
(
    hex (0 1 2 3 4 5 6 7) (12 10 8) simpleGrading
        (1 ((0.5 0.5 3) (0.5 0.5 0.333333333333)) ((0.5 0.5 5) (0.5 0.5 0.2)))
);
boundary
(
    inlet { type patch; faces ((0 4 7 3)); }
    outlet { type patch; faces ((1 2 6 5)); }
    walls { type wall; faces ((0 1 5 4) (3 7 6 2) (0 3 2 1) (4 5 6 7)); }
);
",
    )
    .unwrap();
    for name in ["U", "p", "k", "epsilon", "nut"] {
        let path = dir.join("0").join(name);
        let text = std::fs::read_to_string(&path).unwrap();
        let kept: String = text
            .lines()
            .filter(|l| !l.contains("frontAndBack"))
            .map(|l| format!("{l}\n"))
            .collect();
        std::fs::write(&path, kept).unwrap();
    }
    let cd = dir.join("system/controlDict");
    let end = 0.05 * steps as f64;
    let text = std::fs::read_to_string(&cd)
        .unwrap()
        .replace("endTime 5;", &format!("endTime {end};"))
        .replace("writeInterval 100;", &format!("writeInterval {steps};"));
    std::fs::write(&cd, text).unwrap();
}

/// Full tier: a duct with walls on four sides (one `wall` patch) against a fresh pisoFoam
/// (kEpsilon) run, 10 steps. Its corner cells touch two faces of the wall patch, where
/// OpenFOAM's wall distance (`nearWallDist`: the nearest face of the patch around the wall
/// face) is the distance to the nearer wall, not the face's own normal distance; with it the
/// wall functions' ε, G and νt of those cells are OpenFOAM's. Measured max |Δ|/max|·| over all
/// cells (and over the 4 × 12 corner cells) after 10 steps, with each face's normal distance
/// as y (before): U 5.6e-3 (5.7e-3), k 8.1e-2 (1.0e-1), ε 1.4e-1 (1.9e-1), νt 7.8e-2
/// (4.8e-1), p 1.8e-2; with `nearWallDist`: U 2.0e-15 (1.5e-15), k 3.8e-15 (2.3e-15),
/// ε 1.4e-14 (6.4e-15), νt 4.8e-15 (1.1e-14), p 1.3e-13. The bound, 1e-10, is the channel
/// fixture's.
#[test]
fn duct_corner_cells_match_a_fresh_pisofoam_run() {
    if !testkit::tool("pisoFoam") || !testkit::tool("blockMesh") {
        return;
    }
    let steps = 10;
    let root = tempfile::tempdir().unwrap();
    let (theirs, ours) = (root.path().join("pisoFoam"), root.path().join("fv"));
    write_duct(&theirs, steps);
    testkit::run_ok(testkit::openfoam("blockMesh"), &theirs);
    testkit::copy_dir(&theirs, &ours);
    testkit::run_ok(testkit::openfoam("pisoFoam"), &theirs);
    let mut fluid = fv::Fluid::from_case(&ours).unwrap();
    assert_eq!(fluid.run().unwrap(), steps);
    let g = fluid.geometry();
    let n = g.n_cells;
    // Cells with two or more wall faces: the corners of the duct's cross-section.
    let mut wall_faces = vec![0usize; n];
    for p in g.patches.iter().filter(|p| p.patch_type == "wall") {
        for f in p.faces.clone() {
            wall_faces[g.owner[f] as usize] += 1;
        }
    }
    let corners: Vec<usize> = (0..n).filter(|&c| wall_faces[c] >= 2).collect();
    assert_eq!(corners.len(), 4 * 12);
    let time = format!("{}", 0.05 * steps as f64);
    let (a, b) = (ours.join(&time), theirs.join(&time));
    let mut worst = 0.0f64;
    for name in ["U", "k", "epsilon", "nut", "p"] {
        let (x, y) = if name == "U" {
            (vectors(&a.join(name), n), vectors(&b.join(name), n))
        } else {
            (scalars(&a.join(name), n), scalars(&b.join(name), n))
        };
        let width = x.len() / n;
        let pick = |v: &[f64]| -> Vec<f64> {
            corners
                .iter()
                .flat_map(|&c| v[c * width..(c + 1) * width].to_vec())
                .collect()
        };
        let all = rel(&x, &y);
        let corner = rel(&pick(&x), &pick(&y));
        eprintln!("duct k-epsilon vs pisoFoam after {steps} steps: {name} {all:.3e} (corner cells {corner:.3e})");
        assert!(
            all < 1e-10 && corner < 1e-10,
            "{name}: {all:e}, corners {corner:e}"
        );
        worst = worst.max(all);
    }
    eprintln!("largest difference {worst:.3e}");
}
