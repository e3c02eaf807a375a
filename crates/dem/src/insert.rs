//! `fix insert/pack`: a random, non-overlapping loose pack of spheres in a region, drawn from a
//! discrete size distribution (`particletemplate/sphere` + `particledistribution/discrete`).
//!
//! Algorithm (seeded, deterministic): the number to insert follows from the target
//! (`particles_in_region N` minus the particles whose centres already lie in the region;
//! `volumefraction_region φ`: (φV − V_present)/V̄; `mass_in_region M`: (M − M_present)/m̄,
//! V̄, m̄ the expected particle volume and mass); it is split over the templates by their
//! number fractions (largest-remainder rounding), and the particles are placed largest first
//! at uniformly random positions (centre in the region, or in the region shrunk by the radius
//! with `all_in yes`), a position being rejected while the sphere overlaps an existing or
//! already placed one (`overlapcheck yes`). As in LIGGGHTS the tries share one budget of
//! `maxattempt` × (number wanted); particles left when it is spent are reported (LIGGGHTS
//! warns).
//! The random stream is ChaCha8 seeded with the fix's seed, not LIGGGHTS's Park–Miller
//! generator, so packs are statistically, not particle-by-particle, equal to LIGGGHTS's.

use std::collections::HashMap;

use mesh::v3::V3;
use rand::SeedableRng;

use crate::particles::{NewParticle, Particles};
use crate::region::Region;

/// `fix ID all particletemplate/sphere SEED atom_type T density constant ρ radius constant R`.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereTemplate {
    /// Fix id.
    pub name: String,
    /// Atom type (1-based).
    pub atom_type: u32,
    /// Density (kg/m³).
    pub density: f64,
    /// Radius (m).
    pub radius: f64,
}

impl SphereTemplate {
    /// Volume (m³).
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * self.radius.powi(3)
    }

    /// Mass (kg).
    pub fn mass(&self) -> f64 {
        self.volume() * self.density
    }
}

/// `particledistribution/discrete SEED n t1 w1 t2 w2 …`: templates with *number* fractions.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution {
    /// Fix id.
    pub name: String,
    /// Templates and their number fractions (summing to 1).
    pub parts: Vec<(SphereTemplate, f64)>,
}

impl Distribution {
    /// From weights that are mass fractions (LIGGGHTS's default, `particledistribution/discrete`)
    /// or number fractions (`…/discrete/numberbased`); weights are normalised.
    pub fn new(name: &str, parts: Vec<(SphereTemplate, f64)>, mass_based: bool) -> Distribution {
        let mut w: Vec<f64> = parts
            .iter()
            .map(|(t, w)| if mass_based { w / t.mass() } else { *w })
            .collect();
        let s: f64 = w.iter().sum();
        for x in &mut w {
            *x /= s;
        }
        Distribution {
            name: name.to_string(),
            parts: parts.into_iter().zip(w).map(|((t, _), w)| (t, w)).collect(),
        }
    }

    /// Expected particle volume (m³).
    pub fn volume_expect(&self) -> f64 {
        self.parts.iter().map(|(t, w)| w * t.volume()).sum()
    }

    /// Expected particle mass (kg).
    pub fn mass_expect(&self) -> f64 {
        self.parts.iter().map(|(t, w)| w * t.mass()).sum()
    }
}

/// How many particles an insertion aims at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InsertTarget {
    /// `particles_in_region N`.
    ParticlesInRegion(u64),
    /// `volumefraction_region φ`.
    VolumeFraction(f64),
    /// `mass_in_region M` (kg).
    MassInRegion(f64),
}

/// A `fix insert/pack … insert_every once` specification.
#[derive(Debug, Clone, PartialEq)]
pub struct InsertPack {
    /// Fix id.
    pub name: String,
    /// `seed`.
    pub seed: u64,
    /// `distributiontemplate`.
    pub distribution: Distribution,
    /// `vel constant vx vy vz` (m/s).
    pub velocity: V3,
    /// `omega constant wx wy wz` (rad/s).
    pub omega: V3,
    /// `region`.
    pub region: Region,
    /// Target amount.
    pub target: InsertTarget,
    /// `all_in yes`.
    pub all_in: bool,
    /// `overlapcheck yes`.
    pub overlap_check: bool,
    /// `maxattempt` (LIGGGHTS default 50).
    pub max_attempt: u32,
}

/// Result of one insertion.
#[derive(Debug, Clone, PartialEq)]
pub struct Inserted {
    /// The new particles (ids 0 = to be assigned).
    pub particles: Vec<NewParticle>,
    /// How many were wanted.
    pub wanted: usize,
}

/// What the particles whose centres lie in a region hold (boundary included).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionContent {
    /// Number of particles.
    pub count: u64,
    /// Their volume Σ 4/3 π r³ (m³).
    pub volume: f64,
    /// Their mass (kg).
    pub mass: f64,
}

