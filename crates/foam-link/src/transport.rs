//! Messages to and from the solver ranks that never block on a dead solver: sends are
//! `MPI_Isend` completed by `MPI_Test`, receives wait with `MPI_Improbe`; between polls the
//! coupler checks that every solver pid is alive (`/proc`) and turns a vanished rank into
//! [`LinkError::SolverDied`] naming its log. A rank that reports an OpenFOAM FatalError
//! (tag 30) gives [`LinkError::SolverError`] with the message.

use crate::alive::is_alive;
use crate::case_setup::{log_path, pid_path, tail};
use crate::protocol::tag;
use crate::LinkError;
use mpi::datatype::Equivalence;
use mpi::point_to_point::MatchedReceiveVec;
use mpi::raw::AsRaw;
use mpi::topology::InterCommunicator;
use mpi::traits::*;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// How often the pids are checked while waiting.
const LIVENESS_PERIOD: Duration = Duration::from_millis(50);
/// Polls without sleeping before the wait backs off to short sleeps.
const SPIN_POLLS: u32 = 2000;
/// The longest sleep between polls.
const MAX_NAP: Duration = Duration::from_micros(500);

/// The spawn intercommunicator and what is known of each solver rank.
pub struct Transport {
    inter: Option<InterCommunicator>,
    case: PathBuf,
    pids: Vec<Option<u32>>,
    /// Set once a rank died or failed: the intercommunicator is then leaked, not
    /// disconnected (MPI_Comm_disconnect would wait for the dead rank forever).
    broken: bool,
    /// Seconds spent polling for replies (waiting for the solver to compute and send).
    pub wait_seconds: f64,
}

impl Transport {
    /// Wraps the intercommunicator of a spawn of `ranks` solver ranks on `case`.
    pub fn new(inter: InterCommunicator, case: PathBuf, ranks: usize) -> Transport {
        Transport {
            inter: Some(inter),
            case,
            pids: vec![None; ranks],
            broken: false,
            wait_seconds: 0.0,
        }
    }

    /// Number of solver ranks.
    pub fn ranks(&self) -> usize {
        self.pids.len()
    }

    /// True after a rank died or reported an error.
    pub fn is_broken(&self) -> bool {
        self.broken
    }

    /// The solver log of `rank`.
    pub fn log(&self, rank: usize) -> PathBuf {
        log_path(&self.case, self.ranks(), rank)
    }

    /// Records the pid a rank gave in its handshake (it must match the launcher's pid file).
    pub fn set_pid(&mut self, rank: usize, pid: u32) -> Result<(), LinkError> {
        if let Some(known) = self.pids[rank] {
            if known != pid {
                return Err(LinkError::Protocol {
                    rank,
                    log: self.log(rank),
                    message: format!("handshake pid {pid}, but the launcher recorded {known}"),
                });
            }
        }
        self.pids[rank] = Some(pid);
        Ok(())
    }

    /// The pids known so far (from the launcher's files or the handshakes).
    pub fn pids(&self) -> Vec<Option<u32>> {
        self.pids.clone()
    }

    /// Reads the pid files the launch script wrote (each before it execs the solver).
    pub fn read_pid_files(&mut self) {
        for rank in 0..self.ranks() {
            if self.pids[rank].is_none() {
                let path = pid_path(&self.case, rank);
                self.pids[rank] = std::fs::read_to_string(&path)
                    .ok()
                    .and_then(|s| s.trim().parse().ok());
            }
        }
    }

    /// Err when a rank has sent an error message (tag 30) that is still waiting, e.g. from a
    /// rank other than the one the coupler waits for.
    fn check_errors(&mut self) -> Result<(), LinkError> {
        for rank in 0..self.ranks() {
            let probed = self
                .inter()
                .process_at_rank(rank as i32)
                .immediate_matched_probe_with_tag(tag::ERROR);
            if let Some(msg) = probed {
                self.broken = true;
                let (text, _) = msg.matched_receive_vec::<u8>();
                return Err(LinkError::SolverError {
                    rank,
                    log: self.log(rank),
                    message: String::from_utf8_lossy(&text).trim().to_owned(),
                });
            }
        }
        Ok(())
    }

    /// Err when a rank reported an error or its process is gone.
    pub fn check_alive(&mut self, waiting: &'static str) -> Result<(), LinkError> {
        self.check_errors()?;
        self.read_pid_files();
        for rank in 0..self.ranks() {
            if let Some(pid) = self.pids[rank] {
                if !is_alive(pid) {
                    self.broken = true;
                    // Its error message may have arrived just before it exited.
                    self.check_errors()?;
                    let log = self.log(rank);
                    let text = std::fs::read_to_string(&log).unwrap_or_default();
                    return Err(LinkError::SolverDied {
                        rank,
                        pid,
                        waiting,
                        log,
                        tail: tail(&text, 25),
                    });
                }
            }
        }
        Ok(())
    }

    fn inter(&self) -> &InterCommunicator {
        self.inter
            .as_ref()
            .expect("the intercommunicator lives until the transport is dropped")
    }

