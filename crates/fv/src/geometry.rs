//! Finite-volume geometry computed once from [`mesh::MeshGeometry`]: face interpolation
//! weights, delta vectors and coefficients, non-orthogonal correction vectors, and the
//! cell → face adjacency used by every operator to gather face sums in parallel.
//!
//! Formulas are OpenFOAM v1912's (`surfaceInterpolation::makeWeights`, `makeDeltaCoeffs`,
//! `makeNonOrthDeltaCoeffs`, `makeNonOrthCorrectionVectors`, `fvPatch::delta`), written
//! independently; see each field's doc comment.

use crate::error::{FvError, Result};
use foam::PolyMesh;
use mesh::MeshGeometry;

use crate::ldu::RowAddressing;
use std::sync::Arc;

/// A 3-vector (m, m², m/s … as the field says).
pub use mesh::v3::V3;

/// One boundary patch as the solver sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct FvPatch {
    /// Patch name from `constant/polyMesh/boundary`.
    pub name: String,
    /// The patch `type` (`patch`, `wall`, `empty`, `symmetryPlane`, `cyclic`, …).
    pub patch_type: String,
    /// Face range of the patch in the solver's face numbering ([`FvGeometry`]); empty for a
    /// `cyclic` patch, whose faces are internal faces of the solver ([`Self::cyclic`]).
    pub faces: std::ops::Range<usize>,
    /// Face range of the patch in the mesh (`startFace`, `nFaces`).
    pub mesh_faces: std::ops::Range<usize>,
    /// For a `cyclic` patch: where its faces went.
    pub cyclic: Option<CyclicSide>,
}

/// A `cyclic` patch's faces as internal faces of the solver: face i of the patch is the
/// solver face `pair_faces.start + i`, whose owner is the patch's cell on the side listed
/// first in `boundary` (`owner_side`) and whose area vector points out of that cell.
#[derive(Clone, Debug, PartialEq)]
pub struct CyclicSide {
    /// The partner patch (`neighbourPatch`), by index.
    pub neighbour_patch: usize,
    /// The solver faces of the pairs, in patch face order.
    pub pair_faces: std::ops::Range<usize>,
    /// True for the patch listed first (the pair faces carry its S_f and flux sign).
    pub owner_side: bool,
}

impl FvPatch {
    /// True for `empty` patches, whose faces take no part in the discretisation (2-D cases).
    pub fn is_empty(&self) -> bool {
        self.patch_type == "empty"
    }

    /// True for a `cyclic` patch (its faces are internal faces of the solver).
    pub fn is_cyclic(&self) -> bool {
        self.cyclic.is_some()
    }

    /// The patch faces as indices into boundary arrays (face − number of internal faces).
    pub fn boundary_range(&self, n_internal: usize) -> std::ops::Range<usize> {
        self.faces.start - n_internal..self.faces.end - n_internal
    }

    /// The flux of each face of the patch out of the domain on this side (m³/s) from the solver
    /// face fluxes `phi`: the boundary faces' own, or ± the pair faces' for a cyclic patch
    /// (as OpenFOAM holds `phi` on both sides of a cyclic).
    pub fn face_fluxes(&self, phi: &[f64]) -> Vec<f64> {
        match &self.cyclic {
            Some(c) if c.owner_side => phi[c.pair_faces.clone()].to_vec(),
            Some(c) => phi[c.pair_faces.clone()].iter().map(|x| -x).collect(),
            None => phi[self.faces.clone()].to_vec(),
        }
    }
}

