//! CFDEM's models that observe a run and write what CFDEM writes: the auxiliary "force models"
//! `fieldStore`, `fieldTimeAverage`, `particleCellVolume`, `particleVolume`,
//! `volWeightedAverage`, `totalMomentumExchange` (listed in `forceModels`, they exert no
//! force), `clockModel standardClock` and `IOModel basicIO`/`sophIO`/`trackIO`. This module
//! reads their settings; [`crate::monitor`] computes their values and the runner writes them.

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

/// `fieldTimeAverage`: the running mean of each named field over the coupling steps from
/// `startTime`, written as `timeAverage_<name>` at the write times (CFDEM-PUBLIC's
/// `fieldTimeAverage.C`).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct FieldTimeAverage {
    /// `scalarFieldNames`.
    pub scalar_fields: Vec<String>,
    /// `vectorFieldNames`.
    pub vector_fields: Vec<String>,
    /// `startTime`, s (default 0).
    pub start_time: f64,
}

/// `particleVolume`: Σ 4πr³/3 over the particles whose centre lies in the mesh, each coupling
/// step from `startTime` (CFDEM-PUBLIC's `particleVolume.C`).
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleVolume {
    /// `startTime`, s (default 0).
    pub start_time: f64,
    /// `verbose`: the value goes to the log.
    pub verbose: bool,
    /// `writeToFile`: `postProcessing/particleVolume/<start>/particleVolume.txt`.
    pub write_to_file: bool,
}

/// `totalMomentumExchange`: the fluid–particle momentum exchange summed over the cells, its
/// implicit part Σ V Ksl (U − Us) and its explicit part −Σ V f (N, the force on the particles).
#[derive(Clone, Debug, PartialEq)]
pub struct TotalMomentumExchange {
    /// `explicitMomExFieldName`: `f` (the explicit part is summed) or `none`.
    pub explicit: bool,
    /// `startTime`, s (default 0).
    pub start_time: f64,
    /// `verbose` (CFDEM's header spells it `verbous`; both are read).
    pub verbose: bool,
    /// `writeToFile` (default on): `postProcessing/totalMomentumExchange/<start>/
    /// totalMomentumExchange.txt`.
    pub write_to_file: bool,
}

/// `probeModel particleProbe`: per-particle files of the force models' forces (CFDEM-PUBLIC's
/// `particleProbe.C`). A switch of `particleProbeProps` is on when its key is present, whatever
/// its value, as CFDEM reads them (`propsDict_.found("verboseToFile")`).
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleProbe {
    /// `particleIDsToSample`: the particle indices written (CFDEM's index in its particle
    /// arrays, from 0).
    pub ids: Vec<u64>,
    /// `sampleAll`: every particle.
    pub sample_all: bool,
    /// `verboseToFile`: without it nothing is written.
    pub verbose_to_file: bool,
    /// `printEvery` (coupling steps, default 1).
    pub print_every: u64,
    /// `printOnlyAtStep`: only at this coupling step.
    pub print_only_at: Option<u64>,
    /// `includePosition`: the particle's position after the force.
    pub include_position: bool,
    /// `probeDebug`: the header names every vector, not only the force.
    pub debug: bool,
    /// `writePrecision`: significant digits of the values (default 3).
    pub write_precision: usize,
}

/// `IOModel`: which particle files are written at the write times.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ParticleIo {
    /// `basicIO`: positions, v, r.
    #[default]
    Basic,
    /// `sophIO`: basicIO's and voidfractions, impForces, expForces, DEMForces.
    Soph,
    /// `trackIO`: sophIO's and id.
    Track,
}

