//! `probeModel particleProbe`: the force each force model puts on a particle, as CFDEM's
//! force models hand it to their probe (CFDEM-PUBLIC's `KochHillDrag.C`, `gradPForce.C`,
//! `viscForce.C`, `Archimedes.C`: `vValues` holds the force first, the drags add
//! Ur = U_f − v_p).
//!
//! The forces are split by evaluating [`closures::particle_forces`] — the function the
//! coupler's force loop uses, at the same fluid values ([`crate::forces`]' kernel) — once per
//! model with the other models' inputs set to zero, so the parts are each model's own and sum
//! to the particle's total fluid force ([`crate::forces::ParticleCoupling::total`]) to
//! round-off. Units: N, m/s.

use crate::forces::{ball, Kernel, Physics};
use crate::interpolate::Placement;
use crate::sides::{FluidState, ParticleState};
use closures::particle_forces;
use mesh::v3::V3;

/// One force model's probe of one particle.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelProbe {
    /// The model's CFDEM name (the probe file is `<name>.logDat.<rank>`).
    pub model: &'static str,
    /// The names of its vectors (CFDEM's `vectorFields_`): the force first.
    pub vector_names: &'static [&'static str],
    /// The vectors CFDEM writes on a line: the force, then (drags) U_f − v_p.
    pub vectors: Vec<V3>,
}

