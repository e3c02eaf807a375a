//! CFDEM's model families, one table each: every name CFDEM's `couplingProperties` (and
//! `liggghtsCommands`) accepts for a family, and what foamgrain does with it.
//!
//! A reader who knows a CFDEM keyword finds its handling here by grepping the name. A row is
//! `(name, model)`: the CFDEM name, its other spellings ([`Model::aliases`]) and its
//! [`Support`], one of:
//! * [`Support::Acts`]: it selects foamgrain code; the row holds its constructor ([`Build`]),
//!   the fn that reads the model's `<name>Props` (the keys it reads are in that fn) and sets
//!   the model's typed setting in the configuration being read;
//! * [`Support::Same`]: foamgrain always behaves as the name asks (e.g. `locateModel engine`:
//!   foamgrain's locator finds the same cells), accepted silently;
//! * [`Support::Warn`]: accepted, but it changes nothing in foamgrain; one warning line says
//!   what foamgrain does instead;
//! * [`Support::Refuse`]: a CFDEM model foamgrain does not implement; an error that says what
//!   to use instead.
//!
//! A name in no row is an error listing the family's valid names. A family's reader looks the
//! name up, warns or refuses as the row says and calls the row's constructor; it has no
//! `match` on names of its own. The names of two families come from the crate that defines
//! the models: the voidage methods' spellings are [`voidage::Method::names`] ([`VOIDAGE`]),
//! the drag laws are [`closures::DRAG_LAW_NAMES`] ([`DRAG_LAWS`]).
//!
//! **Adding a model** is one row here and one constructor fn in the file of its family
//! (`forces.rs` for `forceModels`, `monitors.rs`, `momentum.rs`, `smoothing.rs`,
//! `void_fraction.rs`, `commands.rs`), plus the field of its typed setting. A constructor has the
//! signature of [`Build`]: it gets the `Reader` (errors and warnings name the file and key),
//! the `Given` name (as written, maybe an alias) with the dictionary holding it, and the
//! `Setup` to set. The test `every_row_is_reached` walks every row of every family by each of
//! its spellings (with the Props of its `REQUIRED_PROPS` for keys that have no default, where
//! a new model's required keys go), so a row without a working constructor fails it.

use super::{bed_heat, commands, forces, heat, momentum, monitors, smoothing, void_fraction};
use super::{Built, Given, Reader, Setup};
use closures::DragLaw;
use voidage::Method;
use Support::{Acts, Refuse, Same, Warn};

/// The signature of a constructor: reads the model's Props and sets its typed setting.
pub(super) type BuildFn = fn(&mut Reader<'_>, &Given<'_>, &mut Setup) -> Built;

/// An acting model's constructor (a `BuildFn`).
#[derive(Clone, Copy)]
pub struct Build(pub(super) BuildFn);

impl std::fmt::Debug for Build {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Build(fn)")
    }
}

impl PartialEq for Build {
    fn eq(&self, other: &Build) -> bool {
        std::ptr::fn_addr_eq(self.0, other.0)
    }
}

impl Eq for Build {}

/// What foamgrain does with one model name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Support {
    /// Implemented: the constructor turns it (and its Props) into a setting.
    Acts(Build),
    /// foamgrain always does what the name asks; accepted silently.
    Same,
    /// Accepted without effect; the text (one sentence) is the warning.
    Warn(&'static str),
    /// Not implemented; the text says what to use instead.
    Refuse(&'static str),
}

/// One model of a family (the second half of a row; the first is its CFDEM name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Model {
    /// Other spellings that select the same model.
    pub aliases: &'static [&'static str],
    /// What foamgrain does with it.
    pub support: Support,
}

impl Model {
    /// The same model, also selected by `aliases`.
    const fn aka(self, aliases: &'static [&'static str]) -> Model {
        Model { aliases, ..self }
    }
}

