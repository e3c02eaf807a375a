//! Schumann's packed-bed solution (`runner::schumann`) against independent references, and the
//! front check of `openfoam-cases/packed-bed-heating` (`runner::heating`) on profiles that must
//! pass and profiles that must fail.

use runner::heating::{check, level_crossing, HeatingError, HeatingSpec, Phase, Profile, Snapshot};
use runner::schumann::{self, SchumannBed};

/// e^{−x−y} I0(2√(xy)) by its power series Σ_k e^{−x−y} (xy)^k/(k!)², each term in logs
/// (independent of the crate's Poisson sums).
fn scaled_i0(x: f64, y: f64) -> f64 {
    if x == 0.0 || y == 0.0 {
        return (-x - y).exp();
    }
    let (lxy, mut lfact, mut sum) = ((x * y).ln(), 0.0f64, 0.0);
    for k in 0..2000 {
        if k > 0 {
            lfact += (k as f64).ln();
        }
        sum += (k as f64 * lxy - 2.0 * lfact - x - y).exp();
    }
    sum
}

/// The PDEs in physical variables along their characteristics: gas along dx/dt = u,
/// dT_g/dt = (T_s − T_g)/τ_g; solid at fixed x, dT_s/dt = (T_g − T_s)/τ_s; trapezoidal rule on
/// both (second order), Δx = u Δt, so node (i, m) is x = i u Δt, t = (i + m) Δt. Returns
/// θ_g, θ_s on the nodes i ≤ ni, m ≤ nm.
fn characteristics(tau_g: f64, tau_s: f64, dt: f64, ni: usize, nm: usize) -> (Grid, Grid) {
    let (a, b) = (0.5 * dt / tau_g, 0.5 * dt / tau_s);
    let mut g = vec![vec![0.0; nm + 1]; ni + 1];
    let mut s = vec![vec![0.0; nm + 1]; ni + 1];
    for m in 0..=nm {
        g[0][m] = 1.0; // hot gas at the inlet from t = 0
        if m > 0 {
            // solid at the inlet: θ_s' = (1 − θ_s)/τ_s
            s[0][m] = (s[0][m - 1] + b * (2.0 - s[0][m - 1])) / (1.0 + b);
        }
    }
    for i in 1..=ni {
        // m = 0: the gas just arrived, solid still cold
        g[i][0] = (g[i - 1][0] * (1.0 - a)) / (1.0 + a);
        for m in 1..=nm {
            // unknowns G = g[i][m], S = s[i][m]:
            // G = g[i-1][m] + a (s[i-1][m] − g[i-1][m] + S − G)
            // S = s[i][m-1] + b (g[i][m-1] − s[i][m-1] + G − S)
            let rg = g[i - 1][m] + a * (s[i - 1][m] - g[i - 1][m]);
            let rs = s[i][m - 1] + b * (g[i][m - 1] - s[i][m - 1]);
            // (1+a) G − a S = rg ; −b G + (1+b) S = rs
            let det = (1.0 + a) * (1.0 + b) - a * b;
            g[i][m] = (rg * (1.0 + b) + a * rs) / det;
            s[i][m] = ((1.0 + a) * rs + b * rg) / det;
        }
    }
    (g, s)
}

type Grid = Vec<Vec<f64>>;

/// The case's bed (README): d 3 mm, ρ_s 2500, c_s 1, air-like gas ρ 1.2, c 1000, U 0.05 m/s,
/// h 18.4 W/(m²K), ε 0.42.
fn case_bed() -> SchumannBed {
    SchumannBed::of_spheres(0.42, 3e-3, 2500.0, 1.0, 1.2, 1000.0, 0.05, 18.4).unwrap()
}

