//! Issue 17, target 4: the steady pressure drop through a frozen, heterogeneous packed bed must
//! not depend on the time step. A 4 × 4 × 24 column (0.01 × 0.01 × 0.06 m, slip side walls,
//! superficial inlet velocity 0.01 m/s, p = 0 at the outlet) holds a bed in its middle third
//! whose voidage scatters from cell to cell (ε = 0.45 ± 0.07, a fixed pseudo-random pattern);
//! Ksl per cell is Gidaspow's Ergun form at the plug-flow velocity,
//! Ksl = 150 μ (1−ε)²/(ε d²) + 1.75 ρ (1−ε) |U_s/ε| / d (kg/(m³ s)), frozen. With
//! `harmonic_faces` (what coupled runs use) the steady Δp (Pa) is run for Δt = 1e-4 … 1e-3 s:
//!
//! * its spread (max − min)/mean must stay within 0.2 % ([`fv::PorousTimeFlux::Consistent`]);
//! * it must lie between the Darcy bounds of the frozen fields (`foam_solver_tests::darcy`:
//!   rows at uniform pressure below, columns without cross-flow above; 1 % of slack each side
//!   for the viscous stress the bounds neglect, as in the full tier's frozen Ergun bed).
//!
//! Measured (`cargo test -p fv --test steady_dt -- --nocapture` prints it): 154.671, 154.668,
//! 154.664, 154.661 Pa at Δt = 1e-4, 2.5e-4, 5e-4, 1e-3 s (spread 6.4e-5) in the bounds
//! [141.63, 166.28] Pa; the pre-issue formulation ([`fv::PorousTimeFlux::DdtCorr`]) gave
//! 144.32, 149.27, 152.05, 153.53 Pa (spread 6.2 %). `examples/dt_sweep.rs` of
//! `foam-solver-tests` prints both, with grainPisoFoam, on the frozen Ergun bed.

mod common;
use common::{write_case, CaseSpec, PatchSpec};
use fv::PorousTimeFlux;
use mesh::v3::V3;

const NU: f64 = 1.5e-4;
const RHO: f64 = 10.0;
const D: f64 = 1e-3;
const U_S: f64 = 0.01;
const N: [usize; 3] = [4, 4, 24];
const HEIGHT: f64 = 0.06;
const BED: (f64, f64) = (0.02, 0.04);

