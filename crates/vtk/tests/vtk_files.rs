//! Writes meshes and particles, reads them back with a small Rust parser (always) and with
//! VTK's own readers through `tests/check_vtk.py` (when a python3 with `vtk` is installed).

mod support;

use std::path::Path;

use serde_json::Value;
use support::*;
use vtk::{
    write_pvd, write_vtp, write_vtp_with, write_vtu, write_vtu_with, DataArray, Encoding, VtkError,
};

/// Cell data that identifies each cell: id, expected volume and centroid-ish vector.
struct Fields {
    id: Vec<i64>,
    vol: Vec<f64>,
    u: Vec<[f64; 3]>,
}

impl Fields {
    fn arrays(&self) -> [DataArray<'_>; 3] {
        [
            DataArray::int64("id", &self.id),
            DataArray::scalar("vol", &self.vol),
            DataArray::vector("U", &self.u),
        ]
    }
}

fn fields(volumes: &[f64]) -> Fields {
    Fields {
        id: (0..volumes.len() as i64).map(|i| 1000 + i).collect(),
        vol: volumes.to_vec(),
        u: (0..volumes.len())
            .map(|i| [i as f64, -0.5 * i as f64, 1e-3 / (1.0 + i as f64)])
            .collect(),
    }
}

fn json_f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .flat_map(|x| match x {
            Value::Array(a) => a.iter().map(|y| y.as_f64().unwrap()).collect(),
            y => vec![y.as_f64().unwrap()],
        })
        .collect()
}

fn assert_close(found: &[f64], expected: &[f64], tol: f64, what: &str) {
    assert_eq!(found.len(), expected.len(), "{what}: length");
    for (i, (&f, &e)) in found.iter().zip(expected).enumerate() {
        assert!(
            approx::relative_eq!(f, e, epsilon = tol, max_relative = tol),
            "{what}[{i}]: {f} vs {e}"
        );
    }
}

/// Checks a written `.vtu` with the Rust parser: counts, types, arrays and per-cell volumes.
fn rust_check_vtu(path: &Path, types: &[u8], volumes: &[f64], f: &Fields, n_points: usize) {
    let v = read_vtk_xml(path);
    assert_eq!(v.root["type"], "UnstructuredGrid");
    assert_eq!(v.root["header_type"], "UInt64");
    assert_eq!(v.root["byte_order"], "LittleEndian");
    assert_eq!(v.count("NumberOfCells"), types.len());
    assert_eq!(v.count("NumberOfPoints"), n_points);
    let t: Vec<u8> = v
        .array("Cells", "types")
        .values
        .i64()
        .iter()
        .map(|&t| t as u8)
        .collect();
    assert_eq!(t, types);
    assert_close(&vtu_cell_volumes(&v), volumes, 1e-12, "rust face volumes");
    assert_eq!(v.array("CellData", "id").values.i64(), f.id);
    assert_eq!(v.array("CellData", "vol").values.f64(), f.vol);
    let u = v.array("CellData", "U");
    assert_eq!(u.components, 3);
    assert_eq!(u.values.f64(), f.u.as_flattened());
}

/// Checks a `.vtu` with VTK itself: counts, types, volumes (vtkCellSizeFilter and the faces
/// VTK reports) and the cell data values, for every python with `vtk`.
fn python_check_vtu(path: &Path, types: &[u8], volumes: &[f64], f: &Fields, box_volume: f64) {
    for py in vtk_pythons() {
        let j = check_with(&py, path);
        let version = j["vtk_version"].as_str().unwrap().to_string();
        assert_eq!(j["n_cells"].as_u64().unwrap() as usize, types.len());
        let t: Vec<u8> = j["cell_type_list"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap() as u8)
            .collect();
        assert_eq!(t, types, "VTK {version}: cell types");
        let what = format!("VTK {version}: volumes from the faces of each cell");
        assert_close(&json_f64s(&j["face_volumes"]), volumes, 1e-9, &what);
        let what = format!("VTK {version}: vtkCellSizeFilter volumes");
        assert_close(&json_f64s(&j["volumes"]), volumes, 1e-9, &what);
        let total = j["total_volume"].as_f64().unwrap();
        assert!(
            approx::relative_eq!(total, box_volume, epsilon = 0.0, max_relative = 1e-9),
            "VTK {version}: total volume {total} vs {box_volume}"
        );
        let cd = &j["cell_data"];
        assert_eq!(
            json_f64s(&cd["id"]["values"]),
            f.id.iter().map(|&i| i as f64).collect::<Vec<_>>()
        );
        assert_eq!(cd["id"]["type"], "long long", "VTK {version}: id type");
        assert_close(&json_f64s(&cd["vol"]["values"]), &f.vol, 1e-15, "vol");
        assert_eq!(cd["U"]["components"], 3);
        assert_close(
            &json_f64s(&cd["U"]["values"]),
            f.u.as_flattened(),
            1e-15,
            "U",
        );
        eprintln!(
            "VTK {version}: {} cells {:?}, total volume {total:.15} (exact {box_volume})",
            types.len(),
            j["cell_types"]
        );
    }
}

