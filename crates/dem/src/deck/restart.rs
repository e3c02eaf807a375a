//! `read_restart FILE` and `write_restart FILE`: LIGGGHTS 3.8 restart files of `atom_style
//! granular` (the format is `dem_io::restart`'s), as CFDEM's decks use them: the packing deck
//! ends with `write_restart post/restart/liggghts.restart`, the coupled deck begins with
//! `read_restart ../DEM/post/restart/liggghts.restart`.
//!
//! # What a restart carries over
//! - box, boundary, number of atom types, the step (LIGGGHTS continues the step count);
//! - per particle: id, type, position, velocity, angular velocity, radius, density and mass
//!   (the file's mass is kept unless the deck changes radius or density with `set`);
//! - the pair contact history (`fix contacthistory`: shear displacement, plus the rolling
//!   torque of `rolling_friction epsd2`) onto the native pair list, for the pairs that
//!   overlap (LIGGGHTS 3.8 also writes pairs that separated since its last neighbour-list
//!   build with their stale history; it ignores them when reading, and so does this);
//! - each primitive wall's contact history (`fix property/atom history_W`) onto the wall
//!   `fix W wall/gran …` that the deck defines again with the same id before the first run,
//!   as LIGGGHTS hands a fix's saved state to the fix of the same id and style;
//! - the pair style (`pair_style gran …` and `pair_coeff * *` may then be left out, as in
//!   LIGGGHTS);
//! - the CFD coupling forces (`fix property/atom` blocks `dragforce`, `Ksl`, `uf`, which
//!   LIGGGHTS's `couple/cfd/force[/implicit]` saves; the native DEM's F_ext, β, u_f) when the
//!   deck defines a `couple/cfd/force…` fix before the first run, as LIGGGHTS hands them to
//!   the fix that registers them again. A coupled run (CFDEM's `writeLiggghts`) writes the
//!   state after an exchange, so these are the next interval's forces;
//! - the temperatures and heat flows (`fix property/atom` blocks `Temp`, `heatFlux`, which
//!   LIGGGHTS's `heat/gran` saves), taken up by the deck's first heat fix (`heat/gran` or
//!   `couple/cfd/convection`) if it is defined before the first run, as LIGGGHTS hands the
//!   saved values to the `Temp` property the fix creates (after a run LIGGGHTS has dropped
//!   them: a warning says so; `tests/fixtures/dem/restart/heat_continue*.in`); an all-zero
//!   `heatSource` block is accepted (the native DEM has no heat source); a file the native DEM writes has them
//!   whenever it has a heat state (the convective flows are not saved: LIGGGHTS's are not,
//!   and the coupler sets them at each exchange).
//!
//! What the native DEM has no place for is reported as a warning, never dropped silently:
//! groups other than `all`, per-type masses, the global state of other fixes
//! (insertion counters, random seeds of templates) and the per-atom data of other fixes.
//! Restoring a history whose number of values differs from what the deck's contact model
//! keeps is an error, as in LIGGGHTS ("saved simulation state used different contact history
//! model"); so are multisphere bodies (`fix multisphere…` state), which as loose spheres would
//! fall apart, and everything the [`dem_io::restart`] reader refuses (another atom style or
//! version, a corrupt file); and units other than `si`, 2d or triclinic boxes. Periodic
//! image flags are read and written ([`crate::periodic`]).
//!
//! # Continuing a run
//! A restart file holds the velocities at the end of its step but not the forces, which the
//! run evaluated half a step earlier (velocity Verlet evaluates the forces between the two
//! half kicks). LIGGGHTS's set-up evaluates them again at the end-of-step velocities without
//! advancing the history ([`HistoryUse::Setup`](crate::contact::HistoryUse)), so its run
//! continued from a restart file (bit for bit its `run A` + `run B` in one process) drifts
//! from the uninterrupted `run A+B` by the dashpot forces' change over half a step (see
//! `tests/fixtures/dem/restart/README.md`). Reading a LIGGGHTS file, the native DEM does the
//! same and so continues exactly as LIGGGHTS does. Its own files carry one more per-atom block,
//! [`HALF_STEP_ID`]: the velocities half a step earlier, the forces of the step and the part
//! of them the CFD coupling contributed (the coupling was replaced by the next interval's
//! since; files without that part, 12 values per atom, are read too). With them
//! the set-up evaluates the forces of the file's step again
//! ([`HistoryUse::Replay`](crate::contact::HistoryUse)); when they are the recorded ones to
//! round-off (the deck set up the same contacts, walls, gravity) the recorded forces are used,
//! and the continued run is the uninterrupted one bit for bit (on one thread; on several, the
//! fresh neighbour list may sum the forces in another order).
//!
//! A file written here is read by Debian's LIGGGHTS 3.8.0 (`read_restart`), which continues
//! the run with the same contact history and keeps the half-step block unused. The file
//! claims to be a LIGGGHTS 3.8.0 file written by foamgrain, so LIGGGHTS warns that the version
//! string differs from its own.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use dem_io::restart::{
    self as rs, AtomRecord, Contact, FixAtomData, FixState, GranModel, Header, PairSection,
    PerAtomFix, RestartFile, CONTACT_HISTORY_STYLE, IMAGE_DEFAULT, PROPERTY_ATOM_STYLE,
};
use dem_io::Boundary;
use mesh::v3::V3;

use crate::contact::{ContactModel, History, RollingModel};
use crate::particles::NewParticle;
use crate::periodic::{pack_image, unpack_image};
use crate::sim::{HalfStep, SimBox, Simulation};

