//! The polyMesh data model: points, faces, owner, neighbour and boundary patches, exactly as
//! OpenFOAM stores them in `constant/polyMesh` (upper-triangular face order: internal faces
//! first, then each patch's faces contiguously).
//!
//! This module only holds and checks data; reading and writing live in `poly_mesh_io`, geometry
//! (face areas, cell volumes, point location) in the `mesh` crate.

use std::fmt;

/// A cell, face or point index, as OpenFOAM's `label` with `WM_LABEL_SIZE=32`.
pub type Label = u32;

/// A list of faces stored compactly, like OpenFOAM's `faceCompactList`: `offsets` has one entry
/// per face plus one, and face `i` is `labels[offsets[i]..offsets[i + 1]]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceList {
    pub(crate) offsets: Vec<Label>,
    pub(crate) labels: Vec<Label>,
}

impl Default for FaceList {
    fn default() -> Self {
        Self::new()
    }
}

impl FaceList {
    /// An empty list.
    pub fn new() -> Self {
        Self {
            offsets: vec![0],
            labels: Vec::new(),
        }
    }

    /// An empty list with room for `faces` faces of `labels` point labels in all.
    pub fn with_capacity(faces: usize, labels: usize) -> Self {
        let mut offsets = Vec::with_capacity(faces + 1);
        offsets.push(0);
        Self {
            offsets,
            labels: Vec::with_capacity(labels),
        }
    }

    /// Builds from the compact arrays; checks that offsets start at 0, never decrease and end at
    /// `labels.len()`.
    pub fn from_compact(offsets: Vec<Label>, labels: Vec<Label>) -> Result<Self, String> {
        if offsets.first() != Some(&0) {
            return Err("face offsets must start at 0".into());
        }
        if let Some(i) = offsets.windows(2).position(|w| w[1] < w[0]) {
            return Err(format!("face offsets decrease at face {i}"));
        }
        if *offsets.last().unwrap() as usize != labels.len() {
            return Err(format!(
                "last face offset {} differs from the number of labels {}",
                offsets.last().unwrap(),
                labels.len()
            ));
        }
        Ok(Self { offsets, labels })
    }

    /// Appends one face.
    pub fn push(&mut self, face: &[Label]) {
        self.labels.extend_from_slice(face);
        self.offsets.push(self.labels.len() as Label);
    }

    /// Number of faces.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// True when there are no faces.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The point labels of face `i`, in OpenFOAM's order (right-handed: the normal points out of
    /// the owner cell).
    #[inline]
    pub fn face(&self, i: usize) -> &[Label] {
        &self.labels[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Iterates over the faces.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &[Label]> + '_ {
        self.offsets
            .windows(2)
            .map(move |w| &self.labels[w[0] as usize..w[1] as usize])
    }

    /// The offsets array (length `len() + 1`).
    pub fn offsets(&self) -> &[Label] {
        &self.offsets
    }

    /// All point labels, face after face.
    pub fn labels(&self) -> &[Label] {
        &self.labels
    }
}

/// One boundary patch of `constant/polyMesh/boundary`.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// Patch name, e.g. `inlet`.
    pub name: String,
    /// The `type` entry: `patch`, `wall`, `empty`, `symmetryPlane`, `cyclic`, `processor`, …
    pub patch_type: String,
    /// Number of faces (`nFaces`).
    pub n_faces: usize,
    /// Index of the first face (`startFace`).
    pub start_face: usize,
    /// Every other entry of the patch dictionary (`inGroups`, `neighbourPatch`, `myProcNo`, …),
    /// kept in order as keyword and value text so that a rewrite preserves it.
    pub extra: Vec<(String, String)>,
}

impl Patch {
    /// The face index range of this patch.
    pub fn faces(&self) -> std::ops::Range<usize> {
        self.start_face..self.start_face + self.n_faces
    }
}

/// An OpenFOAM polyMesh.
#[derive(Clone, Debug, PartialEq)]
pub struct PolyMesh {
    /// Point coordinates, m.
    pub points: Vec<[f64; 3]>,
    /// All faces: internal faces first, then boundary faces patch by patch.
    pub faces: FaceList,
    /// Owner cell of every face (length = number of faces).
    pub owner: Vec<Label>,
    /// Neighbour cell of every internal face (length = number of internal faces).
    pub neighbour: Vec<Label>,
    /// Boundary patches in file order.
    pub boundary: Vec<Patch>,
    /// Number of cells (one more than the largest owner/neighbour label).
    pub n_cells: usize,
}

/// A structural inconsistency found by [`PolyMesh::check`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TopologyError(pub String);

impl fmt::Display for TopologyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for TopologyError {}

impl PolyMesh {
    /// Number of internal faces.
    pub fn n_internal_faces(&self) -> usize {
        self.neighbour.len()
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.faces.len()
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.points.len()
    }

    /// The patch that owns boundary face `face`, if any.
    pub fn patch_of_face(&self, face: usize) -> Option<usize> {
        self.boundary.iter().position(|p| p.faces().contains(&face))
    }

    /// Number of cells implied by owner and neighbour (largest label + 1).
    pub fn count_cells(owner: &[Label], neighbour: &[Label]) -> usize {
        owner
            .iter()
            .chain(neighbour)
            .copied()
            .max()
            .map_or(0, |m| m as usize + 1)
    }

