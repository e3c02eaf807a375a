//! The checks of a bubbling fluidised bed (`type fluidisedBed` in `validationDict`).
//!
//! * **Packed bed** (the inlet's ramp, before the bed moves): over the samples with
//!   0.25 u_mf ≤ u ≤ 0.8 u_mf, the mean of Δp / Δp_drag, where Δp_drag is the pressure drop of
//!   the case's drag law through the bed measured at that step
//!   ([`crate::reference::packed_bed_pressure_gradient_with`], model A) and u_mf the velocity at
//!   which that reaches the bed's weight per area on the initial bed
//!   ([`crate::reference::packed_bed_velocity_for`]). Below 0.25 u_mf the fluid is still
//!   accelerating from rest (the first steps read up to 3 × the steady value); above 0.8 u_mf the
//!   bed starts to rearrange.
//! * **Fluidised bed**: the last run of samples with the same inlet velocity (after the ramp);
//!   its second half is the averaging window (the first half holds the bed's lift-off and the
//!   first bubbles, as the Ergun case skips the transient after each step). When the window
//!   lasts at least `averagingTime`: the mean pressure drop against the mean weight of the bed
//!   per cross-section, (m − ρ_f V_p) g / A — the momentum balance of a fluidised bed whose
//!   weight the gas carries (Kunii & Levenspiel, *Fluidization Engineering*, 2nd ed. 1991,
//!   ch. 3) — and the mean bed height ([`crate::bed::Bed::height`], the mean surface over bins
//!   of 2 d₃₂) against the experiment's expanded bed height.
//!
//! Plots: `bed_height.png` (bed height against time with the experiment's value and the
//! window) and `pressure_drop.png` (Δp against time with the bed weight per area and the drag
//! law's packed-bed Δp during the ramp).

use crate::error::RunError;
use crate::plot::{LinePlot, Series, Style};
use crate::reference::{packed_bed_pressure_gradient_with, packed_bed_velocity_for};
use crate::sample::mean_of;
use crate::sample::Sample;
use crate::validation::Check;
use closures::input::DragInput;
use closures::model::ModelType;
use couple::CouplerSettings;
use std::path::Path;

/// What `validationDict` asks of a fluidised bed.
#[derive(Clone, Copy, Debug)]
pub struct Targets<'a> {
    /// The experiment's time-averaged expanded bed height, m.
    pub expanded_bed_height: f64,
    /// Accepted relative error of the mean bed height.
    pub bed_height_tolerance: f64,
    /// Accepted relative error of the mean pressure drop.
    pub pressure_drop_tolerance: f64,
    /// Accepted relative error of the packed bed's pressure drop against the drag law.
    pub packed_bed_tolerance: f64,
    /// Shortest window for the fluidised checks, s.
    pub averaging_time: f64,
    /// `bedHeightKnownGap`: added to a failing bed-height check's message.
    pub bed_height_known_gap: Option<&'a str>,
}

/// The averaging window: the second half of the last run of samples with the same inlet
/// velocity (to 1e-9 relative). `None` when no sample has an inlet velocity.
pub fn window(samples: &[Sample]) -> Option<&[Sample]> {
    let u = samples.last()?.inlet_velocity?;
    let same = |s: &Sample| {
        s.inlet_velocity
            .is_some_and(|v| (v - u).abs() <= 1e-9 * u.abs().max(v.abs()))
    };
    let start = samples.len() - samples.iter().rev().take_while(|s| same(s)).count();
    let plateau = &samples[start..];
    Some(&plateau[plateau.len() / 2..])
}

