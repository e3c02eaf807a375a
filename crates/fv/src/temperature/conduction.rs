//! The fluid's conduction in a bed: CFDEM-PFM's `thermCondModel`s as the native temperature
//! equation takes them ([`BedConduction`]).
//!
//! PFM's energy equations carry the gas conduction as `laplacian(voidfraction*thCond, T)`
//! (`applications/solvers/cfdemSolverRhoPimple/EEqn.H`), with `thCond` set per cell by the
//! model; the native equation's laminar term `laplacian(ε ν/Pr, T)` is the same with
//! thCond = k_f = ρ c_p ν/Pr. With a model, ε k_f is replaced by the bed's effective
//! conductivity k_bed(ε), i.e. the laminar diffusivity ε ν/Pr by (k_bed/k_f) ν/Pr
//! ([`BedConduction::ratio`]); the turbulent part α_t ε is unchanged.
//!
//! * `SyamlalThermCond` (Syamlal & Gidaspow 1985, AIChE J. 31:127, the gas phase's
//!   conductivity, as PFM's `SyamlalThermCond.C` computes it): thCond = (1 − √(1 − ε))/ε k_f,
//!   so k_bed/k_f = 1 − √(1 − ε) (1 at ε = 1, 0 at ε = 0).
//! * `ZehnerSchluenderThermCond` (Zehner & Schlünder 1970, Chem.-Ing.-Tech. 42:933, the
//!   stagnant conductivity of a packed bed of spheres, with the contact-flattening weight
//!   w = 7.26e-3 and the shape exponent 1.11 of PFM's `ZehnerSchluenderThermCond.C`), with
//!   A = k_s/k_f, B = 1.25 ((1 − ε)/ε)^1.11, N = 1 − B/A:
//!   k_c/k_f = (2/N) [ (A − 1) B/(A N²) ln(A/B) − (B + 1)/2 − (B − 1)/N ],
//!   k_bed/k_f = (1 − √(1 − ε)) + √(1 − ε) (w A + (1 − w) k_c/k_f).
//!   PFM computes only the second (particle-core) term, divided by 1 − ε, into a field
//!   `partKs` that none of its solvers reads (its `thCond` stays as read); foamgrain gives the
//!   fluid the whole bed conductivity, whose first term is Syamlal's, so that at ε → 1 it is
//!   the fluid's own (k_c/k_f → 1 as B → 0, the core term vanishes with √(1 − ε)). Where
//!   ε ≥ 1 − 10⁻¹⁵ or A < 10⁻¹⁵ the core term is 0 (PFM's `SMALL` guards). At B = A (N = 0)
//!   the bracket's singularity is removable: for |N| < 10⁻³ k_c is the mean of its values at
//!   N = ±10⁻³ (error O(10⁻⁶) relative; the terms' cancellation costs ~10⁻⁷ there).
//!
//! Boundary faces: PFM's `thCond` is `zeroGradient`, so a face's diffusivity is
//! ε_b thCond(ε_owner) = ε_b (k_bed(ε_o)/(ε_o k_f)) k_f; the native equation does the same.

/// PFM's `SMALL` (OpenFOAM's double `SMALL`), the guards of the models.
const SMALL: f64 = 1e-15;
/// ZS's contact-flattening weight w of PFM (dimensionless).
const ZS_FLATTENING: f64 = 7.26e-3;
/// |N| below which the ZS core is the mean of its values at N = ±this.
const ZS_NEAR_SINGULAR: f64 = 1e-3;

/// A bed conductivity model of the fluid's temperature equation (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BedConduction {
    /// `SyamlalThermCond`: k_bed/k_f = 1 − √(1 − ε).
    Syamlal,
    /// `ZehnerSchluenderThermCond` with the particles' to the fluid's conductivity ratio
    /// A = k_s/k_f (dimensionless, > 0).
    ZehnerSchluender {
        /// k_s/k_f.
        ks_over_kf: f64,
    },
}

impl BedConduction {
    /// k_bed/k_f at voidage `eps` (dimensionless; ε in [0, 1]), the factor that replaces ε
    /// on the laminar diffusivity ν/Pr (module docs).
    pub fn ratio(self, eps: f64) -> f64 {
        let fluid_part = syamlal(eps);
        match self {
            BedConduction::Syamlal => fluid_part,
            BedConduction::ZehnerSchluender { ks_over_kf } => fluid_part + zs_core(eps, ks_over_kf),
        }
    }

    /// The model's `thermCondModel` name.
    pub fn name(self) -> &'static str {
        match self {
            BedConduction::Syamlal => "SyamlalThermCond",
            BedConduction::ZehnerSchluender { .. } => "ZehnerSchluenderThermCond",
        }
    }
}

/// ε thCond/k_f of PFM's `SyamlalThermCond`: k_f where 1 − ε < SMALL (so ε k_f), 0 where
/// ε < SMALL, else 1 − √(1 − ε + SMALL).
fn syamlal(eps: f64) -> f64 {
    if 1.0 - eps < SMALL {
        eps
    } else if eps < SMALL {
        0.0
    } else {
        1.0 - (1.0 - eps + SMALL).sqrt()
    }
}

