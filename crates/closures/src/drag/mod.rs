//! Drag laws: each returns the per-particle drag coefficient β (kg/s) of ADR 0004, the drag
//! force on the particle being `F_d = β (u_f − v_p)` with u_f the interstitial fluid velocity.
//!
//! Every β here is the *model A* drag (the drag that, together with the separate pressure
//! gradient force −V_p∇p, balances a fluid equation with −ε∇p); model B's drag is β/ε
//! (see [`crate::model`]). One file per law, named after it; [`DragLaw`] selects among them
//! and [`DragLaw::from_name`] maps CFDEMcoupling's `forceModels` names onto them.

pub mod beetstra;
pub mod di_felice;
pub mod ergun;
pub mod gidaspow;
pub mod koch_hill;
pub mod parcel;
pub mod schiller_naumann;
pub mod wen_yu;

use crate::error::ClosureError;
use crate::input::DragInput;
pub use parcel::Parcel;

/// Default lower bound on ε applied by [`DragLaw::beta`] (the laws with 1/ε or ε^−n terms
/// blow up at ε → 0; a cell full of particle volume is a voidage-model artefact). 0.1 is
/// CFDEMcoupling's floor for `GidaspowDrag` with interpolation; configure it with
/// [`DragClosure`].
pub const DEFAULT_VOIDAGE_FLOOR: f64 = 0.1;

/// A drag law. `beta` evaluates it; parameters that a law needs live in its variant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DragLaw {
    /// Ergun below `switch_voidage`, Wen–Yu at and above it ([`gidaspow`]); CFDEM
    /// `GidaspowDrag` (switch 0.8).
    Gidaspow {
        /// The switching voidage, in (0, 1]; 0.8 in seed `001`.
        switch_voidage: f64,
    },
    /// Ergun's packed-bed law ([`ergun`]).
    Ergun,
    /// Wen & Yu's dilute law ([`wen_yu`]).
    WenYu,
    /// Di Felice (1994) ([`di_felice`]); CFDEM `DiFeliceDrag`.
    DiFelice,
    /// Koch & Hill (2001) ([`koch_hill`]); CFDEM `KochHillDrag`.
    KochHill,
    /// Beetstra et al. (2007), monodisperse ([`beetstra::beta`]); CFDEM(-PFM) `BeetstraDrag`.
    Beetstra,
    /// Beetstra et al. (2007) with the polydisperse correction on the local Sauter-mean
    /// diameter ([`beetstra::beta_polydisperse`]); CFDEM-PFM `BeetstraDragPoly`.
    BeetstraPoly,
    /// Schiller & Naumann single-sphere drag ([`schiller_naumann`]); CFDEM
    /// `SchillerNaumannDrag`. Ignores ε.
    SchillerNaumann,
}

/// Names accepted by [`DragLaw::from_name`]: CFDEMcoupling's `forceModels` names first, then
/// foamgrain's own names for the laws CFDEM has no separate model for (`ErgunDrag`,
/// `WenYuDrag`) and short aliases.
pub const DRAG_LAW_NAMES: [(&str, DragLaw); 16] = [
    ("GidaspowDrag", GIDASPOW),
    ("KochHillDrag", DragLaw::KochHill),
    ("DiFeliceDrag", DragLaw::DiFelice),
    ("BeetstraDrag", DragLaw::Beetstra),
    ("BeetstraDragPoly", DragLaw::BeetstraPoly),
    ("SchillerNaumannDrag", DragLaw::SchillerNaumann),
    ("ErgunDrag", DragLaw::Ergun),
    ("WenYuDrag", DragLaw::WenYu),
    ("gidaspow", GIDASPOW),
    ("koch-hill", DragLaw::KochHill),
    ("di-felice", DragLaw::DiFelice),
    ("beetstra", DragLaw::Beetstra),
    ("beetstra-poly", DragLaw::BeetstraPoly),
    ("schiller-naumann", DragLaw::SchillerNaumann),
    ("ergun", DragLaw::Ergun),
    ("wen-yu", DragLaw::WenYu),
];

const GIDASPOW: DragLaw = DragLaw::Gidaspow {
    switch_voidage: gidaspow::DEFAULT_SWITCH_VOIDAGE,
};

impl DragLaw {
    /// Gidaspow with the seed's switch at ε = 0.8.
    pub const GIDASPOW: DragLaw = GIDASPOW;

