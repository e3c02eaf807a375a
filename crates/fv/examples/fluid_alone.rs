//! Runs the native fluid alone on a case directory, step by step, printing per step the
//! largest |U|, k, ε, νt and the Courant numbers (diagnostics for stability studies):
//! `cargo run --release -p fv --example fluid_alone -- CASE [STEPS] [WRITE_EVERY]`.

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = args
        .get(1)
        .expect("usage: fluid_alone CASE [STEPS] [WRITE_EVERY]");
    let mut fluid = fv::Fluid::from_case(dir).unwrap_or_else(|e| panic!("{e}"));
    let steps: usize = args.get(2).map_or(10, |s| s.parse().unwrap());
    let every: usize = args.get(3).map_or(usize::MAX, |s| s.parse().unwrap());
    let dt = fluid.settings.delta_t;
    for step in 1..=steps {
        let r = fluid.advance(dt);
        let umax = fluid.u().iter().map(|v| v.norm()).fold(0.0, f64::max);
        let (imax, _) = fluid.u().iter().enumerate().fold((0, 0.0), |m, (i, v)| {
            if v.norm() > m.1 {
                (i, v.norm())
            } else {
                m
            }
        });
        let co = fv::courant::courant(fluid.geometry(), fluid.phi(), dt);
        let (kmax, emax, ntmax) = fluid.turbulence().map_or((0.0, 0.0, 0.0), |t| {
            let m = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (m(t.k()), m(t.epsilon()), m(t.nut()))
        });
        println!(
            "step {step} t {:.6} |U|max {umax:.4} at cell {imax} k {kmax:.4e} eps {emax:.4e} nut {ntmax:.4e} Co {:.4}/{:.4}",
            fluid.time(),
            co.mean,
            co.max
        );
        match r {
            Ok(rep) => {
                if step % every == 0 {
                    fluid.write(&fluid.time_name()).unwrap();
                }
                let _ = rep;
            }
            Err(e) => {
                println!("step {step} failed: {e}");
                fluid.write(&fluid.time_name()).unwrap();
                std::process::exit(1);
            }
        }
    }
    fluid.write(&fluid.time_name()).unwrap();
}
