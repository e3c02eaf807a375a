//! The deck commands the native DEM executes: one table row per LIGGGHTS command (its name
//! and aliases, and what it does), the handlers in a module per family — [`setup`] (units,
//! box, boundary, regions, data and restart files, neighbour lists, time step, pair style),
//! [`atoms`] (creating, changing and deleting particles), [`output`] (log, print, thermo,
//! computes, dumps, data and restart files written) and [`run`]; `fix` and `unfix` are
//! [`super::fixes`]'. Adding a command is one row here and one handler.

use liggghts_deck::Command;

use super::{coarse_graining, fixes, Failure, Session};

mod atoms;
mod output;
mod run;
mod setup;

/// What a command does when executed (`Session::line` is set to its deck line first).
type Handler = fn(&mut Session<'_>, &Command) -> Result<(), Failure>;

/// What a command does.
#[derive(Clone, Copy)]
pub(super) enum Action {
    /// Its handler executes it.
    Run(Handler),
    /// Accepted with no effect (parallel set-up, echoing, compute options).
    Ignored,
}

/// A deck command: its LIGGGHTS name and aliases, and what it does.
pub(super) struct CommandStyle {
    /// The names that select it.
    names: &'static [&'static str],
    /// What it does.
    pub(super) action: Action,
}

/// Every command the native DEM knows.
static COMMANDS: &[CommandStyle] = &[
    row(&["atom_style"], setup::atom_style),
    row(&["atom_modify"], setup::atom_modify),
    row(&["units"], setup::units),
    row(&["coarsegraining"], coarse_graining::coarsegraining),
    CommandStyle {
        names: &[
            "newton",
            "communicate",
            "comm_modify",
            "processors",
            "echo",
            "compute_modify",
        ],
        action: Action::Ignored,
    },
    row(&["log"], output::log),
    row(&["print"], output::print),
    row(&["thermo"], output::thermo),
    row(&["thermo_log"], output::thermo_log),
    row(&["thermo_style"], output::thermo_style),
    row(&["thermo_modify"], output::thermo_modify),
    row(&["delete_atoms"], atoms::delete_atoms),
    row(&["compute"], output::compute),
    row(&["uncompute"], output::uncompute),
    row(&["boundary"], setup::boundary),
    row(&["region"], setup::region),
    row(&["create_box"], setup::create_box),
    row(&["read_data"], setup::read_data),
    row(&["read_restart"], setup::read_restart),
    row(&["write_restart"], output::write_restart),
    row(&["create_atoms"], atoms::create_atoms),
    row(&["set"], atoms::set),
    row(&["velocity"], atoms::velocity),
    row(&["neighbor"], setup::neighbor),
    row(&["neigh_modify"], setup::neigh_modify),
    row(&["soft_particles"], setup::soft_particles),
    row(&["hard_particles"], setup::hard_particles),
    row(&["timestep"], setup::timestep),
    row(&["pair_style"], setup::pair_style),
    row(&["pair_coeff"], setup::pair_coeff),
    row(&["fix"], fixes::fix),
    row(&["unfix"], fixes::unfix),
    row(&["dump"], output::dump),
    row(&["dump_modify"], output::dump_modify),
    row(&["undump"], output::undump),
    row(&["run"], run::run),
    row(&["write_data"], output::write_data),
];

/// A row whose handler executes the command.
const fn row(names: &'static [&'static str], handler: Handler) -> CommandStyle {
    CommandStyle {
        names,
        action: Action::Run(handler),
    }
}

/// The command named `name`, if the native DEM knows it.
pub(super) fn find(name: &str) -> Option<&'static CommandStyle> {
    COMMANDS.iter().find(|c| c.names.contains(&name))
}
