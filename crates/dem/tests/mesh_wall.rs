//! STL mesh walls against closed forms: a plane of triangles is the primitive `zplane` wall
//! (the same overlap, the same Hertz–Mindlin force, the same tangential history, bit for bit)
//! wherever a sphere touches it — inside a triangle, on a shared edge, on a vertex where
//! eight triangles meet, and sliding or rolling across them; a triangulated box corner is
//! three primitive planes. Deck-level: `fix mesh/surface` with `scale`/`move`/`rotate`, its
//! file resolved against the deck's directory, and the errors for bad files and unknown meshes.

mod common;

use std::sync::Arc;

use common::meshes::grid;
use common::{plane, sim_with, sphere};
use dem::contact::{ContactModel, RollingModel};
use dem::material::MaterialInput;
use dem::mesh_wall::{MeshSurface, MeshWall};
use dem::trimesh::stl::ascii_stl;
use dem::trimesh::{MeshOptions, TriMesh};
use dem::Simulation;
use mesh::v3::V3;

fn surface(name: &str, tris: &[[V3; 3]]) -> Arc<MeshSurface> {
    let (mesh, dropped) = TriMesh::new(name, tris, &[], MeshOptions::default());
    assert!(dropped.origin.is_empty());
    Arc::new(MeshSurface {
        mesh,
        material_type: 1,
        stress: true,
    })
}

fn model() -> ContactModel {
    ContactModel {
        rolling: Some(RollingModel::Epsd2),
        ..ContactModel::default()
    }
}

fn material() -> MaterialInput {
    let mut m = MaterialInput::single(1e7, 0.3, 0.5, 0.4);
    m.rolling_friction = vec![0.1];
    m
}

/// Spheres of radius 1 mm placed on the plane z = 0 (overlap 0.6 µm, about their weight's) at the interior, on edges
/// and on vertices of the triangulation, with tangential and angular velocities that make
/// them slide and roll across edges and vertices, under a tilted gravity.
fn spheres() -> Vec<dem::particles::NewParticle> {
    let r = 1e-3;
    let z = r - 6e-7;
    // (on the 8 × 8 grid of 2.5 mm cells; all at least 2.5 mm apart throughout)
    let at = [
        (0.0, 0.0, 0.0, 0.0),           // a vertex of eight triangles, at rest
        (0.0025, 0.0, 0.0, 0.0),        // a vertex of four
        (0.00625, 0.0, 0.0, 0.0),       // on an edge
        (-0.00625, -0.00625, 0.0, 0.0), // on a diagonal
        (-0.0035, 0.0061, 0.0, 0.0),    // inside a triangle
        (-0.0049, 0.0025, 1.0, 0.0),    // sliding along a grid line, through vertices
        (-0.009, -0.003, 0.7, 0.7),     // sliding across edges and diagonals
        (0.004, -0.008, -0.2, 0.9),
    ];
    at.iter()
        .enumerate()
        .map(|(k, &(x, y, vx, vy))| {
            let mut s = sphere([x, y, z], [vx, vy, 0.0], r, 2500.0);
            s.id = k as u64 + 1;
            s.omega = V3::new(30.0 * k as f64, -20.0, 5.0);
            s
        })
        .collect()
}

fn run(sim: &mut Simulation, steps: u64) -> Vec<(Vec<V3>, Vec<V3>, Vec<V3>)> {
    let mut states = Vec::new();
    for _ in 0..steps {
        sim.run(1).unwrap();
        let p = &sim.particles;
        states.push((p.x.clone(), p.v.clone(), p.omega.clone()));
    }
    states
}

