//! `fix insert/stream`: particles inserted behind a planar face (`insertion_face`, a `fix
//! mesh/surface`) and carried through it at the insertion velocity, as LIGGGHTS 3.8.0 defines
//! it (read in its `fix_insert_stream.cpp`; the code here is foamgrain's own). The counting
//! (rate, `insert_every`, total, start) is [`crate::insert_rate`]'s; this module is the volume
//! and the carrying.
//!
//! Geometry:
//! - n is the unit normal of the face's first triangle, turned so that v·n > 0 (v the `vel
//!   constant` insertion velocity); v_n = (v·n) n is the velocity the particles enter with.
//!   Errors (as LIGGGHTS): a face that is not planar, |v| < 10⁻⁵ m/s, |v_n| < 10⁻³ m/s.
//! - The insertion volume is the face extruded against n by the length L. L and the insertion
//!   period K (steps) follow from each other with the time step Δt: given `insert_every K`,
//!   L = d·Δt·|v_n| with d = `duration` (default K, d ≤ K); given `extrude_length L`,
//!   K = ⌊(L + 10⁻¹⁴)/(Δt·|v_n|)⌋ (≥ 1). Giving both `insert_every` and `extrude_length`, or
//!   `extrude_length` and `duration`, is an error, as in LIGGGHTS; L must be ≥ 3 r_max.
//! - A particle of radius r is placed at a point uniform over the face's area (a triangle drawn
//!   by area, a point uniform in it), moved against n by a depth r + u·L (`overlapcheck
//!   yes`) or r + u·(L − 2r) (`overlapcheck no`), u uniform in [0, 1): LIGGGHTS's depths, so
//!   with the overlap check a sphere may reach r beyond the extruded volume at its back.
//!   `all_in yes` needs LIGGGHTS's `fix mesh/surface/planar`, which the native DEM does not
//!   read: it is refused.
//!
//! Carrying: an inserted particle starts with v_n and no spin, and until it reaches the face it
//! moves rigidly: at the end of every step its position is x₀ + v_n·(s − s₀)·Δt (x₀, s₀ its
//! insertion position and step), its velocity v_n, its angular velocity, force and torque 0,
//! whatever contacts it has. At its release step s₀ + ⌊(d_n + 10⁻¹⁴)/(|v_n|Δt)⌋ (d_n its
//! depth behind the face) it gets the `vel` and `omega` of the fix and moves freely from then
//! on (LIGGGHTS's `end_of_step`). [`Held`] is that state, kept per particle id.

use mesh::v3::V3;
use rand::Rng;

use crate::insert::InsertVolume;
use crate::trimesh::TriMesh;

/// LIGGGHTS's round-off allowance in the step counts (m).
const TINY: f64 = 1e-14;
/// Two triangles are in one plane when their unit normals differ by less than this (and every
/// vertex is this close to the first triangle's plane, relative to the face's size).
const PLANAR_TOL: f64 = 1e-8;

/// How the extrusion length is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Extrude {
    /// `extrude_length L` (m): the insertion period follows.
    Length(f64),
    /// `insert_every K` given: L = d·Δt·|v_n| with `duration d` (steps; `None`: d = K).
    Duration(Option<u64>),
}

/// The extruded insertion face of an `insert/stream` fix.
#[derive(Debug, Clone, PartialEq)]
pub struct Stream {
    /// The `fix mesh/surface` id of `insertion_face`.
    pub face: String,
    triangles: Vec<[V3; 3]>,
    /// Cumulative triangle areas (m²).
    cum_area: Vec<f64>,
    /// Unit face normal along the insertion velocity.
    normal: V3,
    /// A point of the face (its first vertex).
    p_ref: V3,
    /// The insertion velocity projected on the normal (m/s).
    v_normal: V3,
    /// How L is given.
    pub extrude: Extrude,
    /// L (m), once [`Stream::resolve`] fixed it.
    length: Option<f64>,
    /// Depths as `overlapcheck yes` draws them.
    overlap_check: bool,
}

/// The insertion period and extrusion length fixed with the time step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolved {
    /// K (steps).
    pub every: u64,
    /// L (m).
    pub length: f64,
}

