//! The coupler's heat transfer (`couple::heat`, CFDEM's `LaEuScalarTemp`):
//! * the heat account closes to round-off on a random bed, with divided and exact voidage,
//!   both interpolation rules and with `maxSource` cutting sources (Σ_c Tsource ρ c_p V summed
//!   here from the fields handed over, not from the account);
//! * one sphere in a uniform stream gets q = h A ΔT with h from Li & Mason evaluated by hand,
//!   and the sides receive it (q to the particles, Tsource to the fluid);
//! * two coupler ranks (threads, the fluid on rank 0) give the one-rank result;
//! * heat on with a side without temperature is an error saying what the case needs, and
//!   `maxSource` with the cells' owners elsewhere (several coupler ranks with grainPisoFoam)
//!   is refused;
//! * without heat nothing is handed over.

use closures::heat::{Nusselt, ReynoldsVelocity};
use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use couple::config::{DragSettings, Forces, HeatModel, HeatSettings, MaxSource};
use couple::heat::HeatStep;
use couple::memory::{MemoryFluid, MemoryParticles};
use couple::ranks::Ranks;
use couple::{
    Coupler, CouplerSettings, CouplingStep, FluidSide, FluidState, Interpolation, ParticleState,
    Physics,
};
use foam::{Label, PolyMesh};
use mesh::build::uniform_box;
use mesh::v3::V3;
use std::sync::{Arc, Barrier, Mutex};
use voidage::Method;

const RHO: f64 = 1.2;
const NU: f64 = 1e-5;
const LAMBDA: f64 = 0.0256;
const CP: f64 = 1007.0;

fn heat(interpolation: Interpolation, max_source: Option<f64>) -> HeatSettings {
    HeatSettings {
        model: HeatModel::LaEuScalarTemp,
        nusselt: Nusselt::LiMason,
        reynolds: ReynoldsVelocity::Interstitial,
        voidage_floor: 0.0,
        nusselt_scale: 1.0,
        lambda: LAMBDA,
        cp: CP,
        prandtl: None,
        max_source: max_source.map(MaxSource::KelvinPerSecond),
        interpolation,
    }
}

fn settings(method: Method, heat: Option<HeatSettings>) -> CouplerSettings {
    CouplerSettings {
        method,
        alpha_min: None,
        coupling_interval: 1,
        physics: Physics {
            rho: RHO,
            nu: NU,
            gravity: V3::zeros(),
            model: ModelType::A,
            forces: Forces {
                drag: Some(DragSettings {
                    closure: DragClosure::new(DragLaw::KochHill, 0.3).unwrap(),
                    interpolation: Interpolation::Smooth,
                    implicit_dem: true,
                    explicit_fluid: false,
                    dem_only: false,
                }),
                ..Forces::default()
            },
            implicit_couple: true,
        },
        heat,
    }
}

/// A deterministic bed over [−0.02, 1.02]³ (some particles straddle the boundary, a few lie
/// outside) with varying velocities and temperatures.
struct Bed {
    pos: Vec<V3>,
    rad: Vec<f64>,
    vel: Vec<V3>,
    ids: Vec<u64>,
    den: Vec<f64>,
    temp: Vec<f64>,
}

impl Bed {
    fn state(&self) -> ParticleState<'_> {
        ParticleState {
            ids: &self.ids,
            position: &self.pos,
            velocity: &self.vel,
            radius: &self.rad,
            density: &self.den,
            temperature: Some(&self.temp),
        }
    }

    fn part(&self, keep: impl Fn(usize) -> bool) -> Bed {
        let k: Vec<usize> = (0..self.ids.len()).filter(|&i| keep(i)).collect();
        Bed {
            pos: k.iter().map(|&i| self.pos[i]).collect(),
            rad: k.iter().map(|&i| self.rad[i]).collect(),
            vel: k.iter().map(|&i| self.vel[i]).collect(),
            ids: k.iter().map(|&i| self.ids[i]).collect(),
            den: k.iter().map(|&i| self.den[i]).collect(),
            temp: k.iter().map(|&i| self.temp[i]).collect(),
        }
    }
}

