//! One sphere (practically) at rest in a uniform stream of gas at a fixed temperature (issue 27, item 4): the
//! coupler's `LaEuScalarTemp` (Li & Mason's Nusselt number) hands the native DEM's `fix
//! couple/cfd/convection` the flux q = h A (T_f − T_p), and `fix heat/gran` integrates it, so
//! the particle heats as dT/dt = h A (T_f − T_p)/(m c_p):
//!
//!   T(t) = T_f − (T_f − T_0) exp(−t/τ),  τ = m c_p/(h A),  h = λ Nu/d,  A = π d²,
//!
//! Nu = 2 + 0.6 ε^3.5 Re^½ Pr^0.33 (Li & Mason 2000 for Re < 200, as CFDEM-PUBLIC's
//! LaEuScalarTemp), Re = d|U|/ν, Pr = c_p,f ν ρ/λ, evaluated here by hand from the inputs,
//! with ε = 1 − V_p/V_cell of the one cell that holds the sphere.
//!
//! The flux is held over each coupling interval Δt_c (CFDEM's explicit exchange), so the run
//! follows the geometric sequence (1 − Δt_c/τ)^n, first-order close to the exponential.
//! Richardson's extrapolation of two runs (Δt_c and Δt_c/2) removes the first-order term: the
//! extrapolated history must match the exponential to 1e-6 of T_f − T_0 — the
//! closed form, not the code's own recurrence.

use couple::memory::MemoryFluid;
use couple::{Coupler, CouplingConfig, FluidSide, ParticleSide};
use mesh::build::uniform_box;
use mesh::v3::V3;
use std::f64::consts::PI;
use std::path::Path;

const D: f64 = 1e-3; // m
                     // The sphere is held still by its inertia: 10⁹ times a solid's density with 10⁻⁹ times its
                     // heat capacity (ρ c = 10⁶ J/(m³ K) as for 2000 kg/m³ at 500 J/(kg K)), so the drag moves it
                     // by v/U < 1e-8 over the test while the heat balance sees an ordinary ρ c.
const RHO_P: f64 = 2e12; // kg/m³
const C_P: f64 = 5e-7; // J/(kg K), the particle's thermalCapacity
const T0: f64 = 300.0; // K
const T_F: f64 = 400.0; // K
const U: f64 = 0.5; // m/s
const NU: f64 = 1.5e-5; // m²/s
const RHO_F: f64 = 1.2; // kg/m³
const LAMBDA: f64 = 0.0256; // W/(m K)
const CP_F: f64 = 1007.0; // J/(kg K)
const CELL: f64 = 4e-3; // m, the one cell's edge

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

fn case(dir: &Path) {
    let header = |class: &str, object: &str| {
        format!("FoamFile {{ version 2.0; format ascii; class {class}; object {object}; }}\n")
    };
    write(
        &dir.join("CFD/constant/couplingProperties"),
        &(header("dictionary", "couplingProperties")
            + "modelType B;\ncouplingInterval 1;\nvoidFractionModel divided;\n\
               locateModel engine;\nmeshMotionModel noMeshMotion;\nIOModel off;\n\
               probeModel off;\ndataExchangeModel twoWayMPI;\naveragingModel dense;\n\
               clockModel off;\nsmoothingModel off;\n\
               forceModels ( KochHillDrag LaEuScalarTemp );\n\
               momCoupleModels ( implicitCouple );\n\
               turbulenceModelType turbulenceProperties;\n\
               LaEuScalarTempProps { tempFieldName \"T\"; partTempName \"Temp\";\n\
               partHeatFluxName \"convectiveHeatFlux\"; lambda 0.0256; Cp 1007; }\n\
               KochHillDragProps {}\nimplicitCoupleProps {}\ndividedProps { alphaMin 0.1; }\n\
               twoWayMPIProps { liggghtsPath \"../DEM/in.run\"; }\n"),
    );
    write(
        &dir.join("CFD/constant/transportProperties"),
        &(header("dictionary", "transportProperties")
            + "transportModel Newtonian;\nnu 1.5e-5;\nrho 1.2;\n"),
    );
    write(
        &dir.join("DEM/in.run"),
        "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\n\
         communicate single vel yes\nunits si\n\
         region reg block 0 0.004 0 0.004 0 0.004 units box\ncreate_box 1 reg\n\
         neighbor 0.0002 bin\nneigh_modify delay 0\n\
         fix m1 all property/global youngsModulus peratomtype 5.e6\n\
         fix m2 all property/global poissonsRatio peratomtype 0.45\n\
         fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3\n\
         fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
         fix ftco all property/global thermalConductivity peratomtype 5.\n\
         fix ftca all property/global thermalCapacity peratomtype 5e-7\n\
         pair_style gran model hertz tangential history\npair_coeff * *\n\
         timestep 0.001\n\
         create_atoms 1 single 0.002 0.002 0.002 units box\n\
         set group all diameter 0.001 density 2e12\n\
         fix cfd all couple/cfd couple_every 1 mpi\nfix cfd2 all couple/cfd/force/implicit\n\
         fix heattransfer all heat/gran initial_temperature 300.\n\
         fix cfd3 all couple/cfd/convection T0 300\n\
         fix integr all nve/sphere\n",
    );
}

