//! Material properties per atom type and the contact coefficients LIGGGHTS derives from them per
//! type pair (`fix property/global youngsModulus|poissonsRatio peratomtype …`,
//! `coefficientRestitution|coefficientFriction|coefficientRollingFriction|cohesionEnergyDensity
//! peratomtypepair n …`).
//!
//! Types are numbered from 1 as in LIGGGHTS; a wall takes the material of the type given in
//! `fix wall/gran … primitive type T`.

use crate::error::DemError;

/// Material of the particle types of a simulation, with the per-pair coefficients ready for
/// the contact kernels.
#[derive(Debug, Clone, PartialEq)]
pub struct Materials {
    ntypes: usize,
    /// Young's modulus per type (Pa).
    pub youngs_modulus: Vec<f64>,
    /// Poisson ratio per type (–).
    pub poissons_ratio: Vec<f64>,
    pairs: Vec<PairCoeffs>,
}

/// What the contact kernels need for one type pair (symmetric in the pair).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairCoeffs {
    /// Effective Young's modulus Y* = 1 / ((1−νᵢ²)/Eᵢ + (1−νⱼ²)/Eⱼ) (Pa).
    pub y_eff: f64,
    /// Effective shear modulus G* = 1 / (2(2−νᵢ)(1+νᵢ)/Eᵢ + 2(2−νⱼ)(1+νⱼ)/Eⱼ) (Pa), i.e.
    /// 1/((2−νᵢ)/Gᵢ + (2−νⱼ)/Gⱼ) with G = E/(2(1+ν)).
    pub g_eff: f64,
    /// Damping ratio β = ln e / √(ln²e + π²) (–, ≤ 0; 0 for e = 1).
    pub beta: f64,
    /// Coefficient of restitution e (–).
    pub restitution: f64,
    /// Coulomb friction coefficient μ (–).
    pub friction: f64,
    /// Rolling friction coefficient μᵣ (–), 0 if not given.
    pub rolling_friction: f64,
    /// Cohesion energy density k (J/m³ = N/m²) of SJKR, 0 if not given.
    pub cohesion_energy_density: f64,
}

/// Inputs of [`Materials::new`]: per-type vectors (length n) and per-pair matrices (n × n,
/// row-major, type 1 first) as a `peratomtype` / `peratomtypepair` property lists them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MaterialInput {
    /// `youngsModulus` (Pa), one per type.
    pub youngs_modulus: Vec<f64>,
    /// `poissonsRatio` (–), one per type.
    pub poissons_ratio: Vec<f64>,
    /// `coefficientRestitution` (–), n × n.
    pub restitution: Vec<f64>,
    /// `coefficientFriction` (–), n × n.
    pub friction: Vec<f64>,
    /// `coefficientRollingFriction` (–), n × n; empty = 0.
    pub rolling_friction: Vec<f64>,
    /// `cohesionEnergyDensity` (J/m³), n × n; empty = 0.
    pub cohesion_energy_density: Vec<f64>,
}

impl MaterialInput {
    /// One type with the given E (Pa), ν, e, μ; no rolling friction, no cohesion.
    pub fn single(
        youngs_modulus: f64,
        poissons_ratio: f64,
        restitution: f64,
        friction: f64,
    ) -> Self {
        MaterialInput {
            youngs_modulus: vec![youngs_modulus],
            poissons_ratio: vec![poissons_ratio],
            restitution: vec![restitution],
            friction: vec![friction],
            rolling_friction: Vec::new(),
            cohesion_energy_density: Vec::new(),
        }
    }
}

/// Damping ratio from the coefficient of restitution, β = ln e / √(ln²e + π²) (LIGGGHTS
/// `createBetaEff`; the damped linearised oscillator whose restitution is e).
pub fn beta_from_restitution(e: f64) -> f64 {
    let l = e.ln();
    l / (l * l + std::f64::consts::PI * std::f64::consts::PI).sqrt()
}

