//! Fluid–particle heat transfer: Nusselt correlations for a sphere in a bed, as pure functions.
//!
//! With the particle diameter d (m), the fluid's conductivity λ (W/(m·K)), the Nusselt number Nu
//! of a [`Nusselt`] law, the heat transfer coefficient is h = λ Nu / d (W/(m²·K),
//! [`heat_transfer_coefficient`]) and the convective heat flow into the particle
//! q = h π d² (T_f − T_p) (W). The laws take the particle Reynolds number Re, the Prandtl number
//! Pr = c_p ν ρ / λ ([`prandtl`]) and the voidage ε, all dimensionless; which velocity Re is built
//! on depends on the CFDEM model that uses the law ([`reynolds`]):
//! * CFDEM-PUBLIC's `LaEuScalarTemp` (all three of its laws): Re = d |u_f − v| / ν, u_f the
//!   interstitial fluid velocity;
//! * CFDEM-PFM's `heatTransferGunn` (and Gunn 1978): Re = ε d |u_f − v| / ν, the superficial
//!   slip velocity.
//!
//! Hot-path functions never fail; the caller checks λ, c_p, ν, ρ once (the coupler's
//! configuration reader does).

use crate::error::ClosureError;

/// A Nusselt correlation, by the name and form its CFDEM model computes it with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Nusselt {
    /// Li & Mason (2000), Powder Technol. 112:273, as CFDEM-PUBLIC's `LaEuScalarTemp` computes
    /// it (`NuCorrelation LiMason`, the default), with n = 3.5 and Pr^0.33:
    /// * Re < 200: Nu = 2 + 0.6 ε^n Re^½ Pr^0.33;
    /// * 200 ≤ Re < 1500: Nu = 2 + (0.5 Re^½ + 0.02 Re^0.8) ε^n Pr^0.33;
    /// * Re ≥ 1500: Nu = 2 + 4.5·10⁻⁵ ε^n Re^1.8.
    ///
    /// The branches do not join: Nu jumps at Re = 200 and 1500 as in the paper and in CFDEM.
    LiMason,
    /// Li & Mason (2000) as CFDEM-PUBLIC's `scalarGeneralExchange` computes it (`useLiMason
    /// true`): the branches of [`Nusselt::LiMason`] with Pr^⅓ (the paper's exponent) instead of
    /// Pr^0.33; that model feeds it the superficial Re.
    LiMasonCubeRoot,
    /// Deen et al. (2014), Chem. Eng. Sci. 116:710 (fitted for Re ≤ 100), `LaEuScalarTemp`'s
    /// `NuCorrelation Deen` (and `scalarGeneralExchange`'s default, with the superficial Re):
    /// Nu = (7 − 10ε + 5ε²)(1 + 0.17 Re^0.2 Pr^⅓) + (1.33 − 2.31ε + 1.16ε²) Re^0.7 Pr^⅓.
    Deen,
    /// Gunn (1978), Int. J. Heat Mass Transfer 21:467, `LaEuScalarTemp`'s `NuCorrelation
    /// Gunn`: Nu = (7 − 10ε + 5ε²)(1 + 0.7 Re^0.2 Pr^⅓) + (1.33 − 2.4ε + 1.2ε²) Re^0.7 Pr^⅓ —
    /// the paper's form (CFDEM writes ⅓ as 0.3333333333: a relative difference below 10⁻⁹ in
    /// Nu for Pr < 10⁶). LaEuScalarTemp feeds it the interstitial Re.
    Gunn,
    /// Gunn (1978) as CFDEM-PFM's `heatTransferGunn` computes it: the same form with Pr^0.33
    /// instead of Pr^⅓ (0.4 % lower Nu at Pr = 0.7, 0.5 % higher at Pr = 2). PFM feeds it the
    /// superficial Re and floors ε at 0.01 ([`GUNN_PFM_VOIDAGE_FLOOR`]).
    GunnPfm,
    /// Ranz & Marshall (1952), Chem. Eng. Prog. 48(3):141 (a single sphere): Nu = 2 +
    /// 0.6 Re^½ Pr^⅓, as CFDEM-PFM's `heatTransferRanzMarshall` computes it with its default
    /// `NusseltConstParameter` 0.6 (no ε dependence; PFM feeds it the superficial Re and floors
    /// ε at 0.01, [`GUNN_PFM_VOIDAGE_FLOOR`]).
    RanzMarshall,
}