/// The particle temperature after each coupling step of a run with `couplingInterval` DEM
/// steps of `dt` s, `steps` coupling steps long, and the sphere's largest speed (m/s).
fn run(dir: &Path, dt: f64, steps: usize) -> (Vec<(f64, f64)>, f64) {
    let config = CouplingConfig::read_case(&dir.join("CFD")).unwrap();
    let settings = config.coupler_settings(&dir.join("CFD")).unwrap();
    assert!(settings.heat.is_some());
    let deck_text = std::fs::read_to_string(dir.join("DEM/in.run"))
        .unwrap()
        .replace("timestep 0.001", &format!("timestep {dt}"));
    write(&dir.join("DEM/in.run.dt"), &deck_text);
    let deck = liggghts_deck::Deck::read(dir.join("DEM/in.run.dt")).unwrap();
    let mut dem = runner::native::run_native_deck(&deck, &dir.join("DEM"), &mut |w| {
        panic!("deck warning: {w}")
    })
    .unwrap();
    let mesh = uniform_box([0.0; 3], [CELL; 3], [1, 1, 1]);
    let mut fluid = MemoryFluid::uniform(mesh.clone(), V3::new(0.0, 0.0, U));
    fluid.temperature = Some(vec![T_F]);
    let mut coupler = Coupler::new(fluid.mesh(), settings).unwrap();
    let mut out = Vec::new();
    let mut speed = 0.0f64;
    for _ in 0..steps {
        coupler.step(&mut dem, &mut fluid).unwrap();
        let state = dem.state();
        let t = state.temperature.expect("heat/gran gives temperatures")[0];
        speed = speed.max(state.velocity[0].norm());
        out.push((dem.time(), t));
    }
    (out, speed)
}

#[test]
fn a_sphere_in_a_hot_stream_approaches_the_gas_temperature_exponentially() {
    let dir = tempfile::tempdir().unwrap();
    case(dir.path());
    // the closed form's constants, by hand from the inputs
    let v_p = PI / 6.0 * D.powi(3);
    let eps = 1.0 - v_p / CELL.powi(3);
    let re = D * U / NU;
    let pr = CP_F * NU * RHO_F / LAMBDA;
    let nu_number = 2.0 + 0.6 * eps.powf(3.5) * re.sqrt() * pr.powf(0.33);
    let h = LAMBDA * nu_number / D;
    let tau = RHO_P * v_p * C_P / (h * PI * D * D);
    assert!(re < 200.0 && (30.0..60.0).contains(&re), "Re {re}");
    // Δt_c = τ/2000 and τ/4000, to t = 3τ
    let dt = tau / 2000.0;
    let (coarse, moved) = run(dir.path(), dt, 6000);
    let (fine, _) = run(dir.path(), dt / 2.0, 12000);
    let exact = |t: f64| T_F - (T_F - T0) * (-t / tau).exp();
    let scale = T_F - T0;
    let (mut worst_coarse, mut worst_rich) = (0.0f64, 0.0f64);
    for (k, &(t, tc)) in coarse.iter().enumerate() {
        let (t2, tf) = fine[2 * k + 1];
        assert!((t2 - t).abs() <= 1e-9 * t, "{t2} vs {t}");
        let richardson = 2.0 * tf - tc;
        worst_coarse = worst_coarse.max((tc - exact(t)).abs() / scale);
        worst_rich = worst_rich.max((richardson - exact(t)).abs() / scale);
    }
    // first order in Δt_c/τ = 5e-4: the first interval runs before the first exchange (CFDEM's
    // order: the DEM advances, then the coupling), and the held flux lags by half an interval,
    // together (Δt_c/τ)(1 − t/2τ)e^{−t/τ}, largest at the start
    assert!(
        worst_coarse > 4e-4 && worst_coarse < 6e-4,
        "held-flux error {worst_coarse:e} (expected ≈ 5e-4)"
    );
    eprintln!("error of the run {worst_coarse:e}, of the extrapolation {worst_rich:e}");
    assert!(
        worst_rich <= 1e-6,
        "extrapolated history off the exponential by {worst_rich:e} of T_f − T_0"
    );
    // the particle got close to the gas: 3τ
    let last = coarse.last().unwrap().1;
    assert!(moved < 1e-8 * U, "the sphere moved at {moved} m/s");
    assert!((T_F - last) / scale < 0.06, "{last} K");
}