/// The primitive plane's simulation and one with the triangulated plane instead.
fn pair(n: usize) -> (Simulation, Simulation) {
    let g = [1.3, -0.7, -9.81];
    let dt = 1e-6;
    let mut a = sim_with(material(), model(), g, dt);
    a.add_wall(plane(2, 0.0, model())).unwrap();
    a.add_particles(&spheres()).unwrap();
    let mut b = sim_with(material(), model(), g, dt);
    let s = surface("plane", &grid(0.01, 0.0, n));
    b.add_mesh_wall(MeshWall::new("w", vec![s], model()))
        .unwrap();
    b.add_particles(&spheres()).unwrap();
    (a, b)
}

/// A plane of two triangles and of 2·8² triangles: every step, every sphere's position,
/// velocity and angular velocity are the primitive wall's, bit for bit, and each sphere has
/// exactly one mesh contact (none doubled on edges and vertices, none lost).
#[test]
fn triangulated_plane_is_the_zplane_wall() {
    for n in [1, 8] {
        let (mut a, mut b) = pair(n);
        let (sa, sb) = (run(&mut a, 3000), run(&mut b, 3000));
        for (k, (x, y)) in sa.iter().zip(&sb).enumerate() {
            assert_eq!(x, y, "n = {n}: step {} differs", k + 1);
        }
        let mut touching = 0;
        for (i, c) in b.mesh_contacts().iter().enumerate() {
            let t = b.particles.x[i][2] < b.particles.radius[i];
            assert_eq!(c.len(), t as usize, "particle {i}: {c:?}");
            touching += t as usize;
        }
        assert!(touching >= 6, "{touching} spheres on the plane");
        // the spheres did cross triangles: the sliders moved by more than a cell
        let moved = (b.particles.x[5] - spheres()[5].x).norm();
        assert!(moved > 0.0025, "{moved}");
        // the force on the mesh balances the wall forces on the spheres (Newton's third law)
        let on_mesh = b.mesh_surface_force("plane").unwrap();
        let on_spheres: V3 = b.mesh_contacts().iter().flatten().map(|c| c.force).sum();
        assert_eq!(on_mesh, -on_spheres);
        assert!(on_mesh[2] < 0.0);
    }
}

/// A sphere in the corner of a triangulated box (floor and two walls, two triangles each)
/// meets three faces, as three primitive planes: the same forces to round-off (the sums are
/// taken in another order).
#[test]
fn box_corner_is_three_planes() {
    let p = |x: f64, y: f64, z: f64| V3::new(x, y, z);
    // floor z = 0, walls x = 0 and y = 0, over [0, 1 cm]
    let s = 0.01;
    let tris = vec![
        [p(0., 0., 0.), p(s, 0., 0.), p(s, s, 0.)],
        [p(0., 0., 0.), p(s, s, 0.), p(0., s, 0.)],
        [p(0., 0., 0.), p(0., s, 0.), p(0., s, s)],
        [p(0., 0., 0.), p(0., s, s), p(0., 0., s)],
        [p(0., 0., 0.), p(0., 0., s), p(s, 0., s)],
        [p(0., 0., 0.), p(s, 0., s), p(s, 0., 0.)],
    ];
    let dt = 1e-6;
    let g = [0.0, 0.0, -9.81];
    let r = 1e-3;
    let ball = || {
        let mut b = sphere(
            [r - 2e-5, r - 1e-5, r - 3e-5],
            [-0.01, 0.02, 0.0],
            r,
            2500.0,
        );
        b.omega = V3::new(10.0, -5.0, 3.0);
        vec![b]
    };
    let mut a = sim_with(material(), model(), g, dt);
    for axis in 0..3 {
        a.add_wall(plane(axis, 0.0, model())).unwrap();
    }
    a.add_particles(&ball()).unwrap();
    let mut b = sim_with(material(), model(), g, dt);
    let surf = surface("corner", &tris);
    b.add_mesh_wall(MeshWall::new("w", vec![surf], model()))
        .unwrap();
    b.add_particles(&ball()).unwrap();
    let (sa, sb) = (run(&mut a, 200), run(&mut b, 200));
    let (xa, xb) = (&sa.last().unwrap().0[0], &sb.last().unwrap().0[0]);
    assert!((xa - xb).norm() < 1e-15, "{xa:?} vs {xb:?}");
    for (x, y) in sa.iter().zip(&sb) {
        assert!((x.1[0] - y.1[0]).norm() < 1e-12 * x.1[0].norm().max(1e-3));
    }
    assert_eq!(b.mesh_contacts()[0].len(), 3);
}

