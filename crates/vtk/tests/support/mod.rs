//! Test support: meshes built from cells, a small VTK XML reader, and the Python VTK runner.

#![allow(dead_code)]

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use foam::{FaceList, Label, Patch, PolyMesh};

// ---------------------------------------------------------------------------------------------
// Meshes

/// Builds a polyMesh from cells given as lists of outward faces (global point ids). Faces that
/// two cells share become internal faces owned by the lower cell (asserting that the other cell
/// lists the same face reversed); internal faces are in upper-triangular order, then all other
/// faces form one patch `walls`.
pub fn mesh_from_cells(points: Vec<[f64; 3]>, cells: &[Vec<Vec<Label>>]) -> PolyMesh {
    let key = |f: &[Label]| {
        let mut k = f.to_vec();
        k.sort_unstable();
        k
    };
    let mut open: HashMap<Vec<Label>, (usize, usize)> = HashMap::new();
    let mut internal = Vec::new();
    for (c, faces) in cells.iter().enumerate() {
        for (i, f) in faces.iter().enumerate() {
            if let Some((c0, i0)) = open.remove(&key(f)) {
                let f0 = &cells[c0][i0];
                let mut rev = f.clone();
                rev.reverse();
                let n = f0.len();
                assert!(
                    (0..n).any(|r| (0..n).all(|k| f0[(k + r) % n] == rev[k])),
                    "cells {c0} and {c} share face {f0:?} with the same orientation"
                );
                internal.push((c0 as Label, c as Label, f0.clone()));
            } else {
                open.insert(key(f), (c, i));
            }
        }
    }
    internal.sort_by_key(|&(o, n, _)| (o, n));
    let mut boundary: Vec<(usize, usize)> = open.into_values().collect();
    boundary.sort_unstable();
    let mut faces = FaceList::new();
    let (mut owner, mut neighbour) = (Vec::new(), Vec::new());
    for (o, n, f) in &internal {
        faces.push(f);
        owner.push(*o);
        neighbour.push(*n);
    }
    for &(c, i) in &boundary {
        faces.push(&cells[c][i]);
        owner.push(c as Label);
    }
    let mesh = PolyMesh {
        points,
        faces,
        owner,
        neighbour,
        boundary: vec![Patch {
            name: "walls".into(),
            patch_type: "wall".into(),
            n_faces: boundary.len(),
            start_face: internal.len(),
            extra: vec![],
        }],
        n_cells: cells.len(),
    };
    mesh.check().unwrap();
    mesh
}

/// Outward faces of the hexahedron with corners `c` in OpenFOAM/VTK hex order.
pub fn hex_faces(c: [Label; 8]) -> Vec<Vec<Label>> {
    [
        [0, 4, 7, 3],
        [1, 2, 6, 5],
        [0, 1, 5, 4],
        [3, 7, 6, 2],
        [0, 3, 2, 1],
        [4, 5, 6, 7],
    ]
    .iter()
    .map(|f| f.iter().map(|&i| c[i]).collect())
    .collect()
}

/// A graded Cartesian block of hexahedra on the given coordinate lines, cells numbered x
/// fastest. Returns the mesh and each cell's exact volume.
pub fn cartesian(xs: &[f64], ys: &[f64], zs: &[f64]) -> (PolyMesh, Vec<f64>) {
    let (nx, ny) = (xs.len(), ys.len());
    let id = |i: usize, j: usize, k: usize| (i + nx * (j + ny * k)) as Label;
    let mut points = Vec::new();
    for &z in zs {
        for &y in ys {
            for &x in xs {
                points.push([x, y, z]);
            }
        }
    }
    let (mut cells, mut volumes) = (Vec::new(), Vec::new());
    for k in 0..zs.len() - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                cells.push(hex_faces([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]));
                volumes.push((xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) * (zs[k + 1] - zs[k]));
            }
        }
    }
    (mesh_from_cells(points, &cells), volumes)
}

