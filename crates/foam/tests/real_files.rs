//! The foam crate against files written by Debian's OpenFOAM v1912 (blockMesh, postProcess,
//! decomposePar; see tests/fixtures/foam/README.md): ASCII and binary must give identical data,
//! and read → write → read must be exact in both formats.

use approx::assert_abs_diff_eq;
use foam::{
    parse_file, read_poly_mesh, write_poly_mesh, Case, FieldKind, FieldValues, Format, Item,
    VolField,
};
use std::path::PathBuf;

fn fixture(rel: &str) -> PathBuf {
    testkit::fixture("foam").join(rel)
}

#[test]
fn ascii_and_binary_blockmesh_give_the_same_mesh() {
    let a = read_poly_mesh(&fixture("cavity/constant/polyMesh")).unwrap();
    let b = read_poly_mesh(&fixture("cavity-binary/constant/polyMesh")).unwrap();
    // checkMesh: points 60, faces 98, internal faces 46, cells 24.
    assert_eq!(
        (a.n_points(), a.n_faces(), a.n_internal_faces(), a.n_cells),
        (60, 98, 46, 24)
    );
    let names: Vec<_> = a.boundary.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["movingWall", "fixedWalls", "frontAndBack"]);
    assert_eq!(a.boundary[2].patch_type, "empty");
    assert_eq!(a.boundary[0].n_faces, 4 * 2);
    assert_eq!(a, b);
    // The blockMesh vertex (1.1 1 0.1) scaled by 0.1 is the largest corner.
    let max = a.points.iter().fold([f64::MIN; 3], |m, p| {
        [m[0].max(p[0]), m[1].max(p[1]), m[2].max(p[2])]
    });
    assert!(
        (max[0] - 0.11).abs() < 1e-15
            && (max[1] - 0.1).abs() < 1e-15
            && (max[2] - 0.01).abs() < 1e-15,
        "{max:?}"
    );
}

#[test]
fn mesh_round_trips_exactly_in_both_formats() {
    let m = read_poly_mesh(&fixture("cavity/constant/polyMesh")).unwrap();
    for format in [Format::Ascii, Format::Binary] {
        let dir = tempfile::tempdir().unwrap();
        write_poly_mesh(dir.path(), &m, format).unwrap();
        let back = read_poly_mesh(dir.path()).unwrap();
        assert_eq!(back, m, "{format:?}");
    }
}

#[test]
fn nonuniform_fields_agree_between_formats_and_round_trip() {
    for name in ["V", "C"] {
        let a = VolField::read(&fixture(&format!("cavity/0/{name}"))).unwrap();
        let b = VolField::read(&fixture(&format!("cavity-binary/0/{name}"))).unwrap();
        assert_eq!(a.header.format, Format::Ascii);
        assert_eq!(b.header.format, Format::Binary);
        let va = a.internal(24).unwrap();
        assert_eq!(va, b.internal(24).unwrap(), "{name}");
        for format in [Format::Ascii, Format::Binary] {
            let dir = tempfile::tempdir().unwrap();
            let p = dir.path().join(name);
            a.write(&p, format).unwrap();
            let back = VolField::read(&p).unwrap();
            assert_eq!(back.header.format, format);
            assert_eq!(back.body, a.body, "{name} {format:?}");
        }
    }
    // The total of OpenFOAM's own cell volumes is checkMesh's "Total volume = 0.0001".
    let v = VolField::read(&fixture("cavity/0/V")).unwrap();
    let FieldValues::Scalar(v) = v.internal(24).unwrap() else {
        panic!()
    };
    assert_abs_diff_eq!(v.iter().sum::<f64>(), 1e-4, epsilon = 1e-16);
}