/// Geometry and interpolation data of a polyMesh for the finite-volume operators.
///
/// Faces are numbered as in OpenFOAM — internal faces, then boundary faces patch by patch —
/// except that each pair of `cyclic` faces is one internal face ([`crate::cyclic`]): the
/// mesh's internal faces `0..n_mesh_internal` keep their numbers, the pair faces follow
/// (`n_mesh_internal..n_internal`, pair by pair in the order of their first patch, face by
/// face), then the faces of the other patches in mesh order. Arrays named "boundary" are
/// indexed by `face − n_internal`. Without cyclic patches the numbering is the mesh's.
#[derive(Clone, Debug)]
pub struct FvGeometry {
    /// Number of cells.
    pub n_cells: usize,
    /// Number of internal faces, cyclic pair faces included.
    pub n_internal: usize,
    /// Number of the mesh's own internal faces (the first ones); the faces from
    /// `n_mesh_internal` to `n_internal` are cyclic pairs, which the matrices hold as
    /// interfaces ([`RowAddressing`]).
    pub n_mesh_internal: usize,
    /// Owner cell of every face.
    pub owner: Vec<u32>,
    /// Neighbour cell of every internal face.
    pub neighbour: Vec<u32>,
    /// Face area vectors S_f (m²), pointing out of the owner.
    pub sf: Vec<V3>,
    /// |S_f| (m²).
    pub mag_sf: Vec<f64>,
    /// Face centres (m).
    pub cf: Vec<V3>,
    /// Cell centres (m).
    pub c: Vec<V3>,
    /// Cell volumes (m³).
    pub v: Vec<f64>,
    /// Owner weight of linear interpolation on internal faces,
    /// w = |S·(C_N − C_f)| / (|S·(C_f − C_P)| + |S·(C_N − C_f)|), so
    /// φ_f = w φ_P + (1 − w) φ_N (OpenFOAM `surfaceInterpolation::makeWeights`); on cyclic
    /// pair faces [`crate::cyclic::PairGeometry::weight`].
    pub weight: Vec<f64>,
    /// Delta vector of every face (m): C_N − C_P on internal faces ((C_f − C_P) −
    /// (C_f,N − C_N) across a cyclic pair, v1912's `cyclicFvPatch::delta`); on boundary faces the
    /// normal projection n̂ (n̂·(C_f − C_P)) of the centre-to-face vector (OpenFOAM's
    /// `fvPatch::delta` for non-coupled patches).
    pub delta: Vec<V3>,
    /// Non-orthogonal delta coefficient of every face (1/m): 1 / max(n̂·d, 0.05 |d|)
    /// (OpenFOAM `nonOrthDeltaCoeffs`); on boundary faces 1/(n̂·d).
    pub delta_coeff: Vec<f64>,
    /// Non-orthogonal correction vector of internal faces (dimensionless):
    /// k = n̂ − d · delta_coeff, so that n̂·∇φ ≈ delta_coeff (φ_N − φ_P) + k·(∇φ)_f
    /// ("corrected" snGrad, Jasak 1996 §3.3.1.3 over-relaxed approach as OpenFOAM uses it);
    /// all zero when no component of any face exceeds [`ROUNDOFF_K`] (the round-off of an
    /// orthogonal mesh).
    pub corr_vec: Vec<V3>,
    /// Every internal face's [`Self::corr_vec`] is zero (an orthogonal mesh): the
    /// `corrected` schemes' explicit corrections are then zero, and are skipped.
    pub orthogonal: bool,
    /// Boundary patches in file order.
    pub patches: Vec<FvPatch>,
    /// Whether each boundary face belongs to an `empty` patch (skipped by every operator).
    pub boundary_empty: Vec<bool>,
    /// Cell → face adjacency, CSR offsets (length `n_cells + 1`).
    pub cell_offsets: Vec<u32>,
    /// Cell → face adjacency, the faces of each cell in increasing face order, without faces of
    /// `empty` patches.
    pub cell_faces: Vec<u32>,
    /// Row-wise addressing of the matrices of the mesh (internal faces only).
    pub rows: RowAddressing,
    /// The directions the equations are solved in: false for a direction normal to the
    /// `empty` patches of a 2-D case (OpenFOAM's `polyMesh::solutionD`), whose velocity
    /// component is not solved for.
    pub solution_dirs: [bool; 3],
    /// GAMG's pairing weights of the mesh's matrix entries, made at their first use
    /// ([`FvGeometry::pair_weights`]).
    pair_weights: std::sync::OnceLock<Arc<Vec<f64>>>,
}

