//! Schumann's (1929) solution of the two-phase, one-dimensional packed-bed heating problem: the
//! reference of `openfoam-cases/packed-bed-heating` ([`crate::heating`]).
//!
//! **Model** (T. E. W. Schumann, "Heat transfer: a liquid flowing through a porous prism",
//! J. Franklin Inst. 208 (1929) 405–416; the same model as Anzelius 1926 and Hausen's
//! regenerator): gas in plug flow at the interstitial speed u (m/s) through a bed of voidage ε,
//! no conduction in either phase, a constant volumetric exchange coefficient h·a
//! (h in W/(m²·K), a = 6(1 − ε)/d the particle surface per bed volume, 1/m):
//!
//! ```text
//!   ε ρ_g c_g (∂T_g/∂t + u ∂T_g/∂x) = h a (T_s − T_g)
//!   (1 − ε) ρ_s c_s ∂T_s/∂t          = h a (T_g − T_s)
//! ```
//!
//! bed and gas at T0 for t < 0, gas entering at x = 0 at T_in from t = 0.
//!
//! **Solution.** With ξ = h a x / (ε ρ_g c_g u) (transfer units up to x) and
//! η = h a (t − x/u) / ((1 − ε) ρ_s c_s) (transfer units of the solid since the gas that entered
//! at t = 0 reached x), the system becomes ∂θ_g/∂ξ = θ_s − θ_g, ∂θ_s/∂η = θ_g − θ_s with
//! θ_g(0, η) = 1 and θ_s(ξ, 0) = 0, θ = (T − T0)/(T_in − T0). A Laplace transform in η gives
//! Θ_g = e^{−ξ} e^{ξ/(s+1)} / s, whose inverse is Schumann's result in the form of the
//! J function (Hougen & Watson; Klinkenberg, Ind. Eng. Chem. 40 (1948) 1992):
//!
//! ```text
//!   θ_g = J(ξ, η),   θ_s = J(ξ, η) − e^{−ξ−η} I0(2√(ξη)),
//!   J(ξ, η) = 1 − ∫_0^ξ e^{−η−τ} I0(2√(ητ)) dτ,
//! ```
//!
//! and θ_g = θ_s = 0 where η < 0 (the gas that entered at t = 0 has not reached x). Expanding
//! I0 in its power series and integrating term by term gives the form evaluated here:
//! with N_ξ, N_η independent Poisson variables of means ξ and η,
//!
//! ```text
//!   θ_g = J(ξ, η) = P(N_ξ ≤ N_η),     θ_s = P(N_ξ < N_η),
//! ```
//!
//! (J(ξ,η) = Σ_k e^{−η} η^k/k! · Σ_{j≤k} e^{−ξ} ξ^j/j!; the difference of the two is
//! P(N_ξ = N_η) = e^{−ξ−η} I0(2√(ξη))). This is also Marcum's Q function,
//! J(ξ, η) = Q₁(√(2η), √(2ξ)). The Poisson probabilities are summed over a window of
//! ±(10√μ + 40) about each mean (the rest is below 1e-20), weights built by recursion from the
//! mode and normalised by their sum, so nothing overflows for any finite argument and no
//! Bessel function is needed; absolute error ≲ 1e-13 for ξ + η up to 1e10 (window of 2·10⁶
//! terms). Beyond that (no bed has 10¹⁰ transfer units) the normal approximation of the
//! difference N_η − N_ξ with continuity correction is used (error ≲ 1e-6 there).
//!
//! The tests (`tests/heating_reference.rs`) hold these values against an independent
//! second-order characteristic solution of the PDEs, the identity
//! J(ξ,η) + J(η,ξ) = 1 + e^{−ξ−η} I0(2√(ξη)), the limits and arbitrary-precision quadrature of
//! the integral form.

/// Poisson probabilities of mean `mu` over a window: `p[k - lo]` = P(N = k) for
/// `k in lo..lo + p.len()`; the mass outside is below 1e-20.
struct PoissonWindow {
    lo: i64,
    p: Vec<f64>,
}

impl PoissonWindow {
    fn new(mu: f64) -> PoissonWindow {
        if mu <= 0.0 {
            return PoissonWindow {
                lo: 0,
                p: vec![1.0],
            };
        }
        let mode = mu.floor();
        let half = (10.0 * mu.sqrt() + 40.0).ceil();
        let lo = (mode - half).max(0.0) as i64;
        let hi = (mode + half) as i64;
        let m = mode as i64;
        let mut p = vec![0.0; (hi - lo + 1) as usize];
        let at = |k: i64| (k - lo) as usize;
        p[at(m)] = 1.0;
        // outward recursions P(k+1)/P(k) = μ/(k+1), P(k−1)/P(k) = k/μ from the mode (weight 1)
        for k in m..hi {
            p[at(k + 1)] = p[at(k)] * mu / (k + 1) as f64;
        }
        for k in (lo + 1..=m).rev() {
            p[at(k - 1)] = p[at(k)] * k as f64 / mu;
        }
        let sum: f64 = p.iter().sum();
        p.iter_mut().for_each(|v| *v /= sum);
        PoissonWindow { lo, p }
    }

