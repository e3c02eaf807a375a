//! Time-averaged voidage across a bed's width in thin horizontal slabs — the quantity Müller et
//! al.'s magnetic-resonance measurements of a pseudo-2D fluidised bed give (time-averaged
//! voidage across the width at fixed heights above the distributor, through the bed's whole
//! thickness). `voidageProfiles { … }` in a `fluidisedBed` validationDict asks for it.
//!
//! At each coupling step the particles' volume inside each slab `[h − s/2, h + s/2]` (h above
//! the column's floor, s the slab's thickness) is summed per width bin, exactly: a sphere of
//! radius R whose centre lies at height z holds, between heights a < b, the volume
//! V(b) − V(a), V(x) the ball's volume below the plane at x: the cap of height x − z + R,
//! π h² (3R − h)/3 clamped to 0 ≤ h ≤ 2R ([`voidage::sphere_box::cap_volume`]). The slice is
//! given to the bin of the particle's centre along the width (a slice reaches at most R into the next
//! bin; with 22 bins over 44 mm and R = 0.6 mm, the same choice as the study script
//! `benches/fluidised-bed-study/analyse.py`). The bin's solid fraction is the sum over its
//! volume (bin width × the column's depth × s), the depth being the cross-section over the
//! width. Voidage = 1 − solid fraction.
//!
//! The run keeps one row per coupling step on rank 0 (sums over all ranks) and writes them
//! to `postProcessing/voidage_profiles.csv` at its write times; the check averages the rows of
//! the fluidised bed's window ([`crate::fluidised::window`]) and compares the width-mean voidage
//! (the bins `wallBins` away from each wall, as the measurement's points span) with the
//! measured one at each height.

use crate::error::{io_err, RunError};
use crate::validation::Check;
use couple::Ranks;
use mesh::v3::V3;
use std::path::Path;
use voidage::sphere_box::cap_volume;

/// `voidageProfiles` of a `fluidisedBed` validationDict.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileSpec {
    /// Unit vector across the bed's width (the profile's abscissa).
    pub width_direction: V3,
    /// Slab centres above the column's floor, m.
    pub heights: Vec<f64>,
    /// Slab thickness, m.
    pub slab: f64,
    /// Bins across the width.
    pub bins: usize,
    /// Bins at each wall left out of the width mean (the measurement's points do not reach the
    /// walls).
    pub wall_bins: usize,
    /// The measured width-mean voidage at each height.
    pub measured: Vec<f64>,
    /// The accepted absolute difference at each height (the measurement's own spread).
    pub tolerance: Vec<f64>,
    /// `knownGap`: what the case's documentation traces a failing height to, added to that
    /// check's message.
    pub known_gap: Option<String>,
}

impl ProfileSpec {
    /// Reads the sub-dictionary `voidageProfiles`; errors name the key.
    pub(crate) fn read(d: &foam::Dict) -> Result<ProfileSpec, String> {
        let err = |key: &str, e: String| format!("voidageProfiles: {key}: {e}");
        let list = |key: &str| crate::probes::number_list(d, key).map_err(|e| err(key, e));
        let w = V3::from(
            d.vector("widthDirection")
                .map_err(|e| err("widthDirection", e.to_string()))?,
        );
        let n = w.norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(err("widthDirection", "must be a non-zero vector".into()));
        }
        let slab = d.f64("slab").map_err(|e| err("slab", e.to_string()))?;
        if !(slab.is_finite() && slab > 0.0) {
            return Err(err(
                "slab",
                format!("must be a positive length, got {slab}"),
            ));
        }
        let count = |key: &str| -> Result<usize, String> {
            let v = d.label(key).map_err(|e| err(key, e.to_string()))?;
            usize::try_from(v).map_err(|_| err(key, format!("must not be negative, got {v}")))
        };
        let (bins, wall_bins) = (count("bins")?, count("wallBins")?);
        if bins == 0 || 2 * wall_bins >= bins {
            return Err(err(
                "bins",
                format!("{bins} bins leave none inside {wall_bins} wall bins at each side"),
            ));
        }
        let spec = ProfileSpec {
            width_direction: w / n,
            heights: list("heights")?,
            slab,
            bins,
            wall_bins,
            measured: list("measured")?,
            tolerance: list("tolerance")?,
            known_gap: match d.contains("knownGap") {
                true => Some(
                    d.word("knownGap")
                        .map_err(|e| err("knownGap", e.to_string()))?
                        .to_owned(),
                ),
                false => None,
            },
        };
        let k = spec.heights.len();
        if k == 0 || spec.measured.len() != k || spec.tolerance.len() != k {
            return Err(format!(
                "voidageProfiles: heights, measured and tolerance must be lists of the same \
                 non-zero length (got {k}, {}, {})",
                spec.measured.len(),
                spec.tolerance.len()
            ));
        }
        if let Some(t) = spec
            .tolerance
            .iter()
            .find(|t| !(t.is_finite() && **t > 0.0))
        {
            return Err(err("tolerance", format!("must be positive, got {t}")));
        }
        Ok(spec)
    }
}