impl FvGeometry {
    /// GAMG's `faceAreaPair` weights of this geometry (`crate::linsolve`), computed by `make`
    /// at the first call and kept: they follow the faces alone, so every pressure solve on the
    /// mesh shares them (a geometry changed after that call keeps the old ones).
    pub(crate) fn pair_weights(&self, make: impl FnOnce(&FvGeometry) -> Vec<f64>) -> Arc<Vec<f64>> {
        self.pair_weights
            .get_or_init(|| Arc::new(make(self)))
            .clone()
    }

    /// Builds the geometry of `mesh` (checks topology and cell volumes via
    /// [`MeshGeometry::new`]).
    pub fn new(mesh: &PolyMesh) -> Result<Self> {
        let g = MeshGeometry::new(mesh)?;
        Self::from_geometry(mesh, &g)
    }

    /// Builds from a mesh and its already computed geometry.
    pub fn from_geometry(mesh: &PolyMesh, g: &MeshGeometry) -> Result<Self> {
        g.check_matches(mesh)?;
        let n_cells = mesh.n_cells;
        let pairs = mesh::cyclic::pairs(mesh, g).map_err(FvError::from_mesh)?;
        let order = FaceOrder::new(mesh, &pairs);
        let (n_mesh_internal, n_internal) = (order.n_mesh_internal, order.n_internal);
        let mesh_face = &order.mesh_face;
        let owner: Vec<u32> = mesh_face.iter().map(|&f| mesh.owner[f]).collect();
        let mut neighbour = mesh.neighbour.clone();
        neighbour.extend(order.partner.iter().map(|&f| mesh.owner[f]));
        let sf: Vec<V3> = mesh_face.iter().map(|&f| g.face_areas[f]).collect();
        let cf: Vec<V3> = mesh_face.iter().map(|&f| g.face_centres[f]).collect();
        let c = g.cell_centres.clone();
        let mag_sf: Vec<f64> = sf.iter().map(|&s| s.norm()).collect();
        if let Some(f) = mag_sf.iter().position(|&a| a.is_nan() || a <= 0.0) {
            return Err(FvError::Value {
                what: format!("face {}", mesh_face[f]),
                msg: "zero area".into(),
            });
        }
        let faces = SolverFaces {
            owner: &owner,
            neighbour: &neighbour,
            sf: &sf,
            mag_sf: &mag_sf,
            cf: &cf,
        };
        let deltas = Deltas::new(g, &order, &faces);
        let patches = order.patches(mesh, &pairs);
        let mut boundary_empty = vec![false; mesh_face.len() - n_internal];
        for p in patches.iter().filter(|p| p.is_empty()) {
            for b in p.boundary_range(n_internal) {
                boundary_empty[b] = true;
            }
        }
        let (cell_offsets, cell_faces) = cell_faces(n_cells, &faces, n_internal, &boundary_empty);
        let rows = RowAddressing::new(n_cells, &owner[..n_internal], &neighbour, n_mesh_internal);
        let solution_dirs = solution_dirs(&sf, &boundary_empty, n_internal);
        Ok(FvGeometry {
            n_cells,
            n_internal,
            n_mesh_internal,
            owner,
            neighbour,
            sf,
            mag_sf,
            cf,
            c,
            v: g.cell_volumes.clone(),
            weight: deltas.weight,
            delta: deltas.delta,
            delta_coeff: deltas.delta_coeff,
            orthogonal: deltas.corr_vec.iter().all(|k| k.iter().all(|&x| x == 0.0)),
            corr_vec: deltas.corr_vec,
            patches,
            boundary_empty,
            cell_offsets,
            cell_faces,
            rows,
            solution_dirs,
            pair_weights: std::sync::OnceLock::new(),
        })
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.owner.len()
    }

    /// Number of boundary faces.
    pub fn n_boundary(&self) -> usize {
        self.owner.len() - self.n_internal
    }

    /// The faces of cell `c` (increasing face order, `empty` faces left out).
    #[inline]
    pub fn faces_of(&self, c: usize) -> &[u32] {
        &self.cell_faces[self.cell_offsets[c] as usize..self.cell_offsets[c + 1] as usize]
    }