fn bed(n: usize) -> Bed {
    let phi = 1.324_717_957_244_746_f64;
    let a = V3::new(1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi));
    Bed {
        pos: (0..n)
            .map(|k| a.map(|x| -0.02 + 1.04 * (0.5 + k as f64 * x).fract()))
            .collect(),
        rad: (0..n)
            .map(|k| 0.01 + 0.015 * ((k * 7919) % 101) as f64 / 100.0)
            .collect(),
        vel: (0..n)
            .map(|k| V3::new((k as f64 * 0.37).sin(), 0.1, -0.2))
            .collect(),
        ids: (1..=n as u64).collect(),
        den: vec![2500.0; n],
        temp: (0..n)
            .map(|k| 350.0 + 200.0 * (k as f64 * 0.71).sin())
            .collect(),
    }
}

/// Cell fields varying in space: U, p, ∇p, ∇·τ and T.
struct Fluid {
    u: Vec<V3>,
    zero: Vec<V3>,
    p: Vec<f64>,
    t: Vec<f64>,
}

fn fluid(mesh: &PolyMesh) -> Fluid {
    let vm = voidage::VoidageMesh::new(mesh).unwrap();
    let x = &vm.geometry().cell_centres;
    Fluid {
        u: x.iter()
            .map(|c| V3::new(c[1], -c[0], 0.5 + c[2] * c[2]))
            .collect(),
        zero: vec![V3::zeros(); x.len()],
        p: vec![0.0; x.len()],
        t: x.iter().map(|c| 300.0 + 100.0 * c[0] * c[2]).collect(),
    }
}

fn state(f: &Fluid) -> FluidState<'_> {
    FluidState {
        vorticity: None,
        ddt_u: None,
        turbulence: None,
        u: &f.u,
        p: &f.p,
        grad_p: &f.zero,
        div_tau: &f.zero,
        temperature: Some(&f.t),
    }
}

fn cell_volumes(mesh: &PolyMesh) -> Vec<f64> {
    voidage::VoidageMesh::new(mesh)
        .unwrap()
        .cell_volumes()
        .to_vec()
}

/// Σ_c Tsource_c ρ c_p V_c from the field handed to the fluid, W.
fn fluid_heat(h: &HeatStep, volumes: &[f64]) -> f64 {
    h.tsource
        .iter()
        .zip(volumes)
        .map(|(s, v)| s * RHO * CP * v)
        .sum()
}

#[test]
fn the_heat_account_closes_on_a_random_bed() {
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [9, 8, 7]);
    let volumes = cell_volumes(&mesh);
    let b = bed(4000);
    let f = fluid(&mesh);
    for method in [Method::Divided, Method::Exact] {
        for rule in [Interpolation::Cell, Interpolation::Smooth] {
            let mut c = Coupler::new(&mesh, settings(method, Some(heat(rule, None)))).unwrap();
            let step = c.exchange(&b.state(), &state(&f)).unwrap();
            let h = step.heat.as_ref().unwrap();
            let a = h.account;
            let at = format!("{method:?} {rule:?}");
            let sum_q: f64 = h.q.iter().sum();
            let scale: f64 = h.q.iter().map(|q| q.abs()).sum();
            assert!(scale > 0.0, "{at}");
            // the particles' heat = minus the fluid's, summed here from the fields
            let given = -fluid_heat(h, &volumes);
            assert!(
                (sum_q - given).abs() <= 1e-12 * scale,
                "{at}: {sum_q} vs {given}"
            );
            assert!(a.imbalance.abs() <= 1e-12 * scale, "{at}: {a:?}");
            assert!((a.to_particles - sum_q).abs() <= 1e-12 * scale, "{at}");
            assert!((a.from_fluid - given).abs() <= 1e-12 * scale, "{at}");
            assert_eq!((a.clipped, a.clipped_cells), (0.0, 0), "{at}");
            // the particles outside the mesh get nothing and are counted
            let outside: Vec<usize> = (0..b.ids.len())
                .filter(|&i| !step.placement.inside(i))
                .collect();
            assert!(!outside.is_empty(), "{at}: the bed reaches beyond the mesh");
            assert_eq!(a.particles_outside, outside.len(), "{at}");
            assert!(outside.iter().all(|&i| h.q[i] == 0.0), "{at}");
        }
    }
}

#[test]
fn the_heat_does_not_depend_on_the_thread_count() {
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [9, 8, 7]);
    let b = bed(3000);
    let f = fluid(&mesh);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let s = settings(Method::Divided, Some(heat(Interpolation::Smooth, None)));
            let mut c = Coupler::new(&mesh, s).unwrap();
            c.exchange(&b.state(), &state(&f)).unwrap().heat.unwrap()
        })
    };
    let one = run(1);
    for t in [2, 3, 8] {
        assert_eq!(run(t), one, "{t} threads");
    }
}