/// Volume of a ball of radius `r` centred at height `zc` lying between heights `a` < `b`, m³
/// (see the module's text).
pub fn slab_volume(r: f64, zc: f64, a: f64, b: f64) -> f64 {
    // the ball below a plane at height x is the cap of height x − zc + R
    let below = |x: f64| cap_volume(r, x - zc + r);
    below(b) - below(a)
}

/// The slabs of a column: where its width starts and ends along the width direction and its
/// depth (cross-section over width), with the spec.
#[derive(Clone, Debug)]
pub(crate) struct Profiler {
    spec: ProfileSpec,
    axis: V3,
    floor: f64,
    /// The column's extent along the width direction, m.
    lo: f64,
    hi: f64,
    /// Cross-section over width, m.
    depth: f64,
}

impl Profiler {
    /// The profiler of a column with points `points`, `axis` up, `floor` and cross-section
    /// `area` (m²).
    pub(crate) fn new(
        spec: &ProfileSpec,
        points: &[[f64; 3]],
        axis: V3,
        floor: f64,
        area: f64,
    ) -> Profiler {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in points {
            let x = V3::from(*p).dot(&spec.width_direction);
            lo = lo.min(x);
            hi = hi.max(x);
        }
        Profiler {
            spec: spec.clone(),
            axis,
            floor,
            lo,
            hi,
            depth: area / (hi - lo),
        }
    }

    /// Rank 0's column extents on every rank (collective): a rank holding a part of the mesh
    /// ([`couple::part`]) sees only its part's points.
    pub(crate) fn agree(&mut self, ranks: &dyn Ranks) {
        let mut x = [self.floor, self.lo, self.hi, self.depth];
        ranks.broadcast(&mut x);
        [self.floor, self.lo, self.hi, self.depth] = x;
    }

    /// The solid fraction of every (height, bin), heights outer, summed over the ranks
    /// (collective).
    pub(crate) fn measure(&self, position: &[V3], radius: &[f64], ranks: &dyn Ranks) -> Vec<f64> {
        let s = &self.spec;
        let bin_width = (self.hi - self.lo) / s.bins as f64;
        let mut sums = vec![0.0; s.heights.len() * s.bins];
        for (x, &r) in position.iter().zip(radius) {
            let z = x.dot(&self.axis) - self.floor;
            let across = (x.dot(&s.width_direction) - self.lo) / bin_width;
            let j = (across.floor().max(0.0) as usize).min(s.bins - 1);
            for (k, h) in s.heights.iter().enumerate() {
                let (a, b) = (h - 0.5 * s.slab, h + 0.5 * s.slab);
                if z + r > a && z - r < b {
                    sums[k * s.bins + j] += slab_volume(r, z, a, b);
                }
            }
        }
        ranks.all_sum(&mut sums);
        let cell = bin_width * self.depth * s.slab;
        sums.iter().map(|v| v / cell).collect()
    }

