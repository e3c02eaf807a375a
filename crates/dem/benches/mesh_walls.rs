//! Cost of mesh walls per particle-step, side by side with the primitive walls: 30,000 spheres
//! (R 0.5 mm) settling in a box of 32 × 32 mm, its walls either five primitive planes
//! (`zplane`, `xplane` ×2, `yplane` ×2) or an STL-like open box of 136 triangles (a floor of
//! 8 × 8 cells of two triangles, four walls of two; `tests/common/meshes.rs`'s `open_box`
//! scaled), or no walls at all (the rest of the step). Items = particle-steps, so divan's
//! throughput is particle-steps per second; the difference of the times is the walls' cost.
//!
//! ```text
//! cargo bench -p dem --bench mesh_walls
//! ```

#[path = "../tests/common/meshes.rs"]
mod meshes;

use std::sync::Arc;

use dem::contact::{ContactModel, RollingModel};
use dem::material::{MaterialInput, Materials};
use dem::mesh_wall::{MeshSurface, MeshWall};
use dem::particles::NewParticle;
use dem::trimesh::{MeshOptions, TriMesh};
use dem::walls::{Wall, WallShape};
use dem::{SimBox, SimConfig, Simulation};
use divan::counter::ItemsCount;
use divan::Bencher;
use mesh::v3::V3;

const STEPS: u64 = 20;
const R: f64 = 5e-4;
/// Lattice spacing (m) and cells per side: 31 × 31 × 32 = 30,752 spheres.
const SPACING: f64 = 1.03e-3;
const SIDE: usize = 31;
const LAYERS: usize = 32;

#[derive(Debug, Clone, Copy)]
enum Walls {
    None,
    Primitive,
    Mesh,
}

fn model() -> ContactModel {
    ContactModel {
        rolling: Some(RollingModel::Cdt),
        ..ContactModel::default()
    }
}

/// The spheres on a lattice touching the floor and the side walls, after 200 steps of settling.
fn settling(walls: Walls) -> Simulation {
    let half = 0.5 * SIDE as f64 * SPACING + 0.5 * (SPACING - 2.0 * R);
    let mut input = MaterialInput::single(1e7, 0.3, 0.5, 0.5);
    input.rolling_friction = vec![0.05];
    let mut sim = Simulation::new(SimConfig {
        materials: Materials::new(&input).unwrap(),
        pair_model: model(),
        dt: 1e-5,
        gravity: V3::new(0.0, 0.0, -9.81),
        skin: 2e-4,
        sim_box: SimBox::fixed(
            V3::new(-half - 1e-3, -half - 1e-3, -1e-3),
            V3::new(half + 1e-3, half + 1e-3, 0.1),
        ),
    })
    .unwrap();
    match walls {
        Walls::None => {}
        Walls::Primitive => {
            for (axis, position) in [(2, 0.0), (0, -half), (0, half), (1, -half), (1, half)] {
                sim.add_wall(Wall {
                    name: format!("w{axis}{position}"),
                    shape: WallShape::Plane { axis, position },
                    material_type: 1,
                    model: model(),
                })
                .unwrap();
            }
        }
        Walls::Mesh => {
            let tris: Vec<[V3; 3]> = meshes::open_box()
                .into_iter()
                .map(|t| t.map(|p| 2.0 * half * p - V3::new(half, half, 0.0)))
                .collect();
            let (mesh, _) = TriMesh::new("box", &tris, &[], MeshOptions::default());
            let surface = Arc::new(MeshSurface {
                mesh,
                material_type: 1,
                stress: false,
            });
            sim.add_mesh_wall(MeshWall::new("walls", vec![surface], model()))
                .unwrap();
        }
    }
    let mut ps = Vec::new();
    for k in 0..LAYERS {
        for j in 0..SIDE {
            for i in 0..SIDE {
                let c = |n: usize| -half + R + (SPACING - 2.0 * R) * 0.5 + n as f64 * SPACING;
                ps.push(NewParticle {
                    id: 0,
                    atom_type: 1,
                    x: V3::new(c(i), c(j), R + k as f64 * SPACING),
                    v: V3::zeros(),
                    omega: V3::zeros(),
                    radius: R,
                    density: 2500.0,
                });
            }
        }
    }
    sim.add_particles(&ps).unwrap();
    sim.run(200).unwrap();
    sim
}

#[divan::bench(args = [Walls::None, Walls::Primitive, Walls::Mesh], sample_count = 5)]
fn box_of_30000(bencher: Bencher, walls: Walls) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut sim = pool.install(|| settling(walls));
    let n = sim.particles.len() as u64;
    bencher
        .counter(ItemsCount::new(n * STEPS))
        .bench_local(|| pool.install(|| sim.run(STEPS).unwrap()));
}

fn main() {
    divan::main();
}
