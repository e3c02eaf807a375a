//! Parses every FoamFile under a directory and reports the ones that fail.
//! `cargo run --release -p foam --example parse_tree -- DIR` (e.g. Debian's
//! /usr/share/doc/openfoam-examples/examples or /usr/share/openfoam/etc).

use std::path::{Path, PathBuf};

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            walk(&p, out);
        } else {
            out.push(p);
        }
    }
}

/// The path without a trailing `.gz` (the reader finds the compressed file itself).
fn without_gz(p: &Path) -> PathBuf {
    PathBuf::from(p.to_string_lossy().trim_end_matches(".gz"))
}

/// True when the file (gunzipped if needed) starts, after comments, with `FoamFile`.
fn is_foam_file(p: &Path) -> bool {
    let Ok((_, bytes)) = foam::parser::read_bytes(&without_gz(p)) else {
        return false;
    };
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]).into_owned();
    let mut s = head.as_str();
    loop {
        s = s.trim_start();
        if let Some(r) = s.strip_prefix("//") {
            s = r.split_once('\n').map_or("", |x| x.1);
        } else if let Some(r) = s.strip_prefix("/*") {
            s = r.split_once("*/").map_or("", |x| x.1);
        } else {
            return s.starts_with("FoamFile");
        }
    }
}

fn main() {
    let dir = std::env::args().nth(1).expect("usage: parse_tree DIR");
    let mut files = Vec::new();
    walk(Path::new(&dir), &mut files);
    let (mut ok, mut failed) = (0, 0);
    // polyMesh directories are read as meshes (their files are lists, not dictionaries).
    let mut meshes: Vec<PathBuf> = files
        .iter()
        .filter_map(|f| f.parent())
        .filter(|d| {
            d.ends_with("polyMesh") && d.join("owner").exists() || d.join("owner.gz").exists()
        })
        .map(Path::to_path_buf)
        .collect();
    meshes.sort();
    meshes.dedup();
    let (mut mesh_ok, mut mesh_failed) = (0, 0);
    for m in &meshes {
        match foam::read_poly_mesh(m) {
            Ok(_) => mesh_ok += 1,
            Err(e) => {
                mesh_failed += 1;
                println!("{e}");
            }
        }
    }
    println!("read {mesh_ok} polyMesh directories, {mesh_failed} failed");
    let in_mesh = |f: &Path| f.parent().is_some_and(|d| meshes.iter().any(|m| m == d));
    let m4 = |f: &Path| f.to_string_lossy().contains(".m4");
    for f in files
        .iter()
        .filter(|f| !in_mesh(f) && !m4(f) && is_foam_file(f))
    {
        match foam::parse_file(&without_gz(f)) {
            Ok(_) => ok += 1,
            Err(e) => {
                failed += 1;
                println!("{e}");
            }
        }
    }
    println!("parsed {ok} FoamFiles, {failed} failed");
}
