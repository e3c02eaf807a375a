//! The STL geometries of the mesh-wall tests and decks, generated here (the committed files
//! under `liggghts-inputs/meshes/` are these, written by `ascii_stl`; `tests/mesh_liggghts.rs`
//! checks it).

#![allow(dead_code)]

use mesh::v3::V3;

/// The square [−a, a]² at height z, `n × n` cells of two triangles each (diagonals
/// alternating, so vertices are met by 4, 6 or 8 triangles).
pub fn grid(a: f64, z: f64, n: usize) -> Vec<[V3; 3]> {
    let mut t = Vec::new();
    let c = |i: usize| -a + 2.0 * a * i as f64 / n as f64;
    for i in 0..n {
        for j in 0..n {
            let p = |i: usize, j: usize| V3::new(c(i), c(j), z);
            let (p00, p10, p11, p01) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            if (i + j) % 2 == 0 {
                t.push([p00, p10, p11]);
                t.push([p00, p11, p01]);
            } else {
                t.push([p00, p10, p01]);
                t.push([p10, p11, p01]);
            }
        }
    }
    t
}

/// `liggghts-inputs/meshes/plane.stl`: the square [−1, 1]² at z = 0 in 2 × 2 cells (8 triangles).
pub fn plane() -> Vec<[V3; 3]> {
    grid(1.0, 0.0, 2)
}

/// `liggghts-inputs/meshes/box.stl`: the open box [0, 1]² × [0, 3], its floor 8 × 8 cells
/// (128 triangles), each wall two triangles.
pub fn open_box() -> Vec<[V3; 3]> {
    let mut t: Vec<[V3; 3]> = grid(0.5, 0.0, 8)
        .into_iter()
        .map(|tri| tri.map(|p| p + V3::new(0.5, 0.5, 0.0)))
        .collect();
    let h = 3.0;
    let p = V3::new;
    // x = 0, x = 1, y = 0, y = 1
    for [a, b] in [
        [p(0., 0., 0.), p(0., 1., 0.)],
        [p(1., 1., 0.), p(1., 0., 0.)],
        [p(1., 0., 0.), p(0., 0., 0.)],
        [p(0., 1., 0.), p(1., 1., 0.)],
    ] {
        let up = V3::new(0.0, 0.0, h);
        t.push([a, b, b + up]);
        t.push([a, b + up, a + up]);
    }
    t
}
