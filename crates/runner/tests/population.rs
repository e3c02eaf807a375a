//! A changing particle population through a coupled run on the native stack: the settling
//! case's box (1 × 5 × 1 cm, 2.5 mm cells, fluid ρ 10 kg/m³, ν 1e-5 m²/s) with a deck that
//! inserts 10 spheres (d 1 mm, 2500 kg/m³) every 1000 DEM steps (0.01 s) near the top and no
//! floor: the spheres fall out through the box's fixed bottom face and are lost
//! (`thermo_modify lost ignore`).
//!
//! Checked at every coupling step: the particle count and volume change by exactly what
//! entered minus what left (to round-off); every particle's volume is in a cell or counted
//! outside the mesh; and the fluid's ε carries exactly the deposited volume, Σ(1 − ε)V_c, at the
//! write times; at the end the totals equal the sums of the steps and the DEM's own tallies
//! (inserted by the fix, lost through the face).

use runner::run::{run, Event, RunOptions};
use std::sync::atomic::AtomicBool;

const DECK: &str = "\
atom_style      granular
atom_modify     map array
communicate     single vel yes
boundary        f f f
newton          off
units           si
region          reg block 0 0.01 0 0.05 0 0.01 units box
create_box      1 reg
neighbor        0.0002 bin
neigh_modify    delay 0
fix             m1 all property/global youngsModulus peratomtype 5.e6
fix             m2 all property/global poissonsRatio peratomtype 0.45
fix             m3 all property/global coefficientRestitution peratomtypepair 1 0.3
fix             m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        0.00001
fix             gravi all gravity 9.81 vector 0.0 -1.0 0.0
fix             pts all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 0.0005
fix             pdd all particledistribution/discrete 32452843 1 pts 1.0
region          top block 0.001 0.009 0.012 0.02 0.001 0.009 units box
fix             ins all insert/rate/region seed 49979687 distributiontemplate pdd nparticles 60 &
                particlerate 1000 insert_every 1000 all_in yes vel constant 0. -0.5 0. region top
fix             cfd all couple/cfd couple_every 100 mpi
fix             cfd2 all couple/cfd/force/implicit
fix             integr all nve/sphere
thermo_style    custom step atoms f_ins[1]
thermo          1000
thermo_modify   lost ignore norm no
";

/// Σ (1 − ε) V over the cells of the written time `name`.
fn solid_in_cells(case: &std::path::Path, name: &str, volumes: &[f64]) -> f64 {
    let f = foam::field::VolField::read(&case.join("CFD").join(name).join("voidfraction")).unwrap();
    let foam::field::FieldValues::Scalar(eps) = f.internal(volumes.len()).unwrap() else {
        panic!("voidfraction is a scalar field")
    };
    eps.iter().zip(volumes).map(|(e, v)| (1.0 - e) * v).sum()
}

#[test]
fn inserted_and_lost_particles_are_accounted_for_every_step() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("open");
    testkit::copy_inputs(&testkit::repo_root().join("openfoam-cases/settling"), &case);
    std::fs::remove_file(case.join("validationDict")).unwrap();
    std::fs::write(case.join("DEM/in.liggghts_run"), DECK).unwrap();
    let opts = RunOptions {
        end_time: Some(0.1),
        ..RunOptions::default()
    };
    let mut log = Vec::new();
    let report = run(&case, &opts, &AtomicBool::new(false), &mut |e| {
        if let Event::Message(m) = e {
            log.push(m)
        }
    })
    .unwrap();
    assert_eq!(report.steps, 100);
    assert_eq!(report.particles, 0);
    let s = &report.samples;
    let vmax = s.iter().map(|x| x.particle_volume).fold(0.0, f64::max);
    let (mut n, mut v) = (0usize, 0.0);
    for x in s {
        assert_eq!(
            x.particles + x.particles_out,
            n + x.particles_in,
            "t = {}",
            x.time
        );
        let change = x.particle_volume - v;
        assert!(
            (change - (x.volume_in - x.volume_out)).abs() < 1e-12 * vmax,
            "t = {}: ΔV {change}, in − out {}",
            x.time,
            x.volume_in - x.volume_out
        );
        assert!((x.deposited_volume + x.outside_volume - x.particle_volume).abs() < 1e-12 * vmax);
        (n, v) = (x.particles, x.particle_volume);
    }
    // the insertions at DEM steps 1, 1001, … 5001 are seen at the next exchange: 10 each
    let entered: Vec<(f64, usize)> = s
        .iter()
        .filter(|x| x.particles_in > 0)
        .map(|x| (x.time, x.particles_in))
        .collect();
    assert_eq!(entered.len(), 6, "{entered:?}");
    assert!(entered.iter().all(|e| e.1 == 10));
    let p = &report.population;
    assert_eq!(p.entered, 60);
    // the spheres fall ~0.01 m in the first 0.03 s: the first batches leave within 0.1 s
    assert!(p.left >= 10, "{p:?}");
    assert_eq!(report.particles_at_end, 60 - p.left);
    let sum = |f: fn(&runner::sample::Sample) -> f64| s.iter().map(f).sum::<f64>();
    assert!((sum(|x| x.volume_in) - p.volume_in).abs() < 1e-12 * p.volume_in);
    assert!((sum(|x| x.volume_out) - p.volume_out).abs() < 1e-12 * p.volume_in);
    let one = 4.0 / 3.0 * std::f64::consts::PI * 0.0005f64.powi(3);
    assert!((p.volume_in - 60.0 * one).abs() < 1e-12 * p.volume_in);
    // what entered moved down (inserted at −0.5 m/s), and so did what left
    assert!(p.momentum_in[1] < 0.0 && p.momentum_out[1] < 0.0);
    let line = log.iter().find(|l| l.contains("volume balance")).unwrap();
    eprintln!("{line}");
    assert!(line.contains("60 entered"), "{line}");
    // the fluid's ε holds exactly the deposited volume at the write times
    let volumes = foam::Case::open(case.join("CFD"))
        .unwrap()
        .read_mesh()
        .map(|m| mesh::geometry::MeshGeometry::new(&m).unwrap().cell_volumes)
        .unwrap();
    for (name, k) in [("0.05", 49), ("0.1", 99)] {
        let solid = solid_in_cells(&case, name, &volumes);
        let x = &s[k];
        eprintln!(
            "t = {name}: {} particles, Σ(1−ε)V = {solid:e}, deposited {:e}, outside {:e}",
            x.particles, x.deposited_volume, x.outside_volume
        );
        assert!(
            (solid - x.deposited_volume).abs() < 1e-9 * vmax,
            "t = {name}: Σ(1−ε)V = {solid}, deposited {}",
            x.deposited_volume
        );
    }
    // the DEM's own log: thermo rows of the atoms and of what the fix inserted
    let dem_log = std::fs::read_to_string(case.join("DEM/log.liggghts")).unwrap();
    let last: Vec<&str> = dem_log
        .lines()
        .rfind(|l| l.split_whitespace().count() == 3)
        .unwrap()
        .split_whitespace()
        .collect();
    assert_eq!(last, ["10000", &report.particles_at_end.to_string(), "60"]);
}
