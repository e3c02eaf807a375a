//! A case in CFDEM layout: `CASE/CFD` (an OpenFOAM case with `constant/couplingProperties`),
//! `CASE/DEM` (LIGGGHTS decks run with `DEM/` as working directory) and, for foamgrain's
//! reference cases, `CASE/validationDict` saying which checks the run is held to.

use foam::Dict;
use std::path::{Path, PathBuf};

pub use crate::error::LayoutError;

/// The files of a CFDEM-layout case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseLayout {
    /// The case root.
    pub root: PathBuf,
    /// `CASE/CFD`.
    pub cfd: PathBuf,
    /// `CASE/DEM`.
    pub dem: PathBuf,
    /// `DEM/in.liggghts_init` if present: the deck that prepares the particles (packing).
    pub init_deck: Option<PathBuf>,
    /// The coupled deck: the one couplingProperties names (`<dataExchangeModel>Props/liggghtsPath`,
    /// relative to `CASE/CFD`), else `DEM/in.liggghts_run`.
    pub run_deck: PathBuf,
    /// What `CASE/validationDict` asks for (`None` if the case has no such file).
    pub validation: Option<ValidationSpec>,
    /// `CFD/constant/couplingProperties`, read once here (it also names the coupled deck).
    pub coupling: couple::CouplingConfig,
    /// `CFD/system/controlDict`, read once here (its `application` is checked first); the
    /// fluid's settings, its function objects and the warnings read it from here.
    pub control: ControlDict,
}

/// `system/controlDict`, parsed once.
#[derive(Clone, Debug, PartialEq)]
pub struct ControlDict {
    /// The file (named in errors).
    pub path: PathBuf,
    /// Its entries.
    pub body: Dict,
}

impl ControlDict {
    /// Reads `CASE/system/controlDict` of the OpenFOAM case `case`.
    pub fn read(case: &Path) -> Result<ControlDict, foam::FoamError> {
        let path = case.join("system/controlDict");
        let body = foam::parse_file(&path)?.body;
        Ok(ControlDict { path, body })
    }
}

/// CFDEM solvers whose equations foamgrain's fluids do not solve, each with the reason. A case
/// naming one in `CFD/system/controlDict` (`application`) is refused before its
/// couplingProperties is read, so the user hears why the case cannot run rather than about
/// the first of its models. Every other name runs (CFDEM's tutorials also name `pisoFoam`,
/// `potentialFoam` and others there, left over from their templates).
const UNSUPPORTED_APPLICATIONS: &[(&str, &str)] = &[
    (
        "cfdemSolverRhoPimpleChem",
        "a compressible, reacting solver (rhoPimple with species transport and PFM's \
         chemistryModels, against LIGGGHTS-PFM's `fix chem/shrink/core`); foamgrain's fluids \
         are incompressible (PISO) and carry no species, and neither Debian's LIGGGHTS 3.8 nor \
         the native DEM has the chemistry fixes",
    ),
    (
        "rcfdemSolverRhoSteadyPimpleChem",
        "a recurrence-based compressible, reacting solver (species transport and PFM's \
         chemistryModels); foamgrain's fluids are incompressible (PISO) and carry no species",
    ),
    (
        "cfdemSolverIB",
        "the immersed-boundary (resolved) solver; foamgrain couples unresolved particles only",
    ),
    (
        "cfdemSolverMultiphase",
        "a VOF multiphase solver; foamgrain's fluids have one phase besides the particles",
    ),
];

/// `application` of a coupled case's controlDict, refused when it names a solver foamgrain
/// does not have ([`UNSUPPORTED_APPLICATIONS`]).
fn check_application(control: &ControlDict) -> Result<(), LayoutError> {
    let Ok(app) = control.body.word("application") else {
        return Ok(());
    };
    match UNSUPPORTED_APPLICATIONS
        .iter()
        .find(|(name, _)| *name == app)
    {
        Some((name, why)) => Err(LayoutError::Entry {
            path: control.path.clone(),
            msg: format!("application `{name}` is not supported: it is {why}"),
        }),
        None => Ok(()),
    }
}

