//! Face centres and area vectors, cell centres and volumes, computed exactly as OpenFOAM v1912
//! does (`primitiveMeshFaceCentresAndAreas.C`, `primitiveMeshCellCentresAndVols.C`), with the same
//! operation order, so that the results match OpenFOAM's `writeCellVolumes`/`writeCellCentres`
//! output to the last bit on x86-64 (no fused multiply-add on either side).

use crate::error::MeshError;
use crate::v3::V3;
use foam::{FaceList, Label, PolyMesh};
use rayon::prelude::*;

/// OpenFOAM's `VSMALL` for double precision.
pub const VSMALL: f64 = 1.0e-300;
/// OpenFOAM's `ROOTVSMALL` for double precision.
pub const ROOTVSMALL: f64 = 1.0e-150;

/// An axis-aligned bounding box, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest coordinates.
    pub min: V3,
    /// Largest coordinates.
    pub max: V3,
}

impl Aabb {
    /// The empty box (min = +∞, max = −∞).
    pub const EMPTY: Aabb = Aabb {
        min: V3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
        max: V3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY),
    };

    /// The smallest box holding `points` (EMPTY for no points).
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a V3>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.include(*p);
        }
        b
    }

    /// Grows the box to hold `p`.
    #[inline]
    pub fn include(&mut self, p: V3) {
        self.min = self.min.inf(&p);
        self.max = self.max.sup(&p);
    }

    /// The smallest box holding both.
    pub fn union(&self, o: &Aabb) -> Aabb {
        let mut b = *self;
        b.include(o.min);
        b.include(o.max);
        b
    }

    /// True when `p` lies in the closed box.
    #[inline]
    pub fn contains(&self, p: V3) -> bool {
        (0..3).all(|a| p[a] >= self.min[a] && p[a] <= self.max[a])
    }

    /// Edge lengths `max − min`.
    pub fn extent(&self) -> V3 {
        self.max - self.min
    }
}

/// Geometry of a polyMesh, one array per quantity (structure of arrays), indexed by face or cell.
///
/// All lengths in m, areas in m², volumes in m³.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshGeometry {
    /// Face centres (area-weighted centroid of the triangle fan), m.
    pub face_centres: Vec<V3>,
    /// Face area vectors, m²: magnitude = area, direction = normal out of the owner cell.
    pub face_areas: Vec<V3>,
    /// OpenFOAM's estimated cell centres `cEst` = mean of the cell's face centres, m. This is the
    /// apex of every pyramid (and tetrahedron) of the cell decomposition.
    pub cell_centre_estimates: Vec<V3>,
    /// Cell centres (volume-weighted centroid of the face pyramids), m.
    pub cell_centres: Vec<V3>,
    /// Cell volumes (sum of the face pyramids), m³.
    pub cell_volumes: Vec<f64>,
    /// Bounding box of the mesh points, m.
    pub bounds: Aabb,
}

impl MeshGeometry {
    /// Checks the mesh topology and point coordinates, computes the geometry and checks that
    /// every cell volume is positive ([`MeshError::InvertedCell`], [`MeshError::DegenerateCell`]
    /// name the first bad cell).
    pub fn new(mesh: &PolyMesh) -> Result<Self, MeshError> {
        let g = Self::compute(mesh)?;
        g.check_volumes()?;
        Ok(g)
    }

    /// Checks the mesh topology and point coordinates and computes the geometry exactly as
    /// OpenFOAM does, without judging the cell volumes (inverted cells keep their negative
    /// volumes, as in OpenFOAM).
    pub fn compute(mesh: &PolyMesh) -> Result<Self, MeshError> {
        mesh.check()?;
        if let Some(i) = mesh
            .points
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError::NonFinitePoint {
                point: i as Label,
                coords: mesh.points[i],
            });
        }
        let points = crate::v3::as_vectors(&mesh.points);
        let (face_centres, face_areas) = face_centres_and_areas(points, &mesh.faces);
        let cell_faces = mesh.cell_faces();
        let (cell_centre_estimates, cell_centres, cell_volumes) =
            cell_centres_and_volumes(mesh, &cell_faces, &face_centres, &face_areas);
        Ok(Self {
            face_centres,
            face_areas,
            cell_centre_estimates,
            cell_centres,
            cell_volumes,
            bounds: Aabb::of_points(points),
        })
    }

    /// The first cell whose volume is not positive and finite, as an error.
    pub fn check_volumes(&self) -> Result<(), MeshError> {
        match self
            .cell_volumes
            .iter()
            .position(|&v| !(v.is_finite() && v > VSMALL))
        {
            None => Ok(()),
            Some(c) => {
                let volume = self.cell_volumes[c];
                let cell = c as Label;
                Err(if volume < -VSMALL {
                    MeshError::InvertedCell { cell, volume }
                } else {
                    MeshError::DegenerateCell { cell, volume }
                })
            }
        }
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.cell_volumes.len()
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.face_areas.len()
    }

    /// Sum of the cell volumes, m³ (OpenFOAM's `gSum(V)`, summed in cell order as checkMesh's
    /// "Total volume").
    pub fn total_volume(&self) -> f64 {
        self.cell_volumes.iter().sum()
    }

    /// Errors unless this geometry has as many cells and faces as `mesh`.
    pub fn check_matches(&self, mesh: &PolyMesh) -> Result<(), MeshError> {
        if self.n_cells() != mesh.n_cells
            || self.n_faces() != mesh.n_faces()
            || self.face_centres.len() != mesh.n_faces()
            || self.cell_centre_estimates.len() != mesh.n_cells
        {
            return Err(MeshError::GeometryMismatch {
                geometry: self.n_cells(),
                geometry_faces: self.n_faces(),
                mesh: mesh.n_cells,
                mesh_faces: mesh.n_faces(),
            });
        }
        Ok(())
    }
}

