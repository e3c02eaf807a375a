//! Boundary conditions of the turbulence fields k (m²/s²), ε (m²/s³) and νt (m²/s), read from
//! their files' `boundaryField` with OpenFOAM v1912's names and meanings, and their linear
//! coefficients for the transport equations: face value φ_b = vi φ_P + vb and face normal
//! gradient dc (φ_b − φ_P) (the same form as [`crate::bc`] for U).
//!
//! Supported: `fixedValue`, `zeroGradient`, `inletOutlet` (`inletValue` where the flux enters,
//! φ < 0, zero gradient where it leaves: OpenFOAM's mixed condition with valueFraction
//! 1 − pos0(φ)), `calculated` (νt: the value of the formula, k/ε: refused as OpenFOAM would
//! need a value to solve), `kqRWallFunction` (k: zero gradient), `epsilonWallFunction` (ε:
//! wall-cell values from the log law, [`super::wall_functions`]), `nutkWallFunction` (νt from
//! the wall cell's k), `empty`, `symmetryPlane`/`symmetry` (zero gradient of a scalar),
//! `cyclic` (the patches of a cyclic pair, whose faces are internal faces of the solver).
//! Anything else is an error naming the file and `boundaryField.<patch>.type`.

use crate::bc::{read_all, PatchEntry};
use crate::error::Result;
use crate::geometry::FvGeometry;
use foam::Item;
use std::path::Path;

/// The log-law constants of a `nutkWallFunction` patch (OpenFOAM's defaults: Cmu 0.09,
/// κ 0.41, E 9.8; Launder & Spalding 1974), with what the wall functions derive from them
/// alone computed once ([`LogLaw::new`]) instead of at every wall face of every step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogLaw {
    cmu: f64,
    kappa: f64,
    e: f64,
    /// y⁺_lam of κ and E ([`super::wall_functions::y_plus_lam`]).
    y_plus_lam: f64,
    /// Cμ^¼ and Cμ^¾.
    cmu25: f64,
    cmu75: f64,
}

impl LogLaw {
    /// The law of Cμ, κ and E (all dimensionless).
    pub fn new(cmu: f64, kappa: f64, e: f64) -> LogLaw {
        LogLaw {
            cmu,
            kappa,
            e,
            y_plus_lam: super::wall_functions::y_plus_lam(kappa, e),
            cmu25: cmu.powf(0.25),
            cmu75: cmu.powf(0.75),
        }
    }

    /// Cμ (dimensionless).
    pub fn cmu(&self) -> f64 {
        self.cmu
    }

    /// The von Kármán constant κ (dimensionless).
    pub fn kappa(&self) -> f64 {
        self.kappa
    }

    /// The wall roughness constant E (dimensionless; 9.8 for a smooth wall).
    pub fn e(&self) -> f64 {
        self.e
    }

    /// y⁺ where the viscous sublayer meets the log law (dimensionless).
    pub fn y_plus_lam(&self) -> f64 {
        self.y_plus_lam
    }

    /// Cμ^¼ (dimensionless).
    pub fn cmu25(&self) -> f64 {
        self.cmu25
    }

    /// Cμ^¾ (dimensionless).
    pub fn cmu75(&self) -> f64 {
        self.cmu75
    }
}

impl Default for LogLaw {
    fn default() -> Self {
        LogLaw::new(0.09, 0.41, 9.8)
    }
}

/// The condition of a turbulence scalar on one patch.
#[derive(Clone, Debug, PartialEq)]
pub enum ScalarBc {
    /// Prescribed value per face.
    FixedValue(Vec<f64>),
    /// Zero normal gradient (also `kqRWallFunction`, `symmetryPlane`, `symmetry`).
    ZeroGradient,
    /// A prescribed normal gradient (the temperature's `fixedGradient`, [`crate::temperature`]),
    /// held per face as the face value's increment over the owner's, gradient/δ (δ the
    /// boundary face's delta coefficient, 1/(n̂·d), OpenFOAM v1912's patch `deltaCoeffs`).
    FixedGradient(Vec<f64>),
    /// `inletValue` per face where φ < 0, zero gradient elsewhere.
    InletOutlet(Vec<f64>),
    /// νt: the value of νt = Cμ k_b²/ε_b from the boundary values of k and ε.
    Calculated,
    /// ε: the wall-cell values of the log law; `low_re` is the `lowReCorrection` switch.
    EpsilonWallFunction {
        /// Use 2kν/y² and G = 0 in cells below y⁺_lam.
        low_re: bool,
    },
    /// νt: ν (y⁺κ/ln(E y⁺) − 1) above y⁺_lam, 0 below.
    NutkWallFunction(LogLaw),
    /// Faces of an `empty` patch.
    Empty,
    /// A `cyclic` patch: its faces are internal faces of the solver.
    Cyclic,
}

impl ScalarBc {
    /// The implicit part vi of the face value φ_b = vi φ_P + vb on a face with flux `phi`
    /// (1: the face takes the cell's value; 0: the face value is fixed).
    pub fn value_coeff(&self, phi: f64) -> f64 {
        match self {
            ScalarBc::ZeroGradient | ScalarBc::FixedGradient(_) | ScalarBc::Empty => 1.0,
            ScalarBc::InletOutlet(_) if phi >= 0.0 => 1.0,
            _ => 0.0,
        }
    }
}