/// The observing models of a configuration.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Monitors {
    /// `fieldStore`.
    pub field_store: Option<FieldStore>,
    /// `fieldTimeAverage`.
    pub field_time_average: Option<FieldTimeAverage>,
    /// `particleVolume`.
    pub particle_volume: Option<ParticleVolume>,
    /// `totalMomentumExchange`.
    pub total_momentum_exchange: Option<TotalMomentumExchange>,
    /// `particleCellVolume`.
    pub particle_cell_volume: Option<ParticleCellVolume>,
    /// `probeModel particleProbe`.
    pub particle_probe: Option<ParticleProbe>,
    /// `volWeightedAverage`.
    pub vol_weighted_average: Option<VolWeightedAverage>,
    /// `fieldVolWeighted` (ErgunTestMPI 2016; its source was never published): the
    /// volume-weighted average over every cell, in `volWeightedAverage`'s file layout
    /// (`field_vol_weighted` says what was chosen).
    pub field_vol_weighted: Option<VolWeightedAverage>,
    /// `checkCouplingInterval` ([`crate::interval_check`]).
    pub interval_check: Option<crate::interval_check::IntervalCheckSettings>,
    /// `clockModel standardClock`: the timing table at the end (log and `clockData/timeEval.txt`).
    pub clock: bool,
    /// `IOModel basicIO` (or `sophIO`/`trackIO`): particle positions, velocities and radii
    /// under `<time>/lagrangian/particleCloud/` at each write time.
    pub basic_io: bool,
    /// Which of the IO models writes them (with `basic_io`).
    pub particle_io: ParticleIo,
}

impl Monitors {
    /// True when a model reads whole cell fields (ε, the exchange fields, the fluid).
    pub fn needs_fields(&self) -> bool {
        self.field_store.is_some()
            || self.field_time_average.is_some()
            || self.total_momentum_exchange.is_some()
            || self.particle_cell_volume.is_some()
            || self.vol_weighted_average.is_some()
            || self.field_vol_weighted.is_some()
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

/// `fieldTimeAverage` of `forceModels`.
pub(super) fn field_time_average(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "scalarFieldNames",
            "vectorFieldNames",
            "startTime",
            "verbose",
        ],
    )?;
    s.monitors.field_time_average = Some(FieldTimeAverage {
        scalar_fields: field_names(r, props, dict, "scalarFieldNames", &SCALAR_FIELDS)?,
        vector_fields: field_names(r, props, dict, "vectorFieldNames", &VECTOR_FIELDS)?,
        start_time: number_or(r, props, dict, "startTime", 0.0)?,
    });
    Ok(())
}

/// `particleVolume` of `forceModels`.
pub(super) fn particle_volume(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(props, dict, &["startTime", "verbose", "writeToFile"])?;
    s.monitors.particle_volume = Some(ParticleVolume {
        start_time: number_or(r, props, dict, "startTime", 0.0)?,
        verbose: switch_or(r, props, dict, "verbose")?,
        write_to_file: switch_or(r, props, dict, "writeToFile")?,
    });
    Ok(())
}

