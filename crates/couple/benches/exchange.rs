//! Throughput of the coupling core in particles/s: 10⁶ particles (radius 0.004, centres spread
//! uniformly by Roberts' R3 sequence, so consecutive particles are far apart) on a
//! 50×50×40 = 10⁵-cell axis-aligned grid of the unit cube (h/d ≈ 2.5–3), Koch–Hill drag with
//! gradP, viscous and Archimedes forces, model A, smooth interpolation.
//! * `forces_exchange`: per-particle forces + Ksl/Us/f from given shares, as the coupler does
//!   them per step besides the voidage ([`couplings_and_exchange`], the couplings written into
//!   the recycled vector of the previous call, as [`Coupler::run`] does);
//! * `forces_exchange_fresh`: the same into fresh memory every call (what a caller that does
//!   not [`Coupler::recycle`] pays: the 112 MB of couplings are page-faulted in anew);
//! * `forces`, `exchange`: the two parts on their own (fresh output; the exchange of given
//!   couplings is one in-order pass);
//! * `coupling_step`: the whole [`Coupler::exchange`] (locate, shares and voidage, forces,
//!   exchange), steps recycled.
//!
//! Run: `cargo bench -p couple` (uses every core rayon sees; the target is ≥ 5·10⁶/s on 2).
//!
//! Where the time goes (perf and per-phase CPU time, 10⁶ particles, centre, one core, AMD EPYC
//! VM shared with other builds): the force kernel ≈ 35 ns per particle (a third of it waiting on
//! the cell fields at random cells, Koch–Hill ≈ 6 ns), the in-order exchange sums ≈ 12 ns,
//! writing the 112-byte couplings ≈ 6 ns. Fresh output memory adds ≈ 55 ns per particle of
//! kernel page-fault time (`forces_exchange_fresh`); recycling removes it. The shares and
//! locate of `coupling_step` cost ≈ 45 ns (centre) and ≈ 250 ns (exact, the ball ∩ box
//! kernel) per particle.

use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use couple::config::{DragSettings, Forces};
use couple::exchange::exchange_with;
use couple::forces::{couplings_and_exchange, particle_couplings};
use couple::{
    Coupler, CouplerSettings, FluidState, Interpolation, ParticleState, Physics, Placement,
};
use divan::counter::ItemsCount;
use mesh::v3::V3;
use std::sync::OnceLock;
use voidage::{Method, ParticleSet, VoidageMesh};

const N: usize = 1_000_000;

fn main() {
    divan::main();
}

struct Data {
    mesh: foam::PolyMesh,
    ids: Vec<u64>,
    pos: Vec<V3>,
    vel: Vec<V3>,
    rad: Vec<f64>,
    den: Vec<f64>,
    u: Vec<V3>,
    p: Vec<f64>,
    gp: Vec<V3>,
    dt: Vec<V3>,
}

fn data() -> &'static Data {
    static D: OnceLock<Data> = OnceLock::new();
    D.get_or_init(|| {
        let mesh = mesh::build::uniform_box(V3::repeat(0.0), V3::repeat(1.0), [50, 50, 40]);
        let phi = 1.324_717_957_244_746_f64;
        let alpha = V3::new(1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi));
        let pos: Vec<V3> = (0..N)
            .map(|k| alpha.map(|a| 0.004 + 0.992 * (0.5 + k as f64 * a).fract()))
            .collect();
        let vel = pos
            .iter()
            .map(|x| V3::new(0.01 * x[1], 0.0, -0.02 * x[0]))
            .collect();
        let n = mesh.n_cells;
        Data {
            ids: (1..=N as u64).collect(),
            rad: vec![0.004; N],
            den: vec![2500.0; N],
            vel,
            pos,
            u: vec![V3::new(0.0, 0.0, 0.1); n],
            p: vec![0.0; n],
            gp: vec![V3::new(0.0, 0.0, -0.5); n],
            dt: vec![V3::new(0.01, 0.0, 0.0); n],
            mesh,
        }
    })
}

fn physics() -> Physics {
    Physics {
        rho: 1.2,
        nu: 1.5e-5,
        gravity: V3::new(0.0, 0.0, -9.81),
        model: ModelType::A,
        forces: Forces {
            drag: Some(DragSettings {
                closure: DragClosure::from(DragLaw::KochHill),
                interpolation: Interpolation::Smooth,
                implicit_dem: true,
                explicit_fluid: false,
                dem_only: false,
            }),
            grad_p: Some(Interpolation::Smooth),
            viscous: Some(Interpolation::Smooth),
            archimedes: true,
            no_drag: None,
            ..Forces::default()
        },
        implicit_couple: true,
    }
}

