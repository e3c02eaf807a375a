//! The checks of the reference cases, computed from the run's samples and the case's own
//! parameters, with their plots.
//!
//! * `ergunPackedBed`: the samples are grouped into plateaus of constant inlet velocity; the
//!   mean over the second half of each plateau (the developed flow) is compared with Ergun's equation
//!   ([`crate::reference::ergun_pressure_gradient`]) using the bed height, voidage and Sauter
//!   diameter measured from the particles at that time, when u ≤ 0.8 u_mf, and with the bed's
//!   buoyant weight per area when u ≥ 1.25 u_mf (u_mf from Ergun at the initial bed,
//!   [`crate::reference::ergun_velocity_for`]). Plots: `ergun.png` (Δp against u) and
//!   `pressure_drop.png` (Δp against t).
//! * `settlingSphere`: the first particle's settling speed at the end time against the
//!   CFDEM-style ODE with the case's own drag law at the coupling time step
//!   ([`crate::reference::settling_speed_history_with`]), and against that law's terminal
//!   speed when the run lasted at least five relaxation times. Plot: `settling.png`, which also
//!   shows CFDEM's Schiller–Naumann reference curve.
//! * `fluidisedBed`: [`crate::fluidised`].
//! * `pneumaticConveying`: [`crate::conveyor`].

use crate::error::RunError;
use crate::layout::ValidationSpec;
use crate::plot::{LinePlot, Series, Style};
use crate::reference::{
    ergun_pressure_gradient, ergun_velocity_for, settling_speed_history,
    settling_speed_history_with, terminal_speed_with,
};
use crate::sample::{mean_of, Sample};
use crate::validation::Check;
use closures::input::{sphere_volume, DragInput};
use couple::CouplerSettings;

use std::path::Path;

/// What a run recorded besides its samples, for the checks that need it.
#[derive(Clone, Copy, Debug)]
pub struct Recorded<'a> {
    /// A heating case's profiles at its sample times.
    pub heating: &'a crate::heating_run::Profiles,
    /// A fluidised bed's voidage profiles ([`crate::slab_profile`]).
    pub slabs: &'a crate::slab_profile::Record,
}

/// The checks `spec` asks for, from `samples` (one per coupling step of length `dt_c`) and what
/// the run `recorded`;
/// plots go into `post`, what the log should say besides the checks into `notes`.
pub fn evaluate(
    spec: &ValidationSpec,
    settings: &CouplerSettings,
    samples: &[Sample],
    recorded: Recorded<'_>,
    post: &Path,
    dt_c: f64,
    notes: &mut Vec<String>,
) -> Result<Vec<Check>, RunError> {
    std::fs::create_dir_all(post).map_err(|source| RunError::Io {
        path: post.to_owned(),
        source,
    })?;
    match spec {
        ValidationSpec::ErgunPackedBed {
            pressure_drop_tolerance,
            plateau_tolerance,
            ..
        } => ergun(
            settings,
            samples,
            post,
            *pressure_drop_tolerance,
            *plateau_tolerance,
        ),
        ValidationSpec::SettlingSphere { velocity_tolerance } => {
            settling(settings, samples, post, dt_c, *velocity_tolerance)
        }
        ValidationSpec::FluidisedBed {
            expanded_bed_height,
            bed_height_tolerance,
            pressure_drop_tolerance,
            packed_bed_tolerance,
            averaging_time,
            bed_height_known_gap,
            ..
        } => crate::fluidised::checks(
            recorded.slabs,
            settings,
            samples,
            crate::fluidised::Targets {
                expanded_bed_height: *expanded_bed_height,
                bed_height_tolerance: *bed_height_tolerance,
                pressure_drop_tolerance: *pressure_drop_tolerance,
                packed_bed_tolerance: *packed_bed_tolerance,
                averaging_time: *averaging_time,
                bed_height_known_gap: bed_height_known_gap.as_deref(),
            },
            post,
            dt_c,
            notes,
        ),
        ValidationSpec::PneumaticConveying(spec) => {
            crate::conveyor::checks(spec, samples, post, notes)
        }
        ValidationSpec::PackedBedHeating(case) => {
            crate::heating_run::checks(case, settings, recorded.heating, samples, post, notes)
        }
    }
}