impl RegionContent {
    /// The particles of `existing` whose centres lie in `region`.
    pub fn of(region: &Region, existing: &Particles) -> RegionContent {
        let inside: Vec<usize> = (0..existing.len())
            .filter(|&i| region.contains(existing.x[i]))
            .collect();
        RegionContent {
            count: inside.len() as u64,
            volume: (inside.iter())
                .map(|&i| 4.0 / 3.0 * std::f64::consts::PI * existing.radius[i].powi(3))
                .sum(),
            mass: inside.iter().map(|&i| existing.mass[i]).sum(),
        }
    }
}

impl InsertTarget {
    /// The particles missing to reach the target (real; may be ≤ 0): N − n_present;
    /// (φ·V_region − V_present)/V̄; (M − M_present)/m̄, with V̄, m̄ the distribution's expected
    /// particle volume (m³) and mass (kg), `region_volume` V_region in m³.
    pub fn missing(&self, present: &RegionContent, region_volume: f64, dist: &Distribution) -> f64 {
        match *self {
            InsertTarget::ParticlesInRegion(n) => n as f64 - present.count as f64,
            InsertTarget::VolumeFraction(phi) => {
                (phi * region_volume - present.volume) / dist.volume_expect()
            }
            InsertTarget::MassInRegion(m) => (m - present.mass) / dist.mass_expect(),
        }
    }

    /// How full the region is, in [0, 1]: n_present/N, V_present/(φ·V_region) or
    /// M_present/M (LIGGGHTS's `insertion_ratio`, which widens the tries budget, [`Batch`]).
    pub fn fill_ratio(&self, present: &RegionContent, region_volume: f64) -> f64 {
        let r = match *self {
            InsertTarget::ParticlesInRegion(n) => present.count as f64 / n as f64,
            InsertTarget::VolumeFraction(phi) => present.volume / (phi * region_volume),
            InsertTarget::MassInRegion(m) => present.mass / m,
        };
        if r.is_nan() {
            1.0
        } else {
            r.clamp(0.0, 1.0)
        }
    }
}

impl InsertPack {
    /// Number of particles to insert given those already present: the missing number
    /// ([`InsertTarget::missing`]) rounded to the nearest integer, 0 if none are missing.
    pub fn count(&self, existing: &Particles) -> usize {
        let present = RegionContent::of(&self.region, existing);
        let n = (self.target).missing(&present, self.region.volume(), &self.distribution);
        if n > 0.0 {
            n.round() as usize
        } else {
            0
        }
    }

