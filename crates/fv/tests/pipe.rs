//! Hagen–Poiseuille flow: steady laminar flow in a round pipe of radius R driven by a fixed
//! kinematic pressure drop Δp over the length L (inlet/outlet `fixedValue` p, `zeroGradient` U,
//! `noSlip` wall), against the closed form u(r) = G (R² − r²) / (4ν), G = Δp/L, u_max = G R²/(4ν)
//! (e.g. White, *Viscous Fluid Flow*, 3rd ed., eq. 3-34), on O-grid meshes of the pipe built here
//! (a square core block and four blocks between its sides and the circle).
//!
//! Fast tier: the profile error falls with refinement, the volume-weighted RMS at order 1.5–1.8
//! and the maximum at order 1 (at the corners of the core block, where the O-grid's cells stay
//! skewed under refinement; the straight cell edges also make the cross-section a polygon, an
//! O(h²) error of its own). Full tier: a fresh icoFoam run on the same mesh with the same
//! settings agrees to round-off.

mod common;
use common::{write_case, CaseSpec, PatchSpec};
use foam::{FaceList, Label, Patch, PolyMesh};
use mesh::v3::V3;
use std::collections::HashMap;

/// O-grid of a pipe of radius `r` along z ∈ [0, len]: an `n`×`n` core square of half-side
/// 0.55 r, `m` cells radially between each of its sides and the circle (points spaced
/// linearly between the square's side and the arc at the same angle), `nz` cells along the
/// axis. Patches `inlet` (z = 0), `outlet` (z = len), `wall`; faces in upper-triangular order.
fn pipe_mesh(r: f64, len: f64, n: usize, m: usize, nz: usize) -> PolyMesh {
    let a = 0.55 * r;
    // Cross-section quads as 4 corner points (counter-clockwise seen from +z).
    let mut quads: Vec<[[f64; 2]; 4]> = Vec::new();
    let core = |i: usize, j: usize| {
        let s = |k: usize| a * (2.0 * k as f64 / n as f64 - 1.0);
        [s(i), s(j)]
    };
    for j in 0..n {
        for i in 0..n {
            quads.push([
                core(i, j),
                core(i + 1, j),
                core(i + 1, j + 1),
                core(i, j + 1),
            ]);
        }
    }
    // Side k (0: +x, 1: +y, 2: −x, 3: −y) rotated by 90° k; point (t, q): t along the side,
    // q = 0 on the square, q = m on the circle.
    let rot = |k: usize, p: [f64; 2]| {
        let (mut x, mut y) = (p[0], p[1]);
        for _ in 0..k {
            (x, y) = (-y, x);
        }
        [x, y]
    };
    let ring = |k: usize, t: usize, q: usize| {
        let u = t as f64 / n as f64;
        let square = [a, a * (2.0 * u - 1.0)];
        let th = std::f64::consts::FRAC_PI_2 * (u - 0.5);
        let circle = [r * th.cos(), r * th.sin()];
        let w = q as f64 / m as f64;
        rot(
            k,
            [
                square[0] + w * (circle[0] - square[0]),
                square[1] + w * (circle[1] - square[1]),
            ],
        )
    };
    for k in 0..4 {
        for q in 0..m {
            for t in 0..n {
                quads.push([
                    ring(k, t, q),
                    ring(k, t, q + 1),
                    ring(k, t + 1, q + 1),
                    ring(k, t + 1, q),
                ]);
            }
        }
    }
    // Points shared by coordinates (rounded far below the cell size).
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut ids: HashMap<[i64; 3], Label> = HashMap::new();
    let mut id = |p: [f64; 3]| -> Label {
        let key = p.map(|x| (x * 1e9 / r).round() as i64);
        *ids.entry(key).or_insert_with(|| {
            points.push(p);
            (points.len() - 1) as Label
        })
    };
    // Hexes with OpenFOAM's vertex order (bottom quad, then the top one).
    let mut hexes: Vec<[Label; 8]> = Vec::new();
    for kz in 0..nz {
        let z0 = len * kz as f64 / nz as f64;
        let z1 = len * (kz + 1) as f64 / nz as f64;
        for qd in &quads {
            let b: Vec<Label> = qd.iter().map(|p| id([p[0], p[1], z0])).collect();
            let t: Vec<Label> = qd.iter().map(|p| id([p[0], p[1], z1])).collect();
            hexes.push([b[0], b[1], b[2], b[3], t[0], t[1], t[2], t[3]]);
        }
    }
    from_hexes(points, &hexes, len)
}