/// One sample per run of at least `min_len` consecutive samples with the same inlet velocity
/// (to 1e-9 relative): the mean of the run's second half (the developed flow; the first half
/// holds the transient after the step), with the time of its last sample. Shorter runs (a ramp
/// between two plateaus) are skipped.
pub fn plateau_ends(samples: &[Sample], min_len: usize) -> Vec<Sample> {
    let mut out: Vec<Sample> = Vec::new();
    let mut start = 0;
    for (i, s) in samples.iter().enumerate() {
        let last = i + 1 == samples.len();
        let changes = !last
            && match (s.inlet_velocity, samples[i + 1].inlet_velocity) {
                (Some(a), Some(n)) => (n - a).abs() > 1e-9 * a.abs().max(n.abs()),
                (None, None) => false,
                _ => true,
            };
        if last || changes {
            let run = &samples[start..=i];
            if run.len() >= min_len {
                out.push(mean_of(&run[run.len() / 2..]));
            }
            start = i + 1;
        }
    }
    out
}

/// Samples a plateau needs to count as one.
const MIN_PLATEAU: usize = 3;

fn ergun(
    settings: &CouplerSettings,
    samples: &[Sample],
    post: &Path,
    tol_dp: f64,
    tol_plateau: f64,
) -> Result<Vec<Check>, RunError> {
    let ph = &settings.physics;
    let mu = ph.nu * ph.rho;
    // Ergun's law is the real particles': a parcel of diameter d stands for CG³ of d/CG
    let cg = settings.coarse_graining();
    let mut checks = Vec::new();
    let Some(first) = samples.first() else {
        return Ok(vec![Check::new("samples recorded", 0.0, 1.0, "", 0.0)]);
    };
    // an unmeasured quantity is NaN here, so every check built on it fails
    let v = |x: Option<f64>| x.unwrap_or(f64::NAN);
    let (l0, e0, d0) = (
        v(first.bed_height),
        v(first.bed_voidage),
        v(first.sauter_diameter) / cg,
    );
    let weight = v(first.weight_per_area);
    let u_mf = ergun_velocity_for(weight, l0, e0, d0, mu, ph.rho);
    let ends = plateau_ends(samples, MIN_PLATEAU);
    let mut below = 0;
    for s in &ends {
        let u = v(s.inlet_velocity);
        let (height, voidage) = (v(s.bed_height), v(s.bed_voidage));
        if u <= 0.8 * u_mf {
            below += 1;
            let reference =
                ergun_pressure_gradient(u, voidage, v(s.sauter_diameter) / cg, mu, ph.rho) * height;
            checks.push(Check::new(
                &format!(
                    "pressure drop at u = {u:.4} m/s vs Ergun (L = {height:.5} m, ε = {voidage:.4})"
                ),
                v(s.pressure_drop),
                reference,
                "Pa",
                tol_dp,
            ));
        } else if u >= 1.25 * u_mf {
            checks.push(Check::new(
                &format!(
                    "fluidised plateau: pressure drop at u = {u:.4} m/s vs bed weight per area"
                ),
                v(s.pressure_drop),
                v(s.weight_per_area),
                "Pa",
                tol_plateau,
            ));
        }
    }
    if below == 0 {
        checks.push(Check::new(
            &format!("a velocity plateau below fluidisation (u_mf = {u_mf:.4} m/s)"),
            f64::NAN,
            u_mf,
            "m/s",
            0.0,
        ));
    }
    let u_max = samples
        .iter()
        .filter_map(|s| s.inlet_velocity)
        .fold(0.0f64, f64::max)
        .max(u_mf);
    let curve: Vec<(f64, f64)> = (0..=100)
        .map(|i| {
            let u = u_max * i as f64 / 100.0;
            (u, ergun_pressure_gradient(u, e0, d0, mu, ph.rho) * l0)
        })
        .filter(|p| p.1 <= 1.3 * weight)
        .collect();
    LinePlot {
        title: "Ergun packed bed: pressure drop against inlet velocity".into(),
        x_label: "superficial inlet velocity (m/s)".into(),
        y_label: "pressure drop (Pa)".into(),
        series: vec![
            Series {
                name: format!("Ergun, initial bed (L = {l0:.4} m, ε = {e0:.3})"),
                points: curve,
                style: Style::Line,
            },
            Series {
                name: "bed weight per area".into(),
                points: vec![(0.0, weight), (u_max, weight)],
                style: Style::Line,
            },
            Series {
                name: "plateau means (checked)".into(),
                points: ends
                    .iter()
                    .filter_map(|s| Some((s.inlet_velocity?, s.pressure_drop?)))
                    .collect(),
                style: Style::Points,
            },
            Series {
                name: "simulated, every coupling step".into(),
                points: samples
                    .iter()
                    .filter_map(|s| Some((s.inlet_velocity?, s.pressure_drop?)))
                    .collect(),
                style: Style::Points,
            },
        ],
    }
    .write_png(&post.join("ergun.png"))?;
    LinePlot {
        title: "Ergun packed bed: pressure drop against time".into(),
        x_label: "time (s)".into(),
        y_label: "pressure drop (Pa)".into(),
        series: vec![Series {
            name: "simulated".into(),
            points: samples
                .iter()
                .filter_map(|s| Some((s.time, s.pressure_drop?)))
                .collect(),
            style: Style::Line,
        }],
    }
    .write_png(&post.join("pressure_drop.png"))?;
    Ok(checks)
}

