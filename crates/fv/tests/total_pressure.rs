//! A `totalPressure` inlet (zeroGradient U) at Courant numbers well above 1, as the pneumatic
//! conveyor runs it at the seed's Δt 1e-4 s (largest Courant number ≈ 10).
//!
//! The condition sets p_b = p0 − ½|U_b|² on inflow faces. OpenFOAM v1912 evaluates it when it
//! assembles the pressure equation, with the flux the corrector starts from, and keeps that
//! value through the solve and the velocity correction; re-evaluating it after the solve with
//! the corrector's new flux and velocity feeds ½|U|² back into the same corrector, which blew
//! the conveyor up in its first step (12 000 m/s in an inlet cell, where pisoFoam has 0.45 m/s).
//!
//! Fast tier: a straight duct with slip walls from rest, p0 at the inlet, p = 0 at the
//! outlet. The flow stays uniform, so the column of length L obeys L dU/dt = p0 − ½U²
//! (kinematic; ∇·U = 0 makes U uniform and convection vanish), with the closed form
//! U(t) = U∞ tanh(U∞ t/(2L)), U∞ = √(2 p0) (Bernoulli's outflow speed).
//! Full tier: a laminar channel with no-slip walls against Debian's pisoFoam on the same case.

mod common;
use common::compare::{rel, scalars, vectors};
use common::{write_case, CaseSpec, PatchSpec};
use std::path::Path;

/// Inlet total pressure (m²/s²): U∞ = √(2 p0) = 10 m/s.
const P0: f64 = 50.0;
/// The channel's step (s): U∞Δt/Δx = 1 in its longest cells, ≈ 10 in its shortest.
const DT_CHANNEL: f64 = 0.012;
/// Duct length (m).
const L: f64 = 1.0;
/// Cells along the duct.
const NX: usize = 20;

/// Writes the duct: `ny` cells across a height `h`, walls `wall_u` (U condition) on y,
/// one cell in z (empty), the time scheme `ddt`, step `dt`, end `end`.
/// `grading`: last over first cell length along the duct (1: uniform).
#[allow(clippy::too_many_arguments)]
fn write_duct(
    dir: &Path,
    ny: usize,
    h: f64,
    grading: f64,
    wall_u: &str,
    ddt: &str,
    dt: f64,
    end: f64,
) {
    let m = mesh::build::hex_grid(
        &mesh::build::graded_planes(0.0, L, NX, grading),
        &mesh::build::graded_planes(0.0, h, ny, 1.0),
        &[0.0, 0.1 * h],
    );
    let p_inlet = format!("type totalPressure; p0 uniform {P0}; value uniform 0;");
    let wall_type = if wall_u.contains("noSlip") {
        "wall"
    } else {
        "patch"
    };
    let patches = [
        PatchSpec {
            name: "xMin",
            patch_type: "patch",
            u: "type zeroGradient;",
            p: &p_inlet,
        },
        PatchSpec {
            name: "xMax",
            patch_type: "patch",
            u: "type inletOutlet; inletValue uniform (0 0 0); value uniform (0 0 0);",
            p: "type fixedValue; value uniform 0;",
        },
        PatchSpec {
            name: "yMin",
            patch_type: wall_type,
            u: wall_u,
            p: "type zeroGradient;",
        },
        PatchSpec {
            name: "yMax",
            patch_type: wall_type,
            u: wall_u,
            p: "type zeroGradient;",
        },
        PatchSpec {
            name: "zMin",
            patch_type: "empty",
            u: "type empty;",
            p: "type empty;",
        },
        PatchSpec {
            name: "zMax",
            patch_type: "empty",
            u: "type empty;",
            p: "type empty;",
        },
    ];
    let spec = CaseSpec {
        nu: 1e-3,
        rho: 1.0,
        delta_t: dt,
        end_time: end,
        ddt,
        div: "Gauss limitedLinearV 1",
        n_correctors: 2,
        u_internal: [0.0; 3],
    };
    write_case(dir, m, &patches, &spec);
    // The laminar stress's dev2 term takes `default` (pisoFoam's laminar model needs it).
    let sch = dir.join("system/fvSchemes");
    let text = std::fs::read_to_string(&sch).unwrap();
    std::fs::write(&sch, text.replace("default none;", "default Gauss linear;")).unwrap();
    // pisoFoam's final corrector reads `pFinal` (and `UFinal` without relTol entries).
    let sol = dir.join("system/fvSolution");
    let text = std::fs::read_to_string(&sol).unwrap();
    std::fs::write(
        &sol,
        text.replace(
            "relTol 0; }\n}",
            "relTol 0; }\n    pFinal { $p; }\n    UFinal { $U; }\n}",
        ),
    )
    .unwrap();
    std::fs::write(
        dir.join("constant/turbulenceProperties"),
        "FoamFile { version 2.0; format ascii; class dictionary; object turbulenceProperties; }\nsimulationType laminar;\n",
    )
    .unwrap();
}