/// The ε floor of CFDEM-PFM's `heatTransferGunn` (it clamps ε below 0.01 to 0.01).
pub const GUNN_PFM_VOIDAGE_FLOOR: f64 = 0.01;

/// Names of `LaEuScalarTempProps/NuCorrelation` and their laws.
pub const NUSSELT_NAMES: [(&str, Nusselt); 3] = [
    ("LiMason", Nusselt::LiMason),
    ("Deen", Nusselt::Deen),
    ("Gunn", Nusselt::Gunn),
];

impl Nusselt {
    /// The law of `LaEuScalarTempProps/NuCorrelation` `name` ([`NUSSELT_NAMES`]).
    pub fn from_name(name: &str) -> Result<Nusselt, ClosureError> {
        NUSSELT_NAMES
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, law)| *law)
            .ok_or_else(|| ClosureError::UnknownModel {
                family: "Nusselt correlation",
                name: name.to_string(),
                valid: NUSSELT_NAMES.map(|(n, _)| n).join(", "),
            })
    }

    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Nusselt::LiMason => "LiMason",
            Nusselt::LiMasonCubeRoot => "LiMason (Pr^1/3, CFDEM scalarGeneralExchange)",
            Nusselt::Deen => "Deen",
            Nusselt::Gunn => "Gunn",
            Nusselt::GunnPfm => "Gunn (CFDEM-PFM heatTransferGunn)",
            Nusselt::RanzMarshall => "Ranz-Marshall (CFDEM-PFM heatTransferRanzMarshall)",
        }
    }
}

/// The Nusselt number of `law` at particle Reynolds number `re`, Prandtl number `pr` and
/// voidage `eps` (all dimensionless; [`Nusselt`] gives each form and its source). Inputs are
/// used as given (no floor): Re ≥ 0, Pr > 0, ε in (0, 1].
#[inline]
pub fn nusselt(law: Nusselt, re: f64, pr: f64, eps: f64) -> f64 {
    match law {
        Nusselt::LiMason => li_mason(re, pr.powf(0.33), eps),
        Nusselt::LiMasonCubeRoot => li_mason(re, pr.cbrt(), eps),
        Nusselt::Deen => gunn_form(re, pr.cbrt(), eps, [7.0, 10.0, 5.0, 0.17, 1.33, 2.31, 1.16]),
        Nusselt::Gunn => gunn_form(re, pr.cbrt(), eps, GUNN),
        Nusselt::GunnPfm => gunn_form(re, pr.powf(0.33), eps, GUNN),
        Nusselt::RanzMarshall => 2.0 + 0.6 * re.sqrt() * pr.cbrt(),
    }
}

/// Gunn's (1978) coefficients in the order of [`gunn_form`].
const GUNN: [f64; 7] = [7.0, 10.0, 5.0, 0.7, 1.33, 2.4, 1.2];

/// (a − bε + cε²)(1 + k Re^0.2 P) + (e − fε + gε²) Re^0.7 P with `[a, b, c, k, e, f, g]` and
/// P = Pr^x (the caller's exponent).
#[inline]
fn gunn_form(re: f64, pr_x: f64, eps: f64, k: [f64; 7]) -> f64 {
    let [a, b, c, kr, e, f, g] = k;
    (a - b * eps + c * eps * eps) * (1.0 + kr * re.powf(0.2) * pr_x)
        + (e - f * eps + g * eps * eps) * re.powf(0.7) * pr_x
}

/// Li & Mason (2000) ([`Nusselt::LiMason`]) with `pr_x` = Pr^x, the caller's exponent.
#[inline]
fn li_mason(re: f64, pr_x: f64, eps: f64) -> f64 {
    let en = eps.powf(3.5);
    if re < 200.0 {
        2.0 + 0.6 * en * re.sqrt() * pr_x
    } else if re < 1500.0 {
        2.0 + (0.5 * re.sqrt() + 0.02 * re.powf(0.8)) * en * pr_x
    } else {
        2.0 + 0.000045 * en * re.powf(1.8)
    }
}