type Res<T> = Result<T, String>;

/// The version string written into restart files.
pub const VERSION: &str = concat!(
    "Version LIGGGHTS-PUBLIC 3.8.0, written by foamgrain ",
    env!("CARGO_PKG_VERSION")
);

/// Prefix of the id of the `fix property/atom` holding a primitive wall's history.
const WALL_HISTORY_PREFIX: &str = "history_";

/// Id and style of the per-atom block only the native DEM writes and reads ([`HalfStep`]): the
/// velocities and angular velocities half a step before the file's step, with which that
/// step's forces were evaluated, and those forces and torques (vx vy vz ωx ωy ωz fx fy fz tx
/// ty tz; m/s, rad/s, N, N·m). A fix of this style does not exist in LIGGGHTS, which keeps
/// the block unused when it reads the file.
pub const HALF_STEP_ID: &str = "foamgrain_halfstep";
/// See [`HALF_STEP_ID`].
pub const HALF_STEP_STYLE: &str = "foamgrain/halfstep";
/// Values per atom of the [`HALF_STEP_ID`] block: the [`HalfStep`] velocities, angular
/// velocities, forces, torques and the coupling part of the forces.
const HALF_STEP_VALUES: usize = 15;
/// Values per atom of the block written before the coupling part was recorded (still read).
const HALF_STEP_VALUES_NO_COUPLING: usize = 12;

/// The per-atom blocks of the CFD coupling, as LIGGGHTS's `fix couple/cfd/force[/implicit]`
/// registers them (`fix property/atom`, saved in restart files): id and values per atom. The
/// particle feels F = dragforce + Ksl (uf − v) (N), the native [`crate::coupling::Coupling`]'s
/// F_ext, β (kg/s) and u_f (m/s).
const COUPLING_BLOCKS: [(&str, usize); 3] = [("dragforce", 3), ("Ksl", 1), ("uf", 3)];

/// The per-atom blocks of the heat state, as LIGGGHTS's `heat/gran` registers them (`fix
/// property/atom`, one value per atom, saved in restart files): the temperature (K) and the heat
/// flow of the last step (W).
const HEAT_BLOCKS: [&str; 2] = ["Temp", "heatFlux"];

/// The per-atom heat source LIGGGHTS's `heat/gran` saves (W): the native DEM has none, so a
/// file's block is accepted when it is all zero and reported as dropped otherwise.
const HEAT_SOURCE_ID: &str = "heatSource";

/// Temperature (K) and, if saved, heat flow (W) by particle id.
pub type SavedHeat = HashMap<u64, (f64, Option<f64>)>;

/// A saved pair contact: holder id, partner id, history values as seen from the holder.
type SavedContact = (u64, u64, Vec<f64>);

/// A restart file read by `read_restart`, with what is applied when the simulation is built.
#[derive(Debug)]
pub struct Loaded {
    /// The file (for messages).
    pub file: PathBuf,
    /// Box and boundary.
    pub sim_box: SimBox,
    /// Number of atom types.
    pub ntypes: usize,
    /// The step to continue from.
    pub step: u64,
    /// The particles, in file order (taken by the deck executor).
    pub particles: Vec<NewParticle>,
    /// Their ids, in file order (the order of the wall histories).
    ids: Vec<u64>,
    /// Pair style of the file, if it has one.
    pub pair: Option<GranModel>,
    /// Whether every type pair had coefficients (`pair_coeff`) in the file.
    pub pair_coeff: bool,
    /// (id, radius, density, mass) per particle as the file states them.
    masses: Vec<(u64, f64, f64, f64)>,
    /// (id, periodic image counters) of the particles whose counters are not zero.
    images: Vec<(u64, [i32; 3])>,
    /// Pair contacts with the number of history values each.
    contacts: Option<(usize, Vec<SavedContact>)>,
    /// Wall histories by wall id: values per particle (same order as `particles`).
    walls: Vec<(String, usize, Vec<Vec<f64>>)>,
    /// The [`HalfStep`] values per particle (same order), if recorded (the coupling part zero
    /// when the file has 12 values per atom, `coupling_recorded` false).
    half_step: Option<Vec<[f64; HALF_STEP_VALUES]>>,
    /// Whether the half-step block records the coupling part of the forces.
    coupling_recorded: bool,
    /// The coupling blocks ([`COUPLING_BLOCKS`] order) per particle (same order), those the
    /// file has.
    coupling: [Option<Vec<Vec<f64>>>; 3],
    /// The saved temperatures and heat flows (the `Temp` and `heatFlux` blocks), taken up by the
    /// first heat fix.
    pub heat: Option<SavedHeat>,
}

