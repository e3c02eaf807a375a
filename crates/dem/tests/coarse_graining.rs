//! LIGGGHTS-PFM's `coarsegraining` on the native DEM, against closed forms: a parcel that
//! stands for CG³ particles rebounds from a wall with the restitution coefficient of the real
//! particle (the e set), its contact lasting CG times as long (Hertz: t_c ∝ δ_max/v and
//! δ_max ∝ R at the same density, E and v; Johnson 1985, eqs. 11.23–11.24); the written radii
//! and skin are scaled; PFM's inconsistent models are refused or warned.

use dem::deck::exec::DeckEvent;
use dem::Simulation;
use liggghts_deck::Deck;
use std::f64::consts::PI;
use std::path::Path;

/// A sphere of written diameter 1 mm and density 2500 falling at 1 m/s onto a wall with e =
/// `e`, the deck's `coarsegraining` line `cg_line` first (empty for real particles).
fn impact_deck(cg_line: &str, e: f64) -> String {
    format!(
        "{cg_line}\natom_style granular\nboundary f f f\nunits si\n\
         region box block -0.01 0.01 -0.01 0.01 0 0.02 units box\ncreate_box 1 box\n\
         neighbor 0.0002 bin\n\
         fix m1 all property/global youngsModulus peratomtype 1e7\n\
         fix m2 all property/global poissonsRatio peratomtype 0.3\n\
         fix m3 all property/global coefficientRestitution peratomtypepair 1 {e}\n\
         fix m4 all property/global coefficientFriction peratomtypepair 1 0.5\n\
         pair_style gran model hertz tangential history\npair_coeff * *\n\
         timestep 1e-8\n\
         fix floor all wall/gran model hertz tangential history primitive type 1 zplane 0\n\
         create_atoms 1 single 0 0 0.005 units box\n\
         set group all diameter 0.001 density 2500\n\
         velocity all set 0 0 -1\nfix integr all nve/sphere\n"
    )
}

/// The simulation of a deck, with its warnings.
fn simulate(src: &str) -> Result<(Simulation, Vec<String>), String> {
    let deck = Deck::parse(src, Path::new("cg.in"), &[]).map_err(|e| e.to_string())?;
    let dir = tempfile::tempdir().unwrap();
    let mut warnings = Vec::new();
    let sim = Simulation::from_deck_observed(&deck, dir.path(), &mut |e| {
        if let DeckEvent::Warning { message, .. } = e {
            warnings.push(message)
        }
    })
    .map_err(|e| e.to_string())?;
    Ok((sim, warnings))
}

/// (radius, mass, rebound speed / impact speed, contact time) of the deck's sphere: placed
/// just above the wall, stepped until it leaves it.
fn impact(src: &str) -> (f64, f64, f64, f64) {
    let (mut s, _) = simulate(src).unwrap();
    let r = s.particles.radius[0];
    s.particles.x[0][2] = r + 1e-9;
    s.invalidate_forces();
    let (mut steps, mut t) = (0u64, 0u64);
    while s.particles.x[0][2] < r + 2e-9 || t == 0 {
        s.run(1).unwrap();
        steps += 1;
        if s.particles.x[0][2] < r {
            t += 1;
        }
        assert!(steps < 2_000_000, "no rebound");
    }
    let m = s.particles.mass[0];
    (r, m, s.particles.v[0][2], t as f64 * 1e-8)
}

#[test]
fn a_parcel_rebounds_with_the_real_restitution_and_cg_times_the_contact_time() {
    let e = 0.3;
    let (r1, m1, v1, t1) = impact(&impact_deck("", e));
    let (r2, m2, v2, t2) = impact(&impact_deck("coarsegraining 2 model_check warn", e));
    eprintln!("real: r {r1:e} e {v1:.6} t_c {t1:e}; parcel: r {r2:e} e {v2:.6} t_c {t2:e}");
    // the written diameter is scaled by CG, the mass with it (CG³ real particles)
    assert!((r2 / r1 - 2.0).abs() < 1e-15);
    assert!((m2 / (8.0 * m1) - 1.0).abs() < 1e-12);
    assert!((m1 / (4.0 / 3.0 * PI * 5e-4f64.powi(3) * 2500.0) - 1.0).abs() < 1e-12);
    // the restitution is the e set (analytic.rs: within 1e-3 at t_c/4000; here t_c/≈2000)
    for v in [v1, v2] {
        assert!((v / e - 1.0).abs() < 2e-3, "rebound {v} for e {e}");
    }
    assert!((v2 / v1 - 1.0).abs() < 1e-3, "{v2} vs {v1}");
    assert!((t2 / t1 - 2.0).abs() < 2e-3, "contact {t2} vs {t1}");
    // the undamped contact time against Hertz's closed form for the parcel
    let (_, m, _, t) = impact(&impact_deck("coarsegraining 2 model_check warn", 1.0));
    // the wall is of the particle's material: 1/Y* = 2(1 − ν²)/E
    let yeff = 1e7 / (2.0 * (1.0 - 0.09));
    let dmax = (15.0 * m * 1.0 / (16.0 * yeff * (1e-3f64).sqrt())).powf(0.4);
    let tc = 2.0 * 1.4716 * dmax;
    assert!((t / tc - 1.0).abs() < 1e-3, "contact {t} vs Hertz {tc}");
}

#[test]
fn the_written_length_scales_are_the_parcels() {
    let src = impact_deck("coarsegraining 3 model_check warn", 0.5);
    let (s, warnings) = simulate(&src).unwrap();
    assert!((s.skin() - 3.0 * 0.0002).abs() < 1e-15, "{}", s.skin());
    assert!((s.particles.radius[0] - 3.0 * 0.0005).abs() < 1e-15);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("create_atoms does not yield consistent results")),
        "{warnings:?}"
    );
}

#[test]
fn pfm_rules_refuse_what_coarse_graining_cannot_scale() {
    // create_atoms with model_check error (the default)
    let e = simulate(&impact_deck("coarsegraining 2", 0.5)).unwrap_err();
    assert!(
        e.contains("cg.in:") && e.contains("create_atoms does not yield consistent results"),
        "{e}"
    );
    // cohesion and rolling friction
    let src = impact_deck("coarsegraining 2 model_check warn", 0.5).replace(
        "pair_style gran model hertz tangential history\n",
        "pair_style gran model hertz tangential history cohesion sjkr\n",
    );
    let e = simulate(&src.replace("model_check warn", "")).unwrap_err();
    assert!(e.contains("cohesion model sjkr"), "{e}");
    let src = impact_deck("coarsegraining 2 model_check warn", 0.5).replace(
        "primitive type 1 zplane 0",
        "rolling_friction cdt primitive type 1 zplane 0",
    );
    let e = simulate(&src.replace("model_check warn", "")).unwrap_err();
    assert!(e.contains("rolling model cdt"), "{e}");
    // it must come first
    let late = impact_deck("", 0.5).replace(
        "neighbor 0.0002 bin\n",
        "neighbor 0.0002 bin\ncoarsegraining 2\n",
    );
    let e = simulate(&late).unwrap_err();
    assert!(e.contains("must come first"), "{e}");
    let after_fix = "atom_style granular\nfix g all gravity 9.81 vector 0 0 -1\ncoarsegraining 2\n";
    let e = simulate(after_fix).unwrap_err();
    assert!(
        e.contains("cg.in:3:") && e.contains("before any `fix`"),
        "{e}"
    );
    let e = simulate(&impact_deck("coarsegraining 0.5", 0.5)).unwrap_err();
    assert!(e.contains("cg.in:1:") && e.contains("≥ 1"), "{e}");
}