impl Stream {
    /// The face `face` of a stream with insertion velocity `velocity` (m/s). Errors: the face
    /// is empty or not planar, |v| < 10⁻⁵ m/s, |v_n| < 10⁻³ m/s (LIGGGHTS's limits).
    pub fn new(
        face: &TriMesh,
        velocity: V3,
        extrude: Extrude,
        overlap_check: bool,
    ) -> Result<Stream, String> {
        let name = face.name();
        let tris = face.triangles();
        let Some(first) = tris.first() else {
            return Err(format!("insertion_face {name} has no triangles"));
        };
        let mut normal = face.normal(0);
        let size = face
            .bounds()
            .map(|(lo, hi)| (hi - lo).norm())
            .unwrap_or(0.0);
        for (t, tri) in tris.iter().enumerate() {
            let n = face.normal(t);
            let parallel = (n - normal).norm() < PLANAR_TOL || (n + normal).norm() < PLANAR_TOL;
            let off = tri
                .iter()
                .map(|p| (p - first[0]).dot(&normal).abs())
                .fold(0.0, f64::max);
            if !parallel || off > PLANAR_TOL * size {
                return Err(format!(
                    "insertion_face {name} is not planar (triangle {} leaves the plane of the \
                     first); insert/stream needs a planar face",
                    t + 1
                ));
            }
        }
        if velocity.norm() < 1e-5 {
            return Err("insert/stream: insertion velocity too low (|vel| < 1e-5 m/s)".into());
        }
        if velocity.dot(&normal) < 0.0 {
            normal = -normal;
        }
        let v_normal = normal * velocity.dot(&normal);
        if v_normal.norm() < 1e-3 {
            return Err(format!(
                "insert/stream: the insertion velocity projected on the normal of {name} is \
                 {:.3e} m/s (< 1e-3 m/s)",
                v_normal.norm()
            ));
        }
        let mut cum_area = Vec::with_capacity(tris.len());
        let mut sum = 0.0;
        for t in 0..tris.len() {
            sum += face.area(t);
            cum_area.push(sum);
        }
        Ok(Stream {
            face: name.to_string(),
            triangles: tris.to_vec(),
            cum_area,
            normal,
            p_ref: first[0],
            v_normal,
            extrude,
            length: None,
            overlap_check,
        })
    }

    /// The unit face normal along the insertion velocity.
    pub fn normal(&self) -> V3 {
        self.normal
    }

    /// A point of the face (m).
    pub fn reference_point(&self) -> V3 {
        self.p_ref
    }

    /// The velocity particles enter with, v_n (m/s).
    pub fn v_normal(&self) -> V3 {
        self.v_normal
    }

    /// The face area (m²).
    pub fn area(&self) -> f64 {
        self.cum_area.last().copied().unwrap_or(0.0)
    }

    /// The extrusion length L (m) once resolved.
    pub fn length(&self) -> Option<f64> {
        self.length
    }

    /// Fixes K and L with the time step `dt` (s) (module doc); `every` is `insert_every` if
    /// given, `r_max` the largest particle radius (m). Errors name LIGGGHTS's conditions.
    pub fn resolve(&mut self, dt: f64, every: Option<u64>, r_max: f64) -> Result<Resolved, String> {
        let step = dt * self.v_normal.norm();
        let r =
            match (self.extrude, every) {
                (Extrude::Length(_), Some(_)) => return Err(
                    "insert/stream: give `insert_every` or `extrude_length`, not both (LIGGGHTS \
                     refuses both too)"
                        .into(),
                ),
                (Extrude::Duration(_), None) => {
                    return Err("insert/stream needs `insert_every` or `extrude_length`".into())
                }
                (Extrude::Length(length), None) => {
                    if length < 3.0 * r_max {
                        return Err(format!(
                            "insert/stream: extrude_length {length} m is too small (< 3 × the \
                         largest radius {r_max} m)"
                        ));
                    }
                    let every = ((length + TINY) / step).floor();
                    if every < 1.0 {
                        return Err(format!(
                            "insert/stream: extrude_length {length} m is shorter than one step's \
                         travel {step:.3e} m (insertion velocity too high or extrude_length too \
                         low)"
                        ));
                    }
                    Resolved {
                        every: every as u64,
                        length,
                    }
                }
                (Extrude::Duration(d), Some(every)) => {
                    let d = d.unwrap_or(every);
                    if d > every {
                        return Err(format!(
                            "insert/stream: duration {d} > insert_every {every} is not allowed"
                        ));
                    }
                    let length = d as f64 * step;
                    if length < 3.0 * r_max {
                        return Err(format!(
                        "insert/stream: the extrusion {d} steps × {step:.3e} m = {length:.3e} m \
                         is < 3 × the largest radius {r_max} m ('insert_every' or 'vel' too \
                         small, or the particles too large)"
                    ));
                    }
                    Resolved { every, length }
                }
            };
        self.length = Some(r.length);
        Ok(r)
    }

    /// The bounding box of the extruded volume (m), once resolved.
    pub fn bounds(&self) -> Option<(V3, V3)> {
        let back = -self.length? * self.normal;
        let corners = self.triangles.iter().flatten().flat_map(|&p| [p, p + back]);
        let lo = corners
            .clone()
            .fold(V3::repeat(f64::INFINITY), |a, p| a.inf(&p));
        let hi = corners.fold(V3::repeat(f64::NEG_INFINITY), |a, p| a.sup(&p));
        Some((lo, hi))
    }