    fn hi(&self) -> i64 {
        self.lo + self.p.len() as i64 - 1
    }
}

/// P(N_a ≤ N_b + offset) for independent Poisson variables of means `a`, `b` (≥ 0, finite).
fn poisson_le(a: f64, b: f64, offset: i64) -> f64 {
    if a + b > 1e10 {
        // the difference is normal to O((a+b)^-1/2) in its skewness: ≲ 1e-6 here
        let z = (b - a + offset as f64 + 0.5) / (a + b).sqrt();
        return 0.5 * erfc(-z / std::f64::consts::SQRT_2);
    }
    let wa = PoissonWindow::new(a);
    let wb = PoissonWindow::new(b);
    // cumulative of N_a: cdf[i] = P(N_a ≤ wa.lo + i)
    let mut cdf = Vec::with_capacity(wa.p.len());
    let mut acc = 0.0;
    for v in &wa.p {
        acc += v;
        cdf.push(acc.min(1.0));
    }
    let cdf_a = |k: i64| -> f64 {
        if k < wa.lo {
            0.0
        } else if k >= wa.hi() {
            1.0
        } else {
            cdf[(k - wa.lo) as usize]
        }
    };
    let mut sum = 0.0;
    for (i, pb) in wb.p.iter().enumerate() {
        sum += pb * cdf_a(wb.lo + i as i64 + offset);
    }
    sum.clamp(0.0, 1.0)
}

/// The complementary error function, |relative error| < 1.2e-7 (Numerical Recipes' `erfcc`,
/// Press et al. 1992, §6.2, a Chebyshev fit); used only beyond 10¹⁰ transfer units.
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// Schumann's J function, J(ξ, η) = 1 − ∫_0^ξ e^{−η−τ} I0(2√(ητ)) dτ (dimensionless, in
/// [0, 1]): the normalised gas temperature at ξ transfer units into the bed, η solid transfer
/// units after the hot gas arrived. Negative, NaN or infinite arguments are clamped: ξ ≤ 0
/// gives 1 (the inlet), η ≤ 0 gives e^{−ξ} (the gas just arrived), +∞ the limits.
pub fn j(xi: f64, eta: f64) -> f64 {
    let xi = if xi.is_nan() { 0.0 } else { xi.max(0.0) };
    let eta = if eta.is_nan() { 0.0 } else { eta.max(0.0) };
    if xi == 0.0 {
        return 1.0;
    }
    if xi.is_infinite() {
        return if eta.is_infinite() { 0.5 } else { 0.0 };
    }
    if eta.is_infinite() {
        return 1.0;
    }
    poisson_le(xi, eta, 0)
}

/// The normalised gas temperature θ_g = (T_g − T0)/(T_in − T0) at (ξ, η): [`j`] for η ≥ 0,
/// 0 for η < 0 (the bed's initial gas, not yet displaced).
pub fn gas(xi: f64, eta: f64) -> f64 {
    if eta < 0.0 {
        0.0
    } else {
        j(xi, eta)
    }
}

/// The normalised solid temperature θ_s = (T_s − T0)/(T_in − T0) at (ξ, η):
/// J(ξ, η) − e^{−ξ−η} I0(2√(ξη)) = P(N_ξ < N_η) for η > 0, 0 for η ≤ 0. ξ ≤ 0 (the inlet)
/// gives 1 − e^{−η}.
pub fn solid(xi: f64, eta: f64) -> f64 {
    if eta.is_nan() || eta <= 0.0 {
        return 0.0;
    }
    let xi = if xi.is_nan() { 0.0 } else { xi.max(0.0) };
    if eta.is_infinite() {
        return if xi.is_infinite() { 0.5 } else { 1.0 };
    }
    if xi.is_infinite() {
        return 0.0;
    }
    poisson_le(xi, eta, -1)
}

/// A bed in Schumann's model, in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SchumannBed {
    /// Bed voidage ε.
    pub voidage: f64,
    /// Gas volumetric heat capacity ρ_g c_g, J/(m³·K).
    pub gas_heat_capacity: f64,
    /// Solid volumetric heat capacity ρ_s c_s, J/(m³·K).
    pub solid_heat_capacity: f64,
    /// Interstitial gas speed u, m/s.
    pub interstitial_velocity: f64,
    /// Exchange coefficient per bed volume h·a, W/(m³·K).
    pub exchange: f64,
}