/// `totalMomentumExchange` of `forceModels` (its Props as CFDEM's ErgunTestMPI tutorial of
/// 2012–2016 writes them: `implicitMomExFieldName "Ksl"`, `explicitMomExFieldName "none"`,
/// `fluidVelFieldName "U"`, `granVelFieldName "Us"`).
pub(super) fn total_momentum_exchange(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "implicitMomExFieldName",
            "explicitMomExFieldName",
            "fluidVelFieldName",
            "startTime",
            "verbose",
            "verbous",
            "writeToFile",
        ],
    )?;
    for (key, standard) in [
        ("implicitMomExFieldName", "Ksl"),
        ("fluidVelFieldName", "U"),
    ] {
        let path = format!("{dict}/{key}");
        if let Some(given) = r.opt_word(props, key, &path)? {
            if given != standard {
                return Err(r.err(
                    &path,
                    format!("foamgrain holds `{standard}`, not `{given}`"),
                ));
            }
        }
    }
    let path = format!("{dict}/explicitMomExFieldName");
    let explicit = match r.opt_word(props, "explicitMomExFieldName", &path)? {
        None | Some("f") => true,
        Some("none") => false,
        Some(other) => {
            return Err(r.err(&path, format!("`f` or `none`, not `{other}`")));
        }
    };
    s.monitors.total_momentum_exchange = Some(TotalMomentumExchange {
        explicit,
        start_time: number_or(r, props, dict, "startTime", 0.0)?,
        verbose: switch_or(r, props, dict, "verbose")? || switch_or(r, props, dict, "verbous")?,
        write_to_file: r
            .opt_switch(props, "writeToFile", &format!("{dict}/writeToFile"))?
            .unwrap_or(true),
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
    let bounds = (
        r.number(props, "lowerThreshold", &format!("{dict}/lowerThreshold"))?,
        r.number(props, "upperThreshold", &format!("{dict}/upperThreshold"))?,
    );
    let write_to_file = switch_or(r, props, dict, "writeToFile")?;
    s.monitors.vol_weighted_average = Some(vol_weighted(r, props, dict, bounds, write_to_file)?);
    Ok(())
}

/// The settings of `volWeightedAverage` and `fieldVolWeighted` but for the thresholds
/// `bounds` and `write_to_file`.
fn vol_weighted(
    r: &Reader<'_>,
    props: &Dict,
    dict: &str,
    (lower, upper): (f64, f64),
    write_to_file: bool,
) -> Result<VolWeightedAverage, CoupleError> {
    volume_fraction_name(r, props, dict)?;
    Ok(VolWeightedAverage {
        scalar_fields: field_names(r, props, dict, "scalarFieldNames", &SCALAR_FIELDS)?,
        vector_fields: field_names(r, props, dict, "vectorFieldNames", &VECTOR_FIELDS)?,
        lower,
        upper,
        use_volume_fraction: switch_or(r, props, dict, "useVolumeFraction")?,
        start_time: number_or(r, props, dict, "startTime", 0.0)?,
        verbose: switch_or(r, props, dict, "verbose")?,
        write_to_file,
    })
}

/// `fieldVolWeighted` of `forceModels`: CFDEM's source of this model was never published;
/// only its Props in the ErgunTestMPI tutorial of 2016 (`startTime`, `scalarFieldNames`,
/// `vectorFieldNames`, `useVolumeFraction`, `volumeFractionName`). foamgrain reads those keys
/// and makes it what its name and keys say: the volume-weighted average Σ φ V (ε) / Σ V of each
/// named field over **every** cell (it has no thresholds, unlike `volWeightedAverage`), each
/// coupling step from `startTime`, written to `postProcessing/fieldVolWeighted/<start>/
/// fieldVolWeighted.txt` in `volWeightedAverage`'s layout (`# time | name …`, one row per
/// step). `verbose` puts the values in the log too; no fields are written.
pub(super) fn field_vol_weighted(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "scalarFieldNames",
            "vectorFieldNames",
            "useVolumeFraction",
            "volumeFractionName",
            "startTime",
            "verbose",
        ],
    )?;
    let all = (f64::NEG_INFINITY, f64::INFINITY);
    s.monitors.field_vol_weighted = Some(vol_weighted(r, props, dict, all, true)?);
    Ok(())
}

/// `volumeFractionName`, if given, must be the field foamgrain holds.
fn volume_fraction_name(r: &Reader<'_>, props: &Dict, dict: &str) -> Result<(), CoupleError> {
    if props.contains("volumeFractionName") {
        let path = format!("{dict}/volumeFractionName");
        let name = r.word(props, "volumeFractionName", &path)?;
        if name != "voidfraction" {
            return Err(r.err(&path, format!("only `voidfraction` is held, not `{name}`")));
        }
    }
    Ok(())
}

