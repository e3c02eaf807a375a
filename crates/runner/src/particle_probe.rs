//! CFDEM's `probeModel particleProbe` during a run: per force model the file
//! `<case>/particleProbes/<start time>/<model>.logDat.<rank>` (CFDEM-PUBLIC's
//! `particleProbe.C`: `probeSubDir = dirName_/timeName()`, the file `sprintf("%s%s%d",
//! logFileName, ".", rank)` with `logFileName = typeName + ".logDat"`), written only with
//! `verboseToFile`. Its header (`writeHeader`) and lines (`writeProbe`), as the C++ streams
//! them:
//!
//! ```text
//! #processor: 0
//! #index   time      ||  vectorData:     dragForce   [ ||  position]
//! <index>   <time>   ||   <Fx>   <Fy>   <Fz>   <Urx>   <Ury>   <Urz>   [||   <x>   <y>   <z>]
//! ```
//!
//! The header names only the first vector (the force) unless `probeDebug`, but a line holds
//! every vector the model hands over (the drags add U_f − v_p). With `probeDebug` CFDEM also
//! writes the models' internal scalars (Rep, Cd, β, V_s…) after `||   scalarData:`; foamgrain
//! does not (the configuration warns), so neither that header part nor those columns appear. The time is printed with
//! `IOstream::defaultPrecision() + 7` significant digits (controlDict's `writePrecision` + 7),
//! the vectors and the position with `writePrecision` (default 3), C++'s default float format
//! (`%g`, [`cfmt::format_g`]). A line is written every `printEvery` coupling steps (or only at
//! step `printOnlyAtStep`) for the particles listed in `particleIDsToSample` (or all with
//! `sampleAll`) whose cell is found; the index is the particle's position in the coupler's
//! particle order (by tag: CFDEM's index on one rank when the tags run from 1). The values are
//! those of the exchange, before the fluid advances ([`couple::probe`]). The files are kept in
//! memory and rewritten whole (atomically) after each printed step. One rank only: on several
//! ranks the run warns and writes none.

use crate::error::RunError;
use couple::config::monitors::ParticleProbe;
use couple::forces::Physics;
use couple::interpolate::Placement;
use couple::probe::{particle_probes, probed_models};
use couple::{FluidState, ParticleState};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The probe files of one run.
pub(crate) struct ParticleProbes {
    cfg: ParticleProbe,
    /// One (path, text) per probed force model.
    files: Vec<(PathBuf, String)>,
    /// Coupling steps counted since the last printed one (CFDEM's `printCounter_`).
    counter: u64,
    /// Significant digits of the time (controlDict's `writePrecision` + 7).
    time_digits: usize,
}

impl ParticleProbes {
    /// The probes of `cfg` for the force models of `physics` in the case `cfd` started at the
    /// time named `start`, on `rank`; `None` without `verboseToFile` (CFDEM writes nothing).
    pub(crate) fn new(
        cfg: &ParticleProbe,
        physics: &Physics,
        cfd: &Path,
        start: &str,
        rank: usize,
        write_precision: usize,
    ) -> Option<ParticleProbes> {
        if !cfg.verbose_to_file {
            return None;
        }
        let dir = cfd.join("particleProbes").join(start);
        let files = probed_models(physics)
            .into_iter()
            .map(|(model, names)| {
                let mut h = format!("#processor: {rank}\n#index   time      ||  vectorData:     ");
                // `writeHeader`: the first vector only, all with `probeDebug`
                let shown = if cfg.debug { names.len() } else { 1 };
                for name in &names[..shown] {
                    let _ = write!(h, "{name}   ");
                }
                h.push_str(if cfg.include_position {
                    " ||  position\n"
                } else {
                    "\n"
                });
                (dir.join(format!("{model}.logDat.{rank}")), h)
            })
            .collect();
        Some(ParticleProbes {
            cfg: cfg.clone(),
            files,
            counter: 0,
            time_digits: write_precision + 7,
        })
    }

    /// CFDEM's `setCounter`: whether this coupling step prints.
    fn prints_now(&mut self) -> bool {
        self.counter += 1;
        match self.cfg.print_only_at {
            Some(at) => self.counter == at,
            None if self.counter >= self.cfg.print_every => {
                self.counter = 0;
                true
            }
            None => false,
        }
    }

    /// Probes one coupling step at `time` (s) with the exchange's fluid and particles, and
    /// rewrites the files when it prints.
    pub(crate) fn sample(
        &mut self,
        time: f64,
        physics: &Physics,
        placement: &Placement,
        fluid: &FluidState<'_>,
        voidage: &[f64],
        particles: &ParticleState<'_>,
    ) -> Result<(), RunError> {
        if !self.prints_now() {
            return Ok(());
        }
        let digits = self.cfg.write_precision;
        let g = |x: f64| cfmt::format_g(x, digits);
        let time = cfmt::format_g(time, self.time_digits);
        let indices: Vec<usize> = match self.cfg.sample_all {
            true => (0..particles.len()).collect(),
            false => self
                .cfg
                .ids
                .iter()
                .map(|&i| i as usize)
                .filter(|&i| i < particles.len())
                .collect(),
        };
        for i in indices {
            let Some(probes) = particle_probes(physics, placement, fluid, voidage, particles, i)
            else {
                continue;
            };
            for (probe, (_, text)) in probes.iter().zip(&mut self.files) {
                let _ = write!(text, "{i}   {time}   ||   ");
                for v in &probe.vectors {
                    let _ = write!(text, "{}   {}   {}   ", g(v.x), g(v.y), g(v.z));
                }
                if self.cfg.include_position {
                    let x = particles.position[i];
                    let _ = writeln!(text, "||   {}   {}   {}", g(x.x), g(x.y), g(x.z));
                } else {
                    text.push('\n');
                }
            }
        }
        self.write()
    }

    fn write(&self) -> Result<(), RunError> {
        for (path, text) in &self.files {
            let io = |source| RunError::Io {
                path: path.clone(),
                source,
            };
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir).map_err(io)?;
            }
            atomic_write::write_atomically(path, |w| w.write_all(text.as_bytes())).map_err(io)?;
        }
        Ok(())
    }
}
