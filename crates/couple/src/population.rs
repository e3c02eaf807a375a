//! A changing particle population: which particles entered and which left between two
//! exchanges, matched by tag, with their volume and momentum.
//!
//! A particle is the same one at two exchanges when its tag, radius and density are the same
//! (a DEM may give a new particle the tag of one that left — LIGGGHTS numbers new atoms after
//! the largest tag present — and a changed radius or density then counts as one left and one
//! entered, so volumes balance). What entered is counted at the first exchange that sees it
//! (its volume V = 4/3 πr³ and momentum ρVv then); what left at the last exchange that saw it.
//! So between two exchanges, exactly:
//!
//! Σ V(now) − Σ V(before) = V_in − V_out, and the count likewise.
//!
//! On several ranks ([`crate::ranks`]) a particle may move from one rank to another: it then
//! vanishes on one rank and appears on another. Each rank sends rank 0 the tags and values of
//! what appeared and vanished on it; rank 0 cancels the pairs with the same tag, radius and
//! density (migrations, neither entered nor left) and every rank gets the totals.
//!
//! The first exchange only records the population (nothing entered: it is the initial state).

use mesh::v3::V3;

use crate::ranks::Ranks;
use crate::sides::ParticleState;

/// What entered and left between two exchanges (or in total), SI units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PopulationChange {
    /// Particles that entered.
    pub entered: usize,
    /// Particles that left.
    pub left: usize,
    /// Their volume, m³.
    pub volume_in: f64,
    /// m³.
    pub volume_out: f64,
    /// Their momentum Σ ρ V v, kg·m/s.
    pub momentum_in: V3,
    /// kg·m/s.
    pub momentum_out: V3,
}

impl PopulationChange {
    /// Adds another change (totals over steps).
    pub fn add(&mut self, o: &PopulationChange) {
        self.entered += o.entered;
        self.left += o.left;
        self.volume_in += o.volume_in;
        self.volume_out += o.volume_out;
        self.momentum_in += o.momentum_in;
        self.momentum_out += o.momentum_out;
    }

    fn count(&mut self, rec: &Record, entered: bool) {
        let (v, p) = (rec.volume(), rec.momentum());
        if entered {
            self.entered += 1;
            self.volume_in += v;
            self.momentum_in += p;
        } else {
            self.left += 1;
            self.volume_out += v;
            self.momentum_out += p;
        }
    }

    /// As 10 numbers (for the ranks' sums).
    fn to_array(self) -> [f64; 10] {
        let (a, b) = (self.momentum_in, self.momentum_out);
        [
            self.entered as f64,
            self.left as f64,
            self.volume_in,
            self.volume_out,
            a[0],
            a[1],
            a[2],
            b[0],
            b[1],
            b[2],
        ]
    }

    fn from_array(x: [f64; 10]) -> PopulationChange {
        PopulationChange {
            entered: x[0] as usize,
            left: x[1] as usize,
            volume_in: x[2],
            volume_out: x[3],
            momentum_in: V3::new(x[4], x[5], x[6]),
            momentum_out: V3::new(x[7], x[8], x[9]),
        }
    }
}

/// One particle as last seen.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Record {
    id: u64,
    radius: f64,
    density: f64,
    velocity: V3,
}

impl Record {
    fn volume(&self) -> f64 {
        voidage::sphere_box::ball_volume(self.radius)
    }

    fn momentum(&self) -> V3 {
        self.density * self.volume() * self.velocity
    }

    fn same(&self, o: &Record) -> bool {
        self.id == o.id && self.radius == o.radius && self.density == o.density
    }

    /// id, radius, density, v (as the ranks send it; ids below 2⁵³ are exact).
    const WIDTH: usize = 6;

    fn push(&self, out: &mut Vec<f64>) {
        let v = self.velocity;
        out.extend_from_slice(&[self.id as f64, self.radius, self.density, v[0], v[1], v[2]]);
    }

    fn read(x: &[f64]) -> Record {
        Record {
            id: x[0] as u64,
            radius: x[1],
            density: x[2],
            velocity: V3::new(x[3], x[4], x[5]),
        }
    }
}

/// The population of the last exchange (this rank's particles, by tag).
#[derive(Clone, Debug, Default)]
pub struct Population {
    /// Sorted by tag; `None` before the first exchange.
    last: Option<Vec<Record>>,
    total: PopulationChange,
}

impl foam::HeapBytes for Population {
    fn heap_bytes(&self) -> usize {
        self.last.as_ref().map_or(0, foam::heap::flat)
    }
}

impl Population {
    /// What entered and left since the total started (the first exchange).
    pub fn total(&self) -> PopulationChange {
        self.total
    }

    /// Compares `particles` with the last exchange's (collective over `ranks`): the change
    /// since, summed over ranks without the migrations between them (module docs).
    pub fn update(&mut self, particles: &ParticleState<'_>, ranks: &dyn Ranks) -> PopulationChange {
        let mut now: Vec<Record> = (0..particles.len())
            .map(|i| Record {
                id: particles.ids[i],
                radius: particles.radius[i],
                density: particles.density[i],
                velocity: particles.velocity[i],
            })
            .collect();
        if !now.windows(2).all(|w| w[0].id < w[1].id) {
            now.sort_by_key(|r| r.id);
        }
        let Some(last) = self.last.replace(now) else {
            return PopulationChange::default();
        };
        let now = self.last.as_ref().expect("just set");
        let (appeared, vanished) = differences(&last, now);
        let change = if ranks.size() > 1 {
            without_migrations(&appeared, &vanished, ranks)
        } else {
            let mut c = PopulationChange::default();
            appeared.iter().for_each(|r| c.count(r, true));
            vanished.iter().for_each(|r| c.count(r, false));
            c
        };
        self.total.add(&change);
        change
    }
}

