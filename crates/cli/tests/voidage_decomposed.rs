//! Full tier: `foamgrain voidage` on a case that Debian's `decomposePar` cut into 3 pieces
//! writes each piece's part of the field; `reconstructPar` (OpenFOAM's own) puts the pieces
//! back together into exactly the field foamgrain wrote on the whole mesh.

use std::process::Command;
use testkit::{copy_dir, fixture, openfoam, run_ok, tool};

const DECOMPOSE: &str = r#"FoamFile { version 2.0; format ascii; class dictionary; object decomposeParDict; }
numberOfSubdomains 3;
method simple;
simpleCoeffs { n (3 1 1); delta 0.001; }
"#;

fn cell_values(path: &std::path::Path, n_cells: usize) -> Vec<f64> {
    let field = foam::VolField::read(path).unwrap();
    match field.internal(n_cells).unwrap() {
        foam::FieldValues::Scalar(v) => v,
        other => panic!("{other:?}"),
    }
}

#[test]
fn reconstructpar_of_the_pieces_gives_the_whole_field() {
    if !tool("decomposePar") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path();
    copy_dir(&fixture("foam/cavity/system"), &case.join("system"));
    std::fs::create_dir(case.join("constant")).unwrap();
    std::fs::write(case.join("system/blockMeshDict"), testkit::BOX_BLOCK_MESH).unwrap();
    std::fs::write(case.join("system/decomposeParDict"), DECOMPOSE).unwrap();
    run_ok(openfoam("blockMesh"), case);
    std::fs::create_dir_all(case.join("0")).unwrap();
    run_ok(openfoam("decomposePar"), case);
    let dump = fixture("liggghts/settle.txt");
    let out = Command::new(env!("CARGO_BIN_EXE_foamgrain"))
        .args(["voidage", "--case", ".", "--dump", dump.to_str().unwrap()])
        .args(["--method", "exact", "--json"])
        .current_dir(case)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&out.stdout).lines().last().unwrap()).unwrap();
    assert_eq!(report["pieces"], 3);
    let whole = cell_values(&case.join("0/voidfraction"), 1500);
    assert!(
        whole.iter().any(|&e| e < 0.99),
        "the dump must fill some cells"
    );
    // OpenFOAM reassembles the pieces into the case root, over the whole-mesh file
    std::fs::remove_file(case.join("0/voidfraction")).unwrap();
    let mut reconstruct = openfoam("reconstructPar");
    reconstruct.args(["-withZero", "-fields", "(voidfraction)"]);
    run_ok(reconstruct, case);
    let rebuilt = cell_values(&case.join("0/voidfraction"), 1500);
    assert_eq!(rebuilt.len(), whole.len());
    for (c, (a, b)) in rebuilt.iter().zip(&whole).enumerate() {
        // ASCII round trip: OpenFOAM writes 6 significant digits
        assert!(
            (a - b).abs() <= 1e-6 * b.abs().max(1e-3),
            "cell {c}: {a} vs {b}"
        );
    }
}