/// Reads `path` for `read_restart`; returns the state and the warnings about what the native
/// DEM does not take over.
pub fn read(path: &Path) -> Res<(Loaded, Vec<String>)> {
    let f = rs::read_restart(path).map_err(|e| e.to_string())?;
    let name = path.display();
    let h = &f.header;
    refused(&f).map_err(|what| format!("{name}: {what}"))?;
    let mut warnings = Vec::new();
    let mut warn = |w: String| warnings.push(format!("read_restart {name}: {w}"));

    let extra_groups: Vec<&str> = f
        .groups
        .iter()
        .flatten()
        .skip(1)
        .map(|s| s.as_str())
        .collect();
    if !extra_groups.is_empty() {
        warn(format!(
            "groups {} are dropped (the native DEM knows only `all`)",
            extra_groups.join(" ")
        ));
    }
    if f.type_mass.is_some() {
        warn("per-type masses are ignored (granular particles carry their own mass)".into());
    }

    let particles: Vec<NewParticle> = f
        .atoms
        .iter()
        .map(|a| NewParticle {
            id: a.tag,
            atom_type: a.atom_type,
            x: V3::from(a.x),
            v: V3::from(a.v),
            omega: V3::from(a.omega),
            radius: a.radius,
            density: a.density,
        })
        .collect();
    let masses = f
        .atoms
        .iter()
        .map(|a| (a.tag, a.radius, a.density, a.rmass))
        .collect();
    let images = f
        .atoms
        .iter()
        .filter(|a| a.image != IMAGE_DEFAULT)
        .map(|a| (a.tag, unpack_image(a.image)))
        .collect();

    let data = PerAtomData::read(&f).map_err(|what| format!("{name}: {what}"))?;
    if !data.unused.is_empty() {
        warn(format!(
            "per-atom data of fixes {} is dropped (the native DEM has no such fix)",
            data.unused.join(", ")
        ));
    }
    let ignored: Vec<String> = f
        .global_fixes
        .iter()
        .filter(|g| {
            !(g.style == CONTACT_HISTORY_STYLE
                || (g.style == PROPERTY_ATOM_STYLE && f.peratom_fix(&g.id).is_some()))
        })
        .map(|g| format!("{} ({})", g.id, g.style))
        .collect();
    if !ignored.is_empty() {
        warn(format!(
            "the saved state of fixes {} is not restored (a fix of that id defined again \
             starts afresh)",
            ignored.join(", ")
        ));
    }
    let (pair, pair_coeff) = match &f.pair {
        Some(PairSection::Gran { model, setflag }) => {
            (Some(*model), setflag.iter().all(|&s| s != 0))
        }
        None => (None, false),
    };
    let lo = V3::from(h.lo);
    let hi = V3::from(h.hi);
    Ok((
        Loaded {
            file: path.to_path_buf(),
            sim_box: SimBox {
                lo,
                hi,
                boundary: h.boundary,
            },
            ntypes: h.ntypes,
            step: h.timestep,
            ids: particles.iter().map(|p| p.id).collect(),
            particles,
            pair,
            pair_coeff,
            masses,
            images,
            contacts: data.contacts,
            walls: data.walls,
            half_step: data.half_step,
            coupling_recorded: data.coupling_recorded,
            coupling: data.coupling,
            heat: saved_heat(&f, &data.heat),
        },
        warnings,
    ))
}

/// Why the native DEM refuses a restart file, if it does: units other than `si`, 2d or
/// triclinic boxes, multisphere bodies.
fn refused(f: &RestartFile) -> Res<()> {
    let h = &f.header;
    if h.units != "si" {
        return Err(format!("units `{}`: only `units si` is supported", h.units));
    }
    if h.dimension != 3 {
        return Err(format!("dimension {}: only 3d is supported", h.dimension));
    }
    if h.tilt.is_some() {
        return Err("a triclinic box is not supported".into());
    }
    // clumps of spheres: read as loose spheres they would fall apart (LIGGGHTS too refuses to
    // go on when a deck does not take the bodies up again)
    let bodies = f
        .global_fixes
        .iter()
        .map(|g| (&g.id, &g.style))
        .chain(f.peratom_fixes.iter().map(|p| (&p.id, &p.style)))
        .find(|(_, style)| style.starts_with("multisphere"));
    if let Some((id, style)) = bodies {
        return Err(format!(
            "fix {id} ({style}) holds multisphere bodies, which the native DEM does not support"
        ));
    }
    Ok(())
}

/// The per-atom data of a restart file by kind of block: the pair contact history and the
/// walls' histories, the [`HALF_STEP_ID`] block and the [`COUPLING_BLOCKS`] are used, the
/// other fixes' blocks named (`unused`).
struct PerAtomData {
    /// Pair contacts with the number of history values each.
    contacts: Option<(usize, Vec<SavedContact>)>,
    /// Wall histories by wall id: values per particle (file order).
    walls: Vec<(String, usize, Vec<Vec<f64>>)>,
    /// The [`HalfStep`] values per particle, if recorded.
    half_step: Option<Vec<[f64; HALF_STEP_VALUES]>>,
    /// Whether the half-step block records the coupling part of the forces.
    coupling_recorded: bool,
    /// The coupling blocks ([`COUPLING_BLOCKS`] order) per particle, those the file has.
    coupling: [Option<Vec<Vec<f64>>>; 3],
    /// The [`HEAT_BLOCKS`] values per particle (file order), those the file has.
    heat: [Option<Vec<f64>>; 2],
    /// `ID (STYLE)` of the fixes whose per-atom data is dropped.
    unused: Vec<String>,
}

