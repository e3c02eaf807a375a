//! One plan per run: the case read once into typed settings, before anything runs.
//!
//! [`RunPlan::read`] reads `couplingProperties` (with `transportProperties` and `g`, through
//! the layout), `liggghtsCommands`, `system/controlDict`, `fvSchemes` and `fvSolution` (the
//! fluid's settings), the coupled LIGGGHTS deck and `validationDict`, and checks what they say
//! of each other (the deck's `couple_every` against `couplingInterval`). Every later stage
//! takes what it needs from the plan; no stage reads these files again. Each setting has one
//! home: the coupling interval is [`couple::CouplerSettings::coupling_interval`], the fluid's
//! clock `fv::settings::Settings`, the DEM step the deck's [`Deck::time_step`].

use crate::error::{setup_err, RunError};
use crate::layout::CaseLayout;
use couple::config::LiggghtsCommands;
use couple::CouplerSettings;
use liggghts_deck::Deck;
use std::path::{Path, PathBuf};

/// The fluid solver of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FluidBackend {
    /// The native Rust VANS PISO solver (`fv`).
    #[default]
    Native,
    /// grainPisoFoam (Debian's OpenFOAM v1912) spawned over MPI.
    OpenFoam,
}

/// The DEM of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DemBackend {
    /// The native Rust DEM (`dem`).
    #[default]
    Native,
    /// LIGGGHTS in this process (Debian's libliggghts).
    Liggghts,
    /// LIGGGHTS as a child process, coupled through files (slow by design: LIGGGHTS polls the
    /// files every 10 s).
    LiggghtsFile,
}

impl FluidBackend {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FluidBackend::Native => "native",
            FluidBackend::OpenFoam => "openfoam",
        }
    }
}

impl DemBackend {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DemBackend::Native => "native",
            DemBackend::Liggghts => "liggghts",
            DemBackend::LiggghtsFile => "liggghts-file",
        }
    }
}

/// Options of a run (the command line's).
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Stop at this simulated time instead of `endTime`.
    pub end_time: Option<f64>,
    /// Variables for the init deck (`-var NAME VALUE`, e.g. a smaller particle count).
    pub init_vars: Vec<(String, String)>,
    /// Pack again even if the packed-bed file exists.
    pub repack: bool,
    /// The fluid backend.
    pub fluid: FluidBackend,
    /// The particle backend.
    pub dem: DemBackend,
    /// MPI ranks of the fluid solver (OpenFOAM backend; 0: `numberOfSubdomains` of the case's
    /// `system/decomposeParDict`, 1 without one).
    pub fluid_ranks: usize,
    /// Advance the fluid and the DEM one after the other even where the fluid computes in
    /// processes of its own (grainPisoFoam), whose advance otherwise runs during the next DEM
    /// interval; the results are the same bit for bit.
    pub no_overlap: bool,
}

pub use crate::layout::ControlDict;

/// A case read once.
pub struct RunPlan {
    /// Where the case's parts are; its `coupling` is `couplingProperties`, its `validation`
    /// `validationDict`.
    pub layout: CaseLayout,
    /// The coupler's settings (couplingProperties with ρ, ν, g).
    pub settings: CouplerSettings,
    /// CFDEM's `liggghtsCommands`.
    pub commands: LiggghtsCommands,
    /// The fluid's settings (controlDict, fvSchemes, fvSolution).
    pub fluid: fv::settings::Settings,
    /// The coupled LIGGGHTS deck.
    pub run_deck: Deck,
    /// What the reading found worth a warning (printed before the run starts).
    pub warnings: Vec<String>,
}

impl RunPlan {
    /// Reads the case at `case` for a run with `opts`.
    pub fn read(case: &Path, opts: &RunOptions) -> Result<RunPlan, RunError> {
        let layout = CaseLayout::open(case)?;
        let config = &layout.coupling;
        let mut warnings = config.warnings.clone();
        let settings = config.coupler_settings(&layout.cfd)?;
        let commands = LiggghtsCommands::read_case(&layout.cfd)?;
        warnings.extend(commands.warnings.iter().cloned());
        let case = foam::Case::open(&layout.cfd)?;
        if opts.fluid == FluidBackend::Native {
            warnings.extend(control_dict_warnings(&layout.control));
        }
        let mut fluid = fv::settings::Settings::read_with_control(&case, &layout.control.body)
            .map_err(|e| RunError::Fluid(Box::new(e)))?;
        if let Some(heat) = settings.heat {
            // cfdemSolverPisoScalar's temperature equation: 0/T, Pr, Prt, the T solver
            fluid
                .enable_temperature(&case)
                .map_err(|e| RunError::Fluid(Box::new(e)))?;
            if config.wall_heat.is_some() {
                refuse_on_openfoam(opts, &config.file, "energyModels", "wallHeatTransferYagi")?;
            }
            if let Some(bed) = config.bed_conduction {
                refuse_on_openfoam(opts, &config.file, "thermCondModel", bed.name())?;
                let t = fluid.temperature.as_mut().expect("enabled");
                t.bed = Some(crate::bed_heat::fluid_bed(bed, heat.lambda));
            }
        }
        let run_deck = Deck::read(&layout.run_deck)?;
        // parcels (LIGGGHTS-PFM's `coarsegraining`): the drag at the real particles' diameter
        let settings = match run_deck.coarse_graining()? {
            Some(cg) => settings.with_coarse_graining(
                cg.factor,
                &format!("{}:{}", layout.run_deck.display(), cg.line),
                &layout.coupling.file,
            )?,
            None => settings.with_coarse_graining(1.0, "", &layout.coupling.file)?,
        };
        if let (None, Some(c)) = (
            settings.heat,
            run_deck.fixes("couple/cfd/convection").next(),
        ) {
            warnings.push(format!(
                "{}:{}: `couple/cfd/convection`, but {} names no heat-transfer model \
                 (LaEuScalarTemp, heatTransferGunn): the particles receive no convective heat",
                layout.run_deck.display(),
                c.line,
                layout.coupling.file.display()
            ));
        }
        let plan = RunPlan {
            layout,
            settings,
            commands,
            fluid,
            run_deck,
            warnings,
        };
        plan.check_couple_every(opts.dem)
    }