impl Materials {
    /// Checks the input (LIGGGHTS's sanity rules: E > 0, 0 ≤ ν ≤ 0.5, 0.05 < e ≤ 1, μ ≥ 0,
    /// μᵣ ≥ 0, k ≥ 0, symmetric pair matrices) and derives the per-pair coefficients.
    pub fn new(input: &MaterialInput) -> Result<Materials, DemError> {
        let n = input.youngs_modulus.len();
        let bad = |msg: String| Err(DemError::Material(msg));
        if n == 0 {
            return bad("youngsModulus: no value (one per atom type needed)".into());
        }
        if input.poissons_ratio.len() != n {
            return bad(format!(
                "poissonsRatio has {} values, youngsModulus {} (one per atom type)",
                input.poissons_ratio.len(),
                n
            ));
        }
        for (t, (&e, &nu)) in input
            .youngs_modulus
            .iter()
            .zip(&input.poissons_ratio)
            .enumerate()
        {
            if !(e > 0.0 && e.is_finite()) {
                return bad(format!(
                    "youngsModulus of type {} is {e}: must be > 0",
                    t + 1
                ));
            }
            if !(0.0..=0.5).contains(&nu) {
                return bad(format!(
                    "poissonsRatio of type {} is {nu}: 0 ≤ ν ≤ 0.5 required",
                    t + 1
                ));
            }
        }
        let matrix = |name: &str, v: &[f64], optional: bool| -> Result<Vec<f64>, DemError> {
            if v.is_empty() && optional {
                return Ok(vec![0.0; n * n]);
            }
            if v.len() != n * n {
                return Err(DemError::Material(format!(
                    "{name} has {} values: {n}×{n} = {} needed (peratomtypepair {n})",
                    v.len(),
                    n * n
                )));
            }
            for i in 0..n {
                for j in 0..n {
                    let x = v[i * n + j];
                    if !x.is_finite() || x < 0.0 {
                        return Err(DemError::Material(format!(
                            "{name} for types {} {} is {x}: must be finite and ≥ 0",
                            i + 1,
                            j + 1
                        )));
                    }
                    if x != v[j * n + i] {
                        return Err(DemError::Material(format!(
                            "{name} is not symmetric: types {} {} give {x}, types {} {} give {}",
                            i + 1,
                            j + 1,
                            j + 1,
                            i + 1,
                            v[j * n + i]
                        )));
                    }
                }
            }
            Ok(v.to_vec())
        };
        let e = matrix("coefficientRestitution", &input.restitution, false)?;
        let mu = matrix("coefficientFriction", &input.friction, false)?;
        let mur = matrix("coefficientRollingFriction", &input.rolling_friction, true)?;
        let ced = matrix(
            "cohesionEnergyDensity",
            &input.cohesion_energy_density,
            true,
        )?;
        for (k, &x) in e.iter().enumerate() {
            if !(x > 0.05 && x <= 1.0) {
                return bad(format!(
                    "coefficientRestitution for types {} {} is {x}: 0.05 < e ≤ 1 required",
                    k / n + 1,
                    k % n + 1
                ));
            }
        }
        let (ym, nu) = (&input.youngs_modulus, &input.poissons_ratio);
        let mut pairs = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                let k = i * n + j;
                pairs.push(PairCoeffs {
                    y_eff: 1.0 / ((1.0 - nu[i] * nu[i]) / ym[i] + (1.0 - nu[j] * nu[j]) / ym[j]),
                    g_eff: 1.0
                        / (2.0 * (2.0 - nu[i]) * (1.0 + nu[i]) / ym[i]
                            + 2.0 * (2.0 - nu[j]) * (1.0 + nu[j]) / ym[j]),
                    beta: beta_from_restitution(e[k]),
                    restitution: e[k],
                    friction: mu[k],
                    rolling_friction: mur[k],
                    cohesion_energy_density: ced[k],
                });
            }
        }
        Ok(Materials {
            ntypes: n,
            youngs_modulus: ym.clone(),
            poissons_ratio: nu.clone(),
            pairs,
        })
    }

    /// Number of atom types.
    pub fn ntypes(&self) -> usize {
        self.ntypes
    }

    /// Coefficients of the pair of 1-based types `(ti, tj)`. Types must be in `1..=ntypes`
    /// (checked when particles and walls are created).
    #[inline]
    pub fn pair(&self, ti: u32, tj: u32) -> &PairCoeffs {
        &self.pairs[(ti as usize - 1) * self.ntypes + (tj as usize - 1)]
    }

    /// Whether any pair has a non-zero rolling friction coefficient.
    pub fn any_rolling_friction(&self) -> bool {
        self.pairs.iter().any(|p| p.rolling_friction > 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_material_gives_textbook_effective_moduli() {
        // Y* = E / (2(1−ν²)) and G* = G / (2(2−ν)) for identical spheres (Johnson, Contact
        // Mechanics, eq. 4.22 and 7.6), G = E/(2(1+ν)).
        let m = Materials::new(&MaterialInput::single(5e6, 0.45, 0.3, 0.5)).unwrap();
        let p = m.pair(1, 1);
        assert!((p.y_eff - 5e6 / (2.0 * (1.0 - 0.45f64 * 0.45))).abs() < 1e-6);
        let g = 5e6 / (2.0 * 1.45);
        assert!((p.g_eff - g / (2.0 * 1.55)).abs() < 1e-6);
        // e = 0.3: ln 0.3 = −1.2039728, β = −1.2039728/√(1.4495505 + 9.8696044)
        // = −1.2039728/3.3643952 = −0.3578571
        assert!((p.beta + 0.357_857_1).abs() < 1e-7, "{}", p.beta);
        assert_eq!(beta_from_restitution(1.0), 0.0);
    }

    #[test]
    fn bad_inputs_are_named() {
        let mut inp = MaterialInput::single(5e6, 0.6, 0.3, 0.5);
        let e = Materials::new(&inp).unwrap_err().to_string();
        assert!(e.contains("poissonsRatio of type 1"), "{e}");
        inp.poissons_ratio = vec![0.3];
        inp.restitution = vec![0.01];
        let e = Materials::new(&inp).unwrap_err().to_string();
        assert!(e.contains("coefficientRestitution"), "{e}");
        inp.restitution = vec![0.5, 0.4, 0.3, 0.5];
        let e = Materials::new(&inp).unwrap_err().to_string();
        assert!(e.contains("2×2") || e.contains("1×1"), "{e}");
        let two = MaterialInput {
            youngs_modulus: vec![1e7, 2e7],
            poissons_ratio: vec![0.3, 0.3],
            restitution: vec![0.5, 0.4, 0.3, 0.5],
            friction: vec![0.5; 4],
            ..Default::default()
        };
        let e = Materials::new(&two).unwrap_err().to_string();
        assert!(e.contains("not symmetric"), "{e}");
    }
}