/// Seven conforming cells of every kind the writer distinguishes:
/// 0 hex [0,1]³; 1 hex [2,3]×[0,.5]×[0,1]; 2 prism (lower triangle of [2,3]×[.5,1]);
/// 3 polyhedron [1,2]×[0,1]² whose +x face is split in two at y = .5 (7 quads, neighbour of
/// cells 0 and 1, owner of the face it shares with cell 4); 4 prism (upper triangle);
/// 5 pyramid on top of cell 0; 6 tetrahedron on the pyramid's y = 0 side.
/// Returns the mesh, the expected VTK cell types (prisms are polyhedra) and the exact cell
/// volumes.
pub fn mixed() -> (PolyMesh, Vec<u8>, Vec<f64>) {
    let mut pts: Vec<[f64; 3]> = Vec::new();
    let mut p = |x: f64, y: f64, z: f64| -> Label {
        if let Some(i) = pts.iter().position(|q| *q == [x, y, z]) {
            return i as Label;
        }
        pts.push([x, y, z]);
        (pts.len() - 1) as Label
    };
    let box_hex = |p: &mut dyn FnMut(f64, f64, f64) -> Label, x: [f64; 2], y: [f64; 2]| {
        [
            p(x[0], y[0], 0.),
            p(x[1], y[0], 0.),
            p(x[1], y[1], 0.),
            p(x[0], y[1], 0.),
            p(x[0], y[0], 1.),
            p(x[1], y[0], 1.),
            p(x[1], y[1], 1.),
            p(x[0], y[1], 1.),
        ]
    };
    let a = box_hex(&mut p, [0., 1.], [0., 1.]);
    let e = box_hex(&mut p, [2., 3.], [0., 0.5]);
    let b = box_hex(&mut p, [1., 2.], [0., 1.]);
    let (m0, m1) = (p(2., 0.5, 0.), p(2., 0.5, 1.));
    // Prism from triangle (t0, t1, t2) at z = 0 (counter-clockwise seen from +z) extruded to 1.
    let prism = |p: &mut dyn FnMut(f64, f64, f64) -> Label, t: [[f64; 2]; 3]| {
        let lo: Vec<Label> = t.iter().map(|q| p(q[0], q[1], 0.)).collect();
        let hi: Vec<Label> = t.iter().map(|q| p(q[0], q[1], 1.)).collect();
        vec![
            vec![lo[0], lo[2], lo[1]],
            vec![hi[0], hi[1], hi[2]],
            vec![lo[0], lo[1], hi[1], hi[0]],
            vec![lo[1], lo[2], hi[2], hi[1]],
            vec![lo[2], lo[0], hi[0], hi[2]],
        ]
    };
    let w1 = prism(&mut p, [[2., 0.5], [3., 0.5], [3., 1.]]);
    let w2 = prism(&mut p, [[2., 0.5], [3., 1.], [2., 1.]]);
    let mut poly = hex_faces(b);
    // Split the +x face (b1 b2 b6 b5) in two through m0 (on edge b1-b2) and m1 (on b5-b6);
    // the bottom and top faces then carry m0 and m1 too, so every edge is shared by two faces.
    poly[1] = vec![b[1], m0, m1, b[5]];
    poly.push(vec![m0, b[2], b[6], m1]);
    poly[4] = vec![b[0], b[3], b[2], m0, b[1]];
    poly[5] = vec![b[4], b[5], m1, b[6], b[7]];
    let apex = p(0.5, 0.5, 1.5);
    let pyramid = vec![
        vec![a[4], a[7], a[6], a[5]],
        vec![a[4], a[5], apex],
        vec![a[5], a[6], apex],
        vec![a[6], a[7], apex],
        vec![a[7], a[4], apex],
    ];
    let t = p(0.5, -0.5, 1.25);
    let tet = vec![
        vec![a[4], apex, a[5]],
        vec![a[4], t, apex],
        vec![apex, t, a[5]],
        vec![a[5], t, a[4]],
    ];
    let cells = vec![hex_faces(a), hex_faces(e), w1, poly, w2, pyramid, tet];
    let types = vec![12, 12, 42, 42, 42, 14, 10];
    let volumes = vec![1.0, 0.5, 0.25, 1.0, 0.25, 1.0 / 6.0, 1.0 / 16.0];
    (mesh_from_cells(pts, &cells), types, volumes)
}