impl SchumannBed {
    /// The bed of spheres of diameter `d` (m), voidage `eps`, solid ρ_s (kg/m³) and c_s
    /// (J/(kg·K)), gas ρ_g and c_g, superficial gas velocity `u_sup` (m/s) and particle heat
    /// transfer coefficient `h` (W/(m²·K)); a = 6(1 − ε)/d, u = u_sup/ε. Every input must be
    /// finite and positive, ε in (0, 1); the error names the offending one.
    #[allow(clippy::too_many_arguments)]
    pub fn of_spheres(
        eps: f64,
        d: f64,
        rho_s: f64,
        c_s: f64,
        rho_g: f64,
        c_g: f64,
        u_sup: f64,
        h: f64,
    ) -> Result<SchumannBed, String> {
        for (name, v) in [
            ("particle diameter", d),
            ("solid density", rho_s),
            ("solid heat capacity", c_s),
            ("gas density", rho_g),
            ("gas heat capacity", c_g),
            ("superficial velocity", u_sup),
            ("heat transfer coefficient", h),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be a positive number, got {v}"));
            }
        }
        if !(eps > 0.0 && eps < 1.0) {
            return Err(format!("bed voidage must lie in (0, 1), got {eps}"));
        }
        Ok(SchumannBed {
            voidage: eps,
            gas_heat_capacity: rho_g * c_g,
            solid_heat_capacity: rho_s * c_s,
            interstitial_velocity: u_sup / eps,
            exchange: h * 6.0 * (1.0 - eps) / d,
        })
    }

    /// ξ at depth `x` (m): h a x / (ε ρ_g c_g u).
    pub fn xi(&self, x: f64) -> f64 {
        self.exchange * x / (self.voidage * self.gas_heat_capacity * self.interstitial_velocity)
    }

    /// η at depth `x` (m) and time `t` (s) since the inlet step: h a (t − x/u)/((1−ε) ρ_s c_s).
    pub fn eta(&self, x: f64, t: f64) -> f64 {
        self.exchange * (t - x / self.interstitial_velocity)
            / ((1.0 - self.voidage) * self.solid_heat_capacity)
    }

    /// The normalised gas temperature at depth `x` (m), time `t` (s).
    pub fn gas(&self, x: f64, t: f64) -> f64 {
        gas(self.xi(x), self.eta(x, t))
    }

    /// The normalised solid temperature at depth `x` (m), time `t` (s).
    pub fn solid(&self, x: f64, t: f64) -> f64 {
        solid(self.xi(x), self.eta(x, t))
    }

    /// The speed of the thermal front far into the bed (m/s), where ξ ≈ η:
    /// 1/u_f = (1−ε) ρ_s c_s/(ε ρ_g c_g u) + 1/u (the heat carried by the gas fills solid and
    /// gas behind the front).
    pub fn front_speed(&self) -> f64 {
        let u = self.interstitial_velocity;
        let r = (1.0 - self.voidage) * self.solid_heat_capacity
            / (self.voidage * self.gas_heat_capacity);
        u / (r + 1.0)
    }

    /// The length of one gas transfer unit, ε ρ_g c_g u/(h a) (m): ξ = x / this.
    pub fn transfer_length(&self) -> f64 {
        self.voidage * self.gas_heat_capacity * self.interstitial_velocity / self.exchange
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_cases_by_hand() {
        // η = 0: θ_g = e^{−ξ}; ξ = 0: 1; θ_s(0, η) = 1 − e^{−η}
        assert!((j(1.5, 0.0) - (-1.5f64).exp()).abs() < 1e-15);
        assert_eq!(j(0.0, 3.0), 1.0);
        assert!((solid(0.0, 2.0) - (1.0 - (-2.0f64).exp())).abs() < 1e-15);
        // J(ξ, η) by the double series summed by hand for ξ = η = 1:
        // Σ_k e^{-1}/k! Σ_{j≤k} e^{-1}/j!
        let mut s = 0.0;
        let mut fk = 1.0;
        for k in 0..30 {
            if k > 0 {
                fk *= k as f64;
            }
            let mut inner = 0.0;
            let mut fj = 1.0;
            for jj in 0..=k {
                if jj > 0 {
                    fj *= jj as f64;
                }
                inner += (-1.0f64).exp() / fj;
            }
            s += (-1.0f64).exp() / fk * inner;
        }
        assert!((j(1.0, 1.0) - s).abs() < 1e-14, "{} {s}", j(1.0, 1.0));
    }

    #[test]
    fn nothing_is_nan() {
        let args = [
            0.0,
            1e-300,
            1e-3,
            1.0,
            1e3,
            1e8,
            1e11,
            1e300,
            f64::INFINITY,
            -1.0,
        ];
        for &x in &args {
            for &y in &args {
                let (g, s) = (j(x, y), solid(x, y));
                assert!(
                    (0.0..=1.0).contains(&g) && (0.0..=1.0).contains(&s),
                    "{x} {y}"
                );
            }
        }
        assert!(j(f64::NAN, 1.0).is_finite() && solid(1.0, f64::NAN) == 0.0);
    }

    #[test]
    fn the_normal_branch_joins_the_sum() {
        // just below and above the switch at ξ + η = 1e10
        let m = 0.5e10 - 1.0;
        for d in [-2e5, -5e4, 0.0, 5e4, 2e5] {
            let sum = poisson_le(m, m + d, 0);
            let z = (d + 0.5) / (2.0 * m).sqrt();
            let normal = 0.5 * erfc(-z / std::f64::consts::SQRT_2);
            assert!((sum - normal).abs() < 2e-6, "{d}: {sum} {normal}");
        }
    }
}
