//! The checks of a bubbling fluidised bed (`type fluidisedBed` in `validationDict`).
//!
//! The bed is fluidised at a constant inlet velocity: the last run of samples with the same
//! inlet velocity (after the inlet table's ramp). Its second half is the averaging window (the
//! first half holds the bed's expansion and the first bubbles, as the Ergun case skips the
//! transient after each step). Over the window:
//!
//! * the mean pressure drop inlet → outlet against the mean weight of the bed per
//!   cross-section, (m − ρ_f V_p) g / A — the momentum balance of a fluidised bed whose weight
//!   is carried by the gas, not the walls (Kunii & Levenspiel, *Fluidization Engineering*, 2nd
//!   ed. 1991, ch. 3);
//! * when the window lasts at least `averagingTime`, the mean bed height
//!   ([`crate::bed::Bed::height`], the mean surface over bins of 2 d₃₂) against the experiment's
//!   expanded bed height.
//!
//! Plots: `bed_height.png` (bed height against time with the experiment's value and the
//! window) and `pressure_drop.png` (Δp against time with the bed weight per area).

use crate::checks::mean_of;
use crate::plot::{LinePlot, Series, Style};
use crate::run::RunError;
use crate::sample::Sample;
use crate::validation::Check;
use std::path::Path;

/// What `validationDict` asks of a fluidised bed.
#[derive(Clone, Copy, Debug)]
pub struct Targets {
    /// The experiment's time-averaged expanded bed height, m.
    pub expanded_bed_height: f64,
    /// Accepted relative error of the mean bed height.
    pub bed_height_tolerance: f64,
    /// Accepted relative error of the mean pressure drop.
    pub pressure_drop_tolerance: f64,
    /// Shortest window for the bed-height check, s.
    pub averaging_time: f64,
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

/// The checks over the window of `samples` (coupling steps of `dt_c` seconds); notes for the
/// log go to `notes`, plots into `post`.
pub fn checks(
    samples: &[Sample],
    targets: Targets,
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
    let mean = mean_of(win);
    let (t0, t1) = (win[0].time - dt_c, win[win.len() - 1].time);
    let u = mean.inlet_velocity.unwrap_or(f64::NAN);
    let v = |x: Option<f64>| x.unwrap_or(f64::NAN);
    let (h, h_std) = mean_std(win, |s| s.bed_height);
    let (dp, dp_std) = mean_std(win, |s| s.pressure_drop);
    if let Some(h0) = samples.first().and_then(|s| s.bed_height) {
        notes.push(format!(
            "fluidised bed: packed bed {h0:.4} m high at the start; over t = {t0:.3} … {t1:.3} s \
             at u = {u:.4} m/s the bed height is {h:.4} ± {h_std:.4} m and Δp {dp:.2} ± \
             {dp_std:.2} Pa (mean ± standard deviation)"
        ));
    }
    let mut checks = vec![Check::new(
        &format!(
            "fluidised bed: mean pressure drop over t = {t0:.3} … {t1:.3} s at u = {u:.4} m/s vs \
             bed weight per area"
        ),
        dp,
        v(mean.weight_per_area),
        "Pa",
        targets.pressure_drop_tolerance,
    )];
    let span = t1 - t0;
    if span + 1e-9 >= targets.averaging_time {
        checks.push(Check::new(
            &format!(
                "fluidised bed: mean bed height over t = {t0:.3} … {t1:.3} s vs the experiment's \
                 expanded bed"
            ),
            h,
            targets.expanded_bed_height,
            "m",
            targets.bed_height_tolerance,
        ));
    } else {
        notes.push(format!(
            "fluidised bed: the bed height is not checked: the averaging window ({span:.3} s) is \
             shorter than averagingTime ({} s); run to t ≥ {:.3} s",
            targets.averaging_time,
            // the window is the second half of the plateau: the plateau must last twice as long
            t1 + 2.0 * (targets.averaging_time - span),
        ));
    }
    plots(samples, targets, post, (t0, t1))?;
    Ok(checks)
}

fn plots(
    samples: &[Sample],
    targets: Targets,
    post: &Path,
    (t0, t1): (f64, f64),
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
        ],
    }
    .write_png(&post.join("pressure_drop.png"))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn the_window_is_the_second_half_of_the_last_plateau() {
        let s = run(40);
        let w = window(&s).unwrap();
        assert_eq!(w.len(), 20);
        assert!((w[0].time - 0.31).abs() < 1e-12);
        assert!(window(&[]).is_none());
    }

    #[test]
    fn pressure_drop_and_height_are_averaged_over_the_window() {
        let dir = tempfile::tempdir().unwrap();
        let targets = Targets {
            expanded_bed_height: 0.05,
            bed_height_tolerance: 0.01,
            pressure_drop_tolerance: 0.01,
            averaging_time: 0.2,
        };
        let mut notes = vec![];
        let c = checks(&run(40), targets, dir.path(), 0.01, &mut notes).unwrap();
        assert_eq!(c.len(), 2, "{c:?}");
        // ± alternation over an even count averages out exactly
        assert!((c[0].simulated - 100.0).abs() < 1e-12 && c[0].pass, "{c:?}");
        assert!((c[1].simulated - 0.05).abs() < 1e-12 && c[1].pass, "{c:?}");
        assert!(dir.path().join("bed_height.png").is_file());
        // A window shorter than averagingTime checks Δp only, and says so.
        let mut notes = vec![];
        let c = checks(&run(20), targets, dir.path(), 0.01, &mut notes).unwrap();
        assert_eq!(c.len(), 1);
        assert!(notes.iter().any(|n| n.contains("not checked")), "{notes:?}");
    }
}
