//! The check of `openfoam-cases/packed-bed-heating`: hot gas entering a cold fixed bed, the
//! gas and solid temperature fronts against Schumann's solution ([`crate::schumann`]).
//!
//! **Measured.** At each sample time t (s since the hot gas entered), two axial profiles of the
//! bed, depth z measured from the bed's inlet end (m): the gas temperature of each cross-section
//! slice of cells (the cell average; one cell per slice in the case) and the solid temperature
//! of the particles binned by the height of their centres (mean per bin). Only slices inside the
//! bed belong in them. Each profile is normalised, θ = (T − T0)/(T_in − T0).
//!
//! **Front position and width.** A sampled profile is read as the piecewise-linear curve through
//! its samples, held at its first value between the inlet (z = 0) and the first sample. The
//! position where it crosses the level c is taken as the length of {z : θ(z) > c} (its
//! decreasing rearrangement's crossing): for a profile that falls monotonically, as Schumann's
//! do, this is the crossing itself; for a noisy one (random packing, a few particles per bin) it
//! is still one number, insensitive to wiggles that cross c several times. Position = crossing
//! of 0.5, width = crossing of 0.1 − crossing of 0.9 (m). The reference numbers are the same
//! crossings of Schumann's continuous profiles (bisection to 1e-9 of the sampled length) for the
//! bed's parameters: the measured voidage ε, d, ρ_s, c_s, ρ_g, c_g, the superficial velocity and
//! the heat transfer coefficient h the case's Nusselt law gives at the bed's mean ε and Re.
//!
//! **Tolerances** (the case's `validationDict`, reasons in its README): a front position passes
//! within max(`position_cells` · Δz, `position_fraction` · reference position), Δz the slices'
//! axial size — one cell is what the gas profile resolves, and a fraction of the distance
//! travelled covers the bed's measured voidage (the front speed goes as 1/(1 − ε): δε = 0.01 moves
//! it by ≈ 1.7 %); a width passes within max(`width_cells` · Δz, `width_fraction` · reference
//! width): on the case's grid the 1-D model with its gas conduction, limited-linear T
//! convection and explicit coupling steps widens the front by +7 … +10 % (the case README's
//! table), which leaves ≈ 10 % for the bed's randomness inside 20 %, while a first-order upwind
//! T equation (+45 %) fails.

use crate::schumann::SchumannBed;
use crate::validation::Check;

/// An axial profile: `z` depth from the bed's inlet end (m, strictly increasing, ≥ 0) and the
/// temperature there (K).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Profile {
    /// Depths of the samples, m.
    pub z: Vec<f64>,
    /// Temperatures, K.
    pub temperature: Vec<f64>,
}

/// The two profiles at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Time since the hot gas entered, s.
    pub time: f64,
    /// Gas temperature per cross-section slice of cells (cell averages).
    pub gas: Profile,
    /// Solid temperature per height bin of particles (mean of the particles' temperatures).
    pub solid: Profile,
}

/// What the case asks of the fronts (`validationDict`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatingSpec {
    /// The bed's (and the gas's) initial temperature T0, K.
    pub initial_temperature: f64,
    /// The inlet gas temperature T_in from t = 0, K.
    pub inlet_temperature: f64,
    /// Axial size Δz of the gas slices (cells), m.
    pub cell_size: f64,
    /// Position tolerance in cells.
    pub position_cells: f64,
    /// Position tolerance as a fraction of the reference position.
    pub position_fraction: f64,
    /// Width tolerance in cells.
    pub width_cells: f64,
    /// Width tolerance as a fraction of the reference width.
    pub width_fraction: f64,
}

/// Gas or solid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// The gas temperature front.
    Gas,
    /// The solid (particle) temperature front.
    Solid,
}

impl Phase {
    fn name(self) -> &'static str {
        match self {
            Phase::Gas => "gas",
            Phase::Solid => "solid",
        }
    }
}

