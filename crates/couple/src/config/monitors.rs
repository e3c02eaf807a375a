//! CFDEM's models that observe a run and write what CFDEM writes: the auxiliary "force models"
//! `fieldStore`, `particleCellVolume`, `volWeightedAverage` (listed in `forceModels`, they
//! exert no force), `clockModel standardClock` and `IOModel basicIO`. This module reads their
//! settings; [`crate::monitor`] computes their values and the runner writes them.

use super::{Built, Given, Reader, Setup};
use crate::error::CoupleError;
use foam::Dict;

/// Scalar cell fields a monitor may name (what foamgrain's coupled run holds).
pub const SCALAR_FIELDS: [&str; 5] = ["voidfraction", "ddtVoidfraction", "p", "Ksl", "rho"];
/// Vector cell fields a monitor may name.
pub const VECTOR_FIELDS: [&str; 3] = ["U", "Us", "f"];

/// `fieldStore`: copies of fields kept as `stored_<name>` and written at the write times.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct FieldStore {
    /// `scalarFieldNames`.
    pub scalar_fields: Vec<String>,
    /// `vectorFieldNames`.
    pub vector_fields: Vec<String>,
}

/// `particleCellVolume`: the particle volume Σ (1 − ε) V over the cells whose ε lies strictly
/// between the thresholds, the volume of those cells, their ratio and ε's range there.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleCellVolume {
    /// `lowerThreshold` (CFDEM's default −0.01).
    pub lower: f64,
    /// `upperThreshold` (default 1.01).
    pub upper: f64,
    /// `startTime`, s (default 0): nothing is computed before.
    pub start_time: f64,
    /// `verbose`: the values go to the log every coupling step.
    pub verbose: bool,
    /// `writeToFile`: `postProcessing/particleCellVolume/<start>/particleCellVolume.txt`.
    pub write_to_file: bool,
}

/// `volWeightedAverage`: Σ φ V (ε) / Σ V over the cells where φ (|φ| for vectors) lies
/// strictly between the thresholds, per named field.
#[derive(Clone, Debug, PartialEq)]
pub struct VolWeightedAverage {
    /// `scalarFieldNames`.
    pub scalar_fields: Vec<String>,
    /// `vectorFieldNames`.
    pub vector_fields: Vec<String>,
    /// `lowerThreshold` (required).
    pub lower: f64,
    /// `upperThreshold` (required).
    pub upper: f64,
    /// `useVolumeFraction`: weight by ε as well (default false).
    pub use_volume_fraction: bool,
    /// `startTime`, s (default 0).
    pub start_time: f64,
    /// `verbose`.
    pub verbose: bool,
    /// `writeToFile`: `postProcessing/volWeightedAverage/<start>/volWeightedAverage.txt`.
    pub write_to_file: bool,
}

/// The observing models of a configuration.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Monitors {
    /// `fieldStore`.
    pub field_store: Option<FieldStore>,
    /// `particleCellVolume`.
    pub particle_cell_volume: Option<ParticleCellVolume>,
    /// `volWeightedAverage`.
    pub vol_weighted_average: Option<VolWeightedAverage>,
    /// `clockModel standardClock`: the timing table at the end (log and `clockData/timeEval.txt`).
    pub clock: bool,
    /// `IOModel basicIO`: particle positions, velocities and radii under
    /// `<time>/lagrangian/particleCloud/` at each write time.
    pub basic_io: bool,
}

impl Monitors {
    /// True when a model reads whole cell fields (ε, the exchange fields, the fluid).
    pub fn needs_fields(&self) -> bool {
        self.field_store.is_some()
            || self.particle_cell_volume.is_some()
            || self.vol_weighted_average.is_some()
    }
}

