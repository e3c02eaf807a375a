//! [`couple::Ranks`] over MPI: the coupler ranks of `mpirun -np N foamgrain run …`.
//!
//! Per-cell sums go to rank 0 as variable-length gathers (each rank's touched cells and their
//! values: bytes per rank proportional to the cells its particles touch, never to the mesh),
//! summed in rank order so that a run is deterministic for a fixed rank count; rank 0 keeps
//! each rank's cell list for the scatter back. The byte counts are kept ([`MpiRanks::traffic`])
//! for the scaling report.

use couple::Ranks;
use foam::Label;
use mpi::collective::{CommunicatorCollectives, Root, SystemOperation};
use mpi::datatype::{Partition, PartitionMut};
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::Count;

/// Bytes this rank sent and received in the coupler's exchanges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Bytes sent.
    pub sent: u64,
    /// Bytes received.
    pub received: u64,
}

/// The coupler's ranks on an MPI communicator (module docs).
pub struct MpiRanks {
    comm: SimpleCommunicator,
    /// On rank 0: each rank's cells of the last [`Ranks::sum_to_root`]; elsewhere: this rank's.
    lists: Vec<Vec<Label>>,
    /// On ranks other than 0: the length of the last list.
    own: usize,
    traffic: Traffic,
}

impl MpiRanks {
    /// The coupler's ranks on (a duplicate of) `comm`.
    pub fn new(comm: &SimpleCommunicator) -> MpiRanks {
        MpiRanks {
            comm: comm.duplicate(),
            lists: Vec::new(),
            own: 0,
            traffic: Traffic::default(),
        }
    }

    /// Bytes sent and received so far.
    pub fn traffic(&self) -> Traffic {
        self.traffic
    }

    fn count(&mut self, sent: usize, received: usize) {
        self.traffic.sent += sent as u64;
        self.traffic.received += received as u64;
    }
}

/// Counts and displacements of a variable-length gather or scatter.
fn layout(counts: &[Count]) -> Vec<Count> {
    counts
        .iter()
        .scan(0, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect()
}

impl Ranks for MpiRanks {
    fn rank(&self) -> usize {
        self.comm.rank() as usize
    }

    fn size(&self) -> usize {
        self.comm.size() as usize
    }

    fn sum_to_root(&mut self, cells: &[Label], values: &[f64], width: usize, root: &mut [f64]) {
        let size = self.size();
        let r0 = self.comm.process_at_rank(0);
        let n = cells.len() as Count;
        let f64_bytes = std::mem::size_of::<f64>();
        let cell_bytes = std::mem::size_of::<Label>();
        if self.rank() == 0 {
            let mut counts = vec![0 as Count; size];
            r0.gather_into_root(&n, &mut counts[..]);
            let displs = layout(&counts);
            let total: usize = counts.iter().map(|&c| c as usize).sum();
            let mut all_cells = vec![0 as Label; total];
            {
                let mut part = PartitionMut::new(&mut all_cells[..], &counts[..], &displs[..]);
                r0.gather_varcount_into_root(cells, &mut part);
            }
            let wcounts: Vec<Count> = counts.iter().map(|&c| c * width as Count).collect();
            let wdispls = layout(&wcounts);
            let mut all_values = vec![0.0; total * width];
            {
                let mut part = PartitionMut::new(&mut all_values[..], &wcounts[..], &wdispls[..]);
                r0.gather_varcount_into_root(values, &mut part);
            }
            root.fill(0.0);
            self.lists.resize(size, Vec::new());
            for (r, list) in self.lists.iter_mut().enumerate() {
                let (s, c) = (displs[r] as usize, counts[r] as usize);
                list.clear();
                list.extend_from_slice(&all_cells[s..s + c]);
                couple::ranks::scatter_add(
                    list,
                    &all_values[s * width..(s + c) * width],
                    width,
                    root,
                );
            }
            let own = cells.len() * (cell_bytes + width * f64_bytes);
            self.count(0, total * (cell_bytes + width * f64_bytes) - own);
        } else {
            r0.gather_into(&n);
            r0.gather_varcount_into(cells);
            r0.gather_varcount_into(values);
            self.own = cells.len();
            self.count(cells.len() * (cell_bytes + width * f64_bytes), 0);
        }
    }

    fn scatter_from_root(
        &mut self,
        width: usize,
        value: &dyn Fn(Label, &mut Vec<f64>),
        out: &mut Vec<f64>,
    ) {
        let r0 = self.comm.process_at_rank(0);
        let f64_bytes = std::mem::size_of::<f64>();
        if self.rank() == 0 {
            let mut send = Vec::new();
            let mut counts = Vec::with_capacity(self.lists.len());
            for (r, list) in self.lists.iter().enumerate() {
                if r == 0 {
                    counts.push(0);
                    continue;
                }
                for &c in list {
                    value(c, &mut send);
                }
                counts.push((list.len() * width) as Count);
            }
            debug_assert_eq!(
                send.len(),
                counts.iter().map(|&c| c as usize).sum::<usize>()
            );
            let displs = layout(&counts);
            let part = Partition::new(&send[..], &counts[..], &displs[..]);
            let mut none: [f64; 0] = [];
            r0.scatter_varcount_into_root(&part, &mut none[..]);
            self.count(send.len() * f64_bytes, 0);
        } else {
            out.clear();
            out.resize(self.own * width, 0.0);
            r0.scatter_varcount_into(&mut out[..]);
            self.count(0, out.len() * f64_bytes);
        }
    }

    fn all_sum(&self, x: &mut [f64]) {
        let send = x.to_vec();
        self.comm
            .all_reduce_into(&send[..], x, SystemOperation::sum());
    }

    fn all_max(&self, x: &mut [f64]) {
        let send = x.to_vec();
        self.comm
            .all_reduce_into(&send[..], x, SystemOperation::max());
    }

    fn broadcast(&self, x: &mut [f64]) {
        self.comm.process_at_rank(0).broadcast_into(x);
    }

    fn meet(&self) {
        crate::nap::wait(self.comm.immediate_barrier(), crate::nap::STEP);
    }

    fn traffic(&self) -> (u64, u64) {
        (self.traffic.sent, self.traffic.received)
    }

    fn gather(&self, x: &[f64]) -> Vec<Vec<f64>> {
        let r0 = self.comm.process_at_rank(0);
        let n = x.len() as Count;
        if self.rank() == 0 {
            let mut counts = vec![0 as Count; self.size()];
            r0.gather_into_root(&n, &mut counts[..]);
            let displs = layout(&counts);
            let total: usize = counts.iter().map(|&c| c as usize).sum();
            let mut all = vec![0.0; total];
            {
                let mut part = PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
                r0.gather_varcount_into_root(x, &mut part);
            }
            counts
                .iter()
                .zip(&displs)
                .map(|(&c, &d)| all[d as usize..(d + c) as usize].to_vec())
                .collect()
        } else {
            r0.gather_into(&n);
            r0.gather_varcount_into(x);
            Vec::new()
        }
    }
}
