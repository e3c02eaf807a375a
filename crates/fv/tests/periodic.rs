//! Periodic flows: translational `cyclic` patches and the `fvOptions` mean-velocity sources
//! against closed forms (fast tier).
//!
//! A plane channel between two walls a height h apart, periodic in the flow direction, driven
//! by `meanVelocityForce` holding the mean velocity Ū. The steady continuum solution is plane
//! Poiseuille flow, u(y) = G/(2ν) y (h − y) with the pressure-gradient equivalent
//! G = 12 ν Ū / h² (e.g. White, Viscous Fluid Flow, 3rd ed., §3-3.2).
//!
//! The finite-volume solution on N equal cells across the channel is known in closed form too:
//! the three-point Laplacian is exact for a parabola inside, and the wall cells, whose wall
//! gradient is u_1/(Δy/2), shift the whole profile by a constant,
//! u_j = G/(2ν) (y_j (h − y_j) + Δy²/4) (substitute into the wall-cell balance
//! ν((u_2 − u_1)/Δy − 2u_1/Δy)/Δy = −G); its cell average is G/(2ν) (h²/6 + Δy²/3) (the
//! midpoint rule of ∫y² is short by Δy²/12), so the source that holds Ū is
//! G_N = 12 ν Ū / (h² + 2Δy²). The tests check G_N and u_j to the
//! solver tolerance, and G_N → 12νŪ/h² as the relative error 2(Δy/h)² says.

mod common;

use common::compare::{rel, scalars, vectors};
use fv::{Fluid, V3};
use std::path::Path;

/// Writes a periodic channel (length 0.2 m in x, `ny` cells across h = 0.1 m in y, one cell
/// in z, ν = 0.01 m²/s) with `fv_options` as `system/fvOptions`.
fn channel(dir: &Path, ny: usize, fv_options: &str, voidage: Option<f64>) {
    let xs: Vec<f64> = (0..=4).map(|i| 0.05 * i as f64).collect();
    let ys: Vec<f64> = (0..=ny).map(|j| 0.1 * j as f64 / ny as f64).collect();
    let mut mesh = mesh::build::hex_grid(&xs, &ys, &[0.0, 0.01]);
    for p in &mut mesh.boundary {
        let nbr = match p.name.as_str() {
            "xMin" => "xMax",
            "xMax" => "xMin",
            _ => continue,
        };
        p.extra.push(("neighbourPatch".into(), nbr.into()));
    }
    let cyc = "type cyclic;";
    let wall_u = "type noSlip;";
    let zg = "type zeroGradient;";
    let empty = "type empty;";
    let patches = [
        common::PatchSpec {
            name: "xMin",
            patch_type: "cyclic",
            u: cyc,
            p: cyc,
        },
        common::PatchSpec {
            name: "xMax",
            patch_type: "cyclic",
            u: cyc,
            p: cyc,
        },
        common::PatchSpec {
            name: "yMin",
            patch_type: "wall",
            u: wall_u,
            p: zg,
        },
        common::PatchSpec {
            name: "yMax",
            patch_type: "wall",
            u: wall_u,
            p: zg,
        },
        common::PatchSpec {
            name: "zMin",
            patch_type: "empty",
            u: empty,
            p: empty,
        },
        common::PatchSpec {
            name: "zMax",
            patch_type: "empty",
            u: empty,
            p: empty,
        },
    ];
    let spec = common::CaseSpec {
        nu: 0.01,
        rho: 1.0,
        delta_t: DT,
        end_time: 10.0,
        ddt: "Euler",
        div: "Gauss linear",
        n_correctors: 2,
        u_internal: [0.0; 3],
    };
    common::write_case(dir, mesh, &patches, &spec);
    let head = "FoamFile { version 2.0; format ascii; class dictionary; object fvOptions; }\n";
    std::fs::write(dir.join("system/fvOptions"), format!("{head}{fv_options}")).unwrap();
    if let Some(eps) = voidage {
        let field = format!(
            "FoamFile {{ version 2.0; format ascii; class volScalarField; object voidfraction; }}\n\
             dimensions [0 0 0 0 0 0 0];\ninternalField uniform {eps};\nboundaryField\n{{\n\
             xMin {{ type cyclic; }}\n xMax {{ type cyclic; }}\n yMin {{ type zeroGradient; }}\n\
             yMax {{ type zeroGradient; }}\n zMin {{ type empty; }}\n zMax {{ type empty; }}\n}}\n"
        );
        std::fs::write(dir.join("0/voidfraction"), field).unwrap();
    }
}

