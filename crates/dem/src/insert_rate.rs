//! `fix insert/rate/region` and `fix insert/stream`: continuous insertion at a particle or
//! mass rate, every `insert_every` steps, into a region or behind a face ([`Source`]), as
//! LIGGGHTS 3.8.0 counts it (read in its `fix_insert.cpp`, `fix_insert_rate_region.cpp` and
//! `fix_insert_stream.cpp`; the code here is foamgrain's own). What is particular to the
//! stream (its volume, K from `extrude_length`, the carrying to the face) is in
//! [`crate::insert_stream`]. The same schedule runs `insert/pack … insert_every K`
//! ([`Rate::Fill`], read in LIGGGHTS's `fix_insert_pack.cpp`), which refills its region to
//! the target at each insertion instead of inserting at a rate.
//!
//! Counting:
//! - the rate is `particlerate ṅ` (1/s) or `massrate ṁ` (kg/s, ṅ = ṁ / m̄ with m̄ the
//!   distribution's expected particle mass); each insertion aims at n_per = ṅ · K · Δt particles
//!   (K = `insert_every`, Δt the time step when the first run starts; LIGGGHTS fixes it then);
//! - an insertion inserts ⌊n_per + u⌋ particles, u uniform in [0, 1): exactly n_per when n_per
//!   is an integer, else n_per on average (LIGGGHTS draws u from its own Park–Miller stream, so
//!   the counts agree with LIGGGHTS exactly only for an integer n_per);
//! - the total is `nparticles N` or `mass M` (N = ⌊M / m̄⌋), or unlimited (`INF`); the last
//!   insertion is cut to what is left of N;
//! - the first insertion is at step `start` (default: the step after the fix is defined), then
//!   every K steps until N particles are in;
//! - the positions are drawn as `insert/pack` draws them ([`crate::insert::place`]: uniform in
//!   the region, shrunk by the radius with `all_in yes`, rejected while overlapping with
//!   `overlapcheck yes`, `maxattempt` tries per particle wanted). A full region inserts fewer
//!   particles; the shortfall is not carried over (the insertions simply go on until N are in),
//!   and it is reported as a warning, as LIGGGHTS warns "Less insertions than requested";
//! - an insertion region reaching outside the box while any box face is fixed (`f`) is an
//!   error, as in LIGGGHTS; an extruded stream face reaching outside the box is a warning (as
//!   LIGGGHTS's "may not insert all particles correctly").
//!
//! `insert/pack … insert_every K` ([`Rate::Fill`]; no total, no rate):
//! - it inserts at the step after the fix is defined (or `start`), then every K steps for as
//!   long as the simulation runs (LIGGGHTS has no end for it either);
//! - each insertion wants the particles missing in its region
//!   ([`crate::insert::InsertTarget::missing`], counting every particle whose centre lies in
//!   the region): exactly N − n_present for `particles_in_region N`, ⌊x + u⌋ (u uniform in
//!   [0, 1), as LIGGGHTS) for `volumefraction_region` and `mass_in_region`; none if x ≤ 0
//!   (then nothing happens at that step and the next insertion is K steps later);
//! - the tries budget is ⌊maxattempt · n / (1 − ρ)⌋ with ρ how full the region is
//!   ([`crate::insert::Batch::fill_ratio`], LIGGGHTS's `calc_maxtry`), so a nearly full region
//!   still gets tries to place its last particles; what cannot be placed is not carried over
//!   (the next insertion counts the region again).
//!
//! Particles are inserted after the drift of their step, before its force evaluation (LIGGGHTS's
//! `pre_exchange`), so they receive the second half kick of that step.

use mesh::v3::V3;
use rand::{Rng, SeedableRng};

use crate::insert::{place, split, Batch, Distribution, InsertTarget, InsertVolume, RegionContent};
use crate::insert_stream::{Held, Stream};
use crate::particles::{NewParticle, Particles};
use crate::region::Region;

