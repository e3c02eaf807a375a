//! CFDEM-PFM's smoothing models ([`couple::smoothing`]) on the native diffusion step
//! (`runner::smoothing`), against closed forms: the point-source response of one implicit
//! diffusion step (the kernel of (1 − L²∇²)⁻¹), the heat kernel that n steps of length L/√n
//! tend to, the implicit Euler relaxation of a step change, and the particle volume.

use couple::smoothing::{SmoothingModel, SmoothingSettings};
use mesh::build::uniform_box;
use runner::smoothing::native;

/// A row of `n` cubes of side h along x, walls all round (zero gradient: a 1-D problem).
fn row(n: usize, h: f64) -> foam::PolyMesh {
    uniform_box([0.0; 3], [n as f64 * h, h, h], [n, 1, 1])
}

/// No bounds that act.
fn spatial(length: f64) -> SmoothingSettings {
    SmoothingSettings {
        length,
        lower: -1e99,
        upper: 1e99,
    }
}

/// Σ V (1 − ε), m³.
fn solid(eps: &[f64], v: f64) -> f64 {
    eps.iter().map(|e| (1.0 - e) * v).sum()
}

/// Asserts that `eps` around the source `source` in cell `mid` is the resolvent kernel of
/// length `l` on cells of size `h` within the tolerance of
/// [`one_step_on_a_point_source_is_the_resolvent_kernel`], out to 50 cells, symmetric; returns
/// the largest relative difference.
fn assert_resolvent_kernel(eps: &[f64], mid: usize, source: f64, h: f64, l: f64) -> f64 {
    let hl = h / l;
    let mut worst: f64 = 0.0;
    for i in 0..=50 {
        let x = i as f64 * h;
        let kernel = source * h * (-x / l).exp() / (2.0 * l);
        let rel = ((1.0 - eps[mid + i]) - kernel).abs() / kernel;
        let tol = (x / l) * hl * hl / 24.0 + hl * hl / 8.0 + 1e-10;
        assert!(rel <= tol, "x = {i} h: {rel:e} > {tol:e}");
        // symmetric
        assert!((eps[mid + i] - eps[mid - i]).abs() < 1e-14);
        worst = worst.max(rel);
    }
    worst
}

/// One step of length L on a point source: the solid fraction φ = 1 − ε at distance x is
/// s·h·e^(−|x|/L)/(2L), the 1-D kernel of (1 − L²∇²)⁻¹ (the Green's function of
/// φ − L² φ'' = s h δ). The three-point scheme on cells of size h has the exact discrete solution
/// A·e^(−θ|i|) with cosh θ = 1 + (h/L)²/2, i.e. θ = 2 asinh(h/2L) = (h/L)(1 − (h/L)²/24 + …),
/// and A = s tanh(θ/2) = (s h/2L)(1 − (h/L)²/8 + …): the relative difference from the
/// continuous kernel at |x| is at most (|x|/L)(h/L)²/24 + (h/L)²/8 (to leading order), the
/// tolerance used (4.2e-3 at |x| = 5L with h/L = 0.1), plus the solver's 1e-10.
#[test]
fn one_step_on_a_point_source_is_the_resolvent_kernel() {
    let (n, h, l) = (401, 1e-3, 1e-2);
    let s = native(&row(n, h), spatial(l)).unwrap();
    let mid = n / 2;
    let source = 0.5;
    let mut eps = vec![1.0; n];
    eps[mid] = 1.0 - source;
    let v = h * h * h;
    let before = solid(&eps, v);
    let r = s.smooth(&mut eps).unwrap();
    assert_eq!((r.bounded_cells, r.lagged_volume), (0, 0.0));
    // the integral: zero flux through the walls (solver tolerance 1e-14 of the residual)
    assert!((solid(&eps, v) - before).abs() <= 1e-12 * before);
    let hl = h / l;
    let worst = assert_resolvent_kernel(&eps, mid, source, h, l);
    // the bound is not loose by orders of magnitude (the check can fail)
    assert!(
        worst > 0.3 * (5.0 * hl * hl / 24.0 + hl * hl / 8.0),
        "{worst:e}"
    );
}

