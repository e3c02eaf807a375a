//! Decks: the reference cases' decks (`openfoam-cases/*/DEM/`) run natively; dumps written
//! through dem-io read back; unsupported or bad input names the file, line and command.

use approx::assert_abs_diff_eq;
use mesh::v3::{from_arrays, V3};
use std::path::Path;

use dem::Simulation;
use dem_io::{read_snapshot, DumpFormat, ReadOptions, Selection};
use liggghts_deck::Deck;

fn case_deck(rel: &str) -> std::path::PathBuf {
    testkit::repo_root().join("openfoam-cases").join(rel)
}

fn vars(v: &[(&str, &str)]) -> Vec<(String, String)> {
    v.iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

#[test]
fn ergun_decks_pack_then_couple() {
    let dir = tempfile::tempdir().unwrap();
    let init = Deck::read_with_vars(
        case_deck("ergun/DEM/in.liggghts_init"),
        &vars(&[("np", "150"), ("tsettle", "400")]),
    )
    .unwrap();
    assert!(init.coupling().unwrap().is_none());
    let sim = Simulation::from_deck(&init, dir.path()).unwrap();
    assert_eq!(sim.particles.len(), 150);
    assert_eq!(sim.step(), 400);
    // inserted inside the insertion cylinder (r = 12 mm) and kept by the walls
    for x in &sim.particles.x {
        assert!(x[0].hypot(x[1]) < 0.0138 && x[2] > 0.0 && x[2] < 0.0553);
    }
    assert!(sim.particles.radius.iter().all(|&r| r == 0.0005));
    assert!(dir.path().join("post/packed.data").is_file());

    let run = Deck::read(case_deck("ergun/DEM/in.liggghts_run")).unwrap();
    let c = run.coupling().unwrap().expect("the run deck is coupled");
    assert_eq!(c.couple_every, 50);
    assert!(c.implicit && c.has_force_fix);
    let mut sim2 = Simulation::from_deck(&run, dir.path()).unwrap();
    assert_eq!(sim2.step(), 0);
    assert_eq!(sim2.particles.id, sim.particles.id);
    for (a, b) in sim2.particles.x.iter().zip(&sim.particles.x) {
        for k in 0..3 {
            assert!(
                approx::abs_diff_eq!(a[k], b[k], epsilon = 1e-15 * b[k].abs().max(1e-3)),
                "{a:?} {b:?}"
            );
        }
    }
    // the coupler's part: a drag pair, then DEM steps
    let n = sim2.particles.len();
    sim2.set_coupling(
        &vec![V3::zeros(); n],
        &vec![1e-4; n],
        &vec![V3::new(0.0, 0.0, 0.01); n],
    )
    .unwrap();
    sim2.run(50).unwrap();
    assert_eq!(sim2.step(), 50);
}

#[test]
fn settling_deck_makes_one_coupled_sphere() {
    let dir = tempfile::tempdir().unwrap();
    let deck = Deck::read(case_deck("settling/DEM/in.liggghts_run")).unwrap();
    let c = deck.coupling().unwrap().unwrap();
    assert_eq!(c.couple_every, 100);
    assert!(!c.implicit && c.has_force_fix);
    let mut sim = Simulation::from_deck(&deck, dir.path()).unwrap();
    let p = &sim.particles;
    assert_eq!(p.len(), 1);
    assert_eq!(p.radius[0], 5e-5);
    assert_eq!(p.density[0], 3000.0);
    assert_eq!(p.x[0], V3::new(0.00625, 0.04375, 0.00625));
    // gravity along −y: free fall for 1000 steps of 1e-5 s, v = −g t exactly
    sim.run(1000).unwrap();
    assert!((sim.particles.v[0][1] + 9.81 * 0.01).abs() < 1e-12);
    assert_eq!(sim.particles.v[0][0], 0.0);
}

const SMALL: &str = "\
atom_style granular
atom_modify map array
boundary f f f
newton off
units si
region box block 0 0.01 0 0.01 0 0.01 units box
create_box 1 box
neighbor 0.0002 bin
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.45
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style gran model hertz tangential history
pair_coeff * *
timestep 1e-5
fix g all gravity 9.81 vector 0 0 -1
fix floor all wall/gran model hertz tangential history primitive type 1 zplane 0
create_atoms 1 single 0.005 0.005 0.002 units box
create_atoms 1 single 0.005 0.005 0.004 units box
set group all diameter 0.001 density 2500
fix integr all nve/sphere
";

#[test]
fn dumps_read_back_with_dem_io() {
    let dir = tempfile::tempdir().unwrap();
    let src = format!(
        "{SMALL}dump t all custom 50 post/a.txt id type x y z vx vy vz fx fy fz omegax omegay omegaz radius mass\n\
         dump b all custom 100 post/b.bin id type x y z vx vy vz radius\n\
         dump s all custom 100 post/s_*.txt id x z diameter density\n\
         dump_modify s sort id\nrun 200\n"
    );
    let deck = Deck::parse(&src, Path::new("mem.in"), &[]).unwrap();
    let sim = Simulation::from_deck(&deck, dir.path()).unwrap();
    let opts = ReadOptions::default();
    let t = read_snapshot(dir.path().join("post/a.txt"), &opts, Selection::Last).unwrap();
    assert_eq!(t.timestep, 200);
    let p = t.particles().unwrap();
    assert_eq!(p.id, sim.particles.id);
    assert_eq!(from_arrays(&p.position), sim.particles.x);
    assert_eq!(from_arrays(&p.velocity), sim.particles.v);
    assert_eq!(from_arrays(&p.force.unwrap()), sim.particles.f);
    assert_eq!(p.mass.unwrap(), sim.particles.mass);
    // snapshots at 0, 50, 100, 150, 200
    let mut r = dem_io::DumpReader::open(dir.path().join("post/a.txt"), &opts).unwrap();
    let mut steps = Vec::new();
    while let Some(h) = r.next_header().unwrap() {
        steps.push(h.timestep);
    }
    assert_eq!(steps, [0, 50, 100, 150, 200]);
    assert_eq!(
        DumpFormat::from_path(Path::new("b.bin")),
        DumpFormat::Binary
    );
    let bopts = ReadOptions {
        binary_columns: ["id", "type", "x", "y", "z", "vx", "vy", "vz", "radius"]
            .map(String::from)
            .to_vec(),
        ..Default::default()
    };
    let b = read_snapshot(dir.path().join("post/b.bin"), &bopts, Selection::Last).unwrap();
    assert_eq!(
        from_arrays(&b.particles().unwrap().position),
        sim.particles.x
    );
    let s = read_snapshot(dir.path().join("post/s_200.txt"), &opts, Selection::Last).unwrap();
    assert_eq!(s.column("diameter").unwrap(), [0.001, 0.001]);
    assert!(dir.path().join("post/s_100.txt").is_file());
}

fn deck_error(src: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    match Deck::parse(src, Path::new("bad.in"), &[]) {
        Err(e) => e.to_string(),
        Ok(d) => Simulation::from_deck(&d, dir.path())
            .expect_err("the deck should fail")
            .to_string(),
    }
}

#[test]
fn bad_decks_name_file_line_and_command() {
    let e = deck_error(&format!("{SMALL}fix p all pour 100 1 1\nrun 1\n"));
    assert!(e.starts_with("bad.in:22: `fix pour`"), "{e}");
    assert!(e.contains("not supported"), "{e}");
    let e = deck_error(&format!("{SMALL}write_restart x.restart region r\n"));
    assert!(e.starts_with("bad.in:22: `write_restart`"), "{e}");
    assert!(e.contains("no region"), "{e}");
    let e = deck_error(&SMALL.replace("boundary f f f", "boundary pf f f"));
    assert!(e.contains("bad.in:3") && e.contains("periodic"), "{e}");
    let e = deck_error(&SMALL.replace("timestep 1e-5", "timestep 1e-5x"));
    assert!(
        e.contains("bad.in:15: `timestep`") && e.contains("1e-5x"),
        "{e}"
    );
    let e = deck_error(&SMALL.replace(
        "fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n",
        "",
    ));
    assert!(e.contains("coefficientFriction"), "{e}");
    let e = deck_error(&format!("{SMALL}run 1\n").replace(
        "youngsModulus peratomtype 5.e6",
        "youngsModulus peratomtype 1e5",
    ));
    assert!(
        e.contains("bad.in:22: `run`") && e.contains("soft_particles"),
        "{e}"
    );
    // a wall with a temperature conducts (`heat/gran`): without a heat fix the run stops, as
    // LIGGGHTS's does (no `Temp` property); a bad temperature names the wall's line
    let e = deck_error(&format!("{SMALL}run 1\n").replace("zplane 0", "zplane 0 temperature 300"));
    assert!(
        e.contains("bad.in:22: `run`") && e.contains("temperature") && e.contains("heat/gran"),
        "{e}"
    );
    let e = deck_error(&SMALL.replace("zplane 0", "zplane 0 temperature hot"));
    assert!(
        e.contains("bad.in:17: `fix wall/gran`") && e.contains("temperature"),
        "{e}"
    );
    let e = deck_error(&format!("{SMALL}dump d all custom 10 x.txt id q\n"));
    assert!(e.contains("column `q`"), "{e}");
    let e = deck_error(&format!("{SMALL}run 10 every 5 \"print x\"\n"));
    assert!(e.contains("every"), "{e}");
    let e = deck_error("units lj\n");
    assert!(e.starts_with("bad.in:1: `units`"), "{e}");
}

/// The dem-io fixture `settle.txt` (LIGGGHTS, 200 spheres of ρ 2500 and 2000 with a `mass`
/// column) gives back its densities, and the particles run in a simulation.
#[test]
fn particles_from_a_liggghts_dump() {
    let snap = read_snapshot(
        testkit::fixture("liggghts/settle.txt"),
        &ReadOptions::default(),
        Selection::Last,
    )
    .unwrap();
    let ps = dem::from_dump::particles_from_snapshot(&snap, &[]).unwrap();
    assert_eq!(ps.len(), 200);
    for p in &ps {
        let want = if p.radius == 0.0005 { 2500.0 } else { 2000.0 };
        assert!(
            approx::abs_diff_eq!(p.density / want, 1.0, epsilon = 1e-12),
            "{} {}",
            p.radius,
            p.density
        );
    }
    let no_density = snap.clone().into_columns();
    let keep: Vec<usize> = (0..no_density.0.len())
        .filter(|&k| no_density.0[k] != "mass")
        .collect();
    let s2 = dem_io::Snapshot::new(
        snap.timestep,
        snap.bounds,
        keep.iter().map(|&k| no_density.0[k].clone()).collect(),
        keep.iter().map(|&k| no_density.1[k].clone()).collect(),
    )
    .unwrap();
    let e = dem::from_dump::particles_from_snapshot(&s2, &[]).unwrap_err();
    assert!(e.to_string().contains("no density"), "{e}");
    assert_eq!(
        dem::from_dump::particles_from_snapshot(&s2, &[1000.0]).unwrap()[0].density,
        1000.0
    );
}

/// Runs `src` with an observer; returns the simulation and the output lines.
fn observed(src: &str) -> (Simulation, Vec<String>, Vec<(u64, u64)>) {
    let dir = tempfile::tempdir().unwrap();
    let deck = Deck::parse(src, Path::new("thermo.in"), &[]).unwrap();
    let mut lines = Vec::new();
    let mut runs = Vec::new();
    let sim = Simulation::from_deck_observed(&deck, dir.path(), &mut |e| match e {
        dem::deck::exec::DeckEvent::Output(l) => lines.push(l),
        dem::deck::exec::DeckEvent::RunStart { from, to, .. } => runs.push((from, to)),
        _ => {}
    })
    .unwrap();
    (sim, lines, runs)
}

#[test]
fn thermo_rows_come_at_liggghts_steps_and_do_not_change_the_physics() {
    // Two spheres falling onto a floor and onto each other, spinning after the contact.
    let thermo = "compute rke all erotate/sphere\nthermo_style custom step atoms ke c_rke time\n\
                  thermo 70\nthermo_modify lost ignore norm no\n";
    let (a, lines, runs) = observed(&format!("{SMALL}{thermo}run 250\nrun 100\n"));
    let (b, quiet, _) = observed(&format!("{SMALL}run 250\nrun 100\n"));
    // The same bits whatever the output: the run is cut into chunks at every thermo step.
    assert_eq!(a.particles.x, b.particles.x);
    assert_eq!(a.particles.v, b.particles.v);
    assert_eq!(a.particles.omega, b.particles.omega);
    assert_eq!(runs, [(0, 250), (250, 350)]);
    // LIGGGHTS prints a row at the first step of a run, at multiples of N, and at the last.
    let steps: Vec<u64> = lines
        .iter()
        .filter_map(|l| l.split_whitespace().next()?.parse().ok())
        .collect();
    assert_eq!(steps, [0, 70, 140, 210, 250, 250, 280, 350]);
    let header = &lines[0];
    assert_eq!(
        header.split_whitespace().collect::<Vec<_>>(),
        ["Step", "Atoms", "KinEng", "rke", "Time"]
    );
    // The last row holds the state at step 350: ½m|v|² and ½I|ω|² of the two spheres.
    let last: Vec<f64> = lines[lines.len() - 2]
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    let ke = a.particles.translational_energy();
    let rke = a.particles.rotational_energy();
    assert!(
        approx::abs_diff_eq!(last[2], ke, epsilon = 1e-7 * ke),
        "{last:?} vs {ke}"
    );
    assert!(
        approx::abs_diff_eq!(last[3], rke, epsilon = 1e-7 * rke.max(1e-300)),
        "{last:?} vs {rke}"
    );
    assert_abs_diff_eq!(last[4], 350.0 * 1e-5, epsilon = 1e-12);
    assert!(lines.last().unwrap().starts_with("Loop time of "));
    // The default style (`one`): step atoms ke cpu.
    assert_eq!(
        quiet[0].split_whitespace().collect::<Vec<_>>(),
        ["Step", "Atoms", "KinEng", "CPU"]
    );
}

/// `units cgs` (cm, g, s, dyn): the same physics as SI with every input converted. A small
/// pour (insertion, gravity, Hertz contacts with history, walls) in SI and in cgs ends in the
/// same state, lengths ×100 and velocities ×100, to round-off; and E is bounded by LIGGGHTS's
/// cgs limits (5e7 … 1e10 dyn/cm²), not the SI ones.
#[test]
fn cgs_units_are_si_scaled() {
    // (length, velocity, density, pressure, acceleration) factors SI → cgs
    let deck = |cgs: bool| {
        let (l, d, p) = if cgs {
            (100.0, 1e-3, 10.0)
        } else {
            (1.0, 1.0, 1.0)
        };
        format!(
            "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\n\
             communicate single vel yes\nunits {units}\n\
             region reg block {a} {b} {a} {b} 0 {h} units box\ncreate_box 1 reg\n\
             neighbor {skin} bin\nneigh_modify delay 0\n\
             fix m1 all property/global youngsModulus peratomtype {e}\n\
             fix m2 all property/global poissonsRatio peratomtype 0.45\n\
             fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n\
             fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
             pair_style gran model hertz tangential history\npair_coeff * *\n\
             timestep 0.00001\nfix gravi all gravity {g} vector 0.0 0.0 -1.0\n\
             fix zwall all wall/gran model hertz tangential history primitive type 1 zplane 0.0\n\
             fix xwall all wall/gran model hertz tangential history primitive type 1 xplane {a}\n\
             region ins block {a} {b} {a} {b} {z0} {h} units box\n\
             fix pts1 all particletemplate/sphere 15485863 atom_type 1 density constant {rho} radius constant {r}\n\
             fix pdd1 all particledistribution/discrete 15485867 1 pts1 1.0\n\
             fix ins all insert/pack seed 32452843 distributiontemplate pdd1 vel constant 0. 0. {vz} \
             insert_every once overlapcheck yes all_in yes particles_in_region 20 region ins\n\
             fix integr all nve/sphere\nrun 3000\n",
            units = if cgs { "cgs" } else { "si" },
            a = -0.004 * l,
            b = 0.004 * l,
            h = 0.02 * l,
            z0 = 0.002 * l,
            skin = 0.0005 * l,
            e = 5e6 * p,
            g = 9.81 * l,
            rho = 2000.0 * d,
            r = 0.0005 * l,
            vz = -0.5 * l,
        )
    };
    let run = |src: String| {
        let dir = tempfile::tempdir().unwrap();
        let deck = Deck::parse(&src, Path::new("cgs.in"), &[]).unwrap();
        Simulation::from_deck(&deck, dir.path()).unwrap()
    };
    let si = run(deck(false));
    let cgs = run(deck(true));
    assert_eq!(si.particles.len(), 20);
    assert_eq!(cgs.particles.len(), 20);
    // the pour has hit the floor: contacts acted (and amplify round-off: 7e-9 measured)
    assert!(si.particles.x.iter().any(|x| x[2] < 0.0006));
    let mut worst: f64 = 0.0;
    for i in 0..20 {
        let dx = (cgs.particles.x[i] - 100.0 * si.particles.x[i]).norm() / 0.05;
        let dv = (cgs.particles.v[i] - 100.0 * si.particles.v[i]).norm() / 50.0;
        worst = worst.max(dx).max(dv);
    }
    eprintln!("cgs vs SI × 100: largest difference {worst:e} of the radius / impact speed");
    assert!(worst < 1e-6, "{worst:e}");
    // LIGGGHTS's E bounds follow the unit system: 5e6 dyn/cm² is too soft in cgs
    let soft = deck(true).replace(
        "youngsModulus peratomtype 50000000",
        "youngsModulus peratomtype 5000000",
    );
    let e = deck_error(&soft);
    assert!(e.contains("5e7") && e.contains("CGS"), "{e}");
    assert!(deck_error(&deck(true).replace("units cgs", "units lj")).contains("si, cgs"));
}
