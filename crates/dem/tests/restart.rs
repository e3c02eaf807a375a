//! `read_restart` / `write_restart` on the native DEM, against files and runs of Debian's
//! LIGGGHTS 3.8.0 (`tests/fixtures/dem/restart/`, see its README).
//!
//! Fast tier: the restart file LIGGGHTS wrote is read into exactly the state LIGGGHTS's own
//! text shows (particles, pair and wall contact history); continuing it natively follows
//! LIGGGHTS continuing it; a native run continued from its own restart file is the
//! uninterrupted native run bit for bit; bad files are refused with file and byte. Full tier:
//! LIGGGHTS reads the files the native DEM writes (state and contact history as the native DEM
//! has them, then the same continuation), and a fresh LIGGGHTS run reproduces the committed
//! files that the fast tier compares with.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use dem::Simulation;
use dem_io::restart::{read_restart, write_restart_file, FixAtomData};
use dem_io::{read_snapshot, ReadOptions, Selection, Snapshot};
use liggghts_deck::Deck;
use mesh::v3::V3;

fn fixture(name: &str) -> PathBuf {
    testkit::fixture("dem/restart").join(name)
}

fn vars(v: &[(&str, &str)]) -> Vec<(String, String)> {
    v.iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

/// A directory with `post/` and the given fixtures copied in.
fn workdir(files: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("post")).unwrap();
    for f in files {
        std::fs::copy(fixture(f), dir.path().join(f)).unwrap();
    }
    dir
}

/// Runs the deck file `deck` with `v` natively in `dir` on `threads` threads.
fn native(dir: &Path, deck: &str, v: &[(&str, &str)], threads: usize) -> Simulation {
    let deck = Deck::read_with_vars(dir.join(deck), &vars(v)).unwrap();
    try_native(dir, &deck, threads).unwrap_or_else(|e| panic!("{e}"))
}

fn try_native(dir: &Path, deck: &Deck, threads: usize) -> Result<Simulation, dem::DemError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| Simulation::from_deck(deck, dir))
}

/// `continue.in` with `write_restart FILE` appended (after its final `run 0`), as
/// `continue_write.in` in `dir`.
fn continue_and_write(dir: &Path, file: &str) {
    let text = std::fs::read_to_string(fixture("continue.in")).unwrap();
    std::fs::write(
        dir.join("continue_write.in"),
        format!("{text}write_restart   {file}\n"),
    )
    .unwrap();
}

fn dump(path: &Path) -> Snapshot {
    read_snapshot(path, &ReadOptions::default(), Selection::Last).unwrap()
}

/// Per id: x y z vx vy vz ωx ωy ωz radius mass density type of a dump.
fn rows(s: &Snapshot) -> HashMap<u64, [f64; 13]> {
    let names = [
        "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "radius", "mass", "density",
        "type",
    ];
    let cols = names.map(|c| s.column(c).unwrap());
    s.column("id")
        .unwrap()
        .iter()
        .enumerate()
        .map(|(k, &id)| (id as u64, cols.map(|c| c[k])))
        .collect()
}

fn sim_rows(s: &Simulation) -> HashMap<u64, [f64; 13]> {
    let p = &s.particles;
    (0..p.len())
        .map(|i| {
            let (x, v, w) = (p.x[i], p.v[i], p.omega[i]);
            let row = [
                x[0],
                x[1],
                x[2],
                v[0],
                v[1],
                v[2],
                w[0],
                w[1],
                w[2],
                p.radius[i],
                p.mass[i],
                p.density[i],
                f64::from(p.atom_type[i]),
            ];
            (p.id[i], row)
        })
        .collect()
}