/// One front at one time: measured and Schumann's numbers (m).
#[derive(Clone, Debug, PartialEq)]
pub struct Front {
    /// Gas or solid.
    pub phase: Phase,
    /// Time since the hot gas entered, s.
    pub time: f64,
    /// Measured position (θ = 0.5), m; NaN if the profile does not cross 0.5.
    pub position: f64,
    /// Schumann's position, m.
    pub reference_position: f64,
    /// Accepted |position − reference|, m.
    pub position_tolerance: f64,
    /// Measured width (θ 0.9 → 0.1), m; NaN if the profile does not cross both levels.
    pub width: f64,
    /// Schumann's width, m.
    pub reference_width: f64,
    /// Accepted |width − reference|, m.
    pub width_tolerance: f64,
}

impl Front {
    /// Both the position and the width within their tolerances (and measured).
    pub fn pass(&self) -> bool {
        (self.position - self.reference_position).abs() <= self.position_tolerance
            && (self.width - self.reference_width).abs() <= self.width_tolerance
    }
}

/// The result of [`check`]: every front, and the bed's derived numbers for the report.
#[derive(Clone, Debug, PartialEq)]
pub struct HeatingCheck {
    /// Gas then solid front at each sample time, in the order given.
    pub fronts: Vec<Front>,
    /// Schumann's front speed far into the bed, m/s.
    pub front_speed: f64,
    /// One gas transfer unit, ε ρ_g c_g u/(h a), m.
    pub transfer_length: f64,
}

impl HeatingCheck {
    /// Every front passes.
    pub fn pass(&self) -> bool {
        self.fronts.iter().all(Front::pass)
    }

    /// The fronts as validation records (`validation.json`): position and width of each, with
    /// the tolerance as a fraction of the reference.
    pub fn checks(&self) -> Vec<Check> {
        let mut out = Vec::new();
        for f in &self.fronts {
            let (p, t) = (f.phase.name(), f.time);
            let rows = [
                (
                    ("position", "θ = 0.5"),
                    f.position,
                    f.reference_position,
                    f.position_tolerance,
                ),
                (
                    ("width", "θ 0.9 → 0.1"),
                    f.width,
                    f.reference_width,
                    f.width_tolerance,
                ),
            ];
            for ((what, levels), sim, reference, tol) in rows {
                // the time before the parenthesis: runs are compared by the name's head
                let name = format!(
                    "{p} front {what} at t = {} s ({levels})",
                    cfmt::format_g(t, 6)
                );
                out.push(Check::new(&name, sim, reference, "m", tol / reference));
            }
        }
        out
    }
}

/// Why the check could not be made (bad input or sample times where Schumann's front is not
/// inside the sampled bed).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum HeatingError {
    /// A parameter or sample is unusable; the message names it.
    #[error("packed-bed heating check: {0}")]
    Input(String),
}

fn input(msg: String) -> HeatingError {
    HeatingError::Input(msg)
}

/// Checks the profiles of every snapshot against Schumann's solution for `bed`.
pub fn check(
    bed: &SchumannBed,
    spec: &HeatingSpec,
    snapshots: &[Snapshot],
) -> Result<HeatingCheck, HeatingError> {
    validate_spec(spec)?;
    if snapshots.is_empty() {
        return Err(input("no sample times".into()));
    }
    let mut fronts = Vec::with_capacity(2 * snapshots.len());
    for s in snapshots {
        if !(s.time.is_finite() && s.time > 0.0) {
            return Err(input(format!(
                "sample time must be positive, got {}",
                s.time
            )));
        }
        for (phase, prof) in [(Phase::Gas, &s.gas), (Phase::Solid, &s.solid)] {
            fronts.push(front(bed, spec, phase, s.time, prof)?);
        }
    }
    Ok(HeatingCheck {
        fronts,
        front_speed: bed.front_speed(),
        transfer_length: bed.transfer_length(),
    })
}

fn validate_spec(spec: &HeatingSpec) -> Result<(), HeatingError> {
    let (t0, tin) = (spec.initial_temperature, spec.inlet_temperature);
    if !(t0.is_finite() && tin.is_finite() && t0 != tin) {
        return Err(input(format!(
            "initial ({t0} K) and inlet ({tin} K) temperatures must be finite and differ"
        )));
    }
    for (name, v) in [
        ("cell size", spec.cell_size),
        ("position tolerance in cells", spec.position_cells),
        ("position tolerance fraction", spec.position_fraction),
        ("width tolerance in cells", spec.width_cells),
        ("width tolerance fraction", spec.width_fraction),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(input(format!("{name} must be a number ≥ 0, got {v}")));
        }
    }
    Ok(())
}