impl PerAtomData {
    /// Sorts the file's per-atom blocks by kind (errors without the file name).
    fn read(f: &RestartFile) -> Res<PerAtomData> {
        let mut data = PerAtomData {
            contacts: None,
            walls: Vec::new(),
            half_step: None,
            coupling_recorded: true,
            coupling: Default::default(),
            heat: Default::default(),
            unused: Vec::new(),
        };
        for (k, fix) in f.peratom_fixes.iter().enumerate() {
            let wall_id = fix.id.strip_prefix(WALL_HISTORY_PREFIX);
            let coupling_block = COUPLING_BLOCKS.iter().position(|b| b.0 == fix.id);
            let heat_block = HEAT_BLOCKS.iter().position(|&b| b == fix.id);
            if fix.id == HALF_STEP_ID && fix.style == HALF_STEP_STYLE {
                let (per, recorded) = half_step_block(f, k, fix)?;
                data.coupling_recorded &= recorded;
                data.half_step = Some(per);
            } else if let (Some(b), PROPERTY_ATOM_STYLE) = (coupling_block, fix.style.as_str()) {
                data.coupling[b] = Some(coupling_block_values(f, k, b)?);
            } else if let (Some(b), PROPERTY_ATOM_STYLE) = (heat_block, fix.style.as_str()) {
                data.heat[b] = Some(scalar_block(f, k, HEAT_BLOCKS[b])?);
            } else if fix.id == HEAT_SOURCE_ID
                && fix.style == PROPERTY_ATOM_STYLE
                && scalar_block(f, k, HEAT_SOURCE_ID)?
                    .iter()
                    .all(|&v| v == 0.0)
            {
                // heat/gran's heat source, zero unless a deck sets it: nothing is lost
            } else if fix.style == CONTACT_HISTORY_STYLE {
                data.contacts = Some(pair_contact_block(f, k, fix));
            } else if let (Some(wall), PROPERTY_ATOM_STYLE) = (wall_id, fix.style.as_str()) {
                let (width, per) = wall_block(f, k, fix)?;
                data.walls.push((wall.to_string(), width, per));
            } else {
                data.unused.push(format!("{} ({})", fix.id, fix.style));
            }
        }
        Ok(data)
    }
}

/// The [`HALF_STEP_ID`] block (per-atom fix `k`): the values per particle, and whether every
/// particle's record has the coupling part.
fn half_step_block(
    f: &RestartFile,
    k: usize,
    fix: &PerAtomFix,
) -> Res<(Vec<[f64; HALF_STEP_VALUES]>, bool)> {
    let mut coupling_recorded = true;
    let mut per = Vec::with_capacity(f.atoms.len());
    for a in &f.atoms {
        match &a.fix_data[k] {
            FixAtomData::Values(v)
                if v.len() == HALF_STEP_VALUES || v.len() == HALF_STEP_VALUES_NO_COUPLING =>
            {
                coupling_recorded &= v.len() == HALF_STEP_VALUES;
                per.push(std::array::from_fn(|j| v.get(j).copied().unwrap_or(0.0)))
            }
            _ => {
                return Err(format!(
                    "fix {}: {HALF_STEP_VALUES} (or {HALF_STEP_VALUES_NO_COUPLING}) \
                     values per atom expected",
                    fix.id
                ))
            }
        }
    }
    Ok((per, coupling_recorded))
}

/// A one-value-per-atom `property/atom` block (per-atom fix `k`, id `id`).
fn scalar_block(f: &RestartFile, k: usize, id: &str) -> Res<Vec<f64>> {
    f.atoms
        .iter()
        .map(|a| match &a.fix_data[k] {
            FixAtomData::Values(v) if v.len() == 1 => Ok(v[0]),
            _ => Err(format!(
                "fix {id} (property/atom): 1 value per atom expected"
            )),
        })
        .collect()
}

/// The saved temperatures (and heat flows) by particle id, if the file has temperatures.
fn saved_heat(f: &RestartFile, heat: &[Option<Vec<f64>>; 2]) -> Option<SavedHeat> {
    let temp = heat[0].as_ref()?;
    Some(
        f.atoms
            .iter()
            .enumerate()
            .map(|(i, a)| (a.tag, (temp[i], heat[1].as_ref().map(|q| q[i]))))
            .collect(),
    )
}

/// The coupling block `b` of [`COUPLING_BLOCKS`] (per-atom fix `k`): the values per particle.
fn coupling_block_values(f: &RestartFile, k: usize, b: usize) -> Res<Vec<Vec<f64>>> {
    let (id, width) = COUPLING_BLOCKS[b];
    let mut per = Vec::with_capacity(f.atoms.len());
    for a in &f.atoms {
        match &a.fix_data[k] {
            FixAtomData::Values(v) if v.len() == width => per.push(v.clone()),
            _ => {
                return Err(format!(
                    "fix {id} (property/atom): {width} values per atom expected"
                ))
            }
        }
    }
    Ok(per)
}

/// The pair contact history (per-atom fix `k`): the number of values per contact (from the
/// fix's global state) and every particle's contacts.
fn pair_contact_block(f: &RestartFile, k: usize, fix: &PerAtomFix) -> (usize, Vec<SavedContact>) {
    let dnum = f
        .global_fix(&fix.id, &fix.style)
        .and_then(FixState::values)
        .and_then(|v| v.first().copied())
        .unwrap_or(0.0) as usize;
    let mut list = Vec::new();
    for a in &f.atoms {
        if let FixAtomData::Contacts(cs) = &a.fix_data[k] {
            for c in cs {
                list.push((a.tag, c.partner, c.history.clone()));
            }
        }
    }
    (dnum, list)
}

/// A primitive wall's history (per-atom fix `k`): the values per particle and their number.
fn wall_block(f: &RestartFile, k: usize, fix: &PerAtomFix) -> Res<(usize, Vec<Vec<f64>>)> {
    let mut per = Vec::with_capacity(f.atoms.len());
    let mut width = None;
    for a in &f.atoms {
        let FixAtomData::Values(v) = &a.fix_data[k] else {
            return Err(format!("fix {}: unexpected contact data", fix.id));
        };
        if width.is_some_and(|w| w != v.len()) {
            return Err(format!("fix {}: blocks of different lengths", fix.id));
        }
        width = Some(v.len());
        per.push(v.clone());
    }
    Ok((width.unwrap_or(0), per))
}