fn particles(d: &Data) -> ParticleState<'_> {
    ParticleState {
        temperature: None,
        ids: &d.ids,
        position: &d.pos,
        velocity: &d.vel,
        radius: &d.rad,
        density: &d.den,
    }
}

fn fluid(d: &Data) -> FluidState<'_> {
    FluidState {
        vorticity: None,
        ddt_u: None,
        turbulence: None,
        temperature: None,
        u: &d.u,
        p: &d.p,
        grad_p: &d.gp,
        div_tau: &d.dt,
    }
}

fn method(name: &str) -> Method {
    name.parse().unwrap()
}

/// The placement, voidage and cell volumes of the benchmark's particles with method `name`.
fn placed(name: &str) -> (Placement, Vec<f64>, Vec<f64>) {
    let d = data();
    let vm = VoidageMesh::new(&d.mesh).unwrap();
    let mut centre = vec![None; N];
    let (shares, dep) = vm
        .shares_with_cells(method(name), &ParticleSet::new(&d.pos, &d.rad), &mut centre)
        .unwrap();
    let eps = vm.voidage(&dep, None).unwrap().epsilon;
    (
        Placement { centre, shares },
        eps,
        vm.cell_volumes().to_vec(),
    )
}

#[divan::bench(args = ["centre", "exact"], sample_count = 5, sample_size = 1)]
fn forces(bencher: divan::Bencher, name: &str) {
    let d = data();
    let (placement, eps, _) = placed(name);
    let ph = physics();
    bencher
        .counter(ItemsCount::new(N))
        .bench(|| particle_couplings(&ph, &placement, &fluid(d), &eps, &particles(d)));
}

#[divan::bench(args = ["centre", "exact"], sample_count = 5, sample_size = 1)]
fn exchange(bencher: divan::Bencher, name: &str) {
    let d = data();
    let (placement, eps, vols) = placed(name);
    let f = particle_couplings(&physics(), &placement, &fluid(d), &eps, &particles(d));
    bencher.counter(ItemsCount::new(N)).bench(|| {
        exchange_with(&placement, &vols, |i| {
            let c = &f.particles[i];
            (c.beta_fluid, d.vel[i], c.f_fluid)
        })
    });
}

#[divan::bench(args = ["centre", "exact"], sample_count = 5, sample_size = 1)]
fn forces_exchange(bencher: divan::Bencher, name: &str) {
    pipeline(bencher, name, true);
}

#[divan::bench(args = ["centre", "exact"], sample_count = 5, sample_size = 1)]
fn forces_exchange_fresh(bencher: divan::Bencher, name: &str) {
    pipeline(bencher, name, false);
}

/// [`couplings_and_exchange`] on the benchmark's particles placed by method `name`, writing
/// into the couplings of the previous call when `recycle` is set, into fresh memory otherwise.
fn pipeline(bencher: divan::Bencher, name: &str, recycle: bool) {
    let d = data();
    let (placement, eps, vols) = placed(name);
    let ph = physics();
    let run = |reuse| {
        couplings_and_exchange(
            &ph,
            &placement,
            &fluid(d),
            &eps,
            &particles(d),
            &vols,
            reuse,
            None,
        )
    };
    let mut spare = run(Vec::new()).0.particles;
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        let reuse = if recycle {
            std::mem::take(&mut spare)
        } else {
            Vec::new()
        };
        let (set, exchange) = run(reuse);
        if recycle {
            spare = set.particles;
        }
        exchange
    });
}

#[divan::bench(args = ["centre", "exact"], sample_count = 3, sample_size = 1)]
fn coupling_step(bencher: divan::Bencher, name: &str) {
    let d = data();
    let settings = CouplerSettings {
        method: method(name),
        alpha_min: None,
        coupling_interval: 1,
        physics: physics(),
        heat: None,
    };
    let mut coupler = Coupler::new(&d.mesh, settings).unwrap();
    let first = coupler.exchange(&particles(d), &fluid(d)).unwrap();
    coupler.recycle(first);
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        let step = coupler.exchange(&particles(d), &fluid(d)).unwrap();
        let n = step.exchange.ksl.len();
        coupler.recycle(step);
        n
    });
}
