//! Reading and writing a 10⁶-cell polyMesh (100³ hexahedra, 3.03·10⁶ faces, 1.03·10⁶ points)
//! with the foam crate, ASCII and binary. The files are written once into a temporary
//! directory (page cache), then read repeatedly; sizes are printed so MB/s can be derived.

use foam::{read_poly_mesh, write_poly_mesh, Format};
use mesh::build::uniform_box;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn main() {
    divan::main();
}

struct Files {
    _dir: tempfile::TempDir,
    ascii: PathBuf,
    binary: PathBuf,
}

fn dir_size(p: &Path) -> u64 {
    std::fs::read_dir(p)
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len())
        .sum()
}

fn files() -> &'static Files {
    static F: OnceLock<Files> = OnceLock::new();
    F.get_or_init(|| {
        let mesh = uniform_box([0.0; 3], [1.0; 3], [100; 3]);
        let dir = tempfile::tempdir().unwrap();
        let ascii = dir.path().join("ascii");
        let binary = dir.path().join("binary");
        write_poly_mesh(&ascii, &mesh, Format::Ascii).unwrap();
        write_poly_mesh(&binary, &mesh, Format::Binary).unwrap();
        eprintln!(
            "mesh_io: {} cells; ascii polyMesh {:.1} MB, binary {:.1} MB",
            mesh.n_cells,
            dir_size(&ascii) as f64 / 1e6,
            dir_size(&binary) as f64 / 1e6
        );
        Files {
            _dir: dir,
            ascii,
            binary,
        }
    })
}

#[divan::bench(sample_count = 5)]
fn read_ascii() -> usize {
    read_poly_mesh(&files().ascii).unwrap().n_cells
}

#[divan::bench(sample_count = 5)]
fn read_binary() -> usize {
    read_poly_mesh(&files().binary).unwrap().n_cells
}

#[divan::bench(sample_count = 3)]
fn write_ascii(b: divan::Bencher) {
    let mesh = uniform_box([0.0; 3], [1.0; 3], [100; 3]);
    let dir = tempfile::tempdir().unwrap();
    b.bench(|| write_poly_mesh(dir.path(), &mesh, Format::Ascii).unwrap());
}

#[divan::bench(sample_count = 3)]
fn write_binary(b: divan::Bencher) {
    let mesh = uniform_box([0.0; 3], [1.0; 3], [100; 3]);
    let dir = tempfile::tempdir().unwrap();
    b.bench(|| write_poly_mesh(dir.path(), &mesh, Format::Binary).unwrap());
}