#[test]
fn schumann_matches_an_independent_characteristic_solution() {
    // raw inputs; τ's computed here from them, not from the crate's fields
    let (eps, d, rho_s, c_s, rho_g, c_g, u_sup, h) =
        (0.4, 2e-3, 2000.0, 2.0, 1.0, 1000.0, 0.1, 20.0);
    let bed = SchumannBed::of_spheres(eps, d, rho_s, c_s, rho_g, c_g, u_sup, h).unwrap();
    let ha = h * 6.0 * (1.0 - eps) / d;
    let (tau_g, tau_s) = (eps * rho_g * c_g / ha, (1.0 - eps) * rho_s * c_s / ha);
    let u = u_sup / eps;
    // ξ up to 12, η up to 16; step ξ 0.02 on the fine grid, half that on the finer
    let dt = 0.04 * tau_g;
    let (ni, nm) = (300, (16.0 * tau_s / dt) as usize);
    let (g1, s1) = characteristics(tau_g, tau_s, dt, ni, nm);
    let (g2, s2) = characteristics(tau_g, tau_s, dt / 2.0, 2 * ni, 2 * nm);
    let mut worst = (0.0f64, 0.0f64);
    for i in (0..=ni).step_by(15) {
        for m in (0..=nm).step_by(nm / 20) {
            // Richardson: the scheme is second order
            let gr = (4.0 * g2[2 * i][2 * m] - g1[i][m]) / 3.0;
            let sr = (4.0 * s2[2 * i][2 * m] - s1[i][m]) / 3.0;
            let (x, t) = (i as f64 * u * dt, (i + m) as f64 * dt);
            // m = 0 is the gas front itself (t = x/u): Schumann's limit from behind
            let t = if m == 0 { t * (1.0 + 1e-12) } else { t };
            let (eg, es) = ((bed.gas(x, t) - gr).abs(), (bed.solid(x, t) - sr).abs());
            if m > 0 {
                worst = (worst.0.max(eg), worst.1.max(es));
            } else {
                worst.0 = worst.0.max(eg);
            }
            assert!(
                eg < 1e-6 && es < 1e-6,
                "x {x} t {t}: gas {eg:e} solid {es:e}"
            );
        }
    }
    // the unextrapolated fine grid is within its own O(Δ²) as well
    assert!((bed.gas(150.0 * u * dt, 400.0 * dt) - g1[150][250]).abs() < 1e-3);
    eprintln!(
        "worst |Schumann − characteristics|: gas {:e}, solid {:e}",
        worst.0, worst.1
    );
    // before the gas arrives: the bed's initial state
    assert_eq!(bed.gas(0.1, 0.5 * 0.1 / u), 0.0);
    assert_eq!(bed.solid(0.1, 0.5 * 0.1 / u), 0.0);
}

#[test]
fn identities_and_limits() {
    for &(x, y) in &[
        (0.1, 0.3),
        (1.0, 1.0),
        (2.0, 7.0),
        (15.0, 12.0),
        (40.0, 45.0),
        (200.0, 180.0),
    ] {
        let pe = scaled_i0(x, y);
        let lhs = schumann::j(x, y) + schumann::j(y, x);
        assert!(
            (lhs - 1.0 - pe).abs() < 1e-12,
            "({x},{y}): {lhs} vs {}",
            1.0 + pe
        );
        // θ_g − θ_s = e^{−ξ−η} I0(2√(ξη)) and θ_s(ξ, η) = 1 − J(η, ξ)
        assert!((schumann::j(x, y) - schumann::solid(x, y) - pe).abs() < 1e-12);
        assert!((schumann::solid(x, y) - (1.0 - schumann::j(y, x))).abs() < 1e-12);
    }
    // η → 0: θ_g → e^{−ξ}, θ_s ≈ η e^{−ξ}; ξ → 0: θ_g → 1, θ_s → 1 − e^{−η}
    for x in [0.5, 3.0, 20.0] {
        assert!((schumann::j(x, 1e-9) - (-x).exp()).abs() < 1e-8);
        let s = schumann::solid(x, 1e-6);
        assert!((s / (1e-6 * (-x).exp()) - 1.0).abs() < 1e-5, "{x}: {s}");
    }
    for y in [0.5, 3.0, 20.0] {
        assert!((schumann::j(1e-12, y) - 1.0).abs() < 1e-11);
        assert!((schumann::solid(1e-12, y) - (1.0 - (-y).exp())).abs() < 1e-11);
    }
    // far behind the front hot, far ahead cold
    assert!(schumann::j(10.0, 60.0) > 1.0 - 1e-9 && schumann::j(60.0, 10.0) < 1e-9);
    // large arguments: monotone, finite and centred (the front at ξ ≈ η)
    let big = [
        schumann::j(1e6, 1e6 - 3e3),
        schumann::j(1e6, 1e6),
        schumann::j(1e6, 1e6 + 3e3),
    ];
    assert!(
        big[0] < 0.02 && (big[1] - 0.5).abs() < 1e-3 && big[2] > 0.98,
        "{big:?}"
    );
}

