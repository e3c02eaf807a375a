//! Programmatic polyMesh builders for tests, benchmarks and downstream crates: Cartesian
//! (tensor-product, optionally graded) hexahedral grids, single-cell meshes, and point maps.

use foam::{FaceList, Label, Patch, PolyMesh};

/// `n + 1` plane coordinates from `x0` to `x1` with blockMesh's `simpleGrading` expansion ratio
/// `ratio` = (last cell width) / (first cell width); widths form a geometric series.
/// The end planes are exactly `x0` and `x1`.
pub fn graded_planes(x0: f64, x1: f64, n: usize, ratio: f64) -> Vec<f64> {
    assert!(n >= 1, "at least one cell");
    let r = if n > 1 {
        ratio.powf(1.0 / (n as f64 - 1.0))
    } else {
        1.0
    };
    let widths: Vec<f64> = (0..n).map(|i| r.powi(i as i32)).collect();
    let total: f64 = widths.iter().sum();
    let mut planes = Vec::with_capacity(n + 1);
    let mut acc = 0.0;
    planes.push(x0);
    for w in &widths[..n - 1] {
        acc += w;
        planes.push(x0 + (x1 - x0) * (acc / total));
    }
    planes.push(x1);
    planes
}

/// A tensor-product hexahedral mesh on the planes `xs × ys × zs` (each strictly increasing,
/// at least two values), numbered like blockMesh: point (i, j, k) has label
/// `i + (nx+1)(j + (ny+1)k)`, cell (i, j, k) has label `i + nx(j + ny k)`. Faces are in
/// OpenFOAM's upper-triangular order; six patches `xMin, xMax, yMin, yMax, zMin, zMax`.
pub fn hex_grid(xs: &[f64], ys: &[f64], zs: &[f64]) -> PolyMesh {
    let (nx, ny, nz) = (xs.len() - 1, ys.len() - 1, zs.len() - 1);
    assert!(
        nx >= 1 && ny >= 1 && nz >= 1,
        "at least one cell per direction"
    );
    let mut points = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for &z in zs {
        for &y in ys {
            for &x in xs {
                points.push([x, y, z]);
            }
        }
    }
    let pt = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as Label;
    let cell = |i: usize, j: usize, k: usize| (i + nx * (j + ny * k)) as Label;
    // Faces whose normal is +x, +y, +z at the plane of lower corner (i, j, k).
    let x_face = |i, j, k| {
        [
            pt(i, j, k),
            pt(i, j + 1, k),
            pt(i, j + 1, k + 1),
            pt(i, j, k + 1),
        ]
    };
    let y_face = |i, j, k| {
        [
            pt(i, j, k),
            pt(i, j, k + 1),
            pt(i + 1, j, k + 1),
            pt(i + 1, j, k),
        ]
    };
    let z_face = |i, j, k| {
        [
            pt(i, j, k),
            pt(i + 1, j, k),
            pt(i + 1, j + 1, k),
            pt(i, j + 1, k),
        ]
    };
    let rev = |f: [Label; 4]| [f[0], f[3], f[2], f[1]];
    let n_int = (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1);
    let n_bnd = 2 * (ny * nz + nx * nz + nx * ny);
    let mut faces = FaceList::with_capacity(n_int + n_bnd, 4 * (n_int + n_bnd));
    let mut owner = Vec::with_capacity(n_int + n_bnd);
    let mut neighbour = Vec::with_capacity(n_int);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let c = cell(i, j, k);
                if i + 1 < nx {
                    faces.push(&x_face(i + 1, j, k));
                    owner.push(c);
                    neighbour.push(cell(i + 1, j, k));
                }
                if j + 1 < ny {
                    faces.push(&y_face(i, j + 1, k));
                    owner.push(c);
                    neighbour.push(cell(i, j + 1, k));
                }
                if k + 1 < nz {
                    faces.push(&z_face(i, j, k + 1));
                    owner.push(c);
                    neighbour.push(cell(i, j, k + 1));
                }
            }
        }
    }
    let mut boundary = Vec::new();
    let mut patch = |name: &str, faces_of: &mut dyn FnMut(&mut FaceList, &mut Vec<Label>)| {
        let start = owner.len();
        faces_of(&mut faces, &mut owner);
        boundary.push(Patch {
            name: name.into(),
            patch_type: "patch".into(),
            n_faces: owner.len() - start,
            start_face: start,
            extra: vec![],
        });
    };
    patch("xMin", &mut |f, o| {
        for k in 0..nz {
            for j in 0..ny {
                f.push(&rev(x_face(0, j, k)));
                o.push(cell(0, j, k));
            }
        }
    });
    patch("xMax", &mut |f, o| {
        for k in 0..nz {
            for j in 0..ny {
                f.push(&x_face(nx, j, k));
                o.push(cell(nx - 1, j, k));
            }
        }
    });
    patch("yMin", &mut |f, o| {
        for k in 0..nz {
            for i in 0..nx {
                f.push(&rev(y_face(i, 0, k)));
                o.push(cell(i, 0, k));
            }
        }
    });
    patch("yMax", &mut |f, o| {
        for k in 0..nz {
            for i in 0..nx {
                f.push(&y_face(i, ny, k));
                o.push(cell(i, ny - 1, k));
            }
        }
    });
    patch("zMin", &mut |f, o| {
        for j in 0..ny {
            for i in 0..nx {
                f.push(&rev(z_face(i, j, 0)));
                o.push(cell(i, j, 0));
            }
        }
    });
    patch("zMax", &mut |f, o| {
        for j in 0..ny {
            for i in 0..nx {
                f.push(&z_face(i, j, nz));
                o.push(cell(i, j, nz - 1));
            }
        }
    });
    PolyMesh {
        points,
        faces,
        owner,
        neighbour,
        boundary,
        n_cells: nx * ny * nz,
    }
}

