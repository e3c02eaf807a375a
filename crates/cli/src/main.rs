//! `foamgrain`: the command-line front end. It only wires the library crates together and turns
//! their typed errors into messages and exit codes (1 for a failed command, 2 for bad usage).

mod args;
mod convert;
mod info;
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
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(a) => info::run(&a),
        Command::Convert(c) => convert::run(&c),
        Command::Voidage(a) => voidage::run(&a),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
