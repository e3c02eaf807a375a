//! The packed-bed heating case in a run (`validationDict` `type packedBedHeating;`, issue 27):
//! at the sample times the run records the axial profiles of the gas temperature (cells
//! binned by their centre, volume-weighted) and of the solid temperature (particles binned by
//! their centre, mean per bin, summed over ranks), in bins one cell long from the column's
//! floor; at the end the fronts are checked against Schumann's solution
//! ([`crate::heating::check`]) for the bed as measured (voidage, height, Sauter diameter and
//! density from the first sample) with h from the coupling's own Nusselt law
//! ([`closures::heat`]) at the bed's voidage and the inlet's superficial velocity.

use crate::error::RunError;
use crate::heating::{HeatingSpec, Profile, Snapshot};
use crate::plot::{LinePlot, Series, Style};
use crate::sample::Sample;
use crate::schumann::SchumannBed;
use crate::validation::Check;
use couple::{CouplerSettings, ParticleState, Ranks};
use mesh::v3::V3;
use std::path::Path;

fn check_err(msg: impl Into<String>) -> RunError {
    RunError::Check(format!("packed-bed heating: {}", msg.into()))
}

/// What `validationDict` says of a heating case.
#[derive(Clone, Debug, PartialEq)]
pub struct HeatingCase {
    /// Unit vector along the column, downstream.
    pub axis: V3,
    /// Inlet patch name.
    pub inlet: String,
    /// Outlet patch name.
    pub outlet: String,
    /// The times (s) at which the profiles are taken (write times of the case).
    pub sample_times: Vec<f64>,
    /// Temperatures and tolerances (its `cell_size` is measured from the mesh at run time).
    pub spec: HeatingSpec,
}

/// The bins of a run: the axis, the floor, the bin length and each cell's bin and volume.
pub(crate) struct Profiler {
    axis: V3,
    floor: f64,
    width: f64,
    cells: Vec<(usize, f64)>,
    bins: usize,
    times: Vec<f64>,
    half_step: f64,
}

impl Profiler {
    /// The bins of `mesh` along `case.axis` from `floor`, one cell long (the median axial
    /// extent of the cells, from their faces' centres), for coupling steps of `dt_c` s.
    pub(crate) fn new(
        case: &HeatingCase,
        geometry: &mesh::geometry::MeshGeometry,
        mesh: &foam::PolyMesh,
        floor: f64,
        dt_c: f64,
    ) -> Profiler {
        let axis = case.axis;
        let n = mesh.n_cells;
        let mut lo = vec![f64::INFINITY; n];
        let mut hi = vec![f64::NEG_INFINITY; n];
        for (f, c) in geometry.face_centres.iter().enumerate() {
            let h = c.dot(&axis);
            let mut touch = |cell: usize| {
                lo[cell] = lo[cell].min(h);
                hi[cell] = hi[cell].max(h);
            };
            touch(mesh.owner[f] as usize);
            if let Some(&nb) = mesh.neighbour.get(f) {
                touch(nb as usize);
            }
        }
        let mut extent: Vec<f64> = (0..n).map(|c| hi[c] - lo[c]).collect();
        extent.sort_by(f64::total_cmp);
        let width = extent[n / 2];
        let bin = |x: f64| ((x - floor) / width).floor().max(0.0) as usize;
        let cells: Vec<(usize, f64)> = (0..n)
            .map(|c| {
                (
                    bin(geometry.cell_centres[c].dot(&axis)),
                    geometry.cell_volumes[c],
                )
            })
            .collect();
        let bins = cells.iter().map(|c| c.0 + 1).max().unwrap_or(0);
        Profiler {
            axis,
            floor,
            width,
            cells,
            bins,
            times: case.sample_times.clone(),
            half_step: 0.5 * dt_c,
        }
    }

    /// The bin length, m.
    pub(crate) fn cell_size(&self) -> f64 {
        self.width
    }

    /// Whether `time` is a sample time (to half a coupling step).
    /// Rank 0's bins on every rank (collective): a rank holding a part of the mesh
    /// ([`couple::part`]) sees only its part's cells (its gas bins are never read).
    pub(crate) fn agree(&mut self, ranks: &dyn Ranks) {
        let mut x = [self.floor, self.width, self.bins as f64];
        ranks.broadcast(&mut x);
        (self.floor, self.width, self.bins) = (x[0], x[1], x[2] as usize);
    }

    pub(crate) fn due(&self, time: f64) -> bool {
        self.times.iter().any(|t| (t - time).abs() < self.half_step)
    }

    /// The solid profile, Σ T and count per bin summed over ranks (collective), as (bin
    /// centre, mean T) of the bins holding particles.
    pub(crate) fn solid(&self, ps: &ParticleState<'_>, ranks: &dyn Ranks) -> Option<Profile> {
        let t = ps.temperature?;
        let mut sums = vec![0.0; 2 * self.bins];
        for (x, ti) in ps.position.iter().zip(t) {
            let b = ((x.dot(&self.axis) - self.floor) / self.width).floor();
            if b >= 0.0 && (b as usize) < self.bins {
                sums[2 * b as usize] += ti;
                sums[2 * b as usize + 1] += 1.0;
            }
        }
        ranks.all_sum(&mut sums);
        Some(self.profile(&sums))
    }

