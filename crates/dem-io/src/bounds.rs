//! Simulation box of a snapshot: bounds, tilt factors and boundary conditions.

use std::fmt;

/// Boundary condition of one face of the box, as LIGGGHTS's `boundary` command sets it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Boundary {
    /// `p`: periodic (binary code 0).
    Periodic,
    /// `f`: fixed, particles leaving are lost (binary code 1).
    Fixed,
    /// `s`: shrink-wrapped (binary code 2).
    Shrink,
    /// `m`: shrink-wrapped with a minimum (binary code 3).
    ShrinkMin,
}

impl Boundary {
    /// The letter used in text headers (`p`, `f`, `s`, `m`).
    pub fn letter(self) -> char {
        match self {
            Boundary::Periodic => 'p',
            Boundary::Fixed => 'f',
            Boundary::Shrink => 's',
            Boundary::ShrinkMin => 'm',
        }
    }

    /// Parses a text-header letter.
    pub fn from_letter(c: u8) -> Option<Boundary> {
        match c {
            b'p' => Some(Boundary::Periodic),
            b'f' => Some(Boundary::Fixed),
            b's' => Some(Boundary::Shrink),
            b'm' => Some(Boundary::ShrinkMin),
            _ => None,
        }
    }

    /// The integer code used in binary headers (0 = p, 1 = f, 2 = s, 3 = m).
    pub fn code(self) -> i32 {
        match self {
            Boundary::Periodic => 0,
            Boundary::Fixed => 1,
            Boundary::Shrink => 2,
            Boundary::ShrinkMin => 3,
        }
    }

    /// Parses a binary-header code.
    pub fn from_code(code: i32) -> Option<Boundary> {
        match code {
            0 => Some(Boundary::Periodic),
            1 => Some(Boundary::Fixed),
            2 => Some(Boundary::Shrink),
            3 => Some(Boundary::ShrinkMin),
            _ => None,
        }
    }
}

impl fmt::Display for Boundary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// The box of a snapshot, exactly as the dump states it (lengths in metres for `units si`).
///
/// For an orthogonal box `lo`/`hi` are the box faces. For a triclinic box LIGGGHTS writes, in
/// both text and binary dumps, the *bounding box* of the tilted cell (`xlo_bound` …) in
/// `lo`/`hi` and the tilt factors `xy xz yz` in `tilt`; [`BoxBounds::cell`] recovers the cell.
/// Text dumps print all of these with `%g` (6 significant digits); binary dumps are exact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxBounds {
    /// Lower bound per axis (bounding box for triclinic).
    pub lo: [f64; 3],
    /// Upper bound per axis (bounding box for triclinic).
    pub hi: [f64; 3],
    /// Tilt factors `[xy, xz, yz]` of a triclinic box, `None` for an orthogonal one.
    pub tilt: Option<[f64; 3]>,
    /// Boundary per axis, `[lower face, upper face]`.
    pub boundary: [[Boundary; 2]; 3],
}

/// A (possibly tilted) simulation cell: origin and three edge vectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Corner `(xlo, ylo, zlo)`.
    pub origin: [f64; 3],
    /// Edge vectors `a = (lx, 0, 0)`, `b = (xy, ly, 0)`, `c = (xz, yz, lz)`.
    pub edges: [[f64; 3]; 3],
}

impl Cell {
    /// Converts scaled (fractional) coordinates `xs ys zs` to Cartesian ones.
    pub fn to_cartesian(&self, s: [f64; 3]) -> [f64; 3] {
        let [a, b, c] = self.edges;
        let mut x = self.origin;
        for k in 0..3 {
            x[k] += s[0] * a[k] + s[1] * b[k] + s[2] * c[k];
        }
        x
    }
}

impl BoxBounds {
    /// An orthogonal box with the same boundary on every face.
    pub fn orthogonal(lo: [f64; 3], hi: [f64; 3], boundary: Boundary) -> BoxBounds {
        BoxBounds {
            lo,
            hi,
            tilt: None,
            boundary: [[boundary; 2]; 3],
        }
    }

    /// A triclinic box from its cell (`lo`/`hi` are the faces of the untilted cell, i.e. LIGGGHTS's
    /// `xlo xhi ylo yhi zlo zhi`), stored the way dumps store it (bounding box + tilt).
    pub fn triclinic(
        lo: [f64; 3],
        hi: [f64; 3],
        tilt: [f64; 3],
        boundary: [[Boundary; 2]; 3],
    ) -> BoxBounds {
        let [xy, xz, yz] = tilt;
        let (xmin, xmax) = min_max(&[0.0, xy, xz, xy + xz]);
        let (ymin, ymax) = min_max(&[0.0, yz]);
        BoxBounds {
            lo: [lo[0] + xmin, lo[1] + ymin, lo[2]],
            hi: [hi[0] + xmax, hi[1] + ymax, hi[2]],
            tilt: Some(tilt),
            boundary,
        }
    }

    /// `true` if the box has tilt factors.
    pub fn is_triclinic(&self) -> bool {
        self.tilt.is_some()
    }

    /// The simulation cell. For triclinic boxes this undoes the bounding-box shift:
    /// `xlo = xlo_bound − min(0, xy, xz, xy+xz)`, `xhi = xhi_bound − max(0, xy, xz, xy+xz)`,
    /// `ylo = ylo_bound − min(0, yz)`, `yhi = yhi_bound − max(0, yz)`.
    pub fn cell(&self) -> Cell {
        let [xy, xz, yz] = self.tilt.unwrap_or([0.0; 3]);
        let (xmin, xmax) = min_max(&[0.0, xy, xz, xy + xz]);
        let (ymin, ymax) = min_max(&[0.0, yz]);
        let lo = [self.lo[0] - xmin, self.lo[1] - ymin, self.lo[2]];
        let hi = [self.hi[0] - xmax, self.hi[1] - ymax, self.hi[2]];
        Cell {
            origin: lo,
            edges: [
                [hi[0] - lo[0], 0.0, 0.0],
                [xy, hi[1] - lo[1], 0.0],
                [xz, yz, hi[2] - lo[2]],
            ],
        }
    }

    /// Converts scaled coordinates (`xs ys zs` or `xsu ysu zsu`) to Cartesian ones.
    pub fn scaled_to_cartesian(&self, s: [f64; 3]) -> [f64; 3] {
        self.cell().to_cartesian(s)
    }

    /// The text-header flags, e.g. `mm mm ff`.
    pub fn boundary_string(&self) -> String {
        let axes: Vec<String> = self
            .boundary
            .iter()
            .map(|[a, b]| format!("{a}{b}"))
            .collect();
        axes.join(" ")
    }
}

fn min_max(values: &[f64]) -> (f64, f64) {
    values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
}
