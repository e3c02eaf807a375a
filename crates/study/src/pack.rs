//! The bed, packed once by the native DEM and then read as a fixed set of spheres.
//!
//! A case's coupled deck (`DEM/in.liggghts_run`) reads the packed bed with `read_data FILE`;
//! when FILE is missing (or a repack is asked for) the init deck `DEM/in.liggghts_init` is run
//! natively first and must write it (as `foamgrain run`'s stage 1 does). The particles are
//! then taken from the coupled deck's simulation as built, before any step.

use crate::error::StudyError;
use dem::Simulation;
use liggghts_deck::Deck;
use mesh::v3::V3;
use runner::layout::CaseLayout;

use std::time::Instant;

/// A packed bed: the spheres, in the deck's order (SI units).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PackedBed {
    /// Particle ids (LIGGGHTS tags).
    pub ids: Vec<u64>,
    /// Centres, m.
    pub position: Vec<V3>,
    /// Radii, m.
    pub radius: Vec<f64>,
    /// Densities, kg/m³.
    pub density: Vec<f64>,
}

impl PackedBed {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// The diameters, m.
    pub fn diameters(&self) -> Vec<f64> {
        self.radius.iter().map(|r| 2.0 * r).collect()
    }
}

/// The packed bed of the case: packs it first (init deck, `init_vars` as `-var NAME VALUE`)
/// if the coupled deck's data file is missing or `repack` is set. `events` gets log lines.
pub fn packed_bed(
    layout: &CaseLayout,
    repack: bool,
    init_vars: &[(String, String)],
    events: &mut dyn FnMut(String),
) -> Result<PackedBed, StudyError> {
    let run_deck = Deck::read(&layout.run_deck)?;
    let data = run_deck
        .read_files()
        .into_iter()
        .find(|f| f.command == "read_data")
        .map(|f| layout.dem.join(f.path))
        .ok_or_else(|| StudyError::Setup {
            file: layout.run_deck.clone(),
            message: "has no `read_data FILE`: the study needs a packed bed to freeze".into(),
        })?;
    if repack || !data.exists() {
        let init = layout.init_deck.as_ref().ok_or_else(|| StudyError::Setup {
            file: layout.run_deck.clone(),
            message: format!(
                "reads {} which does not exist, and there is no DEM/in.liggghts_init to make it",
                data.display()
            ),
        })?;
        events(format!(
            "packing: running {} natively (writes {})",
            init.display(),
            data.display()
        ));
        let t = Instant::now();
        let deck = Deck::read_with_vars(init, init_vars)?;
        let sim = Simulation::from_deck(&deck, &layout.dem)?;
        if !data.exists() {
            return Err(StudyError::Setup {
                file: init.clone(),
                message: format!("ran, but did not write {}", data.display()),
            });
        }
        events(format!(
            "packing: {} particles in {:.1} s",
            sim.particles.len(),
            t.elapsed().as_secs_f64()
        ));
    }
    let sim = Simulation::from_deck(&run_deck, &layout.dem)?;
    let p = &sim.particles;
    Ok(PackedBed {
        ids: p.id.clone(),
        position: p.x.clone(),
        radius: p.radius.clone(),
        density: p.density.clone(),
    })
}