/// Largest differences of position (m), velocity (m/s) and angular velocity (rad/s); the
/// other columns must be equal.
fn max_diff(a: &HashMap<u64, [f64; 13]>, b: &HashMap<u64, [f64; 13]>) -> [f64; 3] {
    assert_eq!(a.len(), b.len());
    let mut d = [0.0f64; 3];
    for (id, ra) in a {
        let rb = b.get(id).unwrap_or_else(|| panic!("id {id} missing"));
        for k in 0..9 {
            d[k / 3] = d[k / 3].max((ra[k] - rb[k]).abs());
        }
        assert_eq!(ra[9..], rb[9..], "id {id}: radius, mass, density, type");
    }
    d
}

/// `dump local` rows of `compute pair/gran/local id history`: (id1, id2) → shear seen from id1.
fn local_contacts(path: &Path) -> HashMap<(u64, u64), [f64; 3]> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().skip_while(|l| !l.starts_with("ITEM: ENTRIES"));
    lines.next();
    lines
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            ((v[0] as u64, v[1] as u64), [v[3], v[4], v[5]])
        })
        .collect()
}

/// The native pair contacts equal LIGGGHTS's list: the same pairs, the same history bits
/// (negated when the pair is seen from the other side).
fn assert_same_contacts(sim: &Simulation, theirs: &HashMap<(u64, u64), [f64; 3]>) {
    let id = &sim.particles.id;
    let ours = sim.pair_contacts();
    assert_eq!(ours.len(), theirs.len(), "number of contacts");
    for (i, j, h) in ours {
        let (a, b) = (id[i], id[j]);
        let s: [f64; 3] = h.shear.into();
        match (theirs.get(&(a, b)), theirs.get(&(b, a))) {
            (Some(t), _) => assert_eq!(&s, t, "{a}–{b}"),
            (_, Some(t)) => assert_eq!(s, t.map(|v| -v), "{b}–{a}"),
            _ => panic!("{a}–{b} is not a LIGGGHTS contact"),
        }
    }
}

/// The native wall histories equal the `f_history_W[k]` columns of a LIGGGHTS dump.
fn assert_same_wall_history(sim: &Simulation, s: &Snapshot) -> usize {
    let row: HashMap<u64, usize> = s
        .column("id")
        .unwrap()
        .iter()
        .enumerate()
        .map(|(k, &id)| (id as u64, k))
        .collect();
    let nw = sim.walls().len();
    assert_eq!(nw, 5);
    let mut touching = 0;
    for (i, &id) in sim.particles.id.iter().enumerate() {
        for (w, wall) in sim.walls().iter().enumerate() {
            let h = sim.wall_history()[i * nw + w].shear;
            for k in 0..3 {
                let col = s
                    .column(&format!("f_history_{}[{}]", wall.name, k + 1))
                    .unwrap();
                assert_eq!(h[k], col[row[&id]], "particle {id}, wall {}", wall.name);
            }
            touching += usize::from(h != mesh::v3::V3::zeros());
        }
    }
    touching
}

/// `read_restart` of LIGGGHTS's file gives the state LIGGGHTS's own text of that step shows:
/// every particle value and both contact histories bit for bit, and the step. The pair style
/// comes from the file when the deck gives none. What the native DEM does not take over is
/// named in warnings.
#[test]
fn liggghts_restart_is_read_into_liggghts_state() {
    let dir = workdir(&["continue.in", "restart.25000"]);
    let sim = native(dir.path(), "continue.in", &[("n", "0")], 1);
    assert_eq!(sim.step(), 25000);
    let state = dump(&fixture("state.txt"));
    assert_eq!(max_diff(&sim_rows(&sim), &rows(&state)), [0.0; 3]);
    assert_same_contacts(&sim, &local_contacts(&fixture("contacts.txt")));
    assert!(assert_same_wall_history(&sim, &state) >= 10);
    let w = sim.warnings().join("\n");
    assert!(w.is_empty(), "{w}");
    // the templates' and the insertion's saved state is reported as not restored
    let deck = Deck::read_with_vars(dir.path().join("continue.in"), &vars(&[("n", "0")])).unwrap();
    let mut warnings = Vec::new();
    Simulation::from_deck_observed(&deck, dir.path(), &mut |e| {
        if let dem::deck::exec::DeckEvent::Warning { line, message } = e {
            warnings.push((line, message));
        }
    })
    .unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].1.contains("pts1 (particletemplate/sphere)")
            && warnings[0].1.contains("ins (insert/pack)")
            && warnings[0].1.contains("restart.25000"),
        "{warnings:?}"
    );

    // without pair_style / pair_coeff the file's `gran model hertz tangential history` is used
    let text = std::fs::read_to_string(fixture("continue.in")).unwrap();
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("pair_"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path().join("nopair.in"), text).unwrap();
    let a = native(dir.path(), "continue.in", &[("n", "300")], 1);
    let b = native(dir.path(), "nopair.in", &[("n", "300")], 1);
    assert_eq!(max_diff(&sim_rows(&a), &sim_rows(&b)), [0.0; 3]);
}

