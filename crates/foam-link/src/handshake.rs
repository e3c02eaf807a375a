//! The handshake of the spawned solver ranks (protocol tags 1–4, then the start fields, tag 20),
//! taken from every rank at once, in whatever order the ranks send.
//!
//! Each rank sends its handshake, then OpenFOAM's start-up goes on: grainPisoFoam's ranks meet
//! in collectives (the first `fvc::flux` builds `globalMeshData`, a gather over the solver's
//! ranks) before they send the start fields. A send larger than Open MPI's eager limit (64 KiB
//! over the TCP BTL that carries the spawn's intercommunicator; the cell map is 4 bytes per
//! cell, so more than about 16,000 cells on a rank) completes only once the coupler receives
//! it. Taking the whole handshake of rank 0, start fields included, before any message of
//! rank 1 therefore deadlocked from about 33,000 cells on 2 solver ranks: rank 1 waited for
//! its cell map to be received, rank 0 waited for rank 1 in the gather, the coupler for rank
//! 0's start fields. Here every rank's next message is taken as soon as it has arrived, so no
//! rank's handshake waits for another's start-up.

use crate::protocol::{self, tag, Hello};
use crate::transport::{Poller, Transport};
use crate::LinkError;

/// What the coupler asked of the solver (the launch line's variables), which each rank's
/// hello must confirm.
pub(crate) struct Asked {
    pub heat: bool,
    pub cfdem_ksl: bool,
    pub vorticity: bool,
    pub ddt_u: bool,
}

/// What a rank's handshake gave: its local cells' global indices and its start fields (the
/// tag-20 message).
pub(crate) struct RankStart {
    pub cells: Vec<u32>,
    pub state: Vec<f64>,
}

/// The messages of one rank's handshake, in the order the rank sends them.
#[derive(Clone, Copy, PartialEq)]
enum Step {
    Hello,
    Cells,
    Patches,
    Times,
    State,
    Done,
}

/// One rank's handshake so far.
struct Progress {
    next: Step,
    n_cells: usize,
    cells: Vec<u32>,
    state: Vec<f64>,
}

/// Receives every rank's handshake and start fields, each message as soon as it has arrived
/// (a rank's own messages in its order), checking them against `asked` and the case's
/// `patches`; waits polling, Err as soon as a rank dies, reports an error or breaks the
/// protocol.
pub(crate) fn receive_all(
    tp: &mut Transport,
    asked: &Asked,
    patches: &[String],
) -> Result<Vec<RankStart>, LinkError> {
    let mut ranks: Vec<Progress> = (0..tp.ranks())
        .map(|_| Progress {
            next: Step::Hello,
            n_cells: 0,
            cells: Vec::new(),
            state: Vec::new(),
        })
        .collect();
    let mut poll = Poller::new();
    loop {
        let mut took = false;
        let mut waiting = None;
        for (rank, progress) in ranks.iter_mut().enumerate() {
            if progress.next == Step::Done {
                continue;
            }
            took |= take_next(tp, rank, progress, asked, patches)?;
            if progress.next != Step::Done {
                waiting.get_or_insert(what(progress.next));
            }
        }
        let Some(waiting) = waiting else {
            break;
        };
        if !took {
            tp.idle(&mut poll, waiting)?;
        }
    }
    tp.wait_seconds += poll.waited();
    Ok(ranks
        .into_iter()
        .map(|p| RankStart {
            cells: p.cells,
            state: p.state,
        })
        .collect())
}

/// What the coupler waits for at `step` (for the errors).
fn what(step: Step) -> &'static str {
    match step {
        Step::Hello => "the handshake",
        Step::Cells => "the cell map",
        Step::Patches => "the patch names",
        Step::Times => "the start time",
        Step::State | Step::Done => "the start fields",
    }
}