    /// +1 if cell `c` owns face `f`, −1 if it is the neighbour (the sign of S_f out of `c`).
    #[inline]
    pub fn sign(&self, c: usize, f: usize) -> f64 {
        if self.owner[f] as usize == c {
            1.0
        } else {
            -1.0
        }
    }

    /// The other cell across internal face `f` from cell `c`.
    #[inline]
    pub fn other(&self, c: usize, f: usize) -> usize {
        let o = self.owner[f] as usize;
        if o == c {
            self.neighbour[f] as usize
        } else {
            o
        }
    }

    /// The index of the patch called `name`.
    pub fn patch_index(&self, name: &str) -> Option<usize> {
        self.patches.iter().position(|p| p.name == name)
    }

    /// Unit normal of face `f` (out of the owner).
    #[inline]
    pub fn nhat(&self, f: usize) -> V3 {
        1.0 / self.mag_sf[f] * self.sf[f]
    }

    /// True when internal face `f` is a cyclic pair ([`crate::cyclic`]).
    #[inline]
    pub fn is_pair(&self, f: usize) -> bool {
        (self.n_mesh_internal..self.n_internal).contains(&f)
    }

    /// The vector from the centre of the cell on the `owner_side` (else the neighbour side)
    /// of internal face `f` to the face centre (m). Across a cyclic pair the neighbour's centre
    /// is taken where the translation puts it, C_f − d − C_P (as v1912's `linearUpwind` forms it
    /// on coupled patches).
    #[inline]
    pub fn face_from_cell(&self, f: usize, owner_side: bool) -> V3 {
        let (o, n) = (self.owner[f] as usize, self.neighbour[f] as usize);
        match (owner_side, self.is_pair(f)) {
            (true, _) => self.cf[f] - self.c[o],
            (false, false) => self.cf[f] - self.c[n],
            (false, true) => self.cf[f] - self.delta[f] - self.c[o],
        }
    }

    /// The vector from cell `c` to the cell across internal face `f` (m): C_N − C_P seen
    /// from c (the pair's delta across a cyclic).
    #[inline]
    pub fn to_other(&self, c: usize, f: usize) -> V3 {
        if self.is_pair(f) {
            if self.owner[f] as usize == c {
                self.delta[f]
            } else {
                -self.delta[f]
            }
        } else {
            self.c[self.other(c, f)] - self.c[c]
        }
    }
}

/// The solution directions of a mesh (as OpenFOAM's `polyMesh::solutionD`): with s the sum
/// over the `empty` faces of the component magnitudes of S_f, a direction i is left out when
/// s_i/|s| > 1e-6 (the normal of a 2-D case's front and back planes). A mesh without `empty`
/// faces solves in all three directions.
fn solution_dirs(sf: &[V3], boundary_empty: &[bool], n_internal: usize) -> [bool; 3] {
    let mut sum = V3::zeros();
    for (b, &empty) in boundary_empty.iter().enumerate() {
        if empty {
            let s = sf[n_internal + b];
            for i in 0..3 {
                sum[i] += s[i].abs();
            }
        }
    }
    let m = sum.norm();
    if m == 0.0 {
        return [true; 3];
    }
    std::array::from_fn(|i| sum[i] / m <= 1e-6)
}

/// The solver's faces as mesh faces ([`FvGeometry`]'s numbering): the mesh's internal faces,
/// the first side of each cyclic pair, the faces of the other patches.
struct FaceOrder {
    /// The mesh face of each solver face (the first side's for a pair face).
    mesh_face: Vec<usize>,
    /// The second side's mesh face of each pair face, in pair-face order.
    partner: Vec<usize>,
    /// Per patch, the first pair face of a cyclic patch (`usize::MAX` for the others).
    pair_start: Vec<usize>,
    /// Per patch, the first solver face of its faces (an empty range for a cyclic patch).
    patch_start: Vec<usize>,
    /// The mesh's own internal faces.
    n_mesh_internal: usize,
    /// Internal faces, pair faces included.
    n_internal: usize,
}