    /// The deck's `couple_every` against `couplingInterval`: CFDEM's twoWayMPI exchanges every
    /// couplingInterval DEM steps whatever the deck says (a difference is a warning); LIGGGHTS's
    /// file coupling is driven by couple_every, so there they must be equal.
    fn check_couple_every(mut self, dem: DemBackend) -> Result<RunPlan, RunError> {
        let deck = &self.layout.run_deck;
        let every = self
            .run_deck
            .coupling()?
            .ok_or_else(|| {
                setup_err(
                    deck,
                    "is not coupled: it needs `fix ... couple/cfd couple_every N ...`".into(),
                )
            })?
            .couple_every;
        let interval = self.settings.coupling_interval;
        let config = &self.layout.coupling.file;
        if every != interval && dem != DemBackend::LiggghtsFile {
            self.warnings.push(format!(
                "{}: couple_every {every} differs from couplingInterval {interval} in {}; the \
                 coupling interval is couplingInterval (as CFDEM's twoWayMPI)",
                deck.display(),
                config.display()
            ));
        } else if every != interval {
            return Err(setup_err(
                deck,
                format!(
                    "couple_every {every} differs from couplingInterval {interval} in {} \
                     (LIGGGHTS's file coupling exchanges every couple_every steps: make them \
                     equal)",
                    config.display()
                ),
            ));
        }
        Ok(self)
    }

    /// The file the coupled deck starts from (`start_file`).
    pub fn start_file(&self) -> Option<(PathBuf, bool)> {
        start_file(&self.run_deck, &self.layout.dem)
    }

    /// The native fluid's momentum-coupling model (`modelType`).
    pub fn fluid_model(&self) -> fv::Model {
        match self.layout.coupling.model {
            closures::model::ModelType::A => fv::Model::A,
            _ => fv::Model::B,
        }
    }

    /// The simulated time the run ends: `--end-time`, else the controlDict's `endTime`.
    pub fn end_time(&self, opts: &RunOptions) -> f64 {
        opts.end_time.unwrap_or(self.fluid.end_time)
    }
}

/// The file a coupled deck starts from — `read_data FILE` or `read_restart FILE` (CFDEM's
/// decks) — resolved against the deck's directory, and whether it exists (a `*` in a restart
/// name stands for any step, as LIGGGHTS reads the latest).
pub(crate) fn start_file(deck: &Deck, dem_dir: &Path) -> Option<(PathBuf, bool)> {
    let first = deck.read_files().into_iter().next()?;
    let path = dem_dir.join(first.path);
    let exists = match path.file_name().and_then(|n| n.to_str()) {
        Some(name) if name.contains('*') => {
            let (head, tail) = name.split_once('*').unwrap_or((name, ""));
            path.parent()
                .and_then(|d| std::fs::read_dir(d).ok())
                .is_some_and(|entries| {
                    entries.flatten().any(|e| {
                        let n = e.file_name().to_string_lossy().into_owned();
                        n.len() >= head.len() + tail.len()
                            && n.starts_with(head)
                            && n.ends_with(tail)
                    })
                })
        }
        _ => path.exists(),
    };
    Some((path, exists))
}

/// Warnings for what `system/controlDict` asks of OpenFOAM that the native fluid does not do:
/// its `functions` (function objects such as CFDEM tutorials' `probes` and
/// `surfaceFieldValue`) are not run — one line naming them.
fn control_dict_warnings(control: &ControlDict) -> Vec<String> {
    let path = &control.path;
    let Some(f) = control.body.opt_dict("functions") else {
        return Vec::new();
    };
    // `probes` and `surfaceFieldValue` are run ([`crate::probes`],
    // [`crate::surface_values`], which warn of what they leave out); the others are named.
    let others: Vec<&str> = f
        .keys()
        .filter(|k| {
            let kind = f.opt_dict(k).and_then(|d| d.word("type").ok());
            !matches!(kind, Some("probes" | "surfaceFieldValue"))
        })
        .collect();
    match others.is_empty() {
        true => Vec::new(),
        false => vec![format!(
            "{}: functions ({}) are not run by the native fluid (foamgrain writes \
             postProcessing/integrals.csv and the time directories; `probes` and \
             `surfaceFieldValue` are run)",
            path.display(),
            others.join(" ")
        )],
    }
}

/// The error that the CFDEM-PFM model `name` (of `key` in `file`) acts with the native fluid
/// only, when `opts` runs grainPisoFoam: raised while the plan is read, before anything is
/// spawned.
fn refuse_on_openfoam(
    opts: &RunOptions,
    file: &Path,
    key: &str,
    name: &str,
) -> Result<(), RunError> {
    match opts.fluid {
        FluidBackend::OpenFoam => Err(RunError::Setup {
            file: file.to_path_buf(),
            message: format!(
                "{key} {name}: acts with the native fluid only (grainPisoFoam's temperature \
                 equation has no per-cell conductivity or wall source from the coupler); run \
                 with `--fluid native`"
            ),
        }),
        FluidBackend::Native => Ok(()),
    }
}
