//! Stage 1 with the `liggghts` binary (full tier): the Ergun case's init deck, reduced, packs a
//! bed and writes the data file the run deck reads; a failing deck is reported with its log.

use std::path::Path;

#[test]
fn the_ergun_init_deck_writes_its_packed_bed() {
    if !testkit::tool("liggghts") {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../openfoam-cases/ergun/DEM");
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("post")).unwrap();
    let vars = [
        ("np".to_string(), "50".to_string()),
        ("tsettle".to_string(), "300".to_string()),
    ];
    let run =
        liggghts::run_deck(&root.join("in.liggghts_init"), dir.path(), &vars, "init").unwrap();
    let data = std::fs::read_to_string(dir.path().join("post/packed.data")).unwrap();
    assert!(data.lines().any(|l| l.trim() == "50 atoms"), "{data}");
    assert!(std::fs::read_to_string(&run.log)
        .unwrap()
        .contains("Loop time"));
    // 50 spheres of d = 1 mm inside the insertion cylinder r = 12 mm, above the floor
    let bed = dem::deck::data_file::read_data(&dir.path().join("post/packed.data")).unwrap();
    assert_eq!(bed.particles.len(), 50);
    for p in &bed.particles {
        assert!(
            approx::abs_diff_eq!(p.radius, 0.0005, epsilon = 1e-12),
            "{p:?}"
        );
        assert!(p.x[0].hypot(p.x[1]) < 0.012 + 1e-6 && p.x[2] > 0.0, "{p:?}");
    }
    // and the run deck accepts it: its checks pass with the packed bed in place
    let deck = liggghts::CouplingDeck::read(&root.join("in.liggghts_run"), &[]).unwrap();
    deck.check_inputs(dir.path()).unwrap();
}

#[test]
fn a_failing_deck_reports_the_tail_of_its_log() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("in.bad");
    std::fs::write(
        &deck,
        "atom_style granular\nunits si\nregion reg block 0 1 0 1 0 1 units box\nfrobnicate 3\n",
    )
    .unwrap();
    let e = liggghts::run_deck(&deck, dir.path(), &[], "bad")
        .unwrap_err()
        .to_string();
    assert!(e.contains("exited with status 1"), "{e}");
    assert!(e.contains("ERROR") && e.contains("frobnicate"), "{e}");
    assert!(e.contains("log.bad"), "{e}");
}

/// A stage-1 deck with LIGGGHTS-PFM's `coarsegraining` (ErgunTestCG's init deck) is refused
/// before the binary starts, with a message saying Debian's LIGGGHTS has no coarse graining
/// (it would stop with "Unknown command"). No binary is needed for the refusal.
#[test]
fn a_coarse_grained_deck_is_refused_before_liggghts_starts() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("in.cg");
    std::fs::write(
        &deck,
        "variable cg equal 2\natom_style granular\ncoarsegraining ${cg}\nunits si\n",
    )
    .unwrap();
    let e = liggghts::run_deck(&deck, dir.path(), &[], "cg")
        .unwrap_err()
        .to_string();
    assert!(e.contains("in.cg") && e.contains(":3"), "{e}");
    assert!(
        e.contains("Debian's LIGGGHTS 3.8.0 has no coarse graining"),
        "{e}"
    );
    assert!(!dir.path().join("log.cg").exists());
}

/// Seeds Debian's LIGGGHTS 3.8.0 refuses by default (not prime, as CFDEM-PFM's
/// bubblingFluidizedBed gives) are only a warning with foamgrain's `-seedtolerant`: the deck
/// packs its spheres and writes its data file.
#[test]
fn seeds_that_liggghts_would_refuse_are_a_warning() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("post")).unwrap();
    let deck = dir.path().join("in.seeds");
    // 681573 = 3 · 227191 and 4763687 = 1237 · 3851 are not prime
    std::fs::write(
        &deck,
        "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\n\
         communicate single vel yes\nunits si\n\
         region domain block 0 0.01 0 0.01 0 0.01 units box\ncreate_box 1 domain\n\
         neighbor 0.0002 bin\nneigh_modify delay 0\n\
         fix m1 all property/global youngsModulus peratomtype 1e7\n\
         fix m2 all property/global poissonsRatio peratomtype 0.3\n\
         fix m3 all property/global coefficientRestitution peratomtypepair 1 0.9\n\
         fix m4 all property/global coefficientFriction peratomtypepair 1 0.1\n\
         pair_style gran model hertz tangential history\npair_coeff * *\ntimestep 1e-6\n\
         fix pts1 all particletemplate/sphere 367127 atom_type 1 density constant 1000 \
         radius constant 0.0005\n\
         fix pdd1 all particledistribution/discrete 681573 1 pts1 1.0\n\
         fix ins all insert/pack seed 4763687 distributiontemplate pdd1 insert_every once \
         overlapcheck yes all_in yes particles_in_region 5 region domain\n\
         fix integr all nve/sphere\nrun 1\nwrite_data post/seeds.data\n",
    )
    .unwrap();
    let run = liggghts::run_deck(&deck, dir.path(), &[], "seeds").unwrap();
    let data = std::fs::read_to_string(dir.path().join("post/seeds.data")).unwrap();
    assert!(data.lines().any(|l| l.trim() == "5 atoms"), "{data}");
    let log = std::fs::read_to_string(&run.log).unwrap();
    assert!(log.contains("681573"), "LIGGGHTS's seed warning: {log}");
}

/// An init deck that fixes its `processors` grid (CFDEM's packedBedTemp: `processors 1 1 2`)
/// runs on that many ranks (`mpirun -np 2`): as a singleton LIGGGHTS would stop with
/// "Specified processors != physical processors".
#[test]
fn a_deck_with_a_processors_grid_runs_on_its_ranks() {
    if !testkit::tool("liggghts") || !testkit::tool("mpirun") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("in.grid");
    std::fs::write(
        &deck,
        "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\n\
         communicate single vel yes\nunits si\nprocessors 1 1 2\n\
         region reg block 0 0.1 0 0.1 0 0.1 units box\ncreate_box 1 reg\n\
         neighbor 0.001 bin\n\
         fix m1 all property/global youngsModulus peratomtype 5.e6\n\
         fix m2 all property/global poissonsRatio peratomtype 0.45\n\
         fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n\
         fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
         pair_style gran model hertz tangential history\npair_coeff * *\n\
         timestep 0.00001\n\
         create_atoms 1 single 0.05 0.05 0.02 units box\n\
         create_atoms 1 single 0.05 0.05 0.08 units box\n\
         set group all diameter 0.002 density 2000\n\
         fix integr all nve/sphere\nrun 10\nwrite_data grid.data\n",
    )
    .unwrap();
    let run = liggghts::run_deck(&deck, dir.path(), &[], "grid").unwrap();
    let log = std::fs::read_to_string(&run.log).unwrap();
    assert!(log.contains("on 2 procs"), "{log}");
    let data = std::fs::read_to_string(dir.path().join("grid.data")).unwrap();
    assert!(data.lines().any(|l| l.trim() == "2 atoms"), "{data}");
}