/// The native contact model of a `pair_style gran` code, if the native DEM has it.
pub fn contact_model(m: &GranModel) -> Res<ContactModel> {
    let supported = m.normal == 3
        && m.tangential == 2
        && m.surface == 0
        && matches!(m.cohesion, 0 | 1)
        && matches!(m.rolling, 0 | 1 | 3);
    if !supported {
        return Err(format!(
            "the restart file's pair style `gran {m}` is not supported by the native DEM \
             (give `pair_style gran model hertz tangential history …` after read_restart)"
        ));
    }
    Ok(ContactModel {
        cohesion: m.cohesion == 1,
        rolling: match m.rolling {
            1 => Some(RollingModel::Cdt),
            3 => Some(RollingModel::Epsd2),
            _ => None,
        },
        ..ContactModel::default()
    })
}

/// The code of a native contact model.
fn gran_model(m: &ContactModel) -> GranModel {
    GranModel {
        cohesion: u8::from(m.cohesion),
        rolling: match m.rolling {
            None => 0,
            Some(RollingModel::Cdt) => 1,
            Some(RollingModel::Epsd2) => 3,
        },
        ..GranModel::HERTZ_HISTORY
    }
}

/// Number of history values LIGGGHTS keeps per contact for a model: the shear displacement,
/// plus the rolling torque of `epsd2`.
fn history_len(m: &ContactModel) -> usize {
    if m.rolling == Some(RollingModel::Epsd2) {
        6
    } else {
        3
    }
}

fn to_history(v: &[f64]) -> History {
    let roll = if v.len() >= 6 {
        V3::new(v[3], v[4], v[5])
    } else {
        V3::zeros()
    };
    History {
        shear: V3::new(v[0], v[1], v[2]),
        roll,
    }
}

fn from_history(h: &History, len: usize) -> Vec<f64> {
    let mut v = vec![h.shear[0], h.shear[1], h.shear[2]];
    if len == 6 {
        v.extend_from_slice(&[h.roll[0], h.roll[1], h.roll[2]]);
    }
    v
}

impl Loaded {
    /// Applies what the particles alone do not carry — masses, the step, the pair and wall
    /// contact histories, and with `coupled` (the deck defines `fix couple/cfd/force…`, which
    /// takes the saved `dragforce`, `Ksl` and `uf` up in LIGGGHTS) the coupling forces — to a
    /// simulation just built from the deck (walls defined, the restart's particles added).
    /// Returns warnings.
    pub fn apply(self, sim: &mut Simulation, coupled: bool) -> Res<Vec<String>> {
        let name = self.file.display().to_string();
        let mut warnings = Vec::new();
        sim.set_step(self.step);
        let index: HashMap<u64, usize> = sim
            .particles
            .id
            .iter()
            .enumerate()
            .map(|(i, &id)| (id, i))
            .collect();
        self.apply_masses_and_images(sim, &index);
        warnings.extend(self.apply_pair_contacts(sim, &index, &name)?);
        let used = self.apply_wall_histories(sim, &index, &name)?;
        let saved_coupling = self.coupling.iter().any(Option::is_some);
        if saved_coupling && !coupled {
            warnings.push(format!(
                "{name}: the saved coupling forces (dragforce, Ksl, uf) are dropped: the deck \
                 defines no `fix … couple/cfd/force` before the first run"
            ));
        }
        if coupled && saved_coupling {
            self.apply_coupling(sim, &index, &name)?;
        }
        if let Some(hs) = &self.half_step {
            self.apply_half_step(sim, &index, hs);
        }

        let orphans: Vec<&str> = self
            .walls
            .iter()
            .zip(&used)
            .filter(|(_, &u)| !u)
            .map(|(w, _)| w.0.as_str())
            .collect();
        if !orphans.is_empty() {
            warnings.push(format!(
                "{name}: the saved contact history with walls {} is dropped (no `fix … \
                 wall/gran` of that id before the first run)",
                orphans.join(" ")
            ));
        }
        Ok(warnings)
    }

    /// The file's masses (where the deck left radius and density as the file has them) and
    /// periodic image counters, onto the particles by id (`index`: particle index by id).
    fn apply_masses_and_images(&self, sim: &mut Simulation, index: &HashMap<u64, usize>) {
        let p = &mut sim.particles;
        for &(id, radius, density, mass) in &self.masses {
            if let Some(&i) = index.get(&id) {
                if p.radius[i] == radius && p.density[i] == density {
                    p.mass[i] = mass;
                }
            }
        }
        for &(id, image) in &self.images {
            if let Some(&i) = index.get(&id) {
                p.image[i] = image;
            }
        }
    }

