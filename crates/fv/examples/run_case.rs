//! Runs an OpenFOAM case with the native solver as its controlDict says and prints the time
//! per step: `cargo run --release -p fv --example run_case -- CASE`.

fn main() {
    let Some(dir) = std::env::args().nth(1) else {
        eprintln!("usage: run_case CASE");
        std::process::exit(2);
    };
    let run = || -> fv::Result<(usize, f64)> {
        let mut fluid = fv::Fluid::from_case(&dir)?;
        let t0 = std::time::Instant::now();
        let steps = fluid.run()?;
        Ok((steps, t0.elapsed().as_secs_f64()))
    };
    match run() {
        Ok((steps, secs)) => println!(
            "{steps} steps in {secs:.3} s ({:.3} ms/step)",
            1e3 * secs / steps.max(1) as f64
        ),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