// ---------------------------------------------------------------------------------------------
// A small VTK XML reader

/// Values of one parsed array; integers of every width as i64.
#[derive(Clone, Debug, PartialEq)]
pub enum Vals {
    F64(Vec<f64>),
    I64(Vec<i64>),
}

impl Vals {
    pub fn f64(&self) -> &[f64] {
        match self {
            Vals::F64(v) => v,
            Vals::I64(_) => panic!("integer array where floats were expected"),
        }
    }
    pub fn i64(&self) -> &[i64] {
        match self {
            Vals::I64(v) => v,
            Vals::F64(_) => panic!("float array where integers were expected"),
        }
    }
}

#[derive(Clone, Debug)]
pub struct Array {
    pub name: String,
    pub vtk_type: String,
    pub components: usize,
    pub format: String,
    pub values: Vals,
}

/// A parsed `.vtu`/`.vtp`: the root attributes, the piece attributes and the arrays by section.
#[derive(Debug)]
pub struct VtkXml {
    pub root: HashMap<String, String>,
    pub piece: HashMap<String, String>,
    pub sections: HashMap<String, Vec<Array>>,
}

impl VtkXml {
    pub fn array(&self, section: &str, name: &str) -> &Array {
        self.sections
            .get(section)
            .and_then(|s| s.iter().find(|a| a.name == name))
            .unwrap_or_else(|| panic!("no array {name} in {section}"))
    }
    pub fn count(&self, key: &str) -> usize {
        self.piece[key].parse().unwrap()
    }
}

pub fn attributes(tag: &str) -> HashMap<String, String> {
    let mut out = HashMap::new();
    let mut rest = tag;
    while let Some(eq) = rest.find("=\"") {
        let key = rest[..eq]
            .rsplit(|c: char| c.is_whitespace())
            .next()
            .unwrap();
        let after = &rest[eq + 2..];
        let end = after.find('"').expect("unterminated attribute");
        out.insert(key.to_string(), unescape(&after[..end]));
        rest = &after[end + 1..];
    }
    out
}

fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

fn element<'a>(xml: &'a str, name: &str) -> Option<(&'a str, &'a str)> {
    let open = format!("<{name}");
    let start = xml.find(&open)?;
    let tag_end = start + xml[start..].find('>')?;
    let tag = &xml[start + open.len()..tag_end];
    let close = format!("</{name}>");
    let body_end = tag_end + xml[tag_end..].find(&close)?;
    Some((tag, &xml[tag_end + 1..body_end]))
}

fn parse_array(tag: &str, body: &str) -> Array {
    let a = attributes(tag);
    let vtk_type = a["type"].clone();
    let format = a["format"].clone();
    let components = a
        .get("NumberOfComponents")
        .map_or(1, |c| c.parse().unwrap());
    let size = match vtk_type.as_str() {
        "Float64" | "Int64" | "UInt64" => 8,
        "Int32" => 4,
        "UInt8" => 1,
        t => panic!("unexpected type {t}"),
    };
    let values = if format == "binary" {
        let raw = STANDARD.decode(body.trim()).expect("invalid base64");
        let header = u64::from_le_bytes(raw[..8].try_into().unwrap()) as usize;
        assert_eq!(header, raw.len() - 8, "header byte count of {}", a["Name"]);
        assert_eq!(header % size, 0);
        let data = &raw[8..];
        match vtk_type.as_str() {
            "Float64" => Vals::F64(
                data.chunks(8)
                    .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                    .collect(),
            ),
            "Int64" => Vals::I64(
                data.chunks(8)
                    .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
                    .collect(),
            ),
            "Int32" => Vals::I64(
                data.chunks(4)
                    .map(|c| i32::from_le_bytes(c.try_into().unwrap()) as i64)
                    .collect(),
            ),
            "UInt8" => Vals::I64(data.iter().map(|&b| b as i64).collect()),
            t => panic!("unexpected type {t}"),
        }
    } else {
        assert_eq!(format, "ascii");
        let toks = body.split_whitespace();
        if vtk_type == "Float64" {
            Vals::F64(toks.map(|t| t.parse().unwrap()).collect())
        } else {
            Vals::I64(toks.map(|t| t.parse().unwrap()).collect())
        }
    };
    Array {
        name: a["Name"].clone(),
        vtk_type,
        components,
        format,
        values,
    }
}