/// The time step (s) on 16 cells across: diffusion number νΔt/Δy² = 2.56. At 10 and above
/// the two-corrector PISO step with `meanVelocityForce` grows a transverse mode within a few
/// dozen steps, in Debian's pisoFoam as here (measured on 4×32 cells at Δt 0.01 s), so the
/// step scales with Δy².
const DT: f64 = 0.01;

/// The time step on `ny` cells across (the diffusion number of [`DT`] on 16).
fn dt_for(ny: usize) -> f64 {
    DT * (16.0 / ny as f64).powi(2)
}

const MEAN_FORCE: &str = "momentumSource\n{\n    type meanVelocityForce;\n    \
     meanVelocityForceCoeffs\n    {\n        selectionMode all;\n        fields (U);\n        \
     Ubar (0.1 0 0);\n    }\n}\n";

/// Runs to t = 3.5 s (35 e-folding times h²/(π²ν) of the slowest viscous mode) in steps of
/// `dt` and returns the fluid.
fn run(dir: &Path, dt: f64, voidage: Option<f64>) -> Fluid {
    let mut fluid = Fluid::from_case(dir).unwrap();
    if let Some(eps) = voidage {
        let e = vec![eps; fluid.geometry().n_cells];
        fluid.set_voidage(&e, &e).unwrap();
    }
    let steps = (3.5 / dt).round() as usize;
    for _ in 0..steps {
        fluid.advance(dt).unwrap();
    }
    fluid
}

#[test]
fn periodic_poiseuille_holds_the_mean_velocity_with_the_closed_form_force() {
    let (nu, ubar, h) = (0.01, 0.1, 0.1);
    let continuum = 12.0 * nu * ubar / (h * h);
    for ny in [8usize, 16, 32] {
        let dir = tempfile::tempdir().unwrap();
        channel(dir.path(), ny, MEAN_FORCE, None);
        let fluid = run(dir.path(), dt_for(ny), None);
        let dy = h / ny as f64;
        let discrete = 12.0 * nu * ubar / (h * h + 2.0 * dy * dy);
        let g_force = fluid.mean_forces()[0].gradient();
        let g = fluid.geometry();
        // The profile: the same in every column, the closed form of the module doc.
        let mut worst = 0.0f64;
        for c in 0..g.n_cells {
            let y = g.c[c][1];
            let exact = discrete / (2.0 * nu) * (y * (h - y) + dy * dy / 4.0);
            worst = worst.max((fluid.u()[c][0] - exact).abs() / ubar);
            assert!(
                fluid.u()[c][1].abs() < 1e-10 * ubar,
                "v = {}",
                fluid.u()[c][1]
            );
        }
        let mean: f64 = fluid.u().iter().map(|u| u[0]).sum::<f64>() / g.n_cells as f64;
        eprintln!(
            "ny {ny}: G {g_force:.12e}, discrete closed form {discrete:.12e} (rel {:.2e}), \
             continuum {continuum:.6e} (rel {:.3e}, bound 2(dy/h)^2 = {:.3e}), profile {worst:.2e}, \
             mean {mean:.15}",
            (g_force - discrete).abs() / discrete,
            (g_force - continuum).abs() / continuum,
            2.0 * (dy / h).powi(2),
        );
        assert!(
            (g_force - discrete).abs() < 1e-8 * discrete,
            "{g_force} vs {discrete}"
        );
        assert!(worst < 1e-8, "profile {worst}");
        assert!((mean - ubar).abs() < 1e-10 * ubar, "mean {mean}");
        let rel = (continuum - g_force) / continuum;
        let bound = 2.0 * (dy / h).powi(2);
        assert!(rel > 0.0 && rel <= bound, "{rel} vs {bound}");
    }
}