    /// The saved pair contact history onto the native pair list; returns the warning about
    /// saved contacts naming absent particles, if any.
    fn apply_pair_contacts(
        &self,
        sim: &mut Simulation,
        index: &HashMap<u64, usize>,
        name: &str,
    ) -> Res<Option<String>> {
        let model = *sim.pair_model();
        let Some((dnum, list)) = &self.contacts else {
            return Ok(None);
        };
        let dnum = *dnum;
        let want = history_len(&model);
        if dnum != want {
            return Err(format!(
                "{name}: the saved pair contact history has {dnum} values per contact, \
                 the contact model of the deck keeps {want}: a different contact history \
                 model cannot continue it"
            ));
        }
        let mut missing = 0;
        let mut pairs = Vec::with_capacity(list.len() / 2);
        let mut have: HashSet<(usize, usize)> = HashSet::new();
        // each contact is stored by both particles; take the record of the lower index
        // (the native pair's view), and the other one only where it is alone
        let resolved: Vec<(usize, usize, &Vec<f64>)> = list
            .iter()
            .filter_map(|(a, b, v)| match (index.get(a), index.get(b)) {
                (Some(&i), Some(&j)) => Some((i, j, v)),
                _ => {
                    missing += 1;
                    None
                }
            })
            .collect();
        for &(i, j, v) in resolved.iter().filter(|c| c.0 < c.1) {
            have.insert((i, j));
            pairs.push((i, j, to_history(v)));
        }
        for &(i, j, v) in resolved.iter().filter(|c| c.0 > c.1) {
            if !have.contains(&(j, i)) {
                pairs.push((i, j, to_history(v)));
            }
        }
        sim.set_pair_contacts(&pairs);
        // pairs apart now are skipped without a warning: LIGGGHTS 3.8 writes the stale
        // history of pairs that separated since its last neighbour-list build, and takes
        // up only the overlapping ones when it reads, so nothing it would use is lost
        Ok((missing > 0).then(|| {
            format!(
                "{name}: {missing} saved contacts name particles that are not present; \
                 dropped"
            )
        }))
    }

    /// Each saved wall history onto the deck's primitive wall of the same id; returns which of
    /// the saved walls found theirs.
    fn apply_wall_histories(
        &self,
        sim: &mut Simulation,
        index: &HashMap<u64, usize>,
        name: &str,
    ) -> Res<Vec<bool>> {
        let walls: Vec<(usize, String, usize)> = sim
            .walls()
            .iter()
            .enumerate()
            .map(|(w, wall)| (w, wall.name.clone(), history_len(&wall.model)))
            .collect();
        let mut used = vec![false; self.walls.len()];
        for (w, wall, want) in walls {
            let Some(k) = self.walls.iter().position(|x| x.0 == wall) else {
                continue;
            };
            used[k] = true;
            let (_, width, per) = &self.walls[k];
            if *width != want {
                return Err(format!(
                    "{name}: the saved history of wall {wall} has {width} values per particle, \
                     its contact model in the deck keeps {want}"
                ));
            }
            for (id, v) in self.ids.iter().zip(per) {
                if let Some(&i) = index.get(id) {
                    sim.set_wall_history(i, w, to_history(v));
                }
            }
        }
        Ok(used)
    }

    /// The saved coupling forces (F_ext, β, u_f) onto the particles.
    fn apply_coupling(
        &self,
        sim: &mut Simulation,
        index: &HashMap<u64, usize>,
        name: &str,
    ) -> Res<()> {
        // particles not from the file get no coupling force until the next exchange
        let n = sim.particles.len();
        let (mut f_ext, mut beta, mut u_f) =
            (vec![V3::zeros(); n], vec![0.0; n], vec![V3::zeros(); n]);
        let [drag, ksl, uf] = &self.coupling;
        for (k, id) in self.ids.iter().enumerate() {
            let Some(&i) = index.get(id) else { continue };
            let v3 = |b: &Option<Vec<Vec<f64>>>| {
                b.as_ref()
                    .map_or(V3::zeros(), |b| V3::new(b[k][0], b[k][1], b[k][2]))
            };
            f_ext[i] = v3(drag);
            u_f[i] = v3(uf);
            beta[i] = ksl.as_ref().map_or(0.0, |b| b[k][0]);
        }
        sim.set_coupling(&f_ext, &beta, &u_f)
            .map_err(|e| format!("{name}: the saved coupling forces: {e}"))
    }

    /// The saved [`HalfStep`] values `hs` (file order) onto the particles.
    fn apply_half_step(
        &self,
        sim: &mut Simulation,
        index: &HashMap<u64, usize>,
        hs: &[[f64; HALF_STEP_VALUES]],
    ) {
        // particles not from the file (created after read_restart) keep their velocities
        // and zero recorded forces, which differ from the evaluated ones: the set-up then
        // uses the evaluated forces for all
        let p = &sim.particles;
        let zero = vec![V3::zeros(); p.len()];
        let mut h = HalfStep {
            v: p.v.clone(),
            omega: p.omega.clone(),
            force: zero.clone(),
            torque: zero.clone(),
            coupling: match self.coupling_recorded {
                true => zero,
                false => Vec::new(),
            },
        };
        for (id, r) in self.ids.iter().zip(hs) {
            if let Some(&i) = index.get(id) {
                h.v[i] = V3::new(r[0], r[1], r[2]);
                h.omega[i] = V3::new(r[3], r[4], r[5]);
                h.force[i] = V3::new(r[6], r[7], r[8]);
                h.torque[i] = V3::new(r[9], r[10], r[11]);
                if let Some(c) = h.coupling.get_mut(i) {
                    *c = V3::new(r[12], r[13], r[14]);
                }
            }
        }
        sim.set_half_step(h);
    }
}

/// The file name of `write_restart NAME`: a `*` is replaced by the step, as in LIGGGHTS.
pub fn output_name(name: &str, step: u64) -> String {
    name.replacen('*', &step.to_string(), 1)
}