/// Parses the file written by the crate (not a general XML parser: it knows the layout).
pub fn read_vtk_xml(path: &Path) -> VtkXml {
    let xml = std::fs::read_to_string(path).unwrap();
    assert!(xml.starts_with("<?xml version=\"1.0\"?>"));
    let (root_tag, root_body) = element(&xml, "VTKFile").expect("no VTKFile element");
    let root = attributes(root_tag);
    let (piece_tag, piece_body) = element(root_body, "Piece").expect("no Piece");
    let piece = attributes(piece_tag);
    let mut sections = HashMap::new();
    for s in ["PointData", "CellData", "Points", "Cells", "Verts"] {
        if let Some((_, mut body)) = element(piece_body, s) {
            let mut arrays = Vec::new();
            while let Some((tag, inner)) = element(body, "DataArray") {
                arrays.push(parse_array(tag, inner));
                let end = body.find("</DataArray>").unwrap() + "</DataArray>".len();
                body = &body[end..];
            }
            sections.insert(s.to_string(), arrays);
        }
    }
    VtkXml {
        root,
        piece,
        sections,
    }
}

/// Outward faces of VTK's linear cells in local point numbers (from vtkTetra, vtkHexahedron,
/// vtkPyramid).
fn reference_faces(vtk_type: i64) -> &'static [&'static [usize]] {
    match vtk_type {
        10 => &[&[0, 1, 3], &[1, 2, 3], &[2, 0, 3], &[0, 2, 1]],
        12 => &[
            &[0, 4, 7, 3],
            &[1, 2, 6, 5],
            &[0, 1, 5, 4],
            &[3, 7, 6, 2],
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
        ],
        14 => &[
            &[0, 3, 2, 1],
            &[0, 1, 4],
            &[1, 2, 4],
            &[2, 3, 4],
            &[3, 0, 4],
        ],
        t => panic!("no reference faces for type {t}"),
    }
}

/// The face's share of the enclosed volume (divergence theorem over a triangle fan).
pub fn polygon_volume(points: &[[f64; 3]], face: &[usize]) -> f64 {
    let p0 = points[face[0]];
    face[1..]
        .windows(2)
        .map(|w| {
            let (p1, p2) = (points[w[0]], points[w[1]]);
            (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0])
                + p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]))
                / 6.0
        })
        .sum()
}

/// The volume a VTK linear cell (tetrahedron, hexahedron, pyramid) with global point ids `cell`
/// encloses, from VTK's own definition of its faces (positive when the point order is VTK's).
pub fn linear_cell_volume(points: &[[f64; 3]], cell: &[usize], vtk_type: i64) -> f64 {
    reference_faces(vtk_type)
        .iter()
        .map(|f| {
            let face: Vec<usize> = f.iter().map(|&l| cell[l]).collect();
            polygon_volume(points, &face)
        })
        .sum()
}