/// CFDEM's `meanSupVelocityForce` with `coupled true` holds the superficial velocity ⟨εU⟩ and
/// drives with ε G: in a uniform voidage ε (no drag) the VANS momentum balance is
/// ε ν ∇²U = −ε G, the interstitial profile is Poiseuille's with mean Ū/ε, so the force is
/// G_N (Ū/ε) (the discrete closed form above at the interstitial mean).
#[test]
fn mean_superficial_velocity_force_holds_eps_u_in_a_uniform_voidage() {
    let (nu, ubar, h, eps, ny) = (0.01, 0.1, 0.1, 0.6, 16usize);
    let sup = "momentumSource\n{\n    type meanSupVelocityForce;\n    active yes;\n    \
               meanSupVelocityForceCoeffs\n    {\n        selectionMode all;\n        \
               fields (U);\n        Ubar (0.1 0 0);\n        relaxation 0.9;\n        \
               twoPhase false;\n        coupled true;\n        \
               voidfractionField \"voidfraction\";\n    }\n}\n";
    let dir = tempfile::tempdir().unwrap();
    channel(dir.path(), ny, sup, Some(eps));
    let fluid = run(dir.path(), dt_for(ny), Some(eps));
    let dy = h / ny as f64;
    let expected = 12.0 * nu * (ubar / eps) / (h * h + 2.0 * dy * dy);
    let g_force = fluid.mean_forces()[0].gradient();
    let sup_mean: f64 =
        fluid.u().iter().map(|u| eps * u[0]).sum::<f64>() / fluid.geometry().n_cells as f64;
    eprintln!("meanSupVelocityForce: G {g_force:.12e} vs {expected:.12e}, <eps U> {sup_mean:.15}");
    assert!(
        (g_force - expected).abs() < 1e-8 * expected,
        "{g_force} vs {expected}"
    );
    assert!((sup_mean - ubar).abs() < 1e-10 * ubar, "{sup_mean}");
    // The force and the mean are written at the end and read back by a continued run.
    fluid.write("20").unwrap();
    let props = fv::fv_options::props_path(&dir.path().join("20"), "momentumSource");
    let text = std::fs::read_to_string(&props).unwrap();
    assert!(text.contains("gradient"), "{text}");
    let _ = V3::zeros();
}

/// Other sources, selections and two-phase averaging are refused naming the file and entry.
#[test]
fn unsupported_fv_options_are_refused_naming_the_entry() {
    let cases = [
        (
            "type semiImplicitSource;",
            "momentumSource.type",
            "semiImplicitSource",
        ),
        (
            "selectionMode all;",
            "momentumSource.meanVelocityForceCoeffs.selectionMode",
            "cellZone",
        ),
    ];
    for (from, key, word) in cases {
        let dir = tempfile::tempdir().unwrap();
        let edited = match word {
            "semiImplicitSource" => MEAN_FORCE.replace("type meanVelocityForce;", from),
            _ => MEAN_FORCE.replace(from, "selectionMode cellZone; cellZone c;"),
        };
        channel(dir.path(), 8, &edited, None);
        match Fluid::from_case(dir.path()) {
            Err(fv::FvError::Setting { file, key: k, msg }) => {
                assert!(file.ends_with("system/fvOptions"), "{}", file.display());
                assert_eq!(k, key);
                assert!(msg.contains(word), "{msg}");
            }
            Err(e) => panic!("{e}"),
            Ok(_) => panic!("accepted {word}"),
        }
    }
}