/// The file `read_restart NAME` opens: with a `*`, the file of the directory whose name
/// matches with the largest step in place of the `*` (as LIGGGHTS searches).
pub fn input_name(name: &Path) -> Res<PathBuf> {
    let s = name.to_string_lossy();
    let Some(star) = s.rfind('*') else {
        return Ok(name.to_path_buf());
    };
    let (dir, file) = match s[..star].rfind('/') {
        Some(k) => (PathBuf::from(&s[..k.max(1)]), &s[k + 1..]),
        None => (PathBuf::from("."), &s[..]),
    };
    let star_in_file = file.find('*').expect("the star is in the file name");
    let (begin, end) = (&file[..star_in_file], &file[star_in_file + 1..]);
    let mut best: Option<(u64, PathBuf)> = None;
    let entries = std::fs::read_dir(&dir)
        .map_err(|e| format!("cannot search {} for {s}: {e}", dir.display()))?;
    for e in entries.flatten() {
        let n = e.file_name().to_string_lossy().into_owned();
        let step = n
            .strip_prefix(begin)
            .and_then(|r| r.strip_suffix(end))
            .and_then(|m| m.parse::<u64>().ok());
        if let Some(step) = step {
            if best.as_ref().is_none_or(|b| step > b.0) {
                best = Some((step, dir.join(&n)));
            }
        }
    }
    best.map(|b| b.1)
        .ok_or_else(|| format!("no restart file matches {s}"))
}

/// The box LIGGGHTS would write: shrink-wrapped faces a relative 10⁻⁴ of the box length
/// outside the outermost particle (`m` faces never inside the set box).
fn written_box(b: &SimBox, x: &[V3]) -> ([f64; 3], [f64; 3]) {
    let mut lo: [f64; 3] = b.lo.into();
    let mut hi: [f64; 3] = b.hi.into();
    if x.is_empty() {
        return (lo, hi);
    }
    for k in 0..3 {
        let small = 1e-4 * (b.hi[k] - b.lo[k]);
        let (mn, mx) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, c), p| {
                (a.min(p[k]), c.max(p[k]))
            });
        match b.boundary[k][0] {
            Boundary::Shrink => lo[k] = mn - small,
            Boundary::ShrinkMin => lo[k] = (mn - small).min(b.lo[k]),
            _ => {}
        }
        match b.boundary[k][1] {
            Boundary::Shrink => hi[k] = mx + small,
            Boundary::ShrinkMin => hi[k] = (mx + small).max(b.hi[k]),
            _ => {}
        }
    }
    (lo, hi)
}

/// The restart file of the simulation's current state.
pub fn restart_file(sim: &Simulation) -> RestartFile {
    let p = &sim.particles;
    let n = p.len();
    let ntypes = sim.materials().ntypes();
    let b = sim.sim_box();
    let (lo, hi) = written_box(b, &p.x);
    let model = *sim.pair_model();
    let dnum = history_len(&model);
    let contacts = contacts_per_atom(sim, dnum);
    let half_step = sim.half_step();
    let (global_fixes, peratom_fixes) = fix_blocks(sim, dnum, &contacts, half_step.is_some());
    let atoms = atom_records(sim, contacts, half_step.as_ref());
    let mut f = RestartFile {
        header: Header {
            version: VERSION.into(),
            units: "si".into(),
            timestep: sim.step(),
            dimension: 3,
            procgrid: [1, 1, 1],
            newton_pair: 0,
            newton_bond: 0,
            boundary: b.boundary,
            atom_style: "granular".into(),
            ntypes,
            lo,
            hi,
            special_lj: [0.0; 3],
            special_coul: [0.0; 3],
            tilt: None,
        },
        groups: vec![Some("all".into())],
        type_mass: None,
        pair: Some(PairSection::Gran {
            model: gran_model(&model),
            setflag: vec![1; ntypes * (ntypes + 1) / 2],
        }),
        global_fixes,
        peratom_fixes,
        atoms,
        chunks: vec![n],
    };
    f.update_max_sizes();
    f
}

/// Every particle's pair contacts as LIGGGHTS stores them: by both particles, each with the
/// history as seen from it (`dnum` values).
fn contacts_per_atom(sim: &Simulation, dnum: usize) -> Vec<Vec<Contact>> {
    let p = &sim.particles;
    let mut contacts: Vec<Vec<Contact>> = vec![Vec::new(); p.len()];
    for (i, j, h) in sim.pair_contacts() {
        contacts[i].push(Contact {
            partner: p.id[j],
            history: from_history(&h, dnum),
        });
        let back = History {
            shear: -h.shear,
            roll: -h.roll,
        };
        contacts[j].push(Contact {
            partner: p.id[i],
            history: from_history(&back, dnum),
        });
    }
    contacts
}

