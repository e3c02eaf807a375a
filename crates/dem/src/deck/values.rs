//! What a running deck can name, answered in one place for thermo columns, equal-style
//! variables and `fix print`: thermo keywords, computes, fix vectors, variables and per-atom
//! values by tag.
//!
//! - keywords: `step`, `atoms`, `ke` (Σ ½m|v|², J), `cpu` (wall s since the run began), `time`
//!   (simulated s), `dt` (s), `vol` (box volume, m³, shrink-wrapped faces following the
//!   particles);
//! - computes (`compute ID all STYLE …`): `erotate/sphere` (Σ ½I|ω|², J, a scalar), `com`
//!   (centre of mass, m, a 3-vector), `reduce sum|min|max|ave INPUT…` over the atoms' values
//!   ([`AtomValue`] names: `x vx fx f_dragforce[k]` …; a scalar for one input, a vector for
//!   several; `update_on_run_end yes|no` and `replace` are accepted); any other style is
//!   accepted and cannot be evaluated (a thermo column of it stays blank);
//! - fixes: `f_ID[1..3]` of `fix ID all couple/cfd/force[/implicit]`, the total coupling force
//!   of the last step (N, [`Simulation::coupling_force_total`]); `f_ID[1..3]` of `fix ID all
//!   mesh/surface/stress`, the force of the particles on the surface at the last force
//!   evaluation (N, [`Simulation::mesh_surface_force`]; its torque `[4..6]` and reference point
//!   `[7..9]` are not computed);
//! - `f_ID` of `fix ID all heat/gran` (and of its equation `ste_heattransfer`): Σ m c T over the
//!   particles (J, [`Simulation::heat_energy`]; not divided by `thermo_modify norm yes`: LIGGGHTS's
//!   fix is not extensive);
//! - `v_name` (equal-style or numeric variables) and `name[tag]` (an atom's value, e.g. `vx[1]`).
//!
//! `thermo_modify norm yes` divides the extensive ones (`ke`, `erotate/sphere`, `reduce sum`,
//! the coupling force) by the number of atoms, as LAMMPS does.

use std::collections::HashMap;

use liggghts_deck::expr::Ref;
use liggghts_deck::Variables;

use crate::atom_value::{self, AtomValue};
use crate::sim::Simulation;

type Res<T> = Result<T, String>;

/// The thermo keywords [`Values`] computes.
pub const KEYWORDS: &[&str] = &["step", "atoms", "ke", "cpu", "time", "dt", "vol"];

/// How `compute reduce` combines the atoms' values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReduceOp {
    /// Σ.
    Sum,
    /// Minimum.
    Min,
    /// Maximum.
    Max,
    /// Mean over the atoms.
    Ave,
}

/// A compute style.
#[derive(Debug, Clone, PartialEq)]
pub enum Compute {
    /// `erotate/sphere`.
    RotationalEnergy,
    /// `com`.
    CentreOfMass,
    /// `reduce MODE INPUT…`.
    Reduce {
        /// The combination.
        op: ReduceOp,
        /// The per-atom inputs.
        inputs: Vec<AtomValue>,
    },
    /// A style foamgrain does not compute (its name).
    Unsupported(String),
}

impl Compute {
    /// How many values it has: `None` for a scalar, `Some(n)` for a vector of n.
    fn vector_len(&self) -> Option<usize> {
        match self {
            Compute::RotationalEnergy => None,
            Compute::CentreOfMass => Some(3),
            Compute::Reduce { inputs, .. } if inputs.len() == 1 => None,
            Compute::Reduce { inputs, .. } => Some(inputs.len()),
            Compute::Unsupported(_) => None,
        }
    }
}

/// The computes and the coupling force fixes a deck defined.
#[derive(Debug, Clone, Default)]
pub struct Registry {
    computes: HashMap<String, Compute>,
    force_fixes: Vec<String>,
    mesh_stress_fixes: Vec<String>,
    /// `insert/rate/region` and `insert/stream` fixes: their vector is (particles, mass)
    /// inserted so far.
    insert_fixes: Vec<String>,
    /// `heat/gran` fixes: their scalar is Σ m c T, their per-atom vector the temperature.
    heat_fixes: Vec<String>,
    /// Whether a fix made the heat state (`heat/gran` or `couple/cfd/convection`).
    heat: bool,
    /// Whether the deck has `couple/cfd` (which `couple/cfd/convection` needs).
    cfd: bool,
}

/// The id LIGGGHTS gives the transport equation a heat fix creates.
pub const HEAT_EQUATION_ID: &str = "ste_heattransfer";

