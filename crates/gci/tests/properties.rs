//! Properties over random studies: the order of a monotone model is recovered whatever the
//! (unequal) refinement ratios, and no input of finite numbers yields a non-finite output.

use gci::{analyse, Behaviour, Outcome, Settings};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// φ(h) = φ0 + C h^p0 with h1 = 1: p and φ_ext^21 recovered (Celik eqs. 3a, 4 are exact for
    /// this model; the tolerance covers the round-off of forming ε from φ).
    #[test]
    fn monotone_model_order_is_recovered(
        p0 in 0.3f64..4.0,
        r21 in 1.1f64..3.0,
        r32 in 1.1f64..3.0,
        c in prop_oneof![0.1f64..10.0, -10.0f64..-0.1],
        phi0 in -1.0f64..1.0,
    ) {
        let h = [1.0, r21, r21 * r32];
        let phi = h.map(|h: f64| phi0 + c * h.powf(p0));
        let t = analyse(h, phi, &Settings::default()).unwrap();
        prop_assert_eq!(t.behaviour, Behaviour::MonotonicConvergence);
        let e = t.estimate().unwrap();
        prop_assert!(
    approx::abs_diff_eq!(e.p, p0, epsilon = 1e-10 * p0.max(1.0)),
    "{:?}", e
);
        let scale = phi.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        prop_assert!(
    approx::abs_diff_eq!(e.phi_ext21, phi0, epsilon = 1e-8 * scale),
    "{:?}", e
);
    }

    /// Any finite values on ordered grids: either an estimate whose every number is finite, or
    /// a reason; never NaN or ∞.
    #[test]
    fn outputs_are_finite_or_reasons(
        h1 in 1e-6f64..1.0,
        r21 in 1.0001f64..10.0,
        r32 in 1.0001f64..10.0,
        phi in proptest::array::uniform3(-1e6f64..1e6),
    ) {
        let h = [h1, h1 * r21, h1 * r21 * r32];
        let t = analyse(h, phi, &Settings::default()).unwrap();
        match t.outcome {
            // The reason is the behaviour's, or NoSolution for a converging one.
            Outcome::Undefined(why) => prop_assert_eq!(
                Some(why),
                t.behaviour.undefined().or(Some(gci::Undefined::NoSolution))
            ),
            Outcome::Estimate(e) => {
                prop_assert!(t.behaviour.converges());
                prop_assert!(e.p > 0.0 && e.p.is_finite());
                prop_assert!(e.phi_ext21.is_finite() && e.phi_ext32.is_finite());
                if let Some(r) = e.relative {
                    prop_assert!(r.e_a21.is_finite() && r.e_ext21.is_finite());
                    prop_assert!(r.gci_fine21.is_finite() && r.gci_fine21 >= 0.0);
                }
            }
        }
    }
}