    /// The step count until a particle at `x` reaches the face: ⌊(d_n + 10⁻¹⁴)/(|v_n|Δt)⌋,
    /// d_n its depth behind the face (m).
    pub fn steps_to_face(&self, x: V3, dt: f64) -> u64 {
        let depth = (self.p_ref - x).dot(&self.normal);
        ((depth + TINY) / (self.v_normal.norm() * dt))
            .floor()
            .max(0.0) as u64
    }

    /// Whether `x` lies in the extruded volume: its projection on the face plane inside a
    /// triangle (to `tol` m), its depth behind the face in [−tol, L + tol].
    pub fn contains(&self, x: V3, tol: f64) -> bool {
        let Some(length) = self.length else {
            return false;
        };
        let depth = (self.p_ref - x).dot(&self.normal);
        if depth < -tol || depth > length + tol {
            return false;
        }
        let on = x + depth * self.normal;
        self.triangles
            .iter()
            .any(|t| in_triangle(t, self.normal, on, tol))
    }

    /// A point uniform over the face's area.
    fn point_on_face(&self, rng: &mut rand_chacha::ChaCha8Rng) -> V3 {
        let a = rng.gen::<f64>() * self.area();
        let t = self
            .cum_area
            .partition_point(|&c| c <= a)
            .min(self.triangles.len() - 1);
        let [p0, p1, p2] = self.triangles[t];
        // uniform in a triangle: √u₁ along the median, u₂ across
        let (s, u) = (rng.gen::<f64>().sqrt(), rng.gen::<f64>());
        p0 * (1.0 - s) + p1 * (s * (1.0 - u)) + p2 * (s * u)
    }
}

/// Whether `p` (in the plane of `t`, unit normal ±`n`) lies in triangle `t` to `tol` (m).
fn in_triangle(t: &[V3; 3], n: V3, p: V3, tol: f64) -> bool {
    let area2 = (t[1] - t[0]).cross(&(t[2] - t[0])).dot(&n);
    (0..3).all(|k| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let e = b - a;
        // signed distance of p from edge a→b, positive inside
        let d = e.cross(&(p - a)).dot(&n) * area2.signum() / e.norm();
        d >= -tol
    })
}

impl InsertVolume for Stream {
    /// The module doc's draw; `None` before [`Stream::resolve`], or with `all_in` (refused
    /// when the fix is read).
    fn random_point(
        &self,
        rng: &mut rand_chacha::ChaCha8Rng,
        radius: f64,
        all_in: bool,
    ) -> Option<V3> {
        let length = self.length?;
        if all_in {
            return None;
        }
        let p = self.point_on_face(rng);
        let span = if self.overlap_check {
            length
        } else {
            (length - 2.0 * radius).max(0.0)
        };
        let depth = rng.gen::<f64>() * span + radius;
        Some(p - depth * self.normal)
    }
}

/// A particle being carried to the face (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Held {
    /// Insertion position (m).
    pub x0: V3,
    /// Insertion step.
    pub inserted: u64,
    /// Release step.
    pub release: u64,
    /// Velocity while carried, v_n (m/s).
    pub v_carry: V3,
    /// Velocity given at release, the fix's `vel` (m/s).
    pub v_release: V3,
    /// Angular velocity given at release, the fix's `omega` (rad/s).
    pub omega_release: V3,
}