/// The reference a case is checked against (`type` in `validationDict`).
#[derive(Clone, Debug, PartialEq)]
pub enum ValidationSpec {
    /// `type ergunPackedBed;`: Δp(u) through the bed against Ergun's equation with the bed
    /// height and voidage measured from the particles, and the fluidisation plateau against the
    /// bed's buoyant weight per area.
    ErgunPackedBed {
        /// Unit vector along the column, pointing downstream (against gravity).
        axis: mesh::v3::V3,
        /// Inlet patch name.
        inlet: String,
        /// Outlet patch name.
        outlet: String,
        /// Accepted relative error of Δp below fluidisation.
        pressure_drop_tolerance: f64,
        /// Accepted relative error of the plateau Δp.
        plateau_tolerance: f64,
    },
    /// `type settlingSphere;`: one sphere's velocity against the Schiller–Naumann ODE at the end
    /// time and against Di Felice's terminal velocity.
    SettlingSphere {
        /// Accepted relative error of the velocity.
        velocity_tolerance: f64,
    },
    /// `type fluidisedBed;`: a bed fluidised at a constant inlet velocity (the last plateau of
    /// the inlet's table), averaged over that plateau's second half: Δp against the bed's
    /// weight per area, and the mean bed height against the experiment's expanded bed; and
    /// on the way (the inlet's ramp below fluidisation) the packed bed's Δp against the case's
    /// drag law on the bed measured from the particles.
    FluidisedBed {
        /// Inlet patch name.
        inlet: String,
        /// Outlet patch name.
        outlet: String,
        /// The experiment's time-averaged expanded bed height, m.
        expanded_bed_height: f64,
        /// Accepted relative error of the mean bed height.
        bed_height_tolerance: f64,
        /// Accepted relative error of the mean Δp.
        pressure_drop_tolerance: f64,
        /// Accepted relative error of the packed bed's Δp against the case's drag law (the
        /// inlet ramp below fluidisation).
        packed_bed_tolerance: f64,
        /// Shortest averaging window for the fluidised checks, s (a bubbling bed's surface
        /// rises and falls with each bubble; a shorter window is not a time average).
        averaging_time: f64,
        /// `voidageProfiles { … }`: time-averaged voidage across the width at fixed heights
        /// against a measurement ([`crate::slab_profile`]).
        profiles: Option<crate::slab_profile::ProfileSpec>,
        /// `bedHeightKnownGap`: what the case's documentation traces a failing bed height to,
        /// added to that check's message.
        bed_height_known_gap: Option<String>,
    },
    /// `type pneumaticConveying;`: Madden's (2020) reduced conveyor ([`crate::conveyor`]): the
    /// mean outlet air velocity against the seed's incompressible and compressible results, the
    /// particles' axial velocity in the tube against the experiment, the chamber emptied.
    PneumaticConveying(crate::conveyor::ConveyorSpec),
    /// `type packedBedHeating;`: hot gas through a cold fixed bed, the gas and solid
    /// temperature fronts against Schumann's solution ([`crate::heating_run`]).
    PackedBedHeating(crate::heating_run::HeatingCase),
}

fn entry_err(path: &Path, e: impl std::fmt::Display) -> LayoutError {
    LayoutError::Entry {
        path: path.to_owned(),
        msg: e.to_string(),
    }
}

/// The word `key` of the validationDict `d` (a patch name), as an error naming the file.
fn word(d: &Dict, path: &Path, key: &str) -> Result<String, LayoutError> {
    Ok(d.word(key).map_err(|e| entry_err(path, e))?.to_owned())
}

