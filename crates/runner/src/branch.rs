//! Madden's (2020) full pneumatic conveyor (`openfoam-cases/pneumatic-conveying-full`): the
//! reduced conveyor ([`crate::conveyor`]) continued by a downstream tube, a T branch, a leg
//! venting through the outlet and a leg ending in a closed secondary chamber. What a run
//! measures there and the checks it is held to.
//!
//! Regions ([`BranchSpec::region`]) by the height h along the column axis and the coordinate b
//! along the branch axis (from the column axis towards the vented outlet), in this order: the
//! secondary chamber is h ≥ `tubeFrom` and b ≤ −`secondaryFrom`; past the branch's floor
//! (h ≥ `branchFrom`) the vented leg is b ≥ `ventFrom`, the other leg b ≤ −`ventFrom`, the rest
//! the branch itself; below it, `tubeFrom` ≤ h < `tubeTo` is the downstream tube and
//! `tubeTo` ≤ h the transition to the branch's square section; everything else (h < `tubeFrom`)
//! is the reduced conveyor upstream.
//!
//! Checks ([`checks`]), each able to fail:
//!
//! * the particle volume account closes: the volume at the start plus what entered equals what
//!   left plus what the system holds at the end (relative 1e-9: every term is a sum of the same
//!   spheres' volumes, so only round-off may differ; a particle removed without being counted
//!   breaks it);
//! * the held volume is in the mesh's cells or counted outside it (`deposited + outside`,
//!   relative 1e-9: the voidage model's invariant, at the last step);
//! * particles reach the branch (at least one past its floor, or out, by the end), and the vented
//!   leg receives particles (at least one in the vented leg, or out through the vent);
//! * the air accelerates past the branch, before the outlet (the seed: "a sharp acceleration
//!   immediately before the outlet past the branch"): the largest velocity along the vented
//!   leg, mean over t ≥ `averagingFrom`, exceeds the largest axial velocity in the downstream
//!   tube (the legs' section is the tube's: 81 vs 78.5 mm², so a mean velocity cannot rise
//!   there; a peak that does is the jet the branch's turn contracts).
//!
//! Reported (notes, `distribution.png`, `air_velocity.png`): where the particles are against
//! time (out through the vent, in the vented leg, in the secondary chamber, held elsewhere), the
//! mean air velocity along the tube and the leg. The particle axial velocity in the downstream
//! tube is [`crate::conveyor`]'s tube velocity (its tube ends at `tubeTo` here).

use crate::plot::{LinePlot, Series, Style};
use crate::sample::Sample;
use crate::validation::Check;
use mesh::v3::V3;
use std::path::Path;

/// The full system's keys of a `pneumaticConveying` validationDict (lengths in m).
#[derive(Clone, Debug, PartialEq)]
pub struct BranchSpec {
    /// Unit vector along the branch, from the column axis towards the vented outlet
    /// (`branchAxis`, normalised).
    pub axis: V3,
    /// Height where the downstream tube ends (`tubeTo`).
    pub tube_to: f64,
    /// Height of the branch's floor (`branchFrom`).
    pub branch_from: f64,
    /// Branch coordinate where the vented leg begins (`ventFrom`; the other leg: below −it).
    pub vent_from: f64,
    /// Branch coordinate beyond which (negative) the secondary chamber lies (`secondaryFrom`).
    pub secondary_from: f64,
}

/// Where a point of the full system lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// The reduced conveyor (annulus, plenum, the first part of its tube).
    Upstream,
    /// The downstream tube (`tubeFrom` ≤ h < `tubeTo`).
    Tube,
    /// The transition from the tube's circle to the branch's square.
    Transition,
    /// The branch (the T's junction).
    Branch,
    /// The leg to the secondary chamber.
    Leg,
    /// The leg to the vented outlet.
    Vent,
    /// The closed secondary chamber.
    Secondary,
}

