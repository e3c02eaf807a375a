//! CFDEM's `trilinear` voidage model: a particle's volume shared among the (up to) 8 cells
//! whose centres surround its centre, with trilinear weights.
//!
//! # Formula
//! On a structured grid of equal axis-aligned box cells the cell centres form a lattice of
//! spacings (h_x, h_y, h_z). Let i000 be the cell at the lower corner of the lattice box
//! holding the particle centre p, and per axis a
//!
//! t_a = |p_a − C000_a| / |C100_a − C000_a|  ∈ [0, 1]  (dimensionless),
//!
//! the distance of p from i000's centre in units of the centre spacing (C100 is the centre of
//! the next cell along a; t_a = 0 when there is none). The cell i000 + (δ_x, δ_y, δ_z),
//! δ ∈ {0, 1}³, receives the share w_δ·V of the particle volume V = 4πr³/3 (m³), with
//!
//! w_δ = Π_a (δ_a ? t_a : 1 − t_a),   Σ_δ w_δ = 1.
//!
//! A particle at a cell centre puts its whole volume into that cell, one at a grid node 1/8
//! into each of the 8 cells around the node, one at the centre of a face 1/2 into each of the
//! two cells sharing it. Inside the grid the shares are linear in each coordinate of p and
//! continuous. The radius enters only through V: the shares do not depend on the particle's
//! size (a particle larger than a cell still reaches 8 cells at most), and volume can go to a
//! cell the ball does not touch.
//!
//! # Which cell is i000, and the mesh boundary
//! CFDEM searches i000 among the 3×3×3 block of cells around the cell holding p
//! ([`cfdem_lower_corner`]). When p lies at or above that cell's centre C along every axis
//! (p_a − C_a + SMALL ≥ 0, SMALL = 1e-15 m as OpenFOAM's), i000 is that cell. Otherwise the
//! cells of the block whose centres are not above C are filtered by the sign of the offset:
//! along x (one layer below when p_x < C_x, the same layer otherwise), then y, then z, and
//! i000 is the cell left. When a filter leaves nothing (an axis with a negative offset and no
//! cell below: a cell on a lower wall), i000 falls back to the last cell a filter left alone
//! (possible only when the cell also has no neighbour below along the remaining axes), else to
//! the cell holding p. Then t_a uses the distance |p_a − C000_a| even when p lies below
//! C000 along a. On a box-shaped grid this gives:
//! * **upper walls**: beyond the last centre along an axis, i000 has no neighbour above, t = 0:
//!   that axis's share stays in the last layer (clamped);
//! * **lower walls**: below the first centre, the share along that axis is *mirrored* about the
//!   centre (a particle 0.2 h below the first centre puts 0.2 of it into the second layer).
//!   Which other axes with a negative offset are mirrored depends on the fallback: all of them
//!   when x is the blocked axis; y and z (and x when z has a cell below) when it is y; only z
//!   when it is z. So the shares jump inside the cells along the lower walls (e.g. on the
//!   x = min wall with p_y < C_y, as p_x crosses C_x the y share moves from layers j − 1, j to
//!   j, j + 1): the model is not continuous there ([`crate::Method::is_continuous`]);
//! * **nothing is lost**: i000 always exists and t_a = 0 whenever i000 has no neighbour above,
//!   so no weight goes to a cell beyond the mesh: a particle whose centre is in the mesh has
//!   all of its volume in cells (even the part of the ball beyond the wall). A particle whose
//!   centre is outside the mesh deposits nothing (CFDEM skips it; here it is counted as outside
//!   the mesh, [`crate::Deposit::outside_volume`]). Any weight of a cell beyond the mesh would be
//!   counted outside too, never dropped.
//!
//! CFDEM's first trilinear model (release of 2016-01-15) instead clamped at both walls (the
//! share along a blocked axis stayed in the cell holding p); the behaviour above is that of the
//! current code (release of 2025-07-03), which foamgrain follows.
//!
//! # Requirements (checked: [`check_grid`])
//! CFDEM documents the model for "a structured mesh with equal cubic cells and a clean x/y/z
//! parallel distribution of the cells"; its neighbour search assumes a hex grid, and on other
//! meshes it splits missing corners' weights 0.5/0.5 and 0.33/0.33/0.34 over other cells while
//! overwriting some of them (volume lost). foamgrain requires an axis-aligned structured grid
//! ([`mesh::AxisGrid`]: every cell an axis-aligned box, the cells a tensor product) whose planes
//! are equally spaced along each axis (each plane within [`UNIFORM_TOLERANCE`] of a spacing of
//! its uniform position, room for coordinates written with 6 digits). The cells need not be
//! cubes: CFDEM's code measures the spacing per axis between neighbouring centres, as here.
//! Any other mesh is a [`crate::VoidageError::UnsupportedMesh`] naming the requirement.
//!
//! # Settings, and what foamgrain does differently
//! * `alphaMin` (CFDEM default 0.1, in [0.01, 1]): CFDEM's trilinear skips a cell's share when
//!   it would take that cell's ε to alphaMin or below, so the skipped volume is lost and the
//!   result depends on the particle order (its documentation says alphaMin is not used yet).
//!   foamgrain deposits every share and clips afterwards with the clipped volume reported
//!   ([`crate::Voidage`]), as for every method.
//! * `volScale` is read by CFDEM but not used by trilinear; `weight`, `scaleUpVol` are refused
//!   by CFDEM as deprecated, `porosity` must be 1: V is the plain sphere volume.
//! * CFDEM compares cell centres with a tolerance of SMALL in some places and without one in
//!   others, so centres that differ by rounding can change its choice of i000; foamgrain makes
//!   those comparisons on grid indices (centres along one grid line are equal).
//! * Side effects outside the voidage are not copied: CFDEM replaces the particle's cell by
//!   i000 and its first exchange weight by 1 (its 8 weights then sum to more than 1), and its
//!   per-particle ε array reuses the corner cells of the last particle. foamgrain keeps the
//!   cell holding the centre and exchanges momentum with the same shares as the voidage.
//!
//! Source: CFDEMcoupling-PUBLIC, `src/lagrangian/cfdemParticle/subModels/voidFractionModel/
//! trilinearVoidFraction/trilinearVoidFraction.C` and
//! `doc/voidFractionModel_trilinearVoidFraction` (releases 2016-01-15 and 2025-07-03), read for
//! their behaviour; the code here is written from the description above.

