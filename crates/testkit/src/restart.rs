//! The restart fixture shared by the restart tests (`runner`'s `cases.rs`, `cli`'s
//! `dying_rank.rs`): the settling case turned into a small case in the layout of CFDEM's
//! ErgunTestMPI_restart (18 spheres, `writeLiggghts` at the write times, a deck that reads
//! what it wrote).

use std::path::Path;

/// CFDEM's `liggghtsCommands` of ErgunTestMPI_restart's first run: a LIGGGHTS restart file
/// at every write time, overwritten (`DEM/post/restart/liggghts.restartCFDEM`).
pub const WRITE_LIGGGHTS: &str =
    "FoamFile { version 2.0; format ascii; class dictionary; object liggghtsCommands; }\n\
     liggghtsCommandModels ( runLiggghts writeLiggghts );\n\
     writeLiggghtsProps { writeLastOnly off; writeName \"post/restart/liggghts.restartCFDEM\"; overwrite on; }\n";

/// The particles of the restart fixture: two layers of 9 spheres (d = 1.5 mm, 2000 kg/m³)
/// over the settling case's box, the upper layer landing on the lower one.
pub const RESTART_SETUP: &str = "\
atom_style      granular
atom_modify     map array
communicate     single vel yes
boundary        f f f
newton          off
units           si
";

/// Materials, contacts, gravity and the six walls of the restart fixture's decks.
pub const RESTART_PHYSICS: &str = "\
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
fix             ywall1 all wall/gran model hertz tangential history primitive type 1 yplane 0.0
fix             ywall2 all wall/gran model hertz tangential history primitive type 1 yplane 0.05
fix             xwall1 all wall/gran model hertz tangential history primitive type 1 xplane 0.0
fix             xwall2 all wall/gran model hertz tangential history primitive type 1 xplane 0.01
fix             zwall1 all wall/gran model hertz tangential history primitive type 1 zplane 0.0
fix             zwall2 all wall/gran model hertz tangential history primitive type 1 zplane 0.01
";

/// Turns `case`, a copy of the settling case (`copy_inputs`), into a small restart case in
/// the layout of CFDEM's ErgunTestMPI_restart, run to 0.01 s writing every 0.005 s: `in.liggghts_init` packs 18 spheres and writes
/// `post/restart/liggghts.restart`, `in.liggghts_run` reads it, `in.liggghts_restart` reads
/// what `writeLiggghts` writes (`post/restart/liggghts.restartCFDEM`, overwritten at every
/// write time), with the tutorial's model A and forces (KochHillDrag, gradPForce, viscForce,
/// Archimedes, implicit drag). The coupled decks issue no `run` (see the restart test).
pub fn restart_case(case: &Path) {
    restart_case_with(case, Bed::Landing)
}

/// Where the restart fixture's 18 spheres are when the coupled run starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bed {
    /// Two layers of 9 at the floor, the upper landing on the lower (4000 DEM steps of
    /// packing): contacts all through the coupled run.
    Landing,
    /// Nine layers of 2, 4.5 mm apart between y = 10 and 46 mm, at rest, falling through the
    /// whole run (≤ 4.4 mm in 0.03 s) without touching each other or a wall: a run whose
    /// round-off does not grow through contacts, and whose spheres LIGGGHTS spreads over
    /// its ranks along the column.
    Suspended,
}