/// Where a rate insertion places its particles.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// `insert/rate/region … region R`.
    Region(Region),
    /// `insert/stream … insertion_face F`.
    Stream(Stream),
}

impl Source {
    /// The fix style, for messages.
    pub fn style(&self) -> &'static str {
        match self {
            Source::Region(_) => "insert/rate/region",
            Source::Stream(_) => "insert/stream",
        }
    }
}

/// How much an insertion fix inserts in total.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Total {
    /// `nparticles N`.
    Particles(u64),
    /// `mass M` (kg): ⌊M / m̄⌋ particles.
    Mass(f64),
    /// `nparticles INF` / `mass INF`.
    Unlimited,
}

/// The rate of an insertion fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rate {
    /// `particlerate ṅ` (1/s).
    Particles(f64),
    /// `massrate ṁ` (kg/s).
    Mass(f64),
    /// No rate: `insert/pack … insert_every K` refills its region ([`Source::Region`]) to the
    /// target at each insertion (module doc); its total is [`Total::Unlimited`].
    Fill(InsertTarget),
}

/// A `fix ID all insert/rate/region …` or `insert/stream …` specification.
#[derive(Debug, Clone, PartialEq)]
pub struct InsertRate {
    /// Fix id.
    pub name: String,
    /// `seed`.
    pub seed: u64,
    /// `distributiontemplate`.
    pub distribution: Distribution,
    /// `region` or `insertion_face`.
    pub source: Source,
    /// `nparticles` / `mass`.
    pub total: Total,
    /// `particlerate` / `massrate`.
    pub rate: Rate,
    /// `insert_every K` (steps, ≥ 1); 0 for a stream with `extrude_length`, whose K follows
    /// from the time step ([`Stream::resolve`]).
    pub every: u64,
    /// `start` step; `None`: the step after the fix is defined.
    pub start: Option<u64>,
    /// `vel constant vx vy vz` (m/s).
    pub velocity: V3,
    /// `omega constant wx wy wz` (rad/s).
    pub omega: V3,
    /// `all_in yes`.
    pub all_in: bool,
    /// `overlapcheck yes` (LIGGGHTS's default).
    pub overlap_check: bool,
    /// `maxattempt` (default 50).
    pub max_attempt: u32,
}

impl InsertRate {
    /// The fix style, for messages.
    pub fn style(&self) -> &'static str {
        match self.rate {
            Rate::Fill(_) => "insert/pack",
            _ => self.source.style(),
        }
    }

    /// The number of particles to insert in total (`None`: unlimited).
    pub fn total_particles(&self) -> Option<u64> {
        match self.total {
            Total::Particles(n) => Some(n),
            Total::Mass(m) => Some((m / self.distribution.mass_expect()).floor() as u64),
            Total::Unlimited => None,
        }
    }

    /// Particles per insertion, n_per = ṅ · K · Δt (`dt` in s, K = [`InsertRate::every`]).
    pub fn per_insertion(&self, dt: f64) -> f64 {
        self.per_insertion_every(dt, self.every)
    }

    /// (0 for [`Rate::Fill`], whose insertions count their region instead.)
    fn per_insertion_every(&self, dt: f64, every: u64) -> f64 {
        let rate = match self.rate {
            Rate::Particles(n) => n,
            Rate::Mass(m) => m / self.distribution.mass_expect(),
            Rate::Fill(_) => 0.0,
        };
        rate * every as f64 * dt
    }
}

/// What an insertion fix has done so far (LIGGGHTS's `f_ID[1]`, `f_ID[2]`: number and mass).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InsertStats {
    /// Particles inserted.
    pub inserted: u64,
    /// Their mass (kg).
    pub mass: f64,
    /// Their volume (m³).
    pub volume: f64,
    /// Insertions that placed fewer particles than wanted.
    pub short: u64,
}

