//! Face centres and area vectors, cell centres and volumes, computed exactly as OpenFOAM v1912
//! does (`primitiveMeshFaceCentresAndAreas.C`, `primitiveMeshCellCentresAndVols.C`), with the same
//! operation order, so that the results match OpenFOAM's `writeCellVolumes`/`writeCellCentres`
//! output to the last bit on x86-64 (no fused multiply-add on either side).

use crate::error::MeshError;
use crate::v3::{add, cross, div, dot, mag, scale, sub, V3};
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
    pub min: [f64; 3],
    /// Largest coordinates.
    pub max: [f64; 3],
}

impl Aabb {
    /// The empty box (min = +∞, max = −∞).
    pub const EMPTY: Aabb = Aabb {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    /// The smallest box holding `points` (EMPTY for no points).
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a [f64; 3]>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.include(*p);
        }
        b
    }

    /// Grows the box to hold `p`.
    #[inline]
    pub fn include(&mut self, p: [f64; 3]) {
        for (a, x) in p.into_iter().enumerate() {
            self.min[a] = self.min[a].min(x);
            self.max[a] = self.max[a].max(x);
        }
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
    pub fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|a| p[a] >= self.min[a] && p[a] <= self.max[a])
    }

    /// Edge lengths `max − min`.
    pub fn extent(&self) -> [f64; 3] {
        sub(self.max, self.min)
    }
}

/// Geometry of a polyMesh, one array per quantity (structure of arrays), indexed by face or cell.
///
/// All lengths in m, areas in m², volumes in m³.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshGeometry {
    /// Face centres (area-weighted centroid of the triangle fan), m.
    pub face_centres: Vec<[f64; 3]>,
    /// Face area vectors, m²: magnitude = area, direction = normal out of the owner cell.
    pub face_areas: Vec<[f64; 3]>,
    /// OpenFOAM's estimated cell centres `cEst` = mean of the cell's face centres, m. This is the
    /// apex of every pyramid (and tetrahedron) of the cell decomposition.
    pub cell_centre_estimates: Vec<[f64; 3]>,
    /// Cell centres (volume-weighted centroid of the face pyramids), m.
    pub cell_centres: Vec<[f64; 3]>,
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
        let (face_centres, face_areas) = face_centres_and_areas(&mesh.points, &mesh.faces);
        let cell_faces = mesh.cell_faces();
        let (cell_centre_estimates, cell_centres, cell_volumes) =
            cell_centres_and_volumes(mesh, &cell_faces, &face_centres, &face_areas);
        Ok(Self {
            face_centres,
            face_areas,
            cell_centre_estimates,
            cell_centres,
            cell_volumes,
            bounds: Aabb::of_points(&mesh.points),
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
pub fn face_centre_and_area(points: &[[f64; 3]], face: &[Label]) -> ([f64; 3], [f64; 3]) {
    let p = |i: usize| points[face[i] as usize];
    let n = face.len();
    if n == 3 {
        let c = scale(1.0 / 3.0, add(add(p(0), p(1)), p(2)));
        let a = scale(0.5, cross(sub(p(1), p(0)), sub(p(2), p(0))));
        return (c, a);
    }
    let mut est = p(0);
    for i in 1..n {
        est = add(est, p(i));
    }
    est = div(est, n as f64);
    let mut sum_n = [0.0; 3];
    let mut sum_a = 0.0;
    let mut sum_ac = [0.0; 3];
    for i in 0..n {
        let this = p(i);
        let next = p(if i == n - 1 { 0 } else { i + 1 });
        let c = add(add(this, next), est);
        let ni = cross(sub(next, this), sub(est, this));
        let a = mag(ni);
        sum_n = add(sum_n, ni);
        sum_a += a;
        sum_ac = add(sum_ac, scale(a, c));
    }
    if sum_a < ROOTVSMALL {
        (est, [0.0; 3])
    } else {
        (div(scale(1.0 / 3.0, sum_ac), sum_a), scale(0.5, sum_n))
    }
}

/// Face centres and area vectors of every face, in parallel.
pub fn face_centres_and_areas(
    points: &[[f64; 3]],
    faces: &FaceList,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let n = faces.len();
    let mut centres = vec![[0.0; 3]; n];
    let mut areas = vec![[0.0; 3]; n];
    centres
        .par_iter_mut()
        .zip(areas.par_iter_mut())
        .enumerate()
        .with_min_len(1024)
        .for_each(|(f, (c, a))| {
            (*c, *a) = face_centre_and_area(points, faces.face(f));
        });
    (centres, areas)
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
    let n = mesh.n_cells;
    let mut est = vec![[0.0; 3]; n];
    let mut ctr = vec![[0.0; 3]; n];
    let mut vol = vec![0.0; n];
    let owner = &mesh.owner;
    est.par_iter_mut()
        .zip(ctr.par_iter_mut())
        .zip(vol.par_iter_mut())
        .enumerate()
        .with_min_len(256)
        .for_each(|(c, ((e, cc), v))| {
            let faces = cell_faces.face(c);
            let owned = || faces.iter().filter(|&&f| owner[f as usize] as usize == c);
            let neighboured = || faces.iter().filter(|&&f| owner[f as usize] as usize != c);
            let mut c_est = [0.0; 3];
            let mut count: Label = 0;
            for &f in owned().chain(neighboured()) {
                c_est = add(c_est, fc[f as usize]);
                count += 1;
            }
            c_est = div(c_est, count as f64);
            let mut sum_c = [0.0; 3];
            let mut sum_v = 0.0;
            let mut accumulate = |f: Label, owner_side: bool| {
                let f = f as usize;
                let pyr3 = if owner_side {
                    dot(fa[f], sub(fc[f], c_est))
                } else {
                    dot(fa[f], sub(c_est, fc[f]))
                };
                let pc = add(scale(3.0 / 4.0, fc[f]), scale(1.0 / 4.0, c_est));
                sum_c = add(sum_c, scale(pyr3, pc));
                sum_v += pyr3;
            };
            for &f in owned() {
                accumulate(f, true);
            }
            for &f in neighboured() {
                accumulate(f, false);
            }
            *cc = if sum_v.abs() > VSMALL {
                div(sum_c, sum_v)
            } else {
                c_est
            };
            *v = sum_v * (1.0 / 3.0);
            *e = c_est;
        });
    (est, ctr, vol)
}
