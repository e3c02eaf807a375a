//! The temperature histories of a run with heat (issue 27): the gas at the outlet and the
//! particles' mass-weighted mean against time, `postProcessing/temperatures.png`, and the
//! heat the fluid gives the particles, `postProcessing/heat.png`.

use crate::error::RunError;
use crate::plot::{LinePlot, Series, Style};
use crate::sample::Sample;
use std::path::{Path, PathBuf};

/// Writes the plots when the samples hold temperatures; returns the temperature plot's path,
/// `None` (nothing written) for a run without heat.
pub fn temperatures(samples: &[Sample], post: &Path) -> Result<Option<PathBuf>, RunError> {
    let series = |name: &str, f: fn(&Sample) -> Option<f64>| Series {
        name: name.into(),
        points: samples
            .iter()
            .filter_map(|s| Some((s.time, f(s)?)))
            .collect(),
        style: Style::Line,
    };
    let temps: Vec<Series> = [
        series("gas at the outlet", |s| s.outlet_temperature),
        series("particles, mass-weighted mean", |s| s.particle_temperature),
    ]
    .into_iter()
    .filter(|s| !s.points.is_empty())
    .collect();
    if temps.is_empty() {
        return Ok(None);
    }
    std::fs::create_dir_all(post).map_err(|source| RunError::Io {
        path: post.to_owned(),
        source,
    })?;
    let file = post.join("temperatures.png");
    LinePlot {
        title: "temperature histories".into(),
        x_label: "time (s)".into(),
        y_label: "temperature (K)".into(),
        series: temps,
    }
    .write_png(&file)?;
    let heat: Vec<Series> = [
        series("to the particles, Σ q_p", |s| s.heat_to_particles),
        series("from the fluid, −Σ Tsource ρ c_p V", |s| {
            s.heat_from_fluid
        }),
    ]
    .into_iter()
    .filter(|s| !s.points.is_empty())
    .collect();
    if !heat.is_empty() {
        LinePlot {
            title: "fluid–particle heat transfer rate".into(),
            x_label: "time (s)".into(),
            y_label: "heat flow (W)".into(),
            series: heat,
        }
        .write_png(&post.join("heat.png"))?;
    }
    Ok(Some(file))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_without_heat_writes_nothing_and_one_with_heat_both_plots() {
        let dir = tempfile::tempdir().unwrap();
        let cold: Vec<Sample> = (0..3)
            .map(|k| Sample {
                time: k as f64,
                ..Sample::default()
            })
            .collect();
        assert!(temperatures(&cold, dir.path()).unwrap().is_none());
        assert!(!dir.path().join("temperatures.png").exists());
        let warm: Vec<Sample> = (0..3)
            .map(|k| Sample {
                time: k as f64,
                outlet_temperature: Some(300.0 + k as f64),
                particle_temperature: Some(350.0 - k as f64),
                heat_to_particles: Some(-1.0),
                heat_from_fluid: Some(-1.0),
                ..Sample::default()
            })
            .collect();
        let file = temperatures(&warm, dir.path()).unwrap().unwrap();
        assert!(std::fs::metadata(&file).unwrap().len() > 1000);
        assert!(dir.path().join("heat.png").is_file());
    }
}
