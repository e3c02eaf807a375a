//! The reference cases run end to end on the native stack (debug build: the settling case in
//! full, the Ergun case as a short smoke run; the full Ergun run is in `.ci/cli-smoke`).

use runner::run::{run, Event, RunOptions};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use testkit::restart::{restart_case, set_control, use_restart_deck, WRITE_LIGGGHTS};

/// A copy of a reference case's inputs (what git tracks): a packed bed or time directories that
/// a user's run of the main job left in `openfoam-cases/` are not copied.
fn case_copy(name: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let src = testkit::repo_root().join("openfoam-cases").join(name);
    let dst = dir.path().join(name);
    testkit::copy_inputs(&src, &dst);
    (dir, dst)
}

/// Runs `case` natively with default options, collecting the log lines.
fn run_logged(case: &std::path::Path, stop: &AtomicBool) -> (runner::run::RunReport, Vec<String>) {
    run_logged_with(case, &RunOptions::default(), stop)
}

/// Runs `case` with `opts`, collecting the log lines.
fn run_logged_with(
    case: &std::path::Path,
    opts: &RunOptions,
    stop: &AtomicBool,
) -> (runner::run::RunReport, Vec<String>) {
    let mut log = Vec::new();
    let report = run(case, opts, stop, &mut |e| {
        if let Event::Message(m) = e {
            log.push(m)
        }
    })
    .unwrap();
    (report, log)
}