#[test]
fn max_source_cuts_are_counted_and_the_account_still_closes() {
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [9, 8, 7]);
    let volumes = cell_volumes(&mesh);
    let b = bed(4000);
    let f = fluid(&mesh);
    let free = Coupler::new(
        &mesh,
        settings(Method::Exact, Some(heat(Interpolation::Cell, None))),
    )
    .unwrap()
    .exchange(&b.state(), &state(&f))
    .unwrap();
    let free = free.heat.unwrap();
    let mut sorted: Vec<f64> = free.tsource.iter().map(|s| s.abs()).collect();
    sorted.sort_by(f64::total_cmp);
    let max = sorted[sorted.len() * 3 / 4];
    let expected_cells = sorted.iter().filter(|&&s| s > max).count();
    // the heat cut, from the free sources: Σ over the cut cells of (|S| − max) sign(S) ρ c_p V
    let expected_cut: f64 = free
        .tsource
        .iter()
        .zip(&volumes)
        .filter(|(s, _)| s.abs() > max)
        .map(|(s, v)| -(s - max.copysign(*s)) * RHO * CP * v)
        .sum();
    let mut c = Coupler::new(
        &mesh,
        settings(Method::Exact, Some(heat(Interpolation::Cell, Some(max)))),
    )
    .unwrap();
    let h = c.exchange(&b.state(), &state(&f)).unwrap().heat.unwrap();
    let a = h.account;
    let scale: f64 = h.q.iter().map(|q| q.abs()).sum();
    assert!(h.tsource.iter().all(|s| s.abs() <= max));
    assert_eq!(a.clipped_cells, expected_cells);
    assert!(expected_cells > 0 && a.clipped.abs() > 0.0);
    assert!(
        (a.clipped - expected_cut).abs() <= 1e-12 * scale,
        "{a:?} vs {expected_cut}"
    );
    assert!((a.from_fluid + fluid_heat(&h, &volumes)).abs() <= 1e-12 * scale);
    assert!(a.imbalance.abs() <= 1e-12 * scale, "{a:?}");
    assert_eq!(h.q, free.q, "the cut changes the fluid's source only");
}

#[test]
fn one_sphere_in_a_uniform_stream_gets_h_a_delta_t_of_li_and_mason() {
    // d 1 mm at rest in U = 1 m/s, ν 1e-5 → Re 100; Pr = 1007·1e-5·1.2/0.0256 = 0.47203125;
    // ε = 1 − (π d³/6)/V_c with V_c = 1e-3 m³; by hand (python, Li & Mason's formula):
    // Nu = 2 + 0.6 ε^3.5 √Re Pr^0.33 = 6.683395156050521, h = λ Nu / d = 171.09491599489334,
    // q = h π d² (300 − 600) = −0.1612531593468359 W, Tsource = −q/(ρ c_p V_c) =
    // 0.13344352809238322 K/s.
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(0.3), [3, 3, 3]);
    let mut fluid = MemoryFluid::uniform(mesh, V3::new(0.0, 0.0, 1.0));
    fluid.temperature = Some(vec![300.0; 27]);
    let mut particles = MemoryParticles::new(vec![V3::repeat(0.15)], vec![0.5e-3], 2500.0, 1e-5);
    particles.temperature = Some(vec![600.0]);
    let s = settings(Method::Exact, Some(heat(Interpolation::Cell, None)));
    let mut c = Coupler::new(fluid.mesh(), s).unwrap();
    let step = c.step(&mut particles, &mut fluid).unwrap();
    let h = step.heat.unwrap();
    let q = -0.1612531593468359;
    assert!((h.q[0] - q).abs() <= 1e-12 * q.abs(), "{} vs {q}", h.q[0]);
    let centre = 13; // the middle cell of 3 × 3 × 3
    let tsource = 0.13344352809238322;
    assert!((h.tsource[centre] - tsource).abs() <= 1e-12 * tsource);
    assert!(h
        .tsource
        .iter()
        .enumerate()
        .all(|(k, &s)| k == centre || s == 0.0));
    // what the sides received
    assert_eq!(particles.heat_flux, h.q);
    let got = fluid.received[0].heat_source.as_ref().unwrap();
    assert_eq!(got, &h.tsource);
}