/// An acting model built by `build`.
const fn acts(build: BuildFn) -> Model {
    Model {
        aliases: &[],
        support: Acts(Build(build)),
    }
}

/// A model foamgrain always follows.
const SAME: Model = Model {
    aliases: &[],
    support: Same,
};

/// A model accepted with the warning `why`.
#[allow(dead_code)] // no row warns at present; the kind stays for the tables
const fn warn(why: &'static str) -> Model {
    Model {
        aliases: &[],
        support: Warn(why),
    }
}

/// A model refused, `instead` saying what to use.
const fn refuse(instead: &'static str) -> Model {
    Model {
        aliases: &[],
        support: Refuse(instead),
    }
}

/// The row of voidage method `m`: its names from [`Method::names`], the first the CFDEM name.
const fn method(m: Method, build: BuildFn) -> (&'static str, Model) {
    match m.names().split_first() {
        Some((name, aliases)) => (*name, acts(build).aka(aliases)),
        None => panic!("a voidage method without a name"),
    }
}

/// One model family: the `couplingProperties` key and its rows.
#[derive(Clone, Copy, Debug)]
pub struct Family {
    /// The key (`locateModel`) or list (`forceModels`) that selects models of this family.
    pub key: &'static str,
    /// Every model foamgrain knows, by CFDEM name, with its aliases and handling.
    pub models: &'static [(&'static str, Model)],
}

impl Family {
    /// The handling of `name` (a model's name or one of its aliases), or `None` when the
    /// family has no such name.
    pub fn support(&self, name: &str) -> Option<Support> {
        self.models
            .iter()
            .find(|(n, m)| *n == name || m.aliases.contains(&name))
            .map(|(_, m)| m.support)
    }

