//! CFDEM's model families, one table each: every name CFDEM's `couplingProperties` accepts for
//! a family, and what foamgrain does with it.
//!
//! A reader who knows a CFDEM keyword finds its handling here by grepping the name. A name is
//! one of:
//! * [`Support::Acts`]: it selects foamgrain code (the family's reader builds the setting);
//! * [`Support::Same`]: foamgrain always behaves as the name asks (e.g. `locateModel engine`:
//!   foamgrain's locator finds the same cells), accepted silently;
//! * [`Support::Warn`]: accepted, but it changes nothing in foamgrain; one warning line says
//!   what foamgrain does instead;
//! * [`Support::Refuse`]: a CFDEM model foamgrain does not implement; an error that says what
//!   to use instead.
//!
//! A name in no table is an error listing the family's valid names.

/// What foamgrain does with one model name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Support {
    /// Implemented: the family's reader turns it into a setting.
    Acts,
    /// foamgrain always does what the name asks; accepted silently.
    Same,
    /// Accepted without effect; the text (one sentence) is the warning.
    Warn(&'static str),
    /// Not implemented; the text says what to use instead.
    Refuse(&'static str),
}

/// One model family: the `couplingProperties` key and its names.
#[derive(Clone, Copy, Debug)]
pub struct Family {
    /// The key (`locateModel`) or list (`forceModels`) that selects models of this family.
    pub key: &'static str,
    /// Every name foamgrain knows, with its handling.
    pub models: &'static [(&'static str, Support)],
}