fn field_names(
    r: &Reader<'_>,
    props: &Dict,
    dict: &str,
    key: &str,
    valid: &[&str],
) -> Result<Vec<String>, CoupleError> {
    let path = format!("{dict}/{key}");
    let names = r.word_list_at(props, key, &path)?;
    for n in &names {
        if !valid.contains(&n.as_str()) {
            return Err(r.err(
                &path,
                format!(
                    "foamgrain has no field `{n}` to observe; fields: {}",
                    valid.join(", ")
                ),
            ));
        }
    }
    Ok(names)
}

fn number_or(
    r: &Reader<'_>,
    props: &Dict,
    dict: &str,
    key: &str,
    default: f64,
) -> Result<f64, CoupleError> {
    match props.contains(key) {
        true => r.number(props, key, &format!("{dict}/{key}")),
        false => Ok(default),
    }
}

fn switch_or(r: &Reader<'_>, props: &Dict, dict: &str, key: &str) -> Result<bool, CoupleError> {
    Ok(r.opt_switch(props, key, &format!("{dict}/{key}"))?
        .unwrap_or(false))
}

/// `fieldStore` of `forceModels`.
pub(super) fn field_store(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &["scalarFieldNames", "vectorFieldNames", "verbose"],
    )?;
    s.monitors.field_store = Some(FieldStore {
        scalar_fields: field_names(r, props, dict, "scalarFieldNames", &SCALAR_FIELDS)?,
        vector_fields: field_names(r, props, dict, "vectorFieldNames", &VECTOR_FIELDS)?,
    });
    Ok(())
}

/// `particleCellVolume` of `forceModels`.
pub(super) fn particle_cell_volume(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "upperThreshold",
            "lowerThreshold",
            "startTime",
            "verbose",
            "writeToFile",
        ],
    )?;
    s.monitors.particle_cell_volume = Some(ParticleCellVolume {
        lower: number_or(r, props, dict, "lowerThreshold", -0.01)?,
        upper: number_or(r, props, dict, "upperThreshold", 1.01)?,
        start_time: number_or(r, props, dict, "startTime", 0.0)?,
        verbose: switch_or(r, props, dict, "verbose")?,
        write_to_file: switch_or(r, props, dict, "writeToFile")?,
    });
    Ok(())
}

/// `volWeightedAverage` of `forceModels`.
pub(super) fn vol_weighted_average(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "scalarFieldNames",
            "vectorFieldNames",
            "upperThreshold",
            "lowerThreshold",
            "useVolumeFraction",
            "volumeFractionName",
            "startTime",
            "verbose",
            "writeToFile",
        ],
    )?;
    if props.contains("volumeFractionName") {
        let path = format!("{dict}/volumeFractionName");
        let name = r.word(props, "volumeFractionName", &path)?;
        if name != "voidfraction" {
            return Err(r.err(&path, format!("only `voidfraction` is held, not `{name}`")));
        }
    }
    s.monitors.vol_weighted_average = Some(VolWeightedAverage {
        scalar_fields: field_names(r, props, dict, "scalarFieldNames", &SCALAR_FIELDS)?,
        vector_fields: field_names(r, props, dict, "vectorFieldNames", &VECTOR_FIELDS)?,
        lower: r.number(props, "lowerThreshold", &format!("{dict}/lowerThreshold"))?,
        upper: r.number(props, "upperThreshold", &format!("{dict}/upperThreshold"))?,
        use_volume_fraction: switch_or(r, props, dict, "useVolumeFraction")?,
        start_time: number_or(r, props, dict, "startTime", 0.0)?,
        verbose: switch_or(r, props, dict, "verbose")?,
        write_to_file: switch_or(r, props, dict, "writeToFile")?,
    });
    Ok(())
}

/// `clockModel standardClock`: the timing table (no Props read).
pub(super) fn standard_clock(_: &mut Reader, _: &Given, s: &mut Setup) -> Built {
    s.monitors.clock = true;
    Ok(())
}

/// `IOModel basicIO`: particle output at the write times (no Props read).
pub(super) fn basic_io(_: &mut Reader, _: &Given, s: &mut Setup) -> Built {
    s.monitors.basic_io = true;
    Ok(())
}