/// Whether a name can be evaluated.
#[derive(Debug, Clone, PartialEq)]
pub enum Support {
    /// Computed.
    Yes,
    /// Known, but foamgrain does not compute it (why).
    Blank(String),
}

impl Registry {
    /// `compute ID GROUP STYLE …`.
    pub fn define_compute(&mut self, w: &[String]) -> Res<()> {
        let (Some(id), Some(group), Some(style)) = (w.get(1), w.get(2), w.get(3)) else {
            return Err("usage: compute ID GROUP STYLE …".into());
        };
        let compute = match style.as_str() {
            "erotate/sphere" | "com" | "reduce" if group != "all" => {
                return Err(format!(
                    "compute {style}: only the group `all` is supported"
                ))
            }
            "erotate/sphere" => Compute::RotationalEnergy,
            "com" => Compute::CentreOfMass,
            "reduce" => {
                let c = reduce(&w[4..])?;
                if let Compute::Reduce { inputs, .. } = &c {
                    if !self.heat && inputs.iter().any(|v| v.needs_heat()) {
                        return Err("compute reduce: the heat values (f_Temp, f_heatFlux, \
                                    f_convectiveHeatFlux) need a heat fix defined before \
                                    (heat/gran or couple/cfd/convection)"
                            .into());
                    }
                }
                c
            }
            s => Compute::Unsupported(s.to_owned()),
        };
        self.computes.insert(id.clone(), compute);
        Ok(())
    }

    /// `uncompute ID`.
    pub fn remove_compute(&mut self, id: &str) -> Res<()> {
        self.computes
            .remove(id)
            .map(|_| ())
            .ok_or_else(|| format!("uncompute: no compute `{id}`"))
    }

    /// Records `fix ID all couple/cfd/force[/implicit]` (its vector is the coupling force).
    pub fn add_force_fix(&mut self, id: &str) {
        self.force_fixes.push(id.to_owned());
    }

    /// Records `fix ID all mesh/surface/stress` (its vector's first three elements are the
    /// force on the surface).
    pub fn add_mesh_stress_fix(&mut self, id: &str) {
        self.mesh_stress_fixes.push(id.to_owned());
    }

    /// Records `fix ID all insert/rate/region` (`f_ID[1]`, `f_ID[2]`: the number and the mass
    /// (kg) it inserted so far, as LIGGGHTS's insertion fixes give them).
    pub fn add_insert_fix(&mut self, id: &str) {
        self.insert_fixes.push(id.to_owned());
    }

    /// Records `fix ID all heat/gran` (`f_ID`: Σ m c T; `f_ID[0]` in dumps: the temperature).
    pub fn add_heat_fix(&mut self, id: &str) {
        self.heat_fixes.push(id.to_owned());
        self.heat = true;
    }

    /// Whether a `heat/gran` fix exists.
    pub fn has_heat_fix(&self) -> bool {
        !self.heat_fixes.is_empty()
    }

    /// Records `fix ID all couple/cfd/convection` (it makes the heat state too).
    pub fn add_convection_fix(&mut self) {
        self.heat = true;
    }

    /// Records `fix ID all couple/cfd`.
    pub fn add_cfd_fix(&mut self) {
        self.cfd = true;
    }

    /// Whether the deck has `couple/cfd`.
    pub fn has_cfd_fix(&self) -> bool {
        self.cfd
    }

    /// Whether a heat fix exists (`f_Temp`, `f_heatFlux` then exist).
    pub fn has_heat(&self) -> bool {
        self.heat
    }

    /// The ids whose per-atom vector is the temperature: the `heat/gran` fixes and, once a
    /// heat fix exists, [`HEAT_EQUATION_ID`].
    pub fn temperature_fixes(&self) -> Vec<String> {
        let mut ids = self.heat_fixes.clone();
        if self.heat {
            ids.push(HEAT_EQUATION_ID.to_owned());
        }
        ids
    }

    /// Whether `id` names a fix whose scalar is Σ m c T.
    fn is_heat_scalar(&self, id: &str) -> bool {
        self.heat_fixes.iter().any(|f| f == id) || (self.heat && id == HEAT_EQUATION_ID)
    }

    /// Whether the deck has a coupling force fix (which makes `f_dragforce` exist).
    pub fn has_force_fix(&self) -> bool {
        !self.force_fixes.is_empty()
    }