/// Continued natively, LIGGGHTS's file follows LIGGGHTS continuing it: both evaluate the
/// first forces the same way (LIGGGHTS's set-up) and then the same contact law. After 100
/// steps (`continued_25100.txt`) they agree to round-off — measured: positions identical,
/// velocities 6.9e-18 m/s, ω 2.8e-14 rad/s apart; bound 1e-15 m, 1e-12 m/s, 1e-9 rad/s.
///
/// Later they part at a discrete event: the native DEM resets a pair's tangential history
/// when the spheres separate, LIGGGHTS 3.8 keeps it until its next neighbour-list build, and
/// here spheres 29 and 30 separate at step 25066 and touch again at step 25135 before a
/// rebuild. After 2000 steps (`continued_27000.txt`) the difference — measured 7.4e-8 m,
/// 6.2e-4 m/s, 1.03 rad/s — is of the size by which LIGGGHTS's continued run differs from its
/// uninterrupted one (1.0e-7 m, 5.6e-4 m/s, 0.86 rad/s, README): bound at twice that.
#[test]
fn liggghts_restart_continues_as_liggghts_continues_it() {
    let unint = rows(&dump(&fixture("uninterrupted_27000.txt")));
    let cont = rows(&dump(&fixture("continued_27000.txt")));
    let spread = max_diff(&cont, &unint);
    for threads in [1, 2] {
        let dir = workdir(&["continue.in", "restart.25000"]);
        let sim = native(dir.path(), "continue.in", &[("n", "100")], threads);
        assert_eq!(sim.step(), 25100);
        let ours = rows(&dump(&dir.path().join("post/continued.txt")));
        let d = max_diff(&ours, &rows(&dump(&fixture("continued_25100.txt"))));
        eprintln!("{threads} threads, 100 steps: native vs LIGGGHTS continued {d:?}");
        assert!(d[0] <= 1e-15 && d[1] < 1e-12 && d[2] < 1e-9, "{d:?}");

        native(dir.path(), "continue.in", &[("n", "2000")], threads);
        let ours = rows(&dump(&dir.path().join("post/continued.txt")));
        let d = max_diff(&ours, &cont);
        eprintln!(
            "{threads} threads, 2000 steps: native vs LIGGGHTS continued {d:?}, vs \
             uninterrupted {:?}; LIGGGHTS continued vs uninterrupted {spread:?}",
            max_diff(&ours, &unint)
        );
        for k in 0..3 {
            assert!(d[k] < 2.0 * spread[k], "{d:?} vs {spread:?}");
        }
    }
}