#[test]
fn settling_sphere_passes_its_checks() {
    let (_tmp, case) = case_copy("settling");
    let stop = AtomicBool::new(false);
    let (report, _log) = run_logged(&case, &stop);
    assert_eq!(report.steps, 200);
    assert_eq!(report.particles, 1);
    assert!(!report.checks.is_empty());
    for c in &report.checks {
        assert!(c.pass, "{c:?}");
    }
    // Outputs: time directories with the fluid and exchange fields, particles, CSV, plot, JSON.
    for f in ["U", "p", "voidfraction", "Ksl", "Us", "f"] {
        assert!(case.join("CFD/0.2").join(f).is_file(), "{f}");
    }
    let post = case.join("postProcessing");
    for f in [
        "integrals.csv",
        "validation.json",
        "settling.png",
        "particles/particles.pvd",
    ] {
        assert!(post.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(post.join("integrals.csv")).unwrap();
    assert_eq!(csv.lines().count(), 201);
    // Volume accounting: the sphere is inside the mesh at every step.
    for s in &report.samples {
        assert!(
            (s.deposited_volume + s.outside_volume - s.particle_volume).abs()
                < 1e-12 * s.particle_volume
        );
        assert_eq!(s.outside_volume, 0.0);
    }
}

#[test]
fn ergun_case_runs_packing_and_coupling_in_a_short_smoke_run() {
    let (_tmp, case) = case_copy("ergun");
    let stop = AtomicBool::new(false);
    let opts = RunOptions {
        end_time: Some(0.0015),
        init_vars: vec![
            ("np".into(), "300".into()),
            ("tsettle".into(), "1500".into()),
        ],
        repack: false,
        ..RunOptions::default()
    };
    let report = run(&case, &opts, &stop, &mut |_| {}).unwrap();
    assert!(case.join("DEM/post/packed.data").is_file());
    assert_eq!(report.particles, 300);
    assert_eq!(report.steps, 3);
    // A short run validates nothing it cannot: the checks are computed, and the particle volume
    // is accounted for at every step (inside the cells or outside the polygonal mesh).
    for s in &report.samples {
        assert!(
            (s.deposited_volume + s.outside_volume - s.particle_volume).abs()
                < 1e-12 * s.particle_volume
        );
        assert!(s.pressure_drop.is_some_and(f64::is_finite));
    }
    assert!(case.join("postProcessing/validation.json").is_file());
}

#[test]
fn a_stop_request_ends_after_the_current_step_and_writes_it() {
    let (_tmp, case) = case_copy("settling");
    let stop = AtomicBool::new(true);
    let report = run(&case, &RunOptions::default(), &stop, &mut |_| {}).unwrap();
    assert!(report.stopped);
    assert_eq!(report.steps, 1);
    assert!(report.checks.is_empty());
    assert!(case.join("CFD/0.001/U").is_file());
    assert!(case.join("CFD/0.001/voidfraction").is_file());
}

/// CFDEM's twoWayMPI couples every couplingInterval DEM steps whatever the deck's
/// couple_every says (its tutorials disagree, e.g. ErgunTestMPI's 50 against 100): a warning;
/// LIGGGHTS's file coupling is driven by couple_every, so there it is refused.
#[test]
fn a_deck_whose_coupling_interval_disagrees_warns_or_is_refused() {
    let (_tmp, case) = case_copy("settling");
    let deck = case.join("DEM/in.liggghts_run");
    let text = std::fs::read_to_string(&deck)
        .unwrap()
        .replace("couple_every 100", "couple_every 50");
    std::fs::write(&deck, text).unwrap();
    let stop = AtomicBool::new(true);
    let (report, log) = run_logged(&case, &stop);
    let warning = log.iter().find(|m| m.contains("couple_every 50")).unwrap();
    assert!(warning.contains("couplingInterval 100"), "{warning}");
    // one coupling step of couplingInterval (100) DEM steps of 1e-5 s
    assert_eq!(report.steps, 1);
    assert!((report.time - 1e-3).abs() < 1e-12, "{}", report.time);

    let opts = RunOptions {
        dem: runner::backend::DemBackend::LiggghtsFile,
        ..RunOptions::default()
    };
    let err = run(&case, &opts, &AtomicBool::new(false), &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("couple_every 50") && err.contains("couplingInterval 100"),
        "{err}"
    );
}

/// CFDEM's liggghtsCommands: writeLiggghts writes a LIGGGHTS restart file of the particles at
/// the write times (here the one step a stop request leaves), which the native DEM reads back.
#[test]
fn write_liggghts_writes_a_restart_file_at_the_write_time() {
    let (_tmp, case) = case_copy("settling");
    std::fs::write(case.join("CFD/constant/liggghtsCommands"), WRITE_LIGGGHTS).unwrap();
    let stop = AtomicBool::new(true);
    let (report, log) = run_logged(&case, &stop);
    assert!(report.stopped || report.steps == 1);
    let file = case.join("DEM/post/restart/liggghts.restartCFDEM");
    assert!(file.is_file(), "{log:?}");
    assert!(log
        .iter()
        .any(|m| m.contains("write_restart ../DEM/post/restart/liggghts.restartCFDEM")));
    let restart = dem_io::restart::read_restart(&file).unwrap();
    assert_eq!(restart.atoms.len(), report.particles);
}

/// A coupled deck's run-time monitors (CFDEM's tutorials print their drag this way) act through
/// the whole coupled run: `compute reduce` of `f_dragforce`, `f_cfd2` of the force fix, `vy[1]`
/// and `step*dt` in a `fix print` file and in thermo rows in `DEM/log.liggghts`. Checked
/// against the settling sphere's physics: at terminal velocity the fluid's force balances the
/// weight, mg = 1.54e-8 N, and it is all explicit (`couple/cfd/force`: F_ext, β = 0).
#[test]
fn coupled_deck_monitors_print_through_the_run() {
    let (_tmp, case) = case_copy("settling");
    let deck = case.join("DEM/in.liggghts_run");
    let text = std::fs::read_to_string(&deck).unwrap();
    let monitors =
        "compute dragtotal all reduce sum f_dragforce[1] f_dragforce[2] f_dragforce[3]\n\
                    variable time equal step*dt\nvariable vy equal vy[1]\n\
                    variable fy equal f_cfd2[2]\n\
                    fix extra all print 100 \"${time} ${vy} ${fy} $(c_dragtotal[2])\" \
                    file post/forces.txt title \"# t vy fy dragy\" screen no\n\
                    thermo_style custom step atoms c_dragtotal[2] f_cfd2[2] v_vy\n";
    std::fs::write(
        &deck,
        text.replace("thermo_style    custom step atoms ke\n", monitors),
    )
    .unwrap();
    let stop = AtomicBool::new(false);
    let (report, _) = run_logged(&case, &stop);
    let rows: Vec<Vec<f64>> = std::fs::read_to_string(case.join("DEM/post/forces.txt"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect();
    // every 100 DEM steps (one coupling step) for 200 coupling steps
    assert_eq!(rows.len(), 200);
    let m = 3000.0 * std::f64::consts::PI / 6.0 * 1e-12;
    let last = rows.last().unwrap();
    assert!((last[0] - 0.2).abs() < 1e-12, "t {}", last[0]);
    // explicit coupling: the fix's total is the per-atom force summed
    for r in &rows {
        assert!(
            (r[2] - r[3]).abs() <= 1e-12 * r[2].abs().max(1e-20),
            "{r:?}"
        );
    }
    assert!(
        (last[2] - m * 9.81).abs() < 0.01 * m * 9.81,
        "fy {} vs mg {}",
        last[2],
        m * 9.81
    );
    // the printed velocity is the particle's, as the run's samples record it
    let s = report.samples.last().unwrap();
    assert!(
        (last[1].abs() - s.first_axial_velocity.abs()).abs() < 1e-6 * last[1].abs(),
        "vy {} vs {}",
        last[1],
        s.first_axial_velocity
    );
    // thermo rows continue through the coupled run into the DEM log
    let log = std::fs::read_to_string(case.join("DEM/log.liggghts")).unwrap();
    assert!(log.contains("dragtotal[2]"), "{log}");
    let last_row = log
        .lines()
        .rfind(|l| l.split_whitespace().next() == Some("20000"))
        .unwrap_or_else(|| panic!("no thermo row at step 20000 in\n{log}"));
    let fy: f64 = last_row.split_whitespace().nth(3).unwrap().parse().unwrap();
    assert!(
        (fy - last[2]).abs() < 1e-7 * last[2].abs(),
        "{fy} vs {}",
        last[2]
    );
}

/// The committed LIGGGHTS pack of the Ergun case (`reference/liggghts-settled.dump`: id type x y z
/// vx vy vz radius, ρp 2000 as the init deck's) as the `read_data` file the run deck reads.
fn write_packed_bed_from_reference(case: &std::path::Path) {
    let dump = std::fs::read_to_string(case.join("reference/liggghts-settled.dump")).unwrap();
    let rows: Vec<Vec<&str>> = dump
        .lines()
        .skip(9)
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|w| w.len() == 9)
        .collect();
    assert_eq!(rows.len(), 10_000);
    let mut atoms = String::new();
    let mut velocities = String::new();
    for w in &rows {
        let d = 2.0 * w[8].parse::<f64>().unwrap();
        atoms += &format!("{} {} {d:e} 2000 {} {} {}\n", w[0], w[1], w[2], w[3], w[4]);
        velocities += &format!("{} {} {} {} 0 0 0\n", w[0], w[5], w[6], w[7]);
    }
    let data = format!(
        "LAMMPS data file: the Ergun case's reference pack\n\n{} atoms\n1 atom types\n\n\
         -0.015 0.015 xlo xhi\n-0.015 0.015 ylo yhi\n-0.001 0.0554 zlo zhi\n\n\
         Atoms\n\n{atoms}\nVelocities\n\n{velocities}",
        rows.len()
    );
    std::fs::create_dir_all(case.join("DEM/post")).unwrap();
    std::fs::write(case.join("DEM/post/packed.data"), data).unwrap();
}

/// CFDEM's cases keep the fluid density in the field `0/rho` and not in transportProperties
/// (ErgunTestMPI). The Ergun case in that convention, from its committed LIGGGHTS pack, with
/// the drag explicit on the particle side (`implForceDEM` off: held for the coupling
/// interval's 50 DEM steps, as ErgunTestMPI's Koch–Hill drag): at 0.002 m/s (u/u_mf ≈ 0.15)
/// the packed bed's Δp is Ergun's (the case's Gidaspow drag is Ergun's below ε 0.8) on the
/// bed measured from the particles, and it stays well below the bed's weight per area at
/// every step. With the fluid dividing Ksl by another ρ than the coupling's (fv's default 1
/// against 0/rho's 10), Δp was 10× Ergun's, above the bed's weight from the first step, and
/// the coupled oscillation grew until the run blew up.
#[test]
fn a_packed_bed_whose_density_is_in_0_rho_keeps_erguns_pressure_drop() {
    let (_tmp, case) = case_copy("ergun");
    write_packed_bed_from_reference(&case);
    let tp = case.join("CFD/constant/transportProperties");
    let text = std::fs::read_to_string(&tp).unwrap();
    let without_rho: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("rho "))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_ne!(without_rho, text);
    std::fs::write(&tp, without_rho).unwrap();
    std::fs::write(
        case.join("CFD/0/rho"),
        "FoamFile { version 2.0; format ascii; class volScalarField; object rho; }\n\
         dimensions [1 -3 0 0 0 0 0];\ninternalField uniform 10;\n\
         boundaryField { \".*\" { type zeroGradient; } }\n",
    )
    .unwrap();
    let cp = case.join("CFD/constant/couplingProperties");
    let text = std::fs::read_to_string(&cp).unwrap();
    let gidaspow = text.find("GidaspowDragProps").unwrap();
    let explicit = text[..gidaspow].to_owned()
        + &text[gidaspow..].replacen("implForceDEM            true;", "implForceDEM false;", 1);
    assert_ne!(explicit, text);
    std::fs::write(&cp, explicit).unwrap();

    let stop = AtomicBool::new(false);
    let opts = RunOptions {
        end_time: Some(0.005),
        ..RunOptions::default()
    };
    let report = run(&case, &opts, &stop, &mut |_| {}).unwrap();
    assert_eq!(report.steps, 10);
    // Ergun's equation (Ergun 1952) for the bed measured at each step, fluid ρ 10, ν 1.5e-4.
    let (rho, mu) = (10.0, 10.0 * 1.5e-4);
    let ergun = |s: &runner::sample::Sample| {
        let (u, l, e, d) = (
            s.inlet_velocity.unwrap(),
            s.bed_height.unwrap(),
            s.bed_voidage.unwrap(),
            s.sauter_diameter.unwrap(),
        );
        let viscous = 150.0 * mu * (1.0 - e).powi(2) / (e.powi(3) * d * d) * u;
        let inertial = 1.75 * rho * (1.0 - e) / (e.powi(3) * d) * u * u;
        (viscous + inertial) * l
    };
    let mut late = Vec::new();
    for (k, s) in report.samples.iter().enumerate() {
        let dp = s.pressure_drop.unwrap();
        let (reference, weight) = (ergun(s), s.weight_per_area.unwrap());
        assert!((s.inlet_velocity.unwrap() - 0.002).abs() < 1e-12);
        // measured: 1.2–1.3 Ergun in the first two steps (the fluid starts from rest), 0.55
        // at the fourth as the bed takes the fluid's load, 0.94–1.07 from the sixth on
        assert!(
            dp > 0.4 * reference && dp < 1.5 * reference && dp < 0.3 * weight,
            "step {}: Δp {dp} Pa, Ergun {reference} Pa, weight per area {weight} Pa",
            k + 1
        );
        if k >= 5 {
            late.push(dp / reference);
        }
    }
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    assert!(
        (mean - 1.0).abs() < 0.15,
        "Δp / Ergun over steps 6–10: {late:?}"
    );
}

/// CFDEM's ErgunTestMPI_restart on the native stack: a coupled run to 0.01 s, against the
/// same case run to 0.005 s and restarted with `startFrom latestTime` (the fluid from
/// `CFD/0.005`: U, p, phi, grad(p), the voidage boundary) and the coupled deck that reads the
/// restart `writeLiggghts` wrote at 0.005 s (particles, contact histories, the coupling
/// forces). Measured: the fields of `CFD/0.01` are the same text (bit for bit), the
/// particles' positions and velocities equal bit for bit, and `integrals.csv` the same rows
/// but for the time column's last digits (the restarted clock starts at 0.005 exactly, the
/// uninterrupted one summed five steps).
#[test]
fn a_run_restarted_from_its_write_time_is_the_uninterrupted_run() {
    let stop = AtomicBool::new(false);
    let (_a, whole) = case_copy("settling");
    restart_case(&whole);
    set_control(&whole, "startTime", "0.01", "0.005");
    let (report, log) = run_logged(&whole, &stop);
    assert_eq!(report.steps, 10, "{log:?}");
    assert_eq!(report.particles, 18);

    let (_b, split) = case_copy("settling");
    restart_case(&split);
    set_control(&split, "startTime", "0.005", "0.005");
    let (first, _) = run_logged(&split, &stop);
    assert_eq!(first.steps, 5);
    // the tutorial's second half: the restart deck and startFrom latestTime
    use_restart_deck(&split);
    set_control(&split, "latestTime", "0.01", "0.005");
    let (second, log) = run_logged(&split, &stop);
    assert_eq!(second.steps, 5, "{log:?}");
    assert!(
        log.iter()
            .any(|m| m.starts_with("restart: the fluid starts at t = 0.005")),
        "{log:?}"
    );
    assert!(split.join("CFD/0.005/grad(p)").is_file());

    // the written voidage keeps the start file's boundary conditions (the fluid's boundary
    // voidage at a restart): `top` stays fixedValue 1, not the zeroGradient of Ksl, Us, f
    let eps = foam::VolField::read(&split.join("CFD/0.005/voidfraction")).unwrap();
    let top = eps.boundary().dict("top").unwrap();
    assert_eq!(top.word("type").unwrap(), "fixedValue");
    for f in ["U", "p", "phi", "grad(p)", "voidfraction", "Ksl", "Us", "f"] {
        let a = std::fs::read_to_string(whole.join("CFD/0.01").join(f)).unwrap();
        let b = std::fs::read_to_string(split.join("CFD/0.01").join(f)).unwrap();
        assert!(a == b, "CFD/0.01/{f} differs");
    }
    let state = |case: &std::path::Path| {
        dem_io::restart::read_restart(case.join("DEM/post/restart/liggghts.restartCFDEM")).unwrap()
    };
    let (a, b) = (state(&whole), state(&split));
    assert_eq!(a.header.timestep, b.header.timestep);
    assert_eq!(a.atoms.len(), 18);
    let mut dx: f64 = 0.0;
    let mut dv: f64 = 0.0;
    for (p, q) in a.atoms.iter().zip(&b.atoms) {
        assert_eq!(p.tag, q.tag);
        for k in 0..3 {
            dx = dx.max((p.x[k] - q.x[k]).abs());
            dv = dv.max((p.v[k] - q.v[k]).abs());
        }
    }
    eprintln!("restarted vs uninterrupted: |Δx| {dx:e} m, |Δv| {dv:e} m/s");
    assert_eq!((dx, dv), (0.0, 0.0));

    let rows = |case: &std::path::Path| -> Vec<Vec<f64>> {
        std::fs::read_to_string(case.join("postProcessing/integrals.csv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .map(|c| c.parse().unwrap_or(f64::NAN))
                    .collect()
            })
            .collect()
    };
    let (ra, rb) = (rows(&whole), rows(&split));
    assert_eq!(ra.len(), 10);
    assert_eq!(rb.len(), 10, "the restart keeps the first half's rows");
    for (x, y) in ra.iter().zip(&rb) {
        assert!((x[0] - y[0]).abs() < 1e-15, "time {} vs {}", x[0], y[0]);
        for (u, w) in x[1..].iter().zip(&y[1..]) {
            assert!(u == w || (u.is_nan() && w.is_nan()), "{x:?}\n{y:?}");
        }
    }
    let pvd =
        std::fs::read_to_string(split.join("postProcessing/particles/particles.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 2, "{pvd}");
}

/// The bubbling fluidised bed (Khawaja 2015, case B) from its committed LIGGGHTS pack, one
/// coupling step (the reduced run to 0.1 s is in `.ci/cli-smoke`, the full run in
/// `docs/fluidised-bed.md`): the case opens and couples, every particle's volume is in a cell,
/// and the packed bed is as high as 9240 spheres of d 1.2 mm in the 0.0432 × 0.01 m column at a random packing's voidage
/// (0.36–0.42, close to loose random packing: Scott & Kilgour 1969, Onoda & Liniger 1990):
/// L = N π d³/6 / (A (1 − ε)) = 0.0302 … 0.0333 m; Khawaja reports 0.03 m.
#[test]
fn fluidised_bed_couples_its_committed_pack() {
    let (_tmp, case) = case_copy("fluidised-bed");
    std::fs::create_dir_all(case.join("DEM/post")).unwrap();
    std::fs::copy(
        case.join("reference/packed.data"),
        case.join("DEM/post/packed.data"),
    )
    .unwrap();
    let stop = AtomicBool::new(false);
    let opts = RunOptions {
        end_time: Some(0.00025),
        ..RunOptions::default()
    };
    let report = run(&case, &opts, &stop, &mut |_| {}).unwrap();
    assert_eq!(
        (report.particles, report.steps, report.cells),
        (9240, 1, 312)
    );
    let s = &report.samples[0];
    assert!(
        (s.deposited_volume + s.outside_volume - s.particle_volume).abs()
            < 1e-12 * s.particle_volume
            && s.outside_volume == 0.0,
        "{s:?}"
    );
    let vp = 9240.0 * std::f64::consts::PI / 6.0 * 1.2e-3f64.powi(3);
    let area = 0.0432 * 0.01;
    let (lo, hi) = (vp / (area * 0.64), vp / (area * 0.58));
    let h = s.bed_height.unwrap();
    assert!(h > lo && h < hi, "bed height {h} m, expected {lo} … {hi} m");
    // the inlet's table at t = 0.00025 s: 0.006 + (0.6 − 0.006) · 0.0025
    let u = 0.006 + (0.6 - 0.006) * 0.00025 / 0.1;
    assert!((s.inlet_velocity.unwrap() - u).abs() < 1e-12 * u);
    assert!(s.pressure_drop.is_some_and(|p| p.is_finite() && p > 0.0));
}

/// The controlDict's `probes` function object on the native fluid (CFDEM's Ergun tutorials
/// read their pressure drop from it): OpenFOAM's file layout under
/// `CFD/postProcessing/<name>/<startTime>/`, one row per coupling step, each value the one the
/// run wrote for the cell holding the point (here a cell centre, so the cell is unambiguous);
/// a point outside the mesh and a field the run does not hold are left out with warnings.
#[test]
fn native_probes_write_openfoams_probe_files() {
    let (_tmp, case) = case_copy("settling");
    let cfd = case.join("CFD");
    let mesh = foam::Case::open(&cfd).unwrap().read_mesh().unwrap();
    let geom = mesh::MeshGeometry::new(&mesh).unwrap();
    let (c0, c1) = (3, mesh.n_cells - 5);
    let (x0, x1) = (geom.cell_centres[c0], geom.cell_centres[c1]);
    let control = cfd.join("system/controlDict");
    let mut text = std::fs::read_to_string(&control).unwrap();
    text.push_str(&format!(
        "functions {{ probes {{ type probes; functionObjectLibs (\"libsampling.so\"); \
         probeLocations (({} {} {}) ({} {} {}) (10 10 10)); \
         fields (p U volAverage_voidfraction); outputControl timeStep; outputInterval 1; }} }}\n",
        x0.x, x0.y, x0.z, x1.x, x1.y, x1.z
    ));
    std::fs::write(&control, text).unwrap();
    let opts = RunOptions {
        end_time: Some(0.01),
        ..RunOptions::default()
    };
    let (_, log) = run_logged_with(&case, &opts, &AtomicBool::new(false));
    let warned = |s: &str| log.iter().any(|l| l.contains(s));
    assert!(warned("(10 10 10) is outside the mesh"), "{log:?}");
    assert!(warned("volAverage_voidfraction not held"), "{log:?}");
    assert!(!warned("are not run by the native fluid"), "{log:?}");
    let dir = cfd.join("postProcessing/probes/0");
    let p = std::fs::read_to_string(dir.join("p")).unwrap();
    let lines: Vec<&str> = p.lines().collect();
    assert!(lines[0].starts_with("# Probe 0 ("), "{p}");
    assert!(lines[1].starts_with("# Probe 1 ("), "{p}");
    assert_eq!(
        lines[2].split_whitespace().collect::<Vec<_>>(),
        ["#", "Probe", "0", "1"]
    );
    assert_eq!(
        lines[3].split_whitespace().collect::<Vec<_>>(),
        ["#", "Time"]
    );
    let rows: Vec<Vec<f64>> = lines[4..]
        .iter()
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 10, "one row per coupling step: {p}");
    assert!((rows[0][0] - 0.001).abs() < 1e-12 && (rows[9][0] - 0.01).abs() < 1e-12);
    // the last row against the field the run wrote at 0.01 s, to the files' 6 digits
    let written = |name: &str| {
        foam::VolField::read(&cfd.join("0.01").join(name))
            .unwrap()
            .internal(mesh.n_cells)
            .unwrap()
    };
    let foam::FieldValues::Scalar(pw) = written("p") else {
        panic!("p is scalar")
    };
    for (k, c) in [(1, c0), (2, c1)] {
        let tol = 1e-5 * pw[c].abs().max(1e-12);
        assert!(
            (rows[9][k] - pw[c]).abs() <= tol,
            "{} vs {}",
            rows[9][k],
            pw[c]
        );
    }
    let u = std::fs::read_to_string(dir.join("U")).unwrap();
    let last = u.lines().last().unwrap();
    let foam::FieldValues::Vector(uw) = written("U") else {
        panic!("U is a vector")
    };
    let nums: Vec<f64> = last
        .replace(['(', ')'], " ")
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(nums.len(), 7, "{last}");
    for (i, (a, b)) in nums[1..4].iter().zip(uw[c0]).enumerate() {
        assert!(
            (a - b).abs() <= 1e-5 * b.abs().max(1e-9),
            "U[{i}]: {a} vs {b}"
        );
    }
}

/// The native `surfaceFieldValue` (CFDEM's periodicChannel sums `phi` over its cyclic
/// patches): OpenFOAM v1912's file layout (the header lines grainPisoFoam's OpenFOAM writes for
/// the same entry), one row per coupling step, and the values against what must hold: the
/// flow through the cyclic `inlet` equals Σ of the `phi` the run wrote on that patch, leaves
/// through `outlet` with the opposite sign (one flow across the pair), and nothing crosses the
/// no-slip `wall`, where U is zero.
#[test]
fn native_surface_field_values_write_openfoams_files() {
    let (_tmp, case) = case_copy("periodic-channel");
    let cfd = case.join("CFD");
    let control = cfd.join("system/controlDict");
    let mut text = std::fs::read_to_string(&control).unwrap();
    let object = |name: &str, patch: &str, op: &str, fields: &str| {
        format!(
            "{name} {{ type surfaceFieldValue; functionObjectLibs (\"libfieldFunctionObjects.so\"); \
             outputControl timeStep; outputInterval 1; log false; writeFields false; \
             regionType patch; name {patch}; operation {op}; fields ({fields}); }}\n"
        )
    };
    text.push_str("functions {\n");
    text.push_str(&object("flowIn", "inlet", "sum", "phi voidfraction"));
    text.push_str(&object("flowOut", "outlet", "sum", "phi"));
    text.push_str(&object("wallFlow", "wall", "areaAverage", "phi U p"));
    text.push_str(&object("spread", "wall", "CoV", "p"));
    text.push_str("}\n");
    std::fs::write(&control, text).unwrap();
    let opts = RunOptions {
        end_time: Some(0.005),
        ..RunOptions::default()
    };
    let (_, log) = run_logged_with(&case, &opts, &AtomicBool::new(false));
    let warned = |s: &str| log.iter().any(|l| l.contains(s));
    assert!(warned("voidfraction not held on patches"), "{log:?}");
    assert!(warned("`CoV` is not run by the native fluid"), "{log:?}");
    assert!(!warned("are not run by the native fluid"), "{log:?}");
    let read = |name: &str| {
        std::fs::read_to_string(
            cfd.join("postProcessing")
                .join(name)
                .join("0/surfaceFieldValue.dat"),
        )
        .unwrap()
    };
    let inflow = read("flowIn");
    let lines: Vec<&str> = inflow.lines().collect();
    assert_eq!(
        lines[..5],
        [
            // the case's writePrecision is 10: columns 18 wide, as icoFoam writes them then
            "# Region type :   patch inlet",
            "# Faces           : 16",
            "# Area            : 6.2500000000e-04",
            "# Scale factor    : 1.0000000000e+00",
            "# Time            \tsum(phi)",
        ],
        "{inflow}"
    );
    let rows = |text: &str| -> Vec<Vec<f64>> {
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| {
                l.replace(['(', ')'], " ")
                    .split_whitespace()
                    .map(|w| w.parse().unwrap())
                    .collect()
            })
            .collect()
    };
    let (inn, out) = (rows(&inflow), rows(&read("flowOut")));
    assert_eq!(inn.len(), 5, "one row per coupling step: {inflow}");
    assert!((inn[4][0] - 0.005).abs() < 1e-12);
    // the written phi's inlet faces at 0.005 s
    let phi = std::fs::read_to_string(cfd.join("0.005/phi")).unwrap();
    let at = phi.find("\n    inlet").expect("inlet in phi");
    let body = &phi[at..];
    let list = &body[body.find("List<scalar>").unwrap()..];
    let open = list.find('(').unwrap();
    let close = list.find(')').unwrap();
    let written: f64 = list[open + 1..close]
        .split_whitespace()
        .map(|w| w.parse::<f64>().unwrap())
        .sum();
    let q = inn[4][1];
    assert!(q.abs() > 1e-6, "the held flow moves air: {inflow}");
    assert!(
        (q - written).abs() <= 1e-6 * written.abs(),
        "{q} vs {written}"
    );
    for (a, b) in inn.iter().zip(&out) {
        assert!((a[1] + b[1]).abs() <= 1e-6 * a[1].abs(), "{a:?} vs {b:?}");
    }
    let wall = read("wallFlow");
    assert!(
        wall.contains("# Time            \tareaAverage(phi)\tareaAverage(U)\tareaAverage(p)\n"),
        "{wall}"
    );
    for r in rows(&wall) {
        assert_eq!(r[1..5], [0.0; 4], "{wall}");
        assert!(r[5].is_finite(), "{wall}");
    }
}

/// CFDEM's `particleCellVolume` and `volWeightedAverage` text files on the settling sphere: the
/// particle volume in the cells is the sphere's, π d³/6, on every row; the volume-weighted
/// average of ∂ε/∂t over the cells where ε grew (lowerThreshold 0) is a number where the sphere
/// moved and `NaN` where no cell qualifies (the first row: ε has not changed yet), never 0, so
/// that the columns stay aligned for the tutorials' octave `load`.
#[test]
fn monitor_text_files_hold_the_sphere_and_nan_where_nothing_is_measured() {
    let (_tmp, case) = case_copy("settling");
    let props = case.join("CFD/constant/couplingProperties");
    let text = std::fs::read_to_string(&props).unwrap().replace(
        "    Archimedes\n);",
        "    Archimedes\n    particleCellVolume\n    volWeightedAverage\n);\n\
         particleCellVolumeProps { upperThreshold 1.01; lowerThreshold -0.01; verbose false; writeToFile true; }\n\
         volWeightedAverageProps { scalarFieldNames ( ddtVoidfraction ); vectorFieldNames ( ); \
         upperThreshold 1e20; lowerThreshold 0; verbose false; writeToFile true; }",
    );
    std::fs::write(&props, text).unwrap();
    // to 0.05 s: the sphere (0.13 m/s) crosses cell faces (2.5 mm apart)
    let opts = RunOptions {
        end_time: Some(0.05),
        ..RunOptions::default()
    };
    run_logged_with(&case, &opts, &AtomicBool::new(false));
    let read = |name: &str| {
        std::fs::read_to_string(case.join(format!("CFD/postProcessing/{name}/0/{name}.txt")))
            .unwrap()
    };
    let rows = |text: &str| -> Vec<Vec<f64>> {
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
            .collect()
    };
    let d: f64 = 1e-4;
    let sphere = std::f64::consts::PI * d.powi(3) / 6.0;
    let pcv = rows(&read("particleCellVolume"));
    assert_eq!(pcv.len(), 50);
    // the time column as OpenFOAM names times (no summation round-off)
    assert!(read("particleCellVolume").contains("\n0.009 "));
    for r in &pcv {
        assert_eq!(r.len(), 6, "{r:?}");
        assert!(
            (r[1] - sphere).abs() < 1e-9 * sphere,
            "{} vs {sphere}",
            r[1]
        );
    }
    let vwa = rows(&read("volWeightedAverage"));
    assert_eq!(vwa.len(), 50);
    assert!(vwa.iter().all(|r| r.len() == 2), "{vwa:?}");
    assert!(vwa[0][1].is_nan(), "{vwa:?}");
    assert!(vwa[1..].iter().any(|r| r[1] > 0.0), "{vwa:?}");
    assert!(vwa.iter().all(|r| r[1] != 0.0), "{vwa:?}");
}

/// CFDEM's `fieldTimeAverage`, `particleVolume`, `totalMomentumExchange`, `particleProbe` and
/// `IOModel trackIO` on the settling sphere (d = 0.1 mm, ρ_p = 3000 kg/m³ in a fluid of
/// ρ = 10 kg/m³, ν = 1e-5 m²/s: relaxation time ρ_p d²/(18 μ) = 17 ms, so by 0.1 s the sphere
/// falls at its terminal speed to e⁻⁶):
/// * `particleVolume.txt` (CFDEM's `particleVolume.C`: `time << " " << VsTot`): every row is
///   the sphere, π d³/6;
/// * `timeAverage_voidfraction` (CFDEM: the running mean, `AUTO_WRITE`): the divided voidage
///   keeps Σ V (1 − ε) = π d³/6 at every step, so its time average keeps it too;
/// * `totalMomentumExchange.txt`: at terminal speed the drag holds the buoyant weight, the
///   implicit part's y is (ρ_p − ρ) V g to 1 %;
/// * `particleProbes/0/DiFeliceDrag.logDat.0` and `Archimedes.logDat.0` in
///   `particleProbe.C`'s layout (`#processor: 0`, `#index   time      ||  vectorData:     `
///   force name, then `index   time   ||   Fx   Fy   Fz   …`): Archimedes' force is ρ V g up
///   (3 significant digits, `writePrecision 3`), the drag's y at the last line the buoyant
///   weight to 1 %;
/// * trackIO's `voidfractions`, `impForces`, `expForces`, `DEMForces`, `id` beside basicIO's
///   files (CFDEM's `sophIO.C`, `trackIO.C`).
#[test]
fn cfdem_monitors_probe_and_track_the_settling_sphere() {
    let (_tmp, case) = case_copy("settling");
    let props = case.join("CFD/constant/couplingProperties");
    let text = std::fs::read_to_string(&props)
        .unwrap()
        .replace("IOModel             basicIO;", "IOModel             trackIO;")
        .replace("probeModel          off;", "probeModel          particleProbe;")
        .replace(
            "    Archimedes\n);",
            "    Archimedes\n    fieldTimeAverage\n    particleVolume\n    totalMomentumExchange\n);\n\
             fieldTimeAverageProps { startTime 0; scalarFieldNames ( voidfraction ); \
             vectorFieldNames ( U ); }\n\
             particleVolumeProps { writeToFile true; verbose true; }\n\
             totalMomentumExchangeProps { implicitMomExFieldName \"Ksl\"; \
             explicitMomExFieldName \"none\"; fluidVelFieldName \"U\"; granVelFieldName \"Us\"; }\n\
             particleProbeProps { particleIDsToSample ( 0 ); verboseToFile; includePosition; }\n",
        );
    std::fs::write(&props, text).unwrap();
    let opts = RunOptions {
        end_time: Some(0.1),
        ..RunOptions::default()
    };
    let (_, log) = run_logged_with(&case, &opts, &AtomicBool::new(false));
    let d: f64 = 1e-4;
    let v = std::f64::consts::PI * d.powi(3) / 6.0;
    let weight = (3000.0 - 10.0) * v * 9.81;
    assert!(
        log.iter()
            .any(|l| l.starts_with("Total particle volume (located in domain) = ")),
        "{log:?}"
    );
    let post = |name: &str| {
        std::fs::read_to_string(case.join(format!("CFD/postProcessing/{name}/0/{name}.txt")))
            .unwrap()
    };
    let pv = post("particleVolume");
    let rows: Vec<Vec<f64>> = pv
        .lines()
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 100);
    assert_eq!(rows[9][0], 0.01);
    for r in &rows {
        assert_eq!(r.len(), 2);
        assert!((r[1] - v).abs() < 1e-12 * v, "{} vs {v}", r[1]);
    }
    // the time average at the write time 0.1 of ε: Σ V (1 − ⟨ε⟩) = π d³/6
    let cfd = case.join("CFD");
    let mesh = foam::read_poly_mesh(&cfd.join("constant/polyMesh")).unwrap();
    let volumes = mesh::MeshGeometry::new(&mesh).unwrap().cell_volumes;
    let field = foam::VolField::read(&cfd.join("0.1/timeAverage_voidfraction")).unwrap();
    let foam::FieldValues::Scalar(avg) = field.internal(volumes.len()).unwrap() else {
        panic!("timeAverage_voidfraction is a scalar field")
    };
    let solid: f64 = avg.iter().zip(&volumes).map(|(e, v)| (1.0 - e) * v).sum();
    assert!((solid - v).abs() < 1e-9 * v, "{solid} vs {v}");
    assert!(cfd.join("0.1/timeAverage_U").is_file());
    // the drag at terminal speed, from the exchange fields
    let tme = post("totalMomentumExchange");
    let last = tme.lines().last().unwrap();
    let numbers: Vec<f64> = last
        .replace(['(', ')'], " ")
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(numbers.len(), 10, "{last}");
    assert!(
        (numbers[5] - weight).abs() < 0.01 * weight,
        "{last} vs {weight}"
    );
    assert_eq!(
        &numbers[7..],
        &[0.0, 0.0, 0.0],
        "explicitMomExFieldName none"
    );
    // the probes
    let probe = |model: &str| {
        std::fs::read_to_string(cfd.join(format!("particleProbes/0/{model}.logDat.0"))).unwrap()
    };
    let arch = probe("Archimedes");
    let mut lines = arch.lines();
    assert_eq!(lines.next(), Some("#processor: 0"));
    assert_eq!(
        lines.next(),
        Some("#index   time      ||  vectorData:     archimedesForce    ||  position")
    );
    let first = lines.next().unwrap();
    let w: Vec<&str> = first.split_whitespace().collect();
    assert_eq!(&w[..3], &["0", "0.001", "||"], "{first}");
    let buoyancy = 10.0 * v * 9.81;
    let fy: f64 = w[4].parse().unwrap();
    assert!(
        (fy - buoyancy).abs() < 5e-3 * buoyancy,
        "{first} vs {buoyancy}"
    );
    assert_eq!(w[6], "||");
    assert_eq!(arch.lines().count(), 102);
    let drag = probe("DiFeliceDrag");
    assert!(drag
        .lines()
        .nth(1)
        .unwrap()
        .ends_with("dragForce    ||  position"));
    let last: Vec<&str> = drag.lines().last().unwrap().split_whitespace().collect();
    // index, time, ||, drag (3), Urel (3), ||, position (3)
    assert_eq!(last.len(), 13, "{last:?}");
    // the time with writePrecision + 7 = 17 digits: 0.1 as C++ streams it at that precision
    assert_eq!(last[1], "0.10000000000000001");
    let dy: f64 = last[4].parse().unwrap();
    assert!((dy - weight).abs() < 0.01 * weight, "{dy} vs {weight}");
    // trackIO's files beside basicIO's
    let cloud = cfd.join("0.1/lagrangian/particleCloud");
    for name in [
        "positions",
        "v",
        "r",
        "voidfractions",
        "impForces",
        "expForces",
        "DEMForces",
    ] {
        assert!(cloud.join(name).is_file(), "{name}");
    }
    let id = std::fs::read_to_string(cloud.join("id")).unwrap();
    assert!(id.contains("\n1\n(\n1\n)\n"), "{id}");
}

/// The settling sphere (d = 0.1 mm, ρ_p = 3000 kg/m³, ρ = 10 kg/m³, ν = 1e-5 m²/s) with issue
/// 28's models switched on together: `GaussVoidFraction` (normalised), `localPSizeDiffSmoothing`,
/// `fieldVolWeighted` and `checkCouplingInterval`. The run goes through; the average of the
/// smoothed ε over every cell (`fieldVolWeighted.txt`, volWeightedAverage's layout) times the
/// mesh volume (`particleCellVolume`'s cell volume over all cells) leaves the sphere's volume
/// π d³/6 on every row (voidage and smoothing conserve it); and `checkCouplingInterval` reports
/// the relaxation time ρ_p d²/(18 ρ ν) = 3000·1e-8/(18·1e-4) = 0.01666… s by hand, and the
/// acceleration number Δt_c/τ_p = 1e-3/0.01666… = 0.06 (above CFDEM's 0.005: a warning).
#[test]
fn issue_28_models_run_together_and_conserve_the_sphere() {
    let (_tmp, case) = case_copy("settling");
    let props = case.join("CFD/constant/couplingProperties");
    let text = std::fs::read_to_string(&props)
        .unwrap()
        .replace(
            "voidFractionModel   divided;",
            "voidFractionModel   GaussVoidFraction;",
        )
        .replace(
            "smoothingModel      off;",
            "smoothingModel      localPSizeDiffSmoothing;\n\
             localPSizeDiffSmoothingProps { lowerLimit 0.1; upperLimit 1e10; \
             dSmoothingLength 1e-3; Csmoothing 10; }",
        )
        .replace(
            "    Archimedes\n);",
            "    Archimedes\n    particleCellVolume\n    fieldVolWeighted\n    checkCouplingInterval\n);\n\
             particleCellVolumeProps { upperThreshold 1.01; lowerThreshold -0.01; writeToFile true; }\n\
             fieldVolWeightedProps { startTime 0; scalarFieldNames ( voidfraction ); \
             vectorFieldNames ( U ); useVolumeFraction false; volumeFractionName \"voidfraction\"; }\n\
             checkCouplingIntervalProps { timeInterval 0.01; }",
        );
    std::fs::write(&props, text).unwrap();
    let opts = RunOptions {
        end_time: Some(0.02),
        ..RunOptions::default()
    };
    let (_, log) = run_logged_with(&case, &opts, &AtomicBool::new(false));
    let read = |name: &str| {
        std::fs::read_to_string(case.join(format!("CFD/postProcessing/{name}/0/{name}.txt")))
            .unwrap()
    };
    let fvw = read("fieldVolWeighted");
    assert!(fvw.starts_with("# time | voidfraction | U\n"), "{fvw}");
    let rows: Vec<Vec<&str>> = fvw
        .lines()
        .skip(1)
        .map(|l| l.split_whitespace().collect())
        .collect();
    let pcv: Vec<Vec<f64>> = read("particleCellVolume")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 20);
    let d: f64 = 1e-4;
    let sphere = std::f64::consts::PI * d.powi(3) / 6.0;
    for (r, p) in rows.iter().zip(&pcv) {
        // time, ε, (Ux Uy Uz)
        assert_eq!(r.len(), 5, "{r:?}");
        let eps: f64 = r[1].parse().unwrap();
        let solid = (1.0 - eps) * p[2];
        assert!(
            (solid - sphere).abs() < 1e-6 * sphere,
            "{solid} vs {sphere}"
        );
    }
    let tau = 3000.0 * d * d / (18.0 * 10.0 * 1e-5);
    let reported: Vec<f64> = log
        .iter()
        .filter_map(|l| l.strip_prefix("min. occurring particle relaxation time [s]: "))
        .map(|x| x.parse().unwrap())
        .collect();
    // steps 1 and 11 of 20 (timeInterval 0.01 s = 10 coupling steps)
    assert_eq!(reported.len(), 2, "{log:?}");
    for t in reported {
        assert!((t - tau).abs() < 1e-12 * tau, "{t} vs {tau}");
    }
    assert!(
        log.iter()
            .any(|l| l.starts_with("warning: The max. acceleration nr") && l.contains("0.06")),
        "{log:?}"
    );
}
