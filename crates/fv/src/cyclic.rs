//! Translational `cyclic` patch pairs ([`mesh::cyclic`]) in the solver: each pair of faces is
//! one internal face ([`crate::FvGeometry`]): the owner cell of the first patch's face (the one
//! listed first in `boundary`) and the owner cell of the partner face, with the first face's
//! area vector and centre. The geometric coefficients are v1912's `cyclicFvPatch` ones (see
//! [`face_geometry`]).

use crate::geometry::V3;
use mesh::MeshGeometry;

/// Geometry of one coupled face pair as v1912's `cyclicFvPatch` computes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairGeometry {
    /// Owner weight w = d_N/(d_P + d_N), d_P = n̂_P·(C_f,P − C_P), d_N = n̂_N·(C_f,N − C_N)
    /// (`cyclicFvPatch::makeWeights`).
    pub weight: f64,
    /// Centre-to-centre vector across the pair (m): (C_f,P − C_P) − (C_f,N − C_N)
    /// (`cyclicFvPatch::delta`, parallel case).
    pub delta: V3,
}

/// The weight and delta of the pair of mesh faces `fa` (on the pair's `first` patch, owner
/// cell P) and `fb` (its partner, owner cell N): see [`PairGeometry`].
pub fn face_geometry(
    g: &MeshGeometry,
    p_cell: usize,
    n_cell: usize,
    fa: usize,
    fb: usize,
) -> PairGeometry {
    let (sa, sb) = (g.face_areas[fa], g.face_areas[fb]);
    let da = g.face_centres[fa] - g.cell_centres[p_cell];
    let db = g.face_centres[fb] - g.cell_centres[n_cell];
    let di = (sa / sa.norm()).dot(&da);
    let dni = (sb / sb.norm()).dot(&db);
    PairGeometry {
        weight: dni / (di + dni),
        delta: da - db,
    }
}
