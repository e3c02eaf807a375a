//! The study end to end on the binary bed (fast tier), the frozen side inside a coupler, and
//! the native mesh against Debian's blockMesh (full tier).

use approx::assert_abs_diff_eq;
use couple::memory::MemoryFluid;
use couple::{Coupler, CouplingConfig, ParticleSide};
use mesh::v3::V3;
use std::path::{Path, PathBuf};
use study::frozen::FrozenParticles;
use study::pack::PackedBed;
use study::template::Template;
use study::{StudyOptions, StudyReport};

fn case() -> PathBuf {
    testkit::repo_root().join("openfoam-cases/binary-bed")
}

/// A copy of the binary-bed case with the committed packed bed in `DEM/post`.
fn case_copy(dir: &Path) -> PathBuf {
    let root = dir.join("binary-bed");
    testkit::copy_inputs(&case(), &root);
    std::fs::create_dir_all(root.join("DEM/post")).unwrap();
    std::fs::copy(
        case().join("reference/packed.data"),
        root.join("DEM/post/packed.data"),
    )
    .unwrap();
    root
}

fn small_study(dir: &Path) -> StudyReport {
    let root = case_copy(dir);
    let opts = StudyOptions {
        dx_over_d: vec![2.0, 4.0, 6.0],
        methods: vec![voidage::Method::Exact],
        velocities: vec![0.5],
        max_steps: 1000,
        ..StudyOptions::default()
    };
    study::cellsize(&root, &opts, &mut |_| {}).unwrap()
}