/// The normalised samples of `prof`, checked: same lengths, ≥ 2 samples, z ≥ 0 strictly
/// increasing, temperatures finite.
fn normalised(
    prof: &Profile,
    spec: &HeatingSpec,
    what: &str,
) -> Result<Vec<(f64, f64)>, HeatingError> {
    if prof.z.len() != prof.temperature.len() || prof.z.len() < 2 {
        return Err(input(format!(
            "{what}: {} depths and {} temperatures (need the same number, at least 2)",
            prof.z.len(),
            prof.temperature.len()
        )));
    }
    let span = spec.inlet_temperature - spec.initial_temperature;
    let mut out = Vec::with_capacity(prof.z.len());
    for (i, (&z, &t)) in prof.z.iter().zip(&prof.temperature).enumerate() {
        if !(z.is_finite() && z >= 0.0) || (i > 0 && z <= prof.z[i - 1]) {
            return Err(input(format!(
                "{what}: depth {i} ({z} m) is not ≥ 0 and above the previous one"
            )));
        }
        if !t.is_finite() {
            return Err(input(format!(
                "{what}: temperature {i} at z = {z} m is {t}"
            )));
        }
        out.push((z, (t - spec.initial_temperature) / span));
    }
    Ok(out)
}

/// The length of {z ∈ [0, z_last] : θ(z) > c} for the piecewise-linear profile through
/// `samples`, held at its first value on [0, z_first]; `None` if θ > c nowhere or everywhere
/// (the front is not inside the sampled bed).
pub fn level_crossing(samples: &[(f64, f64)], c: f64) -> Option<f64> {
    let above = samples.iter().filter(|s| s.1 > c).count();
    if above == 0 || above == samples.len() {
        return None;
    }
    let mut len = if samples[0].1 > c { samples[0].0 } else { 0.0 };
    for w in samples.windows(2) {
        let ((z0, a), (z1, b)) = (w[0], w[1]);
        let dz = z1 - z0;
        if a > c && b > c {
            len += dz;
        } else if a > c || b > c {
            len += dz * (a.max(b) - c) / (a - b).abs();
        }
    }
    Some(len)
}

/// The depth (m) where Schumann's profile `theta(z)` (falling in z) crosses `c`, searched on
/// [0, `z_max`]; `None` if it does not cross there.
fn reference_crossing(theta: &dyn Fn(f64) -> f64, c: f64, z_max: f64) -> Option<f64> {
    if theta(0.0) <= c || theta(z_max) > c {
        return None;
    }
    let (mut lo, mut hi) = (0.0, z_max);
    while hi - lo > 1e-9 * z_max {
        let mid = 0.5 * (lo + hi);
        if theta(mid) > c {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

fn front(
    bed: &SchumannBed,
    spec: &HeatingSpec,
    phase: Phase,
    t: f64,
    prof: &Profile,
) -> Result<Front, HeatingError> {
    let what = format!("{} profile at t = {t} s", phase.name());
    let samples = normalised(prof, spec, &what)?;
    let z_max = samples[samples.len() - 1].0;
    let theta = |z: f64| match phase {
        Phase::Gas => bed.gas(z, t),
        Phase::Solid => bed.solid(z, t),
    };
    let mut reference = [0.0; 3];
    for (r, c) in reference.iter_mut().zip([0.9, 0.5, 0.1]) {
        *r = reference_crossing(&theta, c, z_max).ok_or_else(|| {
            input(format!(
                "{what}: Schumann's θ = {c} does not lie in the sampled bed (0 … {z_max} m); \
                 sample at times when the front is inside the bed"
            ))
        })?;
    }
    let measured = |c: f64| level_crossing(&samples, c).unwrap_or(f64::NAN);
    let (position, width) = (measured(0.5), measured(0.1) - measured(0.9));
    let reference_width = reference[2] - reference[0];
    Ok(Front {
        phase,
        time: t,
        position,
        reference_position: reference[1],
        position_tolerance: (spec.position_cells * spec.cell_size)
            .max(spec.position_fraction * reference[1]),
        width,
        reference_width,
        width_tolerance: (spec.width_cells * spec.cell_size)
            .max(spec.width_fraction * reference_width),
    })
}
