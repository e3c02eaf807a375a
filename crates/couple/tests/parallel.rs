//! The parallel force and exchange loops against serial references, bit for bit, with 1 to 8
//! threads:
//! * the exchange fields equal a plain serial loop over the particles written out here
//!   (Ksl_c = Σ w β / V_c, Us_c = Σ w β v / Σ w β, f_c = −Σ w F / V_c, ADR 0004);
//! * the per-particle couplings equal the closures' drag law and forces evaluated at the
//!   fluid fields [`Placement::value_at`] gives, for every combination of interpolation rules;
//! * the pipelined forces + exchange equal the force loop followed by the exchange, over
//!   several stages, also when writing into a recycled vector;
//! * coupling steps that recycle the previous step's buffers give the same results as fresh
//!   ones, with the particle count changing in between;
//! * the first bad particle is named by index and id however the check is split.

#![allow(clippy::needless_range_loop)]

use closures::model::{particle_forces, FluidAtParticle, ModelType};
use closures::{DragClosure, DragInput, DragLaw};
use couple::config::{DragSettings, Forces};
use couple::exchange::{exchange, exchange_with, Exchange, Outside};
use couple::forces::{couplings_and_exchange, particle_couplings, ForceSet};
use couple::memory::{MemoryFluid, MemoryParticles};
use couple::{
    CoupleError, Coupler, CouplerSettings, FluidState, Interpolation, ParticleState, Physics,
    Placement,
};
use mesh::build::{hex_grid, uniform_box};
use mesh::v3::V3;
use voidage::{MeshOptions, Method, ParticleSet, VoidageMesh};

const THREADS: [usize; 4] = [1, 2, 3, 8];

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// A deterministic cloud over [−0.05, 1.05]³: some particles straddle the boundary of the unit
/// cube, some lie outside.
struct Cloud {
    pos: Vec<V3>,
    rad: Vec<f64>,
    vel: Vec<V3>,
    ids: Vec<u64>,
    den: Vec<f64>,
}

impl Cloud {
    /// The cloud as a particle side shows it (ids 1…N, density 2500 kg/m³).
    fn state(&self) -> ParticleState<'_> {
        ParticleState {
            temperature: None,
            ids: &self.ids,
            position: &self.pos,
            velocity: &self.vel,
            radius: &self.rad,
            density: &self.den,
        }
    }
}

fn cloud(n: usize) -> Cloud {
    let phi = 1.324_717_957_244_746_f64;
    let alpha = V3::new(1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi));
    Cloud {
        pos: (0..n)
            .map(|k| alpha.map(|a| -0.05 + 1.1 * (0.5 + k as f64 * a).fract()))
            .collect(),
        rad: (0..n)
            .map(|k| 0.01 + 0.02 * ((k * 7919) % 101) as f64 / 100.0)
            .collect(),
        vel: (0..n)
            .map(|k| {
                let s = k as f64;
                V3::new((s * 0.37).sin(), (s * 0.11).cos(), 0.3 - (s * 0.05).sin())
            })
            .collect(),
        ids: (1..=n as u64).collect(),
        den: vec![2500.0; n],
    }
}

fn place(vm: &VoidageMesh, m: Method, c: &Cloud) -> (Placement, Vec<f64>) {
    let mut centre = vec![None; c.pos.len()];
    let (shares, dep) = vm
        .shares_with_cells(m, &ParticleSet::new(&c.pos, &c.rad), &mut centre)
        .unwrap();
    let eps = vm.voidage(&dep, None).unwrap().epsilon;
    (Placement { centre, shares }, eps)
}

/// The two meshes: a graded axis-aligned grid (closed-form kernels) and the same grid
/// through the general polyhedral path.
fn meshes() -> Vec<VoidageMesh> {
    let xs = mesh::build::graded_planes(0.0, 1.0, 13, 1.3);
    let ys = mesh::build::graded_planes(0.0, 1.0, 9, 0.8);
    let zs = mesh::build::graded_planes(0.0, 1.0, 11, 1.0);
    let grid = hex_grid(&xs, &ys, &zs);
    vec![
        VoidageMesh::new(&grid).unwrap(),
        VoidageMesh::with_options(
            &grid,
            MeshOptions {
                axis_aligned_fast_path: false,
            },
        )
        .unwrap(),
    ]
}