fn settling(
    settings: &CouplerSettings,
    samples: &[Sample],
    post: &Path,
    dt_c: f64,
    tol: f64,
) -> Result<Vec<Check>, RunError> {
    let ph = &settings.physics;
    let Some(last) = samples.last() else {
        return Ok(vec![Check::new("samples recorded", 0.0, 1.0, "", 0.0)]);
    };
    let Some(drag) = ph.forces.drag else {
        return Ok(vec![Check::new(
            "a drag force in couplingProperties",
            f64::NAN,
            1.0,
            "",
            0.0,
        )]);
    };
    let g = ph.gravity.norm();
    let d = last.sauter_diameter.unwrap_or(f64::NAN);
    let rho_p = last.mean_density.unwrap_or(f64::NAN);
    let beta = |x: &DragInput| drag.closure.beta(x);
    let t_end = last.time;
    let ode = settling_speed_history_with(&beta, d, rho_p, ph.rho, ph.nu, g, dt_c, t_end);
    let sn = settling_speed_history(d, rho_p, ph.rho, ph.nu, g, dt_c, t_end);
    let speed = -last.first_axial_velocity;
    let law = drag.closure.law.cfdem_name();
    let mut checks = vec![Check::new(
        &format!("settling speed at t = {t_end:.4} s vs the {law} ODE"),
        speed,
        ode.last().map_or(f64::NAN, |p| p.1),
        "m/s",
        tol,
    )];
    let terminal = terminal_speed_with(&beta, d, rho_p, ph.rho, ph.nu, g);
    let m = rho_p * sphere_volume(d);
    let tau = m / beta(&DragInput::new(1.0, d, terminal, ph.rho, ph.nu * ph.rho));
    if t_end >= 5.0 * tau {
        checks.push(Check::new(
            &format!("settling speed at t = {t_end:.4} s vs the {law} terminal speed"),
            speed,
            terminal,
            "m/s",
            tol,
        ));
    }
    let mut sim = vec![(0.0, 0.0)];
    sim.extend(samples.iter().map(|s| (s.time, -s.first_axial_velocity)));
    LinePlot {
        title: "Settling sphere: speed against time".into(),
        x_label: "time (s)".into(),
        y_label: "settling speed (m/s)".into(),
        series: vec![
            Series {
                name: format!("ODE with the case's drag ({law})"),
                points: ode,
                style: Style::Line,
            },
            Series {
                name: "simulated".into(),
                points: sim,
                style: Style::Points,
            },
            Series {
                name: "CFDEM's reference (Schiller–Naumann ODE)".into(),
                points: sn,
                style: Style::Line,
            },
            Series {
                name: format!("terminal speed ({law})"),
                points: vec![(0.0, terminal), (t_end, terminal)],
                style: Style::Line,
            },
        ],
    }
    .write_png(&post.join("settling.png"))?;
    Ok(checks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plateau_ends_are_the_last_sample_of_each_velocity() {
        let mk = |t: f64, u: f64| Sample {
            time: t,
            inlet_velocity: Some(u),
            ..Sample::default()
        };
        let s = [
            mk(1.0, 0.002),
            mk(2.0, 0.002),
            mk(3.0, 0.003),
            mk(4.0, 0.004),
            mk(5.0, 0.004),
            mk(6.0, 0.006),
        ];
        let times = |e: Vec<Sample>| e.iter().map(|s| s.time).collect::<Vec<f64>>();
        assert_eq!(times(plateau_ends(&s, 1)), vec![2.0, 3.0, 5.0, 6.0]);
        // The one-sample ramp value and the unfinished last plateau are skipped.
        assert_eq!(times(plateau_ends(&s, 2)), vec![2.0, 5.0]);
        // The second half is averaged.
        let mut p: Vec<Sample> = (0..6).map(|i| mk(i as f64, 0.01)).collect();
        for (i, x) in p.iter_mut().enumerate() {
            x.pressure_drop = Some(i as f64);
        }
        let e = plateau_ends(&p, 3);
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].pressure_drop, Some((3.0 + 4.0 + 5.0) / 3.0));
        assert_eq!(e[0].time, 5.0);
        assert!(plateau_ends(&[], 1).is_empty());
    }
}