#[test]
fn one_sphere_with_the_superficial_reynolds_number_of_pfm_and_stm() {
    // as above, with Re = ε d |U − v| / ν = 99.99994764012244:
    // * scalarGeneralExchange (Deen, Pr given 0.7): Nu = (7 − 10ε + 5ε²)(1 + 0.17 Re^0.2
    //   Pr^⅓) + (1.33 − 2.31ε + 1.16ε²) Re^0.7 Pr^⅓ = 6.77287032335025, q = −0.16341196532393068 W;
    // * heatTransferGunn (Pr^0.33, NusseltScalingFactor 1.5): Nu = 1.5 [(7 − 10ε + 5ε²)(1 +
    //   0.7 Re^0.2 Pr^0.33) + (1.33 − 2.4ε + 1.2ε²) Re^0.7 Pr^0.33] = 10.940818523274325,
    //   q = −0.2639738503447891 W (by hand, python).
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(0.3), [3, 3, 3]);
    let mut f = fluid(&mesh);
    f.u = vec![V3::new(0.0, 0.0, 1.0); 27];
    f.t = vec![300.0; 27];
    let one = Bed {
        pos: vec![V3::repeat(0.15)],
        rad: vec![0.5e-3],
        vel: vec![V3::zeros()],
        ids: vec![1],
        den: vec![2500.0],
        temp: vec![600.0],
    };
    let stm = HeatSettings {
        model: HeatModel::ScalarGeneralExchange,
        nusselt: Nusselt::Deen,
        reynolds: ReynoldsVelocity::Superficial,
        prandtl: Some(0.7),
        ..heat(Interpolation::Cell, None)
    };
    let pfm = HeatSettings {
        model: HeatModel::HeatTransferGunn,
        nusselt: Nusselt::GunnPfm,
        reynolds: ReynoldsVelocity::Superficial,
        voidage_floor: 0.01,
        nusselt_scale: 1.5,
        ..heat(Interpolation::Smooth, None)
    };
    for (h, q) in [(stm, -0.16341196532393068), (pfm, -0.2639738503447891)] {
        let mut c = Coupler::new(&mesh, settings(Method::Exact, Some(h))).unwrap();
        let got = c
            .exchange(&one.state(), &state(&f))
            .unwrap()
            .heat
            .unwrap()
            .q[0];
        assert!(
            (got - q).abs() <= 1e-12 * q.abs(),
            "{:?}: {got} vs {q}",
            h.model
        );
    }
}

/// Owners of the fluid's cells that are never reached (`maxSource` is refused first).
struct NoOwners;

impl couple::ranks::CellOwners for NoOwners {
    fn deposit(&mut self, _: &[Label], _: &[f64]) -> Result<Vec<f64>, couple::SideError> {
        unreachable!("maxSource is refused before the owners are asked")
    }
    fn exchange(&mut self, _: &[f64]) -> Result<(), couple::SideError> {
        unreachable!("maxSource is refused before the owners are asked")
    }
    fn traffic(&self) -> (u64, u64) {
        (0, 0)
    }
}

#[test]
fn a_side_without_temperature_is_named() {
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [4, 4, 4]);
    let f = fluid(&mesh);
    let b = bed(200);
    let s = settings(Method::Exact, Some(heat(Interpolation::Cell, None)));
    let mut c = Coupler::new(&mesh, s).unwrap();
    let mut cold = b.state();
    cold.temperature = None;
    let e = c.exchange(&cold, &state(&f)).unwrap_err().to_string();
    assert!(
        e.contains("particle side") && e.contains("fix heat/gran"),
        "{e}"
    );
    let mut dry = state(&f);
    dry.temperature = None;
    let e = c.exchange(&b.state(), &dry).unwrap_err().to_string();
    assert!(e.contains("fluid side") && e.contains("0/T"), "{e}");
    let bad_cp = HeatSettings {
        cp: 0.0,
        ..heat(Interpolation::Cell, None)
    };
    let e = Coupler::new(&mesh, settings(Method::Exact, Some(bad_cp))).err();
    assert!(e.unwrap().to_string().contains("`Cp`"));
    // maxSource cannot be cut where no rank holds a cell's summed Tsource: refused before
    // the owners are asked
    let clipping = settings(Method::Exact, Some(heat(Interpolation::Cell, Some(1.0))));
    let mut owned = Coupler::new(&mesh, clipping).unwrap();
    owned.set_owners(Box::new(NoOwners));
    let e = owned
        .exchange(&b.state(), &state(&f))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("maxSource")
            && e.contains("several coupler ranks")
            && e.contains("one coupler rank"),
        "{e}"
    );
    let mut bad = bed(200);
    bad.temp[17] = f64::NAN;
    let e = c
        .exchange(&bad.state(), &state(&f))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("particle 17 (id 18)") && e.contains("heat flux"),
        "{e}"
    );
    // a particle side that shows temperatures but takes no flux is refused at the hand-over
    let mut fl = MemoryFluid::uniform(mesh, V3::zeros());
    fl.temperature = Some(vec![300.0; 64]);
    let mut p = MemoryParticles::new(vec![V3::repeat(0.5)], vec![0.01], 2500.0, 1e-5);
    let e = c.step(&mut p, &mut fl).unwrap_err().to_string();
    assert!(e.contains("fix heat/gran"), "{e}");
}