/// Mean and standard deviation of `f` over `run` (NaN if a sample lacks it).
fn mean_std(run: &[Sample], f: fn(&Sample) -> Option<f64>) -> (f64, f64) {
    let xs: Vec<f64> = run.iter().map(|s| f(s).unwrap_or(f64::NAN)).collect();
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// The packed-bed check of the ramp (see the module's text), with the drag law's Δp per sample
/// for the plot; `None` with a note when it cannot be made.
fn packed_bed(
    settings: &CouplerSettings,
    samples: &[Sample],
    tolerance: f64,
    notes: &mut Vec<String>,
) -> Option<(Check, Vec<(f64, f64)>)> {
    let ph = &settings.physics;
    let Some(drag) = ph.forces.drag else {
        notes.push("fluidised bed: no drag law in couplingProperties: no packed-bed check".into());
        return None;
    };
    if ph.model != ModelType::A {
        notes.push(format!(
            "fluidised bed: the packed-bed reference is model A's; this case is model {}: no \
             packed-bed check",
            ph.model.name()
        ));
        return None;
    }
    let mu = ph.nu * ph.rho;
    let beta = |x: &DragInput| drag.closure.beta(x);
    let first = samples.first()?;
    let (l0, e0, d0, w0) = (
        first.bed_height?,
        first.bed_voidage?,
        first.sauter_diameter?,
        first.weight_per_area?,
    );
    let u_mf = packed_bed_velocity_for(&beta, w0, l0, e0, d0, ph.rho, mu);
    let reference = |s: &Sample| -> Option<f64> {
        Some(
            packed_bed_pressure_gradient_with(
                &beta,
                s.inlet_velocity?,
                s.bed_voidage?,
                s.sauter_diameter?,
                ph.rho,
                mu,
            ) * s.bed_height?,
        )
    };
    let mut ratios = Vec::new();
    let mut curve = Vec::new();
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for s in samples {
        let (Some(u), Some(dp), Some(r)) = (s.inlet_velocity, s.pressure_drop, reference(s)) else {
            continue;
        };
        if u <= u_mf {
            curve.push((s.time, r));
        }
        if (0.25 * u_mf..=0.8 * u_mf).contains(&u) {
            ratios.push(dp / r);
            range = (range.0.min(u), range.1.max(u));
        }
    }
    let law = drag.closure.law.cfdem_name();
    if ratios.is_empty() {
        notes.push(format!(
            "fluidised bed: no sample at 0.25 … 0.8 u_mf ({law} on the initial bed: u_mf = \
             {u_mf:.4} m/s): no packed-bed check"
        ));
        return None;
    }
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    notes.push(format!(
        "fluidised bed: {law} on the initial bed (L = {l0:.5} m, ε = {e0:.4}) fluidises at \
         u_mf = {u_mf:.4} m/s"
    ));
    let check = Check::new(
        &format!(
            "packed bed: pressure drop / {law} packed-bed pressure drop on the measured bed, mean \
             over u = {:.3} … {:.3} m/s",
            range.0, range.1
        ),
        mean,
        1.0,
        "",
        tolerance,
    );
    Some((check, curve))
}

/// The checks of a fluidised bed from `samples` (coupling steps of `dt_c` seconds); notes for
/// the log go to `notes`, plots into `post`.
pub fn checks(
    slabs: &crate::slab_profile::Record,
    settings: &CouplerSettings,
    samples: &[Sample],
    targets: Targets<'_>,
    post: &Path,
    dt_c: f64,
    notes: &mut Vec<String>,
) -> Result<Vec<Check>, RunError> {
    let Some(win) = window(samples).filter(|w| !w.is_empty()) else {
        return Ok(vec![Check::new(
            "samples with an inlet velocity",
            0.0,
            1.0,
            "",
            0.0,
        )]);
    };
    let mut checks = Vec::new();
    let packed = packed_bed(settings, samples, targets.packed_bed_tolerance, notes);
    let curve = packed.as_ref().map_or(vec![], |p| p.1.clone());
    checks.extend(packed.map(|p| p.0));
    let mean = mean_of(win);
    let (t0, t1) = (win[0].time - dt_c, win[win.len() - 1].time);
    let u = mean.inlet_velocity.unwrap_or(f64::NAN);
    let (h, h_std) = mean_std(win, |s| s.bed_height);
    let (dp, dp_std) = mean_std(win, |s| s.pressure_drop);
    notes.push(format!(
        "fluidised bed: over t = {t0:.3} … {t1:.3} s at u = {u:.4} m/s the bed height is {h:.4} \
         ± {h_std:.4} m and Δp {dp:.2} ± {dp_std:.2} Pa (mean ± standard deviation)"
    ));
    let span = t1 - t0;
    if span + 1e-9 >= targets.averaging_time {
        checks.push(Check::new(
            &format!(
                "fluidised bed: mean pressure drop over t = {t0:.3} … {t1:.3} s at u = {u:.4} m/s \
                 vs bed weight per area"
            ),
            dp,
            mean.weight_per_area.unwrap_or(f64::NAN),
            "Pa",
            targets.pressure_drop_tolerance,
        ));
        checks.push(
            Check::new(
                &format!(
                "fluidised bed: mean bed height over t = {t0:.3} … {t1:.3} s vs the experiment's \
                 expanded bed"
            ),
                h,
                targets.expanded_bed_height,
                "m",
                targets.bed_height_tolerance,
            )
            .with_known_gap(targets.bed_height_known_gap),
        );
        checks.extend(slabs.checks((t0, t1), notes));
    } else {
        notes.push(format!(
            "fluidised bed: Δp and bed height are not checked: the averaging window (the second \
             half of the last inlet-velocity plateau) lasts {span:.3} s, shorter than \
             averagingTime ({} s); the plateau must last {} s",
            targets.averaging_time,
            2.0 * targets.averaging_time,
        ));
    }
    plots(samples, targets, post, (t0, t1), curve)?;
    Ok(checks)
}

fn plots(
    samples: &[Sample],
    targets: Targets<'_>,
    post: &Path,
    (t0, t1): (f64, f64),
    packed_curve: Vec<(f64, f64)>,
) -> Result<(), RunError> {
    let t_end = samples.last().map_or(0.0, |s| s.time);
    let series_of = |f: fn(&Sample) -> Option<f64>| -> Vec<(f64, f64)> {
        samples
            .iter()
            .filter_map(|s| Some((s.time, f(s)?)))
            .collect()
    };
    let heights = series_of(|s| s.bed_height);
    let top = heights.iter().map(|p| p.1).fold(0.0f64, f64::max);
    LinePlot {
        title: "Fluidised bed: bed height against time".into(),
        x_label: "time (s)".into(),
        y_label: "bed height (m)".into(),
        series: vec![
            Series {
                name: "simulated (mean surface over 2 d bins)".into(),
                points: heights,
                style: Style::Line,
            },
            Series {
                name: "experiment's expanded bed".into(),
                points: vec![
                    (0.0, targets.expanded_bed_height),
                    (t_end, targets.expanded_bed_height),
                ],
                style: Style::Line,
            },
            Series {
                name: "averaging window".into(),
                points: vec![(t0, 0.0), (t0, top), (t1, top), (t1, 0.0)],
                style: Style::Line,
            },
        ],
    }
    .write_png(&post.join("bed_height.png"))?;
    let weight = series_of(|s| s.weight_per_area);
    LinePlot {
        title: "Fluidised bed: pressure drop against time".into(),
        x_label: "time (s)".into(),
        y_label: "pressure drop (Pa)".into(),
        series: vec![
            Series {
                name: "simulated".into(),
                points: series_of(|s| s.pressure_drop),
                style: Style::Line,
            },
            Series {
                name: "bed weight per area".into(),
                points: weight,
                style: Style::Line,
            },
            Series {
                name: "drag law's packed bed (u ≤ u_mf)".into(),
                points: packed_curve,
                style: Style::Line,
            },
        ],
    }
    .write_png(&post.join("pressure_drop.png"))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fluidised-bed case's coupling settings (BeetstraDrag, model A, air).
    fn settings() -> CouplerSettings {
        let cfd =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../openfoam-cases/fluidised-bed/CFD");
        couple::CouplingConfig::read_case(&cfd)
            .unwrap()
            .coupler_settings(&cfd)
            .unwrap()
    }

    fn sample(t: f64, u: f64, dp: f64, h: f64) -> Sample {
        Sample {
            time: t,
            inlet_velocity: Some(u),
            pressure_drop: Some(dp),
            bed_height: Some(h),
            weight_per_area: Some(100.0),
            ..Sample::default()
        }
    }

    /// A ramp, then a plateau whose second half alternates around the weight and a height.
    fn run(n_plateau: usize) -> Vec<Sample> {
        let dt = 0.01;
        let mut s: Vec<Sample> = (1..=10)
            .map(|i| sample(i as f64 * dt, 0.05 * i as f64, 10.0 * i as f64, 0.03))
            .collect();
        for k in 0..n_plateau {
            let t = (11 + k) as f64 * dt;
            let first_half = k < n_plateau / 2;
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            let (dp, h) = if first_half {
                (300.0, 0.03)
            } else {
                (100.0 + 5.0 * sign, 0.05 + 0.01 * sign)
            };
            s.push(sample(t, 1.0, dp, h));
        }
        s
    }

    fn targets() -> Targets<'static> {
        Targets {
            expanded_bed_height: 0.05,
            bed_height_tolerance: 0.01,
            pressure_drop_tolerance: 0.01,
            packed_bed_tolerance: 0.01,
            averaging_time: 0.2,
            bed_height_known_gap: None,
        }
    }

    #[test]
    fn the_window_is_the_second_half_of_the_last_plateau() {
        let s = run(40);
        let w = window(&s).unwrap();
        assert_eq!(w.len(), 20);
        assert!((w[0].time - 0.31).abs() < 1e-12);
        assert!(window(&[]).is_none());
    }

    #[test]
    fn a_failing_height_check_carries_the_known_gap() {
        let dir = tempfile::tempdir().unwrap();
        let with_gap = |height: f64| {
            let t = Targets {
                expanded_bed_height: height,
                bed_height_known_gap: Some("the reason"),
                ..targets()
            };
            let rec = crate::slab_profile::Record::default();
            checks(
                &rec,
                &settings(),
                &run(40),
                t,
                dir.path(),
                0.01,
                &mut vec![],
            )
            .unwrap()
        };
        // the run's mean height is 0.05 m: against 0.06 m the height check fails
        let c = with_gap(0.06);
        assert!(
            !c[1].pass && c[1].name.ends_with("known gap: the reason"),
            "{c:?}"
        );
        assert!(c[0].pass && !c[0].name.contains("known gap"), "{c:?}");
        let c = with_gap(0.05);
        assert!(
            c.iter().all(|c| c.pass && !c.name.contains("known gap")),
            "{c:?}"
        );
    }

    #[test]
    fn pressure_drop_and_height_are_averaged_over_the_window() {
        let dir = tempfile::tempdir().unwrap();
        let mut notes = vec![];
        // no voidage in these samples: no packed-bed check
        let c = checks(
            &crate::slab_profile::Record::default(),
            &settings(),
            &run(40),
            targets(),
            dir.path(),
            0.01,
            &mut notes,
        )
        .unwrap();
        assert_eq!(c.len(), 2, "{c:?}");
        // ± alternation over an even count averages out exactly
        assert!((c[0].simulated - 100.0).abs() < 1e-12 && c[0].pass, "{c:?}");
        assert!((c[1].simulated - 0.05).abs() < 1e-12 && c[1].pass, "{c:?}");
        assert!(dir.path().join("bed_height.png").is_file());
        // A window shorter than averagingTime checks neither, and says so.
        let mut notes = vec![];
        let c = checks(
            &crate::slab_profile::Record::default(),
            &settings(),
            &run(20),
            targets(),
            dir.path(),
            0.01,
            &mut notes,
        )
        .unwrap();
        assert!(c.is_empty(), "{c:?}");
        assert!(notes.iter().any(|n| n.contains("not checked")), "{notes:?}");
    }

    #[test]
    fn the_packed_bed_is_checked_between_a_quarter_and_four_fifths_of_u_mf() {
        // A ramp 0 … 0.5 m/s over a bed of L 0.0325 m, ε 0.404, d 1.2 mm whose weight per area
        // (189.6 Pa) BeetstraDrag reaches at u_mf ≈ 0.363 m/s; Δp is 2 % above the law inside
        // 0.25 … 0.8 u_mf and 50 % off outside it, where it must not count.
        let st = settings();
        let beta = |x: &DragInput| st.physics.forces.drag.unwrap().closure.beta(x);
        let (rho, mu) = (st.physics.rho, st.physics.rho * st.physics.nu);
        let (l, e, d, w) = (0.0325, 0.404, 1.2e-3, 189.6);
        let u_mf = packed_bed_velocity_for(&beta, w, l, e, d, rho, mu);
        assert!((u_mf - 0.363).abs() < 0.002, "{u_mf}");
        let samples: Vec<Sample> = (1..=100)
            .map(|k| {
                let u = 0.005 * k as f64;
                let r = packed_bed_pressure_gradient_with(&beta, u, e, d, rho, mu) * l;
                let inside = (0.25 * u_mf..=0.8 * u_mf).contains(&u);
                Sample {
                    time: 0.001 * k as f64,
                    inlet_velocity: Some(u),
                    pressure_drop: Some(r * if inside { 1.02 } else { 1.5 }),
                    bed_height: Some(l),
                    bed_voidage: Some(e),
                    sauter_diameter: Some(d),
                    weight_per_area: Some(w),
                    ..Sample::default()
                }
            })
            .collect();
        let mut notes = vec![];
        let (c, curve) = packed_bed(&st, &samples, 0.05, &mut notes).unwrap();
        assert!((c.simulated - 1.02).abs() < 1e-12 && c.pass, "{c:?}");
        assert!(!curve.is_empty());
        assert!(notes.iter().any(|n| n.contains("u_mf = 0.36")), "{notes:?}");
    }
}
