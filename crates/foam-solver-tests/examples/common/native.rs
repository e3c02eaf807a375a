//! The native solver (`fv`) on a [`FrozenBed`]: shared by the examples.

use foam_solver_tests::darcy;
use foam_solver_tests::frozen_bed::{FrozenBed, RHO};

/// Runs `fv` on a copy of the frozen bed's case for `steps` steps of its Δt with
/// `harmonic_faces` and the porous faces' time term as given; Δp (Pa, inlet mean − outlet) at
/// four equally spaced steps and the last cell pressures (kinematic).
pub fn run_native(
    frozen: &FrozenBed,
    steps: usize,
    harmonic: bool,
    time_flux: fv::PorousTimeFlux,
) -> (Vec<f64>, Vec<f64>) {
    let run = frozen.case.duplicate();
    let mut fluid = fv::Fluid::from_case(&run.dir).expect("native solver reads the case");
    fluid.harmonic_faces = harmonic;
    fluid.porous_time_flux = time_flux;
    fluid.set_voidage(&frozen.eps, &frozen.eps).unwrap();
    fluid
        .set_exchange(&frozen.ksl, mesh::v3::as_vectors(&frozen.us))
        .unwrap();
    fluid.set_force(mesh::v3::as_vectors(&frozen.f)).unwrap();
    let mut history = Vec::new();
    for step in 1..=steps {
        fluid.advance(frozen.dt).unwrap();
        if step % (steps / 4).max(1) == 0 {
            let g = fluid.geometry();
            let inlet = &g.patches[g.patch_index("inlet").expect("inlet patch")];
            let pb = &fluid.p_boundary()[inlet.boundary_range(g.n_internal)];
            history.push(RHO * darcy::area_mean(&g.sf[inlet.faces.clone()], pb));
        }
    }
    (history, fluid.p().to_vec())
}
