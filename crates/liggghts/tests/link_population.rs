//! In-process LIGGGHTS with a changing population (feature `link`, full tier): the deck
//! `liggghts-inputs/outflow.in` (20 spheres inserted every 1000 steps by `insert/rate/region`,
//! lost through the open bottom) coupled to air at rest. The coupler sees LIGGGHTS's
//! insertions at the exchange after them, exactly 20 each, and every loss; at every exchange
//! the particle count and volume change by what entered minus what left, the voidage holds
//! every particle's volume (in cells or outside the mesh), and the native DEM run of the same
//! deck under the same coupler sees the same insertions and ends with the same totals
//! (measured: momentum in −1.06824e-3 vs −1.06838e-3 kg·m/s, out −2.26175e-3 vs −2.26609e-3).
#![cfg(feature = "link")]

use closures::model::ModelType;
use closures::{DragClosure, DragLaw};
use couple::config::{DragSettings, Forces};
use couple::memory::MemoryFluid;
use couple::{Coupler, CouplerSettings, Interpolation, ParticleSide, ParticleState, Physics};
use liggghts::LiggghtsDem;
use mesh::build::uniform_box;
use mesh::v3::V3;
use voidage::Method;

const EXCHANGES: u64 = 200;
const INTERVAL: u64 = 100;

fn physics() -> Physics {
    Physics {
        rho: 1.2,
        nu: 1.5e-5,
        gravity: V3::new(0.0, 0.0, -9.81),
        model: ModelType::B,
        forces: Forces {
            drag: Some(DragSettings {
                closure: DragClosure::from(DragLaw::SchillerNaumann),
                interpolation: Interpolation::Cell,
                implicit_dem: true,
                explicit_fluid: false,
                dem_only: false,
            }),
            grad_p: None,
            viscous: None,
            archimedes: true,
            no_drag: None,
            ..Forces::default()
        },
        implicit_couple: true,
    }
}

fn volume(s: &ParticleState<'_>) -> f64 {
    s.radius
        .iter()
        .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
        .sum()
}

/// The native DEM as a particle side for this test.
struct Native(dem::Simulation);

impl ParticleSide for Native {
    fn advance(&mut self, steps: u64) -> Result<(), couple::SideError> {
        Ok(self.0.run(steps)?)
    }
    fn time_step(&self) -> f64 {
        self.0.dt()
    }
    fn time(&self) -> f64 {
        self.0.time()
    }
    fn state(&self) -> ParticleState<'_> {
        let p = &self.0.particles;
        ParticleState {
            temperature: None,
            ids: &p.id,
            position: &p.x,
            velocity: &p.v,
            radius: &p.radius,
            density: &p.density,
        }
    }
    fn set_forces(&mut self, f: &[V3], beta: &[f64], u: &[V3]) -> Result<(), couple::SideError> {
        Ok(self.0.set_coupling(f, beta, u)?)
    }
}

/// Couples `side` for the whole run, checking every exchange; returns the entered counts per
/// exchange and the totals.
fn couple_run(side: &mut impl ParticleSide) -> (Vec<usize>, couple::PopulationChange) {
    let mesh = uniform_box(
        V3::new(-0.01, -0.01, 0.0),
        V3::new(0.01, 0.01, 0.06),
        [4, 4, 12],
    );
    let mut fluid = MemoryFluid::uniform(mesh.clone(), V3::zeros());
    let settings = CouplerSettings {
        method: Method::Exact,
        alpha_min: None,
        coupling_interval: INTERVAL,
        physics: physics(),
        heat: None,
    };
    let mut coupler = Coupler::new(&mesh, settings).unwrap();
    let first = coupler
        .exchange(&side.state(), &fluid_state(&fluid))
        .unwrap();
    assert_eq!(first.population, couple::PopulationChange::default());
    let (mut n, mut v) = (side.state().len(), volume(&side.state()));
    let mut entered = Vec::new();
    for _ in 0..EXCHANGES {
        let step = coupler.step(side, &mut fluid).unwrap();
        let s = side.state();
        let c = step.population;
        assert_eq!(s.len() + c.left, n + c.entered);
        let vol = volume(&s);
        assert!((vol - v - (c.volume_in - c.volume_out)).abs() < 1e-12 * (vol + v).max(1e-9));
        let d = &step.deposit;
        assert!((d.deposited_volume + d.outside_volume - vol).abs() < 1e-12 * vol.max(1e-9));
        entered.push(c.entered);
        (n, v) = (s.len(), vol);
        coupler.recycle(step);
    }
    (entered, coupler.population_total())
}

fn fluid_state(f: &MemoryFluid) -> couple::FluidState<'_> {
    couple::FluidSide::state(f)
}

#[test]
fn liggghts_insertions_and_losses_are_followed_by_tag() {
    if !testkit::tool("liggghts") {
        return;
    }
    let input = std::fs::read_to_string(testkit::liggghts_input("outflow.in")).unwrap();
    let coupled = input.replace(
        "fix             integr all nve/sphere",
        "fix             cfd all couple/cfd couple_every 100 mpi\n\
         fix             cfd2 all couple/cfd/force/implicit\n\
         fix             integr all nve/sphere",
    );
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("outflow.in");
    std::fs::write(&deck, &coupled).unwrap();
    let universe = mpi::initialize().expect("MPI initialised once");
    let mut lig = LiggghtsDem::open(&universe.world(), &deck, dir.path(), &[]).unwrap();
    assert_eq!(lig.state().len(), 0);
    let (entered, total) = couple_run(&mut lig);
    // insertions at steps 1, 1001, …, 9001: seen at exchanges 1, 11, …, 91
    for (k, &e) in entered.iter().enumerate() {
        let expect = if k % 10 == 0 && k < 100 { 20 } else { 0 };
        assert_eq!(e, expect, "exchange {}", k + 1);
    }
    assert_eq!((total.entered, total.left), (200, 200));
    assert_eq!(lig.state().len(), 0);

    // the native DEM on the same deck under the same coupler
    let stripped = liggghts::CouplingDeck::read(&deck, &[])
        .unwrap()
        .without_runs();
    let d = liggghts_deck::Deck::parse(&stripped, &deck, &[]).unwrap();
    let ndir = tempfile::tempdir().unwrap();
    let mut native = Native(dem::Simulation::from_deck(&d, ndir.path()).unwrap());
    let (n_entered, n_total) = couple_run(&mut native);
    assert_eq!(n_entered, entered);
    assert_eq!((n_total.entered, n_total.left), (200, 200));
    assert!((n_total.volume_in - total.volume_in).abs() < 1e-12 * total.volume_in);
    eprintln!(
        "LIGGGHTS: momentum in {:?}, out {:?}; native: in {:?}, out {:?} (kg·m/s)",
        total.momentum_in, total.momentum_out, n_total.momentum_in, n_total.momentum_out
    );
    // the spheres fall alike in both (random positions, deterministic fall): the momentum
    // that entered (inserted at −0.5 m/s, one exchange of free fall) and left agree to 1 %
    for (a, b) in [
        (total.momentum_in[2], n_total.momentum_in[2]),
        (total.momentum_out[2], n_total.momentum_out[2]),
    ] {
        assert!(a < 0.0 && (a - b).abs() < 0.01 * a.abs(), "{a} vs {b}");
    }
}