fn write(dir: &std::path::Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

/// A deck around a mesh: one sphere of radius 1 mm above the mesh.
fn deck(mesh_line: &str, wall_line: &str) -> String {
    format!(
        "atom_style granular\nboundary f f f\nunits si\n\
         region d block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box\ncreate_box 1 d\n\
         neighbor 0.0002 bin\n\
         fix m1 all property/global youngsModulus peratomtype 1e7\n\
         fix m2 all property/global poissonsRatio peratomtype 0.3\n\
         fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5\n\
         fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
         pair_style gran model hertz tangential history\npair_coeff * *\ntimestep 1e-6\n\
         {mesh_line}\n{wall_line}\n\
         create_atoms 1 single 0.001 0.002 0.0005 units box\n\
         set group all diameter 0.002 density 2500\n\
         fix integr all nve/sphere\nrun 0\n"
    )
}

/// `scale`, `move` and `rotate` in the order given; the STL file relative to the working
/// directory (a subfolder, as a CFDEM case's `DEM/meshes/`); the overlap is the closed form.
#[test]
fn deck_mesh_surface_with_transforms() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("meshes")).unwrap();
    // the unit square in the y–z plane at x = 0, normal +x
    let p = |y: f64, z: f64| V3::new(0.0, y, z);
    let tris = [
        [p(0., 0.), p(1., 0.), p(1., 1.)],
        [p(0., 0.), p(1., 1.), p(0., 1.)],
    ];
    write(
        &dir.path().join("meshes"),
        "sq.stl",
        &ascii_stl("sq", &tris),
    );
    // scale to 2 cm, centre on the origin, turn by 90° about y: the plane z = 0
    // (x' = z, z' = −x; the square spans x, y ∈ [−1, 1] cm). LIGGGHTS's π (3.14159265) leaves
    // cos 90° = 1.8·10⁻⁹, so z' reaches 1.8·10⁻¹¹ m at x' = ±1 cm, as in LIGGGHTS.
    let m = "fix sq all mesh/surface/stress file meshes/sq.stl type 1 scale 0.02 move 0 -0.01 -0.01 rotate axis 0 1 0 angle 90 curvature 1 temperature 300";
    let w = "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes sq\n\
             thermo_style custom step f_sq[3]";
    let text = deck(m, w);
    let mut warnings = Vec::new();
    let mut output = Vec::new();
    let d = liggghts_deck::Deck::parse(&text, &dir.path().join("in.mesh"), &[]).unwrap();
    let mut sim = Simulation::from_deck_observed(&d, dir.path(), &mut |e| match e {
        dem::deck::exec::DeckEvent::Warning { message, .. } => warnings.push(message),
        dem::deck::exec::DeckEvent::Output(line) => output.push(line),
        _ => {}
    })
    .unwrap();
    assert!(
        warnings.iter().any(|w| w.contains("temperature")),
        "{warnings:?}"
    );
    let mesh = &sim.mesh_walls()[0].surfaces[0].mesh;
    let (lo, hi) = mesh.bounds().unwrap();
    assert!((lo - V3::new(-0.01, -0.01, 0.0)).norm() < 2e-11, "{lo:?}");
    assert!((hi - V3::new(0.01, 0.01, 0.0)).norm() < 2e-11, "{hi:?}");
    // the sphere at z = 0.5 mm overlaps by 0.5 mm: Hertz F = 4/3 Y* √R δ^{3/2}
    sim.run(0).unwrap();
    let (e, nu, r, delta): (f64, f64, f64, f64) = (1e7, 0.3, 1e-3, 5e-4);
    let y_eff = e / (2.0 * (1.0 - nu * nu));
    let hertz = 4.0 / 3.0 * y_eff * r.sqrt() * delta.powf(1.5);
    // (the plane's tilt of 1.8·10⁻⁹ rad changes δ by < 2·10⁻¹² m and tilts the force as much)
    let f = sim.mesh_surface_force("sq").unwrap();
    assert!((f[2] + hertz).abs() < 1e-8 * hertz, "{f:?} vs {hertz}");
    assert!(
        f[0].abs() < 1e-8 * hertz && f[1].abs() < 1e-8 * hertz,
        "{f:?}"
    );
    // `f_sq[3]` of mesh/surface/stress in a thermo row of `run 0`: the same force (8 digits)
    let row = output
        .iter()
        .find(|l| l.trim_start().starts_with("0 "))
        .unwrap();
    let fz: f64 = row.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!((fz + hertz).abs() < 1e-7 * hertz, "{output:?}");
}