/// The exchange fields by a serial loop over the particles (ADR 0004).
fn serial_exchange(
    p: &Placement,
    vols: &[f64],
    beta: &[f64],
    vel: &[V3],
    force: &[V3],
) -> Exchange {
    let n = vols.len();
    let (mut ksl, mut bv, mut f) = (
        vec![0.0; n],
        vec![V3::repeat(0.0); n],
        vec![V3::repeat(0.0); n],
    );
    let mut outside = Outside::default();
    for i in 0..p.len() {
        let (cells, shares) = p.shares.of(i);
        if cells.is_empty() {
            outside.particles += 1;
            outside.beta += beta[i];
            for a in 0..3 {
                outside.force[a] += force[i][a];
            }
            continue;
        }
        let inv = 1.0 / shares.iter().sum::<f64>();
        for (&c, &v) in cells.iter().zip(shares) {
            let (c, w) = (c as usize, v * inv);
            ksl[c] += w * beta[i];
            for a in 0..3 {
                bv[c][a] += w * beta[i] * vel[i][a];
                f[c][a] -= w * force[i][a];
            }
        }
    }
    let us = (0..n)
        .map(|c| {
            if ksl[c] != 0.0 {
                bv[c].map(|x| x / ksl[c])
            } else {
                V3::repeat(0.0)
            }
        })
        .collect();
    Exchange {
        ksl: (0..n).map(|c| ksl[c] * (1.0 / vols[c])).collect(),
        us,
        f: (0..n).map(|c| f[c].map(|x| x * (1.0 / vols[c]))).collect(),
        outside,
        cfdem: None,
    }
}

#[test]
fn exchange_equals_a_serial_loop_with_any_thread_count() {
    let c = cloud(30_000);
    let beta: Vec<f64> = c.rad.iter().map(|r| 1e3 * r + 0.25).collect();
    let force: Vec<V3> = c.vel.iter().map(|v| V3::new(v[2], v[0], -v[1])).collect();
    for vm in meshes() {
        let vols = vm.cell_volumes();
        // Graded meshes: every method but trilinear (uniform grids only).
        for m in Method::ANY_MESH {
            let (p, _) = place(&vm, m, &c);
            let reference = serial_exchange(&p, vols, &beta, &c.vel, &force);
            assert!(reference.outside.particles > 0 && reference.outside.particles < p.len());
            for t in THREADS {
                let ex = in_pool(t, || exchange(&p, vols, &beta, &c.vel, &force));
                assert!(ex == reference, "{m}, {t} threads");
            }
        }
    }
}

#[test]
fn exchange_of_many_particles_on_few_cells() {
    // 20 000 particles in 4 cells: every cell range holds thousands of entries from every
    // block of particles.
    let vm = VoidageMesh::new(&uniform_box(V3::repeat(0.0), V3::repeat(1.0), [2, 2, 1])).unwrap();
    let c = cloud(20_000);
    let beta = vec![2.0; c.pos.len()];
    let (p, _) = place(&vm, Method::Exact, &c);
    let reference = serial_exchange(&p, vm.cell_volumes(), &beta, &c.vel, &c.vel);
    for t in THREADS {
        let ex = in_pool(t, || exchange(&p, vm.cell_volumes(), &beta, &c.vel, &c.vel));
        assert!(ex == reference, "{t} threads");
    }
}

const RHO: f64 = 1.2;
const NU: f64 = 1.5e-5;
const G: V3 = V3::new(0.0, 0.0, -9.81);

fn physics(rules: [Interpolation; 3], model: ModelType, law: DragLaw) -> Physics {
    Physics {
        rho: RHO,
        nu: NU,
        gravity: G,
        model,
        forces: Forces {
            drag: Some(DragSettings {
                closure: DragClosure::new(law, 0.3).unwrap(),
                interpolation: rules[0],
                implicit_dem: true,
                explicit_fluid: false,
                dem_only: false,
            }),
            grad_p: Some(rules[1]),
            viscous: Some(rules[2]),
            archimedes: true,
            no_drag: None,
            ..Forces::default()
        },
        implicit_couple: true,
    }
}

/// Cell fields varying in space, so every interpolation rule gives other numbers.
struct Fluid {
    u: Vec<V3>,
    p: Vec<f64>,
    grad_p: Vec<V3>,
    div_tau: Vec<V3>,
}

fn fluid(vm: &VoidageMesh) -> Fluid {
    let x = &vm.geometry().cell_centres;
    Fluid {
        u: x.iter()
            .map(|c| V3::new(c[1], -c[0], 0.5 + c[2] * c[2]))
            .collect(),
        p: x.iter().map(|c| c[2]).collect(),
        grad_p: x.iter().map(|c| V3::new(c[0] * c[1], 1.0, c[2])).collect(),
        div_tau: x
            .iter()
            .map(|c| V3::new(0.1 * c[2], c[0] - c[1], 0.0))
            .collect(),
    }
}

fn state(f: &Fluid) -> FluidState<'_> {
    FluidState {
        vorticity: None,
        ddt_u: None,
        turbulence: None,
        temperature: None,
        u: &f.u,
        p: &f.p,
        grad_p: &f.grad_p,
        div_tau: &f.div_tau,
    }
}

