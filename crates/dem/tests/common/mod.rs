//! Builders shared by the integration tests.

#![allow(dead_code)]

pub mod bed;
pub mod inflow;
pub mod meshes;

use dem::contact::ContactModel;
use dem::material::{MaterialInput, Materials};
use dem::particles::NewParticle;
use dem::walls::{Wall, WallShape};
use dem::{SimBox, SimConfig, Simulation};
use mesh::v3::V3;

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
pub fn sim_with(
    input: MaterialInput,
    model: ContactModel,
    g: impl Into<V3>,
    dt: f64,
) -> Simulation {
    Simulation::new(SimConfig {
        materials: Materials::new(&input).unwrap(),
        pair_model: model,
        dt,
        gravity: g.into(),
        skin: 1e-4,
        sim_box: SimBox::fixed(V3::repeat(-1.0), V3::repeat(1.0)),
    })
    .unwrap()
}

/// A sphere of type 1.
pub fn sphere(x: impl Into<V3>, v: impl Into<V3>, radius: f64, density: f64) -> NewParticle {
    NewParticle {
        id: 0,
        atom_type: 1,
        x: x.into(),
        v: v.into(),
        omega: V3::zeros(),
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

/// Every snapshot of a dump file, in order.
pub fn snapshots(path: impl AsRef<std::path::Path>) -> Vec<dem_io::Snapshot> {
    let (path, options) = (path.as_ref(), dem_io::ReadOptions::default());
    let mut out = Vec::new();
    while let Ok(s) = dem_io::read_snapshot(path, &options, dem_io::Selection::Index(out.len())) {
        out.push(s);
    }
    out
}

/// The last snapshot of a dump file.
pub fn last_snapshot(path: impl AsRef<std::path::Path>) -> dem_io::Snapshot {
    dem_io::read_snapshot(
        path.as_ref(),
        &dem_io::ReadOptions::default(),
        dem_io::Selection::Last,
    )
    .unwrap()
}

/// Runs `f` on a rayon pool of `threads` threads.
pub fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// Asserts that column `c` of every snapshot of `native` is within `tol` × the column's largest
/// magnitude in `reference` of the reference's value (the largest difference is printed).
pub fn assert_column_close(
    native: &[dem_io::Snapshot],
    reference: &[dem_io::Snapshot],
    c: &str,
    tol: f64,
) {
    let values = |s: &[dem_io::Snapshot]| -> Vec<Vec<f64>> {
        s.iter().map(|x| x.column(c).unwrap().to_vec()).collect()
    };
    let (a, b) = (values(native), values(reference));
    let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!("{c}: largest difference {worst:.3e} of scale {scale:.3e}");
    assert!(worst <= tol * scale, "{c}: {worst} > {tol} × {scale}");
}