/// Checks the `<Cells>` arrays of a parsed `.vtu` for consistency and returns each cell's
/// signed volume from its faces as VTK defines them (reference faces, or the face stream).
pub fn vtu_cell_volumes(v: &VtkXml) -> Vec<f64> {
    let (np, nc) = (v.count("NumberOfPoints"), v.count("NumberOfCells"));
    let pts = v.array("Points", "Points");
    assert_eq!((pts.components, pts.vtk_type.as_str()), (3, "Float64"));
    let points: Vec<[f64; 3]> = pts
        .values
        .f64()
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    assert_eq!(points.len(), np);
    let conn = v.array("Cells", "connectivity");
    assert_eq!(conn.vtk_type, "Int64");
    let conn = conn.values.i64();
    let offsets = v.array("Cells", "offsets").values.i64();
    let types = v.array("Cells", "types");
    assert_eq!(types.vtk_type, "UInt8");
    let types = types.values.i64();
    assert_eq!((offsets.len(), types.len()), (nc, nc));
    assert!(conn.iter().all(|&p| p >= 0 && (p as usize) < np));
    let has_faces = v.sections["Cells"].iter().any(|a| a.name == "faces");
    let (faces, face_offsets) = if has_faces {
        (
            v.array("Cells", "faces").values.i64(),
            v.array("Cells", "faceoffsets").values.i64(),
        )
    } else {
        assert!(!types.contains(&42), "polyhedra without a face stream");
        (&[][..], &[][..])
    };
    let mut start = 0usize;
    let mut face_start = 0usize;
    let mut volumes = Vec::with_capacity(nc);
    for c in 0..nc {
        let end = offsets[c] as usize;
        assert!(end > start && end <= conn.len(), "offsets must increase");
        let cell: Vec<usize> = conn[start..end].iter().map(|&p| p as usize).collect();
        let vol = if types[c] == 42 {
            let fend = face_offsets[c];
            assert!(fend > 0, "polyhedron {c} without faces");
            let stream = &faces[face_start..fend as usize];
            let mut k = 1;
            let mut vol = 0.0;
            let mut used = Vec::new();
            for _ in 0..stream[0] {
                let n = stream[k] as usize;
                let face: Vec<usize> = stream[k + 1..k + 1 + n]
                    .iter()
                    .map(|&p| p as usize)
                    .collect();
                used.extend(face.iter().copied());
                vol += polygon_volume(&points, &face);
                k += 1 + n;
            }
            assert_eq!(k, stream.len(), "face stream of cell {c} has trailing data");
            used.sort_unstable();
            used.dedup();
            let mut sorted = cell.clone();
            sorted.sort_unstable();
            assert_eq!(
                used, sorted,
                "polyhedron {c}: connectivity != face stream points"
            );
            face_start = fend as usize;
            vol
        } else {
            if has_faces {
                assert_eq!(face_offsets[c], -1);
            }
            linear_cell_volume(&points, &cell, types[c])
        };
        volumes.push(vol);
        start = end;
    }
    assert_eq!(start, conn.len());
    volumes
}

// ---------------------------------------------------------------------------------------------
// Python VTK

/// Interpreters that can `import vtk`: `$VTK_PYTHON` if set, else `python3` and
/// `/usr/bin/python3` (Debian's `python3-vtk9`), deduplicated by executable and VTK version.
/// None found means the independent check is skipped, unless the full tier is requested
/// (`FOAMGRAIN_FULL=1`, see the testkit crate): then a missing package fails the test.
/// Probed once per test binary.
pub fn vtk_pythons() -> Vec<String> {
    static FOUND: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    FOUND.get_or_init(probe_pythons).clone()
}

fn probe_pythons() -> Vec<String> {
    let candidates: Vec<String> = match std::env::var("VTK_PYTHON") {
        Ok(p) => vec![p],
        Err(_) => vec!["python3".into(), "/usr/bin/python3".into()],
    };
    let mut seen = Vec::new();
    let mut out = Vec::new();
    for c in candidates {
        let Ok(o) = Command::new(&c)
            .args([
                "-c",
                "import sys, vtk; print(sys.executable, vtk.vtkVersion.GetVTKVersion())",
            ])
            .output()
        else {
            continue;
        };
        if o.status.success() {
            let id = String::from_utf8_lossy(&o.stdout).trim().to_string();
            if !seen.contains(&id) {
                eprintln!("independent check with {c}: {id}");
                seen.push(id);
                out.push(c);
            }
        }
    }
    if out.is_empty() && testkit::full_tier() {
        panic!("FOAMGRAIN_FULL=1 but no python3 can `import vtk` (apt install python3-vtk9)");
    }
    if out.is_empty() {
        eprintln!(
            "SKIPPED the independent VTK check: no python3 with the `vtk` module \
             (apt install python3-vtk9, or pip install vtk); pure-Rust checks still run"
        );
    }
    out
}

/// Runs `tests/check_vtk.py` on `file` with `python`; asserts VTK reported no error.
pub fn check_with(python: &str, file: &Path) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/check_vtk.py");
    let o = Command::new(python).arg(script).arg(file).output().unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "check_vtk.py failed on {}:\n{stdout}\n{}",
        file.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_str(&stdout).unwrap()
}

/// Relative difference, safe at zero.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}