#[test]
fn couplings_are_the_laws_at_the_interpolated_fields() {
    use Interpolation::{Cell, Smooth};
    let c = cloud(3000);
    let particles = c.state();
    let vm = &meshes()[0];
    let fl = fluid(vm);
    for m in [Method::Centre, Method::Exact] {
        let (p, eps) = place(vm, m, &c);
        for rules in [
            [Cell, Cell, Cell],
            [Smooth, Smooth, Smooth],
            [Smooth, Cell, Smooth],
            [Cell, Smooth, Cell],
        ] {
            for (model, law) in [
                (ModelType::A, DragLaw::KochHill),
                (ModelType::BFull, DragLaw::GIDASPOW),
            ] {
                let ph = physics(rules, model, law);
                let set = particle_couplings(&ph, &p, &state(&fl), &eps, &particles);
                let mut outside = 0;
                for i in 0..p.len() {
                    let got = set.particles[i];
                    let Some(u) = p.value_at(&fl.u, i, rules[0]) else {
                        outside += 1;
                        assert_eq!(got, Default::default(), "outside particle {i}");
                        continue;
                    };
                    let e = p.value_at(&eps, i, rules[0]).unwrap();
                    let at = FluidAtParticle {
                        u,
                        grad_p: p.value_at(&fl.grad_p, i, rules[1]).unwrap(),
                        div_tau: p.value_at(&fl.div_tau, i, rules[2]).unwrap(),
                        voidage: e.clamp(0.3, 1.0),
                        rho: RHO,
                    };
                    let d = 2.0 * c.rad[i];
                    let slip = (u - c.vel[i]).norm();
                    let beta = DragClosure::new(law, 0.3).unwrap().beta(&DragInput::new(
                        e,
                        d,
                        slip,
                        RHO,
                        NU * RHO,
                    ));
                    let r = c.rad[i];
                    let volume = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
                    let f = particle_forces(model, beta, volume, &at, c.vel[i], G);
                    assert_eq!(got.u_f, u, "{m} {rules:?} {i}");
                    assert_eq!(got.beta_dem, f.beta, "{m} {rules:?} {i}");
                    assert_eq!(got.beta_fluid, f.beta, "{m} {rules:?} {i}");
                    assert_eq!(got.f_ext, f.explicit, "{m} {rules:?} {i}");
                    assert_eq!(got.f_fluid, f.explicit_coupled, "{m} {rules:?} {i}");
                    assert_eq!(got.total, f.total(), "{m} {rules:?} {i}");
                }
                assert!(outside > 0 && outside < p.len());
                assert_eq!(set.outside, outside);
            }
        }
    }
}

#[test]
fn pipeline_equals_forces_then_exchange_with_any_thread_count() {
    // 70 000 particles: three stages of the pipeline.
    let c = cloud(70_000);
    let particles = c.state();
    let grid = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [20, 20, 20]);
    let vm = VoidageMesh::new(&grid).unwrap();
    let fl = fluid(&vm);
    let vols = vm.cell_volumes();
    for (m, model) in [
        (Method::Centre, ModelType::A),
        (Method::Exact, ModelType::BFull),
    ] {
        let ph = physics([Interpolation::Smooth; 3], model, DragLaw::KochHill);
        let (p, eps) = place(&vm, m, &c);
        let set = particle_couplings(&ph, &p, &state(&fl), &eps, &particles);
        let ex = exchange_with(&p, vols, |i| {
            let k = &set.particles[i];
            (k.beta_fluid, c.vel[i], k.f_fluid)
        });
        assert!(set.outside > 0 && ex.outside.particles == set.outside);
        for t in THREADS {
            let (set_t, ex_t) = in_pool(t, || {
                couplings_and_exchange(
                    &ph,
                    &p,
                    &state(&fl),
                    &eps,
                    &particles,
                    vols,
                    Vec::new(),
                    None,
                )
            });
            assert!(set_t == set, "{m}, {t} threads: couplings");
            assert!(ex_t == ex, "{m}, {t} threads: exchange");
        }
        // Into a recycled vector holding other couplings, longer and shorter than needed.
        for len in [100_000, 10] {
            let garbage = vec![set.particles[1]; len];
            let (set_r, ex_r) =
                couplings_and_exchange(&ph, &p, &state(&fl), &eps, &particles, vols, garbage, None);
            assert!(set_r == set && ex_r == ex, "{m}: recycled {len}");
        }
    }
}

