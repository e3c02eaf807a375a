//! Boundary conditions of the velocity U and the kinematic pressure p, read from a field file's
//! `boundaryField` (OpenFOAM names and semantics), evaluated to boundary-face values, and
//! expressed as the linear coefficients the discretisation needs:
//! face value `φ_b = vi ⊙ φ_P + vb` and normal gradient `snGrad_b = dc (φ_b − φ_P)`
//! (dc = 1/|n̂·(C_f − C_P)|, [`crate::FvGeometry::delta_coeff`]).
//!
//! Supported: U — `fixedValue`, `uniformFixedValue` (`constant` or `table` of (time value)
//! pairs, linear interpolation, clamped outside like OpenFOAM's default `outOfBounds clamp`),
//! CFDEMcoupling's `uniformFixedValueVoidfraction` (the same series divided by the face's
//! voidage, [`VelocityBc::UniformFixedValueVoidfraction`]), `noSlip`, `slip`, `zeroGradient`, `inletOutlet`; p — `fixedValue`, `uniformFixedValue`,
//! `zeroGradient`, `fixedFluxPressure`, `totalPressure` (incompressible: p = p0 − ½|U|² on
//! inflow faces, p0 on outflow faces); both — `empty`, `symmetryPlane`/`symmetry` (slip for U,
//! zeroGradient for p), `cyclic` on the patches of a translational cyclic pair (whose faces
//! the solver holds as internal faces, [`crate::cyclic`]) and `calculated` is refused. Anything else is an error naming the file and
//! `boundaryField.<patch>.type`.

use crate::error::{FvError, Result};
use crate::geometry::{FvGeometry, V3};
use foam::{Dict, Item, Value};
use std::path::Path;

/// A value that may vary in time: constant or a piecewise-linear table of (t, value).
#[derive(Clone, Debug, PartialEq)]
pub enum TimeSeries<T> {
    /// The same value at all times.
    Constant(T),
    /// (time s, value) pairs in increasing time; clamped outside the range.
    Table(Vec<(f64, T)>),
}

impl<T: Copy + crate::fvc::Value> TimeSeries<T> {
    /// The value at time `t` (linear interpolation between table rows).
    pub fn at(&self, t: f64) -> T {
        match self {
            TimeSeries::Constant(v) => *v,
            TimeSeries::Table(rows) => {
                let i = rows.partition_point(|r| r.0 <= t);
                if i == 0 {
                    rows[0].1
                } else if i == rows.len() {
                    rows[rows.len() - 1].1
                } else {
                    let (t0, v0) = rows[i - 1];
                    let (t1, v1) = rows[i];
                    let s = (t - t0) / (t1 - t0);
                    T::axpy(v0, s, T::minus(v1, v0))
                }
            }
        }
    }
}

/// Velocity boundary condition of one patch.
#[derive(Clone, Debug, PartialEq)]
pub enum VelocityBc {
    /// Prescribed value per face (m/s).
    FixedValue(Vec<V3>),
    /// The same prescribed value on every face, possibly varying in time.
    UniformFixedValue(TimeSeries<V3>),
    /// CFDEMcoupling's `uniformFixedValueVoidfraction` (`libfiniteVolumeCFDEM`, both
    /// CFDEMcoupling-PUBLIC and -PFM: `src/finiteVolume/fields/fvPatchFields/derived/
    /// uniformFixedValueVoidfraction/uniformFixedValueVoidfractionFvPatchField.C`,
    /// `updateCoeffs`): U_b = u(t)/ε_b (m/s), u(t) the `uniformValue` series (m/s, a
    /// superficial velocity) and ε_b the face value of the field `voidfraction` (its fixed value,
    /// else the owner cell's). The inflow flux ε_b U_b·S is then u(t)·S whatever the voidage at
    /// the inlet. CFDEM's condition holds u(t) undivided from its construction until its first
    /// `updateCoeffs` (the start's `createPhi`); foamgrain divides from the start, which is the
    /// same where the start voidage at the patch is 1 (CFDEM's cases start from ε = 1).
    UniformFixedValueVoidfraction(TimeSeries<V3>),
    /// U = 0.
    NoSlip,
    /// Zero normal component, zero normal gradient of the tangential components.
    Slip,
    /// Zero normal gradient.
    ZeroGradient,
    /// zeroGradient where the flux leaves the domain, `inletValue` (per face) where it enters.
    InletOutlet(Vec<V3>),
    /// Faces of an `empty` patch (2-D): not part of the equations.
    Empty,
    /// A `cyclic` patch: its faces are internal faces of the solver.
    Cyclic,
}