#[test]
fn graded_cartesian_hex_mesh() {
    let xs = [0.0, 0.1, 0.3, 0.6, 1.0];
    let ys = [0.0, 0.5, 1.5];
    let zs = [-1.0, -0.75, -0.5, 0.0];
    let (mesh, volumes) = cartesian(&xs, &ys, &zs);
    let f = fields(&volumes);
    let types = vec![12u8; mesh.n_cells];
    let pz: Vec<f64> = mesh.points.iter().map(|p| p[2]).collect();
    let dir = tempfile::tempdir().unwrap();
    for (enc, name) in [
        (Encoding::Binary, "hex.vtu"),
        (Encoding::Ascii, "hex_ascii.vtu"),
    ] {
        let path = dir.path().join(name);
        write_vtu_with(
            &path,
            &mesh,
            &f.arrays(),
            &[DataArray::scalar("pz", &pz)],
            enc,
        )
        .unwrap();
        rust_check_vtu(&path, &types, &volumes, &f, mesh.n_points());
        let v = read_vtk_xml(&path);
        assert_eq!(v.array("PointData", "pz").values.f64(), pz);
        let expected_format = if enc == Encoding::Binary {
            "binary"
        } else {
            "ascii"
        };
        assert!(v.sections["Cells"]
            .iter()
            .all(|a| a.format == expected_format));
        assert!(
            !v.sections["Cells"].iter().any(|a| a.name == "faces"),
            "no face stream without polyhedra"
        );
        python_check_vtu(&path, &types, &volumes, &f, 1.5);
        for py in vtk_pythons() {
            let j = check_with(&py, &path);
            // Point data stays attached to the right points.
            let pts = json_f64s(&j["points"]);
            let z: Vec<f64> = pts.chunks(3).map(|c| c[2]).collect();
            assert_eq!(json_f64s(&j["point_data"]["pz"]["values"]), z);
        }
    }
}

#[test]
fn mixed_mesh_with_polyhedron() {
    let (mesh, types, volumes) = mixed();
    let f = fields(&volumes);
    let total: f64 = volumes.iter().sum();
    let dir = tempfile::tempdir().unwrap();
    for (enc, name) in [
        (Encoding::Binary, "mixed.vtu"),
        (Encoding::Ascii, "mixed_a.vtu"),
    ] {
        let path = dir.path().join(name);
        write_vtu_with(&path, &mesh, &f.arrays(), &[], enc).unwrap();
        rust_check_vtu(&path, &types, &volumes, &f, mesh.n_points());
        let v = read_vtk_xml(&path);
        let fo = v.array("Cells", "faceoffsets").values.i64();
        assert_eq!(fo, [-1, -1, 24, 62, 86, -1, -1]);
        assert_eq!(fo[4], v.array("Cells", "faces").values.i64().len() as i64);
        // Stream lengths: a prism is 1 + 5 + 2*3 + 3*4 = 24 entries; the split hex has 7 faces,
        // 5 quads and 2 pentagons: 1 + 7 + 5*4 + 2*5 = 38.
        python_check_vtu(&path, &types, &volumes, &f, total);
    }
}