impl Held {
    /// Where the particle is at the end of `step` (m).
    pub fn position(&self, step: u64, dt: f64) -> V3 {
        self.x0 + self.v_carry * (step.saturating_sub(self.inserted) as f64 * dt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trimesh::MeshOptions;
    use rand::SeedableRng;

    /// The unit square at z = 0 in two triangles.
    fn square() -> TriMesh {
        let p = V3::new;
        let tris = [
            [p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.)],
            [p(0., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)],
        ];
        TriMesh::new("face", &tris, &[1, 2], MeshOptions::default()).0
    }

    #[test]
    fn normal_turns_along_the_velocity_and_the_period_follows_the_length() {
        let mut s = Stream::new(
            &square(),
            V3::new(0.3, 0.0, -2.0),
            Extrude::Length(0.1),
            true,
        )
        .unwrap();
        assert_eq!(s.normal(), V3::new(0.0, 0.0, -1.0));
        assert_eq!(s.v_normal(), V3::new(0.0, 0.0, -2.0));
        // K = ⌊0.1 / (1e-4 · 2)⌋ = 500
        let r = s.resolve(1e-4, None, 0.01).unwrap();
        assert_eq!(
            r,
            Resolved {
                every: 500,
                length: 0.1
            }
        );
        let e = s.resolve(1e-4, None, 0.04).unwrap_err();
        assert!(e.contains("too small"), "{e}");
        assert!(s.resolve(1e-4, Some(10), 0.01).is_err());
        // insert_every 400, duration 300: L = 300 · 1e-4 · 2
        let mut d = Stream::new(
            &square(),
            V3::new(0.0, 0.0, 2.0),
            Extrude::Duration(Some(300)),
            true,
        )
        .unwrap();
        let r = d.resolve(1e-4, Some(400), 0.01).unwrap();
        assert_eq!(r.every, 400);
        assert!((r.length - 0.06).abs() < 1e-15);
        assert!(d.resolve(1e-4, Some(200), 0.01).is_err());
    }

    #[test]
    fn velocity_along_the_face_and_bent_faces_are_refused() {
        let e = Stream::new(
            &square(),
            V3::new(1.0, 0.0, 1e-4),
            Extrude::Length(1.0),
            true,
        )
        .unwrap_err();
        assert!(e.contains("< 1e-3"), "{e}");
        let p = V3::new;
        let bent = [
            [p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.)],
            [p(0., 0., 0.), p(1., 1., 0.), p(0., 1., 0.5)],
        ];
        let m = TriMesh::new("bent", &bent, &[3, 4], MeshOptions::default()).0;
        let e = Stream::new(&m, V3::new(0.0, 0.0, 1.0), Extrude::Length(1.0), true).unwrap_err();
        assert!(e.contains("not planar") && e.contains("triangle 2"), "{e}");
    }

    /// Draws are uniform over the face and in depth r … L + r (overlap check) or r … L − r.
    #[test]
    fn draws_are_uniform_in_the_extruded_square() {
        for overlap in [true, false] {
            let mut s = Stream::new(
                &square(),
                V3::new(0.0, 0.0, 1.0),
                Extrude::Length(0.5),
                overlap,
            )
            .unwrap();
            s.resolve(0.01, None, 0.05).unwrap();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
            let n = 40_000;
            let (mut mx, mut my, mut mz) = (0.0, 0.0, 0.0);
            let mut quad = [0usize; 4];
            let (zlo, zhi) = if overlap {
                (-0.55, -0.05)
            } else {
                (-0.45, -0.05)
            };
            for _ in 0..n {
                let x = s.random_point(&mut rng, 0.05, false).unwrap();
                assert!((0.0..=1.0).contains(&x[0]) && (0.0..=1.0).contains(&x[1]));
                assert!(x[2] >= zlo - 1e-15 && x[2] <= zhi + 1e-15, "{x:?}");
                mx += x[0];
                my += x[1];
                mz += x[2];
                quad[(x[0] > 0.5) as usize + 2 * (x[1] > 0.5) as usize] += 1;
            }
            let nf = n as f64;
            // means of uniform variables: σ of a mean = width / √(12 n) ≈ 0.0014 width
            assert!((mx / nf - 0.5).abs() < 0.01, "{}", mx / nf);
            assert!((my / nf - 0.5).abs() < 0.01, "{}", my / nf);
            assert!((mz / nf - 0.5 * (zlo + zhi)).abs() < 0.01 * (zhi - zlo));
            // each quadrant 1/4: binomial σ = √(n·3/16) ≈ 87
            for q in quad {
                assert!((q as f64 - nf / 4.0).abs() < 5.0 * (nf * 3.0 / 16.0).sqrt());
            }
        }
    }

    #[test]
    fn release_steps_and_carried_position() {
        let mut s = Stream::new(
            &square(),
            V3::new(0.0, 0.0, 2.0),
            Extrude::Length(0.1),
            true,
        )
        .unwrap();
        s.resolve(1e-3, None, 0.01).unwrap();
        // depth 0.05 m at 2 m/s and 1 ms steps: 25 steps
        assert_eq!(s.steps_to_face(V3::new(0.5, 0.5, -0.05), 1e-3), 25);
        assert!(s.contains(V3::new(0.5, 0.5, -0.05), 0.0));
        assert!(!s.contains(V3::new(1.5, 0.5, -0.05), 1e-9));
        assert!(!s.contains(V3::new(0.5, 0.5, 0.01), 1e-9));
        let h = Held {
            x0: V3::new(0.5, 0.5, -0.05),
            inserted: 10,
            release: 35,
            v_carry: s.v_normal(),
            v_release: V3::new(0.0, 0.0, 2.0),
            omega_release: V3::zeros(),
        };
        assert!((h.position(35, 1e-3) - V3::new(0.5, 0.5, 0.0)).norm() < 1e-15);
    }
}