#[test]
fn read_modify_write_keeps_boundary_field() {
    let f = VolField::read(&fixture("cavity/0/U")).unwrap();
    assert_eq!(f.kind().unwrap(), FieldKind::Vector);
    assert_eq!(
        f.internal(3).unwrap(),
        FieldValues::Vector(vec![[0.0; 3]; 3])
    );
    let mut g = f.clone();
    let vals: Vec<[f64; 3]> = (0..24).map(|i| [i as f64 * 0.1, -1e-300, 1e300]).collect();
    g.set_internal(FieldValues::Vector(vals.clone())).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for format in [Format::Ascii, Format::Binary] {
        let p = dir.path().join("U");
        g.write(&p, format).unwrap();
        let back = VolField::read(&p).unwrap();
        assert_eq!(back.boundary(), f.boundary());
        assert_eq!(
            back.internal(24).unwrap(),
            FieldValues::Vector(vals.clone())
        );
        assert_eq!(
            back.header.location,
            dir.path().file_name().unwrap().to_str().unwrap()
        );
        let mv = back.boundary().dict("movingWall").unwrap();
        assert_eq!(
            mv.stream("value").unwrap()[1].as_vector(),
            Some([1.0, 0.0, 0.0])
        );
    }
    // A pattern keyword resolves the patch it matches.
    let p = VolField::read(&fixture("cavity/0/p")).unwrap();
    let e = p.boundary().resolve("fixedWalls", &[]).unwrap();
    assert!(e.pattern);
    assert!(p.boundary().resolve("inlet", &[]).is_none());
}

#[test]
fn decomposed_case_parts_add_up() {
    let case = Case::open(fixture("cavity")).unwrap();
    let procs = case.processors().unwrap();
    assert_eq!(procs.len(), 2);
    let mut cells = 0;
    for (n, p) in &procs {
        let m = p.read_mesh().unwrap();
        cells += m.n_cells;
        let proc_patch = m
            .boundary
            .iter()
            .find(|b| b.patch_type == "processor")
            .unwrap();
        let neighb = proc_patch
            .extra
            .iter()
            .find(|(k, _)| k == "neighbProcNo")
            .map(|(_, v)| v.clone())
            .unwrap();
        assert_eq!(neighb, (1 - n).to_string());
        let v = VolField::read(&p.time_path("0").join("V")).unwrap();
        assert_eq!(v.internal(m.n_cells).unwrap().len(), m.n_cells);
    }
    assert_eq!(cells, 24);
}

#[test]
fn case_layout_and_system_dictionaries() {
    let case = Case::open(fixture("cavity")).unwrap();
    let times: Vec<_> = case.times().unwrap().into_iter().map(|t| t.name).collect();
    assert_eq!(times, ["0"]);
    let cd = case.control_dict().unwrap();
    assert_eq!(cd.f64("deltaT").unwrap(), 0.005);
    assert_eq!(cd.word("writeFormat").unwrap(), "ascii");
    assert!(cd.switch("runTimeModifiable").unwrap());
    let fv = case.read_dict("system/fvSolution").unwrap();
    let solvers = fv.dict("solvers").unwrap();
    assert_eq!(
        solvers.dict("p").unwrap().word("preconditioner").unwrap(),
        "DIC"
    );
    let u = solvers.resolve("U", &[]).unwrap();
    assert!(u.pattern && u.keyword == "(U|k)");
    let sch = case.read_dict("system/fvSchemes").unwrap();
    let div = sch
        .dict("divSchemes")
        .unwrap()
        .stream("div(phi,U)")
        .unwrap();
    assert_eq!(
        div,
        [Item::Word("Gauss".into()), Item::Word("linear".into())]
    );
    // blockMeshDict uses $lx inside a list of vertices.
    let bm = parse_file(&fixture("cavity/system/blockMeshDict")).unwrap();
    let verts = bm.body.item("vertices").unwrap();
    let Item::List(v) = verts else { panic!() };
    assert_eq!(v[1].as_vector(), Some([1.0, 0.0, 0.0]));
}

#[test]
fn sorts_time_directories_numerically() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("constant")).unwrap();
    for t in ["0.5", "10", "2", "1e-05", "0", "processor0x", "system"] {
        std::fs::create_dir(dir.path().join(t)).unwrap();
    }
    let case = Case::open(dir.path()).unwrap();
    let names: Vec<_> = case.times().unwrap().into_iter().map(|t| t.name).collect();
    assert_eq!(names, ["0", "1e-05", "0.5", "2", "10"]);
    assert_eq!(case.latest_time().unwrap().unwrap().value, 10.0);
}