/// Pressure boundary condition of one patch (kinematic pressure, m²/s²).
#[derive(Clone, Debug, PartialEq)]
pub enum PressureBc {
    /// Prescribed value per face.
    FixedValue(Vec<f64>),
    /// The same value on every face, possibly varying in time.
    UniformFixedValue(TimeSeries<f64>),
    /// Zero normal gradient.
    ZeroGradient,
    /// The normal gradient that makes the flux equal the one of the velocity condition.
    FixedFluxPressure,
    /// p0 − ½|U|² on inflow faces, p0 on outflow faces.
    TotalPressure(Vec<f64>),
    /// Faces of an `empty` patch.
    Empty,
    /// A `cyclic` patch: its faces are internal faces of the solver.
    Cyclic,
}

impl VelocityBc {
    /// True when the boundary flux is fixed by U (the pressure equation gets no flux from p
    /// there and `phiHbyA` takes ε U_b·S): every condition except zeroGradient and the outflow
    /// part of inletOutlet.
    pub fn fixes_flux(&self) -> bool {
        !matches!(self, VelocityBc::ZeroGradient | VelocityBc::InletOutlet(_))
    }
}

impl VelocityBc {
    /// True when the condition prescribes the value (OpenFOAM's `fixesValue`): fixedValue,
    /// uniformFixedValue, uniformFixedValueVoidfraction, noSlip.
    pub fn fixes_value(&self) -> bool {
        matches!(
            self,
            VelocityBc::FixedValue(_)
                | VelocityBc::UniformFixedValue(_)
                | VelocityBc::UniformFixedValueVoidfraction(_)
                | VelocityBc::NoSlip
        )
    }
}

impl PressureBc {
    /// True when the condition prescribes the value (a Dirichlet condition of the pressure
    /// equation, which removes its null space).
    pub fn fixes_value(&self) -> bool {
        matches!(
            self,
            PressureBc::FixedValue(_)
                | PressureBc::UniformFixedValue(_)
                | PressureBc::TotalPressure(_)
        )
    }
}

/// The patch groups of a patch (`inGroups N(a b)` in the boundary file, plus its type for
/// constraint types), for boundaryField lookup.
fn groups(mesh: &foam::PolyMesh, patch: usize) -> Vec<String> {
    let p = &mesh.boundary[patch];
    let mut g: Vec<String> = p
        .extra
        .iter()
        .filter(|(k, _)| k == "inGroups")
        .flat_map(|(_, v)| {
            let inner = v
                .split_once('(')
                .map_or("", |(_, r)| r.trim_end_matches(')'));
            inner
                .split_whitespace()
                .map(|s| s.trim_end_matches(')').to_string())
                .collect::<Vec<_>>()
        })
        .collect();
    g.push(p.patch_type.clone());
    g
}

/// Reads a patch value: `uniform X` or `nonuniform List<T> N(…)` with `n` entries.
fn read_value<T: Clone>(
    items: &[Item],
    n: usize,
    one: impl Fn(&Item) -> Option<T>,
    list: impl Fn(&Item) -> Option<Vec<T>>,
) -> Option<Vec<T>> {
    match items.first().and_then(Item::as_word) {
        Some("uniform") if items.len() == 2 => one(&items[1]).map(|v| vec![v; n]),
        Some("nonuniform") => items.get(2).and_then(&list).filter(|v| v.len() == n),
        _ => None,
    }
}

