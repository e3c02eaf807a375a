//! vtkio (the VTK crate the project was specified with) as an independent reader of every file
//! kind this crate writes: `.vtp` particles and `.vtu` meshes, binary and ASCII. vtkio 0.6 cannot
//! write or read `VTK_POLYHEDRON` (its `<Cells>` must hold exactly connectivity, offsets and
//! types), which is why foamgrain writes its own XML (docs/adr/0006-vtk-writer-and-vtkio-reader.md);
//! for a mesh with polyhedra vtkio reads everything but the face stream, which the hand-written
//! parser (`support`) and VTK itself (`vtk_files.rs`, full tier) check.

mod support;

use std::collections::HashMap;
use std::path::Path;

use support::*;
use vtk::{write_vtp_with, write_vtu_cells, write_vtu_with, DataArray, Encoding, VtkCells};
use vtkio::model::{Attribute, Attributes, DataSet, Piece, VertexNumbers};

/// What vtkio read from one piece.
struct Read {
    points: Vec<f64>,
    connectivity: Vec<u64>,
    offsets: Vec<u64>,
    types: Vec<u8>,
    point_data: HashMap<String, (usize, Vec<f64>)>,
    cell_data: HashMap<String, (usize, Vec<f64>)>,
}

fn arrays(a: &[Attribute]) -> HashMap<String, (usize, Vec<f64>)> {
    a.iter()
        .map(|x| match x {
            Attribute::DataArray(d) => (
                d.name.clone(),
                (
                    d.elem.num_comp() as usize,
                    d.data.clone().cast_into::<f64>().expect("numeric array"),
                ),
            ),
            Attribute::Field { name, .. } => panic!("unexpected field data {name}"),
        })
        .collect()
}

fn data(d: &Attributes) -> [HashMap<String, (usize, Vec<f64>)>; 2] {
    [arrays(&d.point), arrays(&d.cell)]
}

fn xml_cells(v: VertexNumbers) -> (Vec<u64>, Vec<u64>) {
    match v {
        VertexNumbers::XML {
            connectivity,
            offsets,
        } => (connectivity, offsets),
        VertexNumbers::Legacy { .. } => panic!("an XML file gives XML cells"),
    }
}

fn vtkio_read(path: &Path) -> Read {
    let vtk = vtkio::Vtk::import(path)
        .unwrap_or_else(|e| panic!("vtkio cannot read {}: {e:?}", path.display()));
    match vtk.data {
        DataSet::UnstructuredGrid { pieces, .. } => {
            let [Piece::Inline(p)] = <[_; 1]>::try_from(pieces).expect("one piece") else {
                panic!("an inline piece")
            };
            let (connectivity, offsets) = xml_cells(p.cells.cell_verts);
            let [point_data, cell_data] = data(&p.data);
            Read {
                points: p.points.cast_into::<f64>().unwrap(),
                connectivity,
                offsets,
                types: p.cells.types.iter().map(|&t| t as u8).collect(),
                point_data,
                cell_data,
            }
        }
        DataSet::PolyData { pieces, .. } => {
            let [Piece::Inline(p)] = <[_; 1]>::try_from(pieces).expect("one piece") else {
                panic!("an inline piece")
            };
            assert!(p.lines.is_none() && p.polys.is_none() && p.strips.is_none());
            let (connectivity, offsets) = xml_cells(p.verts.expect("vertices"));
            let [point_data, cell_data] = data(&p.data);
            Read {
                points: p.points.cast_into::<f64>().unwrap(),
                types: vec![1; offsets.len()],
                connectivity,
                offsets,
                point_data,
                cell_data,
            }
        }
        other => panic!("unexpected data set {other:?}"),
    }
}

fn flat(v: &[[f64; 3]]) -> Vec<f64> {
    v.iter().flatten().copied().collect()
}

#[test]
fn particles_read_back_with_vtkio() {
    let x = [[0.0, 0.0, 0.0], [1e-3, -2e-3, 3.5e-3], [0.1, 0.2, 0.3]];
    let v = [[0.0, 0.0, -0.1], [1.0 / 3.0, 0.0, 2e-17], [-5.0, 6.0, 7.0]];
    let r = [5e-4, 4e-4, 1.0 / 7.0];
    let id = [1_i64, 7, 1_000_000_000_000];
    let dir = tempfile::tempdir().unwrap();
    for enc in [Encoding::Binary, Encoding::Ascii] {
        let path = dir.path().join(format!("p_{enc:?}.vtp"));
        let arrays = [
            DataArray::scalar("radius", &r),
            DataArray::vector("v", &v),
            DataArray::int64("id", &id),
        ];
        write_vtp_with(&path, &x, &arrays, enc).unwrap();
        let got = vtkio_read(&path);
        assert_eq!(got.points, flat(&x), "{enc:?}");
        assert_eq!(got.connectivity, [0, 1, 2]);
        assert_eq!(got.offsets, [1, 2, 3]);
        assert_eq!(got.point_data["radius"], (1, r.to_vec()));
        assert_eq!(got.point_data["v"], (3, flat(&v)));
        let ids: Vec<f64> = id.iter().map(|&i| i as f64).collect();
        assert_eq!(got.point_data["id"], (1, ids));
        assert!(got.cell_data.is_empty());
    }
    // no particles at all
    let path = dir.path().join("empty.vtp");
    write_vtp_with(
        &path,
        &[],
        &[DataArray::scalar("radius", &[])],
        Encoding::Binary,
    )
    .unwrap();
    let got = vtkio_read(&path);
    assert!(got.points.is_empty() && got.offsets.is_empty());
}