/// `checkCouplingInterval` of `forceModels` ([`crate::interval_check`] has what it reports).
/// CFDEM-PUBLIC requires `rhoP` and `UmaxExpected`; foamgrain takes each particle's own
/// density without `rhoP` and leaves the expected CFL out without `UmaxExpected`.
/// `maxRelVelChange` is read but its check (|∇U| along a particle's path) is not made: a
/// warning says so.
pub(super) fn check_coupling_interval(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    use crate::interval_check::IntervalCheckSettings;
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "warnOnly",
            "velocityFieldName",
            "rhoP",
            "maxCFL",
            "maxPCFL",
            "maxAccNr",
            "maxRelVelChange",
            "UmaxExpected",
            "minAllowedVcellByVparcel",
            "largeVcellByVparcel",
            "timeInterval",
            "verbose",
        ],
    )?;
    let d = IntervalCheckSettings::default();
    let positive = |key: &str, default: f64| -> Result<f64, CoupleError> {
        let x = number_or(r, props, dict, key, default)?;
        match x.is_finite() && x > 0.0 {
            true => Ok(x),
            false => Err(r.err(&format!("{dict}/{key}"), format!("{x} is not positive"))),
        }
    };
    let optional = |key: &str| -> Result<Option<f64>, CoupleError> {
        match props.contains(key) {
            true => positive(key, 0.0).map(Some),
            false => Ok(None),
        }
    };
    let settings = IntervalCheckSettings {
        rho_p: optional("rhoP")?,
        warn_only: r
            .opt_switch(props, "warnOnly", &format!("{dict}/warnOnly"))?
            .unwrap_or(true),
        max_cfl: positive("maxCFL", d.max_cfl)?,
        max_pcfl: positive("maxPCFL", d.max_pcfl)?,
        max_acc_nr: positive("maxAccNr", d.max_acc_nr)?,
        u_max_expected: optional("UmaxExpected")?,
        min_vcell_by_vparcel: positive("minAllowedVcellByVparcel", d.min_vcell_by_vparcel)?,
        large_vcell_by_vparcel: positive("largeVcellByVparcel", d.large_vcell_by_vparcel)?,
        time_interval: optional("timeInterval")?,
    };
    if props.contains("maxRelVelChange") {
        r.warn(format!(
            "{dict}/maxRelVelChange: the change of the fluid velocity along a particle's path              (|grad U| max|v| couplingTime) is not checked"
        ));
    }
    s.monitors.interval_check = Some(settings);
    Ok(())
}

/// `probeModel particleProbe`, from `particleProbeProps`.
pub(super) fn particle_probe(r: &mut Reader, g: &Given, s: &mut Setup) -> Built {
    let (props, dict) = &g.props(r)?;
    r.check_props(
        props,
        dict,
        &[
            "particleIDsToSample",
            "verbose",
            "verboseToFile",
            "printEvery",
            "printOnlyAtStep",
            "sampleAll",
            "probeDebug",
            "includePosition",
            "writePrecision",
        ],
    )?;
    if props.contains("probeDebug") {
        r.warn(format!(
            "{dict}/probeDebug: the header names every probed vector, but the force models' \
             internal scalars (Rep, Cd, β, Vs…) are not written"
        ));
    }
    let path = format!("{dict}/particleIDsToSample");
    let listed = match props.stream("particleIDsToSample") {
        Ok([item]) | Ok([foam::Item::Label(_), item]) => item.as_f64_list(),
        _ => None,
    };
    let listed =
        listed.ok_or_else(|| r.err(&path, "expected a list of particle indices `( 0 1 … )`"))?;
    let ids = listed
        .iter()
        .map(|&x| match x >= 0.0 && x.fract() == 0.0 {
            true => Ok(x as u64),
            false => Err(r.err(&path, format!("{x} is not a particle index ≥ 0"))),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let count = |key: &str, default: u64| -> Result<u64, CoupleError> {
        let path = format!("{dict}/{key}");
        match props.contains(key) {
            false => Ok(default),
            true => match r.number(props, key, &path)? {
                x if x >= 1.0 && x.fract() == 0.0 => Ok(x as u64),
                x => Err(r.err(&path, format!("{x} is not a whole number ≥ 1"))),
            },
        }
    };
    s.monitors.particle_probe = Some(ParticleProbe {
        ids,
        sample_all: props.contains("sampleAll"),
        verbose_to_file: props.contains("verboseToFile"),
        print_every: count("printEvery", 1)?,
        print_only_at: match props.contains("printOnlyAtStep") {
            true => Some(count("printOnlyAtStep", 1)?),
            false => None,
        },
        include_position: props.contains("includePosition"),
        debug: props.contains("probeDebug"),
        write_precision: count("writePrecision", 3)? as usize,
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

/// `IOModel sophIO`: basicIO's files and the per-particle voidfractions and forces.
pub(super) fn soph_io(_: &mut Reader, _: &Given, s: &mut Setup) -> Built {
    s.monitors.basic_io = true;
    s.monitors.particle_io = ParticleIo::Soph;
    Ok(())
}

/// `IOModel trackIO`: sophIO's files and the particle ids.
pub(super) fn track_io(_: &mut Reader, _: &Given, s: &mut Setup) -> Built {
    s.monitors.basic_io = true;
    s.monitors.particle_io = ParticleIo::Track;
    Ok(())
}