/// A native run continued from its own restart file is the uninterrupted run, bit for bit,
/// on one thread and on two. The per-particle contact sums run in the spatial order of the
/// last list build (`pair_loop`), which the continued run makes afresh at its first step: the
/// two agree bit for bit because on this settled bed that build gives the order the
/// uninterrupted run's list has (a run whose particles have moved between the two builds
/// differs by round-off). The
/// file's half-step block lets the set-up use the forces of the file's step. Without it the set-up is LIGGGHTS's, and the continuation drifts like
/// LIGGGHTS's own (measured 4.0e-8 m, 2.0e-4 m/s after 1000 steps).
#[test]
fn native_run_continued_from_its_restart_file_is_the_uninterrupted_run() {
    for threads in [1, 2] {
        let n = "1000";
        let dir = workdir(&["continue.in", "restart.25000"]);
        let d = dir.path();
        native(d, "continue.in", &[("n", "2000")], threads);
        let whole = rows(&dump(&d.join("post/continued.txt")));

        continue_and_write(d, "post/restart/native.*");
        native(d, "continue_write.in", &[("n", n)], threads);
        let file = d.join("post/restart/native.26000");
        assert!(file.is_file(), "`*` is the step; directories are made");
        let sim = native(
            d,
            "continue.in",
            &[("n", n), ("restart", "post/restart/native.*")],
            threads,
        );
        assert!(sim.warnings().is_empty(), "{:?}", sim.warnings());
        let split = rows(&dump(&d.join("post/continued.txt")));
        let diff = max_diff(&split, &whole);
        eprintln!("{threads} threads: continued vs uninterrupted {diff:?}");
        assert_eq!(diff, [0.0; 3]);

        // the same file without its half-step block continues as LIGGGHTS would
        let mut f = read_restart(&file).unwrap();
        let k = f.peratom_fix("foamgrain_halfstep").unwrap();
        let recorded: Vec<[f64; 12]> = f
            .atoms
            .iter()
            .map(|a| match &a.fix_data[k] {
                FixAtomData::Values(v) => std::array::from_fn(|j| v[j]),
                FixAtomData::Contacts(_) => panic!("values expected"),
            })
            .collect();
        f.peratom_fixes.remove(k);
        for a in &mut f.atoms {
            a.fix_data.remove(k);
        }
        write_restart_file(&d.join("stripped.26000"), &f).unwrap();
        native(
            d,
            "continue.in",
            &[("n", n), ("restart", "stripped.26000")],
            threads,
        );
        let drift = max_diff(&rows(&dump(&d.join("post/continued.txt"))), &whole);
        eprintln!("{threads} threads: without the half-step block {drift:?}");
        assert!(drift[1] > 1e-9, "{drift:?}");

        // a deck that changes the set-up (twice the gravity) gets the forces of its own set-up
        // at the half-step velocities: the recorded ones plus m·Δg
        let text = std::fs::read_to_string(fixture("continue.in"))
            .unwrap()
            .replace("gravity 9.81", "gravity 19.62");
        std::fs::write(d.join("heavier.in"), text).unwrap();
        let sim = native(
            d,
            "heavier.in",
            &[("n", "0"), ("restart", "post/restart/native.26000")],
            threads,
        );
        let p = &sim.particles;
        let ids: HashMap<u64, usize> = p.id.iter().enumerate().map(|(i, &id)| (id, i)).collect();
        for (a, r) in f.atoms.iter().zip(&recorded) {
            let i = ids[&a.tag];
            let df = p.f[i] - mesh::v3::V3::new(r[6], r[7], r[8]);
            let want = mesh::v3::V3::new(0.0, 0.0, -9.81 * p.mass[i]);
            assert!(
                (df - want).norm() < 1e-9 * want.norm(),
                "{df:?} vs {want:?}"
            );
        }
    }
}

/// The coupling forces of the k-th interval for the particles of `sim` (index order): an
/// explicit force of about twice the weight, sideways from k = 1, and a drag β = 50 m (1/s,
/// β·dt/m = 5e-5) towards a fluid velocity that grows with k.
fn coupling_of(sim: &Simulation, k: u32) -> (Vec<V3>, Vec<f64>, Vec<V3>) {
    let p = &sim.particles;
    let k = f64::from(k);
    let f_ext = p
        .mass
        .iter()
        .map(|&m| m * V3::new(0.5 * k, 0.0, 20.0))
        .collect();
    let beta = p.mass.iter().map(|m| 50.0 * m).collect();
    let u_f = (0..p.len()).map(|_| V3::new(0.0, 0.01 * k, 0.02)).collect();
    (f_ext, beta, u_f)
}