#[test]
fn without_heat_nothing_is_handed_over() {
    let mesh = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [4, 4, 4]);
    let mut fluid = MemoryFluid::uniform(mesh, V3::new(0.0, 0.0, 0.1));
    let mut particles = MemoryParticles::new(vec![V3::repeat(0.5)], vec![0.02], 2500.0, 1e-5);
    // temperatures on both sides, heat off: ignored
    fluid.temperature = Some(vec![300.0; 64]);
    particles.temperature = Some(vec![600.0]);
    let mut c = Coupler::new(fluid.mesh(), settings(Method::Exact, None)).unwrap();
    let step = c.step(&mut particles, &mut fluid).unwrap();
    assert!(step.heat.is_none());
    assert!(fluid.received[0].heat_source.is_none());
    assert!(particles.heat_flux.is_empty());
}

/// Two coupler ranks as threads, the fluid on rank 0 (`couple::ranks`' sparse sums).
mod two_ranks {
    use super::*;

    const RANKS: usize = 2;

    #[derive(Default)]
    struct Slots {
        lists: Vec<Vec<Label>>,
        values: Vec<Vec<f64>>,
        reduce: Vec<Vec<f64>>,
        out: Vec<Vec<f64>>,
    }

    struct Shared {
        barrier: Barrier,
        slots: Mutex<Slots>,
    }

    struct ThreadRanks {
        rank: usize,
        shared: Arc<Shared>,
    }

    impl ThreadRanks {
        fn wait(&self) {
            self.shared.barrier.wait();
        }

        fn reduce(&self, x: &mut [f64], op: fn(f64, f64) -> f64) {
            self.shared.slots.lock().unwrap().reduce[self.rank] = x.to_vec();
            self.wait();
            {
                let s = self.shared.slots.lock().unwrap();
                for (k, v) in x.iter_mut().enumerate() {
                    *v = (1..RANKS).fold(s.reduce[0][k], |acc, r| op(acc, s.reduce[r][k]));
                }
            }
            self.wait();
        }
    }

