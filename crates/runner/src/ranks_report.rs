//! What each rank of an N-rank run held and exchanged: the evidence that no rank holds all
//! particles and that the exchange is sparse (`postProcessing/ranks.csv` and the run's log).

use couple::Ranks;
use std::io::Write as _;
use std::path::Path;

/// One rank's figures at the end of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RankFigures {
    /// The rank.
    pub rank: usize,
    /// Particles it held at the end.
    pub particles: usize,
    /// The most it held after any coupling step.
    pub particles_max: usize,
    /// Cells its particles touched in the last exchange (`None` on one rank, where the coupler
    /// does not list them).
    pub cells_touched: Option<usize>,
    /// Bytes it sent to other coupler ranks per coupling step (mean over the run).
    pub sent_per_step: f64,
    /// Bytes it received from other coupler ranks per coupling step (mean over the run).
    pub received_per_step: f64,
    /// Bytes it sent straight to the fluid solver's ranks per coupling step (`None` when the
    /// fluid is on rank 0).
    pub solver_sent_per_step: Option<f64>,
    /// Bytes it received straight from the fluid solver's ranks per coupling step.
    pub solver_received_per_step: Option<f64>,
    /// Peak resident memory of its process, MiB (`VmHWM`; `None` where not reported).
    pub peak_mib: Option<f64>,
    /// Resident memory of its process at the end, MiB (`VmRSS`; `None` where not reported).
    pub end_mib: Option<f64>,
    /// Cells of the mesh its coupler held at the end (its part, [`couple::part`], or the whole
    /// mesh).
    pub cells_held: usize,
    /// Parts of the mesh it cut (`None`: it held the whole mesh).
    pub mesh_cuts: Option<u64>,
    /// What its coupler and fluid side held at the end for the cells, MiB
    /// ([`couple::HeldBytes::mesh`] and [`couple::FluidSide::held_bytes`]).
    pub mesh_mib: f64,
    /// What its coupler and particle side held at the end for the particles, MiB
    /// ([`couple::HeldBytes::particles`] and [`couple::ParticleSide::held_bytes`]; not the DEM
    /// library's own arrays).
    pub particle_mib: f64,
}

/// What one rank gives [`gather`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Local {
    /// Particles it holds now.
    pub particles: usize,
    /// The most it held after any coupling step.
    pub particles_max: usize,
    /// Cells its particles touched in the last exchange (`None` on one rank).
    pub cells_touched: Option<usize>,
    /// Bytes sent to and received from the solver's ranks (`None`: the fluid on rank 0).
    pub solver_traffic: Option<(u64, u64)>,
    /// Cells of the mesh its coupler holds.
    pub cells_held: usize,
    /// Parts of the mesh it cut (`None`: the whole mesh).
    pub mesh_cuts: Option<u64>,
    /// Bytes held for the cells and for the particles ([`RankFigures::mesh_mib`],
    /// [`RankFigures::particle_mib`]).
    pub held: couple::HeldBytes,
}

/// Bytes in a MiB.
const MIB: f64 = 1024.0 * 1024.0;

/// Peak resident set size of this process in MiB (`VmHWM` of `/proc/self/status`), if the
/// platform reports it.
pub fn peak_mib() -> Option<f64> {
    status_mib("VmHWM:")
}