/// CFDEM's `writeLiggghts` writes the state after an exchange, when the DEM already holds the
/// next interval's coupling forces: a coupled native run continued from that file (the
/// coupling forces read back from LIGGGHTS's `dragforce`, `Ksl`, `uf` blocks, the coupling part
/// of the last forces from the half-step block) is the uninterrupted run bit for bit
/// (measured: 0 after 2 + 2 intervals of 100 steps, on one thread).
#[test]
fn coupled_run_continued_from_its_restart_file_is_the_uninterrupted_run() {
    let dir = workdir(&["continue.in", "restart.25000"]);
    let d = dir.path();
    let text = std::fs::read_to_string(fixture("continue.in"))
        .unwrap()
        .replace(
            "fix             integr",
            "fix             cfd all couple/cfd couple_every 100 mpi\n\
             fix             cfd2 all couple/cfd/force/implicit\n\
             fix             integr",
        );
    std::fs::write(d.join("coupled.in"), text).unwrap();
    let interval = |sim: &mut Simulation, k: u32, set: bool| {
        if set {
            let (f, b, u) = coupling_of(sim, k);
            sim.set_coupling(&f, &b, &u).unwrap();
        }
        sim.run(100).unwrap();
    };
    let mut whole = native(d, "coupled.in", &[("n", "0")], 1);
    for k in 0..4 {
        interval(&mut whole, k, true);
    }
    let mut first = native(d, "coupled.in", &[("n", "0")], 1);
    for k in 0..2 {
        interval(&mut first, k, true);
    }
    let (f, b, u) = coupling_of(&first, 2);
    first.set_coupling(&f, &b, &u).unwrap();
    dem::deck::restart::write(&first, "post/restart/coupled.restart", d).unwrap();
    let file = d.join("post/restart/coupled.restart");
    let restart = read_restart(&file).unwrap();
    for id in ["dragforce", "Ksl", "uf"] {
        assert!(restart.peratom_fix(id).is_some(), "{id}");
    }
    let mut second = native(
        d,
        "coupled.in",
        &[("n", "0"), ("restart", "post/restart/coupled.restart")],
        1,
    );
    assert!(second.warnings().is_empty(), "{:?}", second.warnings());
    assert_eq!(second.coupling().beta, b, "Ksl read back as β");
    for k in 2..4 {
        // the third interval's coupling comes from the file
        interval(&mut second, k, k > 2);
    }
    let diff = max_diff(&sim_rows(&second), &sim_rows(&whole));
    eprintln!("coupled, continued vs uninterrupted {diff:?}");
    assert_eq!(diff, [0.0; 3]);

    // the same deck without the coupling fixes drops the saved coupling forces, and says so
    let deck = Deck::read_with_vars(
        d.join("continue.in"),
        &vars(&[("n", "0"), ("restart", "post/restart/coupled.restart")]),
    )
    .unwrap();
    let mut warnings = Vec::new();
    let plain = Simulation::from_deck_observed(&deck, d, &mut |e| {
        if let dem::deck::exec::DeckEvent::Warning { message, .. } = e {
            warnings.push(message);
        }
    })
    .unwrap();
    assert!(!plain.coupling().is_active());
    assert!(
        warnings.iter().any(|w| w.contains("dragforce")),
        "{warnings:?}"
    );
}