/// A polyMesh from hexahedra: faces shared by two cells are internal (owner the lower cell,
/// sorted by owner then neighbour), the others go to `inlet`, `outlet` or `wall` by their centre.
fn from_hexes(points: Vec<[f64; 3]>, hexes: &[[Label; 8]], len: f64) -> PolyMesh {
    const FACES: [[usize; 4]; 6] = [
        [0, 4, 7, 3],
        [1, 2, 6, 5],
        [0, 1, 5, 4],
        [3, 7, 6, 2],
        [0, 3, 2, 1],
        [4, 5, 6, 7],
    ];
    let centre = |pts: &[Label]| {
        let mut c = [0.0; 3];
        for &p in pts {
            for (ci, x) in c.iter_mut().zip(points[p as usize]) {
                *ci += x / pts.len() as f64;
            }
        }
        c
    };
    let mut seen: HashMap<[Label; 4], (usize, [Label; 4])> = HashMap::new();
    let mut internal: Vec<(usize, usize, [Label; 4])> = Vec::new();
    for (c, h) in hexes.iter().enumerate() {
        for f in FACES {
            let verts = f.map(|i| h[i]);
            let mut key = verts;
            key.sort_unstable();
            if let Some((other, v)) = seen.remove(&key) {
                internal.push((
                    other.min(c),
                    other.max(c),
                    if other < c { v } else { verts },
                ));
            } else {
                seen.insert(key, (c, verts));
            }
        }
    }
    internal.sort_unstable_by_key(|&(o, n, _)| (o, n));
    let mut boundary: [Vec<(usize, [Label; 4])>; 3] = Default::default();
    for (c, verts) in seen.into_values() {
        let fc = centre(&verts);
        let which = if fc[2].abs() < 1e-9 * len {
            0
        } else if (fc[2] - len).abs() < 1e-9 * len {
            1
        } else {
            2
        };
        boundary[which].push((c, verts));
    }
    let mut faces = FaceList::new();
    let mut owner = Vec::new();
    let mut neighbour = Vec::new();
    let push = |faces: &mut FaceList, c: usize, verts: [Label; 4]| {
        // Orient S out of the owner: flip when it points towards the cell centre.
        let cc = centre(&hexes[c]);
        let p: Vec<V3> = verts
            .iter()
            .map(|&v| V3::from(points[v as usize]))
            .collect();
        let d1 = p[2] - p[0];
        let d2 = p[3] - p[1];
        let s = d1.cross(&d2);
        let out = s.dot(&(V3::from(centre(&verts)) - V3::from(cc))) > 0.0;
        let v = if out {
            verts
        } else {
            [verts[0], verts[3], verts[2], verts[1]]
        };
        faces.push(&v);
    };
    for &(o, n, verts) in &internal {
        push(&mut faces, o, verts);
        owner.push(o as Label);
        neighbour.push(n as Label);
    }
    let mut patches = Vec::new();
    for (name, mut list) in ["inlet", "outlet", "wall"].into_iter().zip(boundary) {
        list.sort_unstable_by_key(|e| (e.0, e.1));
        patches.push(Patch {
            name: name.into(),
            patch_type: if name == "wall" { "wall" } else { "patch" }.into(),
            n_faces: list.len(),
            start_face: owner.len(),
            extra: Vec::new(),
        });
        for (c, verts) in list {
            push(&mut faces, c, verts);
            owner.push(c as Label);
        }
    }
    PolyMesh {
        points,
        faces,
        owner,
        neighbour,
        boundary: patches,
        n_cells: hexes.len(),
    }
}

const R: f64 = 0.5;
const LEN: f64 = 1.0;
const NU: f64 = 1.0;
const DP: f64 = 4.0;