#[test]
fn schumann_matches_arbitrary_precision_quadrature() {
    // (ξ, η, J, θ_s) from mpmath 1.3.0, 30 digits: J = 1 − quad(e^{−η−τ} I0(2√(ητ)), [0, ξ]
    // split in eighths), θ_s = J − e^{−ξ−η} besseli(0, 2√(ξη)) (script in the case README)
    // ξ η J θ_s
    let table = "\
        0.5 0.2 0.66284647697848607 0.11534729895370349\n\
        1.0 1.0 0.65425416127683552 0.34574583872316448\n\
        2.0 5.0 0.91393447760021258 0.83143108646986859\n\
        5.0 2.0 0.16856891353013141 0.086065522399787415\n\
        10.0 10.0 0.54489015594241301 0.45510984405758699\n\
        10.0 8.0 0.36209664714096958 0.27711155614097914\n\
        10.0 12.0 0.7034920975222181 0.62522597471666309\n\
        30.0 25.0 0.27187331966246805 0.22884820431734671\n\
        30.0 35.0 0.75266188932656583 0.71170755304686728\n\
        100.0 90.0 0.24528540778788625 0.22301367347040994\n\
        100.0 110.0 0.76571527335366585 0.74399605529875873\n\
        3.0 0.1 0.065084225035448471 0.005472226797971418\n\
    ";
    for row in table.lines().filter(|l| !l.trim().is_empty()) {
        let v: Vec<f64> = row.split_whitespace().map(|w| w.parse().unwrap()).collect();
        let (x, y, jj, s) = (v[0], v[1], v[2], v[3]);
        assert!(
            (schumann::j(x, y) - jj).abs() < 1e-13,
            "J({x},{y}) = {}",
            schumann::j(x, y)
        );
        assert!((schumann::solid(x, y) - s).abs() < 1e-13, "θs({x},{y})");
    }
}

#[test]
fn the_front_moves_at_the_heat_capacity_ratio_speed() {
    // far into the bed the 0.5 crossing moves at u_f; the crossings at two late times, 1 s
    // apart, differ by u_f within the spreading's drift (O(√t) terms cancel to ≪ 1 %)
    let bed = case_bed();
    let uf = bed.front_speed();
    let (eps, rho_g, c_g, rho_s, c_s, u) = (0.42, 1.2, 1000.0, 2500.0, 1.0, 0.05 / 0.42);
    let by_hand = u / (1.0 + (1.0 - eps) * rho_s * c_s / (eps * rho_g * c_g));
    assert!((uf / by_hand - 1.0).abs() < 1e-12);
    let cross = |t: f64| {
        let z: Vec<f64> = (0..4000).map(|k| k as f64 * 1e-4).collect();
        let th: Vec<(f64, f64)> = z.iter().map(|&x| (x, bed.gas(x, t))).collect();
        level_crossing(&th, 0.5).unwrap()
    };
    let v = cross(9.0) - cross(8.0);
    assert!((v / uf - 1.0).abs() < 0.01, "{v} vs {uf}");
}

fn spec() -> HeatingSpec {
    HeatingSpec {
        initial_temperature: 300.0,
        inlet_temperature: 400.0,
        cell_size: 3e-3,
        position_cells: 1.0,
        position_fraction: 0.05,
        width_cells: 1.0,
        width_fraction: 0.2,
    }
}