fn deck_error(files: &[(&str, &[u8])], mesh_line: &str, wall_line: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let text = deck(mesh_line, wall_line);
    let d = liggghts_deck::Deck::parse(&text, &dir.path().join("in.mesh"), &[]).unwrap();
    Simulation::from_deck(&d, dir.path())
        .unwrap_err()
        .to_string()
}

/// Missing, malformed and short STL files name the file (and the line for ASCII) and the deck
/// line; a wall naming an unknown mesh names its deck line.
#[test]
fn bad_meshes_are_clear_errors() {
    let w = "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes sq";
    let m = "fix sq all mesh/surface file sq.stl type 1";
    // the mesh fix is line 14 of the deck, the wall line 15
    let e = deck_error(&[], m, w);
    assert!(
        e.contains("in.mesh:14") && e.contains("sq.stl: cannot read"),
        "{e}"
    );
    let tri = [[V3::zeros(), V3::new(1.0, 0.0, 0.0), V3::new(0.0, 1.0, 0.0)]];
    let bad = ascii_stl("sq", &tri).replace("outer loop", "outer lop");
    let e = deck_error(&[("sq.stl", bad.as_bytes())], m, w);
    assert!(
        e.contains("in.mesh:14") && e.contains("sq.stl:3: expected `outer loop`"),
        "{e}"
    );
    let mut short = dem::trimesh::stl::binary_stl(&tri);
    short.pop();
    let e = deck_error(&[("sq.stl", &short)], m, w);
    assert!(
        e.contains("sq.stl") && e.contains("declare 1 triangles"),
        "{e}"
    );
    let good = ascii_stl("sq", &tri);
    let unknown =
        "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes sqq";
    let e = deck_error(&[("sq.stl", good.as_bytes())], m, unknown);
    assert!(
        e.contains("in.mesh:15") && e.contains("mesh `sqq` is not a `fix mesh/surface`"),
        "{e}"
    );
    let e = deck_error(
        &[("sq.stl", good.as_bytes())],
        "fix sq all mesh/surface file sq.stl",
        w,
    );
    assert!(
        e.contains("in.mesh:14") && e.contains("`type T` is required"),
        "{e}"
    );
    let moving = "fix sq all mesh/surface file sq.stl type 1 surface_vel 1 0 0";
    let e = deck_error(&[("sq.stl", good.as_bytes())], moving, w);
    assert!(e.contains("moving surfaces are not supported"), "{e}");
    let n2 = "fix wall all wall/gran model hertz tangential history mesh n_meshes 2 meshes sq";
    let e = deck_error(&[("sq.stl", good.as_bytes())], m, n2);
    assert!(
        e.contains("in.mesh:15") && e.contains("n_meshes 2 but 1 mesh ids"),
        "{e}"
    );
}