/// The particle-core term √(1 − ε)(w A + (1 − w) k_c/k_f) of Zehner & Schlünder (module
/// docs), 0 where ε > 1 − SMALL or A < SMALL.
fn zs_core(eps: f64, a: f64) -> f64 {
    if eps > 1.0 - SMALL || a < SMALL {
        return 0.0;
    }
    let b = 1.25 * ((1.0 - eps) / eps).powf(1.11);
    let n = 1.0 - b / a;
    let kc = match n.abs() < ZS_NEAR_SINGULAR {
        true => {
            let at = |n: f64| zs_bracket(a, a * (1.0 - n));
            0.5 * (at(ZS_NEAR_SINGULAR) + at(-ZS_NEAR_SINGULAR))
        }
        false => zs_bracket(a, b),
    };
    (1.0 - eps).sqrt() * (ZS_FLATTENING * a + (1.0 - ZS_FLATTENING) * kc)
}

/// k_c/k_f = (2/N)[(A − 1) B/(A N²) ln(A/B) − (B + 1)/2 − (B − 1)/N], N = 1 − B/A.
fn zs_bracket(a: f64, b: f64) -> f64 {
    let n = 1.0 - b / a;
    2.0 / n * ((a - 1.0) * b / (a * n * n) * (a / b).ln() - 0.5 * (b + 1.0) - (b - 1.0) / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Syamlal & Gidaspow's gas-phase factor by hand: 1 − √(1 − ε) at ε = 0.4 is
    /// 1 − √0.6 = 0.225403330758517; at 0.9, 1 − √0.1 = 0.683772233983162; ε = 1 gives the
    /// fluid (1), ε = 0 nothing.
    #[test]
    fn syamlal_matches_the_hand_values() {
        let cases = [
            (0.4, 0.225_403_330_758_517),
            (0.9, 0.683_772_233_983_162),
            (1.0, 1.0),
            (0.0, 0.0),
        ];
        for (eps, want) in cases {
            let got = BedConduction::Syamlal.ratio(eps);
            assert!((got - want).abs() < 1e-14, "ε {eps}: {got} vs {want}");
        }
    }

    /// Zehner & Schlünder's bed by hand (Python, the paper's form with B = 1.25((1−ε)/ε)^1.11
    /// and w = 7.26e-3, written out independently of this file):
    /// ε = 0.4, A = 10: B = 1.96052, k_c/k_f = 4.41106, k_bed/k_f = 3.67363;
    /// ε = 0.4, A = 1000 (metal in gas): k_c/k_f = 19.6707, k_bed/k_f = 20.9752;
    /// ε = 0.476, A = 100: k_c/k_f = 9.04959, k_bed/k_f = 7.30490.
    #[test]
    fn zehner_schluender_matches_the_hand_values() {
        let cases = [
            (0.4, 10.0, ZS_0_4_10),
            (0.4, 1000.0, ZS_0_4_1000),
            (0.476, 100.0, ZS_0_476_100),
        ];
        for (eps, a, want) in cases {
            let got = BedConduction::ZehnerSchluender { ks_over_kf: a }.ratio(eps);
            assert!(
                (got - want).abs() < 1e-12 * want,
                "ε {eps}, A {a}: {got} vs {want}"
            );
        }
    }

    /// A = k_s/k_f = 1 (particles of the fluid's conductivity): a bed of the fluid, whose
    /// conductivity Zehner & Schlünder's model must return as k_f within its flattening
    /// term's share (k_bed/k_f = 1 exactly without it: k_c/k_f = 1 at A = 1 for every B).
    /// Also the removable singularity B = A gives the neighbouring values continuously.
    #[test]
    fn zehner_schluender_limits() {
        for eps in [0.3, 0.4, 0.6, 0.9] {
            let got = BedConduction::ZehnerSchluender { ks_over_kf: 1.0 }.ratio(eps);
            assert!((got - 1.0).abs() < 1e-9, "ε {eps}: {got}");
        }
        // B = A at ε = 0.4, A = B(0.4)
        let a = 1.25 * (0.6f64 / 0.4).powf(1.11);
        let f = |a: f64| BedConduction::ZehnerSchluender { ks_over_kf: a }.ratio(0.4);
        let (at, below, above) = (f(a), f(a * (1.0 - 2e-3)), f(a * (1.0 + 2e-3)));
        assert!(at.is_finite());
        assert!(
            (at - 0.5 * (below + above)).abs() < 1e-5 * at,
            "{below} {at} {above}"
        );
        assert_eq!(
            BedConduction::ZehnerSchluender { ks_over_kf: 50.0 }.ratio(1.0),
            1.0
        );
    }

    const ZS_0_4_10: f64 = 3.673_626_440_571_14;
    const ZS_0_4_1000: f64 = 20.975_236_352_672_1;
    const ZS_0_476_100: f64 = 7.304_904_691_744_07;
}