/// Takes `rank`'s next handshake message if it has arrived: true when one was taken.
fn take_next(
    tp: &mut Transport,
    rank: usize,
    progress: &mut Progress,
    asked: &Asked,
    patches: &[String],
) -> Result<bool, LinkError> {
    let waiting = what(progress.next);
    match progress.next {
        Step::Hello => {
            let Some(words) = tp.try_receive::<i32>(rank, tag::HELLO, waiting)? else {
                return Ok(false);
            };
            let hello = Hello::parse(&words).map_err(|m| protocol_error(tp, rank, m))?;
            check_hello(&hello, rank, asked).map_err(|m| protocol_error(tp, rank, m))?;
            tp.set_pid(rank, hello.pid)?;
            progress.n_cells = hello.n_cells;
            progress.next = Step::Cells;
        }
        Step::Cells => {
            let Some(local) = tp.try_receive::<i32>(rank, tag::CELLS, waiting)? else {
                return Ok(false);
            };
            progress.cells =
                check_cells(local, progress.n_cells).map_err(|m| protocol_error(tp, rank, m))?;
            progress.next = Step::Patches;
        }
        Step::Patches => {
            let Some(names) = tp.try_receive::<u8>(rank, tag::PATCHES, waiting)? else {
                return Ok(false);
            };
            let names =
                protocol::parse_patch_names(&names).map_err(|m| protocol_error(tp, rank, m))?;
            if names != patches {
                let m = format!("patches {names:?}; constant/polyMesh/boundary has {patches:?}");
                return Err(protocol_error(tp, rank, m));
            }
            progress.next = Step::Times;
        }
        Step::Times => {
            let Some(times) = tp.try_receive::<f64>(rank, tag::TIMES, waiting)? else {
                return Ok(false);
            };
            if times.len() != 2 {
                let m = format!("{} time values", times.len());
                return Err(protocol_error(tp, rank, m));
            }
            progress.next = Step::State;
        }
        Step::State => {
            let Some(state) = tp.try_receive::<f64>(rank, tag::STATE, waiting)? else {
                return Ok(false);
            };
            progress.state = state;
            progress.next = Step::Done;
        }
        Step::Done => return Ok(false),
    }
    Ok(true)
}

/// A protocol error of `rank` (the link is unusable from then on).
fn protocol_error(tp: &mut Transport, rank: usize, message: String) -> LinkError {
    tp.mark_broken();
    LinkError::Protocol {
        rank,
        log: tp.log(rank),
        message,
    }
}

/// Err (the message) when `hello` is not `rank`'s or does not answer what was asked.
fn check_hello(hello: &Hello, rank: usize, asked: &Asked) -> Result<(), String> {
    if hello.rank != rank {
        return Err(format!("says it is rank {}", hello.rank));
    }
    if hello.heat != asked.heat {
        let m = if asked.heat {
            "answered without heat although FOAMGRAIN_HEAT=1 was set (a grainPisoFoam \
             without the temperature equation: rebuild it with \
             openfoam-cases/solver/build.sh)"
        } else {
            "answered with heat although the coupler did not ask for it"
        };
        return Err(m.into());
    }
    if hello.cfdem_ksl != asked.cfdem_ksl {
        let m = if asked.cfdem_ksl {
            "answered without CFDEM's Ksl form although FOAMGRAIN_KSL was set \
             (an older grainPisoFoam: rebuild it with openfoam-cases/solver/build.sh)"
        } else {
            "answered with CFDEM's Ksl form although the coupler did not ask for it"
        };
        return Err(m.into());
    }
    for (asked, got, what, var) in [
        (
            asked.vorticity,
            hello.vorticity,
            "∇ × U",
            "FOAMGRAIN_VORTICITY",
        ),
        (asked.ddt_u, hello.ddt_u, "DU/Dt", "FOAMGRAIN_DDT_U"),
    ] {
        if asked != got {
            return Err(match asked {
                true => format!(
                    "answered without {what} although {var}=1 was set (an older \
                     grainPisoFoam: rebuild it with openfoam-cases/solver/build.sh)"
                ),
                false => format!("answered with {what} although the coupler did not ask"),
            });
        }
    }
    Ok(())
}

/// The cell map as global indices; Err when its length is not the `announced` count or a
/// cell is negative.
fn check_cells(local: Vec<i32>, announced: usize) -> Result<Vec<u32>, String> {
    if local.len() != announced {
        return Err(format!(
            "{announced} cells announced, {} in its map",
            local.len()
        ));
    }
    local
        .into_iter()
        .map(u32::try_from)
        .collect::<Result<Vec<u32>, _>>()
        .map_err(|_| "a negative cell in its map".into())
}
