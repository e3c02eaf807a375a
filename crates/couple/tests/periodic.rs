//! A particle beyond a cyclic face (a periodic DEM wraps it back only when it rebuilds its
//! neighbour list) is coupled at its image inside the mesh: the coupler on a channel cyclic in
//! x gives it the deposit and forces of the same particle moved back by one period.

use closures::DragLaw;
use couple::{Coupler, CouplerSettings, FluidState, Interpolation, ParticleState};
use mesh::build::uniform_box;
use mesh::v3::V3;
use voidage::Method;

mod common;

/// A channel 0.4 × 0.1 × 0.1 m of 8 × 2 × 2 cells, its x faces a translational cyclic pair.
fn channel() -> foam::PolyMesh {
    let mut m = uniform_box([0.0; 3], [0.4, 0.1, 0.1], [8, 2, 2]);
    for p in &mut m.boundary {
        let other = match p.name.as_str() {
            "xMin" => "xMax",
            "xMax" => "xMin",
            _ => continue,
        };
        p.patch_type = "cyclic".into();
        p.extra = vec![("neighbourPatch".into(), other.into())];
    }
    m
}

fn settings(method: Method) -> CouplerSettings {
    common::drag_settings(method, DragLaw::KochHill, Interpolation::Cell, 1.3, 1.5e-4)
}

#[test]
fn a_centre_beyond_a_cyclic_face_is_coupled_at_its_image() {
    let mesh = channel();
    let n = 32;
    // a flow varying along x, so the cell the particle is placed in matters
    let cells = mesh::MeshGeometry::new(&mesh).unwrap().cell_centres;
    let u: Vec<V3> = cells
        .iter()
        .map(|c| V3::new(1.0 + 10.0 * c[0], 0.0, 0.0))
        .collect();
    let (p, grad_p, div_tau) = (vec![0.0; n], vec![V3::zeros(); n], vec![V3::zeros(); n]);
    let fluid = FluidState {
        vorticity: None,
        ddt_u: None,
        turbulence: None,
        temperature: None,
        u: &u,
        p: &p,
        grad_p: &grad_p,
        div_tau: &div_tau,
    };
    for method in [Method::Centre, Method::Divided, Method::Exact] {
        let step = |x: f64| {
            let (ids, pos) = ([1u64], [V3::new(x, 0.03, 0.04)]);
            let (vel, rad, den) = ([V3::zeros()], [0.0002], [2000.0]);
            let particles = ParticleState {
                temperature: None,
                ids: &ids,
                position: &pos,
                velocity: &vel,
                radius: &rad,
                density: &den,
            };
            Coupler::new(&mesh, settings(method))
                .unwrap()
                .exchange(&particles, &fluid)
                .unwrap()
        };
        // a sphere of radius 0.2 mm 0.3 mm beyond the x = 0.4 face, and wrapped back
        let (beyond, image) = (step(0.4003), step(0.4003 - 0.4));
        // without the image the whole particle would be outside the mesh
        assert_eq!(beyond.deposit.outside_volume, 0.0, "{method:?}");
        assert_eq!(beyond.deposit.solid, image.deposit.solid, "{method:?}");
        assert!(beyond.forces == image.forces, "{method:?}");
        assert_eq!(beyond.placement.centre[0], Some(0), "{method:?}");
    }
}