impl BranchSpec {
    /// The region of the point at height `h` along the column axis and `b` along the branch
    /// axis (m); `tube_from` is the conveyor's `tubeFrom`.
    pub fn region(&self, tube_from: f64, h: f64, b: f64) -> Region {
        if h >= tube_from && b <= -self.secondary_from {
            Region::Secondary
        } else if h >= self.branch_from {
            if b >= self.vent_from {
                Region::Vent
            } else if b <= -self.vent_from {
                Region::Leg
            } else {
                Region::Branch
            }
        } else if h >= self.tube_to {
            Region::Transition
        } else if h >= tube_from {
            Region::Tube
        } else {
            Region::Upstream
        }
    }
}

/// The full system's particle counts of one coupling step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BranchZones {
    /// Particles past the branch's floor: the branch, either leg, the secondary chamber.
    pub past: usize,
    /// Particles in the vented leg.
    pub vent: usize,
    /// Particles in the secondary chamber.
    pub secondary: usize,
}

impl BranchZones {
    /// Counts the particles at `positions` (m); `axis` is the column's unit axis.
    pub fn measure(spec: &BranchSpec, tube_from: f64, axis: V3, positions: &[V3]) -> BranchZones {
        let mut z = BranchZones::default();
        for x in positions {
            match spec.region(tube_from, x.dot(&axis), x.dot(&spec.axis)) {
                Region::Vent => {
                    z.vent += 1;
                    z.past += 1;
                }
                Region::Secondary => {
                    z.secondary += 1;
                    z.past += 1;
                }
                Region::Branch | Region::Leg => z.past += 1,
                _ => {}
            }
        }
        z
    }
}

/// The fluid cells the air velocity is measured over: the downstream tube's and the vented
/// leg's (by their centres), with their volumes (m³).
#[derive(Clone, Debug, Default)]
pub struct AirCells {
    /// (cell, volume) of the downstream tube.
    pub tube: Vec<(usize, f64)>,
    /// (cell, volume) of the vented leg.
    pub vent: Vec<(usize, f64)>,
}

/// One step's air velocities (m/s): volume-weighted means and maxima of U·axis over the
/// downstream tube and of U·branchAxis over the vented leg.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AirVelocities {
    /// Mean axial velocity in the downstream tube.
    pub tube_mean: f64,
    /// Largest axial velocity there.
    pub tube_peak: f64,
    /// Mean velocity along the vented leg.
    pub vent_mean: f64,
    /// Largest velocity along it.
    pub vent_peak: f64,
}

impl AirCells {
    /// The cells of `centres` (m) in the downstream tube and the vented leg.
    pub fn select(
        spec: &BranchSpec,
        tube_from: f64,
        axis: V3,
        centres: &[V3],
        volumes: &[f64],
    ) -> AirCells {
        let mut cells = AirCells::default();
        for (c, (x, &v)) in centres.iter().zip(volumes).enumerate() {
            match spec.region(tube_from, x.dot(&axis), x.dot(&spec.axis)) {
                Region::Tube => cells.tube.push((c, v)),
                Region::Vent => cells.vent.push((c, v)),
                _ => {}
            }
        }
        cells
    }

    /// The velocities of the cell field `u` (m/s); `None` when either region has no cell.
    pub fn measure(&self, spec: &BranchSpec, axis: V3, u: &[V3]) -> Option<AirVelocities> {
        let tube = self.tube.iter().map(|&(c, v)| (u[c], v));
        let vent = self.vent.iter().map(|&(c, v)| (u[c], v));
        Self::stats(spec, axis, tube, vent)
    }

    /// The cells in the order [`AirCells::measure_listed`] takes their velocities: the
    /// downstream tube's, then the vented leg's.
    pub fn listed(&self) -> Vec<usize> {
        self.tube
            .iter()
            .chain(&self.vent)
            .map(|&(c, _)| c)
            .collect()
    }