    /// Checks a name before a run: an error for what LIGGGHTS would refuse (an undefined
    /// compute or variable, an index out of range), [`Support::Blank`] for what foamgrain does
    /// not compute.
    pub fn check(&self, r: Ref, vars: &Variables) -> Res<Support> {
        match r {
            Ref::Keyword(k) if KEYWORDS.contains(&k) => Ok(Support::Yes),
            Ref::Keyword(k) => Ok(Support::Blank(format!(
                "thermo keyword `{k}` is not computed by the native DEM (computed: {})",
                KEYWORDS.join(" ")
            ))),
            Ref::Variable(n) if vars.contains(n) => Ok(Support::Yes),
            Ref::Variable(n) => Err(format!("variable `{n}` is not defined")),
            Ref::Compute(id, index) => {
                let c = self
                    .computes
                    .get(id)
                    .ok_or_else(|| format!("{r}: no compute `{id}`"))?;
                if let Compute::Unsupported(s) = c {
                    return Ok(Support::Blank(format!(
                        "{r}: compute style `{s}` is not computed by the native DEM \
                         (erotate/sphere, com, reduce)"
                    )));
                }
                check_index(r, c.vector_len(), index)?;
                Ok(Support::Yes)
            }
            Ref::Fix(id, index) if self.force_fixes.iter().any(|f| f == id) => {
                check_index(r, Some(3), index)?;
                Ok(Support::Yes)
            }
            Ref::Fix(id, index) if self.mesh_stress_fixes.iter().any(|f| f == id) => {
                check_index(r, Some(9), index)?;
                match index {
                    Some(1..=3) => Ok(Support::Yes),
                    _ => Ok(Support::Blank(format!(
                        "{r}: of mesh/surface/stress the native DEM computes the force [1..3] only"
                    ))),
                }
            }
            Ref::Fix(id, index) if self.insert_fixes.iter().any(|f| f == id) => {
                check_index(r, Some(2), index)?;
                Ok(Support::Yes)
            }
            Ref::Fix(id, index) if self.is_heat_scalar(id) => {
                check_index(r, None, index)?;
                Ok(Support::Yes)
            }
            Ref::Fix(..) => Ok(Support::Blank(format!(
                "{r}: the native DEM gives fix values only for couple/cfd/force, \
                 mesh/surface/stress, insert/rate/region, insert/stream and heat/gran fixes"
            ))),
            Ref::Atom(name, _) => match AtomValue::parse(name) {
                Some(_) => Ok(Support::Yes),
                None => Err(format!(
                    "{r}: unknown per-atom value `{name}` ({})",
                    atom_value::NAMES
                )),
            },
        }
    }
}

fn check_index(r: Ref, len: Option<usize>, index: Option<usize>) -> Res<()> {
    match (len, index) {
        (None, None) => Ok(()),
        (Some(n), Some(i)) if i <= n => Ok(()),
        (None, Some(_)) => Err(format!("{r}: a scalar has no index")),
        (Some(n), None) => Err(format!("{r}: a vector of {n}, name an element [1..{n}]")),
        (Some(n), Some(_)) => Err(format!("{r}: index out of 1..{n}")),
    }
}

/// `reduce [update_on_run_end yes|no] MODE INPUT… [replace …]`.
fn reduce(w: &[String]) -> Res<Compute> {
    let mut k = 0;
    if w.first().map(String::as_str) == Some("update_on_run_end") {
        match w.get(1).map(String::as_str) {
            Some("yes" | "no") => k = 2,
            o => {
                return Err(format!(
                    "compute reduce update_on_run_end `{}` (yes/no expected)",
                    o.unwrap_or("")
                ))
            }
        }
    }
    let op = match w.get(k).map(String::as_str) {
        Some("sum") => ReduceOp::Sum,
        Some("min") => ReduceOp::Min,
        Some("max") => ReduceOp::Max,
        Some("ave") => ReduceOp::Ave,
        o => {
            return Err(format!(
                "compute reduce mode `{}` is not supported (sum, min, max, ave)",
                o.unwrap_or("")
            ))
        }
    };
    let mut inputs = Vec::new();
    for name in w[k + 1..].iter().take_while(|n| n.as_str() != "replace") {
        inputs.push(AtomValue::parse(name).ok_or_else(|| {
            format!(
                "compute reduce input `{name}` is not supported ({})",
                atom_value::NAMES
            )
        })?);
    }
    if inputs.is_empty() {
        return Err("compute reduce needs at least one input".into());
    }
    Ok(Compute::Reduce { op, inputs })
}

/// Evaluates names against a simulation's current state.
pub struct Values<'a> {
    /// The simulation.
    pub sim: &'a Simulation,
    /// Computes and fixes.
    pub registry: &'a Registry,
    /// The variables.
    pub vars: &'a Variables,
    /// Wall seconds since the run began (`cpu`).
    pub cpu: f64,
    /// `thermo_modify norm yes`.
    pub norm: bool,
}