/// A rotational cyclic or a cyclicAMI is refused naming the boundary file and the patch.
#[test]
fn rotational_and_ami_cyclics_are_refused_naming_the_patch() {
    for (edit, key) in [
        ("transform rotational;", "xMin.transform"),
        ("AMI", "xMin.type"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        channel(dir.path(), 8, MEAN_FORCE, None);
        let path = dir.path().join("constant/polyMesh/boundary");
        let text = std::fs::read_to_string(&path).unwrap();
        let text = if edit == "AMI" {
            text.replace("cyclic;", "cyclicAMI;")
        } else {
            text.replacen(
                "neighbourPatch",
                &format!("{edit}\n        neighbourPatch"),
                1,
            )
        };
        std::fs::write(&path, text).unwrap();
        match Fluid::from_case(dir.path()) {
            Err(fv::FvError::Setting { file, key: k, .. }) => {
                assert!(
                    file.ends_with("constant/polyMesh/boundary"),
                    "{}",
                    file.display()
                );
                assert_eq!(k, key);
            }
            Err(e) => panic!("{e}"),
            Ok(_) => panic!("accepted {edit}"),
        }
    }
}

/// The `gradient` of a source's properties file.
fn gradient(time_dir: &Path) -> f64 {
    let path = fv::fv_options::props_path(time_dir, "momentumSource");
    foam::parse_file(&path)
        .unwrap()
        .body
        .f64("gradient")
        .unwrap()
}

/// Runs a fixture case natively into a temporary copy and compares the fields of `end` with
/// pisoFoam's; returns the relative differences of U, p (to Ū²), phi and the source's gradient, and
/// of the `extra` scalar fields.
fn against_pisofoam(fixture: &str, end: &str, ubar: f64, extra: &[&str]) -> Vec<(String, f64)> {
    let case = testkit::fixture(fixture);
    let dir = tempfile::tempdir().unwrap();
    testkit::copy_dir(&case, dir.path());
    let _ = std::fs::remove_dir_all(dir.path().join(end));
    let mut fluid = Fluid::from_case(dir.path()).unwrap();
    fluid.run().unwrap();
    let n = fluid.geometry().n_cells;
    let (ours, theirs) = (dir.path().join(end), case.join(end));
    let mut out = vec![
        (
            "U".to_string(),
            rel(&vectors(&ours.join("U"), n), &vectors(&theirs.join("U"), n)),
        ),
        // p: the periodic flow is driven by the source, p holds only the disturbance
        // (|p| ~ 1e-9 Ū² in the laminar case), so its difference is taken relative to Ū².
        ("p".to_string(), {
            let (a, b) = (scalars(&ours.join("p"), n), scalars(&theirs.join("p"), n));
            a.iter()
                .zip(&b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
                / (ubar * ubar)
        }),
    ];
    // phi, internal faces and the cyclic patches' values (both sides).
    let phi = |d: &Path| -> Vec<f64> {
        let f = foam::parse_file(&d.join("phi")).unwrap();
        let mut v = f.body.stream("internalField").unwrap()[2]
            .as_f64_list()
            .unwrap();
        let bf = f.body.dict("boundaryField").unwrap();
        for p in ["inlet", "outlet"] {
            let items = bf.dict(p).unwrap().stream("value").unwrap();
            v.extend(items[2].as_f64_list().unwrap());
        }
        v
    };
    out.push(("phi".into(), rel(&phi(&ours), &phi(&theirs))));
    let (g_ours, g_theirs) = (gradient(&ours), gradient(&theirs));
    out.push((
        "gradient".into(),
        (g_ours - g_theirs).abs() / g_theirs.abs(),
    ));
    for name in extra {
        out.push((
            name.to_string(),
            rel(
                &scalars(&ours.join(name), n),
                &scalars(&theirs.join(name), n),
            ),
        ));
    }
    out
}

/// A laminar periodic channel with `meanVelocityForce` against Debian's pisoFoam v1912
/// (fixture `tests/fixtures/fv/channel-periodic`, its README says how it was made): x-graded
/// cells, so the two sides of the cyclic pair differ in size, and a disturbance varying
/// along the period, 50 steps. The same solvers (PCG/DIC, PBiCGStab/DILU to 1e-12, the
/// cyclic interfaces left out of the factorisations as OpenFOAM leaves them) and the same
/// discretisation: the fields agree to round-off (measured in the test output).
#[test]
fn laminar_periodic_channel_matches_pisofoam() {
    let d = against_pisofoam("fv/channel-periodic", "0.5", 0.1, &[]);
    eprintln!("laminar periodic channel vs pisoFoam after 50 steps: {d:?}");
    for (name, x) in d {
        assert!(x < 1e-10, "{name}: {x}");
    }
}

/// The laminar periodic channel with `ddtSchemes default backward` and `Gauss limitedLinearV
/// 1` convection (the periodicChannel tutorial's schemes; fixture
/// `tests/fixtures/fv/channel-periodic-backward`): backward's first step is Euler, the other 49
/// second-order backward differencing over two old levels, in the momentum matrix and in
/// `ddtCorr`, against pisoFoam.
#[test]
fn backward_periodic_channel_matches_pisofoam() {
    let d = against_pisofoam("fv/channel-periodic-backward", "0.5", 0.1, &[]);
    eprintln!("backward periodic channel vs pisoFoam after 50 steps: {d:?}");
    for (name, x) in d {
        assert!(x < 1e-10, "{name}: {x}");
    }
}

/// The standard k–ε model with wall functions in a periodic channel (fixture
/// `tests/fixtures/fv/channel-periodic-keps`): k, ε and νt carried across the cyclic pair as
/// U and p are, against pisoFoam after 40 steps at Re = Ū h/ν = 5·10⁴.
#[test]
fn k_epsilon_periodic_channel_matches_pisofoam() {
    let d = against_pisofoam(
        "fv/channel-periodic-keps",
        "2",
        1.0,
        &["k", "epsilon", "nut"],
    );
    eprintln!("k-epsilon periodic channel vs pisoFoam after 40 steps: {d:?}");
    for (name, x) in d {
        assert!(x < 1e-10, "{name}: {x}");
    }
}

/// The laminar periodic channel on a sheared mesh (fixture
/// `tests/fixtures/fv/channel-periodic-skew`): the non-orthogonal correction vectors and the
/// explicit correction of the Laplacians across the cyclic pair, against pisoFoam after 50
/// steps with one non-orthogonal corrector.
#[test]
fn skewed_periodic_channel_matches_pisofoam() {
    let d = against_pisofoam("fv/channel-periodic-skew", "0.2", 0.1, &[]);
    eprintln!("skewed periodic channel vs pisoFoam after 50 steps: {d:?}");
    for (name, x) in d {
        assert!(x < 1e-10, "{name}: {x}");
    }
}

/// A periodic run continued from a written time reproduces the uninterrupted run: `phi` is
/// read back on both sides of the cyclic pair and the source's force from
/// `uniform/momentumSourceProperties` (as OpenFOAM's meanVelocityForce reads it).
#[test]
fn a_periodic_run_restarts_from_its_written_time() {
    let case = testkit::fixture("fv/channel-periodic");
    let whole = tempfile::tempdir().unwrap();
    testkit::copy_dir(&case, whole.path());
    let _ = std::fs::remove_dir_all(whole.path().join("0.5"));
    let parts = tempfile::tempdir().unwrap();
    testkit::copy_dir(whole.path(), parts.path());
    Fluid::from_case(whole.path()).unwrap().run().unwrap();
    let control = parts.path().join("system/controlDict");
    let text = std::fs::read_to_string(&control).unwrap();
    std::fs::write(&control, text.replace("endTime 0.5;", "endTime 0.25;")).unwrap();
    Fluid::from_case(parts.path()).unwrap().run().unwrap();
    let text = std::fs::read_to_string(&control).unwrap();
    std::fs::write(
        &control,
        text.replace("endTime 0.25;", "endTime 0.5;")
            .replace("startTime 0;", "startTime 0.25;"),
    )
    .unwrap();
    Fluid::from_case(parts.path()).unwrap().run().unwrap();
    let n = 128;
    let (a, b) = (whole.path().join("0.5"), parts.path().join("0.5"));
    assert_eq!(vectors(&a.join("U"), n), vectors(&b.join("U"), n));
    assert_eq!(scalars(&a.join("p"), n), scalars(&b.join("p"), n));
    assert_eq!(gradient(&a), gradient(&b));
}
