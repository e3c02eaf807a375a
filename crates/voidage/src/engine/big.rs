//! CFDEM's `bigParticle` voidage (CFDEMcoupling-PUBLIC
//! `voidFractionModel/bigParticleVoidFraction`, for particles larger than a cell): the cells
//! whose centre lies strictly within the particle radius of the particle centre, reached from
//! the centre's cell through internal faces (OpenFOAM's `cellCells`, as CFDEM's recursive
//! `buildLabelHashSet` walks them), and the centre's cell itself, each get an equal share
//! V/N of the particle volume V (N the number of those cells). A particle whose centre is
//! outside the mesh is counted outside. The shares sum to V (to the rounding of N equal
//! parts), so every particle's volume is in a cell or counted outside. Not continuous: a
//! share jumps when a cell centre enters or leaves the ball. CFDEM's `maxCellsPerParticle`
//! (a storage bound whose overflow is a fatal error there) does not bound anything here.

use super::{Ball, Scratch, VoidageMesh};
use foam::Label;

impl VoidageMesh {
    /// Pushes the shares of one particle by CFDEM's `bigParticle` rule (module docs) and
    /// returns its volume outside the mesh.
    pub(super) fn big_particle(
        &self,
        b: Ball,
        s: &mut Scratch,
        out: &mut Vec<(Label, f64)>,
    ) -> f64 {
        if !self.cells_within(b, b.r, s) {
            return b.v;
        }
        let share = b.v / s.candidates.len() as f64;
        out.extend(s.candidates.iter().map(|&c| (c, share)));
        0.0
    }

    /// The centre's cell and the cells whose centre lies strictly within `radius` of the
    /// particle centre, reached from it through internal faces, into `s.candidates`: the
    /// centre's cell first, as CFDEM lists it, the others in mesh order. False when the centre
    /// is outside the mesh (no cells).
    pub(super) fn cells_within(&self, b: Ball, radius: f64, s: &mut Scratch) -> bool {
        let Some(c0) = b.cell else { return false };
        let n_internal = self.neighbour.len();
        let tets = self.locator.tets();
        let centres = &self.geom.cell_centres;
        let r2 = radius * radius;
        s.begin_walk(c0);
        while let Some(c) = s.queue.pop() {
            s.candidates.push(c);
            for &f in tets.cell_faces(c) {
                let f = f as usize;
                if f >= n_internal {
                    continue;
                }
                let n = self.across(f, c);
                // whether a cell's centre is within the ball does not depend on the path, so
                // a cell tested once is never tested again
                if s.visited.insert(n, ()) && (centres[n as usize] - b.c).norm_squared() < r2 {
                    s.queue.push(n);
                }
            }
        }
        s.candidates[1..].sort_unstable();
        true
    }
}