/// A memory line of `/proc/self/status` (kB) in MiB.
fn status_mib(key: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Every rank's figures on rank 0 (collective; empty on the other ranks).
pub fn gather(ranks: &dyn Ranks, local: Local, steps: u64) -> Vec<RankFigures> {
    let (sent, received) = ranks.traffic();
    let per_step = |b: u64| b as f64 / steps.max(1) as f64;
    let solver_traffic = local.solver_traffic;
    let record = [
        local.particles as f64,
        local.particles_max as f64,
        local.cells_touched.map_or(f64::NAN, |c| c as f64),
        per_step(sent),
        per_step(received),
        peak_mib().unwrap_or(f64::NAN),
        solver_traffic.map_or(f64::NAN, |t| per_step(t.0)),
        solver_traffic.map_or(f64::NAN, |t| per_step(t.1)),
        status_mib("VmRSS:").unwrap_or(f64::NAN),
        local.cells_held as f64,
        local.mesh_cuts.map_or(f64::NAN, |c| c as f64),
        local.held.mesh as f64 / MIB,
        local.held.particles as f64 / MIB,
    ];
    ranks
        .gather(&record)
        .iter()
        .enumerate()
        .filter(|(_, r)| r.len() == record.len())
        .map(|(rank, r)| RankFigures {
            rank,
            particles: r[0] as usize,
            particles_max: r[1] as usize,
            cells_touched: r[2].is_finite().then_some(r[2] as usize),
            sent_per_step: r[3],
            received_per_step: r[4],
            peak_mib: r[5].is_finite().then_some(r[5]),
            solver_sent_per_step: r[6].is_finite().then_some(r[6]),
            solver_received_per_step: r[7].is_finite().then_some(r[7]),
            end_mib: r[8].is_finite().then_some(r[8]),
            cells_held: r[9] as usize,
            mesh_cuts: r[10].is_finite().then_some(r[10] as u64),
            mesh_mib: r[11],
            particle_mib: r[12],
        })
        .collect()
}

/// The figures as `ranks.csv` (an unreported memory is an empty cell).
pub fn write_csv(path: &Path, figures: &[RankFigures]) -> std::io::Result<()> {
    let mut text = String::from(
        "rank,particles,particles_max,cells_touched,bytes_sent_per_step,bytes_received_per_step,peak_memory_mib,solver_bytes_sent_per_step,solver_bytes_received_per_step,end_memory_mib,cells_held,mesh_cuts,mesh_mib,particle_mib\n",
    );
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
    for f in figures {
        text.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{:.1},{:.1}\n",
            f.rank,
            f.particles,
            f.particles_max,
            f.cells_touched.map_or(String::new(), |c| c.to_string()),
            f.sent_per_step,
            f.received_per_step,
            f.peak_mib.map_or(String::new(), |m| format!("{m:.1}")),
            opt(f.solver_sent_per_step),
            opt(f.solver_received_per_step),
            f.end_mib.map_or(String::new(), |m| format!("{m:.1}")),
            f.cells_held,
            f.mesh_cuts.map_or(String::new(), |c| c.to_string()),
            f.mesh_mib,
            f.particle_mib,
        ));
    }
    atomic_write::write_atomically(path, |w| w.write_all(text.as_bytes()))
}

/// The figures as log lines.
pub fn table(figures: &[RankFigures]) -> Vec<String> {
    let mut lines = vec![
        "rank  particles (max)      cells touched  cells held (cuts)  kB sent/step  \
         kB received/step  peak MiB  end MiB  mesh MiB  particles MiB  \
         solver kB sent/received per step"
            .into(),
    ];
    let kb = |x: Option<f64>| x.map_or("—".into(), |v| format!("{:.1}", v / 1e3));
    for f in figures {
        lines.push(format!(
            "{:4}  {:9} ({:9})  {:>13}  {:>10} ({:>4})  {:12.1}  {:16.1}  {:>8}  {:>7}  {:8.1}  \
             {:13.1}  {} / {}",
            f.rank,
            f.particles,
            f.particles_max,
            f.cells_touched.map_or("—".into(), |c| c.to_string()),
            f.cells_held,
            f.mesh_cuts.map_or("—".into(), |c| c.to_string()),
            f.sent_per_step / 1e3,
            f.received_per_step / 1e3,
            f.peak_mib.map_or("—".into(), |m| format!("{m:.0}")),
            f.end_mib.map_or("—".into(), |m| format!("{m:.0}")),
            f.mesh_mib,
            f.particle_mib,
            kb(f.solver_sent_per_step),
            kb(f.solver_received_per_step),
        ));
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_rank_reports_itself_and_an_unmeasured_memory_stays_empty() {
        let local = Local {
            particles: 7,
            particles_max: 9,
            cells_held: 12,
            held: couple::HeldBytes {
                mesh: 3 << 20,
                particles: 1 << 19,
            },
            ..Local::default()
        };
        let f = gather(&couple::Serial::default(), local, 2);
        assert_eq!(f.len(), 1);
        assert_eq!(
            (f[0].particles, f[0].particles_max, f[0].cells_touched),
            (7, 9, None)
        );
        assert_eq!((f[0].sent_per_step, f[0].received_per_step), (0.0, 0.0));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ranks.csv");
        assert_eq!((f[0].cells_held, f[0].mesh_cuts), (12, None));
        let unmeasured = RankFigures {
            peak_mib: None,
            end_mib: None,
            ..f[0]
        };
        write_csv(&path, &[unmeasured]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().nth(1), Some("0,7,9,,0,0,,,,,12,,3.0,0.5"));
        let to_solver = Local {
            cells_touched: Some(3),
            solver_traffic: Some((100, 50)),
            ..local
        };
        let to_solver = gather(&couple::Serial::default(), to_solver, 2);
        assert_eq!(
            (
                to_solver[0].solver_sent_per_step,
                to_solver[0].solver_received_per_step
            ),
            (Some(50.0), Some(25.0))
        );
    }
}
