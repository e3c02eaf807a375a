//! blockMesh dictionary templates we own, and the native generator of the same mesh.
//!
//! A template is a `blockMeshDict` whose cell counts are the placeholders `@NX@`, `@NY@`,
//! `@NZ@` (one hexahedral block, `simpleGrading (1 1 1)`), with the box given by the variables
//! `xMin xMax yMin yMax zMin zMax` (m, times `convertToMeters`) and the vertices in blockMesh's
//! order (vertex 0 at the minimum corner, 1 along +x, 3 along +y, 4 along +z). Each patch of
//! its `boundary` lists whole sides of the box as vertex quadruples. [`Template::fill`] gives
//! the dictionary text for given counts (what Debian's `blockMesh` reads);
//! [`Template::mesh`] builds the same mesh natively: [`mesh::build::hex_grid`] (blockMesh's
//! point and cell numbering) with the boundary faces regrouped into the template's patches,
//! in the template's order of patches and of sides within a patch.

use crate::error::StudyError;
use foam::{Dict, FaceList, Item, Patch, PolyMesh};
use std::path::{Path, PathBuf};

/// The placeholders of the cell counts, in x, y, z order.
pub const PLACEHOLDERS: [&str; 3] = ["@NX@", "@NY@", "@NZ@"];

/// One side of the box, in [`mesh::build::hex_grid`]'s patch order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// x = xMin.
    XMin,
    /// x = xMax.
    XMax,
    /// y = yMin.
    YMin,
    /// y = yMax.
    YMax,
    /// z = zMin.
    ZMin,
    /// z = zMax.
    ZMax,
}

impl Side {
    const ALL: [Side; 6] = [
        Side::XMin,
        Side::XMax,
        Side::YMin,
        Side::YMax,
        Side::ZMin,
        Side::ZMax,
    ];

    /// The side whose four corners are the blockMesh vertex labels `face` (0–7: bit 0 of the
    /// label's corner code is x, bit 1 is y, bit 2 is z, with blockMesh's 0 1 2 3 going round
    /// the bottom), or `None` if the labels are not one side.
    fn of_vertices(face: &[i64]) -> Option<Side> {
        // blockMesh's hex vertex order → (x, y, z) corner bits.
        const CORNER: [[u8; 3]; 8] = [
            [0, 0, 0],
            [1, 0, 0],
            [1, 1, 0],
            [0, 1, 0],
            [0, 0, 1],
            [1, 0, 1],
            [1, 1, 1],
            [0, 1, 1],
        ];
        if face.len() != 4 {
            return None;
        }
        let mut c = Vec::with_capacity(4);
        for &v in face {
            c.push(CORNER.get(usize::try_from(v).ok()?)?);
        }
        let mut distinct = face.to_vec();
        distinct.sort_unstable();
        distinct.dedup();
        if distinct.len() != 4 {
            return None;
        }
        (0..3).find_map(|axis| {
            let v = c[0][axis];
            c.iter()
                .all(|k| k[axis] == v)
                .then_some(Side::ALL[2 * axis + v as usize])
        })
    }
}

/// One patch of the template: name, type and the sides it covers (in the template's order).
#[derive(Clone, Debug, PartialEq)]
pub struct TemplatePatch {
    /// Patch name.
    pub name: String,
    /// Patch type (`patch`, `wall`, `symmetryPlane`, …).
    pub patch_type: String,
    /// The box sides, in the order the template lists them.
    pub sides: Vec<Side>,
}

/// A parsed blockMesh template (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Template {
    /// The file it was read from.
    pub path: PathBuf,
    /// The text with placeholders.
    pub text: String,
    /// Lower corner of the box, m.
    pub lo: [f64; 3],
    /// Upper corner of the box, m.
    pub hi: [f64; 3],
    /// The patches.
    pub patches: Vec<TemplatePatch>,
}

fn template_err(path: &Path, message: impl Into<String>) -> StudyError {
    StudyError::Template {
        path: path.to_owned(),
        message: message.into(),
    }
}

impl Template {
    /// Reads and checks the template at `path`.
    pub fn read(path: &Path) -> Result<Template, StudyError> {
        let text = std::fs::read_to_string(path).map_err(crate::error::io_err(path))?;
        Template::parse(&text, path)
    }