use crate::error::VoidageError;
use crate::method::Method;
use foam::Label;
use mesh::v3::V3;
use mesh::AxisGrid;

/// OpenFOAM's `SMALL` for double precision (m, as a coordinate offset): CFDEM's tolerance in
/// `p_a − C_a + SMALL ≥ 0`.
pub const SMALL: f64 = 1e-15;

/// Largest distance of a grid plane from its uniform position, in spacings, for the grid to
/// count as one of equal cells ([`check_grid`]).
pub const UNIFORM_TOLERANCE: f64 = 1e-3;

/// What trilinear needs of a mesh, as [`crate::VoidageError::UnsupportedMesh`] states it.
pub const TRILINEAR_REQUIREMENT: &str = "a structured grid of equal axis-aligned box cells \
     (CFDEM: \"a structured mesh with equal cubic cells and a clean x/y/z parallel \
     distribution of the cells\")";

/// The 8 trilinear weights w_δ = Π_a (δ_a ? t_a : 1 − t_a) of the fractions `t` ∈ [0, 1]³,
/// indexed by δ_x + 2δ_y + 4δ_z (module docs). They sum to 1 up to rounding.
#[inline]
pub fn trilinear_weights(t: [f64; 3]) -> [f64; 8] {
    std::array::from_fn(|bits| {
        (0..3)
            .map(|a| {
                if (bits >> a) & 1 == 1 {
                    t[a]
                } else {
                    1.0 - t[a]
                }
            })
            .product()
    })
}