/// Each cell's volume from vtkio's connectivity with VTK's own face definition of the cell type
/// (`None` for a polyhedron, whose faces vtkio does not read).
fn linear_cell_volumes(read: &Read) -> Vec<Option<f64>> {
    let points: Vec<[f64; 3]> = read.points.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut start = 0;
    read.offsets
        .iter()
        .zip(&read.types)
        .map(|(&end, &t)| {
            let cell: Vec<usize> = read.connectivity[start..end as usize]
                .iter()
                .map(|&p| p as usize)
                .collect();
            start = end as usize;
            (t != 42).then(|| linear_cell_volume(&points, &cell, t as i64))
        })
        .collect()
}

/// Asserts each volume vtkio's cells enclose (polyhedra excepted) is the expected one.
fn assert_volumes(read: &Read, volumes: &[f64]) {
    let got = linear_cell_volumes(read);
    assert_eq!(got.len(), volumes.len());
    for (c, (v, want)) in got.iter().zip(volumes).enumerate() {
        if let Some(v) = v {
            assert!(
                approx::relative_eq!(*v, *want, max_relative = 1e-12),
                "cell {c}: {v} vs {want}"
            );
        }
    }
}

#[test]
fn hexahedral_meshes_read_back_with_vtkio() {
    let (mesh, volumes) = cartesian(
        &[0.0, 0.1, 0.3, 0.6, 1.0],
        &[0.0, 0.5, 1.5],
        &[-1.0, -0.5, 0.0],
    );
    let pz: Vec<f64> = mesh.points.iter().map(|p| p[2]).collect();
    let u: Vec<[f64; 3]> = volumes.iter().map(|&v| [v, -v, 2.0 * v]).collect();
    let dir = tempfile::tempdir().unwrap();
    for enc in [Encoding::Binary, Encoding::Ascii] {
        let path = dir.path().join(format!("hex_{enc:?}.vtu"));
        write_vtu_with(
            &path,
            &mesh,
            &[
                DataArray::scalar("vol", &volumes),
                DataArray::vector("U", &u),
            ],
            &[DataArray::scalar("pz", &pz)],
            enc,
        )
        .unwrap();
        let got = vtkio_read(&path);
        assert_eq!(got.points, flat(&mesh.points), "{enc:?}");
        assert!(got.types.iter().all(|&t| t == 12), "hexahedra");
        // VTK's hexahedron order read back by vtkio encloses each cell's volume, outward.
        assert_volumes(&got, &volumes);
        assert_eq!(got.cell_data["vol"], (1, volumes.clone()));
        assert_eq!(got.cell_data["U"], (3, flat(&u)));
        assert_eq!(got.point_data["pz"], (1, pz.clone()));
    }
}

/// A mesh with tetrahedra, pyramids and polyhedra: vtkio refuses the face stream, and reads all
/// the rest once the two face arrays are taken out.
#[test]
fn polyhedral_meshes_read_back_with_vtkio_but_for_the_face_stream() {
    let (mesh, types, volumes) = mixed();
    let dir = tempfile::tempdir().unwrap();
    for enc in [Encoding::Binary, Encoding::Ascii] {
        let path = dir.path().join(format!("mixed_{enc:?}.vtu"));
        write_vtu_with(
            &path,
            &mesh,
            &[DataArray::scalar("vol", &volumes)],
            &[],
            enc,
        )
        .unwrap();
        let refused = format!("{:?}", vtkio::Vtk::import(&path).unwrap_err());
        assert!(refused.contains("connectivity"), "{refused}");
        let text = std::fs::read_to_string(&path).unwrap();
        let stripped = without_arrays(&text, &["faces", "faceoffsets"]);
        let cut = dir.path().join(format!("mixed_{enc:?}_cells.vtu"));
        std::fs::write(&cut, stripped).unwrap();
        let got = vtkio_read(&cut);
        let ours = read_vtk_xml(&path);
        assert_eq!(got.points, flat(&mesh.points));
        assert_eq!(got.types, types);
        let conn: Vec<u64> = ours
            .array("Cells", "connectivity")
            .values
            .i64()
            .iter()
            .map(|&c| c as u64)
            .collect();
        assert_eq!(got.connectivity, conn);
        assert_eq!(got.cell_data["vol"], (1, volumes.clone()));
        // the cells that are not polyhedra enclose their volumes in VTK's point order
        assert_volumes(&got, &volumes);
    }
}