impl ScalarBc {
    /// The fixed part vb of the face value φ_b = vi φ_P + vb on face `i` of the patch with flux
    /// `phi` (the increment of a fixed gradient, else the value where [`Self::value_coeff`] is
    /// 0); `current` is the face's present value (what a
    /// wall function or `calculated` face holds).
    pub fn fixed_part(&self, i: usize, phi: f64, current: f64) -> f64 {
        match self {
            ScalarBc::FixedValue(v) | ScalarBc::FixedGradient(v) => v[i],
            ScalarBc::InletOutlet(v) if phi < 0.0 => v[i],
            ScalarBc::InletOutlet(_) | ScalarBc::ZeroGradient | ScalarBc::Empty => 0.0,
            _ => current,
        }
    }
}

/// Which field a condition list belongs to (the conditions each may carry).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TurbulenceField {
    /// k.
    K,
    /// ε.
    Epsilon,
    /// νt.
    Nut,
}

impl TurbulenceField {
    fn supported(self) -> &'static str {
        match self {
            TurbulenceField::K => {
                "fixedValue, zeroGradient, inletOutlet, kqRWallFunction, empty, symmetryPlane, \
                 symmetry, cyclic"
            }
            TurbulenceField::Epsilon => {
                "fixedValue, zeroGradient, inletOutlet, epsilonWallFunction, empty, \
                 symmetryPlane, symmetry, cyclic"
            }
            TurbulenceField::Nut => {
                "calculated, fixedValue, zeroGradient, nutkWallFunction, empty, symmetryPlane, \
                 symmetry, cyclic"
            }
        }
    }
}

fn number(e: &PatchEntry<'_>, key: &str, default: f64) -> Result<f64> {
    match e.dict.stream(key) {
        Err(_) => Ok(default),
        Ok([x]) => x
            .as_f64()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| e.err(key, "expected a positive number")),
        Ok(_) => Err(e.err(key, "expected one number")),
    }
}

/// Reads the conditions of every patch of `field` (the parsed file at `file`) for the
/// turbulence field `which`. Wall functions need a `wall` patch, as in OpenFOAM.
pub fn read(
    file: &Path,
    field: &foam::VolField,
    mesh: &foam::PolyMesh,
    g: &FvGeometry,
    which: TurbulenceField,
) -> Result<Vec<ScalarBc>> {
    use TurbulenceField::{Epsilon, Nut, K};
    read_all(file, field, mesh, g, |e, t| {
        let is_wall = g
            .patch_index(&e.name)
            .is_some_and(|i| g.patches[i].patch_type == "wall");
        let wall_only = |name: &str| {
            if is_wall {
                Ok(())
            } else {
                Err(e.err("type", format!("`{name}` needs a patch of type `wall`")))
            }
        };
        let bc = match (t, which) {
            ("fixedValue", _) => {
                ScalarBc::FixedValue(e.values("value", Item::as_f64, Item::as_f64_list)?)
            }
            ("zeroGradient" | "symmetryPlane" | "symmetry", _) | ("kqRWallFunction", K) => {
                if t == "kqRWallFunction" {
                    wall_only(t)?;
                }
                ScalarBc::ZeroGradient
            }
            ("inletOutlet", K | Epsilon) => {
                ScalarBc::InletOutlet(e.values("inletValue", Item::as_f64, Item::as_f64_list)?)
            }
            ("calculated", Nut) => ScalarBc::Calculated,
            ("epsilonWallFunction", Epsilon) => {
                wall_only(t)?;
                let low_re = match e.dict.get("lowReCorrection") {
                    None => false,
                    Some(_) => e
                        .dict
                        .switch("lowReCorrection")
                        .map_err(|x| e.err("lowReCorrection", x.0))?,
                };
                ScalarBc::EpsilonWallFunction { low_re }
            }
            ("nutkWallFunction", Nut) => {
                wall_only(t)?;
                if e.dict.get("U").is_some() {
                    return Err(e.err("U", "a velocity other than U is not supported"));
                }
                ScalarBc::NutkWallFunction(LogLaw::new(
                    number(e, "Cmu", 0.09)?,
                    number(e, "kappa", 0.41)?,
                    number(e, "E", 9.8)?,
                ))
            }
            ("empty", _) => ScalarBc::Empty,
            ("cyclic", _) => ScalarBc::Cyclic,
            _ => return Err(e.unsupported(t, which.supported())),
        };
        let empty = bc == ScalarBc::Empty;
        Ok((bc, empty))
    })
}

/// The boundary-face values (one per boundary face) of a cell field `x` under `bcs`, with the
/// face fluxes `phi` (for inletOutlet); `Calculated`, wall-function and `empty` faces keep the
/// value they have in `out` (their owner sets them).
pub fn evaluate(g: &FvGeometry, bcs: &[ScalarBc], x: &[f64], phi: &[f64], out: &mut [f64]) {
    for (p, bc) in g.patches.iter().zip(bcs) {
        for (i, f) in p.faces.clone().enumerate() {
            let b = f - g.n_internal;
            let xp = x[g.owner[f] as usize];
            match bc {
                ScalarBc::FixedValue(v) => out[b] = v[i],
                ScalarBc::ZeroGradient => out[b] = xp,
                ScalarBc::FixedGradient(v) => out[b] = xp + v[i],
                ScalarBc::InletOutlet(v) => out[b] = if phi[f] < 0.0 { v[i] } else { xp },
                ScalarBc::Calculated
                | ScalarBc::EpsilonWallFunction { .. }
                | ScalarBc::NutkWallFunction(_)
                | ScalarBc::Empty
                | ScalarBc::Cyclic => {}
            }
        }
    }
}