/// A restart file written by the native DEM holds LIGGGHTS's layout and the state: read back
/// natively it gives the same particles and histories.
#[test]
fn written_file_holds_the_state() {
    let dir = workdir(&["continue.in", "restart.25000"]);
    let d = dir.path();
    continue_and_write(d, "post/native.restart");
    let sim = native(d, "continue_write.in", &[("n", "500")], 1);
    let f = read_restart(d.join("post/native.restart")).unwrap();
    assert_eq!(f.header.timestep, 25500);
    assert_eq!(f.header.atom_style, "granular");
    assert!(f
        .header
        .version
        .starts_with("Version LIGGGHTS-PUBLIC 3.8.0, written by foamgrain"));
    let ids: Vec<&str> = f.peratom_fixes.iter().map(|p| p.id.as_str()).collect();
    assert_eq!(
        ids,
        [
            "history_floor",
            "history_xlo",
            "history_xhi",
            "history_ylo",
            "history_yhi",
            "contacthistory",
            "foamgrain_halfstep"
        ]
    );
    let back = native(
        d,
        "continue.in",
        &[("n", "0"), ("restart", "post/native.restart")],
        1,
    );
    assert_eq!(max_diff(&sim_rows(&back), &sim_rows(&sim)), [0.0; 3]);
    assert_eq!(back.pair_contacts(), sim.pair_contacts());
    assert_eq!(back.wall_history(), sim.wall_history());
}

/// Bad files stop the deck with an error naming the deck line, the restart file and the byte.
#[test]
fn bad_restart_files_are_refused_with_file_and_byte() {
    let dir = workdir(&["continue.in", "restart.25000", "state.txt"]);
    let d = dir.path();
    let bytes = std::fs::read(fixture("restart.25000")).unwrap();
    std::fs::write(d.join("cut.restart"), &bytes[..9000]).unwrap();
    let mut style = bytes.clone();
    let at = style.windows(9).position(|w| w == b"granular\0").unwrap();
    style[at..at + 9].copy_from_slice(b"ellipsoi\0");
    std::fs::write(d.join("style.restart"), &style).unwrap();
    for (file, what) in [
        ("cut.restart", "file ends early"),
        ("state.txt", "not a LIGGGHTS restart file"),
        ("style.restart", "atom style `ellipsoi`"),
        ("missing.restart", "No such file"),
    ] {
        let deck =
            Deck::read_with_vars(d.join("continue.in"), &vars(&[("restart", file)])).unwrap();
        let e = try_native(d, &deck, 1).unwrap_err().to_string();
        assert!(e.contains("continue.in:18"), "{e}");
        assert!(e.contains(file) && e.contains(what), "{e}");
        if file != "missing.restart" {
            assert!(e.contains(" (byte "), "{e}");
        }
    }
    // multisphere bodies are refused, not read as loose spheres
    let mut f = read_restart(fixture("restart.25000")).unwrap();
    f.global_fixes.push(dem_io::restart::FixState::from_values(
        "ms",
        "multisphere",
        &[1.0],
    ));
    write_restart_file(&d.join("ms.restart"), &f).unwrap();
    let deck =
        Deck::read_with_vars(d.join("continue.in"), &vars(&[("restart", "ms.restart")])).unwrap();
    let e = try_native(d, &deck, 1).unwrap_err().to_string();
    assert!(
        e.contains("ms.restart") && e.contains("multisphere bodies"),
        "{e}"
    );
    // a history of another contact model is refused, as LIGGGHTS refuses it
    let text = std::fs::read_to_string(fixture("continue.in"))
        .unwrap()
        .replace(
        "pair_style      gran model hertz tangential history",
        "fix m5 all property/global coefficientRollingFriction peratomtypepair 2 0.1 0.1 0.1 0.1\n\
             pair_style      gran model hertz tangential history rolling_friction epsd2",
    );
    std::fs::write(d.join("epsd2.in"), text).unwrap();
    let deck = Deck::read(d.join("epsd2.in")).unwrap();
    let e = try_native(d, &deck, 1).unwrap_err().to_string();
    assert!(
        e.contains("restart.25000") && e.contains("3 values per contact"),
        "{e}"
    );
}

