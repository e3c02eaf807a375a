//! Gidaspow (1994): Ergun in dense regions, Wen–Yu in dilute ones.

use super::{ergun, wen_yu};
use crate::input::DragInput;

/// Voidage at which Gidaspow switches from Ergun to Wen–Yu (seed `001`, eq. 6).
pub const DEFAULT_SWITCH_VOIDAGE: f64 = 0.8;

/// Gidaspow drag coefficient per particle, kg/s: [`ergun::beta`] for ε < `switch_voidage`,
/// [`wen_yu::beta`] for ε ≥ `switch_voidage` (seed `001` eq. 5–6 with 0.8; CFDEMcoupling's
/// `GidaspowDrag` keeps the dense branch at ε = switch exactly, we follow the seed's "≥").
/// The law is discontinuous at the switch; that is the model. At 0.8 Ergun exceeds Wen–Yu by
/// 37.5/(18·0.8^−2.65) = 1.154 in Stokes flow, 1.73 at Re = 100 and 1.75/(0.33·0.8^−1.65) = 3.67
/// for Re ≥ 1000 (tested).
#[inline]
pub fn beta(x: &DragInput, switch_voidage: f64) -> f64 {
    if x.voidage < switch_voidage {
        ergun::beta(x)
    } else {
        wen_yu::beta(x)
    }
}