/// CFDEM's choice of the lower corner cell i000 for a particle whose centre lies in a cell of
/// a structured grid (module docs): `offset` = p − C, the particle centre relative to that
/// cell's centre (m), `has_lower[a]` whether the cell has a neighbour below along axis a.
/// Returns, per axis, whether i000 is the neighbour below (true) or in the cell's layer
/// (false).
pub fn cfdem_lower_corner(offset: [f64; 3], has_lower: [bool; 3]) -> [bool; 3] {
    if offset.iter().all(|&d| d + SMALL >= 0.0) {
        return [false; 3];
    }
    // Offsets (in layers down, per axis) of the block's cells whose centres are not above the
    // cell's centre: the cell itself and the neighbours below that exist.
    let down = offset.map(|d| d < 0.0);
    let mut set = [[false; 3]; 8];
    let mut n = 0;
    for bits in 0..8 {
        let d: [bool; 3] = std::array::from_fn(|a| (bits >> a) & 1 == 1);
        if (0..3).all(|a| !d[a] || has_lower[a]) {
            set[n] = d;
            n += 1;
        }
    }
    let mut keeper = [false; 3];
    for axis in 0..3 {
        let mut kept = 0;
        for i in 0..n {
            if set[i][axis] == down[axis] {
                set[kept] = set[i];
                kept += 1;
            }
        }
        n = kept;
        if axis < 2 && n == 1 {
            keeper = set[0];
        }
    }
    if n > 0 {
        set[n - 1]
    } else {
        keeper
    }
}

/// Checks that `grid` (the mesh's axis-aligned grid, `None` if it is not one) is a grid of
/// equal cells along each axis (module docs) and returns it.
pub fn check_grid(grid: Option<&AxisGrid>) -> Result<&AxisGrid, VoidageError> {
    let unsupported = |problem: String| VoidageError::UnsupportedMesh {
        method: Method::Trilinear,
        requirement: TRILINEAR_REQUIREMENT,
        problem,
    };
    let Some(g) = grid else {
        return Err(unsupported(
            "this mesh is not an axis-aligned structured hex grid".into(),
        ));
    };
    for (a, name) in ["x", "y", "z"].into_iter().enumerate() {
        let pl = g.planes(a);
        let n = pl.len() - 1;
        let h = (pl[n] - pl[0]) / n as f64;
        let uneven = pl
            .iter()
            .enumerate()
            .any(|(i, &x)| (x - (pl[0] + h * i as f64)).abs() > UNIFORM_TOLERANCE * h);
        if uneven {
            let widths = pl.windows(2).map(|w| w[1] - w[0]);
            let min = widths.clone().fold(f64::INFINITY, f64::min);
            let max = widths.fold(0.0, f64::max);
            return Err(unsupported(format!(
                "the cell widths along {name} vary from {min:e} m to {max:e} m"
            )));
        }
    }
    Ok(g)
}

/// Pushes the trilinear shares of one particle (centre `p`, volume `v` in m³, in cell `cell`
/// of the checked grid `g`, `None` outside the mesh) and returns its volume outside the mesh.
/// `centres` are the cell centres (OpenFOAM's, m).
pub(crate) fn grid_trilinear(
    g: &AxisGrid,
    centres: &[V3],
    p: V3,
    cell: Option<Label>,
    v: f64,
    out: &mut Vec<(Label, f64)>,
) -> f64 {
    let Some(c0) = cell else {
        return v;
    };
    let n = g.dims();
    let ijk = g.ijk(c0);
    let c = centres[c0 as usize];
    let down = cfdem_lower_corner(std::array::from_fn(|a| p[a] - c[a]), ijk.map(|i| i > 0));
    let base: [usize; 3] = std::array::from_fn(|a| ijk[a] - down[a] as usize);
    let at = |idx: [usize; 3]| g.cell(idx[0], idx[1], idx[2]);
    let c000 = centres[at(base) as usize];
    let t: [f64; 3] = std::array::from_fn(|a| {
        if base[a] + 1 < n[a] {
            let mut up = base;
            up[a] += 1;
            let c100 = centres[at(up) as usize];
            (c000[a] - p[a]).abs() / (c000[a] - c100[a]).abs()
        } else {
            0.0
        }
    });
    let mut sum = 0.0;
    for (bits, w) in trilinear_weights(t).into_iter().enumerate() {
        let idx: [usize; 3] = std::array::from_fn(|a| base[a] + ((bits >> a) & 1));
        // A weight of a cell beyond the mesh (none on a box grid) stays outside.
        if w > 0.0 && (0..3).all(|a| idx[a] < n[a]) {
            let vol = w * v;
            out.push((at(idx), vol));
            sum += vol;
        }
    }
    v - sum
}
