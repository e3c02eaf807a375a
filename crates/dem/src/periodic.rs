//! Periodic box axes (`boundary p …`): the nearest image of a partner across a periodic face,
//! wrapping positions back into the box, and the image counters `ix iy iz`.
//!
//! As LAMMPS/LIGGGHTS (`Domain::pbc`, `Domain::minimum_image`), positions are wrapped into
//! [lo, hi) only when the neighbour list is rebuilt, so between two builds a particle may stand
//! up to skin/2 outside the box; its image counter on that axis goes −1 (+1) each time it is
//! moved by +L (−L). A pair interacts through the nearest image of its second particle,
//! x_i − (x_j + s) with s a whole number of box lengths per periodic axis (LIGGGHTS evaluates a
//! pair across the face with the ghost copy x_j + s, the same arithmetic). The nearest image is
//! unique while every contact distance (2R_max + skin) is below half the box length, which
//! [`Periodic::check_cutoff`] enforces.

use mesh::v3::V3;

use dem_io::Boundary;

/// LAMMPS's image-flag packing (`IMGMAX`, `IMGBITS` of `lmptype.h` without `LAMMPS_BIGBIG`):
/// ix + 512 in bits 0–9, iy + 512 in bits 10–19, iz + 512 in bits 20–29.
const IMG_MAX: i64 = 512;
/// Bits per axis in a packed image flag.
const IMG_BITS: u32 = 10;

/// The periodic axes of a box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Periodic {
    /// Lower corner (m).
    lo: V3,
    /// Upper corner (m).
    hi: V3,
    /// Box lengths (m); used on the periodic axes only.
    len: V3,
    /// Which axes are periodic.
    axes: [bool; 3],
}

impl Periodic {
    /// The periodic axes of a box with the given corners and boundaries, `None` if no axis is
    /// periodic. Errors: an axis periodic on one face only (LIGGGHTS refuses it too).
    pub fn new(lo: V3, hi: V3, boundary: &[[Boundary; 2]; 3]) -> Result<Option<Periodic>, String> {
        let mut axes = [false; 3];
        for k in 0..3 {
            let [a, b] = boundary[k];
            match (a == Boundary::Periodic, b == Boundary::Periodic) {
                (true, true) => axes[k] = true,
                (false, false) => {}
                _ => {
                    return Err(format!(
                        "axis {}: both faces must be periodic or neither",
                        ["x", "y", "z"][k]
                    ))
                }
            }
        }
        Ok(axes.iter().any(|&a| a).then(|| Periodic {
            lo,
            hi,
            len: hi - lo,
            axes,
        }))
    }

    /// Whether axis `k` is periodic.
    pub fn is_periodic(&self, k: usize) -> bool {
        self.axes[k]
    }

    /// Lower box corner (m).
    pub fn lo(&self) -> V3 {
        self.lo
    }

    /// Box lengths (m).
    pub fn len(&self) -> V3 {
        self.len
    }

    /// The shift s (whole box lengths on the periodic axes, 0 elsewhere) that makes x_j + s
    /// the image of `xj` nearest to `xi` (m).
    #[inline]
    pub fn shift(&self, xi: V3, xj: V3) -> V3 {
        let mut s = V3::zeros();
        for k in 0..3 {
            if self.axes[k] {
                let d = xi[k] - xj[k];
                let half = 0.5 * self.len[k];
                if d > half {
                    s[k] = self.len[k];
                } else if d < -half {
                    s[k] = -self.len[k];
                }
            }
        }
        s
    }

    /// x_i − (x_j + s), the separation from the nearest image of `xj` (m).
    #[inline]
    pub fn delta(&self, xi: V3, xj: V3) -> V3 {
        xi - (xj + self.shift(xi, xj))
    }

