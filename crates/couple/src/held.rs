//! What a coupler holds, in bytes, on its two sides ([`HeldBytes`]): the mesh it works on and
//! its per-particle buffers (issue 29, `docs/scaling.md`: a coupler rank's memory, mesh and
//! particles separately). Capacity-based ([`foam::HeapBytes`]): what the arrays asked the
//! allocator for, not their lengths.

use crate::step::Coupler;
use foam::heap::{flat, HeapBytes};

/// Bytes a coupler (and the sides it is given) holds, by what they grow with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HeldBytes {
    /// What grows with the cells held: the voidage mesh (geometry, locator, the kernels'
    /// per-face and per-cell records), ε per cell, the dense per-cell copies of the fluid a
    /// rank other than 0 receives, and the part's labels and edge marks.
    pub mesh: usize,
    /// What grows with the particles held: centre-cell hints and their tags, `divided`'s
    /// marker memo, the recycled per-particle buffers (couplings, centre cells, volume shares,
    /// F_ext, β, u_f), the added mass's record and the population's last records.
    pub particles: usize,
}

impl std::ops::Add for HeldBytes {
    type Output = HeldBytes;
    fn add(self, o: HeldBytes) -> HeldBytes {
        HeldBytes {
            mesh: self.mesh + o.mesh,
            particles: self.particles + o.particles,
        }
    }
}

impl Coupler {
    /// The bytes this coupler holds (module docs). Left out: the periodic spans and the
    /// smoothing's state (a few values, or one rank's whole ε only with smoothing on one
    /// rank), `KochHillRWDrag`'s eddies (a hash map by tag) and the step a caller holds
    /// between [`Coupler::hand_over`] and [`Coupler::recycle`].
    pub fn held_bytes(&self) -> HeldBytes {
        let r = &self.remote;
        let remote = flat(&r.eps)
            + flat(&r.u)
            + flat(&r.p)
            + flat(&r.grad_p)
            + flat(&r.div_tau)
            + flat(&r.t);
        let part = self
            .part
            .as_ref()
            .map_or(0, |p| flat(&p.global) + flat(&p.edge));
        let s = &self.spare;
        let spare = flat(&s.couplings)
            + flat(&s.centre)
            + s.shares.heap_bytes()
            + flat(&s.f_ext)
            + flat(&s.beta)
            + flat(&s.u_f);
        HeldBytes {
            mesh: self.vm.heap_bytes()
                + flat(&self.voidage)
                + remote
                + part
                + self.root_volumes.as_ref().map_or(0, flat),
            particles: flat(&self.hints)
                + flat(&self.hint_ids)
                + self.memo.heap_bytes()
                + spare
                + flat(&self.before)
                + flat(&self.before_ids)
                + self.population.heap_bytes(),
        }
    }
}
