//! LIGGGHTS 3.8 restart files (`write_restart` / `read_restart`) of `atom_style granular`:
//! a typed model of their content ([`RestartFile`]), a reader ([`read_restart`]) and a writer
//! ([`write_restart`], [`write_restart_file`]) that reproduces a file it read byte for byte.
//!
//! # Units
//! Values are stored in the units the run used (the `units` record; `si`: m, m/s, rad/s, kg,
//! kg/m³, and the contact history in m for the tangential displacement and N·m for a rolling
//! torque). Nothing is converted here.
//!
//! # Layout
//! A restart file is a memory image written by one process with the machine's byte order
//! (little-endian on every platform Debian's LIGGGHTS runs on; only little-endian files are
//! read). Integers are 4-byte `int` unless said otherwise; "bigint" is 8 bytes; a *string* is
//! an `int` n followed by n bytes that end with a NUL. The sections follow each other with no
//! padding, as checked against files written by Debian's LIGGGHTS 3.8.0:
//!
//! 1. **Header**: records of an `int` flag followed by one value, until a flag −1. Flags
//!    0–48, in the order LIGGGHTS writes them: 0 version (string, e.g. `Version
//!    LIGGGHTS-PUBLIC 3.8.0, compiled …`), 1–3 the sizes of smallint, tagint and bigint
//!    (`int`: 4, 4, 8), 4 units (string), 5 the step (bigint), 6 dimension, 7 number of
//!    processes that wrote the file (= number of atom chunks below), 8–10 processor grid,
//!    11–12 newton pair/bond, 13–15 periodic x/y/z (0/1), 16–21 boundary codes of x-lo x-hi
//!    y-lo y-hi z-lo z-hi (0 p, 1 f, 2 s, 3 m), 22 atom style (string; `granular` stores no
//!    further settings), 23 number of atoms (bigint), 24 number of atom types, 25–36 bond,
//!    angle, dihedral and improper counts (bigint for the totals, `int` for the number of
//!    types and per-atom maxima; all zero for granular atoms), 37–42 box `xlo xhi ylo yhi zlo
//!    zhi` (doubles; shrink-wrapped faces hold the box of the moment, which LIGGGHTS keeps a
//!    relative 10⁻⁴ of its length outside the outermost atom), 43–48 the special-bond factors
//!    (doubles), and for a triclinic box 49–51 the tilts `xy xz yz`. A reader that meets a flag
//!    it does not know cannot go on, since a value's length follows from its flag only.
//! 2. **Groups**: an `int` count, then for each group slot a string, an empty slot being a
//!    lone length 0 (deleted groups), up to the slot that completes the count. Bit k of an
//!    atom's mask says whether it belongs to the group of slot k (`all` is slot 0).
//! 3. **Type arrays**: (flag, data) until −1; flag 0 is the per-type mass (ntypes doubles),
//!    absent for granular atoms, which carry their own mass.
//! 4. **Force fields**: (flag, style string, data) until −1; flag 0 is the pair style. For
//!    `gran` the data is the contact model's code (bigint, see [`GranModel`]) and one `int`
//!    "coefficients set" flag per type pair i ≤ j (row by row). Bond, angle, dihedral and
//!    improper styles (flags 1–4) cannot occur with granular atoms.
//! 5. **Fixes with a global state**: an `int` count, then per fix its id and style (strings)
//!    and its state as an `int` byte count plus the bytes ([`FixState`]; LIGGGHTS hands them
//!    back to the fix of the same id and style that the next deck defines).
//! 6. **Fixes with per-atom data**: an `int` count, then per fix its id and style (strings)
//!    and the largest number of values it stores with one atom, its own count included
//!    ([`PerAtomFix`]).
//! 7. **Atoms**: one chunk per writing process: an `int` n then n doubles. A chunk is a
//!    sequence of atom records ([`AtomRecord`]): the record's length as a double (itself
//!    included), x y z, the tag, type, group mask and image flags (each an integer whose
//!    64-bit pattern is stored in the double's 8 bytes, not its value), vx vy vz, radius,
//!    mass, density, ωx ωy ωz — 17 values — then one block per per-atom fix in the order of
//!    section 6, each block starting with its own length as a double. `fix contacthistory`
//!    (the tangential history of `pair_style gran … tangential history`) stores in its block
//!    the number of contacts (integer bits), then per contact the partner's tag (integer bits)
//!    and the history values ([`FixAtomData::Contacts`]); every contact appears in the blocks
//!    of both atoms, each side holding the history as seen from itself (values that change
//!    sign with the pair's order, such as the shear displacement, are negated). A primitive
//!    `fix wall/gran` with id W keeps its per-atom history in a `fix property/atom` named
//!    `history_W` whose block holds the values only.
//!
//! Every per-atom block states its length, so data of fixes this crate does not know is kept
//! as plain values ([`FixAtomData::Values`]) and written back unchanged; what it means is for
//! the caller to decide.
//!
//! # Errors
//! Anything that is not a restart file of this kind — another program's file, another atom
//! style, another LIGGGHTS version, a truncated or corrupt file — is a [`RestartError`] that
//! names the file and the byte offset, never a panic; no allocation exceeds what the rest of
//! the file can hold.