    /// As [`AirCells::measure`], with U of the cells of [`AirCells::listed`] in its order
    /// (what grainPisoFoam's ranks send for them, [`crate::fluid::RunFluid::watched`]);
    /// `None` also when `listed` has another length.
    pub fn measure_listed(
        &self,
        spec: &BranchSpec,
        axis: V3,
        listed: &[V3],
    ) -> Option<AirVelocities> {
        if listed.len() != self.tube.len() + self.vent.len() {
            return None;
        }
        let (tube_u, vent_u) = listed.split_at(self.tube.len());
        let tube = tube_u.iter().zip(&self.tube).map(|(&u, &(_, v))| (u, v));
        let vent = vent_u.iter().zip(&self.vent).map(|(&u, &(_, v))| (u, v));
        Self::stats(spec, axis, tube, vent)
    }

    /// The velocities of (U, cell volume) over the tube and the leg.
    fn stats(
        spec: &BranchSpec,
        axis: V3,
        tube: impl Iterator<Item = (V3, f64)>,
        vent: impl Iterator<Item = (V3, f64)>,
    ) -> Option<AirVelocities> {
        let stats = |cells: &mut dyn Iterator<Item = (V3, f64)>, along: V3| {
            let (mut sum, mut vol, mut peak) = (0.0, 0.0, f64::NEG_INFINITY);
            for (u, v) in cells {
                let w = u.dot(&along);
                sum += w * v;
                vol += v;
                peak = f64::max(peak, w);
            }
            (vol > 0.0).then(|| (sum / vol, peak))
        };
        let (tube_mean, tube_peak) = stats(&mut { tube }, axis)?;
        let (vent_mean, vent_peak) = stats(&mut { vent }, spec.axis)?;
        Some(AirVelocities {
            tube_mean,
            tube_peak,
            vent_mean,
            vent_peak,
        })
    }
}

/// The particle volume account over `samples` (m³): (at the start + in, out + held at the
/// end). The start is empty when the first step's entries are all its particles (the deck
/// inserts them), else what the first step held before its entries and departures.
fn volume_account(samples: &[Sample]) -> Option<(f64, f64)> {
    let (first, last) = (samples.first()?, samples.last()?);
    let start = if first.particles_in == first.particles && first.particles_out == 0 {
        0.0
    } else {
        first.particle_volume - first.volume_in + first.volume_out
    };
    let vin: f64 = samples.iter().map(|s| s.volume_in).sum();
    let vout: f64 = samples.iter().map(|s| s.volume_out).sum();
    Some((start + vin, vout + last.particle_volume))
}