    /// Parses template text (`path` names it in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Template, StudyError> {
        for p in PLACEHOLDERS {
            if !text.contains(p) {
                return Err(template_err(
                    path,
                    format!("placeholder {p} (the cell count) does not occur"),
                ));
            }
        }
        let probe = fill_text(text, [1, 1, 1]);
        let dict = foam::parse_bytes(probe.as_bytes(), path)?.body;
        let get = |k: &str| dict.f64(k).map_err(|e| template_err(path, e.to_string()));
        let scale = dict
            .f64_or("convertToMeters", 1.0)
            .map_err(|e| template_err(path, e.to_string()))?;
        let lo = [get("xMin")?, get("yMin")?, get("zMin")?].map(|v| v * scale);
        let hi = [get("xMax")?, get("yMax")?, get("zMax")?].map(|v| v * scale);
        for a in 0..3 {
            if !(lo[a].is_finite() && hi[a].is_finite() && hi[a] > lo[a]) {
                return Err(template_err(
                    path,
                    format!("the box is empty along axis {a}: {} .. {}", lo[a], hi[a]),
                ));
            }
        }
        check_block(&dict, path)?;
        let patches = read_patches(&dict, path)?;
        Ok(Template {
            path: path.to_owned(),
            text: text.to_owned(),
            lo,
            hi,
            patches,
        })
    }

    /// The box edge lengths, m.
    pub fn lengths(&self) -> [f64; 3] {
        [0, 1, 2].map(|a| self.hi[a] - self.lo[a])
    }

    /// The dictionary text with the cell counts `n` (x, y, z) filled in.
    pub fn fill(&self, n: [usize; 3]) -> String {
        fill_text(&self.text, n)
    }

    /// The mesh blockMesh makes from [`Template::fill`]`(n)`, built natively (module docs).
    pub fn mesh(&self, n: [usize; 3]) -> PolyMesh {
        let planes =
            |a: usize| mesh::build::graded_planes(self.lo[a], self.hi[a], n[a].max(1), 1.0);
        let grid = mesh::build::hex_grid(&planes(0), &planes(1), &planes(2));
        regroup(&grid, &self.patches)
    }

    /// Writes `system/blockMeshDict` (filled) and `constant/polyMesh` (native) into the
    /// OpenFOAM case `cfd`.
    pub fn write_case_mesh(&self, cfd: &Path, n: [usize; 3]) -> Result<PolyMesh, StudyError> {
        let dict = cfd.join("system/blockMeshDict");
        let text = self.fill(n).replace(
            "object      blockMeshDict.template;",
            "object      blockMeshDict;",
        );
        atomic_write::write_atomically(&dict, |w| w.write_all(text.as_bytes()))
            .map_err(crate::error::io_err(&dict))?;
        let mesh = self.mesh(n);
        let dir = cfd.join("constant/polyMesh");
        std::fs::create_dir_all(&dir).map_err(crate::error::io_err(&dir))?;
        foam::poly_mesh_io::write_poly_mesh(&dir, &mesh, foam::Format::Binary)?;
        Ok(mesh)
    }
}

use std::io::Write as _;

fn fill_text(text: &str, n: [usize; 3]) -> String {
    let mut s = text.to_owned();
    for (p, v) in PLACEHOLDERS.iter().zip(n) {
        s = s.replace(p, &v.to_string());
    }
    s
}

/// One block, `hex (0 1 2 3 4 5 6 7) (nx ny nz) simpleGrading (1 1 1)`.
fn check_block(dict: &Dict, path: &Path) -> Result<(), StudyError> {
    let items = dict
        .stream("blocks")
        .map_err(|e| template_err(path, e.to_string()))?;
    let list = match items {
        [Item::List(l)] => l,
        _ => return Err(template_err(path, "`blocks` must be one list")),
    };
    let hexes = list
        .iter()
        .filter(|i| matches!(i, Item::Word(w) if w == "hex"))
        .count();
    let uniform = list.iter().any(
        |i| matches!(i, Item::List(g) if g.len() == 3 && g.iter().all(|x| x.as_f64() == Some(1.0))),
    );
    let order = list.iter().any(|i| {
        matches!(i, Item::List(v) if v.len() == 8
            && v.iter().enumerate().all(|(k, x)| x.as_label() == Some(k as i64)))
    });
    if hexes != 1 || !uniform || !order {
        return Err(template_err(
            path,
            "`blocks` must hold one `hex (0 1 2 3 4 5 6 7) (@NX@ @NY@ @NZ@) simpleGrading (1 1 1)`",
        ));
    }
    Ok(())
}

/// The `boundary` list: `name { type T; faces ((a b c d) …); }` with every face a box side.
fn read_patches(dict: &Dict, path: &Path) -> Result<Vec<TemplatePatch>, StudyError> {
    let items = dict
        .stream("boundary")
        .map_err(|e| template_err(path, e.to_string()))?;
    let list = match items {
        [Item::List(l)] => l,
        _ => return Err(template_err(path, "`boundary` must be one list")),
    };
    let mut out: Vec<TemplatePatch> = Vec::new();
    let mut seen = Vec::new();
    for item in list {
        let Item::Named(name, d) = item else {
            return Err(template_err(
                path,
                "`boundary` entries must be `name { type …; faces (…); }`",
            ));
        };
        let ptype = d
            .word("type")
            .map_err(|e| template_err(path, format!("boundary/{name}: {e}")))?;
        let faces = match d.stream("faces") {
            Ok([Item::List(f)]) => f,
            _ => {
                return Err(template_err(
                    path,
                    format!("boundary/{name}/faces must be a list"),
                ))
            }
        };
        let mut sides = Vec::new();
        for f in faces {
            let labels: Option<Vec<i64>> = match f {
                Item::List(v) => v.iter().map(Item::as_label).collect(),
                Item::Labels(v) => Some(v.clone()),
                _ => None,
            };
            let side = labels.as_deref().and_then(Side::of_vertices).ok_or_else(|| {
                template_err(
                    path,
                    format!("boundary/{name}: face {f:?} is not a side of the box (vertex labels 0-7)"),
                )
            })?;
            if seen.contains(&side) {
                return Err(template_err(
                    path,
                    format!("boundary/{name}: side {side:?} is in two patches"),
                ));
            }
            seen.push(side);
            sides.push(side);
        }
        out.push(TemplatePatch {
            name: name.clone(),
            patch_type: ptype.to_owned(),
            sides,
        });
    }
    if seen.len() != 6 {
        return Err(template_err(
            path,
            format!(
                "`boundary` covers {} of the 6 sides (blockMesh's defaultFaces are not supported)",
                seen.len()
            ),
        ));
    }
    Ok(out)
}