/// Full tier: LIGGGHTS reads a file the native DEM wrote after continuing LIGGGHTS's file for
/// 500 steps and takes up exactly the native state: particles, pair contacts and wall
/// histories bit for bit (its `run 0` dumps). Then LIGGGHTS continues it 100 steps; the
/// native DEM continuing the same file as LIGGGHTS does (without its half-step block) agrees
/// within the round-off bounds of `liggghts_restart_continues_as_liggghts_continues_it`.
#[test]
fn liggghts_reads_native_restart_files() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = workdir(&["continue.in", "restart.25000", "readback.in"]);
    let d = dir.path();
    continue_and_write(d, "native.*");
    let sim = native(d, "continue_write.in", &[("n", "500")], 1);
    let mut c = Command::new("liggghts");
    c.args(["-in", "readback.in", "-var", "restart", "native.25500"])
        .args(["-log", "none", "-screen", "readback.screen"]);
    testkit::run_ok(c, d);
    let state = dump(&d.join("post/readback.txt"));
    assert_eq!(state.timestep, 25500);
    assert_eq!(max_diff(&rows(&state), &sim_rows(&sim)), [0.0; 3]);
    assert_same_contacts(&sim, &local_contacts(&d.join("post/readback_contacts.txt")));
    assert!(assert_same_wall_history(&sim, &state) >= 5);

    let mut c = Command::new("liggghts");
    c.args([
        "-in",
        "continue.in",
        "-var",
        "restart",
        "native.25500",
        "-var",
        "n",
        "100",
    ])
    .args(["-log", "none", "-screen", "continue.screen"]);
    testkit::run_ok(c, d);
    let theirs = rows(&dump(&d.join("post/continued.txt")));
    let mut f = read_restart(d.join("native.25500")).unwrap();
    let k = f.peratom_fix("foamgrain_halfstep").unwrap();
    f.peratom_fixes.remove(k);
    for a in &mut f.atoms {
        a.fix_data.remove(k);
    }
    write_restart_file(&d.join("stripped.25500"), &f).unwrap();
    native(
        d,
        "continue.in",
        &[("n", "100"), ("restart", "stripped.25500")],
        1,
    );
    let ours = rows(&dump(&d.join("post/continued.txt")));
    let diff = max_diff(&ours, &theirs);
    eprintln!("LIGGGHTS vs native continuing a native file 100 steps: {diff:?}");
    assert!(
        diff[0] <= 1e-15 && diff[1] < 1e-12 && diff[2] < 1e-9,
        "{diff:?}"
    );
}

/// Full tier: a fresh LIGGGHTS run of the fixture decks reproduces the committed restart
/// file byte for byte and the committed continuations exactly (serial LIGGGHTS is
/// deterministic), so the fast-tier comparisons hold against LIGGGHTS itself.
#[test]
fn liggghts_rerun_reproduces_the_fixtures() {
    if !testkit::tool("liggghts") {
        return;
    }
    let dir = workdir(&["pack.in", "continue.in"]);
    let d = dir.path();
    let mut c = Command::new("liggghts");
    c.args(["-in", "pack.in", "-log", "none", "-screen", "pack.screen"]);
    testkit::run_ok(c, d);
    let fresh = std::fs::read(d.join("post/restart.25000")).unwrap();
    assert!(fresh == std::fs::read(fixture("restart.25000")).unwrap());
    std::fs::copy(d.join("post/restart.25000"), d.join("restart.25000")).unwrap();
    for (n, committed) in [
        ("100", "continued_25100.txt"),
        ("2000", "continued_27000.txt"),
    ] {
        let mut c = Command::new("liggghts");
        c.args(["-in", "continue.in", "-var", "n", n]).args([
            "-log",
            "none",
            "-screen",
            "continue.screen",
        ]);
        testkit::run_ok(c, d);
        let theirs = rows(&dump(&d.join("post/continued.txt")));
        assert_eq!(
            max_diff(&theirs, &rows(&dump(&fixture(committed)))),
            [0.0; 3]
        );
    }
}
