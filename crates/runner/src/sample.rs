//! Integral quantities of one coupling step, and their CSV log.

use serde::Serialize;
use std::path::Path;

/// What a run records after every coupling step (SI units; Pa for pressures). A quantity that
/// could not be measured (no inlet or outlet patch found, no particles for a bed) is `None`,
/// an empty cell in the CSV, never 0.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Sample {
    /// Simulated time at the end of the step, s.
    pub time: f64,
    /// Mean inflow velocity through the inlet patch, −Σ(U_b·S_f)/Σ|S_f|, m/s.
    pub inlet_velocity: Option<f64>,
    /// Area-averaged pressure on the inlet minus the outlet, ρ·(p_in − p_out), Pa.
    pub pressure_drop: Option<f64>,
    /// Bed height above the floor along the column axis, m.
    pub bed_height: Option<f64>,
    /// Mean voidage of the bed, 1 − V_p/(A·L).
    pub bed_voidage: Option<f64>,
    /// Translational kinetic energy of the particles, J.
    pub kinetic_energy: f64,
    /// Mean particle velocity along the column axis, m/s.
    pub mean_axial_velocity: f64,
    /// Velocity of the first particle along the axis, m/s (the settling case's observable).
    pub first_axial_velocity: f64,
    /// Total fluid force on the particles along the axis, N.
    pub fluid_force_axial: f64,
    /// Σ particle volume, m³.
    pub particle_volume: f64,
    /// Volume deposited in cells, m³.
    pub deposited_volume: f64,
    /// Volume outside the mesh, m³.
    pub outside_volume: f64,
    /// Solid volume removed by the voidage floor, m³.
    pub clipped_volume: f64,
    /// Smallest cell voidage before clipping.
    pub min_voidage: f64,
    /// Number of particles.
    pub particles: usize,
    /// Sauter mean diameter of the particles, m.
    pub sauter_diameter: Option<f64>,
    /// Mean particle density (mass / volume), kg/m³.
    pub mean_density: Option<f64>,
    /// Buoyant weight of the particles per column cross-section, (m − ρ V) g / A, Pa.
    pub weight_per_area: Option<f64>,
    /// Particles that entered since the previous step (inserted; [`couple::population`]).
    pub particles_in: usize,
    /// Particles that left since the previous step (lost, deleted).
    pub particles_out: usize,
    /// Their volume, m³: `particle_volume` − the previous row's = `volume_in` − `volume_out`.
    pub volume_in: f64,
    /// m³.
    pub volume_out: f64,
    /// Their momentum Σ ρ_p V v, kg·m/s.
    pub momentum_in: [f64; 3],
    /// kg·m/s.
    pub momentum_out: [f64; 3],
    /// Mean outflow velocity through the outlet patch, Σ(U_b·S_f)/Σ|S_f|, m/s (cases whose
    /// validationDict names an outlet for it: [`crate::conveyor`]).
    pub outlet_velocity: Option<f64>,
    /// Particles in the conveyor's tube (axial coordinate ≥ its `tubeFrom`).
    pub tube_particles: Option<usize>,
    /// Their mean axial velocity, m/s (`None` when the tube holds none).
    pub tube_axial_velocity: Option<f64>,
    /// Particles still in the conveyor's chamber (axial coordinate < its `chamberTop`).
    pub chamber_particles: Option<usize>,
    /// Of those, the particles in its annulus (axial coordinate < its `annulusTop`).
    pub annulus_particles: Option<usize>,
    /// The conveyor's bed: particles that were ever counted in the annulus before leaving it
    /// ([`crate::conveyor::Evacuation`]; on rank 0 only).
    pub bed_particles: Option<usize>,
    /// Of the bed, the particles that have been in the annulus at every sample so far.
    pub bed_never_left: Option<usize>,
    /// Particles in the annulus that had left it before (fallen back from the plenum).
    pub annulus_returned: Option<usize>,
    /// Heat the fluid gave the particles at the step's exchange, Σ_p q_p, W (cases with heat:
    /// [`couple::heat`]).
    pub heat_to_particles: Option<f64>,
    /// Heat the fluid lost by its source field, −Σ_c Tsource_c ρ c_p V_c, W; equal to
    /// `heat_to_particles` to round-off but for `heat_clipped`.
    pub heat_from_fluid: Option<f64>,
    /// Heat removed from the source field by `maxSource`, W.
    pub heat_clipped: Option<f64>,
    /// Heat the walls gave the fluid (`wallHeatTransferYagi`, [`couple::wall_heat`]), W, after
    /// its `maxSource` cut; its column is written only in runs with it.
    pub heat_from_wall: Option<f64>,
    /// Mass-weighted mean particle temperature Σ m T / Σ m, K.
    pub particle_temperature: Option<f64>,
    /// Mean gas temperature on the outlet patch (area-weighted over the patch's cells: the
    /// patch value of a zeroGradient outlet), K.
    pub outlet_temperature: Option<f64>,
    /// The full conveyor ([`crate::branch`]): particles past the branch's floor (the branch,
    /// both legs, the secondary chamber).
    pub branch_particles: Option<usize>,
    /// Particles in its vented leg.
    pub vent_leg_particles: Option<usize>,
    /// Particles in its secondary chamber.
    pub secondary_particles: Option<usize>,
    /// Volume-weighted mean axial air velocity in its downstream tube, m/s.
    pub tube_air_velocity: Option<f64>,
    /// Largest axial air velocity there, m/s.
    pub tube_air_peak: Option<f64>,
    /// Volume-weighted mean air velocity along its vented leg, m/s.
    pub vent_air_velocity: Option<f64>,
    /// Largest air velocity along it, m/s.
    pub vent_air_peak: Option<f64>,
}