    /// Places the particles (see the module doc). `existing` are checked for overlap.
    pub fn insert(&self, existing: &Particles) -> Inserted {
        let wanted = self.count(existing);
        let mut carry = vec![0.0; self.distribution.parts.len()];
        let batch = Batch {
            counts: split(&self.distribution, wanted, &mut carry),
            velocity: self.velocity,
            omega: self.omega,
            all_in: self.all_in,
            overlap_check: self.overlap_check,
            max_attempt: self.max_attempt,
            fill_ratio: 0.0,
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(self.seed);
        let particles = place(&self.region, &self.distribution, &batch, existing, &mut rng);
        Inserted { particles, wanted }
    }
}

/// A volume particles are inserted into: a [`Region`] (`insert/pack`, `insert/rate/region`)
/// or `insert/stream`'s face extruded against the insertion velocity
/// ([`crate::insert_stream::Stream`]).
pub trait InsertVolume {
    /// A random centre for a sphere of radius `radius` (m), uniform over where the volume
    /// lets it go (`all_in`: the whole sphere inside), or `None` if nowhere.
    fn random_point(
        &self,
        rng: &mut rand_chacha::ChaCha8Rng,
        radius: f64,
        all_in: bool,
    ) -> Option<V3>;
}

impl InsertVolume for Region {
    /// Uniform in the region, shrunk by the radius with `all_in`.
    fn random_point(
        &self,
        rng: &mut rand_chacha::ChaCha8Rng,
        radius: f64,
        all_in: bool,
    ) -> Option<V3> {
        Region::random_point(self, rng, if all_in { radius } else { 0.0 })
    }
}

/// One insertion: how many particles of each template of a [`Distribution`] and how.
#[derive(Debug, Clone, PartialEq)]
pub struct Batch {
    /// Particles per template, in the distribution's order.
    pub counts: Vec<usize>,
    /// Initial velocity (m/s).
    pub velocity: V3,
    /// Initial angular velocity (rad/s).
    pub omega: V3,
    /// Whole sphere inside the volume (`all_in yes`), else the centre.
    pub all_in: bool,
    /// Reject positions where the sphere overlaps another (`overlapcheck yes`).
    pub overlap_check: bool,
    /// Tries per particle wanted, one budget for the batch (`maxattempt`).
    pub max_attempt: u32,
    /// How full the region already is, ρ ∈ [0, 1) (a repeated `insert/pack`'s
    /// [`InsertTarget::fill_ratio`]; 0 otherwise): the budget is ⌊maxattempt · n / (1 − ρ)⌋
    /// tries, as LIGGGHTS's `FixInsertPack::calc_maxtry` (ρ ≥ 1: maxattempt · n).
    pub fill_ratio: f64,
}

/// Splits `n` particles over the templates by their number fractions: largest remainder of
/// wᵢ·n + carryᵢ, the carry keeping what was rounded away for the next call (so the long-run
/// fractions are exact when a rate inserts a few particles at a time; a zero carry gives the
/// plain largest-remainder split). Ties go to the first template.
pub fn split(dist: &Distribution, n: usize, carry: &mut [f64]) -> Vec<usize> {
    let parts = &dist.parts;
    let exact: Vec<f64> = parts
        .iter()
        .zip(carry.iter())
        .map(|((_, w), c)| w * n as f64 + c)
        .collect();
    let mut counts: Vec<usize> = exact.iter().map(|e| e.floor().max(0.0) as usize).collect();
    let mut rest: Vec<usize> = (0..parts.len()).collect();
    rest.sort_by(|&a, &b| {
        (exact[b] - exact[b].floor())
            .total_cmp(&(exact[a] - exact[a].floor()))
            .then(a.cmp(&b))
    });
    let missing = n.saturating_sub(counts.iter().sum::<usize>());
    for &k in rest.iter().take(missing) {
        counts[k] += 1;
    }
    // a carry may round up beyond n: take the excess back from the smallest remainders
    let mut excess = counts.iter().sum::<usize>().saturating_sub(n);
    for &k in rest.iter().rev() {
        while excess > 0 && counts[k] > 0 {
            counts[k] -= 1;
            excess -= 1;
        }
    }
    for (c, (e, k)) in carry.iter_mut().zip(exact.iter().zip(&counts)) {
        *c = e - *k as f64;
    }
    counts
}

/// Places `batch` in `volume`, largest templates first, at uniformly random positions, a
/// position being rejected while the sphere overlaps an `existing` or already placed one (with
/// `overlap_check`). The tries share one budget of `max_attempt` × (number wanted), as
/// LIGGGHTS's `maxattempt`; what is left when it is spent is not placed (the caller compares
/// lengths).
pub fn place(
    volume: &dyn InsertVolume,
    dist: &Distribution,
    batch: &Batch,
    existing: &Particles,
    rng: &mut rand_chacha::ChaCha8Rng,
) -> Vec<NewParticle> {
    let parts = &dist.parts;
    let wanted: usize = batch.counts.iter().sum();
    let mut order: Vec<usize> = (0..parts.len()).collect();
    order.sort_by(|&a, &b| {
        parts[b]
            .0
            .radius
            .total_cmp(&parts[a].0.radius)
            .then(a.cmp(&b))
    });
    let rmax = parts
        .iter()
        .map(|(t, _)| t.radius)
        .chain(existing.radius.iter().copied())
        .fold(0.0, f64::max);
    let mut grid = OverlapGrid::new(2.0 * rmax.max(f64::MIN_POSITIVE));
    if batch.overlap_check {
        for i in 0..existing.len() {
            grid.add(existing.x[i], existing.radius[i]);
        }
    }
    let mut out = Vec::with_capacity(wanted);
    let mut tries_left = u64::from(batch.max_attempt.max(1)) * wanted as u64;
    if batch.fill_ratio > 0.0 && batch.fill_ratio < 1.0 {
        tries_left = (tries_left as f64 / (1.0 - batch.fill_ratio)) as u64;
    }
    'templates: for &k in &order {
        let t = &parts[k].0;
        for _ in 0..batch.counts[k] {
            loop {
                if tries_left == 0 {
                    break 'templates;
                }
                tries_left -= 1;
                let Some(p) = volume.random_point(rng, t.radius, batch.all_in) else {
                    break 'templates;
                };
                if batch.overlap_check && grid.overlaps(p, t.radius) {
                    continue;
                }
                grid.add(p, t.radius);
                out.push(NewParticle {
                    id: 0,
                    atom_type: t.atom_type,
                    x: p,
                    v: batch.velocity,
                    omega: batch.omega,
                    radius: t.radius,
                    density: t.density,
                });
                break;
            }
        }
    }
    out
}

/// Spheres hashed into cubic cells of side ≥ the largest diameter.
struct OverlapGrid {
    side: f64,
    cells: HashMap<[i64; 3], Vec<(V3, f64)>>,
}

