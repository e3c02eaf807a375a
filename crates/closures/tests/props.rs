//! Properties over the whole input range: every law gives a finite, positive β for valid
//! inputs; the floor and the ε ≤ 1 clamp act as documented; β is continuous in ε away from
//! Gidaspow's switch; the drag force β·|u| grows with the slip where the law is monotone.

use closures::{DragClosure, DragInput, DragLaw, DRAG_LAW_NAMES};
use proptest::prelude::*;

fn input() -> impl Strategy<Value = DragInput> {
    (
        0.2f64..=1.0,
        1e-5f64..1e-2,
        0.0f64..50.0,
        0.5f64..1500.0,
        1e-5f64..1e-1,
        0.3f64..3.0,
    )
        .prop_map(|(eps, d, slip, rho, mu, y)| {
            DragInput::new(eps, d, slip, rho, mu).with_sauter_diameter(d / y)
        })
}

proptest! {
    #[test]
    fn beta_is_finite_and_positive(x in input(), floor in 0.01f64..0.5) {
        prop_assert!(x.check().is_ok());
        for (name, law) in DRAG_LAW_NAMES {
            let c = DragClosure::new(law, floor).unwrap();
            let b = c.beta(&x);
            prop_assert!(b.is_finite() && b > 0.0, "{} {:?} -> {}", name, x, b);
            // the floor: any ε below it gives β at the floor
            let low = DragInput { voidage: floor * 0.5, ..x };
            let at_floor = DragInput { voidage: floor, ..x };
            prop_assert_eq!(c.beta(&low), law.beta_unclamped(&at_floor));
        }
    }

    #[test]
    fn continuous_in_voidage(x in input()) {
        let eps = x.voidage.min(0.999);
        for (name, law) in DRAG_LAW_NAMES {
            if matches!(law, DragLaw::Gidaspow { .. }) {
                continue;
            }
            let a = law.beta(&DragInput { voidage: eps, ..x });
            let b = law.beta(&DragInput { voidage: eps + 1e-9, ..x });
            // Koch–Hill's F₀ switches branch at φ = 0.4 with a 1 % step; Wen–Yu's C_d at
            // Re = 1000 with 0.4 %
            prop_assert!(
    approx::abs_diff_eq!(a, b, epsilon = 0.012 * a),
    "{} at ε = {}: {} vs {}", name, eps, a, b
);
        }
    }

    #[test]
    fn drag_force_grows_with_slip(x in input(), k in 1.01f64..3.0) {
        let faster = DragInput { slip: x.slip * k + 1e-6, ..x };
        for law in [DragLaw::Ergun, DragLaw::KochHill, DragLaw::Beetstra, DragLaw::SchillerNaumann] {
            prop_assert!(law.beta(&faster) * faster.slip > law.beta(&x) * x.slip, "{:?}", law);
        }
    }
}
