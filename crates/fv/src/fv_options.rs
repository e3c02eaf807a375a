//! `fvOptions` momentum sources that hold a mean velocity: OpenFOAM v1912's
//! `meanVelocityForce` and CFDEM's `meanSupVelocityForce` (CFDEMcoupling's `fvOptionsCFDEM`,
//! the source of its periodicChannel tutorial), read and applied as the two codes do.
//!
//! A periodic channel has no inlet to set the flow rate, so a uniform force density
//! G·ê (G the kinematic pressure-gradient equivalent, m/s², ê = Ū/|Ū|) drives it, and after
//! each velocity solve the force is adjusted so that the cell-volume average of the velocity
//! along ê is |Ū|:
//!
//! * `constrain` (after the momentum matrix is assembled): r_A = 1/A per cell (A the
//!   momentum diagonal per volume, 1/s), G₀ ← G₀ + ΔG, ΔG ← 0;
//! * `correct` (after the predictor and after every PISO corrector):
//!   ⟨U⟩ = Σ (ê·U_c) w_c V_c / Σ V_c, ⟨r_A⟩ = Σ r_A,c V_c / Σ V_c,
//!   ΔG = λ (|Ū| − ⟨U⟩)/⟨r_A⟩ (λ the `relaxation`, default 1), U_c ← U_c + w_c ê r_A,c ΔG;
//! * the momentum source of the next assembly is w_c (G₀ + ΔG) ê per volume.
//!
//! `meanVelocityForce` has w ≡ 1: it holds the mean (interstitial) velocity. CFDEM's
//! `meanSupVelocityForce` with `coupled true` has w = ε, the voidage of its
//! `voidfractionField` as of its last `correct` (ones before the first): it holds the mean
//! superficial velocity ⟨εU⟩ and the force per volume of mixture is ε G ê, the model-A
//! pressure-gradient form. CFDEM's code compares the source's *type name* with "B" to choose
//! the model-B form, so the ε-weighted form is what it always applies, whatever the coupling
//! model; so does this. With `coupled false` it is `meanVelocityForce`.
//!
//! Both read `<startTime>/uniform/<name>Properties` (`gradient G`) when present and write it at
//! the write times, so a continued run starts from the last force. Supported settings:
//! `type`, `active`, the entries of `<type>Coeffs` or of the source's dictionary itself
//! (OpenFOAM's `optionalSubDict`): `selectionMode all`, `fields (U)`, `Ubar`, `relaxation`;
//! `twoPhase false`, `coupled`, `voidfractionField voidfraction`, `alphaMin` for
//! `meanSupVelocityForce`. Any other source type, selection, field or time window is an
//! error naming the file and the entry. As v1912, `constant/fvOptions` is read when it
//! exists, else `system/fvOptions`.
//!
//! References: OpenFOAM v1912 `src/fvOptions/sources/derived/meanVelocityForce`;
//! CFDEMcoupling-PUBLIC `src/eulerian/fvOptionsCFDEM/sources/derived/meanSupVelocityForce`
//! (read for their behaviour; this is an independent implementation).

use crate::error::{FvError, Result};
use crate::geometry::V3;
use foam::{Case, Dict, Value};
use std::path::{Path, PathBuf};

/// Which mean the source holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeanOf {
    /// The velocity U (OpenFOAM's `meanVelocityForce`; CFDEM's with `coupled false`).
    Velocity,
    /// The superficial velocity εU (CFDEM's `meanSupVelocityForce` with `coupled true`).
    Superficial,
}

/// One mean-velocity source as `fvOptions` states it.
#[derive(Clone, Debug, PartialEq)]
pub struct MeanForceSettings {
    /// The source's name (its dictionary's keyword; names the `uniform/<name>Properties` file).
    pub name: String,
    /// The source's `type`.
    pub kind: String,
    /// Which velocity it averages.
    pub mean_of: MeanOf,
    /// The mean velocity to hold, Ū (m/s).
    pub ubar: V3,
    /// The relaxation λ of the force increment (dimensionless).
    pub relaxation: f64,
}

fn err(file: &Path, key: String, msg: impl Into<String>) -> FvError {
    FvError::setting(file, key, msg)
}

/// The `fvOptions` file v1912 reads for `case`: `constant/fvOptions`, else `system/fvOptions`,
/// else none.
pub fn file_of(case: &Case) -> Option<PathBuf> {
    ["constant/fvOptions", "system/fvOptions"]
        .into_iter()
        .map(|rel| case.root().join(rel))
        .find(|p| p.is_file())
}