/// The full system's checks from `samples` (`averaging_from`: start of the air's average, s);
/// notes for the log go to `notes`, plots (`distribution.png`, `air_velocity.png`) into
/// `post`.
pub fn checks(
    samples: &[Sample],
    averaging_from: f64,
    post: &Path,
    notes: &mut Vec<String>,
) -> Result<Vec<Check>, crate::error::RunError> {
    let mut checks = Vec::new();
    let Some(last) = samples.last() else {
        return Ok(checks);
    };
    let end = last.time;
    // volumes in mm³ for the log (the particles' are ~1e-10 m³)
    const MM3: f64 = 1e9;
    if let Some((supplied, accounted)) = volume_account(samples) {
        checks.push(Check::new(
            &format!(
                "particle volume account at t = {end:.4} s: at the start + entered vs left + held"
            ),
            supplied * MM3,
            accounted * MM3,
            "mm³",
            1e-9,
        ));
    }
    checks.push(Check::new(
        &format!("held particle volume at t = {end:.4} s vs in the cells + outside the mesh"),
        last.particle_volume * MM3,
        (last.deposited_volume + last.outside_volume) * MM3,
        "mm³",
        1e-9,
    ));
    let vented: usize = samples.iter().map(|s| s.particles_out).sum();
    let entered: usize = samples.iter().map(|s| s.particles_in).sum();
    // the most particles at one step that were past the branch (or in the vented leg) or had
    // left by then: distinct particles, none counted twice
    let (mut out, mut past, mut leg) = (0, 0, 0);
    for s in samples {
        out += s.particles_out;
        past = past.max(s.branch_particles.unwrap_or(0) + out);
        leg = leg.max(s.vent_leg_particles.unwrap_or(0) + out);
    }
    checks.push(Check::at_least(
        &format!("particles past the branch's floor or out, most at one step by t = {end:.4} s"),
        past as f64,
        1.0,
        "particles",
    ));
    checks.push(Check::at_least(
        &format!("particles in the vented leg or out, most at one step by t = {end:.4} s"),
        leg as f64,
        1.0,
        "particles",
    ));
    let window: Vec<&Sample> = samples
        .iter()
        .filter(|s| s.time >= averaging_from)
        .collect();
    let mean = |f: fn(&Sample) -> Option<f64>| {
        let v: Vec<f64> = window.iter().filter_map(|s| f(s)).collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    match (
        mean(|s| s.tube_air_peak),
        mean(|s| s.vent_air_peak),
        mean(|s| s.tube_air_velocity),
        mean(|s| s.vent_air_velocity),
    ) {
        (Some(tube_peak), Some(vent_peak), Some(tube), Some(vent)) => {
            notes.push(format!(
                "conveyor (full system, reported): mean air velocity over t ≥ {averaging_from} s: \
                 downstream tube {tube:.2} m/s (largest {tube_peak:.2}), vented leg {vent:.2} m/s \
                 (largest {vent_peak:.2})"
            ));
            checks.push(Check::at_least(
                &format!(
                    "largest air velocity along the vented leg over the downstream tube's, mean \
                     over t = {averaging_from} … {end:.4} s (the air accelerates past the branch)"
                ),
                vent_peak / tube_peak,
                1.0,
                "",
            ));
        }
        _ => notes.push(format!(
            "conveyor (full system): no air velocity sampled after averagingFrom = \
             {averaging_from} s: the acceleration past the branch is not checked"
        )),
    }
    let held = last.particles;
    notes.push(format!(
        "conveyor (full system, reported): of {entered} particles that entered by t = {end:.4} s, \
         {vented} left through the vented outlet, {} are in the vented leg, {} in the secondary \
         chamber and {} elsewhere in the system",
        last.vent_leg_particles.unwrap_or(0),
        last.secondary_particles.unwrap_or(0),
        held - last.vent_leg_particles.unwrap_or(0) - last.secondary_particles.unwrap_or(0)
    ));
    plots(samples, post, entered)?;
    Ok(checks)
}

fn plots(samples: &[Sample], post: &Path, entered: usize) -> Result<(), crate::error::RunError> {
    let of = entered.max(1) as f64;
    let mut vented = 0usize;
    let out: Vec<(f64, f64)> = samples
        .iter()
        .map(|s| {
            vented += s.particles_out;
            (s.time, vented as f64 / of)
        })
        .collect();
    let series = |name: &str, f: &dyn Fn(&Sample) -> Option<f64>| Series {
        name: name.to_owned(),
        points: samples
            .iter()
            .filter_map(|s| Some((s.time, f(s)?)))
            .collect(),
        style: Style::Line,
    };
    LinePlot {
        title:
            "Where the particles are (full system; seed, Fig. 4: distribution into the chambers)"
                .into(),
        x_label: "t (s)".into(),
        y_label: "fraction of the particles that entered".into(),
        series: vec![
            Series {
                name: "out through the vented outlet".into(),
                points: out,
                style: Style::Line,
            },
            series("in the vented leg", &|s| {
                Some(s.vent_leg_particles? as f64 / of)
            }),
            series("in the secondary chamber", &|s| {
                Some(s.secondary_particles? as f64 / of)
            }),
            series("elsewhere in the system", &|s| {
                let rest = s.particles - s.vent_leg_particles? - s.secondary_particles?;
                Some(rest as f64 / of)
            }),
        ],
    }
    .write_png(&post.join("distribution.png"))?;
    let air = [
        series("downstream tube, mean", &|s| s.tube_air_velocity),
        series("downstream tube, largest", &|s| s.tube_air_peak),
        series("vented leg, mean", &|s| s.vent_air_velocity),
        series("vented leg, largest", &|s| s.vent_air_peak),
    ];
    if air.iter().any(|s| !s.points.is_empty()) {
        LinePlot {
            title: "Air velocity along the tube and the vented leg (seed: acceleration past the \
                    branch)"
                .into(),
            x_label: "t (s)".into(),
            y_label: "velocity along the flow (m/s)".into(),
            series: air.to_vec(),
        }
        .write_png(&post.join("air_velocity.png"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The geometry of `openfoam-cases/pneumatic-conveying-full` (geometry.py --full).
    fn spec() -> BranchSpec {
        BranchSpec {
            axis: V3::x(),
            tube_to: 0.145,
            branch_from: 0.155,
            vent_from: 0.0045,
            secondary_from: 0.0245,
        }
    }

    /// Points placed by hand in each part of the full system's geometry.
    #[test]
    fn regions_follow_the_geometry() {
        let s = spec();
        let r = |x: f64, z: f64| s.region(0.065, z, x);
        // the annulus reaches |x| = 0.025 below the tube: upstream, not the chamber
        assert_eq!(r(-0.0248, 0.01), Region::Upstream);
        assert_eq!(r(0.0, 0.06), Region::Upstream);
        // a particle near the tube's wall (|x| 4.75 mm > ventFrom) is still in the tube
        assert_eq!(r(0.00475, 0.1), Region::Tube);
        assert_eq!(r(0.0, 0.15), Region::Transition);
        assert_eq!(r(0.0, 0.16), Region::Branch);
        assert_eq!(r(0.03, 0.16), Region::Vent);
        assert_eq!(r(-0.01, 0.16), Region::Leg);
        // the chamber hangs below the branch's floor
        assert_eq!(r(-0.04, 0.14), Region::Secondary);
        assert_eq!(r(-0.04, 0.16), Region::Secondary);
    }

    #[test]
    fn zones_count_each_region() {
        let p = [
            V3::new(0.0, 0.0, 0.1),
            V3::new(0.0, 0.0, 0.16),
            V3::new(0.03, 0.0, 0.16),
            V3::new(-0.04, 0.0, 0.14),
            V3::new(-0.01, 0.001, 0.16),
        ];
        let z = BranchZones::measure(&spec(), 0.065, V3::z(), &p);
        assert_eq!(
            z,
            BranchZones {
                past: 4,
                vent: 1,
                secondary: 1
            }
        );
    }

    /// Four cells with known velocities: means weighted by volume, peaks along each axis.
    #[test]
    fn air_velocities_by_region() {
        let centres = [
            V3::new(0.0, 0.0, 0.1),
            V3::new(0.001, 0.0, 0.12),
            V3::new(0.02, 0.0, 0.16),
            V3::new(0.0, 0.0, 0.01),
        ];
        let volumes = [1.0, 3.0, 2.0, 5.0];
        let cells = AirCells::select(&spec(), 0.065, V3::z(), &centres, &volumes);
        assert_eq!(cells.tube, vec![(0, 1.0), (1, 3.0)]);
        assert_eq!(cells.vent, vec![(2, 2.0)]);
        let u = [
            V3::new(0.0, 0.0, 40.0),
            V3::new(9.0, 0.0, 60.0),
            V3::new(70.0, 0.0, -3.0),
            V3::new(0.0, 0.0, 4.0),
        ];
        let a = cells.measure(&spec(), V3::z(), &u).unwrap();
        assert_eq!(a.tube_mean, (40.0 + 3.0 * 60.0) / 4.0);
        assert_eq!((a.tube_peak, a.vent_mean, a.vent_peak), (60.0, 70.0, 70.0));
        // the listed cells' velocities (as grainPisoFoam's ranks send them) measure the same
        assert_eq!(cells.listed(), [0, 1, 2]);
        let listed = [u[0], u[1], u[2]];
        assert_eq!(cells.measure_listed(&spec(), V3::z(), &listed), Some(a));
        assert_eq!(cells.measure_listed(&spec(), V3::z(), &listed[..2]), None);
    }

    fn row(t: f64, n: usize, n_in: usize, n_out: usize, v1: f64) -> Sample {
        Sample {
            time: t,
            particles: n,
            particles_in: n_in,
            particles_out: n_out,
            volume_in: n_in as f64 * v1,
            volume_out: n_out as f64 * v1,
            particle_volume: n as f64 * v1,
            deposited_volume: n as f64 * v1 * 0.75,
            outside_volume: n as f64 * v1 * 0.25,
            branch_particles: Some(0),
            vent_leg_particles: Some(0),
            secondary_particles: Some(0),
            ..Sample::default()
        }
    }

    /// The account closes on a consistent history and fails when a particle vanishes without
    /// being counted as out; the reach checks fail while no particle passed the branch.
    #[test]
    fn the_account_and_the_reach_can_fail() {
        let dir = tempfile::tempdir().unwrap();
        let v1 = 6.5e-11;
        let mut s = vec![row(0.001, 10, 10, 0, v1), row(0.002, 10, 0, 0, v1)];
        let c = checks(&s, 0.01, dir.path(), &mut Vec::new()).unwrap();
        assert!(c[0].pass && c[1].pass, "{c:?}");
        assert!(
            !c[2].pass && !c[3].pass,
            "nothing reached the branch: {c:?}"
        );
        // one leaves through the vent, another sits in the vented leg
        s.push(Sample {
            vent_leg_particles: Some(1),
            branch_particles: Some(1),
            ..row(0.003, 9, 0, 1, v1)
        });
        let c = checks(&s, 0.01, dir.path(), &mut Vec::new()).unwrap();
        assert!(c.iter().all(|c| c.pass), "{c:?}");
        assert_eq!(c[3].simulated, 2.0);
        // a particle gone without a departure: 9 held, 0 out
        s.push(row(0.004, 8, 0, 0, v1));
        let c = checks(&s, 0.01, dir.path(), &mut Vec::new()).unwrap();
        assert!(!c[0].pass, "{c:?}");
        assert!(dir.path().join("distribution.png").is_file());
    }

    /// The acceleration check compares the peaks' means over the window only.
    #[test]
    fn acceleration_past_the_branch() {
        let dir = tempfile::tempdir().unwrap();
        let air = |t: f64, tube: f64, vent: f64| Sample {
            tube_air_velocity: Some(tube - 10.0),
            tube_air_peak: Some(tube),
            vent_air_velocity: Some(vent - 20.0),
            vent_air_peak: Some(vent),
            ..row(t, 1, usize::from(t < 0.002), 0, 1e-10)
        };
        // before the window the leg is slower; inside it, faster: passes
        let s = [
            air(0.001, 60.0, 10.0),
            air(0.02, 60.0, 66.0),
            air(0.03, 62.0, 70.0),
        ];
        let c = checks(&s, 0.01, dir.path(), &mut Vec::new()).unwrap();
        let acc = c.last().unwrap();
        assert_eq!(acc.simulated, 68.0 / 61.0);
        assert!(acc.pass);
        let s = [air(0.02, 60.0, 58.0), air(0.03, 62.0, 60.0)];
        let c = checks(&s, 0.01, dir.path(), &mut Vec::new()).unwrap();
        assert!(!c.last().unwrap().pass);
        assert!(dir.path().join("air_velocity.png").is_file());
    }
}
