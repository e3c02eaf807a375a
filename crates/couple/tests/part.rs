//! A coupler rank on its part of the mesh (`couple::part`) against a coupler on the whole mesh,
//! bit for bit: the same particles give the same solid volume per cell (sent under the whole
//! mesh's labels) and the same forces; when the particles move out of the part, a new one is
//! cut and the results stay the same.
//!
//! The rank is rank 1 of two whose rank 0 is played by [`RankOne`]: it records what the rank
//! sends and answers with the whole-mesh coupler's ε and fluid at the cells the rank listed.

use couple::memory::MemoryFluid;
use couple::part::{PartSource, Parted};
use couple::FluidSide;
use couple::{Coupler, Ranks, SideError};
use foam::{Label, PolyMesh};
use mesh::build::hex_grid;
use mesh::part::MeshPart;
use mesh::v3::V3;
use mesh::Aabb;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use voidage::Method;

mod common;
use common::{cluster, varying_fluid as fluid, varying_settings as settings};

/// The whole mesh, kept in memory, as the source of parts; counts the cuts.
struct InMemory {
    whole: PolyMesh,
    cuts: Arc<AtomicUsize>,
}

impl PartSource for InMemory {
    fn cut(&mut self, region: &Aabb) -> Result<Option<MeshPart>, SideError> {
        self.cuts.fetch_add(1, Ordering::SeqCst);
        Ok(MeshPart::around(&self.whole, region))
    }
}

/// What rank 1 sent rank 0 in the last exchange: (cells, values, width) per call.
type Sent = Rc<RefCell<Vec<(Vec<Label>, Vec<f64>, usize)>>>;

/// Rank 0 of two, for a rank 1 under test (module docs).
struct RankOne {
    sent: Sent,
    list: Vec<Label>,
    /// ε and the fluid of the whole mesh (rank 0's).
    eps: Vec<f64>,
    fluid: Rc<MemoryFluid>,
}

impl Ranks for RankOne {
    fn rank(&self) -> usize {
        1
    }
    fn size(&self) -> usize {
        2
    }
    fn sum_to_root(&mut self, cells: &[Label], values: &[f64], width: usize, _root: &mut [f64]) {
        self.sent
            .borrow_mut()
            .push((cells.to_vec(), values.to_vec(), width));
        self.list = cells.to_vec();
    }
    fn scatter_from_root(
        &mut self,
        _width: usize,
        _value: &dyn Fn(Label, &mut Vec<f64>),
        out: &mut Vec<f64>,
    ) {
        let f = &self.fluid;
        for &c in &self.list {
            let c = c as usize;
            let (u, g, t) = (f.u[c], f.grad_p[c], f.div_tau[c]);
            out.extend_from_slice(&[
                self.eps[c],
                u[0],
                u[1],
                u[2],
                f.p[c],
                g[0],
                g[1],
                g[2],
                t[0],
                t[1],
                t[2],
            ]);
        }
    }
    fn all_sum(&self, _x: &mut [f64]) {}
    fn all_max(&self, _x: &mut [f64]) {}
    fn broadcast(&self, _x: &mut [f64]) {}
    fn gather(&self, x: &[f64]) -> Vec<Vec<f64>> {
        vec![x.to_vec()]
    }
}