    /// The law selected by `name` (CFDEM's `forceModels` entry or our alias, see
    /// [`DRAG_LAW_NAMES`]); an unknown name is an error listing the valid ones.
    pub fn from_name(name: &str) -> Result<DragLaw, ClosureError> {
        DRAG_LAW_NAMES
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, law)| *law)
            .ok_or_else(|| ClosureError::UnknownModel {
                family: "drag",
                name: name.to_string(),
                valid: DRAG_LAW_NAMES
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// CFDEMcoupling's name for this law (ours where CFDEM has none).
    pub fn cfdem_name(&self) -> &'static str {
        match self {
            DragLaw::Gidaspow { .. } => "GidaspowDrag",
            DragLaw::Ergun => "ErgunDrag",
            DragLaw::WenYu => "WenYuDrag",
            DragLaw::DiFelice => "DiFeliceDrag",
            DragLaw::KochHill => "KochHillDrag",
            DragLaw::Beetstra => "BeetstraDrag",
            DragLaw::BeetstraPoly => "BeetstraDragPoly",
            DragLaw::SchillerNaumann => "SchillerNaumannDrag",
        }
    }

    /// The lower bound CFDEMcoupling-PUBLIC (3.8) puts on the *interpolated* ε before its drag
    /// model evaluates β (`interpolation true` in the model's Props; ε is also capped at 1):
    /// 0.4 for `KochHillDrag` (below it Koch–Hill's F₀ = 10φ/ε³ is outside the random-array
    /// data of Hill, Koch & Ladd 2001, which reach φ ≈ 0.6 only), 0.3 for `DiFeliceDrag`, 0.1
    /// for `GidaspowDrag`; the laws CFDEM-PUBLIC lacks keep [`DEFAULT_VOIDAGE_FLOOR`]. Without
    /// interpolation CFDEM takes the cell's ε unclamped, which its voidage model has floored
    /// at `alphaMin` (0.1) already, so [`DEFAULT_VOIDAGE_FLOOR`] is the same there.
    pub fn cfdem_interpolated_floor(&self) -> f64 {
        match self {
            DragLaw::KochHill => 0.4,
            DragLaw::DiFelice => 0.3,
            _ => DEFAULT_VOIDAGE_FLOOR,
        }
    }

    /// Checks the law's parameters (Gidaspow's switch in (0, 1]).
    pub fn check(&self) -> Result<(), ClosureError> {
        if let DragLaw::Gidaspow { switch_voidage } = *self {
            if !(switch_voidage > 0.0 && switch_voidage <= 1.0) {
                return Err(ClosureError::BadParameter {
                    model: "GidaspowDrag",
                    key: "switchingVoidfraction",
                    value: switch_voidage,
                    reason: "must be in (0, 1]",
                });
            }
        }
        Ok(())
    }

    /// β (kg/s) with ε clamped to [[`DEFAULT_VOIDAGE_FLOOR`], 1]. Use [`DragClosure`] to set
    /// another floor.
    #[inline]
    pub fn beta(&self, x: &DragInput) -> f64 {
        self.beta_floored(x, DEFAULT_VOIDAGE_FLOOR)
    }

    /// β (kg/s) with ε clamped to [`voidage_floor`, 1] (ε > 1 can come out of interpolation).
    #[inline]
    pub fn beta_floored(&self, x: &DragInput, voidage_floor: f64) -> f64 {
        let mut x = *x;
        x.voidage = x.voidage.clamp(voidage_floor, 1.0);
        self.beta_unclamped(&x)
    }

    /// β (kg/s) at exactly the given ε (must be in (0, 1]; no floor).
    #[inline]
    pub fn beta_unclamped(&self, x: &DragInput) -> f64 {
        match *self {
            DragLaw::Gidaspow { switch_voidage } => gidaspow::beta(x, switch_voidage),
            DragLaw::Ergun => ergun::beta(x),
            DragLaw::WenYu => wen_yu::beta(x),
            DragLaw::DiFelice => di_felice::beta(x),
            DragLaw::KochHill => koch_hill::beta(x),
            DragLaw::Beetstra => beetstra::beta(x),
            DragLaw::BeetstraPoly => beetstra::beta_polydisperse(x),
            DragLaw::SchillerNaumann => schiller_naumann::beta(x),
        }
    }
}

/// A configured drag closure: a law, the voidage floor applied before evaluating it, and the
/// coarse graining of the particles it acts on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragClosure {
    /// The law.
    pub law: DragLaw,
    /// ε is clamped to [`voidage_floor`, 1] before the law sees it; in (0, 1].
    pub voidage_floor: f64,
    /// The parcels' coarse graining ([`parcel`]); [`Parcel::REAL`] unless set with
    /// [`DragClosure::with_parcel`].
    pub parcel: Parcel,
}

impl DragClosure {
    /// A closure with a checked law and floor; errors name the bad parameter.
    pub fn new(law: DragLaw, voidage_floor: f64) -> Result<Self, ClosureError> {
        law.check()?;
        if !(voidage_floor > 0.0 && voidage_floor <= 1.0) {
            return Err(ClosureError::BadParameter {
                model: law.cfdem_name(),
                key: "voidageFloor",
                value: voidage_floor,
                reason: "must be in (0, 1]",
            });
        }
        Ok(DragClosure {
            law,
            voidage_floor,
            parcel: Parcel::REAL,
        })
    }

    /// The same closure acting on parcels `parcel` ([`parcel`]).
    pub fn with_parcel(self, parcel: Parcel) -> Self {
        DragClosure { parcel, ..self }
    }

    /// β (kg/s) of the law at ε clamped to [`voidage_floor`, 1]; for parcels, the law at the
    /// real particles' diameter times scaleDrag·CG³ ([`Parcel`]).
    #[inline]
    pub fn beta(&self, x: &DragInput) -> f64 {
        if self.parcel.is_real() {
            return self.law.beta_floored(x, self.voidage_floor);
        }
        let real = self.parcel.real_particle(x);
        self.parcel
            .scale(self.law.beta_floored(&real, self.voidage_floor))
    }
}

impl From<DragLaw> for DragClosure {
    fn from(law: DragLaw) -> Self {
        DragClosure {
            law,
            voidage_floor: DEFAULT_VOIDAGE_FLOOR,
            parcel: Parcel::REAL,
        }
    }
}