#[test]
fn coupler_exchange_does_not_depend_on_the_thread_count() {
    let c = cloud(20_000);
    let particles = c.state();
    let grid = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [20, 20, 20]);
    let fl = fluid(&VoidageMesh::new(&grid).unwrap());
    let settings = CouplerSettings {
        method: Method::Exact,
        alpha_min: Some(0.4),
        coupling_interval: 1,
        physics: physics([Interpolation::Smooth; 3], ModelType::A, DragLaw::KochHill),
        heat: None,
    };
    let run = |t| {
        in_pool(t, || {
            let step = Coupler::new(&grid, settings)
                .unwrap()
                .exchange(&particles, &state(&fl))
                .unwrap();
            (step.forces, step.exchange, step.voidage.epsilon)
        })
    };
    let one: (ForceSet, Exchange, Vec<f64>) = run(1);
    for t in [2, 3, 8] {
        assert!(run(t) == one, "{t} threads");
    }
}

#[test]
fn recycled_steps_equal_fresh_steps() {
    let grid = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [6, 6, 6]);
    let settings = CouplerSettings {
        method: Method::Exact,
        alpha_min: None,
        coupling_interval: 3,
        physics: physics([Interpolation::Smooth; 3], ModelType::A, DragLaw::KochHill),
        heat: None,
    };
    let mut fresh = Coupler::new(&grid, settings).unwrap();
    let mut recycling = Coupler::new(&grid, settings).unwrap();
    for n in [500, 800, 300] {
        let c = cloud(n);
        let mut p1 = MemoryParticles::new(c.pos.clone(), c.rad.clone(), 2500.0, 1e-3);
        p1.gravity = G;
        let mut p2 = p1.clone();
        let mut f1 = MemoryFluid::uniform(grid.clone(), V3::new(0.0, 0.0, 0.3));
        let mut f2 = MemoryFluid::uniform(grid.clone(), V3::new(0.0, 0.0, 0.3));
        for _ in 0..3 {
            let a = fresh.step(&mut p1, &mut f1).unwrap();
            let b = recycling.step(&mut p2, &mut f2).unwrap();
            assert!(
                a.forces == b.forces && a.exchange == b.exchange,
                "{n} particles"
            );
            assert_eq!(a.placement.centre, b.placement.centre);
            assert_eq!(a.placement.shares, b.placement.shares);
            assert!(a.deposit == b.deposit && a.voidage == b.voidage);
            recycling.recycle(b);
        }
        assert_eq!(p1.velocity, p2.velocity);
        assert!(p1.velocity.iter().any(|v| v[2] != 0.0));
    }
}

#[test]
fn the_first_bad_particle_is_named() {
    let grid = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [4, 4, 4]);
    let n = 50_000;
    let mut c = Cloud {
        pos: vec![V3::repeat(0.5); n],
        rad: vec![0.01; n],
        vel: vec![V3::repeat(0.0); n],
        ids: (0..n as u64).map(|i| 1000 + i).collect(),
        den: vec![2500.0; n],
    };
    c.den[41_234] = -1.0;
    c.vel[45_000] = V3::new(f64::NAN, 0.0, 0.0);
    c.den[30_001] = 0.0;
    c.vel[30_001][2] = f64::INFINITY;
    let fl = fluid(&VoidageMesh::new(&grid).unwrap());
    let settings = CouplerSettings {
        method: Method::Centre,
        alpha_min: None,
        coupling_interval: 1,
        physics: physics([Interpolation::Cell; 3], ModelType::A, DragLaw::KochHill),
        heat: None,
    };
    let error = |c: &Cloud, t| {
        in_pool(t, || {
            Coupler::new(&grid, settings)
                .unwrap()
                .exchange(&c.state(), &state(&fl))
                .unwrap_err()
        })
    };
    for t in THREADS {
        match error(&c, t) {
            CoupleError::Particle { index, id, message } => {
                assert_eq!((index, id), (30_001, Some(31_001)), "{t} threads");
                assert!(message.contains("non-finite velocity"), "{message}");
            }
            other => panic!("{other}"),
        }
    }
    c.den[30_001] = 2500.0;
    c.vel[30_001][2] = 0.0;
    let err = error(&c, 2).to_string();
    assert!(err.contains("41234") && err.contains("42234"), "{err}");
    assert!(err.contains("density -1"), "{err}");
}

/// The owned exchange (`couple::ranks`, `Coupler::set_owners`) of two coupler ranks, run as
/// two threads with test doubles of the MPI ranks and of the solver ranks owning the cells,
/// against one dense coupler holding every particle: the same forces, ε, exchange fields,
/// accounting and clipping statistics, up to the order of the per-cell sums (round-off); with
/// heat also the same q per particle, Tsource per cell and heat account.
mod owned {
    use super::*;
    use couple::ksl::{form_cfdem, CfdemKsl, CfdemSums, KslForm, UsAveraging};
    use couple::ranks::{owner_reply_width, owner_sums_width, CellOwners, Ranks};
    use couple::SideError;
    use foam::Label;
    use std::sync::{Arc, Barrier, Mutex};

    const RANKS: usize = 2;

    /// The fields an owner formed: ε, Ksl, Us, f and Tsource (dense; Tsource 0 without heat).
    type Formed = (Vec<f64>, Vec<f64>, Vec<V3>, Vec<V3>, Vec<f64>);