/// Reads the active sources of the case's `fvOptions` (none without the file).
pub fn read(case: &Case) -> Result<Vec<MeanForceSettings>> {
    let Some(file) = file_of(case) else {
        return Ok(Vec::new());
    };
    let rel = file
        .strip_prefix(case.root())
        .map(|p| p.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dict = case.read_dict(&rel)?;
    let mut out = Vec::new();
    for e in dict.entries() {
        let Value::Dict(src) = &e.value else {
            continue;
        };
        let name = e.keyword.as_str();
        let active = match src.get("active") {
            None => true,
            Some(_) => src
                .switch("active")
                .map_err(|x| err(&file, format!("{name}.active"), x.0))?,
        };
        if !active {
            continue;
        }
        out.push(source(&file, name, src)?);
    }
    Ok(out)
}

fn source(file: &Path, name: &str, src: &Dict) -> Result<MeanForceSettings> {
    let kind = src
        .word("type")
        .map_err(|x| err(file, format!("{name}.type"), x.0))?;
    let mean_sup = match kind {
        "meanVelocityForce" => false,
        "meanSupVelocityForce" => true,
        other => {
            return Err(err(
                file,
                format!("{name}.type"),
                format!(
                    "the source `{other}` is not supported by the native solver \
                     (meanVelocityForce, meanSupVelocityForce)"
                ),
            ))
        }
    };
    let coeffs_key = format!("{kind}Coeffs");
    let (coeffs, prefix) = match src.opt_dict(&coeffs_key) {
        Some(c) => (c, format!("{name}.{coeffs_key}")),
        None => (src, name.to_string()),
    };
    let key = |k: &str| format!("{prefix}.{k}");
    for k in ["timeStart", "duration"] {
        if coeffs.contains(k) || src.contains(k) {
            return Err(err(
                file,
                key(k),
                "time windows of sources are not supported",
            ));
        }
    }
    let mode = coeffs
        .word("selectionMode")
        .or_else(|_| src.word("selectionMode"))
        .map_err(|x| err(file, key("selectionMode"), x.0))?;
    if mode != "all" {
        return Err(err(
            file,
            key("selectionMode"),
            format!("`{mode}` is not supported (all)"),
        ));
    }
    let fields: Vec<&str> = coeffs
        .stream("fields")
        .map_err(|x| err(file, key("fields"), x.0))?
        .iter()
        .flat_map(|i| match i {
            foam::Item::List(l) => l.iter().filter_map(foam::Item::as_word).collect(),
            other => other.as_word().into_iter().collect::<Vec<_>>(),
        })
        .collect();
    if fields != ["U"] {
        return Err(err(
            file,
            key("fields"),
            format!(
                "`({})`: only the velocity `(U)` is supported",
                fields.join(" ")
            ),
        ));
    }
    let ubar = V3::from(
        coeffs
            .vector("Ubar")
            .map_err(|x| err(file, key("Ubar"), x.0))?,
    );
    if !(ubar.norm() > 0.0 && ubar.iter().all(|x| x.is_finite())) {
        return Err(err(file, key("Ubar"), "must be a finite, non-zero vector"));
    }
    let relaxation = coeffs
        .f64_or("relaxation", 1.0)
        .map_err(|x| err(file, key("relaxation"), x.0))?;
    if !(relaxation > 0.0 && relaxation.is_finite()) {
        return Err(err(file, key("relaxation"), "must be a positive number"));
    }
    let mut mean_of = MeanOf::Velocity;
    if mean_sup {
        let flag = |k: &str| -> Result<bool> {
            match coeffs.get(k) {
                None => Ok(false),
                Some(_) => coeffs.switch(k).map_err(|x| err(file, key(k), x.0)),
            }
        };
        if flag("twoPhase")? {
            return Err(err(
                file,
                key("twoPhase"),
                "two-phase (alphaField) averaging is not supported",
            ));
        }
        if flag("coupled")? {
            let field = coeffs
                .word("voidfractionField")
                .map_err(|x| err(file, key("voidfractionField"), x.0))?;
            if field != "voidfraction" {
                return Err(err(
                    file,
                    key("voidfractionField"),
                    format!("`{field}`: the solver's voidage is `voidfraction`"),
                ));
            }
            mean_of = MeanOf::Superficial;
        }
    }
    Ok(MeanForceSettings {
        name: name.to_string(),
        kind: kind.to_string(),
        mean_of,
        ubar,
        relaxation,
    })
}

/// The state of one mean-velocity source during a run (see the module doc).
#[derive(Clone, Debug)]
pub struct MeanForce {
    /// What `fvOptions` says.
    pub settings: MeanForceSettings,
    /// G₀ (m/s²).
    grad_p0: f64,
    /// ΔG (m/s²).
    d_grad_p: f64,
    /// r_A = 1/A per cell (s), from the last `constrain`.
    r_a: Vec<f64>,
    /// The weight w per cell of the source and the average (ε as of the last `correct` for
    /// the superficial mean; 1 otherwise).
    weight: Vec<f64>,
    /// ⟨U⟩ before the last correction (m/s).
    last_mean: f64,
}

/// The properties file of a source in the time directory `time_dir`.
pub fn props_path(time_dir: &Path, name: &str) -> PathBuf {
    time_dir.join("uniform").join(format!("{name}Properties"))
}

impl MeanForce {
    /// The source for a mesh of `n_cells`, starting from the `gradient` of
    /// `<start_dir>/uniform/<name>Properties` when that file exists (else 0).
    pub fn new(settings: MeanForceSettings, n_cells: usize, start_dir: &Path) -> Result<Self> {
        let props = props_path(start_dir, &settings.name);
        let grad_p0 = if props.is_file() {
            foam::parse_file(&props)?
                .body
                .f64("gradient")
                .map_err(|x| err(&props, "gradient".into(), x.0))?
        } else {
            0.0
        };
        Ok(MeanForce {
            settings,
            grad_p0,
            d_grad_p: 0.0,
            r_a: vec![0.0; n_cells],
            weight: vec![1.0; n_cells],
            last_mean: 0.0,
        })
    }

    /// The flow direction ê.
    pub fn direction(&self) -> V3 {
        self.settings.ubar / self.settings.ubar.norm()
    }

    /// The force G = G₀ + ΔG (m/s², kinematic pressure-gradient equivalent).
    pub fn gradient(&self) -> f64 {
        self.grad_p0 + self.d_grad_p
    }

    /// The mean velocity along ê before the last correction (m/s).
    pub fn uncorrected_mean(&self) -> f64 {
        self.last_mean
    }

    /// The momentum source of cell `c` per volume (m/s²): w_c G ê.
    pub fn source(&self, c: usize) -> V3 {
        (self.weight[c] * self.gradient()) * self.direction()
    }

    /// After assembly: r_A = 1/A per cell (`r_a`, s), G₀ ← G₀ + ΔG, ΔG ← 0.
    pub fn constrain(&mut self, r_a: &[f64]) {
        self.r_a.copy_from_slice(r_a);
        self.grad_p0 += self.d_grad_p;
        self.d_grad_p = 0.0;
    }

    /// After a velocity solve: the increment ΔG that brings the mean to |Ū| and the matching
    /// velocity correction of the cells `u` (volumes `v`, voidage `eps`).
    pub fn correct(&mut self, v: &[f64], eps: &[f64], u: &mut [V3]) {
        if self.settings.mean_of == MeanOf::Superficial {
            self.weight.copy_from_slice(eps);
        }
        let dir = self.direction();
        let (mut vol, mut ra, mut mean) = (0.0, 0.0, 0.0);
        for c in 0..u.len() {
            vol += v[c];
            ra += self.r_a[c] * v[c];
            mean += dir.dot(&u[c]) * v[c] * self.weight[c];
        }
        ra /= vol;
        mean /= vol;
        self.last_mean = mean;
        self.d_grad_p = self.settings.relaxation * (self.settings.ubar.norm() - mean) / ra;
        for ((uc, w), ra) in u.iter_mut().zip(&self.weight).zip(&self.r_a) {
            *uc += (w * ra * self.d_grad_p) * dir;
        }
    }

    /// Writes `<time_dir>/uniform/<name>Properties` with the current `gradient`.
    pub fn write(&self, time_dir: &Path, format: foam::Format) -> Result<()> {
        let path = props_path(time_dir, &self.settings.name);
        let dir = path.parent().expect("a file in uniform/");
        std::fs::create_dir_all(dir).map_err(|e| FvError::Value {
            what: dir.display().to_string(),
            msg: e.to_string(),
        })?;
        let mut body = Dict::new();
        body.set_item("gradient", foam::Item::Scalar(self.gradient()));
        let header = foam::Header {
            format,
            arch: foam::Arch::default(),
            class: "dictionary".into(),
            object: format!("{}Properties", self.settings.name),
            location: format!(
                "{}/uniform",
                time_dir
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default()
            ),
            note: None,
        };
        foam::write_dict_file(&path, &header, &body)?;
        Ok(())
    }
}