/// Schumann's profiles of `bed` at `t`, with the depth mapped through `warp` (a shifted or
/// stretched front), sampled as cell averages (5-point Gauss–Legendre over each 3 mm slice) on
/// 40 slices, in K.
fn sampled(bed: &SchumannBed, t: f64, warp: &dyn Fn(f64) -> f64) -> Snapshot {
    let (dz, n) = (3e-3, 40);
    let nodes = [
        (-0.906_179_845_938_664, 0.236_926_885_056_189),
        (-0.538_469_310_105_683, 0.478_628_670_499_366),
        (0.0, 0.568_888_888_888_889),
        (0.538_469_310_105_683, 0.478_628_670_499_366),
        (0.906_179_845_938_664, 0.236_926_885_056_189),
    ];
    let avg = |f: &dyn Fn(f64) -> f64, c: f64| -> f64 {
        nodes
            .iter()
            .map(|(x, w)| 0.5 * w * f(c + 0.5 * dz * x))
            .sum::<f64>()
    };
    let z: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) * dz).collect();
    let to_k = |th: f64| 300.0 + 100.0 * th;
    let gas = z
        .iter()
        .map(|&c| to_k(avg(&|x| bed.gas(warp(x), t), c)))
        .collect();
    let solid = z
        .iter()
        .map(|&c| to_k(avg(&|x| bed.solid(warp(x), t), c)))
        .collect();
    Snapshot {
        time: t,
        gas: Profile {
            z: z.clone(),
            temperature: gas,
        },
        solid: Profile {
            z,
            temperature: solid,
        },
    }
}

#[test]
fn schumanns_own_profiles_pass() {
    let bed = case_bed();
    let snaps: Vec<Snapshot> = [0.5, 1.0, 1.5, 2.0]
        .iter()
        .map(|&t| sampled(&bed, t, &|x| x))
        .collect();
    let r = check(&bed, &spec(), &snaps).unwrap();
    assert_eq!(r.fronts.len(), 8);
    for f in &r.fronts {
        // sampling cell averages on 3 mm slices costs ≪ one cell in position and ≤ 3.1 % in
        // width (at 0.5 s, where the front is 6 cells wide)
        assert!(f.pass(), "{f:?}");
        assert!(
            (f.position - f.reference_position).abs() < 0.1 * 3e-3,
            "{f:?}"
        );
        assert!((f.width / f.reference_width - 1.0).abs() < 0.04, "{f:?}");
    }
    assert!(r.pass());
    let checks = r.checks();
    assert_eq!(checks.len(), 16);
    assert!(checks.iter().all(|c| c.pass && c.unit == "m"));
    // the case README's numbers: the gas front at 2 s is near 62.5 mm, 35 mm wide
    let g2 = &r.fronts[6];
    assert_eq!((g2.phase, g2.time), (Phase::Gas, 2.0));
    assert!((g2.reference_position - 0.0625).abs() < 1e-3, "{g2:?}");
    assert!((g2.reference_width - 0.0353).abs() < 1e-3, "{g2:?}");
}

#[test]
fn a_shifted_front_fails() {
    let bed = case_bed();
    // 2 cells (6 mm) ahead of Schumann at t = 1 s (position ≈ 32 mm: 5 % is 1.6 mm)
    let snap = sampled(&bed, 1.0, &|x| x - 6e-3);
    let r = check(&bed, &spec(), &[snap]).unwrap();
    assert!(!r.pass());
    for f in &r.fronts {
        assert!(!f.pass(), "{f:?}");
        assert!(
            (f.position - f.reference_position - 6e-3).abs() < 3e-4,
            "{f:?}"
        );
        // the width is unchanged: only the position fails
        assert!(
            (f.width - f.reference_width).abs() <= f.width_tolerance,
            "{f:?}"
        );
    }
    // half a cell passes
    let snap = sampled(&bed, 1.0, &|x| x - 1.5e-3);
    assert!(check(&bed, &spec(), &[snap]).unwrap().pass());
}

#[test]
fn a_broadened_front_fails() {
    let bed = case_bed();
    // stretched by 1.4 about the front (what a first-order upwind T equation gives on the case's
    // grid): the position holds, the width fails
    let t = 1.5;
    let x0 = {
        let s = sampled(&bed, t, &|x| x);
        let r = check(&bed, &spec(), &[s]).unwrap();
        r.fronts[0].reference_position
    };
    let snap = sampled(&bed, t, &|x| x0 + (x - x0) / 1.4);
    let r = check(&bed, &spec(), &[snap]).unwrap();
    let g = &r.fronts[0];
    assert!(!g.pass() && !r.pass(), "{g:?}");
    assert!(
        (g.position - g.reference_position).abs() <= g.position_tolerance,
        "{g:?}"
    );
    assert!((g.width / g.reference_width - 1.4).abs() < 0.05, "{g:?}");
    // 10 % broader passes (the case's gas conduction and scheme give up to ≈ 10 %)
    let snap = sampled(&bed, t, &|x| x0 + (x - x0) / 1.1);
    assert!(check(&bed, &spec(), &[snap]).unwrap().fronts[0].pass());
}

