//! grainPisoFoam on the Ergun bed's frozen coupling fields (`fixtures/ergun-bed`: 4480 cells,
//! a LIGGGHTS-packed bed with cell-to-cell scatter in ε and Ksl, the bed on the
//! fixedFluxPressure inlet): the steady Δp lies between the Darcy bounds of those fields
//! (`foam_solver_tests::darcy`), where the linear face coefficients gave 23.0 Pa, 15 % below
//! the lower bound.

use foam_solver_tests::frozen_bed::{self, FrozenBed, RHO};
use foam_solver_tests::grain_piso_foam;

#[test]
fn the_frozen_ergun_bed_drop_lies_between_the_darcy_bounds() {
    let Some(solver) = grain_piso_foam() else {
        return;
    };
    // 80 steps of 0.5 ms from U = 0 (the bed's momentum relaxes in ε/(Ksl/ρ) ≈ 2e-5 s, the
    // clear column above it more slowly).
    let frozen = FrozenBed::new(&frozen_bed::fixture(), 80);
    let reference = frozen.reference();
    let (lower, upper) = (RHO * reference.lower, RHO * reference.upper);
    let (history, _) = frozen.run_grain_piso_foam(&solver);
    let dp = *history.last().unwrap();
    eprintln!(
        "frozen Ergun bed: Δp = {dp:.4} Pa, Darcy bounds [{lower:.4}, {upper:.4}] Pa, \
         uniform flux {:.4} Pa; history {history:.4?}",
        RHO * reference.uniform_flux
    );
    // The bounds neglect the viscous stress and hold exactly for Us = 0 (here |Us| ≤ 1.6e-3
    // m/s against U ≈ 4.6e-3 m/s): 1 % of slack on each side. Measured 28.43 in
    // [27.01, 28.80], last change 1e-5 (28.37 before the time-step-independent face flux of
    // porousFaces.H).
    assert!(
        dp > 0.99 * lower && dp < 1.01 * upper,
        "Δp {dp} Pa outside [{lower}, {upper}] Pa"
    );
    // Steady: the last two writes agree.
    let change = (history[3] - history[2]).abs() / dp;
    assert!(change < 1e-4, "Δp still moving: {history:?}");
}