/// `grid` (six side patches in [`Side`] order) with its boundary faces regrouped into
/// `patches`.
fn regroup(grid: &PolyMesh, patches: &[TemplatePatch]) -> PolyMesh {
    let n_int = grid.neighbour.len();
    let mut faces = FaceList::with_capacity(grid.faces.len(), grid.faces.labels().len());
    let mut owner = Vec::with_capacity(grid.owner.len());
    for f in 0..n_int {
        faces.push(grid.faces.face(f));
        owner.push(grid.owner[f]);
    }
    let mut boundary = Vec::with_capacity(patches.len());
    for p in patches {
        let start = owner.len();
        for side in &p.sides {
            let idx = Side::ALL.iter().position(|s| s == side).unwrap_or(0);
            let src = &grid.boundary[idx];
            for f in src.start_face..src.start_face + src.n_faces {
                faces.push(grid.faces.face(f));
                owner.push(grid.owner[f]);
            }
        }
        boundary.push(Patch {
            name: p.name.clone(),
            patch_type: p.patch_type.clone(),
            n_faces: owner.len() - start,
            start_face: start,
            extra: vec![],
        });
    }
    PolyMesh {
        points: grid.points.clone(),
        faces,
        owner,
        neighbour: grid.neighbour.clone(),
        boundary,
        n_cells: grid.n_cells,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case_template() -> Template {
        let p = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../openfoam-cases/binary-bed/CFD/system/blockMeshDict.template");
        Template::read(&p).unwrap()
    }

    #[test]
    fn the_case_template_reads() {
        let t = case_template();
        let w = 12.0 / 2600.0;
        assert!((t.hi[0] - w).abs() < 1e-15 && t.lo[0] == 0.0);
        assert!((t.hi[2] - 36.0 / 2600.0).abs() < 1e-15);
        let names: Vec<_> = t.patches.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["wall", "inlet", "outlet"]);
        assert_eq!(
            t.patches[0].sides,
            [Side::XMin, Side::XMax, Side::YMin, Side::YMax]
        );
        assert_eq!(t.patches[1].sides, [Side::ZMin]);
        assert!(t.fill([3, 4, 5]).contains("(3 4 5) simpleGrading"));
    }

    #[test]
    fn the_native_mesh_has_the_template_patches_and_volume() {
        let t = case_template();
        let m = t.mesh([2, 3, 4]);
        m.check().unwrap();
        assert_eq!(m.n_cells, 24);
        let count = |name: &str| m.boundary.iter().find(|p| p.name == name).unwrap().n_faces;
        assert_eq!(count("wall"), 2 * (3 * 4) + 2 * (2 * 4));
        assert_eq!((count("inlet"), count("outlet")), (6, 6));
        let g = mesh::MeshGeometry::new(&m).unwrap();
        let [a, b, c] = t.lengths();
        let v: f64 = g.cell_volumes.iter().sum();
        assert!((v - a * b * c).abs() < 1e-12 * a * b * c);
        // Every inlet face centre lies on z = zMin, every outlet one on zMax.
        let inlet = &m.boundary[1];
        for f in inlet.start_face..inlet.start_face + inlet.n_faces {
            assert!(g.face_centres[f][2].abs() < 1e-18);
        }
    }

    #[test]
    fn bad_templates_are_named() {
        let p = Path::new("t/blockMeshDict.template");
        let e = Template::parse("xMin 0;", p).unwrap_err().to_string();
        assert!(
            e.contains("@NX@") && e.contains("blockMeshDict.template"),
            "{e}"
        );
        let t = case_template();
        let broken = t.text.replace("(0 3 2 1)", "(0 3 2 7)");
        let e = Template::parse(&broken, p).unwrap_err().to_string();
        assert!(
            e.contains("boundary/inlet") && e.contains("not a side"),
            "{e}"
        );
        let broken = t.text.replace("xMax    0.004615384615384616;", "xMax 0;");
        let e = Template::parse(&broken, p).unwrap_err().to_string();
        assert!(e.contains("empty along axis 0"), "{e}");
    }
}