    /// What the threads share: a barrier and one slot per rank for each exchange.
    struct Shared {
        barrier: Barrier,
        reduce: Mutex<Vec<Vec<f64>>>,
        cells: Mutex<Vec<Vec<Label>>>,
        solid: Mutex<Vec<Vec<f64>>>,
        sums: Mutex<Vec<Vec<f64>>>,
        formed: Mutex<Option<Formed>>,
    }

    struct ThreadRanks {
        rank: usize,
        shared: Arc<Shared>,
    }

    impl ThreadRanks {
        fn reduce(&self, x: &mut [f64], op: fn(f64, f64) -> f64) {
            self.shared.reduce.lock().unwrap()[self.rank] = x.to_vec();
            self.shared.barrier.wait();
            {
                let all = self.shared.reduce.lock().unwrap();
                for (k, v) in x.iter_mut().enumerate() {
                    *v = (1..RANKS).fold(all[0][k], |acc, r| op(acc, all[r][k]));
                }
            }
            self.shared.barrier.wait();
        }
    }

    impl Ranks for ThreadRanks {
        fn rank(&self) -> usize {
            self.rank
        }
        fn size(&self) -> usize {
            RANKS
        }
        fn sum_to_root(&mut self, _: &[Label], _: &[f64], _: usize, _: &mut [f64]) {
            panic!("the owned exchange does not sum on rank 0");
        }
        fn scatter_from_root(
            &mut self,
            _: usize,
            _: &dyn Fn(Label, &mut Vec<f64>),
            _: &mut Vec<f64>,
        ) {
            panic!("the owned exchange does not scatter from rank 0");
        }
        fn all_sum(&self, x: &mut [f64]) {
            self.reduce(x, |a, b| a + b);
        }
        fn all_max(&self, x: &mut [f64]) {
            self.reduce(x, f64::max);
        }
        fn broadcast(&self, _: &mut [f64]) {
            panic!("the owned exchange does not broadcast");
        }
        fn gather(&self, _: &[f64]) -> Vec<Vec<f64>> {
            panic!("the owned exchange does not gather");
        }
    }

    /// One solver rank owning every cell, as grainPisoFoam's sparse exchange does it
    /// (foam-link's protocol): sums in rank order, ε from the lowest rank touching a cell.
    struct ThreadOwners {
        rank: usize,
        shared: Arc<Shared>,
        fluid: Arc<Fluid>,
        /// T per cell (K) with heat on.
        temperature: Option<Arc<Vec<f64>>>,
        n_cells: usize,
        /// CFDEM's Ksl form: the records carry its sums, formed as grainPisoFoam does.
        cfdem: Option<CfdemKsl>,
    }

    impl CellOwners for ThreadOwners {
        fn deposit(&mut self, cells: &[Label], solid: &[f64]) -> Result<Vec<f64>, SideError> {
            let sh = &self.shared;
            sh.cells.lock().unwrap()[self.rank] = cells.to_vec();
            sh.solid.lock().unwrap()[self.rank] = solid.to_vec();
            sh.barrier.wait();
            let all_cells = sh.cells.lock().unwrap().clone();
            let all_solid = sh.solid.lock().unwrap().clone();
            let mut sum = vec![0.0; self.n_cells];
            let mut lowest = vec![usize::MAX; self.n_cells];
            for q in 0..RANKS {
                for (&c, &s) in all_cells[q].iter().zip(&all_solid[q]) {
                    sum[c as usize] += s;
                    lowest[c as usize] = lowest[c as usize].min(q);
                }
            }
            let f = &self.fluid;
            let mut out = Vec::new();
            for &c in cells {
                let c = c as usize;
                let (u, g, t) = (f.u[c], f.grad_p[c], f.div_tau[c]);
                let home = f64::from(u8::from(lowest[c] == self.rank));
                out.extend_from_slice(&[
                    sum[c], home, u[0], u[1], u[2], f.p[c], g[0], g[1], g[2], t[0], t[1], t[2],
                ]);
                out.extend(self.temperature.as_ref().map(|t| t[c]));
            }
            let heat = self.temperature.is_some();
            assert_eq!(out.len(), cells.len() * owner_reply_width(heat));
            sh.barrier.wait();
            Ok(out)
        }