/// n steps of length ℓ = L/√n on a point source tend to the heat kernel of D t = L² (variance
/// σ² = 2L²): φ(x) = s h e^(−x²/4L²)/√(4π L²). The three-point step's kernel has the
/// characteristic function 1/(1 + 4(ℓ/h)² sin²(kh/2)): variance exactly 2ℓ², excess kurtosis
/// 3 + (h/ℓ)²/2 (the continuous step's 3 plus the grid's part), so the n-step kernel is the
/// Gaussian times 1 + (γ₂/24) He₄(x/σ) + O(1/n²) with γ₂ = (3 + (h/ℓ)²/2)/n (Edgeworth), and
/// |He₄| ≤ 6 for |x| ≤ 2σ; the next terms (γ₄/720)He₆ + (γ₂²/1152)He₈, with the Laplace
/// kernel's γ₄ = 30/n², are at most 1.5/n² there. Tolerance: (3 + (h/ℓ)²/2)/(4n) + 1.5/n²
/// (0.0200 for n = 40, h/ℓ = 0.32; the walls, 7.5σ away, reflect e^(−28) of it).
#[test]
fn repeated_steps_tend_to_the_gaussian_heat_kernel() {
    let (cells, h, l, steps) = (601, 1e-3, 2e-2, 40);
    let step = l / (steps as f64).sqrt();
    let s = native(&row(cells, h), spatial(step)).unwrap();
    let mid = cells / 2;
    let source = 0.5;
    let mut eps = vec![1.0; cells];
    eps[mid] = 1.0 - source;
    for _ in 0..steps {
        s.smooth(&mut eps).unwrap();
    }
    let sigma = (2.0f64).sqrt() * l;
    let hl = h / step;
    let nf = steps as f64;
    let leading = (3.0 + hl * hl / 2.0) / (4.0 * nf);
    let tol = leading + 1.5 / (nf * nf);
    let mut worst: f64 = 0.0;
    for i in 0..=(2.0 * sigma / h) as usize {
        let x = i as f64 * h;
        let gauss = source * h * (-x * x / (4.0 * l * l)).exp()
            / (4.0 * std::f64::consts::PI * l * l).sqrt();
        let rel = ((1.0 - eps[mid + i]) - gauss).abs() / gauss;
        assert!(rel <= tol, "x = {i} h: {rel:e} > {tol:e}");
        worst = worst.max(rel);
    }
    // a single step of length L is far from it: the limit is what is tested
    let s1 = native(&row(cells, h), spatial(l)).unwrap();
    let mut one = vec![1.0; cells];
    one[mid] = 1.0 - source;
    s1.smooth(&mut one).unwrap();
    let peak = source * h / (4.0 * std::f64::consts::PI * l * l).sqrt();
    assert!(((1.0 - one[mid]) - peak).abs() / peak > 0.2);
    // the leading term is the error: the check is not loose
    assert!(worst > 0.5 * leading, "{worst:e}");
    println!("worst {worst:e}, tolerance {tol:e}");
}

/// The temporal models relax a step change of the unsmoothed ε from a to b as implicit Euler
/// steps: temporalSmoothing ε_n − b = (a − b)(γ/(1+γ))ⁿ, constDiffAndTemporalSmoothing
/// ε_n − b = (a − b)(1+γ)⁻ⁿ, to round-off (a uniform field: diffusion leaves it unchanged).
/// For γ small the latter is the continuous relaxation e^(−nγ) (time scale Δt/γ) within the
/// implicit Euler step's error |(1+γ)⁻ⁿ − e^(−nγ)| ≤ nγ²/2.
#[test]
fn temporal_models_relax_a_step_change_in_closed_form() {
    let (n, h) = (8, 1e-3);
    let mesh = row(n, h);
    let (a, b) = (1.0, 0.6);
    for gamma in [0.01, 0.5, 2.0] {
        let temporal = native(
            &mesh,
            SmoothingModel::Temporal {
                gamma,
                lower: 0.0,
                upper: 1.0,
            },
        )
        .unwrap();
        let both = native(
            &mesh,
            SmoothingModel::ConstDiffAndTemporal {
                spatial: spatial(3e-3),
                gamma,
            },
        )
        .unwrap();
        // the history starts at ε = 1 = a: the unsmoothed ε steps to b at the first exchange
        for k in 1..=200 {
            let mut e1 = vec![b; n];
            let mut e2 = vec![b; n];
            temporal.smooth(&mut e1).unwrap();
            let r2 = both.smooth(&mut e2).unwrap();
            let want1 = b + (a - b) * (gamma / (1.0 + gamma)).powi(k);
            let want2 = b + (a - b) * (1.0 + gamma).powi(-k);
            for i in 0..n {
                assert!((e1[i] - want1).abs() < 1e-12, "γ {gamma} k {k}");
                assert!((e2[i] - want2).abs() < 1e-12, "γ {gamma} k {k}");
            }
            // the lag is reported: what the fluid's ε holds plus the lag is the particles'
            let v = h * h * h;
            let lag = (want2 - b) * v * n as f64;
            assert!((r2.lagged_volume - lag).abs() < 1e-12 * v * n as f64);
            if gamma == 0.01 {
                let continuous = b + (a - b) * (-(k as f64) * gamma).exp();
                let bound = (a - b) * k as f64 * gamma * gamma / 2.0;
                assert!((e2[0] - continuous).abs() <= bound, "k {k}");
            }
        }
    }
}