/// Reads `uniformValue`: `constant X`, `table ((t X) …)` or a bare `X`.
fn read_series<T: Copy>(items: &[Item], one: impl Fn(&Item) -> Option<T>) -> Option<TimeSeries<T>> {
    match items {
        [x] => one(x).map(TimeSeries::Constant),
        [Item::Word(w), x] if w == "constant" => one(x).map(TimeSeries::Constant),
        [Item::Word(w), Item::List(rows)] if w == "table" => {
            let mut out = Vec::with_capacity(rows.len());
            for r in rows {
                let Item::List(pair) = r else { return None };
                let [t, v] = pair.as_slice() else { return None };
                out.push((t.as_f64()?, one(v)?));
            }
            if out.is_empty() || out.windows(2).any(|w| w[1].0 <= w[0].0) {
                return None;
            }
            Some(TimeSeries::Table(out))
        }
        _ => None,
    }
}

/// A vector of a dictionary entry (`(x y z)`).
pub(crate) fn as_v3(i: &Item) -> Option<V3> {
    i.as_vector().map(V3::from)
}

pub(crate) fn vec_list(i: &Item) -> Option<Vec<V3>> {
    match i {
        Item::Vectors(v) => Some(mesh::v3::from_arrays(v)),
        Item::List(l) => l.iter().map(as_v3).collect(),
        _ => None,
    }
}

/// The entry of `patch` in `boundaryField`, with the patch's kind of error context.
pub(crate) struct PatchEntry<'a> {
    pub(crate) file: &'a Path,
    pub(crate) name: String,
    pub(crate) dict: &'a Dict,
    pub(crate) n: usize,
}

impl PatchEntry<'_> {
    pub(crate) fn err(&self, key: &str, msg: impl Into<String>) -> FvError {
        FvError::setting(self.file, format!("boundaryField.{}.{key}", self.name), msg)
    }

    pub(crate) fn kind(&self) -> Result<&str> {
        self.dict.word("type").map_err(|e| self.err("type", e.0))
    }

    pub(crate) fn stream(&self, key: &str) -> Result<&[Item]> {
        self.dict.stream(key).map_err(|e| self.err(key, e.0))
    }

    pub(crate) fn values<T: Clone>(
        &self,
        key: &str,
        one: impl Fn(&Item) -> Option<T>,
        list: impl Fn(&Item) -> Option<Vec<T>>,
    ) -> Result<Vec<T>> {
        read_value(self.stream(key)?, self.n, one, list).ok_or_else(|| {
            self.err(
                key,
                format!(
                    "expected `uniform X` or `nonuniform List N(…)` with {} values",
                    self.n
                ),
            )
        })
    }

    pub(crate) fn series<T: Copy>(
        &self,
        one: impl Fn(&Item) -> Option<T>,
    ) -> Result<TimeSeries<T>> {
        read_series(self.stream("uniformValue")?, one).ok_or_else(|| {
            self.err(
                "uniformValue",
                "expected `constant X`, `table ((t X) …)` with increasing times, or `X`",
            )
        })
    }

    pub(crate) fn unsupported(&self, t: &str, supported: &str) -> FvError {
        self.err(
            "type",
            format!("`{t}` is not supported (supported: {supported})"),
        )
    }
}

/// For every patch of `g`, the entry of `field` (a parsed `volScalarField`/`volVectorField` file
/// at `file`) that applies to it, in patch order.
fn patch_entries<'a>(
    file: &'a Path,
    field: &'a foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
) -> Result<Vec<PatchEntry<'a>>> {
    let bf = field.boundary();
    g.patches
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let e = bf.resolve(&p.name, &groups(mesh, i)).ok_or_else(|| {
                FvError::setting(
                    file,
                    format!("boundaryField.{}", p.name),
                    "no entry for this patch",
                )
            })?;
            let Value::Dict(dict) = &e.value else {
                return Err(FvError::setting(
                    file,
                    format!("boundaryField.{}", p.name),
                    "expected a dictionary",
                ));
            };
            if p.patch_type.starts_with("processor") {
                return Err(FvError::setting(
                    file,
                    format!("boundaryField.{}", p.name),
                    format!(
                        "patch type `{}` is not supported by the native solver",
                        p.patch_type
                    ),
                ));
            }
            Ok(PatchEntry {
                file,
                name: p.name.clone(),
                dict,
                n: p.faces.len(),
            })
        })
        .collect()
}

