//! Triplet analyses per second: N = 10⁵ three-grid studies of φ(h) = φ0 + C h^p0 with p0 over
//! [0.5, 3], r21 over [1.3, 2] and r32 over [1.3, 2] (unequal ratios, so the fixed-point
//! iteration of Celik et al. eq. 3a runs to convergence), analysed serially; the summed GCI
//! keeps the work from being optimised away. Run: `cargo bench -p gci`.

use divan::counter::ItemsCount;
use gci::{analyse, Settings};
use std::sync::OnceLock;

const N: usize = 100_000;

fn main() {
    divan::main();
}

type Case = ([f64; 3], [f64; 3]);

/// Deterministic low-discrepancy samples (golden-ratio additive recurrence).
fn cases() -> &'static [Case] {
    static C: OnceLock<Vec<Case>> = OnceLock::new();
    C.get_or_init(|| {
        let g = 0.618_033_988_749_895_f64;
        let u = |k: usize, s: f64| (s + k as f64 * g).fract();
        (0..N)
            .map(|k| {
                let p0 = 0.5 + 2.5 * u(k, 0.1);
                let r21 = 1.3 + 0.7 * u(k * 7, 0.3);
                let r32 = 1.3 + 0.7 * u(k * 13, 0.7);
                let h = [0.01, 0.01 * r21, 0.01 * r21 * r32];
                (h, h.map(|h| 1.0 + 50.0 * h.powf(p0)))
            })
            .collect()
    })
}

#[divan::bench]
fn analyse_triplets(bencher: divan::Bencher) {
    let settings = Settings::default();
    let cases = cases();
    bencher.counter(ItemsCount::new(N)).bench(|| {
        cases
            .iter()
            .map(|(h, phi)| {
                analyse(*h, *phi, &settings)
                    .ok()
                    .and_then(|t| t.estimate().and_then(|e| e.relative).map(|r| r.gci_fine21))
                    .unwrap_or(0.0)
            })
            .sum::<f64>()
    });
}