/// The full conveyor's keys ([`crate::branch::BranchSpec`]): all of them, or none (the
/// reduced conveyor).
fn branch(d: &Dict, path: &Path) -> Result<Option<crate::branch::BranchSpec>, LayoutError> {
    if !d.contains("branchAxis") {
        return Ok(None);
    }
    let a = d.vector("branchAxis").map_err(|e| entry_err(path, e))?;
    let axis = mesh::v3::V3::new(a[0], a[1], a[2]);
    let n = axis.norm();
    if !(n.is_finite() && n > 0.0) {
        return Err(entry_err(path, "branchAxis must be a non-zero vector"));
    }
    Ok(Some(crate::branch::BranchSpec {
        axis: axis / n,
        tube_to: tolerance(d, path, "tubeTo")?,
        branch_from: tolerance(d, path, "branchFrom")?,
        vent_from: tolerance(d, path, "ventFrom")?,
        secondary_from: tolerance(d, path, "secondaryFrom")?,
    }))
}

fn tolerance(d: &Dict, path: &Path, key: &str) -> Result<f64, LayoutError> {
    let t = d.f64(key).map_err(|e| entry_err(path, e))?;
    if !(t.is_finite() && t > 0.0) {
        return Err(entry_err(
            path,
            format!("{key} must be a positive number, got {t}"),
        ));
    }
    Ok(t)
}

impl ValidationSpec {
    /// Reads `validationDict`.
    pub fn read(path: &Path) -> Result<ValidationSpec, LayoutError> {
        let d = foam::parse_file(path)?.body;
        let kind = d.word("type").map_err(|e| entry_err(path, e))?;
        match kind {
            "ergunPackedBed" => {
                let axis = d.vector("axis").map_err(|e| entry_err(path, e))?;
                let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
                if !(n.is_finite() && n > 0.0) {
                    return Err(entry_err(path, "axis must be a non-zero vector"));
                }
                Ok(ValidationSpec::ErgunPackedBed {
                    axis: mesh::v3::V3::new(axis[0] / n, axis[1] / n, axis[2] / n),
                    inlet: word(&d, path, "inletPatch")?,
                    outlet: word(&d, path, "outletPatch")?,
                    pressure_drop_tolerance: tolerance(&d, path, "pressureDropTolerance")?,
                    plateau_tolerance: tolerance(&d, path, "plateauTolerance")?,
                })
            }
            "settlingSphere" => Ok(ValidationSpec::SettlingSphere {
                velocity_tolerance: tolerance(&d, path, "velocityTolerance")?,
            }),
            "fluidisedBed" => Ok(ValidationSpec::FluidisedBed {
                inlet: word(&d, path, "inletPatch")?,
                outlet: word(&d, path, "outletPatch")?,
                // positive numbers, like the tolerances
                expanded_bed_height: tolerance(&d, path, "expandedBedHeight")?,
                bed_height_tolerance: tolerance(&d, path, "bedHeightTolerance")?,
                pressure_drop_tolerance: tolerance(&d, path, "pressureDropTolerance")?,
                packed_bed_tolerance: tolerance(&d, path, "packedBedTolerance")?,
                averaging_time: tolerance(&d, path, "averagingTime")?,
                bed_height_known_gap: match d.contains("bedHeightKnownGap") {
                    true => Some(word(&d, path, "bedHeightKnownGap")?),
                    false => None,
                },
                profiles: d
                    .opt_dict("voidageProfiles")
                    .map(crate::slab_profile::ProfileSpec::read)
                    .transpose()
                    .map_err(|e| entry_err(path, e))?,
            }),
            "pneumaticConveying" => Ok(ValidationSpec::PneumaticConveying(
                crate::conveyor::ConveyorSpec {
                    inlet: word(&d, path, "inletPatch")?,
                    outlet: word(&d, path, "outletPatch")?,
                    chamber_top: tolerance(&d, path, "chamberTop")?,
                    annulus_top: tolerance(&d, path, "annulusTop")?,
                    tube_from: tolerance(&d, path, "tubeFrom")?,
                    averaging_from: tolerance(&d, path, "averagingFrom")?,
                    outlet_velocity: tolerance(&d, path, "outletVelocity")?,
                    outlet_velocity_tolerance: tolerance(&d, path, "outletVelocityTolerance")?,
                    compressible_velocity: tolerance(&d, path, "compressibleOutletVelocity")?,
                    compressible_tolerance: tolerance(&d, path, "compressibleTolerance")?,
                    particle_velocity: tolerance(&d, path, "particleVelocity")?,
                    particle_velocity_tolerance: tolerance(&d, path, "particleVelocityTolerance")?,
                    emptying_time: tolerance(&d, path, "emptyingTime")?,
                    emptied_tolerance: tolerance(&d, path, "emptiedTolerance")?,
                    branch: branch(&d, path)?,
                },
            )),
            "packedBedHeating" => Ok(ValidationSpec::PackedBedHeating(
                crate::heating_run::read_case(&d).map_err(|e| entry_err(path, e))?,
            )),
            other => Err(entry_err(
                path,
                format!(
                    "unknown validation type '{other}' (known: ergunPackedBed, settlingSphere, \
                     fluidisedBed, pneumaticConveying, packedBedHeating)"
                ),
            )),
        }
    }
}