/// Each model conserves the particle volume Σ V(1 − ε) while it is steady: the spatial step
/// exactly (to the solver's tolerance), the relaxation as the weighted mean of the history's
/// and this exchange's integral, so the integral of a steady bed that moves relaxes to the
/// particles' volume geometrically and the fluid's integral plus the reported lag is the
/// particles' volume at every exchange.
#[test]
fn every_model_conserves_the_particle_volume() {
    let mesh = uniform_box([0.0; 3], [0.012; 3], [12, 12, 12]);
    let v = 1e-9;
    let n = 12 * 12 * 12;
    // a bed of 40 cells at ε = 0.4 that moves one cell per exchange
    let bed = |shift: usize| {
        let mut e = vec![1.0; n];
        for k in 0..40 {
            e[(k * 37 + shift * 13) % n] = 0.4;
        }
        e
    };
    let total = solid(&bed(0), v);
    let gamma = 0.3;
    let models = [
        SmoothingModel::ConstDiff(spatial(2e-3)),
        SmoothingModel::Temporal {
            gamma,
            lower: -1e99,
            upper: 1e99,
        },
        SmoothingModel::ConstDiffAndTemporal {
            spatial: spatial(2e-3),
            gamma,
        },
    ];
    for m in models {
        let s = native(&mesh, m).unwrap();
        // the weight the history keeps per exchange
        let keep = match m {
            SmoothingModel::ConstDiff(_) | SmoothingModel::LocalPSizeDiff { .. } => 0.0,
            SmoothingModel::Temporal { .. } => gamma / (1.0 + gamma),
            SmoothingModel::ConstDiffAndTemporal { .. } => 1.0 / (1.0 + gamma),
        };
        for k in 1..=30 {
            let mut e = bed(k);
            let r = s.smooth(&mut e).unwrap();
            let held = solid(&e, v);
            assert!(
                (held + r.lagged_volume - total).abs() <= 1e-12 * total,
                "{}: exchange {k}",
                m.name()
            );
            // the integral relaxes from 0 (the history starts at ε = 1)
            let want = total * (1.0 - keep.powi(k as i32));
            assert!((held - want).abs() <= 1e-12 * total, "{} {k}", m.name());
        }
    }
}

