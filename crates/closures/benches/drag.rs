//! β evaluations per second for every drag law: N = 10⁶ particles with voidage spread over
//! [0.35, 1], slip over [0, 2] m/s, diameters over [0.5, 1.5] mm (air-like fluid), evaluated
//! serially in one loop over plain slices (structure of arrays), result summed so the work
//! cannot be optimised away. Particles/s = N / time. Run: `cargo bench -p closures`.

use closures::{DragInput, DragLaw, DRAG_LAW_NAMES};
use divan::counter::ItemsCount;
use std::sync::OnceLock;

const N: usize = 1_000_000;

fn main() {
    divan::main();
}

struct Particles {
    eps: Vec<f64>,
    d: Vec<f64>,
    slip: Vec<f64>,
}

/// Deterministic low-discrepancy samples (golden-ratio additive recurrence).
fn particles() -> &'static Particles {
    static P: OnceLock<Particles> = OnceLock::new();
    P.get_or_init(|| {
        let g = 0.618_033_988_749_895_f64;
        let u = |k: usize, s: f64| (s + k as f64 * g).fract();
        Particles {
            eps: (0..N).map(|k| 0.35 + 0.65 * u(k, 0.1)).collect(),
            d: (0..N).map(|k| 5e-4 + 1e-3 * u(k * 7, 0.3)).collect(),
            slip: (0..N).map(|k| 2.0 * u(k * 13, 0.7)).collect(),
        }
    })
}

const LAWS: [&str; 8] = [
    "GidaspowDrag",
    "ErgunDrag",
    "WenYuDrag",
    "DiFeliceDrag",
    "KochHillDrag",
    "BeetstraDrag",
    "BeetstraDragPoly",
    "SchillerNaumannDrag",
];

#[divan::bench(args = LAWS, sample_count = 20)]
fn beta(bencher: divan::Bencher, name: &str) {
    assert!(DRAG_LAW_NAMES.iter().any(|(n, _)| *n == name));
    let law = DragLaw::from_name(name).unwrap();
    let p = particles();
    bencher.counter(ItemsCount::new(N)).bench(|| {
        let mut sum = 0.0;
        for i in 0..N {
            let x =
                DragInput::new(p.eps[i], p.d[i], p.slip[i], 1.2, 1.8e-5).with_sauter_diameter(1e-3);
            sum += law.beta(&x);
        }
        divan::black_box(sum)
    });
}