const HEADER: &str = "time,inlet_velocity,pressure_drop,bed_height,bed_voidage,kinetic_energy,mean_axial_velocity,first_axial_velocity,fluid_force_axial,particle_volume,deposited_volume,outside_volume,clipped_volume,min_voidage,particles,sauter_diameter,mean_density,weight_per_area,particles_in,particles_out,volume_in,volume_out,momentum_in_x,momentum_in_y,momentum_in_z,momentum_out_x,momentum_out_y,momentum_out_z,outlet_velocity,tube_particles,tube_axial_velocity,chamber_particles,annulus_particles,bed_particles,bed_never_left,annulus_returned,heat_to_particles,heat_from_fluid,heat_clipped,particle_temperature,outlet_temperature,branch_particles,vent_leg_particles,secondary_particles,tube_air_velocity,tube_air_peak,vent_air_velocity,vent_air_peak";

/// The column a run with wall heat adds after [`HEADER`]'s.
const WALL_COLUMN: &str = ",heat_from_wall";

/// The rows of an earlier run's CSV at `path` up to time `start` (s; to a relative 10⁻⁹),
/// as text: what a run restarted at `start` keeps (none when there is no such file or its
/// header is another one).
pub fn rows_until(path: &Path, start: f64) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Vec::new();
    };
    let mut lines = text.lines();
    match lines.next() {
        Some(h) if h == HEADER || h.strip_suffix(WALL_COLUMN) == Some(HEADER) => {}
        _ => return Vec::new(),
    }
    let until = start + 1e-9 * start.abs().max(1e-300);
    lines
        .take_while(|l| {
            l.split(',')
                .next()
                .and_then(|t| t.parse::<f64>().ok())
                .is_some_and(|t| t <= until)
        })
        .map(str::to_owned)
        .collect()
}