/// A running `insert/rate/region`: the specification and its schedule.
#[derive(Debug, Clone)]
pub struct RateInsertion {
    spec: InsertRate,
    /// The next insertion step; `None` when done.
    next: Option<u64>,
    /// n_per, fixed by the first run's time step.
    per: Option<f64>,
    /// K (steps) and Δt (s), fixed with n_per.
    every: u64,
    dt: f64,
    rng: rand_chacha::ChaCha8Rng,
    carry: Vec<f64>,
    stats: InsertStats,
}

/// One insertion's result.
#[derive(Debug, Clone, PartialEq)]
pub struct RateBatch {
    /// The particles placed (ids to be assigned).
    pub particles: Vec<NewParticle>,
    /// How many were wanted.
    pub wanted: usize,
    /// For a stream, each particle's carrying to the face (same order as `particles`).
    pub held: Vec<Held>,
}

impl RateInsertion {
    /// The fix defined at step `now`: its first insertion is at `start`, else at `now + 1`.
    /// Errors: a `start` before `now + 1`, n_per that cannot be computed (zero rate).
    pub fn new(spec: InsertRate, now: u64) -> Result<RateInsertion, String> {
        let first = match spec.start {
            Some(s) if s < now + 1 => {
                return Err(format!(
                    "{} {}: `start {s}` is before the next step {}",
                    spec.style(),
                    spec.name,
                    now + 1
                ))
            }
            Some(s) => s,
            None => now + 1,
        };
        let parts = spec.distribution.parts.len();
        Ok(RateInsertion {
            rng: rand_chacha::ChaCha8Rng::seed_from_u64(spec.seed),
            carry: vec![0.0; parts],
            next: Some(first),
            per: None,
            every: spec.every,
            dt: 0.0,
            spec,
            stats: InsertStats::default(),
        })
    }

    /// The specification.
    pub fn spec(&self) -> &InsertRate {
        &self.spec
    }

    /// What it inserted so far.
    pub fn stats(&self) -> InsertStats {
        self.stats
    }

    /// The next insertion step, `None` when all particles are in.
    pub fn next_step(&self) -> Option<u64> {
        self.next
    }

    /// Fixes K and n_per with the time step of the first run (LIGGGHTS's `setup`), and checks
    /// the volume against the box: a region reaching outside while a face is fixed is an
    /// error, an extruded face reaching outside a warning (returned).
    pub fn activate(
        &mut self,
        dt: f64,
        fixed_face: bool,
        box_lo: V3,
        box_hi: V3,
    ) -> Result<Vec<String>, String> {
        if self.per.is_some() {
            return Ok(Vec::new());
        }
        let style = self.spec.style();
        let fill = matches!(self.spec.rate, Rate::Fill(_));
        let name = &self.spec.name;
        let r_max = (self.spec.distribution.parts.iter())
            .map(|(t, _)| t.radius)
            .fold(0.0, f64::max);
        let outside = |lo: V3, hi: V3| (0..3).any(|k| lo[k] < box_lo[k] || hi[k] > box_hi[k]);
        let mut warnings = Vec::new();
        let every = match &mut self.spec.source {
            Source::Region(region) => {
                let (lo, hi) = region.bounds();
                if outside(lo, hi) && fixed_face {
                    return Err(format!(
                        "{style} {name}: the insertion region extends outside the simulation box \
                         and a fixed boundary is used (LIGGGHTS refuses this too; use `m` or `s` \
                         faces)"
                    ));
                }
                self.spec.every
            }
            Source::Stream(stream) => {
                let given = (self.spec.every > 0).then_some(self.spec.every);
                let r = stream
                    .resolve(dt, given, r_max)
                    .map_err(|e| format!("{name}: {e}"))?;
                let (lo, hi) = stream.bounds().unwrap_or((box_lo, box_hi));
                if outside(lo, hi) {
                    warnings.push(format!(
                        "{style} {name}: the extruded insertion face extends outside the box; \
                         particles placed outside are lost (LIGGGHTS warns that it may not \
                         insert all particles correctly)"
                    ));
                }
                r.every
            }
        };
        let per = self.spec.per_insertion_every(dt, every);
        let valid = fill || (per > 0.0 && per.is_finite());
        if !valid {
            return Err(format!(
                "{style} {name}: {per} particles per insertion (the rate must be > 0)"
            ));
        }
        self.per = Some(per);
        self.every = every;
        self.dt = dt;
        Ok(warnings)
    }