/// Runs the slip duct natively with step `dt` for `steps` steps; returns the mean axial
/// velocity after each step (m/s), or the error of the step that failed.
fn slip_duct(ddt: &str, dt: f64, steps: usize) -> Result<Vec<f64>, String> {
    let dir = tempfile::tempdir().unwrap();
    write_duct(
        dir.path(),
        1,
        0.1,
        1.0,
        "type slip;",
        ddt,
        dt,
        dt * steps as f64,
    );
    let mut fluid = fv::Fluid::from_case(dir.path()).map_err(|e| e.to_string())?;
    let mut out = Vec::with_capacity(steps);
    for _ in 0..steps {
        fluid.advance(dt).map_err(|e| e.to_string())?;
        let u = fluid.u();
        out.push(u.iter().map(|v| v[0]).sum::<f64>() / u.len() as f64);
    }
    Ok(out)
}

/// Bernoulli's steady outflow at Courant number U∞Δt/Δx = 8, with Euler and with the
/// conveyor's `CrankNicolson 0.9`: the discrete steady state has ∇p = 0 and p_b = p0 − ½U²
/// = 0 at the inlet, so U = √(2 p0) to the linear solvers' tolerance (1e-12); the bound 1e-8
/// leaves room for the residual transient after 100 steps (t = 20 L/U∞, tanh(10) = 1 − 4e-9).
/// Before the fix the first step gave 2.4e3 m/s, and the run overflowed.
#[test]
fn total_pressure_inlet_reaches_bernoulli_speed_at_courant_8() {
    let u_inf = (2.0 * P0).sqrt();
    let dx = L / NX as f64;
    let dt = 8.0 * dx / u_inf;
    for ddt in ["Euler", "CrankNicolson 0.9"] {
        let u = slip_duct(ddt, dt, 100).unwrap_or_else(|e| panic!("{ddt}: {e}"));
        let last = *u.last().unwrap();
        let peak = u.iter().copied().fold(0.0, f64::max);
        eprintln!(
            "{ddt}, Courant 8: U after step 1 {:.4} m/s, peak {peak:.6}, end {last:.10} (U∞ {u_inf})",
            u[0]
        );
        assert!(
            (last / u_inf - 1.0).abs() < 1e-8,
            "{ddt}: {last} m/s, Bernoulli {u_inf}"
        );
        // The approach overshoots U∞ only slightly (the inlet's ½U² is the previous
        // corrector's; measured 5.6e-5 with Euler, 2.0e-3 with OpenFOAM's CrankNicolson 0.9,
        // which damps the approach less: θ = 1/(1 + ψ) = 0.53 on a linear problem); before
        // the fix the run overflowed.
        let overshoot = if ddt == "Euler" { 1e-3 } else { 4e-3 };
        assert!(peak <= u_inf * (1.0 + overshoot), "{ddt}: peak {peak}");
    }
}

/// The transient at a small step (Courant number 0.1) against the closed form
/// U = U∞ tanh(U∞ t/(2L)). Euler's error is first order in Δt/τ (τ = 2L/U∞ = 0.2 s): at
/// Δt = 5e-4 s, Δt/τ = 2.5e-3, measured max |U − U_exact|/U∞ 4.6e-4 over t ≤ 0.4 s and
/// halving with Δt (9.1e-4 at 1e-3 s); the bound 1e-3 holds the first-order error, while dropping ½U² from
/// the inlet (p_b = p0) would make the column accelerate without limit (U = p0 t/L = 20 m/s at
/// t = 0.4 s, +110 %).
#[test]
fn total_pressure_transient_follows_the_tanh_closed_form() {
    let u_inf = (2.0 * P0).sqrt();
    let mut errors = Vec::new();
    for dt in [1e-3, 5e-4] {
        let steps = (0.4 / dt) as usize;
        let u = slip_duct("Euler", dt, steps).unwrap();
        let err = u
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                let t = (i + 1) as f64 * dt;
                (x - u_inf * (u_inf * t / (2.0 * L)).tanh()).abs() / u_inf
            })
            .fold(0.0, f64::max);
        eprintln!("Euler Δt {dt}: max |U − U∞ tanh(U∞t/2L)|/U∞ = {err:.3e}");
        errors.push(err);
    }
    assert!(errors[1] < 1e-3, "{errors:?}");
    let order = (errors[0] / errors[1]).log2();
    assert!((0.8..1.3).contains(&order), "order {order} ({errors:?})");
}