/// The records of `now` not in `last` and those of `last` not in `now` (both sorted by tag).
fn differences(last: &[Record], now: &[Record]) -> (Vec<Record>, Vec<Record>) {
    let (mut appeared, mut vanished) = (Vec::new(), Vec::new());
    let (mut i, mut j) = (0, 0);
    while i < last.len() || j < now.len() {
        match (last.get(i), now.get(j)) {
            (Some(a), Some(b)) if a.id == b.id => {
                if !a.same(b) {
                    vanished.push(*a);
                    appeared.push(*b);
                }
                i += 1;
                j += 1;
            }
            (Some(a), Some(b)) if a.id < b.id => {
                vanished.push(*a);
                i += 1;
            }
            (Some(a), None) => {
                vanished.push(*a);
                i += 1;
            }
            (_, Some(b)) => {
                appeared.push(*b);
                j += 1;
            }
            (None, None) => unreachable!("the loop condition"),
        }
    }
    (appeared, vanished)
}

/// The change over all ranks: rank 0 pairs what vanished on one rank with what appeared on
/// another (same tag, radius and density) and counts the rest; every rank gets the sums.
fn without_migrations(
    appeared: &[Record],
    vanished: &[Record],
    ranks: &dyn Ranks,
) -> PopulationChange {
    let mut mine = vec![appeared.len() as f64];
    appeared.iter().for_each(|r| r.push(&mut mine));
    vanished.iter().for_each(|r| r.push(&mut mine));
    let all = ranks.gather(&mine);
    let mut sums = [0.0; 10];
    if ranks.rank() == 0 {
        let (mut ins, mut outs) = (Vec::new(), Vec::new());
        for x in &all {
            let n_in = x.first().copied().unwrap_or(0.0) as usize;
            for (k, rec) in x[1..].chunks_exact(Record::WIDTH).enumerate() {
                match k < n_in {
                    true => ins.push(Record::read(rec)),
                    false => outs.push(Record::read(rec)),
                }
            }
        }
        ins.sort_by_key(|r| r.id);
        outs.sort_by_key(|r| r.id);
        // a migration is in both lists, with the same tag, radius and density
        let (entered, left) = differences(&outs, &ins);
        let mut c = PopulationChange::default();
        entered.iter().for_each(|r| c.count(r, true));
        left.iter().for_each(|r| c.count(r, false));
        sums = c.to_array();
    }
    ranks.broadcast(&mut sums);
    PopulationChange::from_array(sums)
}

/// For each particle of `ids`, its index among the particles `old_ids` (by tag; `None` for a
/// particle not seen before): how the per-particle state kept between exchanges follows a
/// changed population.
pub(crate) fn follow_tags(old_ids: &[u64], ids: &[u64]) -> Vec<Option<usize>> {
    let at: std::collections::HashMap<u64, usize> = old_ids.iter().copied().zip(0..).collect();
    ids.iter().map(|id| at.get(id).copied()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ranks::Serial;

    struct State {
        ids: Vec<u64>,
        x: Vec<V3>,
        v: Vec<V3>,
        r: Vec<f64>,
        rho: Vec<f64>,
    }

    impl State {
        fn new(parts: &[(u64, f64, f64)]) -> State {
            State {
                ids: parts.iter().map(|p| p.0).collect(),
                x: vec![V3::zeros(); parts.len()],
                v: parts.iter().map(|p| V3::new(0.0, 0.0, p.2)).collect(),
                r: parts.iter().map(|p| p.1).collect(),
                rho: vec![1000.0; parts.len()],
            }
        }

        fn view(&self) -> ParticleState<'_> {
            ParticleState {
                temperature: None,
                ids: &self.ids,
                position: &self.x,
                velocity: &self.v,
                radius: &self.r,
                density: &self.rho,
            }
        }
    }

    fn vol(r: f64) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * r * r * r
    }

    #[test]
    fn entered_and_left_balance_the_volume_change() {
        let mut p = Population::default();
        let s0 = State::new(&[(1, 1.0, 0.0), (2, 2.0, 0.0), (3, 1.0, 0.0)]);
        assert_eq!(
            p.update(&s0.view(), &Serial::default()),
            PopulationChange::default()
        );
        // 2 left; 4 and 5 entered (unsorted, as the native DEM's index order may be); 3's
        // tag came back with another radius: one left, one entered
        let s1 = State::new(&[(5, 1.0, -2.0), (1, 1.0, 0.0), (4, 3.0, 1.0), (3, 2.0, 0.5)]);
        let c = p.update(&s1.view(), &Serial::default());
        assert_eq!((c.entered, c.left), (3, 2));
        assert!((c.volume_in - (vol(1.0) + vol(3.0) + vol(2.0))).abs() < 1e-12);
        assert!((c.volume_out - (vol(2.0) + vol(1.0))).abs() < 1e-12);
        let total = |s: &State| s.r.iter().map(|&r| vol(r)).sum::<f64>();
        let change = total(&s1) - total(&s0);
        assert!((c.volume_in - c.volume_out - change).abs() < 1e-12 * total(&s1));
        // momentum ρVv of what entered: 5 moving at −2, 4 at +1, 3 at +0.5
        let pz = 1000.0 * (-2.0 * vol(1.0) + vol(3.0) + 0.5 * vol(2.0));
        assert!((c.momentum_in[2] - pz).abs() < 1e-9 * pz.abs());
        assert_eq!(c.momentum_out, V3::zeros());
        assert_eq!(p.total(), c);
        // unchanged: nothing
        assert_eq!(
            p.update(&s1.view(), &Serial::default()),
            PopulationChange::default()
        );
    }
}