/// The frozen bed: ε and Ksl per cell of the column.
fn bed_fields(g: &fv::FvGeometry) -> (Vec<f64>, Vec<f64>) {
    let mu = NU * RHO;
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut eps = Vec::with_capacity(g.n_cells);
    for c in &g.c {
        // xorshift64*: a fixed pattern, the same on every machine.
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        let r = (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64;
        eps.push(if c[2] > BED.0 && c[2] < BED.1 {
            0.38 + 0.14 * r
        } else {
            1.0
        });
    }
    let ksl = eps
        .iter()
        .map(|&e| {
            if e < 1.0 {
                150.0 * mu * (1.0 - e).powi(2) / (e * D * D)
                    + 1.75 * RHO * (1.0 - e) * (U_S / e) / D
            } else {
                0.0
            }
        })
        .collect();
    (eps, ksl)
}

/// The column case in `dir`.
fn write_column(dir: &std::path::Path, delta_t: f64) {
    let m = mesh::build::uniform_box([0.0; 3], [0.01, 0.01, HEIGHT], N);
    let slip = "type slip;";
    let zg = "type zeroGradient;";
    let inlet = format!("type fixedValue; value uniform (0 0 {U_S});");
    let wall = |name| PatchSpec {
        name,
        patch_type: "wall",
        u: slip,
        p: zg,
    };
    let patches = [
        PatchSpec {
            name: "zMin",
            patch_type: "patch",
            u: &inlet,
            p: "type fixedFluxPressure; value uniform 0;",
        },
        PatchSpec {
            name: "zMax",
            patch_type: "patch",
            u: zg,
            p: "type fixedValue; value uniform 0;",
        },
        wall("xMin"),
        wall("xMax"),
        wall("yMin"),
        wall("yMax"),
    ];
    let spec = CaseSpec {
        nu: NU,
        rho: RHO,
        delta_t,
        end_time: 1.0,
        ddt: "Euler",
        div: "Gauss upwind",
        n_correctors: 2,
        u_internal: [0.0, 0.0, U_S],
    };
    write_case(dir, m, &patches, &spec);
}

/// Steady Δp (Pa, inlet area mean − outlet) at time step `dt` with the given time term, and
/// the number of steps taken. Steady: Δp changes by less than 1e-9 of itself over 0.01 s.
fn steady_dp(dt: f64, time_flux: PorousTimeFlux) -> (f64, usize) {
    let dir = tempfile::tempdir().unwrap();
    write_column(dir.path(), dt);
    let mut fluid = fv::Fluid::from_case(dir.path()).unwrap();
    fluid.harmonic_faces = true;
    fluid.porous_time_flux = time_flux;
    let g = fluid.geometry().clone();
    let (eps, ksl) = bed_fields(&g);
    fluid.set_voidage(&eps, &eps).unwrap();
    fluid
        .set_exchange(&ksl, &vec![V3::zeros(); g.n_cells])
        .unwrap();
    let inlet = &g.patches[g.patch_index("zMin").unwrap()];
    let window = (0.01 / dt).round() as usize;
    let mut last = f64::NAN;
    for step in 1..=(2.0 / dt).round() as usize {
        fluid.advance(dt).unwrap();
        if step % window == 0 {
            let pb = &fluid.p_boundary()[inlet.boundary_range(g.n_internal)];
            let dp = RHO * foam_solver_tests::darcy::area_mean(&g.sf[inlet.faces.clone()], pb);
            if ((dp - last) / dp).abs() < 1e-9 {
                return (dp, step);
            }
            last = dp;
        }
    }
    panic!("not steady after 2 s at Δt = {dt}: Δp {last}");
}

#[test]
fn steady_bed_pressure_drop_does_not_depend_on_the_time_step() {
    let dir = tempfile::tempdir().unwrap();
    write_column(dir.path(), 1e-3);
    let case = foam::Case::open(dir.path()).unwrap();
    let poly = case.read_mesh().unwrap();
    let geo = mesh::MeshGeometry::new(&poly).unwrap();
    let g = fv::FvGeometry::new(&poly).unwrap();
    let (eps, ksl) = bed_fields(&g);
    let us = vec![[0.0; 3]; g.n_cells];
    let bed = foam_solver_tests::darcy::Bed::new(&geo, &eps, &ksl, &us, RHO, N[2]);
    let bounds = bed.bounds(U_S);
    let (lower, upper) = (RHO * bounds.lower, RHO * bounds.upper);
    eprintln!("Darcy bounds [{lower:.4}, {upper:.4}] Pa");

    let dts = [1e-4, 2.5e-4, 5e-4, 1e-3];
    let mut dps = Vec::new();
    for &dt in &dts {
        let (dp, steps) = steady_dp(dt, PorousTimeFlux::Consistent);
        eprintln!("Δt {dt:.1e} s: Δp {dp:.5} Pa ({steps} steps)");
        dps.push(dp);
    }
    let max = dps.iter().copied().fold(f64::MIN, f64::max);
    let min = dps.iter().copied().fold(f64::MAX, f64::min);
    let mean = dps.iter().sum::<f64>() / dps.len() as f64;
    let spread = (max - min) / mean;
    eprintln!("spread {:.2e} %", 100.0 * spread);
    assert!(spread < 2e-3, "Δp {dps:?} spreads by {spread}");
    for dp in dps {
        assert!(
            dp > 0.99 * lower && dp < 1.01 * upper,
            "Δp {dp} Pa outside [{lower}, {upper}] Pa"
        );
    }
}