/// [`restart_case`] with the spheres of `bed`.
pub fn restart_case_with(case: &Path, bed: Bed) {
    std::fs::remove_file(case.join("validationDict")).unwrap();
    let mut init = format!(
        "{RESTART_SETUP}region reg block 0 0.01 0 0.05 0 0.01 units box\ncreate_box 1 reg\n"
    );
    let mut at = |x: f64, y: f64, z: f64| {
        init.push_str(&format!("create_atoms 1 single {x} {y} {z} units box\n"));
    };
    let steps = match bed {
        Bed::Landing => {
            // the upper layer shifted by 0.4 mm so that its spheres land on the lower ones' sides
            for (y, shift) in [(0.004, 0.0), (0.007, 0.0004)] {
                for x in [0.0025, 0.005, 0.0075] {
                    for z in [0.0025, 0.005, 0.0075] {
                        at(x + shift, y, z);
                    }
                }
            }
            4000
        }
        Bed::Suspended => {
            for layer in 0..9 {
                for x in [0.0033, 0.0067] {
                    at(x, 0.010 + 0.0045 * layer as f64, 0.005);
                }
            }
            1
        }
    };
    init.push_str("set group all diameter 0.0015 density 2000\n");
    init.push_str(RESTART_PHYSICS);
    init.push_str(&format!(
        "fix integr all nve/sphere\nrun {steps}\nwrite_restart post/restart/liggghts.restart\n"
    ));
    std::fs::write(case.join("DEM/in.liggghts_init"), init).unwrap();
    for (deck, file) in [
        ("in.liggghts_run", "liggghts.restart"),
        ("in.liggghts_restart", "liggghts.restartCFDEM"),
    ] {
        std::fs::write(
            case.join("DEM").join(deck),
            format!(
                "{RESTART_SETUP}read_restart ../DEM/post/restart/{file}\n{RESTART_PHYSICS}\
                 fix cfd all couple/cfd couple_every 100 mpi\n\
                 fix cfd2 all couple/cfd/force/implicit\n\
                 fix integr all nve/sphere\n"
            ),
        )
        .unwrap();
    }
    let cp = case.join("CFD/constant/couplingProperties");
    let text = std::fs::read_to_string(&cp)
        .unwrap()
        .replace("\"B\"", "\"A\"")
        .replace(
            "    DiFeliceDrag\n    Archimedes\n",
            "    KochHillDrag\n    gradPForce\n    viscForce\n    Archimedes\n",
        );
    std::fs::write(
        &cp,
        format!(
            "{text}\nKochHillDragProps {{ }}\ngradPForceProps {{ }}\nviscForceProps {{ }}\n\
             twoWayMPIProps {{ liggghtsPath \"../DEM/in.liggghts_run\"; }}\n"
        ),
    )
    .unwrap();
    std::fs::write(case.join("CFD/constant/liggghtsCommands"), WRITE_LIGGGHTS).unwrap();
    set_control(case, "startTime", "0.01", "0.005");
}

/// Rewrites `CFD/system/controlDict`: `startFrom`, `endTime` and `writeInterval`.
pub fn set_control(case: &Path, start_from: &str, end: &str, write: &str) {
    let path = case.join("CFD/system/controlDict");
    let text: String = std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .map(|l| {
            let key = l.split_whitespace().next().unwrap_or("");
            match key {
                "startFrom" => format!("startFrom       {start_from};"),
                "endTime" => format!("endTime         {end};"),
                "writeInterval" => format!("writeInterval   {write};"),
                _ => l.to_owned(),
            }
        })
        .map(|l| l + "\n")
        .collect();
    std::fs::write(path, text).unwrap();
}

/// The tutorial's second half: `couplingProperties` names the deck that reads what
/// `writeLiggghts` wrote (`in.liggghts_restart`).
pub fn use_restart_deck(case: &Path) {
    let cp = case.join("CFD/constant/couplingProperties");
    let text = std::fs::read_to_string(&cp)
        .unwrap()
        .replace("in.liggghts_run", "in.liggghts_restart");
    std::fs::write(&cp, text).unwrap();
}

/// The settling case's gas made a viscous liquid (ν 1e-4 m²/s, ρ 1000 kg/m³, 0.1 Pa·s) in
/// `case`: with [`Bed::Suspended`] the spheres reach their Stokes speed, (ρp − ρ) g d² / (18 μ)
/// = 12 mm/s at Re 0.2, within τ = ρp d² / (18 μ) = 2.5 ms, a creeping flow in which a
/// perturbation decays (in the case's gas the spheres fall through cells at 0.1–0.3 m/s and
/// round-off grows).
pub fn viscous_liquid(case: &Path) {
    let tp = case.join("CFD/constant/transportProperties");
    let text = std::fs::read_to_string(&tp).unwrap();
    let text = text
        .replace("nu              1e-5;", "nu              1e-4;")
        .replace("rho             10;", "rho             1000;");
    assert!(text.contains("1e-4;") && text.contains("1000;"), "{text}");
    std::fs::write(&tp, text).unwrap();
}