        fn exchange(&mut self, sums: &[f64]) -> Result<(), SideError> {
            let sh = &self.shared;
            sh.sums.lock().unwrap()[self.rank] = sums.to_vec();
            sh.barrier.wait();
            if self.rank == 0 {
                let n = self.n_cells;
                let heat_w = 8 + usize::from(self.temperature.is_some());
                let width = owner_sums_width(self.temperature.is_some(), self.cfdem.is_some());
                let mut cfdem = CfdemSums::new(n, UsAveraging::Dense);
                let mut tsource = vec![0.0; n];
                let (mut eps, mut ksl) = (vec![1.0; n], vec![0.0; n]);
                let (mut kus, mut f) = (vec![V3::zeros(); n], vec![V3::zeros(); n]);
                let mut seen = vec![false; n];
                let cells = sh.cells.lock().unwrap();
                let sums = sh.sums.lock().unwrap();
                for q in 0..RANKS {
                    assert_eq!(sums[q].len(), cells[q].len() * width);
                    for (&c, s) in cells[q].iter().zip(sums[q].chunks_exact(width)) {
                        let c = c as usize;
                        if !seen[c] {
                            eps[c] = s[0];
                            seen[c] = true;
                        }
                        ksl[c] += s[1];
                        kus[c] += V3::new(s[2], s[3], s[4]);
                        f[c] += V3::new(s[5], s[6], s[7]);
                        if heat_w > 8 {
                            tsource[c] += s[8];
                        }
                        if self.cfdem.is_some() {
                            let mut rec = Vec::new();
                            cfdem.record(c, &mut rec);
                            for (a, b) in rec.iter_mut().zip(&s[heat_w..]) {
                                *a += b;
                            }
                            cfdem.set(c, &rec);
                        }
                    }
                }
                let mut us: Vec<V3> = kus
                    .iter()
                    .zip(&ksl)
                    .map(|(v, &k)| if k > 0.0 { v / k } else { V3::zeros() })
                    .collect();
                if let Some(k) = &self.cfdem {
                    let vols = VoidageMesh::new(&uniform_box(
                        V3::repeat(0.0),
                        V3::repeat(1.0),
                        [12, 12, 12],
                    ))
                    .unwrap()
                    .cell_volumes()
                    .to_vec();
                    form_cfdem(k, &cfdem, &self.fluid.u, &eps, &vols, &mut ksl, &mut us);
                }
                *sh.formed.lock().unwrap() = Some((eps, ksl, us, f, tsource));
            }
            sh.barrier.wait();
            Ok(())
        }