    /// Checks the structure: list lengths agree, every face names existing points and has at
    /// least three of them, owner < neighbour on internal faces, patches cover the boundary
    /// faces contiguously in order, and every cell has at least four faces.
    pub fn check(&self) -> Result<(), TopologyError> {
        let err = |s: String| Err(TopologyError(s));
        let nf = self.faces.len();
        let np = self.points.len();
        if self.owner.len() != nf {
            return err(format!(
                "owner has {} entries but there are {nf} faces",
                self.owner.len()
            ));
        }
        if self.neighbour.len() > nf {
            return err(format!(
                "neighbour has {} entries but there are only {nf} faces",
                self.neighbour.len()
            ));
        }
        for (i, f) in self.faces.iter().enumerate() {
            if f.len() < 3 {
                return err(format!(
                    "face {i} has {} points (needs at least 3)",
                    f.len()
                ));
            }
            if let Some(&p) = f.iter().find(|&&p| p as usize >= np) {
                return err(format!(
                    "face {i} names point {p} but there are only {np} points"
                ));
            }
        }
        for (i, (&o, &n)) in self.owner.iter().zip(&self.neighbour).enumerate() {
            if o >= n {
                return err(format!(
                    "internal face {i}: owner {o} is not below neighbour {n}"
                ));
            }
        }
        for (i, &c) in self.owner.iter().chain(&self.neighbour).enumerate() {
            if c as usize >= self.n_cells {
                return err(format!(
                    "owner/neighbour entry {i} names cell {c} but there are {} cells",
                    self.n_cells
                ));
            }
        }
        let mut next = self.n_internal_faces();
        for p in &self.boundary {
            if p.start_face != next {
                return err(format!(
                    "patch {}: startFace {} but the previous faces end at {next}",
                    p.name, p.start_face
                ));
            }
            next += p.n_faces;
        }
        if next != nf {
            return err(format!(
                "patches end at face {next} but there are {nf} faces"
            ));
        }
        let mut count = vec![0u32; self.n_cells];
        for &c in self.owner.iter().chain(&self.neighbour) {
            count[c as usize] += 1;
        }
        if let Some(c) = count.iter().position(|&k| k < 4) {
            return err(format!(
                "cell {c} has {} faces (needs at least 4)",
                count[c]
            ));
        }
        Ok(())
    }

    /// For each cell, the list of its faces (owner and neighbour sides), in face order.
    pub fn cell_faces(&self) -> FaceList {
        let mut count = vec![0 as Label; self.n_cells + 1];
        for &c in self.owner.iter().chain(&self.neighbour) {
            count[c as usize + 1] += 1;
        }
        for i in 0..self.n_cells {
            count[i + 1] += count[i];
        }
        let offsets = count.clone();
        let mut labels = vec![0 as Label; *count.last().unwrap() as usize];
        let mut fill = count;
        for (f, &c) in self.owner.iter().enumerate() {
            labels[fill[c as usize] as usize] = f as Label;
            fill[c as usize] += 1;
        }
        for (f, &c) in self.neighbour.iter().enumerate() {
            labels[fill[c as usize] as usize] = f as Label;
            fill[c as usize] += 1;
        }
        for c in 0..self.n_cells {
            let (a, b) = (offsets[c] as usize, offsets[c + 1] as usize);
            labels[a..b].sort_unstable();
        }
        FaceList { offsets, labels }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube as one hex cell with six boundary faces in one patch.
    pub(crate) fn unit_cube() -> PolyMesh {
        let points = vec![
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [1., 1., 1.],
            [0., 1., 1.],
        ];
        let mut faces = FaceList::new();
        for f in [
            [0, 4, 7, 3],
            [1, 2, 6, 5],
            [0, 1, 5, 4],
            [3, 7, 6, 2],
            [0, 3, 2, 1],
            [4, 5, 6, 7],
        ] {
            faces.push(&f);
        }
        PolyMesh {
            points,
            faces,
            owner: vec![0; 6],
            neighbour: vec![],
            boundary: vec![Patch {
                name: "walls".into(),
                patch_type: "wall".into(),
                n_faces: 6,
                start_face: 0,
                extra: vec![],
            }],
            n_cells: 1,
        }
    }

    #[test]
    fn unit_cube_is_valid_and_cell_faces_lists_all_six() {
        let m = unit_cube();
        m.check().unwrap();
        let cf = m.cell_faces();
        assert_eq!(cf.len(), 1);
        assert_eq!(cf.face(0), &[0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn check_reports_bad_point_label() {
        let mut m = unit_cube();
        let mut faces = FaceList::new();
        for (i, f) in m.faces.iter().enumerate() {
            if i == 2 {
                faces.push(&[0, 1, 9, 4]);
            } else {
                faces.push(f);
            }
        }
        m.faces = faces;
        let e = m.check().unwrap_err();
        assert!(e.0.contains("face 2 names point 9"), "{e}");
    }

    #[test]
    fn face_list_rejects_inconsistent_offsets() {
        assert!(FaceList::from_compact(vec![0, 4, 3], vec![0; 3]).is_err());
        assert!(FaceList::from_compact(vec![1, 4], vec![0; 4]).is_err());
        assert!(FaceList::from_compact(vec![0, 4], vec![0; 5]).is_err());
        let f = FaceList::from_compact(vec![0, 3, 7], (0..7).collect()).unwrap();
        assert_eq!(f.face(1), &[3, 4, 5, 6]);
    }
}