/// Bad settings are errors naming the key.
#[test]
fn bad_temporal_settings_are_errors() {
    let mesh = row(3, 1.0);
    let e = native(
        &mesh,
        SmoothingModel::Temporal {
            gamma: -1.0,
            lower: 0.0,
            upper: 1.0,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("temporalSmoothing") && e.contains("gamma"),
        "{e}"
    );
    let e = native(
        &mesh,
        SmoothingModel::ConstDiffAndTemporal {
            spatial: spatial(0.0),
            gamma: 1.0,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("smoothingLength"), "{e}");
}

/// `constDiffAndTemporalSmoothing` on the coupler: the fluid receives at exchange k a solid
/// volume Σ V(1 − ε) = V_p (1 − (1+γ)⁻ᵏ) (the history starts at ε = 1, the particle stays in
/// the mesh), and the step's clipped volume reports the rest, V_p (1+γ)⁻ᵏ, so the two add up
/// to the particle's volume at every exchange.
#[test]
fn the_coupler_hands_the_fluid_the_relaxed_voidage_and_reports_the_lag() {
    use closures::model::ModelType;
    use couple::config::Forces;
    use couple::memory::{MemoryFluid, MemoryParticles};
    use couple::{Coupler, CouplerSettings, FluidSide, Physics};
    use mesh::v3::V3;
    let d = 1e-3;
    let mesh = uniform_box([0.0; 3], [0.01; 3], [10, 10, 10]);
    let mut fluid = MemoryFluid::uniform(mesh, V3::zeros());
    let (centre, r) = (V3::new(0.0031, 0.0062, 0.0044), d / 2.0);
    let mut particles = MemoryParticles::new(vec![centre], vec![r], 2500.0, 1e-5);
    let settings = CouplerSettings {
        method: voidage::Method::Exact,
        alpha_min: None,
        coupling_interval: 1,
        physics: Physics {
            rho: 1000.0,
            nu: 1e-6,
            gravity: V3::zeros(),
            model: ModelType::A,
            forces: Forces::default(),
            implicit_couple: true,
        },
        heat: None,
    };
    let mut coupler = Coupler::new(fluid.mesh(), settings).unwrap();
    let gamma = 0.5;
    let model = SmoothingModel::ConstDiffAndTemporal {
        spatial: spatial(1e-3),
        gamma,
    };
    coupler.set_smoothing(native(fluid.mesh(), model).unwrap());
    let mut clipped = Vec::new();
    coupler
        .run(&mut particles, &mut fluid, 4, |s| {
            clipped.push(s.voidage.clipped_volume)
        })
        .unwrap();
    let vols = coupler.voidage_mesh().cell_volumes().to_vec();
    let vp = std::f64::consts::PI * d * d * d / 6.0;
    assert_eq!(fluid.received.len(), 4);
    for (k, got) in fluid.received.iter().enumerate() {
        let held: f64 = got
            .voidage_new
            .iter()
            .zip(&vols)
            .map(|(e, v)| (1.0 - e) * v)
            .sum();
        let lag = vp * (1.0 + gamma).powi(-(k as i32 + 1));
        assert!(
            (held - (vp - lag)).abs() < 1e-9 * vp,
            "exchange {k}: {held}"
        );
        assert!(
            (clipped[k] - lag).abs() < 1e-9 * vp,
            "exchange {k}: {}",
            clipped[k]
        );
    }
}

/// `localPSizeDiffSmoothing` with Csmoothing c and dSmoothingLength L₀.
fn local(c: f64, l0: f64) -> SmoothingModel {
    SmoothingModel::LocalPSizeDiff {
        spatial: spatial(l0),
        c,
    }
}

/// `localPSizeDiffSmoothing` with one particle size d everywhere is one implicit step of length
/// L = c·d: on a point source the same resolvent kernel s·h·e^(−|x|/L)/(2L) as
/// [`one_step_on_a_point_source_is_the_resolvent_kernel`], with its discrete tolerance; and
/// dSmoothingLength (here 3 L, in no cell) changes nothing.
#[test]
fn local_size_smoothing_of_one_size_is_the_resolvent_kernel() {
    let (n, h, d, c) = (401, 1e-3, 4e-3, 2.5);
    let l = c * d;
    let s = native(&row(n, h), local(c, 3.0 * l)).unwrap();
    let mid = n / 2;
    let source = 0.5;
    let mut eps = vec![1.0; n];
    eps[mid] = 1.0 - source;
    let v = h * h * h;
    let before = solid(&eps, v);
    let diameters = vec![d; n];
    let r = s.smooth_sized(&mut eps, Some(&diameters)).unwrap();
    assert_eq!((r.bounded_cells, r.lagged_volume), (0, 0.0));
    assert!((solid(&eps, v) - before).abs() <= 1e-12 * before);
    assert_resolvent_kernel(&eps, mid, source, h, l);
    // without the sizes the model refuses (it never falls back silently)
    assert!(s.smooth(&mut eps).is_err());
}

/// The length follows the local size: particles of d₁ on the left half (L₁ = c d₁ = 3h) and on
/// the right half either particles of d₂ = d₁/2 (L₂ = 1.5h) or none (dSmoothingLength L₀ =
/// 1.5h), a source in the two cells between them. Each side decays away from the source by
/// its own discrete root r_i < 1 of k_i r² − (1 + 2k_i) r + k_i = 0, k_i = (L_i/h)² (the
/// three-point recurrence of constant coefficients within a side; the walls, 100 cells away,
/// reflect r^200), to the solver's tolerance; the particle volume is conserved.
#[test]
fn local_size_smoothing_follows_the_local_size_and_conserves() {
    let (n, h, c) = (300, 1e-3, 2.0);
    let d1 = 1.5e-3;
    let root = |l: f64| {
        let k = (l / h).powi(2);
        ((1.0 + 2.0 * k) - ((1.0 + 2.0 * k).powi(2) - 4.0 * k * k).sqrt()) / (2.0 * k)
    };
    let (l1, l_right) = (c * d1, 1.5e-3);
    assert!((root(l1) - root(l_right)).abs() > 0.15);
    for right in [d1 / 2.0, 0.0] {
        let s = native(&row(n, h), local(c, l_right)).unwrap();
        let diameters: Vec<f64> = (0..n).map(|i| if i < 150 { d1 } else { right }).collect();
        let mut eps = vec![1.0; n];
        eps[149] = 0.4;
        eps[150] = 0.4;
        let v = h * h * h;
        let before = solid(&eps, v);
        let r = s.smooth_sized(&mut eps, Some(&diameters)).unwrap();
        assert_eq!(r.bounded_cells, 0);
        assert!((solid(&eps, v) - before).abs() <= 1e-12 * before);
        let phi = |i: usize| 1.0 - eps[i];
        for i in 130..148 {
            let ratio = phi(i - 1) / phi(i);
            assert!((ratio - root(l1)).abs() < 1e-8, "left {i}: {ratio}");
        }
        for i in 152..162 {
            let ratio = phi(i + 1) / phi(i);
            assert!((ratio - root(l_right)).abs() < 1e-7, "right {i}: {ratio}");
        }
    }
}