        fn traffic(&self) -> (u64, u64) {
            (0, 0)
        }
    }

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-12 * scale.max(f64::MIN_POSITIVE)
    }

    /// The heat of the owned tests: T per cell and per particle, K.
    struct Temperatures {
        fluid: Arc<Vec<f64>>,
        particles: Vec<f64>,
    }

    /// `settings`' exchange of the cloud `c` on [`RANKS`] threads (rank r holds the particles
    /// k with k % RANKS == r: neighbours, so many cells are shared), the cells owned by
    /// [`ThreadOwners`]; each rank's step and the fields the owners formed.
    fn owned_steps(
        c: &Cloud,
        grid: &foam::PolyMesh,
        fl: &Arc<Fluid>,
        settings: CouplerSettings,
        temps: Option<&Temperatures>,
        form: KslForm,
    ) -> (Vec<couple::CouplingStep>, Formed) {
        let n_cells = grid.n_cells;
        let shared = Arc::new(Shared {
            barrier: Barrier::new(RANKS),
            reduce: Mutex::new(vec![Vec::new(); RANKS]),
            cells: Mutex::new(vec![Vec::new(); RANKS]),
            solid: Mutex::new(vec![Vec::new(); RANKS]),
            sums: Mutex::new(vec![Vec::new(); RANKS]),
            formed: Mutex::new(None),
        });
        let steps: Vec<_> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..RANKS)
                .map(|r| {
                    let (shared, fl) = (shared.clone(), fl.clone());
                    let mine = pick_of(c, r);
                    let part = Cloud {
                        pos: mine.iter().map(|&k| c.pos[k]).collect(),
                        rad: mine.iter().map(|&k| c.rad[k]).collect(),
                        vel: mine.iter().map(|&k| c.vel[k]).collect(),
                        ids: mine.iter().map(|&k| c.ids[k]).collect(),
                        den: mine.iter().map(|&k| c.den[k]).collect(),
                    };
                    let part_temp: Option<Vec<f64>> =
                        temps.map(|t| mine.iter().map(|&k| t.particles[k]).collect());
                    let temperature = temps.map(|t| t.fluid.clone());
                    s.spawn(move || {
                        let mut coupler = Coupler::new(grid, settings).unwrap();
                        coupler.set_ksl_form(form);
                        coupler.set_ranks(Box::new(ThreadRanks {
                            rank: r,
                            shared: shared.clone(),
                        }));
                        coupler.set_owners(Box::new(ThreadOwners {
                            rank: r,
                            shared,
                            fluid: fl,
                            temperature,
                            n_cells,
                            cfdem: form.cfdem(),
                        }));
                        let empty = Fluid {
                            u: Vec::new(),
                            p: Vec::new(),
                            grad_p: Vec::new(),
                            div_tau: Vec::new(),
                        };
                        let mut state_r = part.state();
                        state_r.temperature = part_temp.as_deref();
                        coupler.exchange(&state_r, &state(&empty)).unwrap()
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        let formed = shared.formed.lock().unwrap().take().unwrap();
        (steps, formed)
    }

    /// The particles of rank `r` (indices into `c`).
    fn pick_of(c: &Cloud, r: usize) -> Vec<usize> {
        (0..c.ids.len()).filter(|k| k % RANKS == r).collect()
    }

    fn owned_settings(heat: Option<couple::HeatSettings>) -> CouplerSettings {
        CouplerSettings {
            method: Method::Exact,
            // high enough that some cells clip: the statistics must count each cell once
            alpha_min: Some(0.9),
            coupling_interval: 1,
            physics: physics([Interpolation::Smooth; 3], ModelType::A, DragLaw::KochHill),
            heat,
        }
    }

    #[test]
    fn two_ranks_with_the_cells_elsewhere_equal_one_dense_rank() {
        let c = cloud(6000);
        let grid = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [12, 12, 12]);
        let fl = Arc::new(fluid(&VoidageMesh::new(&grid).unwrap()));
        let settings = owned_settings(None);
        let reference = Coupler::new(&grid, settings)
            .unwrap()
            .exchange(&c.state(), &state(&fl))
            .unwrap();
        assert!(reference.voidage.clipped_cells > 0);
        let n_cells = grid.n_cells;
        let (steps, formed) = owned_steps(&c, &grid, &fl, settings, None, KslForm::Conserving);
        for (r, step) in steps.iter().enumerate() {
            assert!(step.heat.is_none());
            for (j, &k) in pick_of(&c, r).iter().enumerate() {
                let (a, b) = (&step.forces.particles[j], &reference.forces.particles[k]);
                let scale = b.total.norm();
                for d in 0..3 {
                    assert!(
                        close(a.total[d], b.total[d], scale),
                        "particle {k}: {a:?} vs {b:?}"
                    );
                    assert!(close(a.f_ext[d], b.f_ext[d], scale), "particle {k}");
                }
                assert!(close(a.beta_dem, b.beta_dem, b.beta_dem), "particle {k}");
            }
            let (d, e) = (&step.deposit, &reference.deposit);
            assert_eq!(d.particles, e.particles);
            assert!(close(
                d.particle_volume,
                e.particle_volume,
                e.particle_volume
            ));
            assert!(close(d.outside_volume, e.outside_volume, e.particle_volume));
            let (v, w) = (&step.voidage, &reference.voidage);
            assert!(v.epsilon.is_empty(), "no rank holds the whole ε");
            assert_eq!(
                (v.clipped_cells, v.negative_cells),
                (w.clipped_cells, w.negative_cells)
            );
            assert!(close(v.clipped_volume, w.clipped_volume, w.clipped_volume));
            assert!(close(v.min_epsilon, w.min_epsilon, 1.0));
        }
        let (eps, ksl, us, f, tsource) = formed;
        assert!(tsource.iter().all(|&x| x == 0.0), "no heat, no source");
        let e = &reference.exchange;
        let kmax = e.ksl.iter().cloned().fold(0.0, f64::max);
        let fmax = e.f.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for cell in 0..n_cells {
            assert!(
                close(eps[cell], reference.voidage.epsilon[cell], 1.0),
                "ε of cell {cell}"
            );
            assert!(close(ksl[cell], e.ksl[cell], kmax), "Ksl of cell {cell}");
            for d in 0..3 {
                assert!(close(us[cell][d], e.us[cell][d], 1.0), "Us of cell {cell}");
                assert!(close(f[cell][d], e.f[cell][d], fmax), "f of cell {cell}");
            }
        }
        assert!(
            e.outside.particles > 0,
            "the cloud has particles outside the mesh"
        );
        assert_eq!(steps[0].exchange.outside.particles, e.outside.particles);
    }

    /// CFDEM's Ksl form (`couple::ksl`): the ranks' sums carry Σ w F, Σ w, Σ w v and the
    /// owners form Ksl and Us from them (as grainPisoFoam does, here with the coupler's own
    /// `form_cfdem`); equal to the one dense rank with CFDEM's form to 1e-12, and different from
    /// the conserving form (the cloud's velocities differ within a cell).
    #[test]
    fn two_ranks_with_the_cells_elsewhere_and_cfdem_ksl_equal_one_dense_rank() {
        let c = cloud(6000);
        let grid = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [12, 12, 12]);
        let fl = Arc::new(fluid(&VoidageMesh::new(&grid).unwrap()));
        let settings = owned_settings(None);
        let form = KslForm::Cfdem(CfdemKsl::default());
        let mut dense = Coupler::new(&grid, settings).unwrap();
        dense.set_ksl_form(form);
        let reference = dense.exchange(&c.state(), &state(&fl)).unwrap();
        let conserving = Coupler::new(&grid, settings)
            .unwrap()
            .exchange(&c.state(), &state(&fl))
            .unwrap();
        let (_, formed) = owned_steps(&c, &grid, &fl, settings, None, form);
        let (_, ksl, us, _, _) = formed;
        let e = &reference.exchange;
        let kmax = e.ksl.iter().cloned().fold(0.0, f64::max);
        let mut differ = 0;
        for cell in 0..grid.n_cells {
            assert!(close(ksl[cell], e.ksl[cell], kmax), "Ksl of cell {cell}");
            for d in 0..3 {
                assert!(close(us[cell][d], e.us[cell][d], 1.0), "Us of cell {cell}");
            }
            if (e.ksl[cell] - conserving.exchange.ksl[cell]).abs() > 1e-6 * kmax {
                differ += 1;
            }
        }
        // (408 of the 1728 cells differ here: those the cloud reaches)
        assert!(differ > 100, "{differ} cells differ");
    }

    /// With heat (PFM's `heatTransferGunn`: Gunn's Nu of ε and the superficial Re, ε floored
    /// at 0.95 so that both branches of the floor occur; smooth interpolation of U, T and ε):
    /// each rank's q per particle, the Tsource the owners sum from the ranks' shares, and the
    /// heat account summed over the ranks equal the one-rank heat step (fluid on rank 0) to
    /// 1e-12.
    #[test]
    fn two_ranks_with_the_cells_elsewhere_and_heat_equal_one_dense_rank() {
        use closures::heat::{Nusselt, ReynoldsVelocity};
        use couple::config::HeatModel;
        let c = cloud(6000);
        let grid = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [12, 12, 12]);
        let vm = VoidageMesh::new(&grid).unwrap();
        let fl = Arc::new(fluid(&vm));
        let temps = Temperatures {
            fluid: Arc::new(
                vm.geometry()
                    .cell_centres
                    .iter()
                    .map(|x| 300.0 + 100.0 * x[0] + 50.0 * x[1] * x[2])
                    .collect(),
            ),
            particles: (0..c.ids.len())
                .map(|k| 350.0 + 200.0 * (k as f64 * 0.71).sin())
                .collect(),
        };
        let heat = couple::HeatSettings {
            model: HeatModel::HeatTransferGunn,
            nusselt: Nusselt::Gunn,
            reynolds: ReynoldsVelocity::Superficial,
            voidage_floor: 0.95,
            nusselt_scale: 1.0,
            lambda: 0.0256,
            cp: 1007.0,
            prandtl: None,
            max_source: None,
            interpolation: Interpolation::Smooth,
        };
        let settings = owned_settings(Some(heat));
        let mut all = c.state();
        all.temperature = Some(&temps.particles);
        let mut whole = state(&fl);
        whole.temperature = Some(&temps.fluid);
        let reference = Coupler::new(&grid, settings)
            .unwrap()
            .exchange(&all, &whole)
            .unwrap();
        let h = reference.heat.as_ref().unwrap();
        let (steps, formed) =
            owned_steps(&c, &grid, &fl, settings, Some(&temps), KslForm::Conserving);
        let qmax = h.q.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!(qmax > 0.0);
        for (r, step) in steps.iter().enumerate() {
            let sh = step.heat.as_ref().expect("heat on every rank");
            assert!(sh.tsource.is_empty(), "the owners hold Tsource");
            let mine = pick_of(&c, r);
            assert_eq!(sh.q.len(), mine.len());
            for (j, &k) in mine.iter().enumerate() {
                assert!(
                    close(sh.q[j], h.q[k], qmax),
                    "q of particle {k}: {} vs {}",
                    sh.q[j],
                    h.q[k]
                );
            }
            let (a, b) = (&sh.account, &h.account);
            let scale = b.to_particles.abs().max(b.from_fluid.abs());
            assert!(
                close(a.to_particles, b.to_particles, scale),
                "{a:?} vs {b:?}"
            );
            assert!(close(a.from_fluid, b.from_fluid, scale), "{a:?} vs {b:?}");
            assert!(close(a.imbalance, 0.0, scale), "{a:?}");
            assert_eq!(a.particles_outside, b.particles_outside);
            assert!(b.particles_outside > 0, "the cloud has particles outside");
            assert_eq!((a.clipped, a.clipped_cells), (0.0, 0));
        }
        let tsource = formed.4;
        let tmax = h.tsource.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!(tmax > 0.0);
        for cell in 0..grid.n_cells {
            assert!(
                close(tsource[cell], h.tsource[cell], tmax),
                "Tsource of cell {cell}: {} vs {}",
                tsource[cell],
                h.tsource[cell]
            );
        }
    }
}