/// `path` with `.` and `dir/..` pairs removed, without touching the file system
/// (`CASE/CFD/../DEM/in.liggghts_run` → `CASE/DEM/in.liggghts_run`).
pub(crate) fn lexically_normal(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

impl CaseLayout {
    /// Finds the parts of the case at `root`.
    pub fn open(root: &Path) -> Result<CaseLayout, LayoutError> {
        let cfd = root.join("CFD");
        let dem = root.join("DEM");
        if !cfd.is_dir() {
            return Err(LayoutError::Missing {
                path: cfd,
                what: "the CFD case directory",
            });
        }
        if !dem.is_dir() {
            return Err(LayoutError::Missing {
                path: dem,
                what: "the DEM directory",
            });
        }
        let coupling = cfd.join("constant/couplingProperties");
        if !coupling.is_file() {
            return Err(LayoutError::Missing {
                path: coupling,
                what: "couplingProperties",
            });
        }
        let control_path = cfd.join("system/controlDict");
        if !control_path.is_file() {
            return Err(LayoutError::Missing {
                path: control_path,
                what: "the CFD case's controlDict",
            });
        }
        let control = ControlDict::read(&cfd)?;
        check_application(&control)?;
        // CFDEM names the coupled deck in couplingProperties (`twoWayMPIProps/liggghtsPath`,
        // relative to the CFD case); without it, DEM/in.liggghts_run.
        let config = couple::CouplingConfig::read(&coupling)?;
        let (run_deck, what) = match &config.liggghts_path {
            Some(p) => (
                lexically_normal(&cfd.join(p)),
                "the coupled LIGGGHTS deck that couplingProperties names (liggghtsPath)",
            ),
            None => (dem.join("in.liggghts_run"), "the coupled LIGGGHTS deck"),
        };
        if !run_deck.is_file() {
            return Err(LayoutError::Missing {
                path: run_deck,
                what,
            });
        }
        let init = dem.join("in.liggghts_init");
        let vpath = root.join("validationDict");
        let validation = if vpath.is_file() {
            Some(ValidationSpec::read(&vpath)?)
        } else {
            None
        };
        Ok(CaseLayout {
            root: root.to_owned(),
            cfd,
            dem,
            init_deck: init.is_file().then_some(init),
            run_deck,
            validation,
            coupling: config,
            control,
        })
    }

    /// Where the run writes its CSV, plots and `validation.json`: `CASE/postProcessing`.
    pub fn post_processing(&self) -> PathBuf {
        self.root.join("postProcessing")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn repo() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
    }

    #[test]
    fn the_reference_cases_open() {
        let e = CaseLayout::open(&repo().join("openfoam-cases/ergun")).unwrap();
        assert!(e.init_deck.is_some());
        match e.validation.unwrap() {
            ValidationSpec::ErgunPackedBed {
                axis,
                inlet,
                outlet,
                ..
            } => {
                assert_eq!(axis, mesh::v3::V3::z());
                assert_eq!((inlet.as_str(), outlet.as_str()), ("inlet", "outlet"));
            }
            v => panic!("{v:?}"),
        }
        let f = CaseLayout::open(&repo().join("openfoam-cases/fluidised-bed")).unwrap();
        assert!(f.init_deck.is_some());
        match f.validation.unwrap() {
            ValidationSpec::FluidisedBed {
                inlet,
                outlet,
                expanded_bed_height,
                profiles,
                ..
            } => {
                assert_eq!((inlet.as_str(), outlet.as_str()), ("inlet", "outlet"));
                assert_eq!(expanded_bed_height, 0.05);
                let p = profiles.expect("voidageProfiles");
                assert_eq!(p.heights, [0.0164, 0.0312]);
                assert_eq!((p.bins, p.wall_bins), (22, 1));
            }
            v => panic!("{v:?}"),
        }
        let s = CaseLayout::open(&repo().join("openfoam-cases/settling")).unwrap();
        assert!(s.init_deck.is_none());
        assert!(matches!(
            s.validation,
            Some(ValidationSpec::SettlingSphere { .. })
        ));
    }

    #[test]
    fn missing_parts_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let err = CaseLayout::open(dir.path()).unwrap_err().to_string();
        assert!(err.contains("CFD") && err.contains("not found"), "{err}");
        std::fs::create_dir_all(dir.path().join("CFD/constant")).unwrap();
        std::fs::create_dir_all(dir.path().join("DEM")).unwrap();
        let err = CaseLayout::open(dir.path()).unwrap_err().to_string();
        assert!(err.contains("couplingProperties"), "{err}");
    }

    #[test]
    fn a_reacting_cfdem_case_is_refused_by_its_application() {
        // PFM's cfdemSolverRhoPimpleChem tutorials select `chemistryModels (species …)` and
        // `reactionHeat`; the user must hear that the solver is missing, not about a model
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("CFD/constant")).unwrap();
        std::fs::create_dir_all(dir.path().join("CFD/system")).unwrap();
        std::fs::create_dir_all(dir.path().join("DEM")).unwrap();
        std::fs::write(
            dir.path().join("CFD/constant/couplingProperties"),
            "chemistryModels ( species );\nenergyModels ( reactionHeat );\n",
        )
        .unwrap();
        let control = dir.path().join("CFD/system/controlDict");
        std::fs::write(&control, "application cfdemSolverRhoPimpleChem;\n").unwrap();
        let err = CaseLayout::open(dir.path()).unwrap_err().to_string();
        assert!(
            err.contains("controlDict")
                && err.contains("cfdemSolverRhoPimpleChem")
                && err.contains("incompressible"),
            "{err}"
        );
        // an application foamgrain runs goes on to couplingProperties (which is bad here)
        std::fs::write(&control, "application cfdemSolverPiso;\n").unwrap();
        let err = CaseLayout::open(dir.path()).unwrap_err().to_string();
        assert!(err.contains("couplingProperties"), "{err}");
    }

    #[test]
    fn the_deck_couplingproperties_names_is_the_run_deck() {
        let dir = tempfile::tempdir().unwrap();
        let case = dir.path().join("case");
        testkit::copy_inputs(&repo().join("openfoam-cases/settling"), &case);
        let cp = case.join("CFD/constant/couplingProperties");
        let text = std::fs::read_to_string(&cp).unwrap();
        // CFDEM's form: the Props under a pattern key, naming the deck
        assert!(text.contains("twoWayMPIProps") && text.contains("../DEM/in.liggghts_run"));
        let text = text
            .replace("twoWayMPIProps", "\"(twoWayMPIProps|M2MProps)\"")
            .replace("../DEM/in.liggghts_run", "../DEM/in.resume");
        std::fs::write(&cp, text).unwrap();
        let err = CaseLayout::open(&case).unwrap_err().to_string();
        assert!(
            err.contains("DEM/in.resume") && err.contains("liggghtsPath") && !err.contains(".."),
            "{err}"
        );
        std::fs::rename(case.join("DEM/in.liggghts_run"), case.join("DEM/in.resume")).unwrap();
        let l = CaseLayout::open(&case).unwrap();
        assert_eq!(l.run_deck, case.join("DEM/in.resume"));
    }

    /// The reduced conveyor has no branch; the full one's branch keys agree with the numbers
    /// its geometry script builds the mesh from (`geometry.py`'s Z_SQ, Z_J0, HALF, X_LEG).
    #[test]
    fn the_conveyors_open_with_their_geometry() {
        let spec = |case: &str| match CaseLayout::open(&repo().join(case)).unwrap().validation {
            Some(ValidationSpec::PneumaticConveying(c)) => c,
            v => panic!("{v:?}"),
        };
        assert_eq!(spec("openfoam-cases/pneumatic-conveying").branch, None);
        let full = spec("openfoam-cases/pneumatic-conveying-full");
        let b = full.branch.unwrap();
        let geo =
            std::fs::read_to_string(repo().join("openfoam-cases/pneumatic-conveying/geometry.py"))
                .unwrap();
        let value = |name: &str| -> f64 {
            let line = geo
                .lines()
                .find(|l| l.starts_with(&format!("{name} = ")))
                .unwrap_or_else(|| panic!("{name} not in geometry.py"));
            line.split('=')
                .nth(1)
                .unwrap()
                .split('#')
                .next()
                .unwrap()
                .trim()
                .parse()
                .unwrap()
        };
        let (z_out, z_sq, z_j0, half) =
            (value("Z_OUT"), value("Z_SQ"), value("Z_J0"), value("HALF"));
        assert!(geo.contains("X_LEG = -HALF - 0.020"));
        assert_eq!(b.axis, mesh::v3::V3::x());
        assert_eq!(
            (full.tube_from, b.tube_to, b.branch_from),
            (z_out, z_sq, z_j0)
        );
        assert_eq!(b.vent_from, half);
        assert!((b.secondary_from - (half + 0.020)).abs() < 1e-15);
    }

    #[test]
    fn bad_validation_dicts_name_the_key() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("validationDict");
        std::fs::write(&p, "type settlingSphere;\nvelocityTolerance -1;\n").unwrap();
        let err = ValidationSpec::read(&p).unwrap_err().to_string();
        assert!(
            err.contains("velocityTolerance") && err.contains("validationDict"),
            "{err}"
        );
        std::fs::write(&p, "type bubbling;\n").unwrap();
        let err = ValidationSpec::read(&p).unwrap_err().to_string();
        assert!(err.contains("bubbling"), "{err}");
        std::fs::write(
            &p,
            "type fluidisedBed;\ninletPatch inlet;\noutletPatch outlet;\nexpandedBedHeight 0.05;\n",
        )
        .unwrap();
        let err = ValidationSpec::read(&p).unwrap_err().to_string();
        assert!(err.contains("bedHeightTolerance"), "{err}");
        // the full conveyor's keys come all together
        let reduced = std::fs::read_to_string(
            repo().join("openfoam-cases/pneumatic-conveying/validationDict"),
        )
        .unwrap();
        std::fs::write(&p, format!("{reduced}\nbranchAxis (1 0 0);\n")).unwrap();
        let err = ValidationSpec::read(&p).unwrap_err().to_string();
        assert!(
            err.contains("tubeTo") && err.contains("validationDict"),
            "{err}"
        );
        std::fs::write(&p, "type ergunPackedBed;\naxis (0 0 0);\n").unwrap();
        let err = ValidationSpec::read(&p).unwrap_err().to_string();
        assert!(err.contains("axis"), "{err}");
    }
}