const U_SUPPORTED: &str = "fixedValue, uniformFixedValue, uniformFixedValueVoidfraction, \
                           noSlip, slip, zeroGradient, inletOutlet, empty, symmetryPlane, symmetry, cyclic";
const P_SUPPORTED: &str = "fixedValue, uniformFixedValue, zeroGradient, fixedFluxPressure, \
                           totalPressure, empty, symmetryPlane, symmetry, cyclic";

/// Reads one condition per patch with `parse` (given the entry and its `type`), checking that
/// `empty` patches and `empty` conditions go together, and so do `cyclic` patches and
/// `cyclic` conditions (as OpenFOAM requires of constraint patches): `parse` sees the type
/// `cyclic` only on a cyclic patch, whose faces are internal faces of the solver.
pub(crate) fn read_all<T>(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
    parse: impl Fn(&PatchEntry<'_>, &str) -> Result<(T, bool)>,
) -> Result<Vec<T>> {
    patch_entries(file, field, mesh, g)?
        .into_iter()
        .zip(&g.patches)
        .map(|(e, p)| {
            let kind = e.kind()?;
            if (kind == "cyclic") != p.is_cyclic() {
                return Err(e.err(
                    "type",
                    if p.is_cyclic() {
                        format!("a `cyclic` patch needs the `cyclic` condition, not `{kind}`")
                    } else {
                        "the `cyclic` condition needs a `cyclic` patch".to_string()
                    },
                ));
            }
            let (bc, is_empty) = parse(&e, kind)?;
            check_empty(&e, p.is_empty(), is_empty)?;
            Ok(bc)
        })
        .collect()
}

/// Reads the velocity conditions of every patch from `U`'s boundaryField.
pub fn read_velocity(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
) -> Result<Vec<VelocityBc>> {
    read_all(file, field, mesh, g, |e, t| {
        let bc = match t {
            "fixedValue" => VelocityBc::FixedValue(e.values("value", as_v3, vec_list)?),
            "uniformFixedValue" => VelocityBc::UniformFixedValue(e.series(as_v3)?),
            "uniformFixedValueVoidfraction" => {
                VelocityBc::UniformFixedValueVoidfraction(e.series(as_v3)?)
            }
            "noSlip" => VelocityBc::NoSlip,
            "slip" | "symmetryPlane" | "symmetry" => VelocityBc::Slip,
            "zeroGradient" => VelocityBc::ZeroGradient,
            "inletOutlet" => VelocityBc::InletOutlet(e.values("inletValue", as_v3, vec_list)?),
            "empty" => VelocityBc::Empty,
            "cyclic" => VelocityBc::Cyclic,
            _ => return Err(e.unsupported(t, U_SUPPORTED)),
        };
        let empty = bc == VelocityBc::Empty;
        Ok((bc, empty))
    })
}

/// Reads the voidage boundary values of every patch from `voidfraction`'s boundaryField:
/// `fixedValue` gives ε per face (each in (0, 1]), `zeroGradient`/`calculated`/`slip`/
/// `symmetry`/`empty` mean "the owner cell's ε" (`None`). CFDEM cases set inlets and outlets
/// to `fixedValue 1`: the velocity there is then superficial (fluid without particles).
pub fn read_voidage(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
) -> Result<Vec<Option<Vec<f64>>>> {
    read_all(file, field, mesh, g, |e, t| match t {
        "fixedValue" => {
            let v = e.values("value", Item::as_f64, Item::as_f64_list)?;
            if let Some(bad) = v.iter().find(|x| !(**x > 0.0 && **x <= 1.0)) {
                return Err(e.err("value", format!("voidage {bad} is not in (0, 1]")));
            }
            Ok((Some(v), false))
        }
        "zeroGradient" | "calculated" | "slip" | "symmetryPlane" | "symmetry" | "cyclic" => {
            Ok((None, false))
        }
        "empty" => Ok((None, true)),
        _ => Err(e.unsupported(
            t,
            "fixedValue, zeroGradient, calculated, slip, symmetry, empty, cyclic",
        )),
    })
}

/// Reads the pressure conditions of every patch from `p`'s boundaryField.
pub fn read_pressure(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
) -> Result<Vec<PressureBc>> {
    // OpenFOAM's totalPressure reads `rho`/`psi` only when p is in Pa; with a kinematic p
    // (m²/s², what this solver and CFDEM's solvers use) it ignores them, and so does this
    let kinematic = match field.body.item("dimensions") {
        Ok(Item::Dims(d)) => {
            let d: Vec<f64> = d.iter().filter_map(Item::as_f64).collect();
            d.len() >= 3 && d[..3] == [0.0, 2.0, -2.0] && d[3..].iter().all(|&x| x == 0.0)
        }
        _ => false,
    };
    read_all(file, field, mesh, g, |e, t| {
        let bc = match t {
            "fixedValue" => {
                PressureBc::FixedValue(e.values("value", Item::as_f64, Item::as_f64_list)?)
            }
            "uniformFixedValue" => PressureBc::UniformFixedValue(e.series(Item::as_f64)?),
            "zeroGradient" | "symmetryPlane" | "symmetry" => PressureBc::ZeroGradient,
            "fixedFluxPressure" => PressureBc::FixedFluxPressure,
            "totalPressure" => {
                if !kinematic && e.dict.word("rho").is_ok_and(|r| r != "none") {
                    return Err(e.err(
                        "rho",
                        "only the kinematic form is supported: p in m²/s² (`dimensions [0 2 -2 \
                         0 0 0 0]`, where `rho` is ignored as OpenFOAM does) or `rho none;`",
                    ));
                }
                if !kinematic && e.dict.word("psi").is_ok_and(|r| r != "none") {
                    return Err(e.err("psi", "compressible totalPressure is not supported"));
                }
                PressureBc::TotalPressure(e.values("p0", Item::as_f64, Item::as_f64_list)?)
            }
            "empty" => PressureBc::Empty,
            "cyclic" => PressureBc::Cyclic,
            _ => return Err(e.unsupported(t, P_SUPPORTED)),
        };
        let empty = bc == PressureBc::Empty;
        Ok((bc, empty))
    })
}

/// The `value` entry of each `totalPressure` patch of `p` (`None` for other patches and where
/// the entry is absent). OpenFOAM v1912's totalPressure starts from its `value` when the file
/// has one (else from p0) and keeps it until the pressure equation first evaluates the
/// condition: the first momentum predictor of a run sees that value (a case started from rest
/// with `value uniform 0` sees no gradient at the inlet), and a written time keeps the value
/// the last corrector used.
pub fn read_total_pressure_values(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
) -> Result<Vec<Option<Vec<f64>>>> {
    read_all(file, field, mesh, g, |e, t| {
        let empty = t == "empty";
        if t != "totalPressure" || !e.dict.contains("value") {
            return Ok((None, empty));
        }
        Ok((
            Some(e.values("value", Item::as_f64, Item::as_f64_list)?),
            empty,
        ))
    })
}

fn check_empty(e: &PatchEntry<'_>, patch_empty: bool, bc_empty: bool) -> Result<()> {
    if patch_empty != bc_empty {
        return Err(e.err(
            "type",
            if patch_empty {
                "an `empty` patch needs the `empty` condition"
            } else {
                "the `empty` condition needs an `empty` patch"
            },
        ));
    }
    Ok(())
}

/// Boundary-face velocity values (m/s), one per boundary face, at time `t` given the cell
/// values, the boundary-face voidage `eps_b` (one per boundary face, for
/// uniformFixedValueVoidfraction) and the current face fluxes `phi` (for inletOutlet: inflow
/// where φ < 0).
pub fn eval_velocity(
    g: &FvGeometry,
    bcs: &[VelocityBc],
    t: f64,
    u: &[V3],
    eps_b: &[f64],
    phi: &[f64],
    out: &mut [V3],
) {
    for (p, bc) in g.patches.iter().zip(bcs) {
        let first = p.faces.start;
        let range = p.boundary_range(g.n_internal);
        // Each face on its own (in parallel on a large patch: a 2-D case's `empty` ones).
        crate::gather::each_mut(&mut out[range], |i, out| {
            let f = first + i;
            let b = f - g.n_internal;
            let up = u[g.owner[f] as usize];
            *out = match bc {
                VelocityBc::FixedValue(v) => v[i],
                VelocityBc::UniformFixedValue(s) => s.at(t),
                VelocityBc::UniformFixedValueVoidfraction(s) => s.at(t) / eps_b[b],
                VelocityBc::NoSlip => V3::zeros(),
                VelocityBc::Slip => {
                    let n = g.nhat(f);
                    up - (n.dot(&up) * n)
                }
                VelocityBc::ZeroGradient | VelocityBc::Empty | VelocityBc::Cyclic => up,
                VelocityBc::InletOutlet(v) => {
                    if phi[f] < 0.0 {
                        v[i]
                    } else {
                        up
                    }
                }
            };
        });
    }
}

/// The implicit part `vi` of the boundary value φ_b = vi ⊙ U_P + vb for each boundary face
/// (1 for zeroGradient-like faces, 1 − n_k² for slip, 0 for fixed values).
pub fn velocity_value_coeffs(g: &FvGeometry, bcs: &[VelocityBc], phi: &[f64]) -> Vec<V3> {
    let mut out = vec![V3::zeros(); g.n_boundary()];
    for (p, bc) in g.patches.iter().zip(bcs) {
        for f in p.faces.clone() {
            out[f - g.n_internal] = match bc {
                VelocityBc::ZeroGradient | VelocityBc::Empty => V3::repeat(1.0),
                VelocityBc::InletOutlet(_) if phi[f] >= 0.0 => V3::repeat(1.0),
                VelocityBc::Slip => {
                    let n = g.nhat(f);
                    V3::new(1.0 - n[0] * n[0], 1.0 - n[1] * n[1], 1.0 - n[2] * n[2])
                }
                _ => V3::zeros(),
            };
        }
    }
    out
}

/// Whether the velocity condition fixes the flux on each boundary face at this moment.
pub fn flux_fixed(g: &FvGeometry, bcs: &[VelocityBc], phi: &[f64]) -> Vec<bool> {
    let mut out = vec![false; g.n_boundary()];
    for (p, bc) in g.patches.iter().zip(bcs) {
        for f in p.faces.clone() {
            out[f - g.n_internal] = match bc {
                VelocityBc::InletOutlet(_) => phi[f] < 0.0,
                VelocityBc::Empty => false,
                other => other.fixes_flux(),
            };
        }
    }
    out
}

/// Boundary-face pressure values (m²/s²) at time `t`: prescribed values, p0 − ½|U_b|² on
/// totalPressure faces where φ < 0 (inflow; p0 elsewhere), and the owner value on
/// zeroGradient faces. fixedFluxPressure faces also get the owner value here (the solver
/// replaces it with the value of the flux-matching gradient once it has the predicted flux).
pub fn eval_pressure(
    g: &FvGeometry,
    bcs: &[PressureBc],
    t: f64,
    p: &[f64],
    u_b: &[V3],
    phi: &[f64],
    out: &mut [f64],
) {
    for (patch, bc) in g.patches.iter().zip(bcs) {
        let first = patch.faces.start;
        let range = patch.boundary_range(g.n_internal);
        // Each face on its own (in parallel on a large patch: a 2-D case's `empty` ones).
        crate::gather::each_mut(&mut out[range], |i, out| {
            let f = first + i;
            let b = f - g.n_internal;
            *out = match bc {
                PressureBc::FixedValue(v) => v[i],
                PressureBc::UniformFixedValue(s) => s.at(t),
                PressureBc::TotalPressure(p0) if phi[f] < 0.0 => p0[i] - 0.5 * u_b[b].dot(&u_b[b]),
                PressureBc::TotalPressure(p0) => p0[i],
                PressureBc::ZeroGradient
                | PressureBc::FixedFluxPressure
                | PressureBc::Empty
                | PressureBc::Cyclic => p[g.owner[f] as usize],
            };
        });
    }
}
