//! grainPisoFoam driven serially through the link equals the same solver fed the same fields
//! from files (`couplingSource prescribed`, ε blended per step by hand) on the porous cavity;
//! on a 1-D porous column it agrees with the native solver and its per-patch sums match
//! continuity and the boundary conditions.

mod common;
use common::*;
use foam_link::OpenFoamFluid;
use foam_solver_tests::TestCase;

#[test]
fn serial_link_matches_prescribed_files_and_the_native_solver() {
    let Some(solver) = tools() else {
        return;
    };
    let universe = universe();
    let world = universe.world();

    let (case, fields) = porous_cavity();
    let (u_files, p_files) = run_prescribed(&case, &fields, &solver);

    let linked = case.duplicate();
    let mut fluid = OpenFoamFluid::spawn(&world, &linked.dir, 1, &solver).unwrap();
    assert_eq!(fluid.ranks(), 1);
    assert!(fluid.decomposition().is_none());
    // The start state is the case's 0/ (U = 0 in the cells, p = 0).
    let start = couple::FluidSide::state(&fluid);
    assert!(start.u.iter().flatten().all(|&x| x == 0.0));
    run_link(&mut fluid, &fields);
    let state = couple::FluidSide::state(&fluid);
    let du = rel_diff_v(state.u, &u_files);
    let dp = rel_diff(state.p, &p_files);
    eprintln!("serial link vs prescribed files: U {du:.2e}, p {dp:.2e} (max-norm, relative)");
    // Same solver and arithmetic; the files hold 17 digits.
    assert!(
        du < 1e-12 && dp < 1e-12,
        "link vs prescribed: U {du:e}, p {dp:e}"
    );
    // ∇p is OpenFOAM's Gauss-linear gradient of the returned p: spot-check its size.
    assert!(state.grad_p.iter().flatten().any(|&g| g != 0.0));
    let stats = fluid.stats();
    assert_eq!(stats.intervals, 2);
    let (sent, received) = foam_link::protocol::advance_bytes(256, 1, 3);
    assert_eq!(stats.bytes_sent, 2 * sent as u64);
    assert_eq!(stats.bytes_received, 2 * received as u64);
    fluid.write().unwrap();
    fluid.finish().unwrap();
    // The write went through OpenFOAM: the written U equals the returned one.
    assert!(rel_diff_v(&mesh::v3::from_arrays(&linked.vectors(END, "U")), &u_files) < 1e-12);
    let log = std::fs::read_to_string(linked.dir.join("log.grainPisoFoam")).unwrap();
    assert!(log.contains("couplingSource mpi"), "{log}");

    column_patch_sums(&world, &solver);
}

/// The 1-D column (600 cells of 0.1 mm, inlet U = 0.01 m/s fixed, outlet p = 0) with a porous
/// block (ε = 0.45, Ksl = 5000 kg/(m³ s) for 20 mm < z < 36 mm), 4 intervals of 5 steps of
/// 1 ms. U and p equal a `frozen` run with the same fields in `0/`, and agree with the native
/// solver; the inlet flux is −U_s A, the outlet's +U_s A (continuity, ε = 1 at both ends),
/// the outlet's mean p 0 and the inlet's equal to its cell's p (zeroGradient).
fn column_patch_sums(world: &mpi::topology::SimpleCommunicator, solver: &std::path::Path) {
    let case = TestCase::template("column");
    case.edit("system/blockMeshDict", "(1 1 60)", "(1 1 600)");
    case.block_mesh();
    let (_, g) = case.mesh();
    let bed: Vec<bool> = g
        .cell_centres
        .iter()
        .map(|c| c[2] > 0.020 && c[2] < 0.036)
        .collect();
    let eps: Vec<f64> = bed.iter().map(|&b| if b { 0.45 } else { 1.0 }).collect();
    let ksl: Vec<f64> = bed.iter().map(|&b| if b { 5000.0 } else { 0.0 }).collect();
    let zeros = vec![mesh::v3::V3::zeros(); eps.len()];

    let mut native = fv::Fluid::from_case(&case.dir).expect("native solver reads the case");
    // grainPisoFoam's faces next to porous cells are resistance-consistent (porousFaces.H).
    native.harmonic_faces = true;
    native.set_voidage(&eps, &eps).unwrap();
    native.set_exchange(&ksl, &zeros).unwrap();
    for _ in 0..20 {
        native.advance(0.001).unwrap();
    }

    let frozen = case.duplicate();
    frozen.set_field("voidfraction", foam::FieldValues::Scalar(eps.clone()));
    frozen.set_field("Ksl", foam::FieldValues::Scalar(ksl.clone()));
    frozen.run(solver);

    let mut fluid = OpenFoamFluid::spawn(world, &case.dir, 1, solver).unwrap();
    let fields = foam_link::protocol::FieldsIn {
        eps_old: &eps,
        eps_new: &eps,
        ksl: &ksl,
        us: &zeros,
        f: &zeros,
    };
    for _ in 0..4 {
        fluid.set_fields(&fields).unwrap();
        fluid.advance_interval(0.005).unwrap();
    }
    let state = couple::FluidSide::state(&fluid);
    let du_frozen = rel_diff_v(
        state.u,
        &mesh::v3::from_arrays(&frozen.vectors("0.02", "U")),
    );
    let dp_frozen = rel_diff(state.p, &frozen.scalars("0.02", "p"));
    let du = rel_diff_v(state.u, native.u());
    let dp = rel_diff(state.p, native.p());
    let inlet = fluid.patch("inlet").unwrap();
    let outlet = fluid.patch("outlet").unwrap();
    let area = inlet.area;
    eprintln!(
        "column: link vs frozen files U {du_frozen:.2e}, p {dp_frozen:.2e}; vs native fv U \
         {du:.2e}, p {dp:.2e}; inlet {inlet:?}, outlet {outlet:?}"
    );
    // The frozen run starts its flux from ε of 0/ (ε_f U_f·S; the link's 0/ has ε = 1, so
    // U_f·S): the first step's convection differs and the faces next to the block remember it
    // (two frozen runs with either start flux differ by 1.2e-8 in p, 1.9e-8 in U; measured
    // here 8.3e-9, 1.3e-8).
    assert!(
        du_frozen < 1e-7 && dp_frozen < 1e-7,
        "link vs frozen: U {du_frozen:e}, p {dp_frozen:e}"
    );
    // The same face coefficients and, next to the block, the same time term (fv's
    // harmonic_faces and PorousTimeFlux::Consistent, grainPisoFoam's porousFaces.H); clear
    // faces keep their own forms (fv harmonic, grainPisoFoam pisoFoam's linear ones): measured
    // U 4.9e-3 (interface cells), p 8.4e-4 (5.2e-3 and 7.7e-4 before issue 17, when the
    // ddtCorr coefficients next to the block differed).
    assert!(du < 1e-2 && dp < 2e-3, "link vs native: U {du:e}, p {dp:e}");
    assert!(
        (inlet.flux + 0.01 * area).abs() < 1e-12 * 0.01 * area,
        "{inlet:?}"
    );
    assert!(
        approx::abs_diff_eq!(outlet.flux, 0.01 * area, epsilon = 1e-9 * 0.01 * area),
        "{outlet:?}"
    );
    assert_eq!(outlet.mean_p, 0.0);
    let p0 = state.p[0];
    assert!(
        approx::abs_diff_eq!(inlet.mean_p, p0, epsilon = 1e-12 * p0.abs()),
        "{inlet:?} vs {p0}"
    );
    assert!(fluid.patch("nowhere").is_none());
    fluid.finish().unwrap();
}