/// Deterministic pseudo-random numbers in [0, 1).
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn particles_with_arrays_and_a_pvd_series() {
    let n = 777;
    let mut s = 42;
    let pos: Vec<[f64; 3]> = (0..n)
        .map(|_| [lcg(&mut s), lcg(&mut s) - 0.5, 1e-3 * lcg(&mut s)])
        .collect();
    let radius: Vec<f64> = (0..n).map(|_| 1e-4 * (1.0 + lcg(&mut s))).collect();
    let vel: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, -(i as f64), 0.25]).collect();
    let ids: Vec<i64> = (0..n as i64).map(|i| (1 << 40) + i).collect();
    let kinds: Vec<i32> = (0..n as i32).map(|i| i % 3 - 1).collect();
    let weird = "T&<x>\"";
    let arrays = [
        DataArray::scalar("radius", &radius),
        DataArray::vector("v", &vel),
        DataArray::int64("id", &ids),
        DataArray::int32(weird, &kinds),
    ];
    let dir = tempfile::tempdir().unwrap();
    let mut series = Vec::new();
    for (k, enc) in [Encoding::Binary, Encoding::Ascii, Encoding::Binary]
        .into_iter()
        .enumerate()
    {
        let path = dir.path().join(format!("particles_{k}.vtp"));
        let m = n - 100 * k; // a shrinking particle count, as with outflow
        let sub: Vec<DataArray> = arrays
            .iter()
            .map(|a| DataArray {
                name: a.name,
                values: match a.values {
                    vtk::Values::Scalar(v) => vtk::Values::Scalar(&v[..m]),
                    vtk::Values::Vector(v) => vtk::Values::Vector(&v[..m]),
                    vtk::Values::Int64(v) => vtk::Values::Int64(&v[..m]),
                    vtk::Values::Int32(v) => vtk::Values::Int32(&v[..m]),
                },
            })
            .collect();
        write_vtp_with(&path, &pos[..m], &sub, enc).unwrap();
        series.push((k as f64 * 5e-4, path.clone()));

        let v = read_vtk_xml(&path);
        assert_eq!(v.root["type"], "PolyData");
        assert_eq!(v.count("NumberOfPoints"), m);
        assert_eq!(v.count("NumberOfVerts"), m);
        let conn = v.array("Verts", "connectivity").values.i64();
        let offs = v.array("Verts", "offsets").values.i64();
        assert_eq!(conn, (0..m as i64).collect::<Vec<_>>());
        assert_eq!(offs, (1..=m as i64).collect::<Vec<_>>());
        assert_eq!(
            v.array("Points", "Points").values.f64(),
            pos[..m].as_flattened()
        );
        assert_eq!(v.array("PointData", "radius").values.f64(), &radius[..m]);
        assert_eq!(
            v.array("PointData", "v").values.f64(),
            vel[..m].as_flattened()
        );
        assert_eq!(v.array("PointData", "id").values.i64(), &ids[..m]);
        let kv = v.array("PointData", weird);
        assert_eq!(kv.vtk_type, "Int32");
        assert_eq!(
            kv.values.i64(),
            kinds[..m].iter().map(|&k| k as i64).collect::<Vec<_>>()
        );

        for py in vtk_pythons() {
            let j = check_with(&py, &path);
            assert_eq!(j["n_points"].as_u64().unwrap() as usize, m);
            assert_eq!(j["n_verts"].as_u64().unwrap() as usize, m);
            assert_eq!(
                j["cell_types"]["1"].as_u64().unwrap() as usize,
                m,
                "VTK_VERTEX"
            );
            assert_close(
                &json_f64s(&j["points"]),
                pos[..m].as_flattened(),
                1e-15,
                "pos",
            );
            let pd = &j["point_data"];
            assert_close(
                &json_f64s(&pd["radius"]["values"]),
                &radius[..m],
                1e-15,
                "r",
            );
            assert_close(
                &json_f64s(&pd["v"]["values"]),
                vel[..m].as_flattened(),
                0.0,
                "v",
            );
            let id_back: Vec<i64> = json_f64s(&pd["id"]["values"])
                .iter()
                .map(|&x| x as i64)
                .collect();
            assert_eq!(id_back, &ids[..m]);
            assert_eq!(pd[weird]["type"], "int");
            assert_eq!(pd[weird]["range"], serde_json::json!([-1.0, 1.0]));
        }
    }

    let pvd = dir.path().join("particles.pvd");
    write_pvd(&pvd, &series).unwrap();
    let text = std::fs::read_to_string(&pvd).unwrap();
    assert!(text.contains(r#"type="Collection""#));
    let sets: Vec<_> = text
        .lines()
        .filter(|l| l.contains("<DataSet"))
        .map(attributes)
        .collect();
    assert_eq!(sets.len(), 3);
    for (k, s) in sets.iter().enumerate() {
        assert_eq!(
            s["file"],
            format!("particles_{k}.vtp"),
            "relative to the .pvd"
        );
        assert_eq!(s["timestep"].parse::<f64>().unwrap(), k as f64 * 5e-4);
        assert_eq!(s["part"], "0");
    }
    for py in vtk_pythons() {
        let j = check_with(&py, &pvd);
        let d = j["datasets"].as_array().unwrap();
        let counts: Vec<u64> = d.iter().map(|x| x["n_points"].as_u64().unwrap()).collect();
        assert_eq!(counts, [777, 677, 577]);
    }
}

#[test]
fn default_writers_are_binary() {
    let (mesh, volumes) = cartesian(&[0., 1.], &[0., 1.], &[0., 2.]);
    let dir = tempfile::tempdir().unwrap();
    let (vtu, vtp) = (dir.path().join("m.vtu"), dir.path().join("p.vtp"));
    write_vtu(&vtu, &mesh, &[DataArray::scalar("v", &volumes)], &[]).unwrap();
    write_vtp(&vtp, &mesh.points, &[]).unwrap();
    for p in [&vtu, &vtp] {
        let v = read_vtk_xml(p);
        assert!(v.sections["Points"].iter().all(|a| a.format == "binary"));
    }
    assert_eq!(vtu_cell_volumes(&read_vtk_xml(&vtu)), [2.0]);
}

#[test]
fn length_mismatch_and_bad_mesh_are_errors_naming_the_path() {
    let (mesh, _) = cartesian(&[0., 1., 2.], &[0., 1.], &[0., 1.]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.vtu");
    let short = [1.0];
    let e = write_vtu(&path, &mesh, &[DataArray::scalar("p", &short)], &[]).unwrap_err();
    assert!(
        matches!(
            e,
            VtkError::Length { ref name, expected: 2, found: 1, location: "cell", .. } if name == "p"
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("bad.vtu"), "{e}");
    let e = write_vtu(&path, &mesh, &[], &[DataArray::scalar("q", &short)]).unwrap_err();
    assert!(
        matches!(
            e,
            VtkError::Length {
                location: "point",
                expected: 12,
                ..
            }
        ),
        "{e:?}"
    );
    let two = [1.0, 2.0];
    let e = write_vtu(
        &path,
        &mesh,
        &[DataArray::scalar("p", &two), DataArray::scalar("p", &two)],
        &[],
    )
    .unwrap_err();
    assert!(matches!(e, VtkError::Invalid { .. }), "{e:?}");

    let mut broken = mesh.clone();
    broken.owner[3] = 9;
    let e = write_vtu(&path, &broken, &[], &[]).unwrap_err();
    assert!(matches!(e, VtkError::Mesh { .. }), "{e:?}");
    assert!(e.to_string().contains("bad.vtu"), "{e}");

    let e = write_vtp(
        dir.path().join("p.vtp"),
        &[[0.0; 3]; 2],
        &[DataArray::scalar("r", &short)],
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            VtkError::Length {
                expected: 2,
                found: 1,
                ..
            }
        ),
        "{e:?}"
    );
    let e = write_pvd(dir.path().join("s.pvd"), &[(f64::NAN, "a.vtp")]).unwrap_err();
    assert!(matches!(e, VtkError::Invalid { .. }), "{e:?}");

    // Nothing was written, not even a temporary.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn empty_particle_set_is_readable() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("none.vtp");
    write_vtp(&path, &[], &[DataArray::scalar("radius", &[])]).unwrap();
    let v = read_vtk_xml(&path);
    assert_eq!(v.count("NumberOfPoints"), 0);
    assert!(v.array("Points", "Points").values.f64().is_empty());
    for py in vtk_pythons() {
        let j = check_with(&py, &path);
        assert_eq!(j["n_points"], 0);
    }
}

/// The legacy `.vtk` particles read by VTK's own `vtkPolyDataReader` (what ParaView uses for
/// LIGGGHTS's `dump custom/vtk` files): points, vertices and arrays, to 1e-15 (VTK's ASCII
/// number parser is not always correctly rounded: one ulp off was seen).
#[test]
fn legacy_particles_read_by_vtk() {
    let n = 50;
    let mut s = 7;
    let pos: Vec<[f64; 3]> = (0..n)
        .map(|_| [lcg(&mut s), lcg(&mut s) - 0.5, 1e-3 * lcg(&mut s)])
        .collect();
    let radius: Vec<f64> = (0..n).map(|_| 1e-4 * (1.0 + lcg(&mut s))).collect();
    let vel: Vec<[f64; 3]> = (0..n)
        .map(|i| [i as f64 / 3.0, -(i as f64), 0.25])
        .collect();
    let ids: Vec<i64> = (0..n as i64).map(|i| 1 + i).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dump_100.vtk");
    vtk::write_legacy_vtk(
        &path,
        "foamgrain",
        &pos,
        &[
            DataArray::scalar("radius", &radius),
            DataArray::vector("v", &vel),
            DataArray::int64("id", &ids),
        ],
    )
    .unwrap();
    for py in vtk_pythons() {
        let j = check_with(&py, &path);
        assert_eq!(j["n_points"].as_u64().unwrap() as usize, n);
        assert_eq!(j["n_verts"].as_u64().unwrap() as usize, n);
        assert_close(&json_f64s(&j["points"]), pos.as_flattened(), 1e-15, "pos");
        let pd = &j["point_data"];
        assert_close(&json_f64s(&pd["radius"]["values"]), &radius, 1e-15, "r");
        assert_close(
            &json_f64s(&pd["v"]["values"]),
            vel.as_flattened(),
            1e-15,
            "v",
        );
        let id: Vec<f64> = ids.iter().map(|&i| i as f64).collect();
        assert_close(&json_f64s(&pd["id"]["values"]), &id, 1e-15, "id");
    }
}