/// Writes the pipe case for the O-grid (n, m) with one cell along the axis into `dir`, U
/// starting from the analytic profile (the steady discrete solution is independent of the
/// start; starting close to it shortens the transient); returns the time step and step count.
fn write_pipe_case(dir: &std::path::Path, n: usize, m: usize) -> (f64, usize) {
    let mesh = pipe_mesh(R, LEN, n, m, 1);
    let centres = fv::FvGeometry::new(&mesh).unwrap().c;
    let zg = "type zeroGradient;";
    let inlet_p = format!("type fixedValue; value uniform {DP};");
    let patches = [
        PatchSpec {
            name: "inlet",
            patch_type: "patch",
            u: zg,
            p: &inlet_p,
        },
        PatchSpec {
            name: "outlet",
            patch_type: "patch",
            u: zg,
            p: "type fixedValue; value uniform 0;",
        },
        PatchSpec {
            name: "wall",
            patch_type: "wall",
            u: "type noSlip;",
            p: zg,
        },
    ];
    // Diffusion number ν Δt / h² = 1 on the radial cell size h (PISO with the explicit
    // non-orthogonal correction diverged at 2 on the finest mesh); the slowest mode decays as
    // exp(−5.78 ν t / R²), so by t = 0.25 the start's deviation has fallen by e^−5.8.
    let end = 0.25;
    let h = (R - 0.55 * R) / m as f64;
    let steps = (end / (h * h / NU)).ceil() as usize;
    let delta_t = end / steps as f64;
    let spec = CaseSpec {
        nu: NU,
        rho: 1.0,
        delta_t,
        end_time: end,
        ddt: "Euler",
        div: "Gauss linear",
        n_correctors: 2,
        u_internal: [0.0; 3],
    };
    write_case(dir, mesh, &patches, &spec);
    let u_path = dir.join("0/U");
    let text = std::fs::read_to_string(&u_path).unwrap();
    let values: Vec<String> = centres
        .iter()
        .map(|c| format!("(0 0 {})", exact(c)))
        .collect();
    let list = format!(
        "internalField nonuniform List<vector> {}({});",
        values.len(),
        values.join(" ")
    );
    let text = text.replace("internalField uniform (0 0 0);", &list);
    std::fs::write(&u_path, text).unwrap();
    (delta_t, steps)
}

/// The Hagen–Poiseuille velocity (m/s) at the point `c`.
fn exact(c: &V3) -> f64 {
    DP / LEN * (R * R - c[0] * c[0] - c[1] * c[1]) / (4.0 * NU)
}

/// (max, volume-weighted RMS) of |u_z − u_exact(r)| / u_max over the cells, and the largest
/// transverse speed / u_max.
fn profile_error(centres: &[V3], volumes: &[f64], u: &[V3]) -> (f64, f64, f64) {
    let umax = DP / LEN * R * R / (4.0 * NU);
    let (mut max, mut sq, mut vol, mut transverse) = (0.0f64, 0.0, 0.0, 0.0f64);
    for ((c, v), u) in centres.iter().zip(volumes).zip(u) {
        let e = (u[2] - exact(c)).abs() / umax;
        max = max.max(e);
        sq += v * e * e;
        vol += v;
        transverse = transverse.max(u[0].hypot(u[1]) / umax);
    }
    (max, (sq / vol).sqrt(), transverse)
}

fn pipe_error(n: usize, m: usize) -> (f64, f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let (dt, steps) = write_pipe_case(dir.path(), n, m);
    let mut fluid = fv::Fluid::from_case(dir.path()).unwrap();
    for _ in 0..steps {
        fluid.advance(dt).unwrap();
    }
    let g = fluid.geometry();
    profile_error(&g.c, &g.v, fluid.u())
}