#[test]
fn a_rank_on_its_part_deposits_and_forces_as_on_the_whole_mesh_and_follows_its_particles() {
    // a graded grid, so that no two cells are alike
    let xs = mesh::build::graded_planes(0.0, 1.0, 17, 1.2);
    let ys = mesh::build::graded_planes(0.0, 0.6, 9, 0.9);
    let zs = mesh::build::graded_planes(0.0, 1.0, 15, 1.0);
    let whole = hex_grid(&xs, &ys, &zs);
    for method in [Method::Exact, Method::Divided, Method::Centre] {
        let cuts = Arc::new(AtomicUsize::new(0));
        let source = InMemory {
            whole: whole.clone(),
            cuts: cuts.clone(),
        };
        let mut w = Coupler::new(&whole, settings(method)).unwrap();
        let fl = Rc::new(fluid(&whole, &w.voidage_mesh().geometry().cell_centres));
        let first = cluster(V3::new(0.25, 0.3, 0.3));
        let (part_mesh, parted) = Parted::first(Box::new(source), &first.position, &first.radius)
            .unwrap()
            .expect("the cluster's part is smaller than the mesh");
        assert!(
            part_mesh.n_cells < whole.n_cells / 2,
            "{}",
            part_mesh.n_cells
        );
        let mut p = Coupler::new(&part_mesh, settings(method)).unwrap();
        p.set_part(parted);
        let sent: Sent = Default::default();
        let mut worst: f64 = 0.0;
        for (k, at) in [(0.25, 0.3, 0.3), (0.27, 0.31, 0.3), (0.75, 0.3, 0.7)]
            .into_iter()
            .enumerate()
        {
            let c = cluster(V3::new(at.0, at.1, at.2));
            let ws = w.exchange(&c.state(), &fl.state()).unwrap();
            p.set_ranks(Box::new(RankOne {
                sent: sent.clone(),
                list: Vec::new(),
                eps: ws.voidage.epsilon.clone(),
                fluid: fl.clone(),
            }));
            sent.borrow_mut().clear();
            // rank 1 reads no fluid of its own: rank 0 sends it the cells' values
            let mut none = MemoryFluid::uniform(part_mesh.clone(), V3::zeros());
            (none.u, none.p, none.grad_p, none.div_tau) = (vec![], vec![], vec![], vec![]);
            let ps = p.exchange(&c.state(), &none.state()).unwrap();
            // the solid volume per cell, under the whole mesh's labels, is the whole mesh's
            let (cells, solid, width) = sent.borrow()[0].clone();
            assert_eq!(width, 1);
            assert!(cells.windows(2).all(|w| w[0] < w[1]));
            let scale = ws.deposit.solid.iter().copied().fold(0.0, f64::max);
            for (&cell, &v) in cells.iter().zip(&solid) {
                // round-off against the largest cell's solid volume (a thin cap's volume is a
                // difference of larger terms, computed about another grid origin on the part)
                let x = ws.deposit.solid[cell as usize];
                let d = (v - x).abs() / scale;
                worst = worst.max(d);
                assert!(d <= 1e-13, "{method:?} step {k} cell {cell}: {v} vs {x}");
            }
            let in_whole = ws.deposit.solid.iter().filter(|&&v| v > 0.0).count();
            assert_eq!(solid.iter().filter(|&&v| v > 0.0).count(), in_whole);
            assert_eq!(ps.deposit.particle_volume, ws.deposit.particle_volume);
            let outside = ps.deposit.outside_volume - ws.deposit.outside_volume;
            assert!(
                outside.abs() <= 1e-13 * ws.deposit.particle_volume,
                "{outside}"
            );
            // the forces
            for (a, b) in ps.forces.particles.iter().zip(&ws.forces.particles) {
                let d = (a.total - b.total).norm() / b.total.norm().max(1e-300);
                let d = d.max(rel(a.beta_dem, b.beta_dem));
                worst = worst.max(d);
                assert!(d <= 1e-13, "{method:?} step {k}: {a:?} vs {b:?}");
            }
            // the centre cells, mapped
            let global = p.part().unwrap().to_global(
                &ps.placement
                    .centre
                    .iter()
                    .map(|c| c.unwrap())
                    .collect::<Vec<_>>(),
            );
            let whole_centres: Vec<Label> =
                ws.placement.centre.iter().map(|c| c.unwrap()).collect();
            assert_eq!(global, whole_centres);
            // a small move stays in the first part; the cluster's jump across the mesh cuts a
            // second
            let expected_cuts = if k < 2 { 1 } else { 2 };
            assert_eq!(
                cuts.load(Ordering::SeqCst),
                expected_cuts,
                "{method:?} step {k}"
            );
            assert_eq!(p.part().unwrap().cuts as usize, expected_cuts);
        }
        println!("{method:?}: largest relative difference from the whole mesh {worst:.1e}");
    }
}

/// |a − b| relative to |b| (absolute below 1e-300).
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}
