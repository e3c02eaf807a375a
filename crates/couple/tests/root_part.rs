//! Rank 0 on its part of the mesh while the fluid is on rank 0 (`Coupler::set_root_volumes`,
//! the native fluid on several coupler ranks) against a coupler on the whole mesh: the whole
//! solid volume per cell, ε, the exchange fields handed to the fluid, the voidage kept for the
//! next hand-over and the forces are the whole-mesh coupler's, bit for bit with `divided` and
//! `centre` (to 1e-13 of the scale with `exact`, whose kernel on an axis-aligned part measures
//! its planes from another origin), while the particles move a little and then across the
//! mesh (a second cut). The root's sums are played by one rank ([`couple::Serial`]): its
//! sum to the root is its own cells, scattered into the whole-length arrays.

use closures::DragLaw;
use couple::memory::MemoryFluid;
use couple::part::{PartSource, Parted};
use couple::FluidSide;
use couple::{Coupler, CouplerSettings, Interpolation, SideError};
use foam::PolyMesh;
use mesh::build::hex_grid;
use mesh::part::MeshPart;
use mesh::v3::V3;
use mesh::Aabb;
use voidage::Method;

mod common;
use common::Particles;

/// The whole mesh, kept in memory, as the source of parts.
struct InMemory(PolyMesh);

impl PartSource for InMemory {
    fn cut(&mut self, region: &Aabb) -> Result<Option<MeshPart>, SideError> {
        Ok(MeshPart::around(&self.0, region))
    }
}

/// Fields varying in space over the cells of `mesh` at centres `x`.
fn fluid(mesh: &PolyMesh, x: &[V3]) -> MemoryFluid {
    let mut f = MemoryFluid::uniform(mesh.clone(), V3::zeros());
    f.u = x
        .iter()
        .map(|c| V3::new(c[1], -c[0], 0.5 + c[2] * c[2]))
        .collect();
    f.p = x.iter().map(|c| 10.0 * c[2] + c[0]).collect();
    f.grad_p = x
        .iter()
        .map(|c| V3::new(0.1 * c[1], 0.0, 9.0 + c[0]))
        .collect();
    f.div_tau = x.iter().map(|c| V3::new(c[2], c[0] * c[1], -0.2)).collect();
    f
}

fn settings(method: Method) -> CouplerSettings {
    common::drag_settings(
        method,
        DragLaw::DiFelice,
        Interpolation::Smooth,
        1.2,
        1.5e-5,
    )
}

/// A cluster of 40 spheres (radius 0.012–0.02 m) about `at`, ids 1…40.
fn cluster(at: V3) -> Particles {
    let n = 40;
    let pos = (0..n)
        .map(|k| {
            let s = k as f64;
            at + 0.08 * V3::new((s * 1.7).sin(), (s * 0.9).cos(), (s * 2.3).sin())
        })
        .collect();
    let vel = (0..n)
        .map(|k| V3::new(0.1, 0.0, -0.01 * k as f64))
        .collect();
    let mut c = Particles::new(pos, vel);
    c.radius = (0..n).map(|k| 0.012 + 0.0002 * k as f64).collect();
    c
}

/// The largest |a − b| over the pairs, relative to `scale`.
fn worst<'a>(a: impl IntoIterator<Item = &'a f64>, b: &[f64], scale: f64) -> f64 {
    let mut n = 0;
    let w = a
        .into_iter()
        .zip(b)
        .map(|(x, y)| {
            n += 1;
            (x - y).abs() / scale
        })
        .fold(0.0, f64::max);
    assert_eq!(n, b.len(), "lengths differ");
    w
}

fn flat(v: &[V3]) -> Vec<f64> {
    v.iter().flat_map(|x| [x[0], x[1], x[2]]).collect()
}

fn largest(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).fold(1e-300, f64::max)
}

#[test]
fn rank_0_on_its_part_hands_the_fluid_the_whole_mesh_fields() {
    // a graded grid, so that no two cells are alike
    let xs = mesh::build::graded_planes(0.0, 1.0, 17, 1.2);
    let ys = mesh::build::graded_planes(0.0, 0.6, 9, 0.9);
    let zs = mesh::build::graded_planes(0.0, 1.0, 15, 1.0);
    let whole = hex_grid(&xs, &ys, &zs);
    for method in [Method::Exact, Method::Divided, Method::Centre] {
        let tolerance = if method == Method::Exact { 1e-13 } else { 0.0 };
        let mut w = Coupler::new(&whole, settings(method)).unwrap();
        let geometry = w.voidage_mesh().geometry();
        let volumes = geometry.cell_volumes.clone();
        let fl = fluid(&whole, &geometry.cell_centres);
        let first = cluster(V3::new(0.25, 0.3, 0.3));
        let source = Box::new(InMemory(whole.clone()));
        let (part_mesh, parted) = Parted::first(source, &first.position, &first.radius)
            .unwrap()
            .expect("the cluster's part is smaller than the mesh");
        let mut p = Coupler::new(&part_mesh, settings(method)).unwrap();
        p.set_part(parted);
        p.set_root_volumes(volumes);
        assert_eq!(p.voidage().len(), whole.n_cells);
        assert!(p.voidage().iter().all(|&e| e == 1.0));
        for (k, at) in [(0.25, 0.3, 0.3), (0.27, 0.31, 0.3), (0.75, 0.3, 0.7)]
            .into_iter()
            .enumerate()
        {
            let c = cluster(V3::new(at.0, at.1, at.2));
            let ws = w.exchange(&c.state(), &fl.state()).unwrap();
            let ps = p.exchange(&c.state(), &fl.state()).unwrap();
            let held = p.voidage_mesh().n_cells();
            assert!(held < whole.n_cells / 2, "step {k}: {held} cells held");
            let solid = &ws.deposit.solid;
            let d = worst(&ps.deposit.solid, solid, largest(solid));
            let eps = &ws.voidage.epsilon;
            let d = d.max(worst(&ps.voidage.epsilon, eps, 1.0));
            let d = d.max(worst(p.voidage(), w.voidage(), 1.0));
            let (a, b) = (&ps.exchange, &ws.exchange);
            let d = d.max(worst(&a.ksl, &b.ksl, largest(&b.ksl)));
            let us = flat(&b.us);
            let d = d.max(worst(&flat(&a.us), &us, largest(&us)));
            let f = flat(&b.f);
            let d = d.max(worst(&flat(&a.f), &f, largest(&f)));
            let total: Vec<f64> = ws.forces.particles.iter().flat_map(|c| flat(&[c.total])).collect();
            let mine: Vec<f64> = ps.forces.particles.iter().flat_map(|c| flat(&[c.total])).collect();
            let d = d.max(worst(&mine, &total, largest(&total)));
            assert!(d <= tolerance, "{method:?} step {k}: {d:e}");
            assert_eq!(ps.deposit.particle_volume, ws.deposit.particle_volume);
            assert_eq!(ps.voidage.clipped_cells, ws.voidage.clipped_cells);
            let cuts = p.part().unwrap().cuts;
            assert_eq!(cuts, if k < 2 { 1 } else { 2 }, "{method:?} step {k}");
            // what rank 0 holds for the mesh: its part's voidage mesh and the whole mesh's
            // volumes, ε and the handed-over voidage (not its voidage mesh)
            let (part_bytes, whole_bytes) = (p.held_bytes().mesh, w.held_bytes().mesh);
            assert!(part_bytes < whole_bytes / 2, "{part_bytes} of {whole_bytes} B");
            println!("{method:?} step {k}: {held} cells held, {d:.1e}, mesh {part_bytes} of {whole_bytes} B");
        }
    }
}