/// Which velocity a model's particle Reynolds number is built on (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReynoldsVelocity {
    /// Re = d |u_f − v| / ν (CFDEM-PUBLIC's `LaEuScalarTemp`).
    Interstitial,
    /// Re = ε d |u_f − v| / ν (CFDEM-PFM's `heatTransferGunn`).
    Superficial,
}

/// The particle Reynolds number for diameter `d` (m), slip speed `slip` = |u_f − v| (m/s),
/// kinematic viscosity `nu` (m²/s) and voidage `eps` by the convention `velocity`.
#[inline]
pub fn reynolds(velocity: ReynoldsVelocity, d: f64, slip: f64, nu: f64, eps: f64) -> f64 {
    match velocity {
        ReynoldsVelocity::Interstitial => d * slip / nu,
        ReynoldsVelocity::Superficial => eps * d * slip / nu,
    }
}

/// Pr = c_p ν ρ / λ for c_p in J/(kg·K), ν in m²/s, ρ in kg/m³ and λ in W/(m·K).
#[inline]
pub fn prandtl(cp: f64, nu: f64, rho: f64, lambda: f64) -> f64 {
    cp * nu * rho / lambda
}

/// h = λ Nu / d, W/(m²·K), for λ in W/(m·K) and d in m.
#[inline]
pub fn heat_transfer_coefficient(lambda: f64, nu_number: f64, d: f64) -> f64 {
    lambda * nu_number / d
}

/// The convective heat flow into a sphere of diameter `d` (m) with coefficient `h`
/// (W/(m²·K)): q = h π d² (T_f − T_p), W.
#[inline]
pub fn heat_flow(h: f64, d: f64, t_fluid: f64, t_particle: f64) -> f64 {
    h * std::f64::consts::PI * d * d * (t_fluid - t_particle)
}

