//! Corrupted copies of real OpenFOAM files: every problem is an error that names the file and
//! where in it, never a panic.

use foam::{read_poly_mesh, VolField};
use std::path::{Path, PathBuf};

fn fixture(rel: &str) -> PathBuf {
    testkit::fixture("foam").join(rel)
}

/// A copy of a fixture polyMesh with `file` replaced by `edit(original bytes)`.
fn mesh_with(
    case: &str,
    file: &str,
    edit: impl Fn(Vec<u8>) -> Vec<u8>,
) -> (tempfile::TempDir, String) {
    let src = fixture(case).join("constant/polyMesh");
    let dir = tempfile::tempdir().unwrap();
    for f in ["points", "faces", "owner", "neighbour", "boundary"] {
        let mut b = std::fs::read(src.join(f)).unwrap();
        if f == file {
            b = edit(b);
        }
        std::fs::write(dir.path().join(f), b).unwrap();
    }
    let e = read_poly_mesh(dir.path()).unwrap_err().to_string();
    (dir, e)
}

fn replace(b: Vec<u8>, from: &str, to: &str) -> Vec<u8> {
    let s = String::from_utf8(b).unwrap();
    assert!(s.contains(from), "fixture lacks {from:?}");
    s.replacen(from, to, 1).into_bytes()
}

fn assert_names(e: &str, dir: &Path, file: &str, want: &str) {
    let path = if file.is_empty() {
        dir.to_path_buf()
    } else {
        dir.join(file)
    };
    assert!(e.contains(&path.display().to_string()), "{e}");
    assert!(e.contains(want), "expected {want:?} in: {e}");
}

#[test]
fn ascii_mesh_errors() {
    let (d, e) = mesh_with("cavity", "points", |b| replace(b, "\n60\n", "\n61\n"));
    assert_names(&e, d.path(), "points", "declares 61 vectors but holds 60");
    let (d, e) = mesh_with("cavity", "points", |b| replace(b, "(0 0 0)", "(0 zero 0)"));
    assert_names(&e, d.path(), "points", "line 2");
    assert!(e.contains("should be a number, found word `zero`"), "{e}");
    let (d, e) = mesh_with("cavity", "faces", |b| {
        replace(b, "4(1 6 26 21)", "4(1 6 999 21)")
    });
    assert_names(
        &e,
        d.path(),
        "",
        "names point 999 but there are only 60 points",
    );
    let (d, e) = mesh_with("cavity", "faces", |b| {
        replace(b, "4(1 6 26 21)", "4(1 6 -3 21)")
    });
    assert_names(&e, d.path(), "faces", "label -3 is negative");
    let (d, e) = mesh_with("cavity", "neighbour", |b| {
        replace(b, "\n46\n(\n1\n", "\n46\n(\n0\n")
    });
    assert_names(&e, d.path(), "", "owner 0 is not below neighbour 0");
    let (d, e) = mesh_with("cavity", "owner", |b| {
        let s = String::from_utf8(b).unwrap();
        let i = s.rfind(')').unwrap();
        s[..i - 3].to_string().into_bytes()
    });
    assert_names(&e, d.path(), "owner", "ends with the file");
}

#[test]
fn binary_mesh_errors() {
    // Cut the binary points list short: the error gives the byte offset.
    let (d, e) = mesh_with("cavity-binary", "points", |b| {
        let i = b.windows(4).position(|w| w == b"\n60\n").unwrap();
        b[..i + 4 + 1 + 100].to_vec()
    });
    assert_names(
        &e,
        d.path(),
        "points",
        "binary list cut short: needs 1440 bytes",
    );
    // A wrong count in a binary list shows up at the closing bracket.
    let (d, e) = mesh_with("cavity-binary", "owner", |b| {
        let i = b.windows(4).position(|w| w == b"\n98\n").unwrap();
        let mut c = b.clone();
        c[i + 1..i + 3].copy_from_slice(b"97");
        c
    });
    assert_names(&e, d.path(), "owner", "is not closed by `)`");
    // Owner with a cell label beyond nCells of its note.
    let (d, e) = mesh_with("cavity", "owner", |b| replace(b, "nCells:24", "nCells:20"));
    assert_names(&e, d.path(), "owner", "nCells:20");
}

#[test]
fn field_errors() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("V");
    let s = std::fs::read_to_string(fixture("cavity/0/V")).unwrap();
    std::fs::write(&p, s.replace("volScalarField", "surfaceScalarField")).unwrap();
    let e = VolField::read(&p).unwrap_err().to_string();
    assert!(
        e.contains("surfaceScalarField") && e.contains(&p.display().to_string()),
        "{e}"
    );
    let f = VolField::read(&fixture("cavity/0/V")).unwrap();
    assert!(f
        .internal(25)
        .unwrap_err()
        .contains("has 24 values but the mesh has 25 cells"));
    let mut g = f.clone();
    g.set_internal(foam::FieldValues::Scalar(vec![f64::NAN; 24]))
        .unwrap();
    let e = g
        .write(&dir.path().join("W"), foam::Format::Ascii)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("non-finite") && e.contains("internalField"),
        "{e}"
    );
    assert!(!dir.path().join("W").exists(), "no half-written file");
}