    /// Moves `x` into [lo, hi) on the periodic axes and counts the crossings in `image`, as
    /// `Domain::pbc` does (one box length per call and axis: a particle never moves more
    /// than skin/2 between two builds). Returns whether it moved.
    pub fn wrap(&self, x: &mut V3, image: &mut [i32; 3]) -> bool {
        let mut moved = false;
        for k in 0..3 {
            if !self.axes[k] {
                continue;
            }
            if x[k] < self.lo[k] {
                x[k] += self.len[k];
                image[k] -= 1;
                moved = true;
            }
            if x[k] >= self.hi[k] {
                x[k] -= self.len[k];
                x[k] = x[k].max(self.lo[k]);
                image[k] += 1;
                moved = true;
            }
        }
        moved
    }

    /// Refuses a contact distance (2R_max + skin, m) of half a box length or more on a periodic
    /// axis: a particle would then touch two images of another.
    pub fn check_cutoff(&self, cutoff: f64) -> Result<(), String> {
        for k in (0..3).filter(|&k| self.axes[k]) {
            if 2.0 * cutoff >= self.len[k] {
                return Err(format!(
                    "the periodic box is {} m long in {}: contacts reach {} m (2 R_max + skin), \
                     which must be less than half of it",
                    self.len[k],
                    ["x", "y", "z"][k],
                    cutoff
                ));
            }
        }
        Ok(())
    }
}

/// Image counters packed as LAMMPS stores them in restart files.
pub fn pack_image(image: [i32; 3]) -> i64 {
    let mask = (1i64 << IMG_BITS) - 1;
    let f = |k: usize| (image[k] as i64 + IMG_MAX) & mask;
    f(0) | (f(1) << IMG_BITS) | (f(2) << (2 * IMG_BITS))
}

/// Image counters of a packed LAMMPS image flag.
pub fn unpack_image(packed: i64) -> [i32; 3] {
    let mask = (1i64 << IMG_BITS) - 1;
    let f = |k: u32| (((packed >> (k * IMG_BITS)) & mask) - IMG_MAX) as i32;
    [f(0), f(1), f(2)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel() -> Periodic {
        let p = Boundary::Periodic;
        let f = Boundary::Fixed;
        Periodic::new(
            V3::zeros(),
            V3::new(0.4, 0.1, 0.1),
            &[[p, p], [f, f], [f, f]],
        )
        .unwrap()
        .unwrap()
    }

    #[test]
    fn nearest_image_across_the_face() {
        let per = channel();
        let d = per.delta(V3::new(0.0004, 0.05, 0.05), V3::new(0.3998, 0.05, 0.05));
        assert!((d[0] - 0.0006).abs() < 1e-15, "{d:?}");
        // a fixed axis is never shifted
        let d = per.delta(V3::new(0.1, 0.0, 0.0), V3::new(0.1, 0.09, 0.0));
        assert_eq!(d[1], -0.09);
    }

    #[test]
    fn wrap_counts_images_and_packs_as_lammps() {
        let per = channel();
        let mut x = V3::new(0.4001, 0.05, 0.05);
        let mut im = [0; 3];
        assert!(per.wrap(&mut x, &mut im));
        assert!((x[0] - 0.0001).abs() < 1e-15 && im == [1, 0, 0]);
        let mut x = V3::new(-0.0001, 0.05, 0.05);
        per.wrap(&mut x, &mut im);
        assert_eq!(im, [0, 0, 0]);
        assert_eq!(pack_image([0, 0, 0]), dem_io::restart::IMAGE_DEFAULT);
        assert_eq!(unpack_image(pack_image([-3, 7, 0])), [-3, 7, 0]);
        assert!(per.check_cutoff(0.19).is_ok() && per.check_cutoff(0.2).is_err());
    }

    #[test]
    fn one_sided_periodic_axis_is_refused() {
        let p = Boundary::Periodic;
        let f = Boundary::Fixed;
        assert!(Periodic::new(V3::zeros(), V3::repeat(1.0), &[[p, f], [f, f], [f, f]]).is_err());
        assert!(Periodic::new(V3::zeros(), V3::repeat(1.0), &[[f, f]; 3])
            .unwrap()
            .is_none());
    }
}