    impl Ranks for ThreadRanks {
        fn rank(&self) -> usize {
            self.rank
        }
        fn size(&self) -> usize {
            RANKS
        }
        fn sum_to_root(&mut self, cells: &[Label], values: &[f64], width: usize, root: &mut [f64]) {
            {
                let mut s = self.shared.slots.lock().unwrap();
                s.lists[self.rank] = cells.to_vec();
                s.values[self.rank] = values.to_vec();
            }
            self.wait();
            if self.rank == 0 {
                root.fill(0.0);
                let s = self.shared.slots.lock().unwrap();
                for q in 0..RANKS {
                    couple::ranks::scatter_add(&s.lists[q], &s.values[q], width, root);
                }
            }
            self.wait();
        }
        fn scatter_from_root(
            &mut self,
            _width: usize,
            value: &dyn Fn(Label, &mut Vec<f64>),
            out: &mut Vec<f64>,
        ) {
            if self.rank == 0 {
                let mut s = self.shared.slots.lock().unwrap();
                for q in 1..RANKS {
                    let mut buf = Vec::new();
                    for &c in &s.lists[q] {
                        value(c, &mut buf);
                    }
                    s.out[q] = buf;
                }
            }
            self.wait();
            if self.rank != 0 {
                out.extend_from_slice(&self.shared.slots.lock().unwrap().out[self.rank]);
            }
            self.wait();
        }
        fn all_sum(&self, x: &mut [f64]) {
            self.reduce(x, |a, b| a + b);
        }
        fn all_max(&self, x: &mut [f64]) {
            self.reduce(x, f64::max);
        }
        fn broadcast(&self, x: &mut [f64]) {
            // the sum with zeros elsewhere is rank 0's value
            if self.rank != 0 {
                x.fill(0.0);
            }
            self.reduce(x, |a, b| a + b);
        }
        fn gather(&self, x: &[f64]) -> Vec<Vec<f64>> {
            self.shared.slots.lock().unwrap().reduce[self.rank] = x.to_vec();
            self.wait();
            let all = match self.rank {
                0 => self.shared.slots.lock().unwrap().reduce.clone(),
                _ => Vec::new(),
            };
            self.wait();
            all
        }
    }

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-12 * scale
    }

    #[test]
    fn two_ranks_give_the_serial_heat() {
        let mesh = uniform_box(V3::repeat(0.0), V3::repeat(1.0), [9, 8, 7]);
        let b = bed(3000);
        let f = fluid(&mesh);
        for rule in [Interpolation::Cell, Interpolation::Smooth] {
            let s = settings(Method::Divided, Some(heat(rule, Some(1e-3))));
            let serial: CouplingStep = Coupler::new(&mesh, s)
                .unwrap()
                .exchange(&b.state(), &state(&f))
                .unwrap();
            let reference = serial.heat.as_ref().unwrap();
            assert!(
                reference.account.clipped_cells > 0,
                "maxSource must cut some cells"
            );
            let shared = Arc::new(Shared {
                barrier: Barrier::new(RANKS),
                slots: Mutex::new(Slots {
                    lists: vec![Vec::new(); RANKS],
                    values: vec![Vec::new(); RANKS],
                    reduce: vec![Vec::new(); RANKS],
                    out: vec![Vec::new(); RANKS],
                }),
            });
            let parts: Vec<Bed> = (0..RANKS).map(|r| b.part(|i| i % RANKS == r)).collect();
            let steps: Vec<CouplingStep> = std::thread::scope(|scope| {
                let handles: Vec<_> = (0..RANKS)
                    .map(|r| {
                        let (shared, mesh, part, f) = (shared.clone(), &mesh, &parts[r], &f);
                        scope.spawn(move || {
                            let mut c = Coupler::new(mesh, s).unwrap();
                            c.set_ranks(Box::new(ThreadRanks { rank: r, shared }));
                            c.exchange(&part.state(), &state(f)).unwrap()
                        })
                    })
                    .collect();
                handles.into_iter().map(|h| h.join().unwrap()).collect()
            });
            let scale: f64 = reference.q.iter().map(|q| q.abs()).sum();
            for (r, step) in steps.iter().enumerate() {
                let h = step.heat.as_ref().unwrap();
                let mine: Vec<usize> = (0..b.ids.len()).filter(|i| i % RANKS == r).collect();
                assert_eq!(h.q.len(), mine.len());
                for (j, &i) in mine.iter().enumerate() {
                    let want = reference.q[i];
                    assert!(close(h.q[j], want, want.abs().max(1e-300)), "particle {i}");
                }
                let (a, e) = (h.account, reference.account);
                assert!(close(a.to_particles, e.to_particles, scale), "rank {r}");
                assert!(close(a.from_fluid, e.from_fluid, scale), "rank {r}");
                assert!(close(a.clipped, e.clipped, scale), "rank {r}");
                assert_eq!(a.clipped_cells, e.clipped_cells, "rank {r}");
                assert_eq!(a.particles_outside, e.particles_outside, "rank {r}");
                assert!(a.imbalance.abs() <= 1e-12 * scale, "rank {r}: {a:?}");
                if r > 0 {
                    assert!(h.tsource.is_empty(), "Tsource lives on rank 0");
                }
            }
            let t0 = &steps[0].heat.as_ref().unwrap().tsource;
            let smax = reference
                .tsource
                .iter()
                .map(|s| s.abs())
                .fold(0.0, f64::max);
            for (c, (&a, &e)) in t0.iter().zip(&reference.tsource).enumerate() {
                assert!(close(a, e, smax), "Tsource of cell {c}: {a} vs {e}");
            }
        }
    }
}