/// `write_vtu_cells` (cells already translated) gives the same file as `write_vtu`.
#[test]
fn precomputed_cells_read_back_with_vtkio() {
    let (mesh, volumes) = cartesian(&[0.0, 1.0, 2.0], &[0.0, 1.0], &[0.0, 3.0]);
    let cells = VtkCells::from_poly_mesh(&mesh).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cells.vtu");
    write_vtu_cells(
        &path,
        &mesh.points,
        &cells,
        &[DataArray::scalar("vol", &volumes)],
        &[],
        Encoding::Binary,
    )
    .unwrap();
    let got = vtkio_read(&path);
    assert_volumes(&got, &[3.0, 3.0]);
}

/// The XML text without the `<DataArray … Name="NAME" …>…</DataArray>` elements named.
fn without_arrays(text: &str, names: &[&str]) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(start) = rest.find("<DataArray") {
        let end_tag = rest[start..].find('>').unwrap() + start;
        let tag = &rest[start..=end_tag];
        let close = rest[start..].find("</DataArray>").unwrap() + start + "</DataArray>".len();
        out.push_str(&rest[..start]);
        if !names.iter().any(|n| tag.contains(&format!("Name=\"{n}\""))) {
            out.push_str(&rest[start..close]);
        }
        rest = &rest[close..];
    }
    out.push_str(rest);
    out
}

/// The legacy `.vtk` particles (LIGGGHTS's `dump custom/vtk` form) read back exactly by vtkio's
/// legacy parser: points, one vertex per point, scalar, vector and integer point data.
#[test]
fn legacy_particles_read_back_with_vtkio() {
    let x = [[0.0, 0.0, 0.0], [1e-3, -2e-3, 3.5e-3], [0.1, 0.2, 0.3]];
    let v = [[0.0, 0.0, -0.1], [1.0 / 3.0, 0.0, 2e-17], [-5.0, 6.0, 7.0]];
    let r = [5e-4, 4e-4, 1.0 / 7.0];
    let ty = [1_i32, 2, 1];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p_100.vtk");
    let arrays = [
        DataArray::scalar("radius", &r),
        DataArray::vector("v", &v),
        DataArray::int32("type", &ty),
    ];
    vtk::write_legacy_vtk(&path, "foamgrain dump", &x, &arrays).unwrap();
    let vtk = vtkio::Vtk::import(&path).unwrap_or_else(|e| panic!("vtkio: {e:?}"));
    assert_eq!(vtk.title, "foamgrain dump");
    let DataSet::PolyData { pieces, .. } = vtk.data else {
        panic!("PolyData expected")
    };
    let [Piece::Inline(p)] = <[_; 1]>::try_from(pieces).expect("one piece") else {
        panic!("an inline piece")
    };
    assert_eq!(p.points.cast_into::<f64>().unwrap(), flat(&x));
    match p.verts.expect("vertices") {
        VertexNumbers::Legacy {
            num_cells,
            vertices,
        } => {
            assert_eq!(num_cells, 3);
            assert_eq!(vertices, [1, 0, 1, 1, 1, 2]);
        }
        VertexNumbers::XML { .. } => panic!("legacy cells expected"),
    }
    // the arrays come as one field of point data
    let [Attribute::Field { data_array, .. }] = p.data.point.as_slice() else {
        panic!("one field of point data expected: {:?}", p.data.point)
    };
    let point: HashMap<String, (usize, Vec<f64>)> = data_array
        .iter()
        .map(|a| {
            let v = a.data.clone().cast_into::<f64>().expect("numeric");
            (a.name.clone(), (a.elem as usize, v))
        })
        .collect();
    assert_eq!(point["radius"], (1, r.to_vec()));
    assert_eq!(point["v"], (3, flat(&v)));
    assert_eq!(point["type"], (1, vec![1.0, 2.0, 1.0]));
    // bad input names the file
    let nan = [f64::NAN, 0.0, 0.0];
    let e = vtk::write_legacy_vtk(&path, "t", &x, &[DataArray::scalar("r", &nan)]).unwrap_err();
    assert!(e.to_string().contains("p_100.vtk"), "{e}");
}