impl Values<'_> {
    fn per_atom(&self) -> f64 {
        let n = self.sim.particles.len();
        if self.norm && n > 0 {
            1.0 / n as f64
        } else {
            1.0
        }
    }

    /// The value of `r` now.
    pub fn resolve(&self, r: Ref) -> Res<f64> {
        let sim = self.sim;
        let p = &sim.particles;
        match r {
            Ref::Keyword(k) => match k {
                "step" => Ok(sim.step() as f64),
                "atoms" => Ok(p.len() as f64),
                "ke" => Ok(p.translational_energy() * self.per_atom()),
                "cpu" => Ok(self.cpu),
                "time" => Ok(sim.time()),
                "dt" => Ok(sim.dt()),
                "vol" => {
                    let b = sim.sim_box().dump_bounds(&p.x);
                    Ok((0..3).map(|k| b.hi[k] - b.lo[k]).product())
                }
                other => Err(format!(
                    "thermo keyword `{other}` is not computed by the native DEM (computed: {})",
                    KEYWORDS.join(" ")
                )),
            },
            Ref::Variable(n) => self.vars.number(n, &|r| self.resolve(r)),
            Ref::Compute(id, index) => {
                let c = self
                    .registry
                    .computes
                    .get(id)
                    .ok_or_else(|| format!("{r}: no compute `{id}`"))?;
                check_index(r, c.vector_len(), index)?;
                let i = index.map_or(0, |i| i - 1);
                match c {
                    Compute::RotationalEnergy => Ok(p.rotational_energy() * self.per_atom()),
                    Compute::CentreOfMass => {
                        let m: f64 = p.mass.iter().sum();
                        let mx: f64 = (0..p.len()).map(|a| p.mass[a] * p.x[a][i]).sum();
                        if m > 0.0 {
                            Ok(mx / m)
                        } else {
                            Ok(0.0)
                        }
                    }
                    Compute::Reduce { op, inputs } => {
                        let v = inputs[i];
                        let (c, h) = (sim.coupling(), sim.heat());
                        let vals = (0..p.len()).map(|a| v.get(p, c, h, a));
                        Ok(match op {
                            ReduceOp::Sum => vals.sum::<f64>() * self.per_atom(),
                            ReduceOp::Min => vals.fold(f64::INFINITY, f64::min),
                            ReduceOp::Max => vals.fold(f64::NEG_INFINITY, f64::max),
                            ReduceOp::Ave if p.is_empty() => 0.0,
                            ReduceOp::Ave => vals.sum::<f64>() / p.len() as f64,
                        })
                    }
                    Compute::Unsupported(s) => Err(format!(
                        "{r}: compute style `{s}` is not computed by the native DEM"
                    )),
                }
            }
            Ref::Fix(id, Some(i @ 1..=3))
                if self.registry.mesh_stress_fixes.iter().any(|f| f == id) =>
            {
                let f = sim.mesh_surface_force(id).unwrap_or_default();
                Ok(f[i - 1] * self.per_atom())
            }
            Ref::Fix(id, index) if self.registry.insert_fixes.iter().any(|f| f == id) => {
                check_index(r, Some(2), index)?;
                let ins = sim.rate_insertions().iter().find(|f| f.spec().name == id);
                let stats = ins.map(|f| f.stats()).unwrap_or_default();
                Ok(match index {
                    Some(1) => stats.inserted as f64,
                    _ => stats.mass,
                })
            }
            Ref::Fix(id, index) if self.registry.is_heat_scalar(id) => {
                check_index(r, None, index)?;
                Ok(sim.heat_energy().unwrap_or(0.0))
            }
            Ref::Fix(id, index) => {
                if !self.registry.force_fixes.iter().any(|f| f == id) {
                    return Err(format!(
                        "{r}: the native DEM gives fix values only for couple/cfd/force fixes"
                    ));
                }
                check_index(r, Some(3), index)?;
                let i = index.expect("checked: a vector element") - 1;
                Ok(sim.coupling_force_total()[i] * self.per_atom())
            }
            Ref::Atom(name, tag) => {
                let v = AtomValue::parse(name).ok_or_else(|| {
                    format!(
                        "{r}: unknown per-atom value `{name}` ({})",
                        atom_value::NAMES
                    )
                })?;
                let a =
                    p.id.iter()
                        .position(|&t| t == tag)
                        .ok_or_else(|| format!("{r}: there is no atom with tag {tag}"))?;
                Ok(v.get(p, sim.coupling(), sim.heat(), a))
            }
        }
    }

    /// `text` with its variables substituted now (`fix print`).
    pub fn substitute(&self, text: &str) -> Res<String> {
        self.vars.substitute(text, &|r| self.resolve(r))
    }
}
