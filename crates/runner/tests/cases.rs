//! The reference cases run end to end on the native stack (debug build: the settling case in
//! full, the Ergun case as a short smoke run; the full Ergun run is in `.ci/cli-smoke`).

use runner::run::{run, Event, RunOptions};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

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
    let mut log = Vec::new();
    let report = run(case, &RunOptions::default(), stop, &mut |e| {
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
    std::fs::write(
        case.join("CFD/constant/liggghtsCommands"),
        "FoamFile { version 2.0; format ascii; class dictionary; object liggghtsCommands; }\n\
         liggghtsCommandModels ( runLiggghts writeLiggghts );\n\
         writeLiggghtsProps { writeLastOnly off; writeName \"post/restart/liggghts.restartCFDEM\"; overwrite on; }\n",
    )
    .unwrap();
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

/// The bubbling fluidised bed (Khawaja 2015, case B) from its committed LIGGGHTS pack, one
/// coupling step (the full run and the reduced CI run are in `.ci/cli-smoke`): the case opens
/// and couples, every particle's volume is in a cell, and the packed bed is as high as 9240
/// spheres of d 1.2 mm in the 0.0432 × 0.01 m column at a random packing's voidage
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
    // the inlet's table at t = 0.00025 s: 0.0066 + (0.66 − 0.0066) · 0.0025
    let u = 0.0066 + (0.66 - 0.0066) * 0.00025 / 0.1;
    assert!((s.inlet_velocity.unwrap() - u).abs() < 1e-12 * u);
    assert!(s.pressure_drop.is_some_and(|p| p.is_finite() && p > 0.0));
}