#[test]
fn hagen_poiseuille_profile_error_falls_with_refinement() {
    let levels = [(3, 2), (6, 4), (12, 8)];
    let e: Vec<(f64, f64, f64)> = levels.iter().map(|&(n, m)| pipe_error(n, m)).collect();
    for ((n, m), (max, rms, tr)) in levels.iter().zip(&e) {
        eprintln!(
            "pipe O-grid {n}x{n} core, {m} radial ({} cells/section): max error {max:.3e}, rms {rms:.3e} of u_max, transverse {tr:.1e}",
            n * n + 4 * n * m
        );
    }
    let order_rms = [(e[0].1 / e[1].1).log2(), (e[1].1 / e[2].1).log2()];
    let order_max = [(e[0].0 / e[1].0).log2(), (e[1].0 / e[2].0).log2()];
    eprintln!("observed order: rms {order_rms:.2?}, max {order_max:.2?}");
    // Measured: rms 5.17e-2, 1.52e-2, 5.50e-3 (order 1.76, 1.47); max 6.45e-2, 2.28e-2, 1.14e-2
    // (order 1.50, 1.00), the max at the corners of the core square, where three cells meet
    // and the cells stay skewed under refinement (icoFoam has the same errors on these meshes).
    assert!(e[2].1 < 6e-3 && e[2].0 < 1.2e-2, "{e:?}");
    assert!(
        order_rms.iter().all(|&p| p > 1.4),
        "rms order {order_rms:?}"
    );
    assert!(
        order_max.iter().all(|&p| p > 0.95),
        "max order {order_max:?}"
    );
    assert!(e.iter().all(|x| x.2 < 1e-12), "transverse velocity {e:?}");
}

/// Full tier: icoFoam on the same O-grid (6×6 core, 4 radial) with the same settings
/// (PBiCGStab/DILU for U, PCG/DIC for p, 80 steps): the velocities agree to round-off
/// (measured 5.6e-16 of u_max), so the profile error above is the scheme's on this mesh, not
/// ours alone.
#[test]
fn pipe_matches_a_fresh_icofoam_run() {
    if !testkit::tool("icoFoam") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (ours, theirs) = (dir.path().join("fv"), dir.path().join("icoFoam"));
    let (dt, steps) = write_pipe_case(&ours, 6, 4);

    // icoFoam asks for the final corrector's pressure solver by name.
    let sol = ours.join("system/fvSolution");
    let text = std::fs::read_to_string(&sol).unwrap().replacen(
        "solvers\n{\n",
        "solvers\n{\n    pFinal { solver PCG; preconditioner DIC; tolerance 1e-12; relTol 0; }\n",
        1,
    );
    std::fs::write(&sol, text).unwrap();
    let cd = ours.join("system/controlDict");
    let text = std::fs::read_to_string(&cd).unwrap().replace(
        "writeInterval 100000;",
        &format!("writeInterval {steps};\nwritePrecision 17;"),
    );
    std::fs::write(&cd, text).unwrap();
    testkit::copy_dir(&ours, &theirs);
    testkit::run_ok(testkit::openfoam("icoFoam"), &theirs);
    let mut fluid = fv::Fluid::from_case(&ours).unwrap();
    for _ in 0..steps {
        fluid.advance(dt).unwrap();
    }
    let n = fluid.geometry().n_cells;
    let case = foam::Case::open(&theirs).unwrap();
    let last = case.latest_time().unwrap().unwrap();
    assert!(
        approx::abs_diff_eq!(last.value, dt * steps as f64, epsilon = 1e-12),
        "icoFoam ended at {}",
        last.value
    );
    let foam::FieldValues::Vector(u_ico) = foam::VolField::read(&last.path.join("U"))
        .unwrap()
        .internal(n)
        .unwrap()
    else {
        panic!("U is a vector field");
    };
    let umax = DP / LEN * R * R / (4.0 * NU);
    let du = fluid
        .u()
        .iter()
        .zip(&u_ico)
        .flat_map(|(a, b)| (0..3).map(move |k| (a[k] - b[k]).abs()))
        .fold(0.0, f64::max)
        / umax;
    let g = fluid.geometry();
    let (e_ours, _, _) = profile_error(&g.c, &g.v, fluid.u());
    let (e_ico, _, _) = profile_error(&g.c, &g.v, &mesh::v3::from_arrays(&u_ico));
    eprintln!(
        "pipe 6x6/4 vs icoFoam: max |ΔU|/u_max = {du:.3e}; max error vs Hagen–Poiseuille: fv {e_ours:.4e}, icoFoam {e_ico:.4e}"
    );
    assert!(du < 1e-12, "max |ΔU|/u_max = {du}");
}