#[test]
fn a_small_study_matches_gidaspow_on_the_measured_bed() {
    let dir = tempfile::tempdir().unwrap();
    let report = small_study(dir.path());
    // The committed bed: 5589 spheres, d32 = 1/2600 m nominal (0.7/0.3 by mass of 0.5 and
    // 0.25 mm), Ergun–Sauter's U_mf above the model's (the model's viscous drag is larger,
    // reference module docs).
    let bed = &report.bed;
    assert_eq!(bed.particles, 5589);
    assert_abs_diff_eq!(bed.diameters.sauter, 1.0 / 2600.0, epsilon = 0.01 / 2600.0);
    assert!(bed.u_mf_gidaspow < bed.u_mf_ergun);
    assert_eq!(report.rows.len(), 3);
    for r in &report.rows {
        assert!(r.run.steady, "{r:?}");
        // Total fluid force per area against Gidaspow on the measured bed: within 10 %
        // (measured +2.7 %, −7.5 %, +7.3 % for Δx = 2, 4, 6 d32: the side walls' looser layer,
        // the bed surface and, at 4 d32, a bed floor in the middle of a cell layer, none of
        // which a uniform bed has; docs/cellsize.md).
        assert!(
            r.error.abs() < 0.10,
            "Δx/d32 {}: error {}",
            r.target,
            r.error
        );
        // Steady force balance: the force on the particles equals A·Δp (to 0.5 %).
        let dp = r.run.pressure_drop;
        assert!(
            approx::abs_diff_eq!(r.force_per_area, dp, epsilon = 5e-3 * dp),
            "{} vs {dp}",
            r.force_per_area
        );
        // Model A: the drag alone is about ε̄ of the total (the rest is −V_p ∇p).
        let share = r.run.drag / r.run.fluid_force;
        assert!(
            approx::abs_diff_eq!(share, bed.voidage, epsilon = 0.1),
            "{share} vs {}",
            bed.voidage
        );
        // The grid asked for is the grid made (12 × 12 × 36 d32 box).
        assert_abs_diff_eq!(r.cell_size.over_sauter, r.target, epsilon = 0.01 * r.target);
    }
    // One GCI triplet over the three grids.
    assert_eq!(report.gci.len(), 1);
    assert_eq!(report.gci[0].triplets.len(), 1, "{:?}", report.gci[0].note);
    let files = study::write_outputs(&report, &dir.path().join("out")).unwrap();
    assert!(files.iter().any(|f| f.ends_with("cellsize.csv")));
    let csv = std::fs::read_to_string(dir.path().join("out/cellsize.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);
    assert!(csv.starts_with(study::cellsize::CSV_HEADER));
}

#[test]
fn a_frozen_bed_gives_the_same_exchange_every_step() {
    let root = case();
    let config = CouplingConfig::read_case(&root.join("CFD")).unwrap();
    let settings = config.coupler_settings(&root.join("CFD")).unwrap();
    let template = Template::read(&root.join("CFD/system/blockMeshDict.template")).unwrap();
    let mesh = template.mesh([4, 4, 12]);
    // A few spheres in the middle of the box.
    let bed = PackedBed {
        ids: vec![1, 2, 3],
        position: vec![
            V3::new(2.0e-3, 2.0e-3, 5.0e-3),
            V3::new(2.6e-3, 2.3e-3, 5.2e-3),
            V3::new(1.2e-3, 3.0e-3, 7.0e-3),
        ],
        radius: vec![2.5e-4, 1.25e-4, 2.5e-4],
        density: vec![2500.0; 3],
    };
    let mut particles = FrozenParticles::new(bed.clone(), 2e-6).unwrap();
    let mut fluid = MemoryFluid::uniform(mesh.clone(), V3::new(0.0, 0.0, 0.1));
    let mut coupler = Coupler::new(&mesh, settings).unwrap();
    coupler
        .exchange(&particles.state(), &couple::FluidSide::state(&fluid))
        .unwrap();
    for _ in 0..3 {
        let step = coupler.step(&mut particles, &mut fluid).unwrap();
        coupler.recycle(step);
    }
    assert_eq!(fluid.received.len(), 3);
    for r in &fluid.received {
        assert_eq!(r.voidage_old, r.voidage_new, "ε changed within a step");
        assert_eq!(r.voidage_new, fluid.received[0].voidage_new);
        assert_eq!(r.exchange.ksl, fluid.received[0].exchange.ksl);
    }
    assert!(fluid.received[0].voidage_new.iter().any(|&e| e < 1.0));
    assert_eq!(particles.state().position, bed.position.as_slice());
    assert_eq!(particles.steps(), 3 * config.coupling_interval);
    // β reached the particle side: positive for every particle, with u_f = U.
    let (_, beta, u_f) = particles.forces();
    assert!(beta.iter().all(|&b| b > 0.0));
    assert!(u_f.iter().all(|u| (u[2] - 0.1).abs() < 1e-12));
}

/// Cell centres, volumes and patches of the native mesh against Debian's blockMesh on the
/// filled template (full tier).
#[test]
fn the_native_mesh_equals_blockmesh() {
    if !testkit::tool("blockMesh") {
        return;
    }
    let template = Template::read(&case().join("CFD/system/blockMeshDict.template")).unwrap();
    let scale = template.lengths().iter().fold(0.0f64, |a, &b| a.max(b));
    for n in [[2, 2, 6], [4, 3, 7], [12, 12, 36]] {
        let dir = tempfile::tempdir().unwrap();
        let cfd = dir.path().join("CFD");
        testkit::copy_dir(&case().join("CFD/system"), &cfd.join("system"));
        std::fs::write(cfd.join("system/blockMeshDict"), template.fill(n)).unwrap();
        // Binary points: blockMesh's ASCII output keeps only writePrecision digits.
        let control = cfd.join("system/controlDict");
        let text = std::fs::read_to_string(&control).unwrap();
        std::fs::write(
            &control,
            text.replace("writeFormat     ascii;", "writeFormat     binary;"),
        )
        .unwrap();
        let mut c = testkit::openfoam("blockMesh");
        c.arg("-case").arg(&cfd);
        testkit::run_ok(c, dir.path());
        let theirs = foam::read_poly_mesh(&cfd.join("constant/polyMesh")).unwrap();
        let ours = template.mesh(n);
        assert_eq!(theirs.n_cells, ours.n_cells);
        assert_eq!(theirs.points.len(), ours.points.len());
        assert_eq!(theirs.neighbour.len(), ours.neighbour.len());
        let gt = mesh::MeshGeometry::new(&theirs).unwrap();
        let go = mesh::MeshGeometry::new(&ours).unwrap();
        for c in 0..ours.n_cells {
            for a in 0..3 {
                let d = (gt.cell_centres[c][a] - go.cell_centres[c][a]).abs();
                assert!(d <= 1e-12 * scale, "{n:?} cell {c}: centre differs by {d}");
            }
            let (vt, vo) = (gt.cell_volumes[c], go.cell_volumes[c]);
            assert!(
                approx::abs_diff_eq!(vt, vo, epsilon = 1e-12 * vo),
                "{n:?} cell {c}: volume {vt} vs {vo}"
            );
        }
        assert_eq!(theirs.boundary.len(), ours.boundary.len());
        for (pt, po) in theirs.boundary.iter().zip(&ours.boundary) {
            assert_eq!(
                (&pt.name, &pt.patch_type, pt.n_faces, pt.start_face),
                (&po.name, &po.patch_type, po.n_faces, po.start_face)
            );
            // The same faces (as sets of face centres with their owners).
            let faces = |g: &mesh::MeshGeometry, m: &foam::PolyMesh| {
                let mut v: Vec<(u32, [i64; 3])> = (po.start_face..po.start_face + po.n_faces)
                    .map(|f| {
                        let q = g.face_centres[f]
                            .map(|x| (x / scale * 1e9).round() as i64)
                            .into();
                        (m.owner[f], q)
                    })
                    .collect();
                v.sort();
                v
            };
            assert_eq!(
                faces(&gt, &theirs),
                faces(&go, &ours),
                "{n:?} patch {}",
                po.name
            );
        }
    }
}