#[test]
fn noisy_profiles_and_bad_input() {
    // a wiggle crossing 0.5 three times still gives one position: the length above 0.5
    let s = [
        (0.0, 1.0),
        (1.0, 0.6),
        (2.0, 0.4),
        (3.0, 0.6),
        (4.0, 0.4),
        (5.0, 0.0),
    ];
    let p = level_crossing(&s, 0.5).unwrap();
    // above 0.5: [0, 1.5) and (2.5, 3.5): 1.5 + 1.0
    assert!((p - 2.5).abs() < 1e-12, "{p}");
    assert_eq!(level_crossing(&s[..2], 0.5), None);
    let bed = case_bed();
    let good = sampled(&bed, 1.0, &|x| x);
    // the front not yet inside the sampled part: an error naming the time and phase
    let mut short = good.clone();
    short.gas.z.truncate(5);
    short.gas.temperature.truncate(5);
    let err = check(&bed, &spec(), &[short]).unwrap_err().to_string();
    assert!(
        err.contains("gas profile at t = 1 s") && err.contains("inside the bed"),
        "{err}"
    );
    let mut nan = good.clone();
    nan.solid.temperature[3] = f64::NAN;
    let err = check(&bed, &spec(), &[nan]).unwrap_err().to_string();
    assert!(
        err.contains("solid profile") && err.contains("temperature 3"),
        "{err}"
    );
    let mut unsorted = good.clone();
    unsorted.gas.z.swap(2, 3);
    assert!(matches!(
        check(&bed, &spec(), &[unsorted]),
        Err(HeatingError::Input(_))
    ));
    let mut same = spec();
    same.inlet_temperature = 300.0;
    assert!(check(&bed, &same, std::slice::from_ref(&good)).is_err());
    assert!(check(&bed, &spec(), &[]).is_err());
    assert!(SchumannBed::of_spheres(1.2, 3e-3, 2500.0, 1.0, 1.2, 1e3, 0.05, 18.4).is_err());
    let err = SchumannBed::of_spheres(0.4, 3e-3, 2500.0, 1.0, 1.2, 1e3, -1.0, 18.4).unwrap_err();
    assert!(err.contains("superficial velocity"), "{err}");
    // a measured front that never falls below 0.1 inside the bed: width NaN, fails
    let mut hot = good;
    hot.gas
        .temperature
        .iter_mut()
        .for_each(|t| *t = t.max(320.0));
    let r = check(&bed, &spec(), &[hot]).unwrap();
    assert!(r.fronts[0].width.is_nan() && !r.fronts[0].pass());
    assert!(!r.checks()[1].pass);
}

/// `openfoam-cases/packed-bed-heating/FILE` parsed by `foam`.
fn case_dict(file: &str) -> foam::Dict {
    let p = testkit::repo_root()
        .join("openfoam-cases/packed-bed-heating")
        .join(file);
    foam::parse_file(&p).unwrap().body
}