    /// Sends `data` with `tag` to `rank`, waiting for completion without blocking on a dead
    /// solver.
    pub fn send<T: Equivalence>(
        &mut self,
        rank: usize,
        data: &[T],
        tag: i32,
        waiting: &'static str,
    ) -> Result<(), LinkError> {
        let count = i32::try_from(data.len()).map_err(|_| {
            LinkError::Parameter(format!("message of {} values to rank {rank}", data.len()))
        })?;
        let comm = self.inter().as_raw();
        let mut request = unsafe { mpi::ffi::RSMPI_REQUEST_NULL };
        // SAFETY: `data` outlives the request: it completes below before returning, or, when
        // the solver died, the request is abandoned together with the whole link (`broken`),
        // the slice is never written by MPI (a send only reads) and the process is about to
        // report the failure.
        unsafe {
            mpi::ffi::MPI_Isend(
                data.as_ptr().cast(),
                count,
                T::equivalent_datatype().as_raw(),
                rank as i32,
                tag,
                comm,
                &mut request,
            );
        }
        let mut poll = Poller::new();
        loop {
            let mut done = 0;
            // SAFETY: `request` is the live request of the Isend above.
            unsafe {
                mpi::ffi::MPI_Test(&mut request, &mut done, mpi::ffi::RSMPI_STATUS_IGNORE);
            }
            if done != 0 {
                // A send's time is exchange cost (copy to the solver), not waiting.
                return Ok(());
            }
            // On failure the request is abandoned with the link (a dead rank never matches it).
            self.idle(&mut poll, waiting)?;
        }
    }

    /// Receives the next message of `rank`, which must carry `tag`; a tag-30 message becomes
    /// [`LinkError::SolverError`].
    pub fn receive<T: Equivalence>(
        &mut self,
        rank: usize,
        expected: i32,
        waiting: &'static str,
    ) -> Result<Vec<T>, LinkError> {
        let mut poll = Poller::new();
        loop {
            if let Some(msg) = self.try_receive(rank, expected, waiting)? {
                self.wait_seconds += poll.waited();
                return Ok(msg);
            }
            self.idle(&mut poll, waiting)?;
        }
    }

    /// The next message of `rank` if one has arrived (it must carry `expected`, as in
    /// [`Transport::receive`]), else `None` at once.
    pub fn try_receive<T: Equivalence>(
        &mut self,
        rank: usize,
        expected: i32,
        waiting: &'static str,
    ) -> Result<Option<Vec<T>>, LinkError> {
        let Some(msg) = self
            .inter()
            .process_at_rank(rank as i32)
            .immediate_matched_probe()
        else {
            return Ok(None);
        };
        let got = msg.1.tag();
        if got == expected {
            return Ok(Some(msg.matched_receive_vec::<T>().0));
        }
        self.broken = true;
        if got == tag::ERROR {
            let (text, _) = msg.matched_receive_vec::<u8>();
            return Err(LinkError::SolverError {
                rank,
                log: self.log(rank),
                message: String::from_utf8_lossy(&text).trim().to_owned(),
            });
        }
        let _ = msg.matched_receive_vec::<u8>();
        Err(LinkError::Protocol {
            rank,
            log: self.log(rank),
            message: format!("message with tag {got} while waiting for {waiting}"),
        })
    }

    /// One pause of a wait that found nothing to receive: the liveness check when due (Err
    /// when a rank died or reported an error), then a spin or a nap.
    pub(crate) fn idle(
        &mut self,
        poll: &mut Poller,
        waiting: &'static str,
    ) -> Result<(), LinkError> {
        if poll.due_for_liveness() {
            self.check_alive(waiting)?;
        }
        poll.nap();
        Ok(())
    }

    /// Marks the link unusable (a failure outside the transport, e.g. a protocol error).
    pub fn mark_broken(&mut self) {
        self.broken = true;
    }
}

impl Drop for Transport {
    fn drop(&mut self) {
        if let Some(inter) = self.inter.take() {
            if self.broken {
                // MPI_Comm_disconnect waits for every remote rank: never with a dead one. The
                // ranks still alive may wait in a reduction with the dead one: end them.
                std::mem::forget(inter);
                for pid in self.pids.iter().flatten() {
                    if is_alive(*pid) {
                        let _ = std::process::Command::new("kill")
                            .arg(pid.to_string())
                            .status();
                    }
                }
            } else {
                drop(inter);
            }
        }
    }
}

/// Polling with a short spin, then naps of growing length, and a liveness clock.
pub(crate) struct Poller {
    start: Instant,
    last_check: Instant,
    polls: u32,
    nap: Duration,
}

impl Poller {
    pub(crate) fn new() -> Poller {
        let now = Instant::now();
        Poller {
            start: now,
            last_check: now,
            polls: 0,
            nap: Duration::from_micros(10),
        }
    }

    pub(crate) fn waited(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    fn due_for_liveness(&mut self) -> bool {
        if self.last_check.elapsed() >= LIVENESS_PERIOD {
            self.last_check = Instant::now();
            return true;
        }
        false
    }

    fn nap(&mut self) {
        self.polls += 1;
        if self.polls < SPIN_POLLS {
            std::hint::spin_loop();
            return;
        }
        std::thread::sleep(self.nap);
        self.nap = (self.nap * 2).min(MAX_NAP);
    }
}