/// Centre and area vector of one face (points in OpenFOAM order), as
/// `primitiveMesh::makeFaceCentresAndAreas` of v1912:
///
/// * triangle: centre = ⅓(p₀+p₁+p₂), area = ½(p₁−p₀)×(p₂−p₀);
/// * n > 3 points: estimate e = mean of the points; for each edge (pᵢ, pᵢ₊₁) the triangle
///   (pᵢ, pᵢ₊₁, e) gives nᵢ = (pᵢ₊₁−pᵢ)×(e−pᵢ) (twice its area vector) and aᵢ = |nᵢ|;
///   centre = ⅓ Σ aᵢ(pᵢ+pᵢ₊₁+e) / Σ aᵢ, area = ½ Σ nᵢ. The centre is weighted by the
///   triangle area *magnitudes* aᵢ (newer OpenFOAM Foundation releases weight by aᵢ·n̂ instead).
/// * zero-area guard: if Σ aᵢ < `ROOTVSMALL` the centre is e and the area is zero.
///
/// Units: points in m, centre in m, area vector in m².
#[inline]
pub fn face_centre_and_area(points: &[V3], face: &[Label]) -> (V3, V3) {
    let p = |i: usize| points[face[i] as usize];
    let n = face.len();
    if n == 3 {
        let c = 1.0 / 3.0 * ((p(0) + p(1)) + p(2));
        let a = 0.5 * (p(1) - p(0)).cross(&(p(2) - p(0)));
        return (c, a);
    }
    let mut est = p(0);
    for i in 1..n {
        est += p(i);
    }
    est /= n as f64;
    let mut sum_n = V3::zeros();
    let mut sum_a = 0.0;
    let mut sum_ac = V3::zeros();
    for i in 0..n {
        let this = p(i);
        let next = p(if i == n - 1 { 0 } else { i + 1 });
        let c = (this + next) + est;
        let ni = (next - this).cross(&(est - this));
        let a = ni.norm();
        sum_n += ni;
        sum_a += a;
        sum_ac += a * c;
    }
    if sum_a < ROOTVSMALL {
        (est, V3::zeros())
    } else {
        (((1.0 / 3.0 * sum_ac) / sum_a), (0.5 * sum_n))
    }
}

/// Face centres and area vectors of every face, in parallel.
pub fn face_centres_and_areas(points: &[V3], faces: &FaceList) -> (Vec<V3>, Vec<V3>) {
    // Collected, not written into zero-filled vectors: a `Vec<V3>` is not zero-allocated as a
    // `Vec<[f64; 3]>` is, and filling it first cost a fifth of the whole geometry.
    (0..faces.len())
        .into_par_iter()
        .with_min_len(1024)
        .map(|f| face_centre_and_area(points, faces.face(f)))
        .unzip()
}

/// Cell centre estimates, centres and volumes as `primitiveMesh::makeCellCentresAndVols` of
/// v1912, per cell in parallel. Accumulation order per cell is OpenFOAM's: first the faces the
/// cell owns in face order, then the faces it neighbours in face order.
///
/// * cEst = mean of the face centres;
/// * per face, 3 × pyramid volume V₃ = A·(f_c − cEst) on the owner side and A·(cEst − f_c) on the
///   neighbour side (m³), pyramid centroid p_c = ¾ f_c + ¼ cEst (m);
/// * centre = Σ V₃ p_c / Σ V₃ when |Σ V₃| > `VSMALL`, else cEst; volume = ⅓ Σ V₃.
fn cell_centres_and_volumes(
    mesh: &PolyMesh,
    cell_faces: &FaceList,
    fc: &[V3],
    fa: &[V3],
) -> (Vec<V3>, Vec<V3>, Vec<f64>) {
    let owner = &mesh.owner;
    let ((est, ctr), vol) = (0..mesh.n_cells)
        .into_par_iter()
        .with_min_len(256)
        .map(|c| {
            let faces = cell_faces.face(c);
            let owned = || faces.iter().filter(|&&f| owner[f as usize] as usize == c);
            let neighboured = || faces.iter().filter(|&&f| owner[f as usize] as usize != c);
            let mut c_est = V3::zeros();
            let mut count: Label = 0;
            for &f in owned().chain(neighboured()) {
                c_est += fc[f as usize];
                count += 1;
            }
            c_est /= count as f64;
            let mut sum_c = V3::zeros();
            let mut sum_v = 0.0;
            let mut accumulate = |f: Label, owner_side: bool| {
                let f = f as usize;
                let pyr3 = if owner_side {
                    fa[f].dot(&(fc[f] - c_est))
                } else {
                    fa[f].dot(&(c_est - fc[f]))
                };
                let pc = (3.0 / 4.0 * fc[f]) + (1.0 / 4.0 * c_est);
                sum_c += pyr3 * pc;
                sum_v += pyr3;
            };
            for &f in owned() {
                accumulate(f, true);
            }
            for &f in neighboured() {
                accumulate(f, false);
            }
            let centre = if sum_v.abs() > VSMALL {
                sum_c / sum_v
            } else {
                c_est
            };
            ((c_est, centre), sum_v * (1.0 / 3.0))
        })
        .unzip();
    (est, ctr, vol)
}

impl foam::HeapBytes for MeshGeometry {
    fn heap_bytes(&self) -> usize {
        use foam::heap::flat;
        flat(&self.face_centres)
            + flat(&self.face_areas)
            + flat(&self.cell_centre_estimates)
            + flat(&self.cell_centres)
            + flat(&self.cell_volumes)
    }
}