impl OverlapGrid {
    fn new(side: f64) -> Self {
        OverlapGrid {
            side,
            cells: HashMap::new(),
        }
    }

    fn key(&self, p: V3) -> [i64; 3] {
        [0, 1, 2].map(|k| (p[k] / self.side).floor() as i64)
    }

    fn add(&mut self, p: V3, r: f64) {
        let k = self.key(p);
        self.cells.entry(k).or_default().push((p, r));
    }

    fn overlaps(&self, p: V3, r: f64) -> bool {
        let k = self.key(p);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(v) = self.cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                        for &(q, rq) in v {
                            let d2: f64 = (0..3).map(|a| (p[a] - q[a]).powi(2)).sum();
                            if d2 < (r + rq) * (r + rq) {
                                return true;
                            }
                        }
                    }
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn template(name: &str, r: f64, rho: f64) -> SphereTemplate {
        SphereTemplate {
            name: name.into(),
            atom_type: 1,
            density: rho,
            radius: r,
        }
    }

    /// A volume whose every point overlaps the sphere at the origin; it counts its draws.
    struct Blocked(std::cell::Cell<u64>);

    impl InsertVolume for Blocked {
        fn random_point(&self, _: &mut rand_chacha::ChaCha8Rng, _: f64, _: bool) -> Option<V3> {
            self.0.set(self.0.get() + 1);
            Some(V3::zeros())
        }
    }

    /// The tries budget of a batch that places nothing: maxattempt · n, widened to
    /// ⌊maxattempt · n / (1 − ρ)⌋ for a region already a fraction ρ full (LIGGGHTS's
    /// `FixInsertPack::calc_maxtry`): 50 · 2 / 0.25 = 400.
    #[test]
    fn the_tries_budget_grows_with_the_fill_ratio() {
        let d = Distribution::new("d", vec![(template("s", 1e-3, 1000.0), 1.0)], false);
        let mut existing = Particles::default();
        let q = NewParticle {
            id: 1,
            atom_type: 1,
            x: V3::zeros(),
            v: V3::zeros(),
            omega: V3::zeros(),
            radius: 1e-3,
            density: 1000.0,
        };
        existing.push(q, 1).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        for (ratio, tries) in [(0.0, 100), (0.75, 400), (1.0, 100)] {
            let batch = Batch {
                counts: vec![2],
                velocity: V3::zeros(),
                omega: V3::zeros(),
                all_in: false,
                overlap_check: true,
                max_attempt: 50,
                fill_ratio: ratio,
            };
            let v = Blocked(std::cell::Cell::new(0));
            assert!(place(&v, &d, &batch, &existing, &mut rng).is_empty());
            assert_eq!(v.0.get(), tries, "ρ = {ratio}");
        }
    }

    #[test]
    fn mass_fractions_become_number_fractions() {
        // equal mass of spheres with radii 1 and 2 (same ρ): number ratio 8 : 1
        let d = Distribution::new(
            "d",
            vec![
                (template("a", 1.0, 1.0), 0.5),
                (template("b", 2.0, 1.0), 0.5),
            ],
            true,
        );
        assert!((d.parts[0].1 - 8.0 / 9.0).abs() < 1e-15);
        assert!((d.parts[1].1 - 1.0 / 9.0).abs() < 1e-15);
    }

    #[test]
    fn pack_is_non_overlapping_inside_and_deterministic() {
        let spec = InsertPack {
            name: "ins".into(),
            seed: 12345,
            distribution: Distribution::new(
                "d",
                vec![
                    (template("s", 5e-4, 2500.0), 0.5),
                    (template("l", 7e-4, 2500.0), 0.5),
                ],
                false,
            ),
            velocity: V3::new(0.0, 0.0, -0.1),
            omega: V3::zeros(),
            region: Region::Cylinder {
                axis: 2,
                centre: [0.0, 0.0],
                radius: 0.01,
                lo: 0.0,
                hi: 0.03,
            },
            target: InsertTarget::ParticlesInRegion(1000),
            all_in: true,
            overlap_check: true,
            max_attempt: 200,
        };
        let a = spec.insert(&Particles::default());
        assert_eq!(a.wanted, 1000);
        assert_eq!(a.particles.len(), 1000);
        assert_eq!(a.particles.iter().filter(|p| p.radius == 7e-4).count(), 500);
        for (i, p) in a.particles.iter().enumerate() {
            assert!(spec.region.contains_sphere(p.x, p.radius));
            for q in &a.particles[..i] {
                let d2: f64 = (0..3).map(|k| (p.x[k] - q.x[k]).powi(2)).sum();
                assert!(d2 >= (p.radius + q.radius).powi(2));
            }
        }
        assert_eq!(spec.insert(&Particles::default()), a);
    }
}