/// `Ok` if the fluid's conductivity `lambda` (W/(m·K)) and heat capacity `cp` (J/(kg·K)) are
/// finite and positive, else an error naming the parameter (key `lambda` or `Cp`).
pub fn check_properties(model: &'static str, lambda: f64, cp: f64) -> Result<(), ClosureError> {
    for (key, value) in [("lambda", lambda), ("Cp", cp)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(ClosureError::BadParameter {
                model,
                key,
                value,
                reason: "must be finite and > 0",
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // Reference values evaluated by hand (python, double precision) from the papers' formulas
    // as written in the docs of `Nusselt`, not from this code.

    #[test]
    fn li_mason_against_the_paper_incl_branch_boundaries() {
        let cases = [
            // (Re, Pr, ε, Nu)
            (10.0, 0.7, 0.4, 2.0682721489838807),
            (199.999, 0.7, 0.45, 2.461095956636104),
            (200.0, 0.7, 0.45, 2.4595797031839437),
            (1499.999, 2.0, 0.5, 4.923581082885777),
            (1500.0, 2.0, 0.5, 4.07286870687849),
            (3000.0, 0.7, 0.9, 58.47803202195974),
            // packedBedTemp-like: d 0.022 m, U 1 m/s, ν 1.5e-3 → Re 14.667
            (14.667, 1021.0, 0.4436, 3.3145308186851077),
        ];
        for (re, pr, eps, nu) in cases {
            assert_relative_eq!(
                nusselt(Nusselt::LiMason, re, pr, eps),
                nu,
                max_relative = 1e-13
            );
        }
    }

    #[test]
    fn li_mason_with_the_cube_root_of_pr() {
        // scalarGeneralExchange's form: Pr^(1/3); the last branch has no Pr
        let cases = [
            (10.0, 0.7, 0.4, 2.0681910273338318),
            (500.0, 70.097, 0.45, 5.545190020671152),
            (2000.0, 2.0, 0.5, 5.479056815498659),
        ];
        for (re, pr, eps, nu) in cases {
            let got = nusselt(Nusselt::LiMasonCubeRoot, re, pr, eps);
            assert_relative_eq!(got, nu, max_relative = 1e-13);
        }
    }

    #[test]
    fn li_mason_tends_to_two_without_flow() {
        for eps in [0.3, 0.6, 1.0] {
            for law in [Nusselt::LiMason, Nusselt::LiMasonCubeRoot] {
                assert_eq!(nusselt(law, 0.0, 0.7, eps), 2.0);
                let nu = nusselt(law, 1e-12, 0.7, eps);
                assert!(nu > 2.0 && nu - 2.0 < 1e-6, "{nu}");
            }
        }
    }

    #[test]
    fn gunn_and_deen_against_the_papers() {
        let cases = [
            // (Re, Pr, ε, Gunn Pr^⅓, Gunn Pr^0.33, Deen)
            (
                10.0,
                0.7,
                0.4,
                10.04417436609237,
                10.051602582788565,
                7.34172890864637,
            ),
            (
                100.0,
                2.0,
                0.6,
                19.193553096221947,
                19.155719669580996,
                15.750273990297337,
            ),
            (
                50.0,
                0.7,
                1.0,
                6.503036685551898,
                6.508393603909724,
                5.131399156366221,
            ),
        ];
        for (re, pr, eps, gunn, gunn_pfm, deen) in cases {
            assert_relative_eq!(
                nusselt(Nusselt::Gunn, re, pr, eps),
                gunn,
                max_relative = 1e-13
            );
            assert_relative_eq!(
                nusselt(Nusselt::GunnPfm, re, pr, eps),
                gunn_pfm,
                max_relative = 1e-13
            );
            assert_relative_eq!(
                nusselt(Nusselt::Deen, re, pr, eps),
                deen,
                max_relative = 1e-13
            );
        }
    }

    /// Ranz & Marshall (1952): Nu = 2 + 0.6 Re^½ Pr^⅓, evaluated independently (python:
    /// `2 + 0.6*math.sqrt(re)*pr**(1/3)`); ε does not enter.
    #[test]
    fn ranz_marshall_by_hand() {
        for (re, pr, nu) in [
            (0.0, 0.7, 2.0),
            (50.0, 0.7, 5.76705764404919),
            (400.0, 2.0, 17.119052598738477),
        ] {
            for eps in [0.4, 1.0] {
                assert_relative_eq!(
                    nusselt(Nusselt::RanzMarshall, re, pr, eps),
                    nu,
                    max_relative = 1e-14
                );
            }
        }
    }

    #[test]
    fn gunn_without_particles_or_flow_is_two() {
        // ε = 1, Re = 0: (7 − 10 + 5)·1 + 0 = 2, the conduction limit of a single sphere
        for law in [Nusselt::Gunn, Nusselt::GunnPfm, Nusselt::Deen] {
            assert_eq!(nusselt(law, 0.0, 0.7, 1.0), 2.0, "{law:?}");
        }
    }

    #[test]
    fn names_and_conventions() {
        assert_eq!(Nusselt::from_name("Deen"), Ok(Nusselt::Deen));
        let e = Nusselt::from_name("RanzMarshall").unwrap_err().to_string();
        assert!(
            e.contains("RanzMarshall") && e.contains("LiMason, Deen, Gunn"),
            "{e}"
        );
        let i = reynolds(ReynoldsVelocity::Interstitial, 0.022, 1.0, 1.5e-3, 0.5);
        let s = reynolds(ReynoldsVelocity::Superficial, 0.022, 1.0, 1.5e-3, 0.5);
        assert_relative_eq!(i, 0.022 / 1.5e-3, max_relative = 1e-15);
        assert_relative_eq!(s, 0.5 * 0.022 / 1.5e-3, max_relative = 1e-15);
        // air at 300 K: c_p 1007, ν 1.589e-5, ρ 1.177, λ 0.0263 → Pr ≈ 0.716
        assert_relative_eq!(
            prandtl(1007.0, 1.589e-5, 1.177, 0.0263),
            0.7161,
            epsilon = 1e-3
        );
        let e = check_properties("LaEuScalarTemp", 0.0263, -1.0).unwrap_err();
        assert!(e.to_string().contains("`Cp`"), "{e}");
        assert!(check_properties("LaEuScalarTemp", 0.0263, 1007.0).is_ok());
    }
}