#[test]
fn the_case_samples_fronts_inside_its_bed() {
    // the committed LIGGGHTS pack, measured as the runner measures a bed
    let root = testkit::repo_root().join("openfoam-cases/packed-bed-heating");
    let data = dem::deck::data_file::read_data(&root.join("reference/packed.data")).unwrap();
    let x: Vec<mesh::v3::V3> = data.particles.iter().map(|p| p.x).collect();
    let r: Vec<f64> = data.particles.iter().map(|p| p.radius).collect();
    let rho: Vec<f64> = data.particles.iter().map(|p| p.density).collect();
    let bed =
        runner::bed::Bed::measure(&x, mesh::v3::V3::z(), &r, &rho, 0.0, 0.024 * 0.024).unwrap();
    assert_eq!(bed.particles, 3000);
    // the README's numbers
    assert!((bed.voidage - 0.452).abs() < 5e-4, "{bed:?}");
    assert!((bed.height - 0.1343).abs() < 5e-4, "{bed:?}");
    let d = 2.0 * r[0];
    // the case's parameters, read from its files
    let tp = case_dict("CFD/constant/transportProperties");
    let (nu, rho_g, pr) = (
        tp.f64("nu").unwrap(),
        tp.f64("rho").unwrap(),
        tp.f64("Pr").unwrap(),
    );
    let cp = case_dict("CFD/constant/couplingProperties");
    let la = cp.dict("LaEuScalarTempProps").unwrap();
    let (lambda, c_g) = (la.f64("lambda").unwrap(), la.f64("Cp").unwrap());
    assert!(
        (c_g * nu * rho_g / lambda / pr - 1.0).abs() < 1e-4,
        "Pr = Cp ν ρ/λ"
    );
    let u_sup = 0.05;
    // Li & Mason (2000) as CFDEM's LaEuScalarTemp (Re < 200 branch), at the bed's mean ε
    let eps = bed.voidage;
    let re = d * u_sup / eps / nu;
    let nu_p = 2.0 + 0.6 * eps.powf(3.5) * re.sqrt() * pr.powf(0.33);
    let h = lambda * nu_p / d;
    assert!(re < 200.0 && (h - 18.68).abs() < 0.01, "Re {re} h {h}");
    let sb = SchumannBed::of_spheres(eps, d, rho[0], 1.0, rho_g, c_g, u_sup, h).unwrap();
    assert!(
        (sb.front_speed() - 0.03137).abs() < 1e-5 && (sb.transfer_length() - 2.93e-3).abs() < 1e-5
    );
    // validationDict → the check's spec; sample times are write times before endTime
    let v = case_dict("validationDict");
    let spec = HeatingSpec {
        initial_temperature: v.f64("initialTemperature").unwrap(),
        inlet_temperature: v.f64("inletTemperature").unwrap(),
        cell_size: 3e-3,
        position_cells: v.f64("positionToleranceCells").unwrap(),
        position_fraction: v.f64("positionTolerance").unwrap(),
        width_cells: v.f64("widthToleranceCells").unwrap(),
        width_fraction: v.f64("widthTolerance").unwrap(),
    };
    let times = v.stream("sampleTimes").unwrap()[0].as_f64_list().unwrap();
    let cd = case_dict("CFD/system/controlDict");
    let (end, write) = (cd.f64("endTime").unwrap(), cd.f64("writeInterval").unwrap());
    for t in &times {
        assert!(
            *t <= end + 1e-12 && ((t / write).round() * write - t).abs() < 1e-9,
            "{t}"
        );
    }
    // the slices inside the bed (centres below height − d) hold every front at every time:
    // Schumann's own cell averages there pass
    let n = ((bed.height - d) / 3e-3) as usize;
    let snaps: Vec<Snapshot> = times
        .iter()
        .map(|&t| {
            let mut s = sampled(&sb, t, &|x| x);
            for p in [&mut s.gas, &mut s.solid] {
                p.z.truncate(n);
                p.temperature.truncate(n);
            }
            s
        })
        .collect();
    let r = check(&sb, &spec, &snaps).unwrap();
    assert!(r.pass(), "{r:?}");
    let last = r.fronts.last().unwrap();
    assert!(
        last.reference_position > 0.075 && last.reference_position < 0.08,
        "{last:?}"
    );
}

#[test]
fn the_case_init_deck_packs_on_the_native_dem() {
    let deck = testkit::repo_root().join("openfoam-cases/packed-bed-heating/DEM/in.liggghts_init");
    let vars: Vec<(String, String)> = [("np", "100"), ("tsettle", "300")]
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    let init = liggghts_deck::Deck::read_with_vars(deck, &vars).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let sim = dem::Simulation::from_deck(&init, dir.path()).unwrap();
    assert_eq!(sim.particles.len(), 100);
    for x in &sim.particles.x {
        assert!(x[0] > 0.0 && x[0] < 0.024 && x[1] > 0.0 && x[1] < 0.024 && x[2] > 0.0);
    }
    assert!(dir.path().join("post/packed.data").is_file());
}
