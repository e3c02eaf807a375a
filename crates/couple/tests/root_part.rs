//! Rank 0 on its part of the mesh while the fluid is on rank 0 (`Coupler::set_root_volumes`,
//! the native fluid on several coupler ranks) against a coupler on the whole mesh: the whole
//! solid volume per cell, ε, the exchange fields handed to the fluid, the voidage kept for the
//! next hand-over and the forces are the whole-mesh coupler's, bit for bit with `divided` and
//! `centre` (to 1e-13 of the scale with `exact`, whose kernel on an axis-aligned part measures
//! its planes from another origin), while the particles move a little and then across the
//! mesh (a second cut). Both couplers are rank 0 of two whose other rank has no particle
//! ([`RootOfTwo`]): the reference is what rank 0 on the whole mesh computes on several ranks.

use couple::part::{PartSource, Parted};
use couple::FluidSide;
use couple::{Coupler, Ranks, Serial, SideError};
use foam::Label;
use foam::PolyMesh;
use mesh::build::hex_grid;
use mesh::part::MeshPart;
use mesh::v3::V3;
use mesh::Aabb;
use voidage::Method;

mod common;
use common::{cluster, varying_fluid as fluid, varying_settings as settings};

/// The whole mesh, kept in memory, as the source of parts.
struct InMemory(PolyMesh);

impl PartSource for InMemory {
    fn cut(&mut self, region: &Aabb) -> Result<Option<MeshPart>, SideError> {
        Ok(MeshPart::around(&self.0, region))
    }
}

/// Rank 0 of two whose rank 1 holds no particle: rank 0's sums are its own cells (as
/// [`Serial`]'s), the other rank sends and receives nothing.
#[derive(Default)]
struct RootOfTwo(Serial);

impl Ranks for RootOfTwo {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        2
    }
    fn sum_to_root(&mut self, cells: &[Label], values: &[f64], width: usize, root: &mut [f64]) {
        self.0.sum_to_root(cells, values, width, root);
    }
    fn scatter_from_root(
        &mut self,
        _width: usize,
        _value: &dyn Fn(Label, &mut Vec<f64>),
        _out: &mut Vec<f64>,
    ) {
    }
    fn all_sum(&self, _x: &mut [f64]) {}
    fn all_max(&self, _x: &mut [f64]) {}
    fn broadcast(&self, _x: &mut [f64]) {}
    fn gather(&self, x: &[f64]) -> Vec<Vec<f64>> {
        // rank 1 saw nothing enter or leave
        vec![x.to_vec(), vec![0.0]]
    }
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
        w.set_ranks(Box::<RootOfTwo>::default());
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
        p.set_ranks(Box::<RootOfTwo>::default());
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
            let total: Vec<f64> = ws
                .forces
                .particles
                .iter()
                .flat_map(|c| flat(&[c.total]))
                .collect();
            let mine: Vec<f64> = ps
                .forces
                .particles
                .iter()
                .flat_map(|c| flat(&[c.total]))
                .collect();
            let d = d.max(worst(&mine, &total, largest(&total)));
            assert!(d <= tolerance, "{method:?} step {k}: {d:e}");
            assert_eq!(ps.deposit.particle_volume, ws.deposit.particle_volume);
            assert_eq!(ps.voidage.clipped_cells, ws.voidage.clipped_cells);
            let cuts = p.part().unwrap().cuts;
            assert_eq!(cuts, if k < 2 { 1 } else { 2 }, "{method:?} step {k}");
            // what rank 0 holds for the mesh: its part's voidage mesh and the whole mesh's
            // volumes, ε and the handed-over voidage (not its voidage mesh)
            let (part_bytes, whole_bytes) = (p.held_bytes().mesh, w.held_bytes().mesh);
            assert!(
                part_bytes < whole_bytes / 2,
                "{part_bytes} of {whole_bytes} B"
            );
            println!("{method:?} step {k}: {held} cells held, {d:.1e}, mesh {part_bytes} of {whole_bytes} B");
        }
    }
}