/// A laminar channel (no-slip walls, Re = U∞H/ν = 1000, 20 × 10 cells) from rest with the
/// total-pressure inlet at Courant numbers up to ≈ 5–8, natively and with Debian's pisoFoam
/// (Euler, the same schemes and linear solvers to 1e-12). The first step agrees to pisoFoam's
/// 6 written digits (8.7e-7); from the second step on the two differ by more than round-off
/// (2.4e-4 of max |U| after step 2, 1.7e-3 after 10, 6.8e-3 after 60 — measured; the cause
/// is not found yet: there is no backflow at the outlet). The bound 2e-2 therefore checks
/// that both run stably to the same flow at Courant numbers up to ≈ 9, not round-off.
/// The same with OpenFOAM's `CrankNicolson 0.9` (each solver's own implementation; the native
/// one is OpenFOAM's recursion, `fv::ddt::CrankNicolsonDdt0`): the same bound, for the same
/// reason (Euler's difference, not the time scheme's: the cavity and the k–ε channel agree
/// with pisoFoam's CrankNicolson to round-off). Measured after 60 steps: max|ΔU|/max|U|
/// 5.1e-3, max|Δp|/max|p| 1.3e-2 (the θ-scheme it replaced: 1.8e-2, 2.4e-2).
#[test]
fn total_pressure_channel_matches_pisofoam_at_high_courant() {
    if !testkit::tool("pisoFoam") {
        return;
    }
    for ddt in ["Euler", "CrankNicolson 0.9"] {
        let (co_max, umax, du, dp) = channel_vs_pisofoam(ddt);
        eprintln!(
            "channel, {ddt}, pisoFoam's largest Courant number {co_max:.2}, max |U| {umax:.3} m/s: \
             max|ΔU|/max|U| {du:.2e}, max|Δp|/max|p| {dp:.2e}"
        );
        // The comparison is made where it matters: well above Courant 1, in a moving flow.
        assert!(co_max > 4.0, "{ddt}: largest Courant number {co_max}");
        assert!(umax > 5.0, "{ddt}: max |U| {umax}");
        assert!(du < 2e-2 && dp < 2e-2, "{ddt}: ΔU {du:e}, Δp {dp:e}");
    }
}

/// Runs the channel with `ddt` natively and with pisoFoam: (pisoFoam's largest Courant number,
/// max |U| (m/s), max|ΔU|/max|U|, max|Δp|/max|p|) at the end.
fn channel_vs_pisofoam(ddt: &str) -> (f64, f64, f64, f64) {
    let root = tempfile::tempdir().unwrap();
    let (ours, theirs) = (root.path().join("fv"), root.path().join("pisoFoam"));
    let dt = DT_CHANNEL;
    let steps = 60;
    write_duct(
        &theirs,
        10,
        0.1,
        0.1,
        "type noSlip;",
        ddt,
        dt,
        dt * steps as f64,
    );
    // pisoFoam writes the end time only as a write time.
    let cd = theirs.join("system/controlDict");
    let text = std::fs::read_to_string(&cd).unwrap();
    std::fs::write(
        &cd,
        text.replace("writeInterval 100000;", &format!("writeInterval {steps};")),
    )
    .unwrap();
    testkit::copy_dir(&theirs, &ours);
    let log = testkit::run_ok(testkit::openfoam("pisoFoam"), &theirs);
    let co_max = log
        .lines()
        .filter_map(|l| l.strip_prefix("Courant Number mean: "))
        .filter_map(|l| l.split("max: ").nth(1)?.trim().parse::<f64>().ok())
        .fold(0.0, f64::max);
    let mut fluid = fv::Fluid::from_case(&ours).unwrap();
    assert_eq!(fluid.run().unwrap(), steps);
    let n = fluid.geometry().n_cells;
    let time = fluid.time_name();
    let (a, b) = (ours.join(&time), theirs.join(&time));
    let u_ref = vectors(&b.join("U"), n);
    let du = rel(&vectors(&a.join("U"), n), &u_ref);
    let dp = rel(&scalars(&a.join("p"), n), &scalars(&b.join("p"), n));
    let umax = u_ref.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (co_max, umax, du, dp)
}