impl Family {
    /// The handling of `name`, or `None` when the family has no such name.
    pub fn support(&self, name: &str) -> Option<Support> {
        self.models
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, s)| s)
    }

    /// The names a user may write (everything not refused), for error messages.
    pub fn valid_names(&self) -> String {
        self.models
            .iter()
            .filter(|(_, s)| !matches!(s, Support::Refuse(_)))
            .map(|(n, _)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

use Support::{Acts, Refuse, Same, Warn};

/// `locateModel`: which cell holds a particle.
pub const LOCATE: Family = Family {
    key: "locateModel",
    models: &[
        ("engine", Same),
        ("engineIB", Same),
        ("standard", Same),
        ("turboEngine", Same),
        ("turboEngineM2M", Same),
        ("engineSearchMany2Many", Same),
    ],
};

/// `meshMotionModel`.
pub const MESH_MOTION: Family = Family {
    key: "meshMotionModel",
    models: &[("noMeshMotion", Same)],
};

/// `regionModel` (CFDEM-PFM).
pub const REGION: Family = Family {
    key: "regionModel",
    models: &[("allRegion", Same)],
};

/// `smoothingModel`.
pub const SMOOTHING: Family = Family {
    key: "smoothingModel",
    models: &[
        ("off", Same),
        ("noSmoothing", Same),
        ("constDiffSmoothing", Acts),
        (
            "localPSizeDiffSmoothing",
            Refuse("not implemented; use `constDiffSmoothing` or `off`"),
        ),
        (
            "temporalSmoothing",
            Refuse("not implemented; use `constDiffSmoothing` or `off`"),
        ),
        (
            "constDiffAndTemporalSmoothing",
            Refuse("not implemented; use `constDiffSmoothing` or `off`"),
        ),
    ],
};

/// `averagingModel`: how Us is averaged over a cell's particles.
pub const AVERAGING: Family = Family {
    key: "averagingModel",
    models: &[
        ("dense", Same),
        (
            "dilute",
            Warn(
                "foamgrain's Us is always the β-weighted average of the particle velocities \
                 (dense)",
            ),
        ),
    ],
};

/// `dataExchangeModel`: how CFDEM talks to LIGGGHTS. foamgrain's `--dem` option chooses the
/// DEM; the name only selects which `<name>Props` gives `liggghtsPath`.
pub const DATA_EXCHANGE: Family = Family {
    key: "dataExchangeModel",
    models: &[
        ("twoWayMPI", Same),
        ("twoWayM2M", Same),
        ("twoWayOne2One", Same),
        ("twoWayFiles", Same),
        ("oneWayVTK", Same),
        ("noDataExchange", Same),
    ],
};

/// `IOModel`: particle output at the fluid's write times.
pub const IO: Family = Family {
    key: "IOModel",
    models: &[
        ("off", Same),
        ("basicIO", Acts),
        (
            "trackIO",
            Warn("foamgrain writes basicIO's files (positions, v, r), not trackIO's"),
        ),
        (
            "sophIO",
            Warn("foamgrain writes basicIO's files (positions, v, r), not sophIO's"),
        ),
    ],
};

/// `probeModel`.
pub const PROBE: Family = Family {
    key: "probeModel",
    models: &[
        ("off", Same),
        (
            "particleProbe",
            Warn("particle probes are not written (postProcessing/particles/*.vtp has every particle's state at the write times)"),
        ),
    ],
};

/// `clockModel`: the timing table.
pub const CLOCK: Family = Family {
    key: "clockModel",
    models: &[("off", Same), ("standardClock", Acts)],
};

/// `momCoupleModels`: how the particles' reaction reaches the fluid.
pub const MOM_COUPLE: Family = Family {
    key: "momCoupleModels",
    models: &[
        ("implicitCouple", Acts),
        ("explicitCouple", Acts),
        ("off", Same),
        ("noCouple", Same),
        ("explicitCoupleSource", Refuse("use explicitCouple")),
    ],
};

/// `forceModels` other than the drag laws (those are [`closures::DRAG_LAW_NAMES`], all acting).
pub const FORCES: Family = Family {
    key: "forceModels",
    models: &[
        ("gradPForce", Acts),
        ("viscForce", Acts),
        ("Archimedes", Acts),
        ("noDrag", Acts),
        ("fieldStore", Acts),
        ("particleCellVolume", Acts),
        ("volWeightedAverage", Acts),
        ("virtualMassForce", Refuse("not implemented")),
        ("MeiLift", Refuse("not implemented")),
        ("SaffmanLift", Refuse("not implemented")),
        (
            "ArchimedesIB",
            Refuse("immersed-boundary models are not implemented"),
        ),
        (
            "ShirgaonkarIB",
            Refuse("immersed-boundary models are not implemented"),
        ),
        ("DEMbasedDrag", Refuse("use one of the drag laws")),
        ("RongDrag", Refuse("use one of the drag laws")),
        ("totalMomentumExchange", Refuse("not implemented")),
        ("fieldTimeAverage", Refuse("not implemented")),
        ("fieldVolWeighted", Refuse("not implemented")),
        ("LaEuScalarTemp", Refuse("heat transfer is not implemented")),
        (
            "scalarGeneralExchange",
            Refuse("heat transfer is not implemented"),
        ),
    ],
};

/// `liggghtsCommandModels` of `constant/liggghtsCommands` ([`super::commands`]).
pub const LIGGGHTS_COMMANDS: Family = Family {
    key: "liggghtsCommandModels",
    models: &[
        ("runLiggghts", Same),
        ("writeLiggghts", Acts),
        ("execute", Acts),
        (
            "readLiggghtsData",
            Refuse("use `execute` with a read_data command"),
        ),
        (
            "setDEMGravity",
            Refuse("set gravity in the deck (`fix … gravity`)"),
        ),
    ],
};

/// Top-level single-name families, checked the same way: the key, its table.
pub const SINGLE_NAME: [Family; 8] = [
    LOCATE,
    MESH_MOTION,
    REGION,
    SMOOTHING,
    AVERAGING,
    DATA_EXCHANGE,
    IO,
    PROBE,
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_within_a_family() {
        for f in SINGLE_NAME
            .iter()
            .chain([&CLOCK, &MOM_COUPLE, &FORCES, &LIGGGHTS_COMMANDS])
        {
            for (i, (a, _)) in f.models.iter().enumerate() {
                assert!(
                    f.models[i + 1..].iter().all(|(b, _)| a != b),
                    "{}: `{a}` twice",
                    f.key
                );
            }
        }
    }

    #[test]
    fn refused_names_are_not_offered() {
        let names = SMOOTHING.valid_names();
        assert_eq!(names, "off, noSmoothing, constDiffSmoothing");
        assert_eq!(
            SMOOTHING
                .support("temporalSmoothing")
                .map(|s| matches!(s, Refuse(_))),
            Some(true)
        );
        assert_eq!(LOCATE.support("nowhere"), None);
    }
}