impl FaceOrder {
    fn new(mesh: &PolyMesh, pairs: &[mesh::cyclic::CyclicPair]) -> FaceOrder {
        let n_mesh_internal = mesh.n_internal_faces();
        let mut mesh_face: Vec<usize> = (0..n_mesh_internal).collect();
        let mut partner: Vec<usize> = Vec::new();
        let mut pair_start = vec![usize::MAX; mesh.boundary.len()];
        for pr in pairs {
            pair_start[pr.first] = mesh_face.len();
            pair_start[pr.second] = mesh_face.len();
            let (a, b) = (&mesh.boundary[pr.first], &mesh.boundary[pr.second]);
            mesh_face.extend(a.faces());
            partner.extend(b.faces());
        }
        let n_internal = mesh_face.len();
        let mut patch_start = vec![0; mesh.boundary.len()];
        for (i, p) in mesh.boundary.iter().enumerate() {
            patch_start[i] = mesh_face.len();
            if p.patch_type != "cyclic" {
                mesh_face.extend(p.faces());
            }
        }
        FaceOrder {
            mesh_face,
            partner,
            pair_start,
            patch_start,
            n_mesh_internal,
            n_internal,
        }
    }

    /// The mesh's patches with their solver faces ([`FvPatch`]).
    fn patches(&self, mesh: &PolyMesh, pairs: &[mesh::cyclic::CyclicPair]) -> Vec<FvPatch> {
        mesh.boundary
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let cyclic = pairs
                    .iter()
                    .find(|pr| pr.first == i || pr.second == i)
                    .map(|pr| CyclicSide {
                        neighbour_patch: if pr.first == i { pr.second } else { pr.first },
                        pair_faces: self.pair_start[i]..self.pair_start[i] + p.n_faces,
                        owner_side: pr.first == i,
                    });
                let start = self.patch_start[i];
                FvPatch {
                    name: p.name.clone(),
                    patch_type: p.patch_type.clone(),
                    faces: if cyclic.is_some() {
                        start..start
                    } else {
                        start..start + p.n_faces
                    },
                    mesh_faces: p.faces(),
                    cyclic,
                }
            })
            .collect()
    }
}

/// The per-face arrays of [`FvGeometry`] in the solver's numbering, for the helpers building
/// the rest.
struct SolverFaces<'a> {
    owner: &'a [u32],
    neighbour: &'a [u32],
    sf: &'a [V3],
    mag_sf: &'a [f64],
    cf: &'a [V3],
}

/// The largest component of a non-orthogonal correction vector k = n̂ − d·δ (a dimensionless
/// difference of unit-size vectors) that is round-off: a mesh none of whose faces has more is
/// orthogonal, and its vectors are set to zero. The faces of blockMesh's uniform boxes leave
/// up to 2.3e-13 (the 320² and 48³ RAS cavities), a face tilted by 0.001° leaves 1.7e-5: far
/// apart. Without it every `corrected` scheme on such a box spent a Gauss gradient and a face
/// pass per equation and corrector on corrections of relative size 1e-13 (OpenFOAM computes
/// them too; 6 % of the one-thread time of 30 steps of the 48³ cavity). On a mesh with a
/// real correction anywhere every face keeps its vector as computed, OpenFOAM's arithmetic
/// (the elbow's 1200 p solves take icoFoam's iterations, `cli/tests/fluid.rs`).
pub const ROUNDOFF_K: f64 = 1e-10;

/// [`FvGeometry`]'s interpolation weights, delta vectors and coefficients and non-orthogonal
/// correction vectors (see the fields' docs there).
struct Deltas {
    weight: Vec<f64>,
    delta: Vec<V3>,
    delta_coeff: Vec<f64>,
    corr_vec: Vec<V3>,
}