mod error;
mod gran;
mod read;
mod write;

pub use error::{RestartError, RestartErrorKind};
pub use gran::GranModel;
pub use read::{read_restart, read_restart_from};
pub use write::{write_restart, write_restart_file};

use crate::bounds::Boundary;

/// Image flags of an atom that never crossed a periodic boundary (LIGGGHTS's default build:
/// 10 bits per axis, each holding the offset 512).
pub const IMAGE_DEFAULT: i64 = (512 << 20) | (512 << 10) | 512;

/// Number of values of an atom record of `atom_style granular` before the fixes' blocks,
/// the record's own length included.
pub const ATOM_VALUES: usize = 17;

/// The fix style that holds the pair contact history.
pub const CONTACT_HISTORY_STYLE: &str = "contacthistory";

/// The style of the per-atom storage of a primitive wall's contact history (`history_<id>`).
pub const PROPERTY_ATOM_STYLE: &str = "property/atom";

/// Everything a restart file of `atom_style granular` holds.
#[derive(Debug, Clone, PartialEq)]
pub struct RestartFile {
    /// The header records.
    pub header: Header,
    /// Group names by slot (`None`: a deleted group's empty slot); slot 0 is `all`.
    pub groups: Vec<Option<String>>,
    /// Per-type masses, if the file has them (granular atoms do not).
    pub type_mass: Option<Vec<f64>>,
    /// The pair style and its coefficients flags, if a pair style was defined.
    pub pair: Option<PairSection>,
    /// Fixes with a global state, in file order.
    pub global_fixes: Vec<FixState>,
    /// Fixes that store values with each atom, in file order (= block order in the records).
    pub peratom_fixes: Vec<PerAtomFix>,
    /// The atoms, in file order.
    pub atoms: Vec<AtomRecord>,
    /// Number of atom records in each chunk (one chunk per process that wrote the file); the
    /// header's number of processes is its length, its sum is `atoms.len()`.
    pub chunks: Vec<usize>,
}

/// The header records (section 1 of the [layout](self#layout)). The number of atoms and of
/// writing processes are not stored here: they are `atoms.len()` and `chunks.len()` of the
/// [`RestartFile`].
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// The version string of the program that wrote the file (without the NUL).
    pub version: String,
    /// `units` style (e.g. `si`).
    pub units: String,
    /// The step at which the file was written (LIGGGHTS continues from it).
    pub timestep: u64,
    /// 2 or 3.
    pub dimension: i32,
    /// Processor grid of the writing run.
    pub procgrid: [i32; 3],
    /// `newton` setting for pairs (0/1).
    pub newton_pair: i32,
    /// `newton` setting for bonds (0/1).
    pub newton_bond: i32,
    /// Boundary per axis and face; the periodicity records follow from it.
    pub boundary: [[Boundary; 2]; 3],
    /// `granular` or `sphere`.
    pub atom_style: String,
    /// Number of atom types.
    pub ntypes: usize,
    /// Box lower corner.
    pub lo: [f64; 3],
    /// Box upper corner.
    pub hi: [f64; 3],
    /// Special-bond factors for Lennard-Jones (1-2, 1-3, 1-4), unused by granular atoms.
    pub special_lj: [f64; 3],
    /// Special-bond factors for Coulomb (1-2, 1-3, 1-4), unused by granular atoms.
    pub special_coul: [f64; 3],
    /// Tilts `xy xz yz` of a triclinic box.
    pub tilt: Option<[f64; 3]>,
}