    /// The gas profile from the cell temperatures `t`: the volume-weighted mean per bin.
    pub(crate) fn gas(&self, t: &[f64]) -> Profile {
        let mut sums = vec![0.0; 2 * self.bins];
        for (&(b, v), ti) in self.cells.iter().zip(t) {
            sums[2 * b] += v * ti;
            sums[2 * b + 1] += v;
        }
        self.profile(&sums)
    }

    fn profile(&self, sums: &[f64]) -> Profile {
        let mut p = Profile {
            z: Vec::new(),
            temperature: Vec::new(),
        };
        for (b, s) in sums.chunks_exact(2).enumerate() {
            if s[1] > 0.0 {
                p.z.push((b as f64 + 0.5) * self.width);
                p.temperature.push(s[0] / s[1]);
            }
        }
        p
    }
}

/// The profiles of the bed only: the bins whose centre lies below the bed's top less one
/// particle diameter (the surface's half-filled bins are not bed).
fn within(p: &Profile, top: f64) -> Profile {
    let keep: Vec<usize> = (0..p.z.len()).filter(|&i| p.z[i] <= top).collect();
    Profile {
        z: keep.iter().map(|&i| p.z[i]).collect(),
        temperature: keep.iter().map(|&i| p.temperature[i]).collect(),
    }
}

/// What a heating run recorded for its check: the profiles at the sample times, the bins'
/// length (m) and the particles' heat capacity the deck declares (J/(kg K)).
#[derive(Clone, Debug, Default)]
pub struct Profiles {
    /// The snapshots, in time order.
    pub snapshots: Vec<Snapshot>,
    /// The bin length (one cell), m.
    pub cell_size: f64,
    /// `thermalCapacity` of the run deck.
    pub particle_capacity: Option<f64>,
}

/// The checks of a heating run: the fronts of the recorded profiles against Schumann's
/// solution.
pub(crate) fn checks(
    case: &HeatingCase,
    settings: &CouplerSettings,
    profiles: &Profiles,
    samples: &[Sample],
    post: &Path,
    notes: &mut Vec<String>,
) -> Result<Vec<Check>, RunError> {
    if profiles.snapshots.is_empty() {
        return Err(check_err(format!(
            "the run reached none of the sample times {:?} s (validationDict's sampleTimes)",
            case.sample_times
        )));
    }
    let (particle_capacity, cell_size, snapshots) = (
        profiles.particle_capacity,
        profiles.cell_size,
        &profiles.snapshots,
    );
    let heat = settings.heat.ok_or_else(|| {
        check_err("a packedBedHeating case needs a heat-transfer model in couplingProperties")
    })?;
    let c_s = particle_capacity
        .ok_or_else(|| check_err("the run deck declares no `thermalCapacity` for the particles"))?;
    let first = samples
        .first()
        .ok_or_else(|| check_err("the run recorded no coupling step"))?;
    let measured = |what: &str, v: Option<f64>| {
        v.filter(|x| x.is_finite() && *x > 0.0)
            .ok_or_else(|| check_err(format!("the first sample has no {what}")))
    };
    let eps = measured("bed voidage", first.bed_voidage)?;
    let height = measured("bed height", first.bed_height)?;
    let d = measured("Sauter diameter", first.sauter_diameter)?;
    let rho_s = measured("particle density", first.mean_density)?;
    let u_sup = measured("inlet velocity", first.inlet_velocity)?;
    let ph = &settings.physics;
    let re = closures::heat::reynolds(heat.reynolds, d, u_sup / eps, ph.nu, eps);
    let pr = closures::heat::prandtl(heat.cp, ph.nu, ph.rho, heat.lambda);
    let nu_number = heat.nusselt_scale
        * closures::heat::nusselt(heat.nusselt, re, pr, eps.max(heat.voidage_floor));
    let h = closures::heat::heat_transfer_coefficient(heat.lambda, nu_number, d);
    notes.push(format!(
        "packed-bed heating: bed ε {eps:.4}, height {height:.4} m, d {d:.4e} m, Re {re:.2}, Pr \
         {pr:.4}, Nu {nu_number:.4}, h {h:.3} W/(m² K)"
    ));
    let bed = SchumannBed::of_spheres(eps, d, rho_s, c_s, ph.rho, heat.cp, u_sup, h)
        .map_err(check_err)?;
    let top = height - d;
    let bedded: Vec<Snapshot> = snapshots
        .iter()
        .map(|s| Snapshot {
            time: s.time,
            gas: within(&s.gas, top),
            solid: within(&s.solid, top),
        })
        .collect();
    let spec = HeatingSpec {
        cell_size,
        ..case.spec
    };
    plot(&bed, &spec, &bedded, top, post)?;
    let result =
        crate::heating::check(&bed, &spec, &bedded).map_err(|e| check_err(e.to_string()))?;
    let mut checks = result.checks();
    checks.push(heat_balance(samples)?);
    Ok(checks)
}

