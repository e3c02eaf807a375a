//! Runs a LIGGGHTS deck with the native DEM, in the deck's directory (as `liggghts -in` run
//! there would).
//!
//! `cargo run --release -p dem --example run_deck -- DECK [-var NAME VALUE]…`

use std::path::Path;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(deck_path) = args.first() else {
        eprintln!("usage: run_deck DECK [-var NAME VALUE]…");
        std::process::exit(2);
    };
    let mut vars = Vec::new();
    let mut k = 1;
    while k < args.len() {
        if args[k] == "-var" && k + 2 < args.len() {
            vars.push((args[k + 1].clone(), args[k + 2].clone()));
            k += 3;
        } else {
            eprintln!("unexpected argument `{}`", args[k]);
            std::process::exit(2);
        }
    }
    let deck = match dem::deck::Deck::read_with_vars(deck_path, &vars) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    let dir = Path::new(deck_path)
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let t0 = Instant::now();
    match dem::Simulation::from_deck(&deck, dir) {
        Ok(sim) => {
            let secs = t0.elapsed().as_secs_f64();
            println!(
                "step {} (t = {:.6} s): {} particles, {} lost, kinetic energy {:.6e} J, \
                 {:.2} s wall time on {} threads",
                sim.step(),
                sim.time(),
                sim.particles.len(),
                sim.lost(),
                sim.particles.kinetic_energy(),
                secs,
                rayon::current_num_threads()
            );
            for w in sim.warnings() {
                println!("warning: {w}");
            }
            if let Some(c) = deck.coupling() {
                println!(
                    "coupled deck: couple_every {}, {} force fix",
                    c.couple_every,
                    if c.implicit { "implicit" } else { "explicit" }
                );
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