/// The pair style of the force-field section.
#[derive(Debug, Clone, PartialEq)]
pub enum PairSection {
    /// `pair_style gran`.
    Gran {
        /// The contact model (its code in the file).
        model: GranModel,
        /// Whether `pair_coeff` set type pair (i, j), for i ≤ j row by row (ntypes(ntypes+1)/2).
        setflag: Vec<i32>,
    },
}

/// A fix's global state (section 5).
#[derive(Debug, Clone, PartialEq)]
pub struct FixState {
    /// Fix id.
    pub id: String,
    /// Fix style.
    pub style: String,
    /// The bytes the fix wrote.
    pub state: Vec<u8>,
}

impl FixState {
    /// The state read as doubles (how every fix of LIGGGHTS 3.8.0 that granular decks use
    /// stores it), or `None` if its length is not a multiple of 8.
    pub fn values(&self) -> Option<Vec<f64>> {
        self.state.len().is_multiple_of(8).then(|| {
            self.state
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                .collect()
        })
    }

    /// A state made of doubles.
    pub fn from_values(id: &str, style: &str, values: &[f64]) -> FixState {
        FixState {
            id: id.to_string(),
            style: style.to_string(),
            state: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }
}

/// A fix that stores values with each atom (section 6).
#[derive(Debug, Clone, PartialEq)]
pub struct PerAtomFix {
    /// Fix id.
    pub id: String,
    /// Fix style.
    pub style: String,
    /// The largest block one atom may carry, its length value included. A writer must keep it
    /// at least as large as every atom's block ([`RestartFile::update_max_sizes`]).
    pub max_size: usize,
}

/// One atom (section 7).
#[derive(Debug, Clone, PartialEq)]
pub struct AtomRecord {
    /// Position.
    pub x: [f64; 3],
    /// Atom id (tag), ≥ 1.
    pub tag: u64,
    /// Atom type, 1..=ntypes.
    pub atom_type: u32,
    /// Group membership bits (bit k: group slot k).
    pub mask: i64,
    /// Periodic image flags ([`IMAGE_DEFAULT`] without periodic crossings).
    pub image: i64,
    /// Velocity.
    pub v: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Mass.
    pub rmass: f64,
    /// Density.
    pub density: f64,
    /// Angular velocity.
    pub omega: [f64; 3],
    /// One block per entry of [`RestartFile::peratom_fixes`], in that order.
    pub fix_data: Vec<FixAtomData>,
}

/// One fix's block in an atom record, without its length value.
#[derive(Debug, Clone, PartialEq)]
pub enum FixAtomData {
    /// `fix contacthistory`: the contacts of this atom.
    Contacts(Vec<Contact>),
    /// Any other fix: its values as stored (`fix property/atom`: its values).
    Values(Vec<f64>),
}

impl FixAtomData {
    /// Number of doubles the block takes in the file, its length value included.
    pub fn stored_len(&self) -> usize {
        match self {
            FixAtomData::Contacts(c) => 2 + c.iter().map(|c| 1 + c.history.len()).sum::<usize>(),
            FixAtomData::Values(v) => 1 + v.len(),
        }
    }
}

/// One contact in an atom's `fix contacthistory` block.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// The tag of the other atom.
    pub partner: u64,
    /// The history values as seen from the atom holding the block (for `tangential history`:
    /// the shear displacement x y z, m; `rolling_friction epsd2` appends its torque x y z, N·m).
    pub history: Vec<f64>,
}

impl RestartFile {
    /// Index of the per-atom fix with this id.
    pub fn peratom_fix(&self, id: &str) -> Option<usize> {
        self.peratom_fixes.iter().position(|f| f.id == id)
    }

    /// The global state of the fix with this id and style.
    pub fn global_fix(&self, id: &str, style: &str) -> Option<&FixState> {
        self.global_fixes
            .iter()
            .find(|f| f.id == id && f.style == style)
    }

    /// Sets each per-atom fix's `max_size` to the largest block its atoms carry (at least the
    /// minimum a block of its kind takes), as LIGGGHTS states it.
    pub fn update_max_sizes(&mut self) {
        for (k, fix) in self.peratom_fixes.iter_mut().enumerate() {
            let least = if fix.style == CONTACT_HISTORY_STYLE {
                2
            } else {
                1
            };
            fix.max_size = self
                .atoms
                .iter()
                .filter_map(|a| a.fix_data.get(k).map(FixAtomData::stored_len))
                .fold(least, usize::max);
        }
    }
}