    /// The names a user may write (everything not refused, aliases after their name), for
    /// error messages.
    pub fn valid_names(&self) -> String {
        self.models
            .iter()
            .filter(|(_, m)| !matches!(m.support, Support::Refuse(_)))
            .flat_map(|(n, m)| std::iter::once(n).chain(m.aliases))
            .copied()
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `voidFractionModel`: how a particle's volume is shared among cells. The names and aliases
/// are [`Method::names`] (the one list of voidage spellings, also the command line's).
pub const VOIDAGE: Family = Family {
    key: "voidFractionModel",
    models: &[
        method(Method::Centre, void_fraction::centre),
        method(Method::Divided, void_fraction::divided),
        method(Method::Trilinear, void_fraction::trilinear),
        method(Method::Cube, void_fraction::cube),
        method(Method::CorrectedCube, void_fraction::corrected_cube),
        method(Method::Exact, void_fraction::exact),
        method(Method::BigParticle, void_fraction::big_particle),
        method(Method::Gauss, void_fraction::gauss),
        ("IBVoidFraction", refuse("use exact")),
        (
            "dividedSmooth",
            refuse(
                "no such model in CFDEMcoupling-PUBLIC or -PFM (sources, tutorials, documentation \
                 and their git histories); use divided or exact",
            ),
        ),
    ],
};

/// The drag laws of `forceModels`: closures' list (a name or alias, and its law), every row
/// acting, with the one constructor `forces::drag` (the `<law>Props` keys it reads are
/// `forces::drag_keys`).
pub const DRAG_LAWS: &[(&str, DragLaw)] = &closures::DRAG_LAW_NAMES;

/// `locateModel`: which cell holds a particle.
pub const LOCATE: Family = Family {
    key: "locateModel",
    models: &[
        ("engine", SAME),
        ("engineIB", SAME),
        ("standard", SAME),
        ("turboEngine", SAME),
        ("turboEngineM2M", SAME),
        ("engineSearchMany2Many", SAME),
    ],
};

/// `meshMotionModel`.
pub const MESH_MOTION: Family = Family {
    key: "meshMotionModel",
    models: &[("noMeshMotion", SAME)],
};

/// `regionModel` (CFDEM-PFM).
pub const REGION: Family = Family {
    key: "regionModel",
    models: &[("allRegion", SAME)],
};

/// `smoothingModel`.
pub const SMOOTHING: Family = Family {
    key: "smoothingModel",
    models: &[
        ("off", SAME),
        ("noSmoothing", SAME),
        ("constDiffSmoothing", acts(smoothing::const_diff)),
        (
            "localPSizeDiffSmoothing",
            acts(smoothing::local_p_size_diff),
        ),
        ("temporalSmoothing", acts(smoothing::temporal)),
        (
            "constDiffAndTemporalSmoothing",
            acts(smoothing::const_diff_and_temporal),
        ),
    ],
};

/// `averagingModel`: how Us is averaged over a cell's particles.
pub const AVERAGING: Family = Family {
    key: "averagingModel",
    models: &[("dense", SAME), ("dilute", acts(momentum::dilute))],
};

/// `dataExchangeModel`: how CFDEM talks to LIGGGHTS. foamgrain's `--dem` option chooses the
/// DEM; the name only selects which `<name>Props` gives `liggghtsPath`.
pub const DATA_EXCHANGE: Family = Family {
    key: "dataExchangeModel",
    models: &[
        ("twoWayMPI", SAME),
        ("twoWayM2M", SAME),
        ("twoWayOne2One", SAME),
        ("twoWayFiles", SAME),
        ("oneWayVTK", SAME),
        ("noDataExchange", SAME),
    ],
};

/// `IOModel`: particle output at the fluid's write times.
pub const IO: Family = Family {
    key: "IOModel",
    models: &[
        ("off", SAME),
        ("basicIO", acts(monitors::basic_io)),
        ("trackIO", acts(monitors::track_io)),
        ("sophIO", acts(monitors::soph_io)),
    ],
};

/// `probeModel`.
pub const PROBE: Family = Family {
    key: "probeModel",
    models: &[
        ("off", SAME),
        ("particleProbe", acts(monitors::particle_probe)),
    ],
};

/// `clockModel`: the timing table.
pub const CLOCK: Family = Family {
    key: "clockModel",
    models: &[
        ("off", SAME),
        ("standardClock", acts(monitors::standard_clock)),
    ],
};

/// `momCoupleModels`: how the particles' reaction reaches the fluid.
pub const MOM_COUPLE: Family = Family {
    key: "momCoupleModels",
    models: &[
        ("implicitCouple", acts(momentum::implicit)),
        ("explicitCouple", acts(momentum::explicit)),
        ("off", SAME),
        // PFM's deactivateCouple hands the fluid zero Ksl and f, as noCouple
        ("noCouple", SAME.aka(&["deactivateCouple"])),
        (
            "explicitCoupleSource",
            refuse(
                "only named in CFDEMcoupling-PUBLIC's periodicPressure documentation; its source \
                 is in neither CFDEMcoupling-PUBLIC nor -PFM (nor their git histories); use \
                 explicitCouple",
            ),
        ),
    ],
};

/// Why `DEMbasedDrag` and `RongDrag` are refused.
const UNPUBLISHED_DRAG: &str = "named in CFDEM's tutorials (ErgunTestMPI, PFM's multiphase \
    cases) with empty Props, but its source is in neither CFDEMcoupling-PUBLIC nor -PFM (nor \
    their git histories); use one of the drag laws";

/// `forceModels` other than the drag laws (those are [`closures::DRAG_LAW_NAMES`], all acting).
pub const FORCES: Family = Family {
    key: "forceModels",
    models: &[
        ("gradPForce", acts(forces::grad_p)),
        ("viscForce", acts(forces::viscous)),
        ("Archimedes", acts(forces::archimedes)),
        ("noDrag", acts(forces::no_drag)),
        ("fieldStore", acts(monitors::field_store)),
        ("particleCellVolume", acts(monitors::particle_cell_volume)),
        ("volWeightedAverage", acts(monitors::vol_weighted_average)),
        ("virtualMassForce", acts(forces::virtual_mass)),
        ("MeiLift", acts(forces::mei_lift)),
        ("SaffmanLift", acts(forces::saffman_lift)),
        (
            "ArchimedesIB",
            refuse("immersed-boundary models are not implemented"),
        ),
        (
            "ShirgaonkarIB",
            refuse("immersed-boundary models are not implemented"),
        ),
        ("DEMbasedDrag", refuse(UNPUBLISHED_DRAG)),
        ("RongDrag", refuse(UNPUBLISHED_DRAG)),
        ("KochHillRWDrag", acts(forces::koch_hill_rw)),
        (
            "totalMomentumExchange",
            acts(monitors::total_momentum_exchange),
        ),
        ("fieldTimeAverage", acts(monitors::field_time_average)),
        ("particleVolume", acts(monitors::particle_volume)),
        ("fieldVolWeighted", acts(monitors::field_vol_weighted)),
        (
            "checkCouplingInterval",
            acts(monitors::check_coupling_interval),
        ),
        ("LaEuScalarTemp", acts(heat::la_eu_scalar_temp)),
        ("scalarGeneralExchange", acts(heat::scalar_general_exchange)),
    ],
};

/// `energyModels` (CFDEM-PFM): the heat exchanged with the particles ([`super::heat`]).
pub const ENERGY: Family = Family {
    key: "energyModels",
    models: &[
        ("heatTransferGunn", acts(heat::heat_transfer_gunn)),
        ("off", SAME),
        (
            "heatTransferRanzMarshall",
            acts(heat::heat_transfer_ranz_marshall),
        ),
        (
            "heatTransferInterGrain",
            acts(bed_heat::heat_transfer_inter_grain),
        ),
        (
            "reactionHeat",
            refuse(
                "it reads the per-particle heat of reaction `reactionHeat` that LIGGGHTS-PFM's \
                 `fix couple/cfd/chemistry` (with `fix chem/shrink/core`) writes; neither \
                 Debian's LIGGGHTS 3.8 nor foamgrain's DEM has those fixes, and only PFM's \
                 compressible, reacting solvers (cfdemSolverRhoPimpleChem, \
                 rcfdemSolverRhoSteadyPimpleChem) select it; foamgrain's fluids are \
                 incompressible",
            ),
        ),
        (
            "wallHeatTransferYagi",
            acts(bed_heat::wall_heat_transfer_yagi),
        ),
    ],
};

/// `thermCondModel` (CFDEM-PFM): the fluid's effective conductivity in a bed.
pub const THERM_COND: Family = Family {
    key: "thermCondModel",
    models: &[
        ("noTherm", SAME),
        ("SyamlalThermCond", acts(bed_heat::syamlal)),
        (
            "ZehnerSchluenderThermCond",
            acts(bed_heat::zehner_schluender),
        ),
    ],
};

/// Why PFM's chemistry models are refused: they exist for its compressible, reacting solvers.
const REACTING: &str = "PFM's chemistry models serve its compressible, reacting solvers \
    (cfdemSolverRhoPimpleChem, rcfdemSolverRhoSteadyPimpleChem: species transport against \
    LIGGGHTS-PFM's `fix chem/shrink/core`; the 10 of the 53 couplingProperties in PFM's tutorials \
    that select one all belong to them); foamgrain's fluids are incompressible (PISO) and carry no species, and \
    neither Debian's LIGGGHTS 3.8 nor the native DEM has the chemistry fixes";

/// `chemistryModels` (CFDEM-PFM).
pub const CHEMISTRY: Family = Family {
    key: "chemistryModels",
    models: &[
        ("off", SAME),
        ("noChemistry", SAME),
        ("species", refuse(REACTING)),
        ("diffusionCoefficients", refuse(REACTING)),
        ("massTransferCoeff", refuse(REACTING)),
        ("reactantPerParticle", refuse(REACTING)),
        ("initMultiLayers", refuse(REACTING)),
    ],
};

/// `liggghtsCommandModels` of `constant/liggghtsCommands` ([`super::commands`]).
pub const LIGGGHTS_COMMANDS: Family = Family {
    key: "liggghtsCommandModels",
    models: &[
        ("runLiggghts", SAME),
        ("writeLiggghts", acts(commands::write_liggghts)),
        ("execute", acts(commands::execute)),
        ("readLiggghtsData", acts(commands::read_liggghts_data)),
        ("setDEMGravity", acts(commands::set_dem_gravity)),
    ],
};

/// Top-level single-name families, checked the same way: the key, its table.
pub const SINGLE_NAME: [Family; 9] = [
    LOCATE,
    MESH_MOTION,
    REGION,
    SMOOTHING,
    AVERAGING,
    DATA_EXCHANGE,
    IO,
    PROBE,
    THERM_COND,
];

/// The families read by a reader of their own; with [`SINGLE_NAME`], every family with a table
/// here (the drag laws are [`DRAG_LAWS`]).
pub const OTHERS: [Family; 7] = [
    VOIDAGE,
    CLOCK,
    MOM_COUPLE,
    FORCES,
    ENERGY,
    CHEMISTRY,
    LIGGGHTS_COMMANDS,
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The Props the acting models need beyond their defaults, for [`every_row_is_reached`].
    const REQUIRED_PROPS: &str = "\
        constDiffSmoothingProps { smoothingLength 0.01; lowerLimit 0; upperLimit 1; }\n\
        \"bigParticle(VoidFraction)?Props\" { maxCellsPerParticle 1000; }\n\
        temporalSmoothingProps { lowerLimit 0; upperLimit 1; refField voidfraction; gamma 0.1; }\n\
        constDiffAndTemporalSmoothingProps { lowerLimit 0; upperLimit 1; smoothingLength 0.01; \
            smoothingStrength 0.1; }\n\
        localPSizeDiffSmoothingProps { lowerLimit 0.1; upperLimit 1e10; dSmoothingLength 1.5e-3; \
            Csmoothing 1.0; }\n\
        fieldStoreProps { scalarFieldNames ( ); vectorFieldNames ( U ); }\n\
        fieldTimeAverageProps { scalarFieldNames ( voidfraction ); vectorFieldNames ( ); }\n\
        fieldVolWeightedProps { scalarFieldNames ( ); vectorFieldNames ( U ); }\n\
        volWeightedAverageProps { lowerThreshold 0; upperThreshold 1; \
            scalarFieldNames ( ); vectorFieldNames ( ); }\n\
        executeProps0 { command ( write_restart r ); runFirst on; }\n\
        particleProbeProps { particleIDsToSample ( 0 ); verboseToFile; }\n\
        readLiggghtsDataProps0 { startIndex 0; filePath ( dotdot slash DEM slash d ); \
            runFirst on; }\n\
        setDEMGravityProps0 { startTime 0; endTime 1; timeInterval 1; }\n\
        LaEuScalarTempProps { tempFieldName \"T\"; lambda 0.0256; Cp 1007; }\n\
        heatTransferGunnProps { partTempName \"Temp\"; implicit false; }\n\
        heatTransferRanzMarshallProps { partTempName \"Temp\"; implicit false; }\n\
        scalarGeneralExchangeProps { tempFieldName \"T\"; partTempName \"Temp\"; \
            partHeatFluxName \"convectiveHeatFlux\"; lambda 0.0256; Prandtl 0.7; \
            partSpeciesNames ( ); partSpeciesFluxNames ( ); partSpeciesTransCoeffNames ( ); \
            partSpeciesFluidNames ( ); DMolecular ( ); }\n\
        ZehnerSchluenderThermCondProps { thermalConductivities ( 1.2 ); }\n\
        heatTransferInterGrainProps { thermalConductivities ( 1.2 ); }\n\
        wallHeatTransferYagiProps { wallTempName \"Twall\"; voidfractionMax 0.9; \
            implicit false; }\n";

    /// A case's `constant/` with a `transportProperties` holding ρ, ν and PFM's `kf` and `Cp`
    /// and a `scalarTransportProperties` (the heat models read them next to the
    /// `couplingProperties` the tests name).
    fn coupling_properties() -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let constant = dir.path().join("constant");
        std::fs::create_dir(&constant).unwrap();
        std::fs::write(
            constant.join("transportProperties"),
            "nu 1.5e-5;\nrho 1.2;\nkf kf [1 1 -3 -1 0 0 0] 0.0256;\nCp Cp [0 2 -2 -1 0 0 0] 1007;\n",
        )
        .unwrap();
        std::fs::write(constant.join("g"), "value (0 0 -9.81);\n").unwrap();
        std::fs::write(
            constant.join("scalarTransportProperties"),
            "scalarTransportModel generalManual;\n\
             generalManualProps { cpVolumetric 1196; eulerianFields ( T ); }\n",
        )
        .unwrap();
        let file = constant.join("couplingProperties");
        (dir, file)
    }

    fn top() -> foam::Dict {
        let file = std::path::Path::new("couplingProperties");
        foam::parse_bytes(REQUIRED_PROPS.as_bytes(), file)
            .unwrap()
            .body
    }

    /// Applies `family` to `name` as its reader does: the result, the settings set and the
    /// warnings.
    fn apply(
        family: &Family,
        name: &str,
        top: &foam::Dict,
    ) -> (Result<bool, String>, Setup, Vec<String>) {
        let (_dir, file) = coupling_properties();
        let mut r = Reader::new(&file);
        let mut setup = Setup::default();
        let given = Given {
            key: family.key,
            name,
            top,
        };
        let result = r
            .apply(family, &given, &mut setup)
            .map_err(|e| e.to_string());
        (result, setup, r.warnings)
    }

    #[test]
    fn every_row_is_reached() {
        let top = top();
        for f in SINGLE_NAME.into_iter().chain(OTHERS) {
            for (name, model) in f.models {
                for spelling in std::iter::once(name).chain(model.aliases) {
                    let (result, setup, warnings) = apply(&f, spelling, &top);
                    let at = format!("{} {spelling}", f.key);
                    match model.support {
                        Acts(_) => {
                            assert_eq!(result, Ok(true), "{at}");
                            assert_ne!(setup, Setup::default(), "{at}: nothing set");
                            // GaussVoidFraction says how it differs from CFDEM's
                            let said = match spelling.parse::<Method>() {
                                Ok(Method::Gauss) if f.key == VOIDAGE.key => {
                                    vec![void_fraction::GAUSS_WARNING.to_owned()]
                                }
                                _ => Vec::new(),
                            };
                            assert_eq!(warnings.len(), said.len(), "{at}: {warnings:?}");
                            assert!(warnings.iter().zip(&said).all(|(w, s)| w.ends_with(s)));
                        }
                        Same => {
                            assert_eq!(result, Ok(false), "{at}");
                            assert_eq!(setup, Setup::default(), "{at}");
                            assert!(warnings.is_empty(), "{at}: {warnings:?}");
                        }
                        Warn(why) => {
                            assert_eq!(result, Ok(false), "{at}");
                            assert_eq!(setup, Setup::default(), "{at}");
                            assert_eq!(warnings.len(), 1, "{at}");
                            assert!(warnings[0].contains(&at) && warnings[0].contains(why));
                        }
                        Refuse(instead) => {
                            let e = result.unwrap_err();
                            assert!(e.contains(f.key) && e.contains(spelling), "{at}: {e}");
                            assert!(e.contains("not supported") && e.contains(instead), "{e}");
                        }
                    }
                    if f.key == VOIDAGE.key && matches!(model.support, Acts(_)) {
                        // the voidage spellings select the same method here as on the
                        // command line
                        let method = spelling.parse::<Method>().unwrap();
                        assert_eq!(setup.voidage.map(|v| v.method), Some(method), "{at}");
                    }
                }
            }
            let (result, _, _) = apply(&f, "noSuchModel", &top);
            let e = result.unwrap_err();
            assert!(e.contains("unknown model `noSuchModel`"), "{}: {e}", f.key);
            assert!(e.contains(&f.valid_names()), "{}: {e}", f.key);
        }
    }

    #[test]
    fn every_drag_law_is_reached() {
        let top = top();
        for &(name, law) in DRAG_LAWS {
            let mut r = Reader::new(std::path::Path::new("couplingProperties"));
            let mut setup = Setup::default();
            let given = Given {
                key: FORCES.key,
                name,
                top: &top,
            };
            forces::drag(&mut r, &given, law, &mut setup).unwrap();
            assert_eq!(
                setup.forces.drag.map(|d| d.closure.law),
                Some(law),
                "{name}"
            );
            // and through the forceModels reader
            let text = format!("forceModels ( {name} );\n{REQUIRED_PROPS}");
            let file = std::path::Path::new("couplingProperties");
            let list = foam::parse_bytes(text.as_bytes(), file).unwrap().body;
            let mut setup = Setup::default();
            forces::read_forces(&mut r, &list, &mut setup).unwrap();
            assert_eq!(
                setup.forces.drag.map(|d| d.closure.law),
                Some(law),
                "{name}"
            );
        }
    }

    #[test]
    fn spellings_are_unique_within_a_family() {
        for f in SINGLE_NAME.into_iter().chain(OTHERS) {
            let mut seen: Vec<&str> = DRAG_LAWS.iter().map(|(n, _)| *n).collect();
            if f.key != FORCES.key {
                seen.clear();
            }
            for (name, model) in f.models {
                for spelling in std::iter::once(name).chain(model.aliases) {
                    assert!(!seen.contains(spelling), "{}: `{spelling}` twice", f.key);
                    seen.push(spelling);
                }
            }
        }
    }

    #[test]
    fn names_are_unique_within_a_family() {
        for f in SINGLE_NAME.iter().chain(&OTHERS[1..]) {
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
        // the immersed-boundary models stay refused (issue 28 leaves them out)
        let names = VOIDAGE.valid_names();
        assert!(
            names.contains("exact") && !names.contains("IBVoidFraction"),
            "{names}"
        );
        assert!(names.contains("GaussVoidFraction"), "{names}");
        assert_eq!(
            VOIDAGE
                .support("IBVoidFraction")
                .map(|s| matches!(s, Refuse(_))),
            Some(true)
        );
        assert_eq!(LOCATE.support("nowhere"), None);
        // of the momentum coupling's families, only the immersed-boundary models and the
        // names whose source CFDEM never published are refused
        let unpublished = [
            "DEMbasedDrag",
            "RongDrag",
            "explicitCoupleSource",
            "dividedSmooth",
        ];
        for f in [VOIDAGE, FORCES, SMOOTHING, MOM_COUPLE, AVERAGING, IO, PROBE] {
            for (name, model) in f.models {
                if let Refuse(why) = model.support {
                    let ib = name.ends_with("IB") || name.starts_with("IB");
                    assert!(ib || unpublished.contains(name), "{} {name}", f.key);
                    if !ib {
                        assert!(why.contains("neither") || why.contains("no such"), "{why}");
                    }
                }
            }
        }
        for name in [
            "checkCouplingInterval",
            "KochHillRWDrag",
            "fieldVolWeighted",
            "localPSizeDiffSmoothing",
            "GaussVoidFraction",
        ] {
            let support = [FORCES, SMOOTHING, VOIDAGE]
                .iter()
                .find_map(|f| f.support(name));
            assert!(matches!(support, Some(Acts(_))), "{name}");
        }
    }
}