/// The CFDEM names of the probed models of `physics` with their vectors' names, in the order
/// foamgrain applies them: the drag law, `gradPForce`, `viscForce`, `Archimedes`.
pub fn probed_models(physics: &Physics) -> Vec<(&'static str, &'static [&'static str])> {
    let f = &physics.forces;
    let mut out = Vec::new();
    if let Some(d) = f.drag {
        let name = closures::DRAG_LAW_NAMES
            .iter()
            .find(|(_, law)| *law == d.closure.law)
            .map_or("drag", |(n, _)| *n);
        out.push((name, &["dragForce", "Urel"][..]));
    }
    if f.grad_p.is_some() {
        out.push(("gradPForce", &["gradPForce"][..]));
    }
    if f.viscous.is_some() {
        out.push(("viscForce", &["viscForce"][..]));
    }
    if f.archimedes {
        out.push(("Archimedes", &["archimedesForce"][..]));
    }
    out
}

/// The probes of particle `i` ([`probed_models`]' order), `None` when it is outside the mesh
/// (CFDEM probes only particles whose cell is found).
pub fn particle_probes(
    physics: &Physics,
    placement: &Placement,
    fluid: &FluidState<'_>,
    voidage: &[f64],
    particles: &ParticleState<'_>,
    i: usize,
) -> Option<Vec<ModelProbe>> {
    let kernel = Kernel::new(physics, fluid, voidage, None);
    let at = kernel.fluid_at(placement, i)?;
    let (r, v) = (particles.radius[i], particles.velocity[i]);
    let (beta, full) = kernel.drag_at(at.u, at.voidage, at.grad_p, at.div_tau, r, v);
    let volume = ball(r);
    let zero = V3::zeros();
    // one model's inputs, the others' zero
    let part = |beta: f64, grad_p: V3, div_tau: V3, g: V3| {
        let mut fluid = full;
        fluid.grad_p = grad_p;
        fluid.div_tau = div_tau;
        particle_forces(physics.model, beta, volume, &fluid, v, g)
    };
    let probes = probed_models(physics)
        .into_iter()
        .map(|(model, vector_names)| {
            let vectors = match vector_names[0] {
                "dragForce" => vec![part(beta, zero, zero, zero).drag, at.u - v],
                "gradPForce" => vec![part(0.0, at.grad_p, zero, zero).explicit],
                "viscForce" => vec![part(0.0, zero, at.div_tau, zero).explicit],
                _ => vec![part(0.0, zero, zero, kernel.gravity()).explicit],
            };
            ModelProbe {
                model,
                vector_names,
                vectors,
            }
        })
        .collect();
    Some(probes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{DragSettings, Forces};
    use crate::forces::particle_couplings;
    use crate::interpolate::Interpolation;
    use approx::assert_relative_eq;
    use closures::{DragClosure, DragLaw, ModelType};
    use voidage::{CellShares, Method};

    /// The probes' forces are what the particles received: for each particle, the models'
    /// forces sum to the coupler's total fluid force (its force loop,
    /// [`particle_couplings`]), and each is the model's closed form — drag β(U − v) with the
    /// law's β, gradPForce −V ρ ∇p, viscForce V ρ ∇·τ, Archimedes −ρ V g (Zhou et al. 2010,
    /// model A).
    #[test]
    fn probes_sum_to_the_particle_force() {
        let drag = DragSettings {
            closure: DragClosure::new(DragLaw::KochHill, closures::DEFAULT_VOIDAGE_FLOOR).unwrap(),
            interpolation: Interpolation::Cell,
            implicit_dem: false,
            explicit_fluid: false,
            dem_only: false,
        };
        let physics = Physics {
            rho: 1.2,
            nu: 1.5e-5,
            gravity: V3::new(0.0, 0.0, -9.81),
            model: ModelType::A,
            forces: Forces {
                drag: Some(drag),
                grad_p: Some(Interpolation::Cell),
                viscous: Some(Interpolation::Cell),
                archimedes: true,
                no_drag: None,
                virtual_mass: None,
                mei_lift: None,
                saffman_lift: None,
                random_walk: None,
            },
            implicit_couple: true,
        };
        let u = [V3::new(0.5, 0.0, 1.0), V3::new(0.1, 0.2, 0.3)];
        let p = [0.0, 0.0];
        let grad_p = [V3::new(0.0, 0.0, -20.0), V3::new(1.0, 2.0, -3.0)];
        let div_tau = [V3::new(0.01, 0.0, 0.0), V3::new(0.0, -0.02, 0.0)];
        let fluid = FluidState {
            u: &u,
            p: &p,
            grad_p: &grad_p,
            div_tau: &div_tau,
            temperature: None,
            vorticity: None,
            ddt_u: None,
            turbulence: None,
        };
        let eps = [0.45, 0.7];
        let placement = Placement {
            centre: vec![Some(0), Some(1), None],
            shares: CellShares {
                method: Method::Centre,
                offsets: vec![0, 1, 2, 2],
                cells: vec![0, 1],
                volumes: vec![1e-9, 1e-9],
            },
        };
        let ids = [1, 2, 3];
        let radius = [1e-3, 2e-3, 1e-3];
        let position = [V3::zeros(); 3];
        let velocity = [V3::new(0.0, 0.0, -0.1), V3::new(0.2, 0.0, 0.0), V3::zeros()];
        let density = [2500.0; 3];
        let particles = ParticleState {
            ids: &ids,
            position: &position,
            velocity: &velocity,
            radius: &radius,
            density: &density,
            temperature: None,
        };
        let set = particle_couplings(&physics, &placement, &fluid, &eps, &particles);
        for i in 0..2 {
            let probes =
                particle_probes(&physics, &placement, &fluid, &eps, &particles, i).expect("inside");
            let names: Vec<&str> = probes.iter().map(|m| m.model).collect();
            assert_eq!(
                names,
                ["KochHillDrag", "gradPForce", "viscForce", "Archimedes"]
            );
            let sum: V3 = probes.iter().map(|m| m.vectors[0]).sum();
            let total = set.particles[i].total;
            for k in 0..3 {
                assert_relative_eq!(sum[k], total[k], epsilon = 1e-15, max_relative = 1e-12);
            }
            let vol = 4.0 / 3.0 * std::f64::consts::PI * radius[i].powi(3);
            let c = i;
            let expect = [
                -vol * 1.2 * grad_p[c],
                vol * 1.2 * div_tau[c],
                -1.2 * vol * physics.gravity,
            ];
            for (m, e) in probes[1..].iter().zip(expect) {
                assert_relative_eq!(m.vectors[0], e, max_relative = 1e-14);
            }
            // drag = β (U − v), its direction that of U − v, and Urel = U − v
            assert_eq!(probes[0].vectors[1], u[c] - velocity[i]);
            let d = probes[0].vectors[0];
            assert_relative_eq!(
                d.normalize(),
                (u[c] - velocity[i]).normalize(),
                max_relative = 1e-12
            );
        }
        assert!(particle_probes(&physics, &placement, &fluid, &eps, &particles, 2).is_none());
    }
}