    /// The bins' centres along the width from the column's first wall, m.
    fn centres(&self) -> Vec<f64> {
        let w = (self.hi - self.lo) / self.spec.bins as f64;
        (0..self.spec.bins).map(|j| (j as f64 + 0.5) * w).collect()
    }
}

/// The rows a run recorded: time and solid fractions (heights outer, bins inner).
#[derive(Clone, Debug, Default)]
pub struct Record {
    /// The profiler (absent when the case asks for no profiles).
    pub(crate) profiler: Option<Profiler>,
    /// One row per coupling step: (time, solid fractions).
    pub rows: Vec<(f64, Vec<f64>)>,
}

impl Record {
    /// Writes the rows as `time,h<k>_b<j>,…` (voidage, not solid fraction), atomically.
    pub(crate) fn write_csv(&self, path: &Path) -> Result<(), RunError> {
        let Some(p) = &self.profiler else {
            return Ok(());
        };
        let s = &p.spec;
        atomic_write::write_atomically(path, |w| {
            use std::io::Write;
            write!(w, "time")?;
            for h in &s.heights {
                for x in p.centres() {
                    write!(w, ",eps(z={h:.5};x={x:.5})")?;
                }
            }
            writeln!(w)?;
            for (t, phi) in &self.rows {
                write!(w, "{t:?}")?;
                for v in phi {
                    write!(w, ",{:?}", 1.0 - v)?;
                }
                writeln!(w)?;
            }
            Ok(())
        })
        .map_err(io_err(path))
    }