/// Writes the samples as CSV (header line, the `kept` rows of an earlier run, one row per
/// coupling step), atomically.
pub fn write_csv(path: &Path, kept: &[String], samples: &[Sample]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    atomic_write::write_atomically(path, |w| {
        use std::io::Write;
        let wall = samples.iter().any(|s| s.heat_from_wall.is_some());
        let wall_column = if wall { WALL_COLUMN } else { "" };
        writeln!(w, "{HEADER}{wall_column}")?;
        for row in kept {
            writeln!(w, "{row}")?;
        }
        // an unmeasured quantity is an empty cell
        let o = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:?}"));
        let n = |x: Option<usize>| x.map_or(String::new(), |x| x.to_string());
        for s in samples {
            write!(
                w,
                "{:?},{},{},{},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{},{},{},{},{},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                s.time,
                o(s.inlet_velocity),
                o(s.pressure_drop),
                o(s.bed_height),
                o(s.bed_voidage),
                s.kinetic_energy,
                s.mean_axial_velocity,
                s.first_axial_velocity,
                s.fluid_force_axial,
                s.particle_volume,
                s.deposited_volume,
                s.outside_volume,
                s.clipped_volume,
                s.min_voidage,
                s.particles,
                o(s.sauter_diameter),
                o(s.mean_density),
                o(s.weight_per_area),
                s.particles_in,
                s.particles_out,
                s.volume_in,
                s.volume_out,
                s.momentum_in[0],
                s.momentum_in[1],
                s.momentum_in[2],
                s.momentum_out[0],
                s.momentum_out[1],
                s.momentum_out[2],
                o(s.outlet_velocity),
                n(s.tube_particles),
                o(s.tube_axial_velocity),
                n(s.chamber_particles),
                n(s.annulus_particles),
                n(s.bed_particles),
                n(s.bed_never_left),
                n(s.annulus_returned),
                o(s.heat_to_particles),
                o(s.heat_from_fluid),
                o(s.heat_clipped),
                o(s.particle_temperature),
                o(s.outlet_temperature),
                n(s.branch_particles),
                n(s.vent_leg_particles),
                n(s.secondary_particles),
                o(s.tube_air_velocity),
                o(s.tube_air_peak),
                o(s.vent_air_velocity),
                o(s.vent_air_peak)
            )?;
            match wall {
                true => writeln!(w, ",{}", o(s.heat_from_wall))?,
                false => writeln!(w)?,
            }
        }
        Ok(())
    })
}

/// The mean of the plateau quantities over `run` (time: the last one's).
pub(crate) fn mean_of(run: &[Sample]) -> Sample {
    let k = run.len() as f64;
    // a quantity missing from one sample is missing from the mean
    let avg =
        |f: fn(&Sample) -> Option<f64>| run.iter().map(f).sum::<Option<f64>>().map(|sum| sum / k);
    Sample {
        time: run[run.len() - 1].time,
        inlet_velocity: avg(|s| s.inlet_velocity),
        pressure_drop: avg(|s| s.pressure_drop),
        bed_height: avg(|s| s.bed_height),
        bed_voidage: avg(|s| s.bed_voidage),
        sauter_diameter: avg(|s| s.sauter_diameter),
        weight_per_area: avg(|s| s.weight_per_area),
        ..run[run.len() - 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trips_header_and_values() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("post/integrals.csv");
        let s = Sample {
            time: 0.1,
            pressure_drop: Some(23.25),
            particles: 7,
            ..Sample::default()
        };
        write_csv(&p, &[], &[s, s]).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        let cols: Vec<&str> = lines[0].split(',').collect();
        let vals: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(cols.len(), vals.len());
        let at = |name: &str| vals[cols.iter().position(|c| *c == name).unwrap()];
        assert_eq!(at("time").parse::<f64>().unwrap(), 0.1);
        assert_eq!(at("pressure_drop").parse::<f64>().unwrap(), 23.25);
        assert_eq!(at("particles"), "7");
        // not measured: empty, not 0
        assert_eq!(at("inlet_velocity"), "");
        assert_eq!(at("bed_height"), "");
    }

    /// A restarted run keeps the earlier rows up to its start time and appends its own.
    #[test]
    fn a_restart_keeps_the_rows_until_its_start() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("integrals.csv");
        let at = |time| Sample {
            time,
            ..Sample::default()
        };
        write_csv(&p, &[], &[at(0.001), at(0.002), at(0.003)]).unwrap();
        // 0.002 as a sum of steps: within round-off of the start time 0.002
        let kept = rows_until(&p, 0.0020000000000000005);
        assert_eq!(kept.len(), 2);
        write_csv(&p, &kept, &[at(0.003)]).unwrap();
        let times: Vec<f64> = std::fs::read_to_string(&p)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap().parse().unwrap())
            .collect();
        assert_eq!(times, [0.001, 0.002, 0.003]);
        assert!(rows_until(&dir.path().join("none.csv"), 1.0).is_empty());
    }
}