    /// K (steps): `insert_every`, or for a stream with `extrude_length` what the time step
    /// gives (0 before [`RateInsertion::activate`]).
    pub fn every(&self) -> u64 {
        self.every
    }

    /// The insertion due at `step`, if any: the particles placed among `existing` (the
    /// schedule moves on whether or not all could be placed).
    pub fn due(&mut self, step: u64, existing: &Particles) -> Option<RateBatch> {
        if self.next != Some(step) {
            return None;
        }
        let per = self.per?;
        let total = self.spec.total_particles();
        let (mut n, fill_ratio) = match (self.spec.rate, &self.spec.source) {
            (Rate::Fill(target), Source::Region(region)) => {
                let dist = &self.spec.distribution;
                let present = RegionContent::of(region, existing);
                let missing = target.missing(&present, region.volume(), dist);
                let n = match target {
                    InsertTarget::ParticlesInRegion(_) => missing,
                    _ => (missing + self.rng.gen::<f64>()).floor(),
                };
                let ratio = target.fill_ratio(&present, region.volume());
                (n.max(0.0) as u64, ratio)
            }
            // `Fill` is made with a region only (`deck::insertion::insert_pack`)
            (Rate::Fill(_), Source::Stream(_)) => (0, 0.0),
            _ => ((per + self.rng.gen::<f64>()).floor() as u64, 0.0),
        };
        if let Some(t) = total {
            n = n.min(t.saturating_sub(self.stats.inserted));
        }
        // a stream's particles enter with v_n and no spin, and get `vel`, `omega` at the face
        let (velocity, omega) = match &self.spec.source {
            Source::Region(_) => (self.spec.velocity, self.spec.omega),
            Source::Stream(s) => (s.v_normal(), V3::zeros()),
        };
        let batch = Batch {
            counts: split(&self.spec.distribution, n as usize, &mut self.carry),
            velocity,
            omega,
            all_in: self.spec.all_in,
            overlap_check: self.spec.overlap_check,
            max_attempt: self.spec.max_attempt,
            fill_ratio,
        };
        let volume: &dyn InsertVolume = match &self.spec.source {
            Source::Region(r) => r,
            Source::Stream(s) => s,
        };
        let particles = place(
            volume,
            &self.spec.distribution,
            &batch,
            existing,
            &mut self.rng,
        );
        let held = match &self.spec.source {
            Source::Region(_) => Vec::new(),
            Source::Stream(s) => (particles.iter())
                .map(|p| Held {
                    x0: p.x,
                    inserted: step,
                    release: step + s.steps_to_face(p.x, self.dt),
                    v_carry: s.v_normal(),
                    v_release: self.spec.velocity,
                    omega_release: self.spec.omega,
                })
                .collect(),
        };
        let s = &mut self.stats;
        s.inserted += particles.len() as u64;
        for p in &particles {
            let v = 4.0 / 3.0 * std::f64::consts::PI * p.radius.powi(3);
            s.volume += v;
            s.mass += v * p.density;
        }
        if particles.len() < n as usize {
            s.short += 1;
        }
        let more = total.is_none_or(|t| s.inserted < t);
        self.next = more.then_some(step + self.every);
        Some(RateBatch {
            particles,
            wanted: n as usize,
            held,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::insert::SphereTemplate;

    fn spec(total: Total, rate: Rate, every: u64) -> InsertRate {
        let t = SphereTemplate {
            name: "t".into(),
            atom_type: 1,
            density: 2000.0,
            radius: 1e-3,
        };
        InsertRate {
            name: "ins".into(),
            seed: 7,
            distribution: Distribution::new("d", vec![(t, 1.0)], true),
            source: Source::Region(Region::Block {
                lo: V3::new(0.0, 0.0, 0.0),
                hi: V3::new(0.02, 0.02, 0.02),
            }),
            total,
            rate,
            every,
            start: None,
            velocity: V3::new(0.0, 0.0, -1.0),
            omega: V3::zeros(),
            all_in: true,
            overlap_check: true,
            max_attempt: 100,
        }
    }

    fn run(ins: &mut RateInsertion, steps: u64) -> Vec<(u64, usize)> {
        let mut p = Particles::default();
        let mut log = Vec::new();
        for step in 1..=steps {
            if let Some(b) = ins.due(step, &p) {
                log.push((step, b.particles.len()));
                for q in b.particles {
                    p.push(q, 1).unwrap();
                }
            }
        }
        log
    }

    /// `insert/pack … insert_every 10 particles_in_region 10`: each insertion wants N minus the
    /// particles whose centres are in the region (LIGGGHTS's `FixInsertPack::calc_ninsert_this`),
    /// at steps 1, 11, 21, … with no end, none wanted once the region holds 10.
    #[test]
    fn fill_wants_the_target_minus_the_particles_present() {
        let mut s = spec(
            Total::Unlimited,
            Rate::Fill(InsertTarget::ParticlesInRegion(10)),
            10,
        );
        s.name = "pack".into();
        let mut ins = RateInsertion::new(s, 0).unwrap();
        assert_eq!(ins.spec().style(), "insert/pack");
        ins.activate(1e-3, false, V3::repeat(-1.0), V3::repeat(1.0))
            .unwrap();
        let mut p = Particles::default();
        // three inside the region (0–20 mm), two outside
        for (k, z) in [0.005, 0.01, 0.015, 0.03, -0.01].into_iter().enumerate() {
            let q = NewParticle {
                id: k as u64 + 1,
                atom_type: 1,
                x: V3::new(0.01, 0.01, z),
                v: V3::zeros(),
                omega: V3::zeros(),
                radius: 1e-3,
                density: 2000.0,
            };
            p.push(q, 1).unwrap();
        }
        let mut log = Vec::new();
        for step in 1..=35 {
            if let Some(b) = ins.due(step, &p) {
                log.push((step, b.wanted, b.particles.len()));
                for q in b.particles {
                    p.push(q, 1).unwrap();
                }
            }
        }
        assert_eq!(log, [(1, 7, 7), (11, 0, 0), (21, 0, 0), (31, 0, 0)]);
        assert_eq!(ins.next_step(), Some(41));
        assert_eq!(ins.stats().inserted, 7);
    }

    /// `volumefraction_region φ`: x = φ·V/V̄ particles missing in an empty region is
    /// inserted as ⌊x + u⌋, u uniform (LIGGGHTS): x on average. V = (20 mm)³, R = 1 mm,
    /// φ = 0.01: x = 19.0986; over 2000 insertions the mean is within 4σ of x (σ = √(f(1−f)/n),
    /// f = 0.0986 the fractional part).
    #[test]
    fn fill_volume_fraction_rounds_at_random_to_the_missing_number() {
        let s = spec(
            Total::Unlimited,
            Rate::Fill(InsertTarget::VolumeFraction(0.01)),
            1,
        );
        let mut ins = RateInsertion::new(s, 0).unwrap();
        ins.activate(1e-3, false, V3::repeat(-1.0), V3::repeat(1.0))
            .unwrap();
        let x = 0.01 * 8e-6 / (4.0 / 3.0 * std::f64::consts::PI * 1e-9);
        let n = 2000;
        let mut sum = 0;
        for step in 1..=n {
            let b = ins.due(step, &Particles::default()).unwrap();
            assert!(b.wanted == 19 || b.wanted == 20, "{}", b.wanted);
            sum += b.wanted;
        }
        let f = x - x.floor();
        let sigma = (f * (1.0 - f) / n as f64).sqrt();
        let mean = sum as f64 / n as f64;
        assert!((mean - x).abs() < 4.0 * sigma, "{mean} vs {x} ± {sigma}");
    }

    /// ṅ = 1000/s, K = 10, Δt = 1e-3 s: 10 per insertion at steps 1, 11, 21, … until 35 are
    /// in (the fourth insertion cut to 5).
    #[test]
    fn integer_rate_counts_are_exact_and_the_last_is_cut() {
        let mut ins =
            RateInsertion::new(spec(Total::Particles(35), Rate::Particles(1000.0), 10), 0).unwrap();
        ins.activate(1e-3, false, V3::repeat(-1.0), V3::repeat(1.0))
            .unwrap();
        assert_eq!(run(&mut ins, 100), [(1, 10), (11, 10), (21, 10), (31, 5)]);
        assert_eq!(ins.next_step(), None);
        let m = 4.0 / 3.0 * std::f64::consts::PI * 1e-9 * 2000.0;
        assert!((ins.stats().mass - 35.0 * m).abs() < 1e-12 * 35.0 * m);
    }

    /// A mass rate: ṅ = ṁ / m, and a non-integer n_per averages to n_per.
    #[test]
    fn mass_rate_averages_to_the_rate() {
        let m = 4.0 / 3.0 * std::f64::consts::PI * 1e-9 * 2000.0;
        // n_per = 2.5
        let s = spec(Total::Mass(1e6 * m), Rate::Mass(2500.0 * m), 1);
        assert_eq!(s.total_particles(), Some(1_000_000));
        let mut ins = RateInsertion::new(s, 0).unwrap();
        ins.activate(1e-3, false, V3::repeat(-1.0), V3::repeat(1.0))
            .unwrap();
        let mut p = Particles::default();
        let mut n = 0;
        for step in 1..=400 {
            let b = ins.due(step, &p).unwrap();
            assert!(matches!(b.wanted, 2 | 3));
            n += b.wanted;
            p = Particles::default();
        }
        // 400 draws of ⌊2.5 + u⌋: mean 2.5, standard deviation of the sum 0.5·√400 = 10
        assert!((n as f64 - 1000.0).abs() < 50.0, "{n}");
    }

    #[test]
    fn region_outside_a_fixed_box_is_refused_and_start_is_checked() {
        let mut ins =
            RateInsertion::new(spec(Total::Unlimited, Rate::Particles(1.0), 1), 0).unwrap();
        let e = ins
            .activate(1.0, true, V3::repeat(0.0), V3::repeat(0.01))
            .unwrap_err();
        assert!(e.contains("outside the simulation box"), "{e}");
        let mut s = spec(Total::Unlimited, Rate::Particles(1.0), 1);
        s.start = Some(5);
        assert!(RateInsertion::new(s.clone(), 5).is_err());
        assert_eq!(RateInsertion::new(s, 4).unwrap().next_step(), Some(5));
    }

    /// A region that cannot take the batch inserts what fits and reports the shortfall.
    #[test]
    fn a_full_region_inserts_fewer() {
        let mut s = spec(Total::Unlimited, Rate::Particles(1e6), 1);
        s.source = Source::Region(Region::Block {
            lo: V3::zeros(),
            hi: V3::new(0.0041, 0.0021, 0.0021),
        });
        let mut ins = RateInsertion::new(s, 0).unwrap();
        ins.activate(1e-5, false, V3::repeat(-1.0), V3::repeat(1.0))
            .unwrap();
        // 10 wanted; with all_in the centres lie in a 2.1 mm × 0.1 mm × 0.1 mm box, where at
        // most two spheres of 2 mm diameter fit without overlap
        let b = ins.due(1, &Particles::default()).unwrap();
        assert_eq!(b.wanted, 10);
        assert!(
            (1..=2).contains(&b.particles.len()),
            "{}",
            b.particles.len()
        );
        assert_eq!(ins.stats().short, 1);
        assert_eq!(ins.next_step(), Some(2));
    }
}