    /// The checks over the window `t0 < t ≤ t1`: at each height the width-mean voidage
    /// (inner bins) against the measured one, with notes on the profile's wall and centre
    /// values; `None` without profiles or rows in the window.
    pub(crate) fn checks(&self, (t0, t1): (f64, f64), notes: &mut Vec<String>) -> Vec<Check> {
        let Some(p) = &self.profiler else {
            return Vec::new();
        };
        let s = &p.spec;
        let eps = 1e-9 * t1.abs().max(1e-300);
        let rows: Vec<&Vec<f64>> = self
            .rows
            .iter()
            .filter(|(t, _)| *t > t0 + eps && *t <= t1 + eps)
            .map(|(_, v)| v)
            .collect();
        if rows.is_empty() {
            notes.push("voidage profiles: no coupling step in the window".into());
            return Vec::new();
        }
        let n = rows.len() as f64;
        let mut checks = Vec::new();
        for (k, h) in s.heights.iter().enumerate() {
            let profile: Vec<f64> = (0..s.bins)
                .map(|j| 1.0 - rows.iter().map(|r| r[k * s.bins + j]).sum::<f64>() / n)
                .collect();
            let inner = &profile[s.wall_bins..s.bins - s.wall_bins];
            let mean = inner.iter().sum::<f64>() / inner.len() as f64;
            let centre = profile.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            notes.push(format!(
                "voidage profile at {:.1} mm over t = {t0:.3} … {t1:.3} s ({} steps): walls \
                 {:.3} / {:.3}, largest {centre:.3}, mean of the inner {} bins {mean:.4}",
                h * 1e3,
                rows.len(),
                profile[0],
                profile[s.bins - 1],
                inner.len()
            ));
            let (measured, tol) = (s.measured[k], s.tolerance[k]);
            checks.push(
                Check::new(
                    &format!(
                    "fluidised bed: time- and width-averaged voidage at {:.1} mm over t = {t0:.3} \
                     … {t1:.3} s vs the MR measurement (tolerance ±{tol} absolute)",
                    h * 1e3
                ),
                    mean,
                    measured,
                    "",
                    tol / measured,
                )
                .with_known_gap(s.known_gap.as_deref()),
            );
        }
        checks
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn slab_volumes_of_a_sphere_add_up_and_match_caps() {
        let (r, zc) = (0.6e-3, 0.01);
        let full = 4.0 / 3.0 * PI * r * r * r;
        // the whole ball in one slab; split in three slabs
        assert!((slab_volume(r, zc, 0.0, 0.02) - full).abs() < 1e-15 * full.max(1e-30) + 1e-24);
        let cuts = [zc - 1.0, zc - 0.3e-3, zc + 0.1e-3, zc + 1.0];
        let sum: f64 = cuts
            .windows(2)
            .map(|w| slab_volume(r, zc, w[0], w[1]))
            .sum();
        assert!((sum - full).abs() <= 1e-12 * full, "{sum} vs {full}");
        // a cap of height h: π h² (3R − h) / 3
        let h = 0.25e-3;
        let cap = PI * h * h * (3.0 * r - h) / 3.0;
        let got = slab_volume(r, zc, zc + r - h, zc + 1.0);
        assert!((got - cap).abs() <= 1e-12 * cap, "{got} vs {cap}");
        // the half ball
        assert!((slab_volume(r, zc, zc, zc + 1.0) - 0.5 * full).abs() <= 1e-12 * full);
    }

    fn spec() -> ProfileSpec {
        ProfileSpec {
            width_direction: V3::new(1.0, 0.0, 0.0),
            heights: vec![0.0164, 0.0312],
            slab: 0.002,
            bins: 4,
            wall_bins: 1,
            measured: vec![0.5, 0.5],
            tolerance: vec![0.01, 0.01],
            known_gap: Some("the reason".into()),
        }
    }

    /// A simple cubic lattice of touching spheres (spacing d) fills space to π/6 whatever slab
    /// spans a whole number of layers: a column 8 d wide, 2 d deep, the slabs 2 d thick.
    #[test]
    fn a_simple_cubic_lattice_has_solid_fraction_pi_over_six() {
        let d = 1e-3;
        let mut s = spec();
        s.slab = 2.0 * d;
        s.heights = vec![10.0 * d, 15.5 * d];
        let (nx, ny, nz) = (8, 2, 30);
        let corners = [
            [0.0, 0.0, 0.0],
            [nx as f64 * d, ny as f64 * d, nz as f64 * d],
        ];
        let p = Profiler::new(
            &s,
            &corners,
            V3::new(0.0, 0.0, 1.0),
            0.0,
            (nx * ny) as f64 * d * d,
        );
        let mut pos = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                for k in 0..nz {
                    let c = |n: usize| (n as f64 + 0.5) * d;
                    pos.push(V3::new(c(i), c(j), c(k)));
                }
            }
        }
        let radius = vec![0.5 * d; pos.len()];
        let phi = p.measure(&pos, &radius, &couple::Serial::default());
        assert_eq!(phi.len(), 8);
        for v in &phi {
            assert!((v - PI / 6.0).abs() < 1e-12, "{v} vs {}", PI / 6.0);
        }
        // a record of two such steps, checked against a measured 1 − π/6
        let mut s2 = s.clone();
        s2.measured = vec![1.0 - PI / 6.0; 2];
        let rec = Record {
            profiler: Some(Profiler { spec: s2, ..p }),
            rows: vec![(0.1, phi.clone()), (0.2, phi)],
        };
        let mut notes = Vec::new();
        let checks = rec.checks((0.05, 0.2), &mut notes);
        assert_eq!(checks.len(), 2);
        assert!(
            checks.iter().all(|c| c.pass && c.rel_error < 1e-12),
            "{checks:?}"
        );
        assert!(checks.iter().all(|c| !c.name.contains("known gap")));
        // outside the window: no rows, no checks
        assert!(rec.checks((0.2, 0.3), &mut notes).is_empty());
        // a measurement the lattice misses: the failing check carries the known gap
        let mut rec = rec;
        if let Some(p) = rec.profiler.as_mut() {
            p.spec.measured = vec![0.6, 1.0 - PI / 6.0];
        }
        let checks = rec.checks((0.05, 0.2), &mut notes);
        assert!(!checks[0].pass && checks[0].name.ends_with("known gap: the reason"));
        assert!(checks[1].pass && !checks[1].name.contains("known gap"));
    }
}