/// A uniform `n[0] × n[1] × n[2]` grid on the box `[lo, hi]`.
pub fn uniform_box(lo: impl Into<[f64; 3]>, hi: impl Into<[f64; 3]>, n: [usize; 3]) -> PolyMesh {
    let (lo, hi) = (lo.into(), hi.into());
    let planes = |a: usize| graded_planes(lo[a], hi[a], n[a], 1.0);
    hex_grid(&planes(0), &planes(1), &planes(2))
}

/// A one-cell mesh: every face is a boundary face of cell 0 in patch `walls`. Faces must be
/// ordered so that their normals (right-hand rule) point out of the cell.
pub fn single_cell(points: Vec<[f64; 3]>, faces: &[&[Label]]) -> PolyMesh {
    let mut list = FaceList::new();
    for f in faces {
        list.push(f);
    }
    PolyMesh {
        points,
        faces: list,
        owner: vec![0; faces.len()],
        neighbour: vec![],
        boundary: vec![Patch {
            name: "walls".into(),
            patch_type: "wall".into(),
            n_faces: faces.len(),
            start_face: 0,
            extra: vec![],
        }],
        n_cells: 1,
    }
}

/// The same mesh with every point moved by `f`.
pub fn map_points(mesh: &PolyMesh, f: impl Fn([f64; 3]) -> [f64; 3]) -> PolyMesh {
    let mut m = mesh.clone();
    for p in &mut m.points {
        *p = f(*p);
    }
    m
}

/// The affine map `p ↦ a·p + b` (row-major 3×3 matrix `a`), e.g. for [`map_points`].
pub fn affine(a: [[f64; 3]; 3], b: impl Into<[f64; 3]>) -> impl Fn([f64; 3]) -> [f64; 3] {
    let b = b.into();
    move |p| {
        let mut q = b;
        for (r, row) in a.iter().enumerate() {
            q[r] += row[0] * p[0] + row[1] * p[1] + row[2] * p[2];
        }
        q
    }
}

/// The rotation matrix about the unit axis `axis` by `angle` (radians), Rodrigues' formula.
pub fn rotation(axis: impl Into<[f64; 3]>, angle: f64) -> [[f64; 3]; 3] {
    let axis = axis.into();
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = [axis[0] / n, axis[1] / n, axis[2] / n];
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}