/// The heat account over the run: the heat the fluid gave up (−Σ Tsource ρ c_p V per step,
/// plus what `maxSource` cut) against the heat the particles received (Σ q_p per step), summed
/// over the coupling steps; they must agree to round-off (relative 1e-9).
fn heat_balance(samples: &[Sample]) -> Result<Check, RunError> {
    let (mut given, mut taken) = (0.0, 0.0);
    for s in samples {
        match (s.heat_to_particles, s.heat_from_fluid, s.heat_clipped) {
            (Some(q), Some(f), Some(c)) => {
                given += q;
                taken += f + c;
            }
            _ => {
                return Err(check_err(format!(
                    "the step at t = {} s has no heat account",
                    s.time
                )))
            }
        }
    }
    Ok(Check::new(
        "heat balance: received by the particles vs given by the fluid, summed over the steps",
        given,
        taken,
        "W (sum over steps)",
        1e-9,
    ))
}

/// `heating_fronts.png`: the measured gas and solid profiles (normalised, points) and
/// Schumann's (lines) at each sample time.
fn plot(
    bed: &SchumannBed,
    spec: &HeatingSpec,
    snapshots: &[Snapshot],
    top: f64,
    post: &Path,
) -> Result<(), RunError> {
    let theta = |t: f64| {
        (t - spec.initial_temperature) / (spec.inlet_temperature - spec.initial_temperature)
    };
    let mut series = Vec::new();
    for s in snapshots {
        let curve = |f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
            (0..=200)
                .map(|i| {
                    let z = top * i as f64 / 200.0;
                    (z, f(z))
                })
                .collect()
        };
        let points = |p: &Profile| -> Vec<(f64, f64)> {
            p.z.iter()
                .zip(&p.temperature)
                .map(|(&z, &t)| (z, theta(t)))
                .collect()
        };
        series.push(Series {
            name: format!("Schumann gas, t = {} s", cfmt::format_g(s.time, 6)),
            points: curve(&|z| bed.gas(z, s.time)),
            style: Style::Line,
        });
        series.push(Series {
            name: format!("Schumann solid, t = {} s", cfmt::format_g(s.time, 6)),
            points: curve(&|z| bed.solid(z, s.time)),
            style: Style::Line,
        });
        series.push(Series {
            name: format!("gas (cells), t = {} s", cfmt::format_g(s.time, 6)),
            points: points(&s.gas),
            style: Style::Points,
        });
        series.push(Series {
            name: format!("particles (binned), t = {} s", cfmt::format_g(s.time, 6)),
            points: points(&s.solid),
            style: Style::Points,
        });
    }
    std::fs::create_dir_all(post).map_err(|source| RunError::Io {
        path: post.to_owned(),
        source,
    })?;
    LinePlot {
        title: "packed-bed heating: temperature fronts against Schumann (1929)".into(),
        x_label: "distance from the bed's inlet (m)".into(),
        y_label: "(T − T0)/(T_in − T0)".into(),
        series,
    }
    .write_png(&post.join("heating_fronts.png"))?;
    Ok(())
}

/// Reads a `packedBedHeating` validationDict body `d`; an error names the key.
pub(crate) fn read_case(d: &foam::Dict) -> Result<HeatingCase, String> {
    let err = |key: &str, e: String| format!("{key}: {e}");
    let num = |key: &str| d.f64(key).map_err(|e| err(key, e.to_string()));
    let axis = d.vector("axis").map_err(|e| err("axis", e.to_string()))?;
    let axis = V3::from(axis);
    let n = axis.norm();
    if !(n.is_finite() && n > 0.0) {
        return Err(err("axis", "must be a non-zero vector".into()));
    }
    let times = crate::probes::number_list(d, "sampleTimes").map_err(|e| err("sampleTimes", e))?;
    if times.is_empty() || times.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(err(
            "sampleTimes",
            "a list of positive times is needed".into(),
        ));
    }
    let word = |key: &str| {
        d.word(key)
            .map(str::to_owned)
            .map_err(|e| err(key, e.to_string()))
    };
    Ok(HeatingCase {
        axis: axis / n,
        inlet: word("inletPatch")?,
        outlet: word("outletPatch")?,
        sample_times: times,
        spec: HeatingSpec {
            initial_temperature: num("initialTemperature")?,
            inlet_temperature: num("inletTemperature")?,
            cell_size: f64::NAN,
            position_cells: num("positionToleranceCells")?,
            position_fraction: num("positionTolerance")?,
            width_cells: num("widthToleranceCells")?,
            width_fraction: num("widthTolerance")?,
        },
    })
}