/// The fixes' global states and per-atom blocks, in LIGGGHTS's order: the walls' histories
/// (created with the walls), then the pair contact history (created at the first run), then
/// the [`HALF_STEP_ID`] block (with `half_step`) and the coupling blocks.
fn fix_blocks(
    sim: &Simulation,
    dnum: usize,
    contacts: &[Vec<Contact>],
    half_step: bool,
) -> (Vec<FixState>, Vec<PerAtomFix>) {
    let walls = sim.walls();
    let nw = walls.len();
    let mut peratom_fixes = Vec::with_capacity(nw + 1);
    let mut global_fixes = Vec::with_capacity(nw + 1);
    for wall in walls {
        let id = format!("{WALL_HISTORY_PREFIX}{}", wall.name);
        let len = history_len(&wall.model);
        global_fixes.push(FixState::from_values(
            &id,
            PROPERTY_ATOM_STYLE,
            &[len as f64],
        ));
        peratom_fixes.push(PerAtomFix {
            id,
            style: PROPERTY_ATOM_STYLE.into(),
            max_size: len + 1,
        });
    }
    let maxtouch = contacts.iter().map(Vec::len).max().unwrap_or(0);
    global_fixes.push(FixState::from_values(
        CONTACT_HISTORY_STYLE,
        CONTACT_HISTORY_STYLE,
        &[dnum as f64, maxtouch as f64],
    ));
    peratom_fixes.push(PerAtomFix {
        id: CONTACT_HISTORY_STYLE.into(),
        style: CONTACT_HISTORY_STYLE.into(),
        max_size: 0,
    });

    if half_step {
        peratom_fixes.push(PerAtomFix {
            id: HALF_STEP_ID.into(),
            style: HALF_STEP_STYLE.into(),
            max_size: HALF_STEP_VALUES + 1,
        });
    }
    // the coupling forces of the next interval, as LIGGGHTS's coupling fixes save them
    if sim.coupling().is_active() {
        for (id, width) in COUPLING_BLOCKS {
            global_fixes.push(FixState::from_values(
                id,
                PROPERTY_ATOM_STYLE,
                &[width as f64],
            ));
            peratom_fixes.push(PerAtomFix {
                id: id.into(),
                style: PROPERTY_ATOM_STYLE.into(),
                max_size: width + 1,
            });
        }
    }
    // the temperatures and heat flows, as LIGGGHTS's heat fixes save them
    if sim.heat().is_some() {
        for id in HEAT_BLOCKS {
            global_fixes.push(FixState::from_values(id, PROPERTY_ATOM_STYLE, &[1.0]));
            peratom_fixes.push(PerAtomFix {
                id: id.into(),
                style: PROPERTY_ATOM_STYLE.into(),
                max_size: 2,
            });
        }
    }
    (global_fixes, peratom_fixes)
}

/// Every particle's record, with its data for the per-atom blocks of [`fix_blocks`] (same
/// order): wall histories, pair contacts (`contacts`), half step, coupling.
fn atom_records(
    sim: &Simulation,
    contacts: Vec<Vec<Contact>>,
    half_step: Option<&HalfStep>,
) -> Vec<AtomRecord> {
    let p = &sim.particles;
    let walls = sim.walls();
    let nw = walls.len();
    let coupling = sim.coupling();
    let wall_hist = sim.wall_history();
    (0..p.len())
        .zip(contacts)
        .map(|(i, cs)| {
            let mut fix_data: Vec<FixAtomData> = walls
                .iter()
                .enumerate()
                .map(|(w, wall)| {
                    FixAtomData::Values(from_history(
                        &wall_hist[i * nw + w],
                        history_len(&wall.model),
                    ))
                })
                .collect();
            fix_data.push(FixAtomData::Contacts(cs));
            if let Some(h) = half_step {
                let c = h.coupling.get(i).copied().unwrap_or_else(V3::zeros);
                let values = [h.v[i], h.omega[i], h.force[i], h.torque[i], c]
                    .iter()
                    .flat_map(|x| [x[0], x[1], x[2]])
                    .collect();
                fix_data.push(FixAtomData::Values(values));
            }
            if coupling.is_active() {
                let (f, u) = (coupling.f_ext[i], coupling.u_f[i]);
                fix_data.push(FixAtomData::Values(vec![f[0], f[1], f[2]]));
                fix_data.push(FixAtomData::Values(vec![coupling.beta[i]]));
                fix_data.push(FixAtomData::Values(vec![u[0], u[1], u[2]]));
            }
            if let Some(h) = sim.heat() {
                fix_data.push(FixAtomData::Values(vec![h.temp[i]]));
                fix_data.push(FixAtomData::Values(vec![h.flux[i]]));
            }
            AtomRecord {
                x: p.x[i].into(),
                tag: p.id[i],
                atom_type: p.atom_type[i],
                mask: 1,
                image: pack_image(p.image[i]),
                v: p.v[i].into(),
                radius: p.radius[i],
                rmass: p.mass[i],
                density: p.density[i],
                omega: p.omega[i].into(),
                fix_data,
            }
        })
        .collect()
}

/// `write_restart NAME`: writes the state to NAME (`*` → the step; missing directories are
/// created). Returns the path written and warnings (particles LIGGGHTS would not place in the
/// box it reads).
pub fn write(sim: &Simulation, name: &str, workdir: &Path) -> Res<(PathBuf, Vec<String>)> {
    if name.contains('%') {
        return Err("restart files split per process (`%` in the name) are not supported".into());
    }
    let path = workdir.join(output_name(name, sim.step()));
    let f = restart_file(sim);
    let outside = f
        .atoms
        .iter()
        .filter(|a| (0..3).any(|k| !(a.x[k] >= f.header.lo[k] && a.x[k] < f.header.hi[k])))
        .count();
    let mut warnings = Vec::new();
    if outside > 0 {
        warnings.push(format!(
            "write_restart {}: {outside} particles lie outside the box [lo, hi) of the file; \
             LIGGGHTS reading it would not place them",
            path.display()
        ));
    }
    rs::write_restart_file(&path, &f)
        .map_err(|e| format!("cannot write restart file {}: {e}", path.display()))?;
    Ok((path, warnings))
}
