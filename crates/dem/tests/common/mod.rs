//! Builders shared by the integration tests.

#![allow(dead_code)]

pub mod bed;

use dem::contact::ContactModel;
use dem::material::{MaterialInput, Materials};
use dem::particles::NewParticle;
use dem::walls::{Wall, WallShape};
use dem::{SimBox, SimConfig, Simulation};

/// A simulation with one material (E, ν, e, μ), no walls, gravity `g`, time step `dt`.
pub fn sim(e_mod: f64, nu: f64, e: f64, mu: f64, g: [f64; 3], dt: f64) -> Simulation {
    sim_with(
        MaterialInput::single(e_mod, nu, e, mu),
        ContactModel::default(),
        g,
        dt,
    )
}

/// A simulation with the given materials and contact model.
pub fn sim_with(input: MaterialInput, model: ContactModel, g: [f64; 3], dt: f64) -> Simulation {
    Simulation::new(SimConfig {
        materials: Materials::new(&input).unwrap(),
        pair_model: model,
        dt,
        gravity: g,
        skin: 1e-4,
        sim_box: SimBox::fixed([-1.0; 3], [1.0; 3]),
    })
    .unwrap()
}

/// A sphere of type 1.
pub fn sphere(x: [f64; 3], v: [f64; 3], radius: f64, density: f64) -> NewParticle {
    NewParticle {
        id: 0,
        atom_type: 1,
        x,
        v,
        omega: [0.0; 3],
        radius,
        density,
    }
}

/// A plane wall of material type 1 with the given model.
pub fn plane(axis: usize, position: f64, model: ContactModel) -> Wall {
    Wall {
        name: format!("plane{axis}_{position}"),
        shape: WallShape::Plane { axis, position },
        material_type: 1,
        model,
    }
}
