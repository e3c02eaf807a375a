//! [`SolverCells`]: a coupler rank's straight link to the grainPisoFoam ranks that own the
//! cells its particles touch — the [`couple::ranks::CellOwners`] of a run on several coupler
//! ranks with grainPisoFoam (`mpirun -np N foamgrain run … --fluid openfoam`).
//!
//! Each coupling step, in the protocol's sparse exchange ([`crate::protocol`]): coupler rank 0
//! sends every solver rank [`Command::Exchange`]; every coupler rank sends every solver rank
//! the local cells it touches there and its solid volume in each (two messages, empty when it
//! touches none of that rank's cells), receives the summed volume and the fluid of those cells,
//! and after its forces sends ε and its force sums. A coupler rank's bytes per step are 8·(1 +
//! 1 + 12 + 8) = 176 per touched cell (192 with heat: T back, its Tsource share out; 56 more
//! with CFDEM's Ksl form: its seven sums out) plus four
//! empty-or-not messages per solver rank: they scale with its particles, not with the mesh,
//! and no coupler rank relays for another.

use crate::protocol::{sparse_reply_words, sparse_sums_words, tag, Command};
use crate::ranks::RankMap;
use crate::transport::Transport;
use couple::ranks::CellOwners;
use couple::SideError;
use foam::Label;
use std::cell::RefCell;
use std::rc::Rc;

/// A coupler rank's link to the solver ranks (module docs).
pub struct SolverCells {
    /// This coupler rank (0 sends the exchange command).
    rank: usize,
    transport: Rc<RefCell<Transport>>,
    map: RankMap,
    /// Per solver rank, the positions (in the last deposit's cell list) of its cells.
    groups: Vec<Vec<usize>>,
    /// Cells of the last deposit.
    touched: usize,
    /// The solver solves heat: the records carry T and the Tsource share.
    heat: bool,
    /// CFDEM's Ksl form: the sums carry its seven columns ([`couple::ksl::CfdemSums`]).
    cfdem_ksl: bool,
    sent: u64,
    received: u64,
}

impl SolverCells {
    /// The link of coupler rank `rank` over `transport`, with the solver's cell `map`, for a
    /// solver spawned with `options` (heat, CFDEM's Ksl form).
    pub(crate) fn new(
        rank: usize,
        transport: Rc<RefCell<Transport>>,
        map: RankMap,
        options: crate::SpawnOptions,
    ) -> SolverCells {
        let np = map.ranks();
        SolverCells {
            rank,
            transport,
            map,
            groups: vec![Vec::new(); np],
            touched: 0,
            heat: options.heat,
            cfdem_ksl: options.cfdem_ksl.is_some(),
            sent: 0,
            received: 0,
        }
    }

    /// Solver ranks.
    pub fn solver_ranks(&self) -> usize {
        self.map.ranks()
    }
}

impl CellOwners for SolverCells {
    fn deposit(&mut self, cells: &[Label], solid: &[f64]) -> Result<Vec<f64>, SideError> {
        let np = self.map.ranks();
        let mut transport = self.transport.borrow_mut();
        if self.rank == 0 {
            let words = Command::Exchange.words();
            for s in 0..np {
                transport.send(s, &words, tag::COMMAND, "the exchange command to arrive")?;
            }
            self.sent += (8 * words.len() * np) as u64;
        }
        for g in &mut self.groups {
            g.clear();
        }
        let mut local: Vec<Vec<i32>> = vec![Vec::new(); np];
        let mut volume: Vec<Vec<f64>> = vec![Vec::new(); np];
        for (k, (&c, &v)) in cells.iter().zip(solid).enumerate() {
            let (s, l) = self.map.locate(c as usize);
            self.groups[s].push(k);
            local[s].push(l as i32);
            volume[s].push(v);
        }
        for s in 0..np {
            transport.send(
                s,
                &local[s],
                tag::SPARSE_CELLS,
                "the touched cells to arrive",
            )?;
            transport.send(
                s,
                &volume[s],
                tag::SPARSE_SOLID,
                "the solid volumes to arrive",
            )?;
            self.sent += (12 * local[s].len()) as u64;
        }
        let width = sparse_reply_words(self.heat);
        let mut out = vec![0.0; cells.len() * width];
        for s in 0..np {
            let msg: Vec<f64> =
                transport.receive(s, tag::SPARSE_REPLY, "the touched cells' fluid")?;
            let group = &self.groups[s];
            if msg.len() != group.len() * width {
                transport.mark_broken();
                return Err(Box::new(crate::LinkError::Protocol {
                    rank: s,
                    log: transport.log(s),
                    message: format!(
                        "sparse reply of {} values for {} cells",
                        msg.len(),
                        group.len()
                    ),
                }));
            }
            self.received += 8 * msg.len() as u64;
            for (&k, rec) in group.iter().zip(msg.chunks_exact(width)) {
                out[k * width..(k + 1) * width].copy_from_slice(rec);
            }
        }
        self.touched = cells.len();
        Ok(out)
    }

    fn exchange(&mut self, sums: &[f64]) -> Result<(), SideError> {
        let width = sparse_sums_words(self.heat, self.cfdem_ksl);
        if sums.len() != self.touched * width {
            return Err(format!(
                "{} exchange values for {} touched cells",
                sums.len(),
                self.touched
            )
            .into());
        }
        let mut transport = self.transport.borrow_mut();
        let mut buf = Vec::new();
        for (s, group) in self.groups.iter().enumerate() {
            buf.clear();
            for &k in group {
                buf.extend_from_slice(&sums[k * width..(k + 1) * width]);
            }
            transport.send(s, &buf, tag::SPARSE_SUMS, "the force sums to arrive")?;
            self.sent += 8 * buf.len() as u64;
        }
        Ok(())
    }

    fn traffic(&self) -> (u64, u64) {
        (self.sent, self.received)
    }
}
