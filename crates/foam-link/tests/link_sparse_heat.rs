//! Heat over the sparse exchange (issue 27; full tier): the heat channel (a porous block
//! 40 mm < x < 60 mm, ε 0.6, Ksl 500 kg/(m³ s), cooled by Tsource = −5 K/s; three intervals
//! of 10 steps of 10 ms) driven by 2 coupler ranks × 2 grainPisoFoam ranks
//! (`examples/sparse_heat.rs` under `mpirun -np 2`: the ranks' Ksl and Tsource shares add up
//! to the same fields, in cells on both solver ranks) against 1 coupler rank with the dense
//! exchange on 2 solver ranks: T after the run, the T the sparse reply carried after two
//! intervals (the dense run's T then) and the outlet's Σ φ and Σ φ T_b after every interval
//! (the sparse run's patch reply with heat) agree to solver tolerance; so do U of every third
//! cell and max |U|/∛V that the watch (protocol v3) gave rank 0 after two intervals, against the
//! dense run's U then (max |U|/∛V over its cells with the coupler's cell volumes).

mod common;
use common::*;
use foam_link::{OpenFoamFluid, SpawnOptions};
use foam_solver_tests::TestCase;
use std::collections::BTreeMap;
use std::process::Command;

/// What the example wrote (its module docs): reply T per cell, outlet sums per interval, T.
#[derive(Default)]
struct Sparse {
    reply_t: BTreeMap<usize, f64>,
    watch_u: Vec<(usize, [f64; 3])>,
    watch_cfl: Option<f64>,
    outlet: Vec<(f64, f64)>,
    t: Vec<f64>,
}

fn parse(text: &str) -> Sparse {
    let mut s = Sparse::default();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let num = |k: usize| -> f64 { w[k].parse().unwrap() };
        match w[0] {
            "reply_T" => {
                s.reply_t.insert(w[1].parse().unwrap(), num(2));
            }
            "outlet" => s.outlet.push((num(2), num(3))),
            "watch_U" => s
                .watch_u
                .push((w[1].parse().unwrap(), [num(2), num(3), num(4)])),
            "watch_cfl" => s.watch_cfl = Some(num(1)),
            "T" => s.t.push(num(2)),
            other => panic!("unexpected line {other}"),
        }
    }
    s
}

/// The example under `mpirun -np 2` on a copy of `case`.
fn sparse_run(case: &TestCase, solver: &std::path::Path) -> Sparse {
    // built next to this test's binary: target/debug/{deps,examples}
    let exe = std::env::current_exe().unwrap();
    let example = exe.ancestors().nth(2).unwrap().join("examples/sparse_heat");
    assert!(example.is_file(), "{} not built", example.display());
    let copy = case.duplicate();
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("sparse.txt");
    let out = Command::new("mpirun")
        .args(["-np", "2", "--oversubscribe"])
        .arg(&example)
        .arg(&copy.dir)
        .arg(solver)
        .arg(&out_path)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    parse(&std::fs::read_to_string(&out_path).unwrap())
}

#[test]
fn two_coupler_ranks_with_heat_equal_one() {
    let Some(solver) = tools() else {
        return;
    };
    let case = TestCase::new("heat-channel");
    // before this process initialises MPI: mpirun's children are not its spawn
    let sparse = sparse_run(&case, &solver);
    let universe = universe();
    let world = universe.world();

    let channel = HeatChannel::new(&case);
    let block = &channel.block;
    let copy = case.duplicate();
    let heat = SpawnOptions {
        heat: true,
        cfdem_ksl: None,
        vorticity: false,
        ddt_u: false,
    };
    let mut fluid = OpenFoamFluid::spawn_with(&world, &copy.dir, 2, &solver, heat).unwrap();
    let mut after_two = Vec::new();
    let mut u_two = Vec::new();
    let mut outlet = Vec::new();
    for i in 0..3 {
        if i == 2 {
            after_two = fluid.temperature().unwrap().to_vec();
            u_two = couple::FluidSide::state(&fluid).u.to_vec();
        }
        fluid
            .set_fields_with_heat(&channel.fields(i), Some(&channel.tsource))
            .unwrap();
        fluid.advance_interval(0.1).unwrap();
        let o = fluid.patch("outlet").unwrap();
        outlet.push((o.flux, o.t_flux.unwrap()));
    }
    let dense = fluid.temperature().unwrap().to_vec();
    fluid.finish().unwrap();

    let dt = rel_diff(&sparse.t, &dense);
    let cooled = dense.iter().cloned().fold(f64::MAX, f64::min);
    assert_eq!(sparse.reply_t.len(), block.iter().filter(|&&b| b).count());
    let (cells, reply): (Vec<usize>, Vec<f64>) = sparse.reply_t.into_iter().unzip();
    let dense_two: Vec<f64> = cells.iter().map(|&c| after_two[c]).collect();
    let dreply = rel_diff(&reply, &dense_two);
    eprintln!(
        "sparse heat, 2 coupler × 2 solver ranks vs dense 1 × 2: T {dt:.2e}, reply T after two \
         intervals {dreply:.2e}; min T {cooled} K; outlet (Σφ, Σφ T_b) sparse {:?} dense {outlet:?}",
        sparse.outlet
    );
    // the block is cooled (the source reached the solver): below the initial 0 K by a
    // fraction of 5 K/s × 0.3 s / ε
    assert!(cooled < -0.5, "min T {cooled}");
    assert!(dt < 1e-8, "T {dt:e}");
    assert!(dreply < 1e-8, "reply T {dreply:e}");
    // the watch: every third cell, last first, on both solver ranks
    let n = u_two.len();
    assert_eq!(sparse.watch_u.len(), n.div_ceil(3));
    assert_eq!(sparse.watch_u[0].0, n - 1);
    let mut du: f64 = 0.0;
    for &(c, u) in &sparse.watch_u {
        let d = u_two[c];
        for k in 0..3 {
            du = du.max((u[k] - d[k]).abs() / d.norm().max(1e-12));
        }
    }
    let volumes = copy.mesh().1.cell_volumes;
    let cfl = u_two
        .iter()
        .zip(&volumes)
        .map(|(u, v)| u.norm() / v.cbrt())
        .fold(0.0, f64::max);
    let watch_cfl = sparse.watch_cfl.unwrap();
    eprintln!("watch: U {du:.2e} of |U|; max |U|/∛V {watch_cfl} vs dense {cfl}");
    assert!(cfl > 0.0 && du < 1e-8, "watched U {du:e}");
    assert!(
        (watch_cfl - cfl).abs() <= 1e-8 * cfl,
        "max |U|/∛V {watch_cfl} vs {cfl}"
    );
    assert_eq!(sparse.outlet.len(), 3);
    for ((f, tf), (g, tg)) in sparse.outlet.iter().zip(&outlet) {
        assert!((f - g).abs() <= 1e-8 * g.abs(), "outlet flux {f} vs {g}");
        assert!(
            (tf - tg).abs() <= 1e-8 * tg.abs().max(1e-12),
            "outlet Σφ T_b {tf} vs {tg}"
        );
    }
}