impl Deltas {
    fn new(g: &MeshGeometry, order: &FaceOrder, faces: &SolverFaces) -> Deltas {
        let (n_mesh_internal, n_internal) = (order.n_mesh_internal, order.n_internal);
        let n_faces = order.mesh_face.len();
        let SolverFaces {
            owner,
            neighbour,
            sf,
            mag_sf,
            cf,
        } = *faces;
        let c = &g.cell_centres;
        let mut weight = vec![0.5; n_internal];
        let mut delta = vec![V3::zeros(); n_faces];
        let mut delta_coeff = vec![0.0; n_faces];
        let mut corr_vec = vec![V3::zeros(); n_internal];
        for f in 0..n_internal {
            let (p, n) = (owner[f] as usize, neighbour[f] as usize);
            let nhat = 1.0 / mag_sf[f] * sf[f];
            let d = if f < n_mesh_internal {
                let sfd_own = sf[f].dot(&(cf[f] - c[p])).abs();
                let sfd_nei = sf[f].dot(&(c[n] - cf[f])).abs();
                if sfd_own + sfd_nei > mesh::geometry::ROOTVSMALL {
                    weight[f] = sfd_nei / (sfd_own + sfd_nei);
                }
                c[n] - c[p]
            } else {
                let k = f - n_mesh_internal;
                let pg =
                    crate::cyclic::face_geometry(g, p, n, order.mesh_face[f], order.partner[k]);
                weight[f] = pg.weight;
                pg.delta
            };
            delta[f] = d;
            delta_coeff[f] = 1.0 / nhat.dot(&d).max(0.05 * d.norm());
            corr_vec[f] = nhat - (delta_coeff[f] * d);
        }
        // An orthogonal mesh leaves only round-off here (≤ 2.3e-13 on the RAS cavities of
        // benches/fluid-speed): when no face has more, the mesh is orthogonal (ROUNDOFF_K).
        // A mesh with one real correction keeps every face's vector as computed.
        if corr_vec.iter().all(|k| k.amax() <= ROUNDOFF_K) {
            corr_vec.iter_mut().for_each(|k| *k = V3::zeros());
        }
        for f in n_internal..n_faces {
            let p = owner[f] as usize;
            let nhat = 1.0 / mag_sf[f] * sf[f];
            let d = nhat.dot(&(cf[f] - c[p])) * nhat;
            delta[f] = d;
            let dn = nhat.dot(&d);
            delta_coeff[f] = 1.0 / dn.max(0.05 * d.norm()).max(mesh::geometry::VSMALL);
        }
        Deltas {
            weight,
            delta,
            delta_coeff,
            corr_vec,
        }
    }
}

/// The cell → face adjacency ([`FvGeometry::cell_offsets`], [`FvGeometry::cell_faces`]),
/// faces of `empty` patches left out.
fn cell_faces(
    n_cells: usize,
    faces: &SolverFaces,
    n_internal: usize,
    boundary_empty: &[bool],
) -> (Vec<u32>, Vec<u32>) {
    let (owner, neighbour) = (faces.owner, faces.neighbour);
    let n_faces = owner.len();
    let mut count = vec![0u32; n_cells + 1];
    for f in 0..n_faces {
        if f >= n_internal && boundary_empty[f - n_internal] {
            continue;
        }
        count[owner[f] as usize + 1] += 1;
        if f < n_internal {
            count[neighbour[f] as usize + 1] += 1;
        }
    }
    for i in 0..n_cells {
        count[i + 1] += count[i];
    }
    let cell_offsets = count;
    let mut fill: Vec<u32> = cell_offsets[..n_cells].to_vec();
    let mut cell_faces = vec![0u32; cell_offsets[n_cells] as usize];
    for f in 0..n_faces {
        if f >= n_internal && boundary_empty[f - n_internal] {
            continue;
        }
        let p = owner[f] as usize;
        cell_faces[fill[p] as usize] = f as u32;
        fill[p] += 1;
        if f < n_internal {
            let n = neighbour[f] as usize;
            cell_faces[fill[n] as usize] = f as u32;
            fill[n] += 1;
        }
    }
    // Faces were visited in increasing order, so each cell's list is sorted: sums over a
    // cell's faces run in face order, as OpenFOAM's face loops accumulate them.
    (cell_offsets, cell_faces)
}
