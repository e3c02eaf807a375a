//! Waiting for other ranks without spinning: a nonblocking MPI request tested with naps.
//!
//! A blocking MPI call (`MPI_Allreduce`, `MPI_Barrier`, a LIGGGHTS `run`'s first collective)
//! busy-polls in Open MPI: a rank that arrives while another works alone (rank 0 packing the
//! bed, running the native fluid, writing a time, waiting for grainPisoFoam) takes a core
//! until it arrives (measured: docs/scaling.md, "Ranks that wait"). Testing a nonblocking
//! request between naps leaves the core to the rank that works.

use mpi::request::{Request, Scope};
use std::time::Duration;

/// How a wait naps: a few tests back to back (a wait of microseconds costs no nap), then naps
/// from `first` doubling to `longest` (the wait's extra latency at most).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Naps {
    /// Tests before the first nap.
    pub(crate) polls: u32,
    /// The first nap.
    pub(crate) first: Duration,
    /// The longest nap.
    pub(crate) longest: Duration,
}

/// A stage boundary (minutes of waiting possible): naps from 50 µs to 20 ms.
pub(crate) const STAGE: Naps = Naps {
    polls: 0,
    first: Duration::from_micros(50),
    longest: Duration::from_millis(20),
};

/// Within a coupling step (seconds at most; every step pays the latency): 1000 tests, then
/// naps from 10 µs to 1 ms, as foam-link waits for grainPisoFoam.
pub(crate) const STEP: Naps = Naps {
    polls: 1000,
    first: Duration::from_micros(10),
    longest: Duration::from_millis(1),
};

/// Waits for `request` to complete, napping as `naps` says.
pub(crate) fn wait<'a, D: ?Sized, S: Scope<'a>>(mut request: Request<'a, D, S>, naps: Naps) {
    let mut polls = 0;
    let mut nap = naps.first;
    loop {
        match request.test() {
            Ok(_) => return,
            Err(pending) => request = pending,
        }
        if polls < naps.polls {
            polls += 1;
            continue;
        }
        std::thread::sleep(nap);
        nap = (nap * 2).min(naps.longest);
    }
}
