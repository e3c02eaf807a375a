//! `foamgrain`: the command-line front end. It only wires the library crates together and turns
//! their typed errors into messages and exit codes: 0 done (and every check passed), 1 an error
//! (bad usage included), 2 a run that completed with a failed check.

mod args;
mod convert;
mod couple;
mod dem;
mod fluid;
mod gci;
mod info;
mod progress;
mod run;
mod study;
mod timestep;
mod voidage;

use clap::{Parser, Subcommand};

/// foamgrain: CFD-DEM coupling of OpenFOAM and LIGGGHTS, with exact voidage.
#[derive(Parser)]
#[command(name = "foamgrain", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Summarise an OpenFOAM case: mesh size, patches, total volume, bounding box, times.
    Info(info::InfoArgs),
    /// Convert LIGGGHTS dumps and OpenFOAM cases to VTK files for ParaView.
    #[command(subcommand)]
    Convert(convert::ConvertCommand),
    /// Void fraction of a LIGGGHTS snapshot on an OpenFOAM mesh, written as `voidfraction`.
    Voidage(voidage::VoidageArgs),
    /// One-way coupling of LIGGGHTS dumps with a frozen fluid: writes voidfraction, Ksl, Us, f
    /// and the particle forces per dump time.
    Couple(couple::CoupleArgs),
    /// DEM, CFD and coupling time-step advice (Rayleigh, Hertz, relaxation time, CFL).
    Timestep(timestep::TimestepArgs),
    /// Run a LIGGGHTS deck on the native DEM, as `liggghts -in DECK` would: thermo lines,
    /// dumps, write_data, a progress bar (`foamgrain dem DECK -var NAME VALUE …`).
    Dem(dem::DemArgs),
    /// Run the native fluid alone on a plain OpenFOAM case (pisoFoam, icoFoam), writing time
    /// directories as OpenFOAM does, to put it side by side with OpenFOAM.
    Fluid(fluid::FluidArgs),
    /// Run a coupled CFD-DEM case (CFDEM layout: CASE/CFD, CASE/DEM) and check it against
    /// its references (CASE/validationDict). `mpirun -np N foamgrain run CASE --dem liggghts`
    /// runs LIGGGHTS on N ranks, each coupling its own particles (the native fluid on rank 0;
    /// grainPisoFoam on its own ranks, each coupler rank exchanging straight with them).
    Run(run::RunArgs),
    /// Grid Convergence Index (Celik et al. 2008) of a grid-refinement study from a CSV table.
    Gci(gci::GciArgs),
    /// Studies over many runs of a case (`study cellsize`: the cell-size study of a frozen bed).
    #[command(subcommand)]
    Study(study::StudyCommand),
}

fn main() {
    restore_default_sigpipe();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // --help and --version exit 0; bad usage is an error like any other (exit 1)
        Err(e) if e.exit_code() == 0 => e.exit(),
        Err(e) => {
            let _ = e.print();
            std::process::exit(1);
        }
    };
    let result = match cli.command {
        Command::Info(a) => info::run(&a),
        Command::Convert(c) => convert::run(&c),
        Command::Voidage(a) => voidage::run(&a),
        Command::Couple(a) => couple::run(&a),
        Command::Timestep(a) => timestep::run(&a),
        Command::Run(a) => run::run(&a),
        Command::Dem(a) => dem::run(&a),
        Command::Fluid(a) => fluid::run(&a),
        Command::Gci(a) => gci::run(&a),
        Command::Study(c) => study::run(&c),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(exit_code(&e));
    }
}

/// 2 when a run completed and a check failed ([`run::ChecksFailed`]), 1 for any other error.
fn exit_code(e: &anyhow::Error) -> i32 {
    if e.downcast_ref::<run::ChecksFailed>().is_some() {
        2
    } else {
        1
    }
}

/// A closed pipe ends foamgrain quietly, as it ends `cat` or `grep` (`foamgrain timestep | head`):
/// Rust's runtime ignores SIGPIPE, which turns the closed pipe into a panic in `println!`.
fn restore_default_sigpipe() {
    // SAFETY: called first in `main`, before any thread exists; SIG_DFL is a valid disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
